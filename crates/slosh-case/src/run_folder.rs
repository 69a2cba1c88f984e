//! The output folder of one run: locked while the run writes it, emptied of an earlier run's
//! outputs before it starts, and never taken over from a folder that holds other files.

use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock file: held under the operating system's lock by the run that writes the folder,
/// and naming it (process id and host).
pub const LOCK_FILE: &str = ".slosh.lock";

/// Files a run writes at the top of its folder (and removes again before the next run in the
/// same folder), each also as its temporary sibling `NAME.tmp` / `NAME.part` while written.
const GENERATED_FILES: [&str; 8] = [
    "series.csv",
    "series_units.csv",
    "summary.ron",
    "roof_pressure.csv",
    "roof_points.csv",
    "roof_points.vtp",
    "input_spectrum.csv",
    "roof_spectrum.csv",
];
/// The folders a run writes into; only the files [`generated`] accepts may be in them.
const GENERATED_DIRS: [&str; 5] = ["frames", "plots", "post", "checkpoint", ".series-rewrite"];
/// The plots a run draws into `plots/`, each as `.png` and `.svg` (and `.part.png`,
/// `.part.svg` while drawn): `docs/formats.md` lists them.
const PLOT_STEMS: [&str; 12] = [
    "eta",
    "base_shear",
    "roof_force",
    "roof_pressure",
    "ground_accel",
    "roof_pressure_map",
    "fig7_a",
    "fig7_b",
    "fig7_c",
    "frame_peak",
    "input_spectrum",
    "roof_spectrum",
];
/// The record of the names a run chose at run time (the `post/` tables and plots a script
/// asks for): one relative path stem per line, written before the file is created, so that
/// the next run in the folder can prove the file is slosh's.
pub const OUTPUTS_FILE: &str = ".slosh-outputs";
/// Files another slosh command writes into a run folder (a sweep's log of the case), kept
/// when a run starts again in the folder.
const KNOWN_FILES: [&str; 2] = ["run.log", LOCK_FILE];

/// A run's claim on its output folder; the lock is released when it is dropped.
#[derive(Debug)]
pub struct RunFolder {
    dir: PathBuf,
    lock: PathBuf,
    /// The open lock file, locked until it is closed (after the path is removed).
    _held: std::fs::File,
    /// The folder itself, open and locked as the file is (where the file system locks
    /// folders): a lock file removed by hand does not let a second run in.
    _held_folder: Option<std::fs::File>,
    case: String,
    script: String,
}

/// What `summary.ron` says from the first step until the run ends, and for a run that
/// stopped before its first output.
#[derive(Serialize)]
struct ShortSummary<'a> {
    version: &'a str,
    case: &'a str,
    script: &'a str,
    status: &'a str,
    pid: u32,
    error: Option<&'a str>,
}

impl RunFolder {
    /// Claims `dir` for a run of `case` (script `script`): creates it, takes the lock (a
    /// folder locked by a live process is refused with its pid; a stale lock of a dead one is
    /// taken over), refuses a non-empty folder that is not a slosh run folder, removes an
    /// earlier run's outputs, and writes `summary.ron` with `status: "running"`.
    pub fn claim(dir: &Path, case: &str, script: &Path) -> Result<RunFolder> {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the output folder {}", dir.display()))?;
        let folder = Self::lock(dir, case, script)?;
        remove_earlier_outputs(dir)?;
        folder.write_short_summary("running", None)?;
        Ok(folder)
    }

    /// Claims `dir` to continue the interrupted run it holds: locked as [`Self::claim`] does,
    /// but its outputs are kept (the run appends to them).
    pub fn claim_to_resume(dir: &Path, case: &str, script: &Path) -> Result<RunFolder> {
        let folder = Self::lock(dir, case, script)?;
        folder.write_short_summary("running", None)?;
        Ok(folder)
    }

