//! `slosh assess`: a suite of motions runs into `runs/<name>/`, the report and its table are
//! written from the summaries, a second assessment reruns nothing, array tasks run one by one
//! and `--collect` give the same report as the local run, and bad suites are refused with the
//! file and line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_slosh"))
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-assess-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small 2D tank with a roof (0.4 m wide, 0.2 m of water, roof at 0.26 m) under a sine of
/// amplitude `amp` near its sloshing period, 0.6 s in all.
fn small_case(dir: &Path) -> PathBuf {
    let script = r#"
let amp = param("amp", 1.0);         // peak ground acceleration (m/s²)
let period = param("period", 0.75);  // sine period (s)
let dx = param("dx", 0.02);
tank(#{ shape: "rect", width: 0.4, height: 0.26, depth: 0.2, roof: true });
numerics(#{ dx: dx });
run(#{ settle: 0.0, duration: 0.6, output_interval: 0.005 });
fn ground_accel(t) { amp * sin(2.0 * PI() * t / period) }
"#;
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

/// The rows of a CSV table (the numbers need no quoting) without the columns that depend
/// on the wall clock or the thread count: `wall_time_s`, `particle_steps_per_s`,
/// `fluid_particle_steps_per_s` and `threads`.
fn table_without_timing(path: &Path) -> Vec<Vec<String>> {
    const TIMING: [&str; 4] = [
        "wall_time_s",
        "particle_steps_per_s",
        "fluid_particle_steps_per_s",
        "threads",
    ];
    let text = std::fs::read_to_string(path).unwrap();
    let rows: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert!(rows[0].iter().any(|c| c == "wall_time_s"), "{:?}", rows[0]);
    let keep: Vec<bool> = rows[0]
        .iter()
        .map(|c| !TIMING.contains(&c.as_str()))
        .collect();
    rows.into_iter()
        .map(|r| {
            r.into_iter()
                .zip(&keep)
                .filter(|(_, k)| **k)
                .map(|(c, _)| c)
                .collect()
        })
        .collect()
}

#[test]
fn local_assessment_reports_resumes_and_equals_task_by_task() {
    let dir = temp("local");
    let case = small_case(&dir);
    let suite = dir.join("suite.csv");
    std::fs::write(
        &suite,
        "name,amp\ngentle,0.5\nmedium,1.5\n# a comment\nstrong,3\n",
    )
    .unwrap();
    let local = dir.join("local");
    let o = slosh(&[
        "assess",
        case.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--out",
        local.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    assert!(out.contains("Freeboard 0.06"), "{out}");

    let rows = table_without_timing(&local.join("assessment.csv"));
    let header = &rows[0];
    assert_eq!(rows.len(), 4, "{rows:?}");
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    for (row, name) in rows[1..].iter().zip(["gentle", "medium", "strong"]) {
        assert_eq!(row[col("name")], name);
        assert_eq!(row[col("status")], "completed");
    }
    // The stronger the motion, the larger its spectrum and its waves; the code wave heights
    // scale with S_a(T_c) (ACI 350.3-06 Eq. 7-1: (L/2) S_a/g with L = 0.4 m).
    let num = |r: usize, c: &str| rows[r][col(c)].parse::<f64>().unwrap();
    assert!(num(1, "sa_tc_0p5pct_g") < num(2, "sa_tc_0p5pct_g"));
    assert!(num(2, "sa_tc_0p5pct_g") < num(3, "sa_tc_0p5pct_g"));
    assert!(num(1, "max_eta_m") < num(3, "max_eta_m"));
    for r in 1..=3 {
        let aci = num(r, "wave_height_aci_350_3_06_m");
        assert!((aci - 0.2 * num(r, "sa_tc_0p5pct_g")).abs() < 1e-9 * aci.max(1e-9));
        assert!((num(r, "pga_m_s2") - [0.5, 1.5, 3.0][r - 1]).abs() < 0.01);
    }
    let report = std::fs::read_to_string(local.join("assessment.md")).unwrap();
    for words in [
        "## Verdict",
        "Freeboard 0.06",
        "84th percentile",
        "plots/spectra.png",
    ] {
        assert!(report.contains(words), "{words} not in\n{report}");
    }
    for plot in ["wave_heights.png", "spectra.png"] {
        assert!(local.join("plots").join(plot).is_file(), "{plot}");
    }
    // The freeboard verdict counts the motions whose wave passed the freeboard.
    let exceeded = (1..=3).filter(|&r| num(r, "max_eta_m") > 0.06).count();
    assert!(
        report.contains(&format!("exceeded in {exceeded} of 3 motions")),
        "{report}"
    );

    // Again: nothing reruns.
    let summary = local.join("runs/medium/summary.ron");
    let before = std::fs::metadata(&summary).unwrap().modified().unwrap();
    let o = slosh(&[
        "assess",
        case.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--out",
        local.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        before,
        std::fs::metadata(&summary).unwrap().modified().unwrap()
    );

    // The Slurm way without Slurm: the batch script, one task at a time, then --collect.
    let tasks = dir.join("tasks");
    let o = slosh(&[
        "assess",
        case.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--out",
        tasks.to_str().unwrap(),
        "--slurm",
        "--time",
        "00:10:00",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let batch = std::fs::read_to_string(tasks.join("assess.sbatch")).unwrap();
    assert!(batch.contains("#SBATCH --array=0-2\n"), "{batch}");
    assert!(batch.contains("#SBATCH --time=00:10:00\n"), "{batch}");
    let tasks_s = tasks.to_str().unwrap();
    let o = Command::new(exe())
        .args(["assess", "--task", "--out", tasks_s])
        .env("SLURM_ARRAY_TASK_ID", "1")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let o = slosh(&["assess", "--collect", "--out", tasks_s]);
    assert!(!o.status.success());
    let out = text(&o);
    assert!(
        out.contains("missing: gentle") && out.contains("strong") && !out.contains("medium ("),
        "{out}"
    );
    for i in ["0", "2"] {
        let o = slosh(&["assess", "--task", i, "--out", tasks_s]);
        assert!(o.status.success(), "{}", text(&o));
    }
    let o = slosh(&["assess", "--task", "3", "--out", tasks_s]);
    assert!(text(&o).contains("has 3 motions"), "{}", text(&o));
    let o = slosh(&["assess", "--collect", "--out", tasks_s]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        table_without_timing(&local.join("assessment.csv")),
        table_without_timing(&tasks.join("assessment.csv"))
    );
    assert_eq!(
        report,
        std::fs::read_to_string(tasks.join("assessment.md")).unwrap()
    );
}

#[test]
fn bad_suites_and_arguments_are_refused_with_file_and_line() {
    let dir = temp("bad");
    let case = small_case(&dir);
    let case_s = case.to_str().unwrap();
    let out = dir.join("out");
    let out_s = out.to_str().unwrap();
    for (file, content, extra, words) in [
        (
            "unknown.csv",
            "name,amp\na,1\n",
            vec!["--set", "ampp=2"],
            vec!["unknown parameter(s) for --set: ampp", "amp = 1"],
        ),
        (
            "column.csv",
            "name,ampp\na,1\n",
            vec![],
            vec![
                "column.csv:2: column `ampp` is not a parameter",
                "period = 0.75",
            ],
        ),
        (
            "type.ron",
            "[\n  (name: \"a\", amp: 1.0),\n  (name: \"b\", amp: \"strong\"),\n]\n",
            vec![],
            vec!["type.ron:3: column `amp`: expects a number"],
        ),
        (
            "both.csv",
            "amp\n1\n",
            vec!["--set", "amp=2"],
            vec!["--set amp: the suite", "line 2"],
        ),
        (
            "slurm.csv",
            "amp\n1\n",
            vec!["--slurm", "--time", "4h"],
            vec!["--time 4h: expected HH:MM:SS"],
        ),
    ] {
        let suite = dir.join(file);
        std::fs::write(&suite, content).unwrap();
        let mut args = vec![
            "assess",
            case_s,
            "--motions",
            suite.to_str().unwrap(),
            "--out",
            out_s,
        ];
        args.extend(extra);
        let o = slosh(&args);
        let t = text(&o);
        assert!(!o.status.success(), "{file}: {t}");
        assert!(!t.contains("panicked"), "{file}: {t}");
        for w in words {
            assert!(t.contains(w), "{file}: `{w}` not in {t}");
        }
    }
    let o = slosh(&[
        "assess",
        "--collect",
        "--out",
        dir.join("none").to_str().unwrap(),
    ]);
    assert!(text(&o).contains("assess.ron"), "{}", text(&o));
    let o = Command::new(exe())
        .args(["assess", "--task", "--out", out_s])
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap();
    assert!(text(&o).contains("SLURM_ARRAY_TASK_ID"), "{}", text(&o));
}

#[test]
fn sweep_as_array_tasks_gives_the_local_sweep_table() {
    let dir = temp("sweep");
    let case = small_case(&dir);
    let case_s = case.to_str().unwrap();
    let sweep = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "sweep",
            case_s,
            "--vary",
            "amp=0.5,2",
            "--vary",
            "period=0.5,0.75",
        ];
        args.extend(["--out", out.to_str().unwrap()]);
        args.extend(extra);
        slosh(&args)
    };
    let local = dir.join("local");
    let o = sweep(&local, &["--jobs", "2", "--quiet"]);
    assert!(o.status.success(), "{}", text(&o));
    let tasks = dir.join("tasks");
    let o = sweep(&tasks, &["--slurm", "--cpus-per-task", "2"]);
    assert!(o.status.success(), "{}", text(&o));
    let batch = std::fs::read_to_string(tasks.join("sweep.sbatch")).unwrap();
    assert!(batch.contains("#SBATCH --array=0-3\n"), "{batch}");
    assert!(
        batch.contains("--vary amp=0.5,2 --vary period=0.5,0.75"),
        "{batch}"
    );
    for i in ["3", "0"] {
        let o = sweep(&tasks, &["--task", i]);
        assert!(o.status.success(), "{}", text(&o));
    }
    let o = sweep(&tasks, &["--collect"]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("2 of 4 cases have not run yet"),
        "{}",
        text(&o)
    );
    for i in ["1", "2"] {
        let o = sweep(&tasks, &["--task", i]);
        assert!(o.status.success(), "{}", text(&o));
    }
    let o = sweep(&tasks, &["--collect"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        table_without_timing(&local.join("sweep.csv")),
        table_without_timing(&tasks.join("sweep.csv"))
    );
}

/// The freeboard the report judges is the tank's as simulated: at dx = 0.025 m the roof of
/// the small case (0.26 m) goes to the nearest lattice level, 10 spacings = 0.25 m, over
/// 0.2 m of water (8 rows): 0.05 m where the script asks for 0.06 m; the report names both.
/// Array tasks take `$SLURM_CPUS_PER_TASK` threads, and `--threads` overrides it.
#[test]
fn the_freeboard_is_the_simulated_tanks_and_tasks_take_slurm_cpus() {
    let dir = temp("fitted");
    let case = small_case(&dir);
    let suite = dir.join("suite.csv");
    std::fs::write(&suite, "name,amp\ngentle,0.5\nstrong,3\n").unwrap();
    let out = dir.join("out");
    let o = slosh(&[
        "assess",
        case.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--set",
        "dx=0.025",
        "--slurm",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    for (task, threads, expected) in [("0", None, "threads: 3,"), ("1", Some("2"), "threads: 2,")] {
        let mut c = Command::new(exe());
        c.args(["assess", "--task", task, "--out", out.to_str().unwrap()])
            .env("SLURM_CPUS_PER_TASK", "3");
        if let Some(n) = threads {
            c.args(["--threads", n]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let name = if task == "0" { "gentle" } else { "strong" };
        let summary =
            std::fs::read_to_string(out.join("runs").join(name).join("summary.ron")).unwrap();
        assert!(
            summary.contains(expected),
            "task {task}: {expected} not in {summary}"
        );
    }
    let o = slosh(&["assess", "--collect", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));

    let rows = table_without_timing(&out.join("assessment.csv"));
    let col = |name: &str| rows[0].iter().position(|c| c == name).unwrap();
    for r in &rows[1..] {
        let free: f64 = r[col("freeboard_m")].parse().unwrap();
        let specified: f64 = r[col("freeboard_specified_m")].parse().unwrap();
        assert!((free - 0.05).abs() < 1e-9, "simulated freeboard {free} m");
        assert!(
            (specified - 0.06).abs() < 1e-12,
            "specified freeboard {specified} m"
        );
        let eta: f64 = r[col("max_eta_m")].parse().unwrap();
        assert_eq!(r[col("freeboard_exceeded")], (eta > free).to_string());
    }
    let report = std::fs::read_to_string(out.join("assessment.md")).unwrap();
    for words in [
        "Freeboard 0.0500 m (tank as simulated, fitted to the particle lattice; 0.0600 m as \
         specified)",
        "to the roof 0.0500 m in the tank as simulated",
        "0.0600 m in the tank as specified",
    ] {
        assert!(report.contains(words), "{words} not in\n{report}");
    }
}

/// `--converge` runs the motion with the largest design load again at finer lattices (here
/// two levels, dx = 0.02 and 0.01 m) into `converge/<motion>/`, and the report puts the
/// design loads' values at each level beside the table, whose columns include the equivalent
/// static roof force at each roof period.
#[test]
fn converge_studies_the_worst_motion_and_reports_it() {
    let dir = temp("converge");
    let case = small_case(&dir);
    let suite = dir.join("suite.csv");
    std::fs::write(&suite, "name,amp\ngentle,0.5\nstrong,3\n").unwrap();
    let out = dir.join("out");
    let o = slosh(&[
        "assess",
        case.to_str().unwrap(),
        "--motions",
        suite.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "2",
        "--converge",
        "--converge-levels",
        "2",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("--converge runs motion strong"),
        "{}",
        text(&o)
    );
    let study = out.join("converge").join("strong");
    assert!(study.join("convergence.csv").is_file());
    let report = std::fs::read_to_string(out.join("assessment.md")).unwrap();
    assert!(report.contains("## Resolution"), "{report}");
    assert!(
        report.contains("Motion `strong` at dx=0.02, dx=0.01"),
        "{report}"
    );
    assert!(report.contains("| max_eta_left |"), "{report}");
    let header = std::fs::read_to_string(out.join("assessment.csv")).unwrap();
    let header = header.lines().next().unwrap();
    for c in [
        "roof_f_eq_20ms",
        "roof_f_eq_200ms",
        "roof_impact_impulse_median",
    ] {
        assert!(header.split(',').any(|h| h == c), "{c} in {header}");
    }
}
