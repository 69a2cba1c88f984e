//! The output folder of one run: locked while the run writes it, emptied of an earlier run's
//! outputs before it starts, and never taken over from a folder that holds other files.

use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock file: it holds the process id of the run that writes the folder.
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
        take_lock(&lock)?;
        let folder = RunFolder {
            dir: dir.to_path_buf(),
            lock,
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
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// Creates the lock file with this process's id; a lock left by a process that no longer
/// runs is replaced, one held by a live process is an error naming it.
fn take_lock(lock: &Path) -> Result<()> {
    for _ in 0..2 {
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut f) => {
                write!(f, "{}", std::process::id())
                    .with_context(|| format!("cannot write the lock {}", lock.display()))?;
                return Ok(());
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let holder = std::fs::read_to_string(lock)
                    .ok()
                    .and_then(|t| t.trim().parse::<u32>().ok());
                match holder {
                    Some(pid) if process_alive(pid) && pid != std::process::id() => bail!(
                        "{} is being written by another slosh run (pid {pid}); wait for it to \
                         end, stop it, or choose another --out folder",
                        lock.parent().unwrap_or(lock).display()
                    ),
                    _ => {
                        // Stale: its process has ended (or the file is unreadable).
                        let _ = std::fs::remove_file(lock);
                    }
                }
            }
            Err(e) => {
                return Err(e).with_context(|| {
                    format!(
                        "cannot create the lock {} (is the folder writable?)",
                        lock.display()
                    )
                })
            }
        }
    }
    bail!(
        "cannot take the lock {}: another run took it at the same moment",
        lock.display()
    )
}

/// True when a process with this id runs (Linux: `/proc/<pid>` exists; elsewhere a lock is
/// always taken as live, the safe side).
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
        // A second claim while this process holds it is refused only for another pid: fake
        // a live holder with pid 1 (init always runs).
        std::fs::write(d.join(LOCK_FILE), "1").unwrap();
        let err = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap_err();
        assert!(err.to_string().contains("pid 1"), "{err}");
        drop(claim);
        assert!(!d.join(LOCK_FILE).exists());
    }

    #[test]
    fn stale_lock_is_taken_over_and_foreign_folder_refused() {
        let d = temp("stale");
        // A pid that cannot run (beyond the kernel's pid_max of 2^22).
        std::fs::write(d.join(LOCK_FILE), "99999999").unwrap();
        let claim = RunFolder::claim(&d, "c", Path::new("c.rhai")).unwrap();
        drop(claim);
        let f = temp("foreign");
        std::fs::write(f.join("thesis.tex"), "mine").unwrap();
        let err = RunFolder::claim(&f, "c", Path::new("c.rhai")).unwrap_err();
        assert!(err.to_string().contains("thesis.tex"), "{err}");
        assert!(f.join("thesis.tex").exists());
    }
}