    /// Takes the lock of the existing folder `dir` and checks that it is a run folder.
    fn lock(dir: &Path, case: &str, script: &Path) -> Result<RunFolder> {
        let lock = dir.join(LOCK_FILE);
        let held_folder = lock_folder(dir, &lock)?;
        let held = take_lock(&lock)?;
        let folder = RunFolder {
            dir: dir.to_path_buf(),
            lock,
            _held: held,
            _held_folder: held_folder,
            case: case.to_string(),
            script: script.display().to_string(),
        };
        check_is_run_folder(dir)?;
        Ok(folder)
    }

    /// After a run that stopped with `error` before writing its own summary (a bad tank, a
    /// refused setting): `summary.ron` says `status: "failed"` with the error instead of
    /// "running".
    ///
    /// On a full disk, where the new summary cannot be written beside the old one and renamed
    /// over it, the old file (slosh's own, never a link) is overwritten in place: cutting it
    /// first frees the space the short summary needs. `Err` says that even this failed, so
    /// that the caller can tell the user that `summary.ron` still says "running".
    pub fn mark_failed_if_running(&self, error: &str) -> Result<()> {
        let path = self.dir.join("summary.ron");
        let summary = std::fs::read_to_string(&path).unwrap_or_default();
        if !summary.contains("status: \"running\"") {
            return Ok(());
        }
        let Err(atomic) = self.write_short_summary("failed", Some(error)) else {
            return Ok(());
        };
        slosh_io::overwrite_ron_in_place(&path, &self.short_summary("failed", Some(error))).map_err(
            |e| {
                anyhow::anyhow!(
                    "{} could not be updated ({atomic:#}; in place: {e}): it still says \
                     \"running\"",
                    path.display()
                )
            },
        )
    }

    fn short_summary<'a>(&'a self, status: &'a str, error: Option<&'a str>) -> ShortSummary<'a> {
        ShortSummary {
            version: env!("CARGO_PKG_VERSION"),
            case: &self.case,
            script: &self.script,
            status,
            pid: std::process::id(),
            error,
        }
    }

    fn write_short_summary(&self, status: &str, error: Option<&str>) -> Result<()> {
        slosh_io::write_ron(
            self.dir.join("summary.ron"),
            &self.short_summary(status, error),
        )?;
        Ok(())
    }
}

