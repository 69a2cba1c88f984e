//! The output folder of one run: locked while the run writes it, emptied of an earlier run's
//! outputs before it starts, and never taken over from a folder that holds other files.

use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock file: held under the operating system's lock by the run that writes the folder,
/// and naming it (process id and host).
pub const LOCK_FILE: &str = ".slosh.lock";

/// Files and folders a run writes (and removes again before the next run in the same folder).
const GENERATED_FILES: [&str; 7] = [
    "series.csv",
    "series_units.csv",
    "summary.ron",
    "roof_pressure.csv",
    "roof_points.csv",
    "roof_points.vtp",
    "input_spectrum.csv",
];
const GENERATED_DIRS: [&str; 4] = ["frames", "plots", "post", "checkpoint"];
/// Files another slosh command writes into a run folder (a sweep's log of the case).
const KNOWN_FILES: [&str; 2] = ["run.log", LOCK_FILE];

/// A run's claim on its output folder; the lock is released when it is dropped.
#[derive(Debug)]
pub struct RunFolder {
    dir: PathBuf,
    lock: PathBuf,
    /// The open lock file, locked until it is closed (after the path is removed).
    _held: std::fs::File,
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
        let held = take_lock(&lock)?;
        let folder = RunFolder {
            dir: dir.to_path_buf(),
            lock,
            _held: held,
            case: case.to_string(),
            script: script.display().to_string(),
        };
        check_is_run_folder(dir)?;
        Ok(folder)
    }

    /// After a run that stopped with `error` before writing its own summary (a bad tank, a
    /// refused setting): `summary.ron` says `status: "failed"` with the error instead of
    /// "running".
    pub fn mark_failed_if_running(&self, error: &str) {
        let summary = std::fs::read_to_string(self.dir.join("summary.ron")).unwrap_or_default();
        if summary.contains("status: \"running\"") {
            let _ = self.write_short_summary("failed", Some(error));
        }
    }

    fn write_short_summary(&self, status: &str, error: Option<&str>) -> Result<()> {
        slosh_io::write_ron(
            self.dir.join("summary.ron"),
            &ShortSummary {
                version: env!("CARGO_PKG_VERSION"),
                case: &self.case,
                script: &self.script,
                status,
                pid: std::process::id(),
                error,
            },
        )?;
        Ok(())
    }
}

impl Drop for RunFolder {
    fn drop(&mut self) {
        // Removed while still locked; the lock ends when `_held` closes just after.
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
        let mut file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(lock)
            .with_context(|| {
                format!(
                    "cannot create the lock {} (is the folder writable?)",
                    lock.display()
                )
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

/// A folder is a run folder when it is empty, or holds what a run writes.
fn check_is_run_folder(dir: &Path) -> Result<()> {
    let names: Vec<String> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot list the output folder {}", dir.display()))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect();
    let ours = |n: &String| {
        GENERATED_FILES.contains(&n.as_str())
            || GENERATED_DIRS.contains(&n.as_str())
            || KNOWN_FILES.contains(&n.as_str())
    };
    let foreign: Vec<&String> = names.iter().filter(|n| !ours(n)).collect();
    let is_run = names
        .iter()
        .any(|n| n == "summary.ron" || n == "series.csv" || n == "run.log");
    if !foreign.is_empty() && !is_run {
        let shown: Vec<&str> = foreign.iter().take(3).map(|s| s.as_str()).collect();
        bail!(
            "the output folder {} holds files that no slosh run wrote ({}{}); choose a new or \
             empty --out folder so that nothing of yours is overwritten",
            dir.display(),
            shown.join(", "),
            if foreign.len() > 3 { ", …" } else { "" }
        );
    }
    Ok(())
}

/// Removes the outputs of an earlier run (its summary, series, roof files, frames, plots and
/// post-processing), so that nothing stale stands beside the new run's files.
fn remove_earlier_outputs(dir: &Path) -> Result<()> {
    for f in GENERATED_FILES {
        let p = dir.join(f);
        if p.exists() {
            std::fs::remove_file(&p)
                .with_context(|| format!("cannot remove the earlier run's {}", p.display()))?;
        }
    }
    for d in GENERATED_DIRS {
        let p = dir.join(d);
        let removed = match std::fs::symlink_metadata(&p) {
            Ok(m) if m.is_dir() => std::fs::remove_dir_all(&p),
            Ok(_) => std::fs::remove_file(&p),
            Err(_) => Ok(()),
        };
        removed.with_context(|| format!("cannot remove the earlier run's {}", p.display()))?;
    }
    Ok(())
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

    #[test]
    fn a_foreign_folder_is_refused_untouched() {
        let f = temp("foreign");
        std::fs::write(f.join("thesis.tex"), "mine").unwrap();
        let err = RunFolder::claim(&f, "c", Path::new("c.rhai")).unwrap_err();
        assert!(err.to_string().contains("thesis.tex"), "{err}");
        assert!(f.join("thesis.tex").exists());
    }
}
