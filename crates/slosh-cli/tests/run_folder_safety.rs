//! A run folder holds only slosh's own files, at every depth: a user's file anywhere in it,
//! or a link planted where slosh writes, makes the run stop before it touches anything; a lock
//! file removed by hand does not let a second run in; names (an `--out` folder in a batch
//! script, a motion's name in `assess.ron` or a suite) stay data, never a line of a script or
//! a path outside the assessment.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_slosh"))
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-folder-safety").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small 2D tank (0.4 m wide, 0.2 m of water, a roof at 0.26 m) under a sine of
/// acceleration `amp`, `duration` s in all.
fn case(dir: &Path, duration: f64) -> PathBuf {
    let script = format!(
        "let amp = param(\"amp\", 1.0);\n\
         tank(#{{ shape: \"rect\", width: 0.4, height: 0.26, depth: 0.2, roof: true }});\n\
         numerics(#{{ dx: 0.02 }});\n\
         run(#{{ settle: 0.0, duration: {duration}, output_interval: 0.005 }});\n\
         fn ground_accel(t) {{ amp * sin(8.0 * t) }}\n"
    );
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

fn slosh(args: &[&str]) -> Output {
    Command::new(exe()).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn run_into(c: &Path, out: &Path) -> Output {
    Command::new(exe())
        .args(["run", c.to_str().unwrap(), "--quiet", "--out"])
        .arg(out)
        .output()
        .unwrap()
}

/// A folder of an earlier run where the user added files of their own inside slosh's
/// sub-folders (or a `series.csv` beside a paper): the run stops, names them and deletes
/// nothing; the same folder with only slosh's files is cleaned and run.
#[test]
fn users_files_inside_the_folders_of_a_run_are_never_deleted() {
    let dir = temp("users_files");
    let c = case(&dir, 0.02);
    let out = dir.join("out");
    assert!(run_into(&c, &out).status.success());
    let mine = [
        ("plots/fig.png", "my figure"),
        ("post/notes.txt", "my notes"),
        ("frames/mine.vtp", "my frame"),
        ("checkpoint/keep.bin", "my state"),
    ];
    for (rel, content) in mine {
        std::fs::create_dir_all(out.join(rel).parent().unwrap()).unwrap();
        std::fs::write(out.join(rel), content).unwrap();
        let o = run_into(&c, &out);
        assert!(!o.status.success(), "{rel}: {}", text(&o));
        assert!(text(&o).contains(rel), "{rel} not named: {}", text(&o));
        assert_eq!(std::fs::read_to_string(out.join(rel)).unwrap(), content);
        assert!(
            out.join("series.csv").exists(),
            "the earlier run's files are kept too"
        );
        std::fs::remove_file(out.join(rel)).unwrap();
    }
    // A folder of a paper beside a log and a figure is not a run folder.
    let paper = dir.join("paper");
    std::fs::create_dir_all(paper.join("plots")).unwrap();
    std::fs::write(paper.join("run.log"), "mine").unwrap();
    std::fs::write(paper.join("paper.tex"), "mine").unwrap();
    std::fs::write(paper.join("plots/figure1.png"), "mine").unwrap();
    let o = run_into(&c, &paper);
    assert!(!o.status.success());
    assert!(text(&o).contains("paper.tex"), "{}", text(&o));
    assert_eq!(
        std::fs::read_to_string(paper.join("plots/figure1.png")).unwrap(),
        "mine"
    );
    // With only slosh's files the folder is run again.
    assert!(run_into(&c, &out).status.success());
}

/// A link planted where slosh writes (its lock, a temporary summary, a roof table's part, the
/// series' staging folder) is refused at the claim; the file it points to is untouched.
#[cfg(unix)]
#[test]
fn links_planted_in_a_run_folder_are_never_written_through() {
    let dir = temp("links");
    let c = case(&dir, 0.02);
    for planted in [
        ".slosh.lock",
        "summary.ron.tmp",
        "roof_pressure.csv.part",
        ".series-rewrite",
        "plots/eta.png",
    ] {
        let out = dir.join(format!("out-{}", planted.replace('/', "_")));
        let victim = dir.join(format!("victim-{}", planted.replace('/', "_")));
        std::fs::write(&victim, "precious").unwrap();
        let link = out.join(planted);
        std::fs::create_dir_all(link.parent().unwrap()).unwrap();
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let o = run_into(&c, &out);
        assert!(!o.status.success(), "{planted}: {}", text(&o));
        assert!(text(&o).contains("link"), "{planted}: {}", text(&o));
        assert_eq!(
            std::fs::read_to_string(&victim).unwrap(),
            "precious",
            "written through {planted}"
        );
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
    }
}

/// Two runs never share a folder, even when the first run's lock file is removed by hand:
/// the running process also holds the folder.
#[test]
fn a_lock_removed_by_hand_does_not_let_a_second_run_in() {
    let dir = temp("lock_removed");
    let c = case(&dir, 30.0);
    let out = dir.join("out");
    let mut first = Command::new(exe())
        .args(["run", c.to_str().unwrap(), "--quiet", "--out"])
        .arg(&out)
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while !out.join(".slosh.lock").exists() || !out.join("series.csv").exists() {
        assert!(
            started.elapsed().as_secs() < 60,
            "the first run did not start"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::fs::remove_file(out.join(".slosh.lock")).unwrap();
    let o = run_into(&c, &out);
    let _ = first.kill();
    let _ = first.wait();
    assert!(!o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("held by another slosh command: a run whose lock file"),
        "{}",
        text(&o)
    );
}

/// `--out` with a newline (which would split the batch script's `#SBATCH --output=` line and
/// run what follows) is refused before anything is written, for assessments and sweeps.
#[test]
fn a_folder_name_never_becomes_a_line_of_the_batch_script() {
    let dir = temp("slurm_names");
    let c = case(&dir, 0.02);
    let suite = dir.join("suite.csv");
    std::fs::write(&suite, "name,amp\na,1.0\n").unwrap();
    let out = dir.join("SN7\ntouch pwned #");
    let o = slosh(&[
        "assess",
        c.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--slurm",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("control character"), "{}", text(&o));
    assert!(!out.exists(), "the folder was created before the refusal");
    let o = slosh(&[
        "sweep",
        c.to_str().unwrap(),
        "--vary",
        "amp=1,2",
        "--slurm",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("control character"), "{}", text(&o));
    assert!(!out.exists(), "the folder was created before the refusal");
}

/// A motion's name read back from `assess.ron` (edited by hand to `../../victim`) or from a
/// suite (`..`) is refused: no run is written outside `runs/`, and nothing there is deleted.
#[test]
fn a_motion_name_never_leads_outside_the_assessment() {
    let dir = temp("motion_names");
    let c = case(&dir, 0.02);
    let suite = dir.join("suite.csv");
    std::fs::write(&suite, "name,amp\ngentle,1.0\n").unwrap();
    let out = dir.join("assess");
    let o = slosh(&[
        "assess",
        c.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--slurm",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let manifest = out.join("assess.ron");
    let ron = std::fs::read_to_string(&manifest).unwrap();
    assert!(ron.contains("\"gentle\""), "{ron}");
    std::fs::write(&manifest, ron.replace("\"gentle\"", "\"../../victim\"")).unwrap();
    let victim = dir.join("victim");
    std::fs::create_dir_all(victim.join("plots")).unwrap();
    std::fs::write(victim.join("plots/precious.png"), "precious").unwrap();
    let o = slosh(&["assess", "--task", "0", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("not a plain folder name"), "{}", text(&o));
    assert_eq!(
        std::fs::read_to_string(victim.join("plots/precious.png")).unwrap(),
        "precious"
    );
    assert!(!victim.join("summary.ron").exists());

    for name in ["..", "."] {
        std::fs::write(&suite, format!("name,amp\n{name},1.0\n")).unwrap();
        let o = slosh(&[
            "assess",
            c.to_str().unwrap(),
            "--motions",
            suite.to_str().unwrap(),
            "--out",
            dir.join(format!("assess-{}", name.len())).to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{name}: {}", text(&o));
        assert!(
            text(&o).contains("suite.csv:2"),
            "{name}: the refusal names the row: {}",
            text(&o)
        );
    }
}

/// A sweep killed outright (SIGKILL, which it cannot pass on) does not leave its case running
/// unwatched: the case gets SIGTERM from the system, stops with a checkpoint as on a time
/// limit, and releases its folder, so the sweep can be run again.
#[cfg(target_os = "linux")]
#[test]
fn a_killed_sweep_takes_its_running_case_with_it() {
    let dir = temp("killed_sweep");
    let c = case(&dir, 60.0);
    let out = dir.join("sweep");
    let mut sweep = Command::new(exe())
        .args([
            "sweep",
            c.to_str().unwrap(),
            "--vary",
            "amp=1,2",
            "--jobs",
            "1",
            "--quiet",
        ])
        .arg("--out")
        .arg(&out)
        .spawn()
        .unwrap();
    // The first case's folder, once its run has written a few rows.
    let started = std::time::Instant::now();
    let case_dir = loop {
        let running = std::fs::read_dir(&out).ok().and_then(|entries| {
            entries.filter_map(|e| e.ok()).map(|e| e.path()).find(|d| {
                std::fs::read_to_string(d.join("series.csv")).is_ok_and(|t| t.lines().count() >= 5)
            })
        });
        if let Some(d) = running {
            break d;
        }
        assert!(started.elapsed().as_secs() < 60, "the case did not start");
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    sweep.kill().unwrap();
    let _ = sweep.wait();
    let started = std::time::Instant::now();
    loop {
        let summary = std::fs::read_to_string(case_dir.join("summary.ron")).unwrap_or_default();
        if summary.contains("status: \"interrupted\"") {
            break;
        }
        assert!(
            started.elapsed().as_secs() < 30,
            "the case runs on after its sweep was killed: {summary}"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    // Its folder is free again: the lock is released.
    let started = std::time::Instant::now();
    while case_dir.join(".slosh.lock").exists() {
        assert!(
            started.elapsed().as_secs() < 30,
            "the case still holds its folder"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// A link planted where a sweep writes its batch script (`sweep.sbatch`) or an assessment its
/// manifest and batch script is refused: the link's target is neither written nor made
/// executable.
#[test]
fn links_planted_where_the_batch_script_goes_are_never_written_through() {
    let dir = temp("slurm_links");
    let c = case(&dir, 0.02);
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "mine").unwrap();
    let out = dir.join("sweep");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink(&victim, out.join("sweep.sbatch")).unwrap();
    let o = slosh(&[
        "sweep",
        c.to_str().unwrap(),
        "--vary",
        "amp=1,2",
        "--slurm",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("link"), "{}", text(&o));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "mine");
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&victim).unwrap().permissions().mode();
    assert_eq!(mode & 0o111, 0, "the link's target was made executable");

    let suite = dir.join("suite.csv");
    std::fs::write(&suite, "name,amp\na,1.0\n").unwrap();
    for planted in ["assess.ron", "assess.sbatch"] {
        let out = dir.join(format!("assess_{planted}"));
        std::fs::create_dir_all(&out).unwrap();
        std::os::unix::fs::symlink(&victim, out.join(planted)).unwrap();
        let o = slosh(&[
            "assess",
            c.to_str().unwrap(),
            "--motions",
            suite.to_str().unwrap(),
            "--slurm",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{planted}: {}", text(&o));
        assert_eq!(
            std::fs::read_to_string(&victim).unwrap(),
            "mine",
            "{planted}"
        );
    }
}