impl Drop for RunFolder {
    fn drop(&mut self) {
        // The folder's lock first, while the lock file is still there and held: a run that
        // comes in now finds the file held and names this one. Then the file is removed while
        // still locked; its lock ends when `_held` closes just after.
        drop(self._held_folder.take());
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// Takes the lock `lock` for this process: the file held under the operating system's
/// exclusive advisory lock (`flock` on Unix, `LockFileEx` on Windows), which the system
/// releases when the process ends in any way (also SIGKILL or a lost node's expired NFS
/// lease), so a lock left behind is never mistaken for a live one, whatever process now has
/// its pid, and a run on another node of a shared file system is seen. The file names the
/// holder (pid and host) for the message of a refused run. On a file system without locks
/// (ENOLCK, a Lustre mount without `flock`) the holder's pid alone decides, as a fallback.
fn take_lock(lock: &Path) -> Result<std::fs::File> {
    // A holder that ends removes the path while still locked; a run that opened the old file
    // just before may lock it then: it finds the path gone or new, and opens again.
    for _ in 0..3 {
        let mut file = open_no_follow(lock, false).map_err(|e| {
            if e.kind() == std::io::ErrorKind::Other {
                anyhow::anyhow!("cannot take the lock: {e}")
            } else {
                anyhow::anyhow!(
                    "cannot create the lock {} (is the folder writable?): {e}",
                    lock.display()
                )
            }
        })?;
        match file.try_lock() {
            Ok(()) if !names_file(lock, &file) => continue,
            Ok(()) => {
                write_holder(&mut file, lock)?;
                return Ok(file);
            }
            Err(std::fs::TryLockError::WouldBlock) => return Err(busy(lock)),
            Err(std::fs::TryLockError::Error(_)) => {
                let holder = std::fs::read_to_string(lock).unwrap_or_default();
                if holder_pid(&holder)
                    .is_some_and(|pid| pid != std::process::id() && process_alive(pid))
                {
                    return Err(busy(lock));
                }
                write_holder(&mut file, lock)?;
                return Ok(file);
            }
        }
    }
    bail!(
        "cannot take the lock {}: other runs took and released it at the same moment",
        lock.display()
    )
}

/// The system's exclusive advisory lock (`flock`) on the open folder `dir`, the lock every
/// slosh process that writes into a folder holds on it (runs, sweeps, assessments).
pub enum FolderLock {
    /// Taken: held until the file is dropped (or the process ends in any way).
    Held(std::fs::File),
    /// Another process holds it.
    Busy,
    /// The folder cannot be opened or its file system cannot lock a folder.
    Unsupported,
}

/// Tries to take [`FolderLock`] on `dir` without waiting.
pub fn try_lock_folder(dir: &Path) -> FolderLock {
    let Ok(folder) = std::fs::File::open(dir) else {
        return FolderLock::Unsupported;
    };
    match folder.try_lock() {
        Ok(()) => FolderLock::Held(folder),
        Err(std::fs::TryLockError::WouldBlock) => FolderLock::Busy,
        Err(std::fs::TryLockError::Error(_)) => FolderLock::Unsupported,
    }
}

/// Locks the folder `dir` itself for this process ([`try_lock_folder`]), the second lock
/// beside the lock file `lock`: a run that finds the file gone (removed by hand) still finds
/// the folder held, and is refused before it writes anything. `None` where the file system
/// cannot lock a folder.
fn lock_folder(dir: &Path, lock: &Path) -> Result<Option<std::fs::File>> {
    match try_lock_folder(dir) {
        FolderLock::Held(folder) => Ok(Some(folder)),
        FolderLock::Busy if std::fs::symlink_metadata(lock).is_ok() => Err(busy(lock)),
        FolderLock::Busy => bail!(
            "{} is held by another slosh command: a run whose lock file {LOCK_FILE} was \
             removed, or a sweep or an assessment using this folder; wait for it to end, stop \
             it, or choose another --out folder",
            dir.display()
        ),
        FolderLock::Unsupported => Ok(None),
    }
}

/// The error of a folder whose lock `lock` another run holds, naming it.
fn busy(lock: &Path) -> anyhow::Error {
    let holder = std::fs::read_to_string(lock).unwrap_or_default();
    anyhow::anyhow!(
        "{} is being written by another slosh run ({}); wait for it to end, stop it, or choose \
         another --out folder",
        lock.parent().unwrap_or(lock).display(),
        describe_holder(&holder)
    )
}

/// Writes this process's pid and host into the lock file, in place of an earlier holder's.
fn write_holder(file: &mut std::fs::File, lock: &Path) -> Result<()> {
    use std::io::Seek;
    let text = match host_name() {
        Some(host) => format!("{} {host}", std::process::id()),
        None => std::process::id().to_string(),
    };
    file.set_len(0)
        .and_then(|()| file.rewind())
        .and_then(|()| file.write_all(text.as_bytes()))
        .with_context(|| format!("cannot write the lock {}", lock.display()))
}

/// The pid of the lock file's text ("PID" or "PID HOST").
fn holder_pid(text: &str) -> Option<u32> {
    text.split_whitespace().next()?.parse().ok()
}

/// "pid N on HOST", "pid N", or "its pid not yet written" for a lock file's text.
fn describe_holder(text: &str) -> String {
    let mut words = text.split_whitespace();
    match (holder_pid(text), words.nth(1)) {
        (Some(pid), Some(host)) => format!("pid {pid} on {host}"),
        (Some(pid), None) => format!("pid {pid}"),
        (None, _) => "its pid not yet written".to_string(),
    }
}

/// The machine's host name (Linux; `None` elsewhere), to tell the nodes of a cluster apart in
/// a lock's message.
fn host_name() -> Option<String> {
    let name = std::fs::read_to_string("/proc/sys/kernel/hostname").ok()?;
    let name = name.trim();
    (!name.is_empty()).then(|| name.to_string())
}

/// Whether `path` still names the open `file` (Unix: the same device and inode; elsewhere
/// a locked file cannot be removed, so it does).
fn names_file(path: &Path, file: &std::fs::File) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(path), file.metadata()) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (path, file);
        true
    }
}

