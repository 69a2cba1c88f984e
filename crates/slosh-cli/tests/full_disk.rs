//! A full disk during a run: the run stops with an error that says what is kept, `series.csv`
//! ends on a whole row, no partial file of slosh's is left behind, `summary.ron` says
//! "failed" with the reason, and the last good checkpoint continues the run once there is room.
//!
//! As root where tmpfs can be mounted (CI), the disk is a 1 MiB tmpfs, so that every file —
//! the summary too — meets the full disk. Elsewhere the write failure is injected with the
//! process's file-size limit (`RLIMIT_FSIZE`, each file at most 1 MiB; writes past it fail
//! with EFBIG as a full disk fails them with ENOSPC).

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// 0.8 m × 0.4 m of water at dx = 0.02 m, 3 s with a row every 0.5 ms (≈ 300 bytes a row):
/// `series.csv` alone passes 1 MiB after ≈ 1.7 s of simulated time, and each checkpoint holds
/// the whole series so far.
const CASE: &str = "tank(#{ shape: \"rect\", width: 0.8, height: 0.6, depth: 0.4 });\n\
                    numerics(#{ dx: 0.02 });\n\
                    run(#{ settle: 0.0, duration: 3.0, output_interval: 0.0005, \
                    frame_interval: 0.0 });\n\
                    fn ground_accel(t) { 0.1 * sin(5.0 * t) }\n";

const LIMIT_BYTES: u64 = 1 << 20;

/// Where the disk fills: a small tmpfs, or a file-size limit on the process.
enum FullDisk {
    Tmpfs(PathBuf),
    FileSizeLimit,
}

impl FullDisk {
    fn set_up(dir: &Path) -> FullDisk {
        let mount = dir.join("disk");
        std::fs::create_dir_all(&mount).unwrap();
        // SAFETY: geteuid has no preconditions.
        if unsafe { libc::geteuid() } == 0 {
            let ok = Command::new("mount")
                .args(["-t", "tmpfs", "-o", "size=1m", "tmpfs"])
                .arg(&mount)
                .output()
                .is_ok_and(|o| o.status.success());
            if ok {
                return FullDisk::Tmpfs(mount);
            }
        }
        eprintln!("full_disk: no tmpfs here; the write failures come from RLIMIT_FSIZE");
        FullDisk::FileSizeLimit
    }

    fn out(&self, dir: &Path) -> PathBuf {
        match self {
            FullDisk::Tmpfs(mount) => mount.join("run"),
            FullDisk::FileSizeLimit => dir.join("run"),
        }
    }

    fn command(&self) -> Command {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_slosh"));
        if let FullDisk::FileSizeLimit = self {
            // SAFETY: only async-signal-safe calls (signal, setrlimit) between fork and exec.
            unsafe {
                cmd.pre_exec(|| {
                    libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
                    let limit = libc::rlimit {
                        rlim_cur: LIMIT_BYTES as libc::rlim_t,
                        rlim_max: LIMIT_BYTES as libc::rlim_t,
                    };
                    if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                    Ok(())
                });
            }
        }
        cmd
    }

    /// Gives the run room to go on.
    fn make_room(&self) {
        if let FullDisk::Tmpfs(mount) = self {
            let o = Command::new("mount")
                .args(["-o", "remount,size=64m"])
                .arg(mount)
                .output()
                .unwrap();
            assert!(o.status.success(), "{o:?}");
        }
    }
}

impl Drop for FullDisk {
    fn drop(&mut self) {
        if let FullDisk::Tmpfs(mount) = self {
            let _ = Command::new("umount").arg(mount).output();
        }
    }
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Every file under `dir` (no links followed).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if std::fs::symlink_metadata(&path).unwrap().is_dir() {
            all.extend(files(&path));
        } else {
            all.push(path);
        }
    }
    all
}

#[test]
fn a_full_disk_stops_the_run_with_whole_rows_a_failed_summary_and_a_checkpoint_to_resume() {
    let dir = std::env::temp_dir().join("slosh-full-disk");
    if dir.join("disk").exists() {
        let _ = Command::new("umount").arg(dir.join("disk")).output();
    }
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let script = dir.join("case.rhai");
    std::fs::write(&script, CASE).unwrap();
    let disk = FullDisk::set_up(&dir);
    let out = disk.out(&dir);

    let o = disk
        .command()
        .args([
            "run",
            script.to_str().unwrap(),
            "--quiet",
            "--checkpoint-every",
            "0.2s",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let said = text(&o);
    assert!(!o.status.success(), "the run must fail: {said}");
    assert!(
        said.contains("could not be written")
            && said.contains("series.csv ends at its last whole row"),
        "{said}"
    );
    assert!(
        said.contains("slosh resume"),
        "a checkpoint must be kept: {said}"
    );

    // series.csv: whole rows only, each with the header's number of fields.
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert!(series.ends_with('\n'), "series.csv ends mid-row");
    let mut lines = series.lines();
    let n_columns = lines.next().unwrap().split(',').count();
    let rows: Vec<&str> = lines.collect();
    assert!(
        rows.len() > 100,
        "only {} rows before the disk filled",
        rows.len()
    );
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(
            row.split(',').count(),
            n_columns,
            "row {} is cut: {row}",
            i + 1
        );
    }
    // No temporary or partial file of slosh's is left to starve the disk.
    for f in files(&out) {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            !name.ends_with(".tmp") && !name.ends_with(".part"),
            "{} left behind",
            f.display()
        );
    }
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"failed\""), "{summary}");
    assert!(summary.contains("could not be written"), "{summary}");
    assert!(out.join("checkpoint/state.bin").is_file());

    // With room again, the kept checkpoint continues the run to its end.
    disk.make_room();
    let o = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["resume", "--quiet"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"completed\""), "{summary}");
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert_eq!(
        series.lines().count(),
        6001,
        "3 s at 0.5 ms: 6000 rows and the header"
    );
    drop(disk);
}