/// True when a process with this id runs (Linux: `/proc/<pid>` exists; elsewhere a lock is
/// always taken as live, the safe side); the fallback of file systems without locks.
fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new(&format!("/proc/{pid}")).exists()
    } else {
        true
    }
}

/// Whether `name` is `base` or one of its temporary siblings (`.tmp`, `.part`).
fn is_or_temp_of(name: &str, base: &str) -> bool {
    name.strip_prefix(base)
        .is_some_and(|rest| rest.is_empty() || rest == ".tmp" || rest == ".part")
}

/// Whether the file at `rel` (relative to the run folder, as its components) is one a run
/// writes; `chosen` are the stems of [`OUTPUTS_FILE`] (`post/NAME`).
fn generated(rel: &[&str], chosen: &[String]) -> bool {
    let drawn = |name: &str, stem: &str| {
        name.strip_prefix(stem)
            .is_some_and(|ext| matches!(ext, ".png" | ".svg" | ".part.png" | ".part.svg"))
    };
    match rel {
        [name] => {
            GENERATED_FILES.iter().any(|f| is_or_temp_of(name, f))
                || KNOWN_FILES.contains(name)
                || *name == OUTPUTS_FILE
        }
        ["checkpoint", name] => ["run.ron", "state.bin"]
            .iter()
            .any(|f| is_or_temp_of(name, f)),
        ["frames", name] => {
            is_or_temp_of(name, "frames.pvd")
                || name
                    .strip_prefix("frame_")
                    .and_then(|r| {
                        r.strip_suffix(".vtp")
                            .or_else(|| r.strip_suffix(".vtp.tmp"))
                    })
                    .is_some_and(|n| n.len() >= 6 && n.bytes().all(|b| b.is_ascii_digit()))
        }
        ["plots", name] => PLOT_STEMS.iter().any(|stem| drawn(name, stem)),
        [".series-rewrite", name] => {
            is_or_temp_of(name, "series.csv") || is_or_temp_of(name, "series_units.csv")
        }
        ["post", name] => chosen.iter().any(|c| {
            c.strip_prefix("post/").is_some_and(|stem| {
                drawn(name, stem)
                    || name
                        .strip_prefix(stem)
                        .is_some_and(|ext| ext == ".csv" || ext == ".csv.part")
            })
        }),
        _ => false,
    }
}

/// The files of the run folder `dir` that an earlier run wrote (relative paths, folders
/// last), after checking every entry at every depth without following links: anything that
/// is not a file slosh writes (a file of another name, another folder, a link, a device) is
/// refused with its path, and nothing is touched.
fn earlier_outputs(dir: &Path) -> Result<Vec<PathBuf>> {
    let chosen: Vec<String> = std::fs::read_to_string(dir.join(OUTPUTS_FILE))
        .unwrap_or_default()
        .lines()
        .map(str::to_string)
        .collect();
    let list = |d: &Path| -> Result<Vec<std::fs::DirEntry>> {
        std::fs::read_dir(d)
            .with_context(|| format!("cannot list the output folder {}", d.display()))?
            .map(|e| e.with_context(|| format!("cannot list {}", d.display())))
            .collect()
    };
    let mut files = Vec::new();
    let mut folders = Vec::new();
    let mut foreign: Vec<String> = Vec::new();
    // `post/` files of a run made before runs recorded their names: they look like slosh's,
    // but nothing proves it, so they are neither removed nor called someone else's.
    let mut unproven: Vec<String> = Vec::new();
    for entry in list(dir)? {
        let name = entry.file_name().to_string_lossy().into_owned();
        let kind = entry.file_type()?;
        if kind.is_dir() && GENERATED_DIRS.contains(&name.as_str()) {
            for inner in list(&entry.path())? {
                let inner_name = inner.file_name().to_string_lossy().into_owned();
                let inner_kind = inner.file_type()?;
                let rel = format!("{name}/{inner_name}");
                if inner_kind.is_file() && generated(&[&name, &inner_name], &chosen) {
                    files.push(PathBuf::from(rel));
                } else if name == "post"
                    && chosen.is_empty()
                    && inner_kind.is_file()
                    && looks_like_post_output(&inner_name)
                {
                    unproven.push(rel);
                } else {
                    foreign.push(describe(&rel, &inner_kind));
                }
            }
            folders.push(PathBuf::from(&name));
        } else if kind.is_file() && generated(&[&name], &chosen) {
            if !KNOWN_FILES.contains(&name.as_str()) {
                files.push(PathBuf::from(&name));
            }
        } else {
            foreign.push(describe(&name, &kind));
        }
    }
    if foreign.is_empty() && !unproven.is_empty() {
        unproven.sort();
        bail!(
            "the output folder {} holds post-processing outputs ({}) of a run made before slosh \
             recorded the names it chose ({OUTPUTS_FILE}), so nothing proves they are slosh's: \
             remove post/ yourself if they are, or choose a new or empty --out folder",
            dir.display(),
            unproven
                .iter()
                .take(5)
                .map(String::as_str)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    foreign.extend(unproven);
    if !foreign.is_empty() {
        foreign.sort();
        let shown: Vec<&str> = foreign.iter().take(5).map(String::as_str).collect();
        bail!(
            "the output folder {} holds what no slosh run wrote ({}{}); slosh removes only its \
             own files and writes through no link: move them away, or choose a new or empty \
             --out folder",
            dir.display(),
            shown.join(", "),
            if foreign.len() > 5 {
                format!(" and {} more", foreign.len() - 5)
            } else {
                String::new()
            }
        );
    }
    files.extend(folders);
    Ok(files)
}

/// Whether `name` has the shape of a file a script's `post` writes (`[A-Za-z0-9_-]+` with a
/// table's or plot's extension).
fn looks_like_post_output(name: &str) -> bool {
    [".csv", ".png", ".svg"].iter().any(|ext| {
        name.strip_suffix(ext).is_some_and(|stem| {
            !stem.is_empty()
                && stem
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        })
    })
}

/// A folder entry for the refusal's list: a link or another kind of file says what it is.
fn describe(rel: &str, kind: &std::fs::FileType) -> String {
    if kind.is_symlink() {
        format!("{rel} (a link)")
    } else if kind.is_dir() {
        format!("{rel}/")
    } else if kind.is_file() {
        rel.to_string()
    } else {
        format!("{rel} (not a file)")
    }
}

/// A folder is a run folder when it is empty, or holds only what a run writes.
fn check_is_run_folder(dir: &Path) -> Result<()> {
    earlier_outputs(dir).map(|_| ())
}

/// Removes the outputs of an earlier run (its summary, series, roof files, frames, plots and
/// post-processing), so that nothing stale stands beside the new run's files: file by file,
/// each proven to be slosh's ([`earlier_outputs`]), then the folders they leave empty (a
/// folder that is not empty by then is kept with what it holds).
fn remove_earlier_outputs(dir: &Path) -> Result<()> {
    for rel in earlier_outputs(dir)? {
        let p = dir.join(&rel);
        if GENERATED_DIRS.iter().any(|d| rel == Path::new(d)) {
            let _ = std::fs::remove_dir(&p);
        } else {
            std::fs::remove_file(&p)
                .with_context(|| format!("cannot remove the earlier run's {}", p.display()))?;
        }
    }
    Ok(())
}

/// Records that the run in `out` writes `rel_stem` (`post/NAME`), before it creates the file:
/// the next run in the folder removes it as its own ([`OUTPUTS_FILE`]).
pub fn record_output(out: &Path, rel_stem: &str) -> Result<()> {
    let path = out.join(OUTPUTS_FILE);
    let known = std::fs::read_to_string(&path).unwrap_or_default();
    if known.lines().any(|l| l == rel_stem) {
        return Ok(());
    }
    let mut file =
        open_no_follow(&path, true).with_context(|| format!("cannot write {}", path.display()))?;
    file.write_all(format!("{rel_stem}\n").as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Opens `path` for writing (appending when `append`, otherwise keeping its contents), creating
/// it when missing, never through a link (`O_NOFOLLOW`: a link there is an error).
fn open_no_follow(path: &Path, append: bool) -> std::io::Result<std::fs::File> {
    slosh_io::open_no_follow(
        path,
        std::fs::OpenOptions::new()
            .read(!append)
            .write(true)
            .append(append)
            .create(true)
            .truncate(false),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join("slosh-run-folder").join(name);
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn earlier_outputs_go_and_the_lock_holds() {
        let d = temp("earlier");
        std::fs::write(d.join("summary.ron"), "(status: \"completed\")").unwrap();
        std::fs::create_dir_all(d.join("plots")).unwrap();
        std::fs::write(d.join("plots/fig7_a.png"), "x").unwrap();
        std::fs::write(d.join("run.log"), "kept").unwrap();
        let claim = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap();
        assert!(!d.join("plots").exists());
        assert!(d.join("run.log").exists());
        let s = std::fs::read_to_string(d.join("summary.ron")).unwrap();
        assert!(s.contains("status: \"running\""), "{s}");
        // A second claim while the first holds the lock is refused, naming the holder (the
        // system's lock conflicts between two opens of the file, even in one process).
        let err = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap_err();
        let pid = format!("pid {}", std::process::id());
        assert!(err.to_string().contains(&pid), "{err}");
        drop(claim);
        assert!(!d.join(LOCK_FILE).exists());
        drop(RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap());
    }

    /// A lock file that no process holds is taken over whatever pid it names: one of a
    /// process that has ended, and one whose pid a live process has since been given
    /// (pid 1, init, always runs) — after a restart, a killed run's pid is often reused.
    #[test]
    fn a_lock_nobody_holds_is_taken_over_whatever_pid_it_names() {
        let d = temp("unheld");
        for text in ["99999999", "1", "1 another-node", ""] {
            std::fs::write(d.join(LOCK_FILE), text).unwrap();
            let claim = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap();
            let written = std::fs::read_to_string(d.join(LOCK_FILE)).unwrap();
            assert_eq!(holder_pid(&written), Some(std::process::id()), "{written}");
            drop(claim);
        }
    }

    /// `post/` files go with the run when its record names them; without a record (a folder
    /// of an older slosh) they are kept and the run is refused with why.
    #[test]
    fn post_outputs_go_only_when_the_record_names_them() {
        let d = temp("post");
        std::fs::write(d.join("summary.ron"), "(status: \"completed\")").unwrap();
        std::fs::create_dir_all(d.join("post")).unwrap();
        std::fs::write(d.join("post/table.csv"), "t\n").unwrap();
        let err = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap_err();
        assert!(err.to_string().contains("post/table.csv"), "{err}");
        assert!(err.to_string().contains(OUTPUTS_FILE), "{err}");
        assert!(d.join("post/table.csv").exists());
        record_output(&d, "post/table").unwrap();
        record_output(&d, "post/table").unwrap();
        assert_eq!(
            std::fs::read_to_string(d.join(OUTPUTS_FILE)).unwrap(),
            "post/table\n"
        );
        std::fs::write(d.join("post/notes.txt"), "mine").unwrap();
        let err = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap_err();
        assert!(err.to_string().contains("post/notes.txt"), "{err}");
        std::fs::remove_file(d.join("post/notes.txt")).unwrap();
        drop(RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap());
        assert!(!d.join("post").exists());
        assert!(!d.join(OUTPUTS_FILE).exists());
    }

    #[test]
    fn a_foreign_folder_is_refused_untouched() {
        let f = temp("foreign");
        std::fs::write(f.join("thesis.tex"), "mine").unwrap();
        let err = RunFolder::claim(&f, "c", Path::new("c.rhai")).unwrap_err();
        assert!(err.to_string().contains("thesis.tex"), "{err}");
        assert!(f.join("thesis.tex").exists());
    }
}
