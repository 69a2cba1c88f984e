//! `slosh assess --slurm` on a real Slurm: a single-node cluster (munged, slurmctld, slurmd)
//! started in a temporary folder, a 3-motion 2D suite submitted as a job array, collected,
//! and its report compared with the one `slosh assess --jobs 2` writes locally; the same for
//! a 2-case `slosh sweep --slurm` and its `sweep.csv`; then an array task requeued while it
//! runs (`scontrol requeue`: Slurm sends SIGTERM, as at a time limit or a preemption) continues
//! from its checkpoint when it runs again, with `$SLURM_CPUS_PER_TASK` threads, and ends with
//! the files of the same motion run locally.
//!
//! Needs Debian's `slurm-wlm` and `munge` and root (the daemons run as root, without
//! systemd); `.ci/run` installs them. Without them the test passes and says on the terminal
//! that it skipped the scenario, except where `CI` is set (then it fails saying what is
//! missing); `SLOSH_SKIP_SLURM=1` skips it even there.

mod scenario;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_slosh"))
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The full path of a program, searched in $PATH and the sbin folders.
fn program(name: &str) -> Option<PathBuf> {
    let path = std::env::var("PATH").unwrap_or_default();
    path.split(':')
        .map(PathBuf::from)
        .chain(["/usr/sbin", "/usr/bin", "/sbin", "/usr/local/sbin"].map(PathBuf::from))
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// A single-node Slurm cluster whose daemons stop when it is dropped.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
    daemons: Vec<(&'static str, Child)>,
}

impl Cluster {
    fn start(dir: &Path, bin: &dyn Fn(&str) -> PathBuf) -> Result<Cluster, String> {
        let mut cluster = Cluster {
            dir: dir.to_path_buf(),
            conf: dir.join("slurm.conf"),
            daemons: Vec::new(),
        };
        use std::os::unix::fs::PermissionsExt;
        let set_mode = |p: &Path, mode: u32| {
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(mode)).unwrap()
        };
        // munged checks that its socket folder is reachable by all and its key private.
        for (sub, mode) in [
            ("munge-key", 0o700),
            ("munge-socket", 0o755),
            ("state", 0o755),
            ("spool", 0o755),
        ] {
            std::fs::create_dir_all(dir.join(sub)).unwrap();
            set_mode(&dir.join(sub), mode);
        }
        set_mode(dir, 0o755);
        let key = dir.join("munge-key/munge.key");
        let mut bytes = vec![0u8; 1024];
        std::fs::File::open("/dev/urandom")
            .and_then(|mut f| f.read_exact(&mut bytes))
            .map_err(|e| format!("cannot read /dev/urandom: {e}"))?;
        std::fs::write(&key, &bytes).unwrap();
        set_mode(&key, 0o400);
        let socket = dir.join("munge-socket/munge.sock");
        cluster.spawn(
            "munged",
            Command::new(bin("munged")).args([
                "-F".into(),
                format!("--socket={}", socket.display()),
                format!("--key-file={}", key.display()),
                format!("--log-file={}", dir.join("munged.log").display()),
                format!(
                    "--pid-file={}",
                    dir.join("munge-socket/munged.pid").display()
                ),
                format!(
                    "--seed-file={}",
                    dir.join("munge-key/munged.seed").display()
                ),
            ]),
        )?;
        cluster.wait_for("munged's socket", || socket.exists())?;

        let node = Command::new(bin("slurmd"))
            .arg("-C")
            .output()
            .map_err(|e| format!("slurmd -C: {e}"))?;
        let node_line = String::from_utf8_lossy(&node.stdout)
            .lines()
            .find(|l| l.starts_with("NodeName="))
            .ok_or("slurmd -C printed no NodeName line")?
            .to_string();
        let host = node_line
            .split_whitespace()
            .next()
            .and_then(|w| w.strip_prefix("NodeName="))
            .unwrap()
            .to_string();
        let [ctld_port, slurmd_port] = [free_port(), free_port()];
        let d = dir.display();
        let conf = format!(
            "ClusterName=slosh-test\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmctldPort={ctld_port}\n\
             SlurmdPort={slurmd_port}\n\
             SlurmUser=root\n\
             SlurmdUser=root\n\
             AuthType=auth/munge\n\
             CredType=cred/munge\n\
             AuthInfo=socket={socket}\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/slurmctld.log\n\
             SlurmdLogFile={d}/slurmd.log\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             MpiDefault=none\n\
             ReturnToService=2\n\
             {node_line} State=UNKNOWN\n\
             PartitionName=assess Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n",
            socket = socket.display()
        );
        std::fs::write(&cluster.conf, conf).unwrap();
        let conf = cluster.conf.clone();
        cluster.spawn(
            "slurmctld",
            Command::new(bin("slurmctld"))
                .arg("-D")
                .arg("-f")
                .arg(&conf),
        )?;
        cluster.wait_for("slurmctld", || {
            cluster_command("sinfo", &conf)
                .arg("-h")
                .output()
                .is_ok_and(|o| o.status.success())
        })?;
        cluster.spawn(
            "slurmd",
            Command::new(bin("slurmd")).arg("-D").arg("-f").arg(&conf),
        )?;
        cluster.wait_for("the node to be idle", || {
            cluster_command("sinfo", &conf)
                .args(["-h", "-o", "%T"])
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        })?;
        Ok(cluster)
    }

    fn spawn(&mut self, name: &'static str, command: &mut Command) -> Result<(), String> {
        let log = std::fs::File::create(self.dir.join(format!("{name}.out"))).unwrap();
        let child = command
            .stdin(Stdio::null())
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .spawn()
            .map_err(|e| format!("cannot start {name}: {e}"))?;
        self.daemons.push((name, child));
        Ok(())
    }

    /// Waits up to 60 s for `ready`, failing early when a daemon has died.
    fn wait_for(&mut self, what: &str, ready: impl Fn() -> bool) -> Result<(), String> {
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(60) {
            if ready() {
                return Ok(());
            }
            let exited = self
                .daemons
                .iter_mut()
                .find_map(|(name, child)| Some((*name, child.try_wait().ok()??)));
            if let Some((name, status)) = exited {
                return Err(format!(
                    "{name} exited ({status}) while waiting for {what}; the logs:\n{}",
                    self.logs()
                ));
            }
            std::thread::sleep(Duration::from_millis(200));
        }
        Err(format!(
            "timed out waiting for {what}; the logs:\n{}",
            self.logs()
        ))
    }

    fn logs(&self) -> String {
        [
            "munged.out",
            "slurmctld.out",
            "slurmctld.log",
            "slurmd.out",
            "slurmd.log",
        ]
        .iter()
        .map(|f| {
            let t = std::fs::read_to_string(self.dir.join(f)).unwrap_or_default();
            let tail: Vec<&str> = t.lines().rev().take(15).collect();
            format!(
                "--- {f}\n{}",
                tail.into_iter().rev().collect::<Vec<_>>().join("\n")
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
    }
}

impl Drop for Cluster {
    /// Stops the daemons this test started (SIGTERM, then SIGKILL after 10 s), last first.
    fn drop(&mut self) {
        for (_, child) in self.daemons.iter_mut().rev() {
            if let Ok(pid) = i32::try_from(child.id()) {
                // SAFETY: kill(2) on a child this test started and has not reaped.
                unsafe {
                    libc::kill(pid, libc::SIGTERM);
                }
            }
            let start = Instant::now();
            while matches!(child.try_wait(), Ok(None)) {
                if start.elapsed() > Duration::from_secs(10) {
                    let _ = child.kill();
                    let _ = child.wait();
                    break;
                }
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    }
}

/// A TCP port free at the time of asking.
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .unwrap()
}

/// A Slurm client command talking to the test's cluster.
fn cluster_command(name: &str, conf: &Path) -> Command {
    let mut c = Command::new(program(name).unwrap_or_else(|| PathBuf::from(name)));
    c.env("SLURM_CONF", conf);
    c
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
fn slurm_job_array_gives_the_local_report() {
    let start = Instant::now();
    let needed = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"];
    let missing: Vec<&str> = needed
        .iter()
        .copied()
        .filter(|n| program(n).is_none())
        .collect();
    // SAFETY: geteuid(2) has no preconditions.
    let root = unsafe { libc::geteuid() } == 0;
    if !missing.is_empty() || !root {
        let why = if missing.is_empty() {
            "the test starts slurmctld, slurmd and munged as root, and runs as another user".into()
        } else {
            format!(
                "Slurm is not installed here ({} not found); install Debian's slurm-wlm and munge \
                 (.ci/run does: apt-get install -y slurm-wlm munge)",
                missing.join(", ")
            )
        };
        let how = "as root with Debian's slurm-wlm and munge installed (.ci/run installs them), \
                   cargo test --release -p slosh-cli --test assess_slurm";
        if std::env::var("SLOSH_SKIP_SLURM").as_deref() == Ok("1") {
            // Asked for by name, even where CI is set.
            let _ = std::io::Write::write_all(
                &mut std::io::stderr(),
                format!("\nSKIPPED the Slurm job-array scenario (SLOSH_SKIP_SLURM=1): {why}. To run it: {how}\n")
                    .as_bytes(),
            );
            return;
        }
        scenario::skip_or_require("the Slurm job-array scenario", &why, how);
        return;
    }
    let bin = |name: &str| program(name).unwrap();

    let dir = std::env::temp_dir().join("slosh-assess-slurm");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let cluster = Cluster::start(&dir.join("cluster"), &bin).unwrap_or_else(|e| panic!("{e}"));
    let cluster_up = start.elapsed();

    // Three motions on the 2D El Centro tank, coarse (dx = 0.1 m: 300 fluid particles) and
    // short (0.5 s settling, 4 s of the record).
    let case = repo_root().join("scripts/elcentro_2d.rhai");
    let suite = dir.join("suite.csv");
    std::fs::write(&suite, "name,pga\nec_2,2.0\nec_4,4.0\nec_6,6.0\n").unwrap();
    let common = |out: &Path| -> Vec<String> {
        [
            "assess",
            case.to_str().unwrap(),
            "--motions",
            suite.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--set",
            "dx=0.1",
            "--set",
            "dt=0.0005",
            "--set",
            "settle=0.5",
            "--set",
            "duration=4.5",
            "--set",
            "frame_interval=0",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };

    let on_slurm = dir.join("slurm");
    let mut args = common(&on_slurm);
    args.extend(
        [
            "--slurm",
            "--submit",
            "--time",
            "00:05:00",
            "--cpus-per-task",
            "1",
        ]
        .map(String::from),
    );
    let o = Command::new(exe())
        .args(&args)
        .env("SLURM_CONF", &cluster.conf)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}\n{}", text(&o), cluster.logs());
    let job = text(&o)
        .lines()
        .find_map(|l| {
            l.strip_prefix("submitted: job ")
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| panic!("no job id in {}", text(&o)));

    // `slosh sweep --slurm`: two short cases of the same tank.
    let sweep = |out: &Path, extra: &[&str]| -> Output {
        let mut args: Vec<String> = ["sweep", case.to_str().unwrap()].map(String::from).to_vec();
        for v in [
            "pga=2,4",
            "dx=0.1",
            "dt=0.0005",
            "settle=0.5",
            "duration=1.5",
            "frame_interval=0",
        ] {
            args.extend(["--vary".to_string(), v.to_string()]);
        }
        args.extend(["--out".to_string(), out.to_str().unwrap().to_string()]);
        args.extend(extra.iter().map(|s| s.to_string()));
        Command::new(exe())
            .args(&args)
            .env("SLURM_CONF", &cluster.conf)
            .output()
            .unwrap()
    };
    let sweep_on_slurm = dir.join("sweep-slurm");
    let o = sweep(&sweep_on_slurm, &["--slurm", "--submit"]);
    assert!(o.status.success(), "{}\n{}", text(&o), cluster.logs());
    let sweep_job = text(&o)
        .lines()
        .find_map(|l| {
            l.strip_prefix("submitted: job ")
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| panic!("no job id in {}", text(&o)));

    // The local runs while the arrays run.
    let local = dir.join("local");
    let mut args = common(&local);
    args.extend(["--jobs", "2", "--quiet"].map(String::from));
    let o = Command::new(exe()).args(&args).output().unwrap();
    assert!(o.status.success(), "{}", text(&o));

    let sweep_local = dir.join("sweep-local");
    let o = sweep(&sweep_local, &["--jobs", "2", "--quiet"]);
    assert!(o.status.success(), "{}", text(&o));

    let wait = Instant::now();
    let jobs = format!("{job},{sweep_job}");
    loop {
        let q = cluster_command("squeue", &cluster.conf)
            .args(["-h", "-j", &jobs])
            .output()
            .unwrap();
        if q.status.success() && String::from_utf8_lossy(&q.stdout).trim().is_empty() {
            break;
        }
        assert!(
            wait.elapsed() < Duration::from_secs(150),
            "jobs {jobs} still queued after 150 s: {}\n{}",
            text(&q),
            cluster.logs()
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    let task_logs = || {
        std::fs::read_dir(on_slurm.join("slurm"))
            .map(|d| {
                d.flatten()
                    .map(|e| std::fs::read_to_string(e.path()).unwrap_or_default())
                    .collect::<Vec<_>>()
                    .join("\n")
            })
            .unwrap_or_default()
    };
    let o = Command::new(exe())
        .args(["assess", "--collect", "--out", on_slurm.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{}\ntask logs:\n{}",
        text(&o),
        task_logs()
    );
    // One log per array task, each with its own index.
    assert_eq!(
        std::fs::read_dir(on_slurm.join("slurm")).unwrap().count(),
        3,
        "{}",
        task_logs()
    );

    let slurm_rows = table_without_timing(&on_slurm.join("assessment.csv"));
    assert_eq!(slurm_rows.len(), 4);
    let status = slurm_rows[0].iter().position(|c| c == "status").unwrap();
    assert!(
        slurm_rows[1..].iter().all(|r| r[status] == "completed"),
        "{slurm_rows:?}"
    );
    assert_eq!(
        slurm_rows,
        table_without_timing(&local.join("assessment.csv"))
    );
    assert_eq!(
        std::fs::read_to_string(on_slurm.join("assessment.md")).unwrap(),
        std::fs::read_to_string(local.join("assessment.md")).unwrap()
    );
    let o = sweep(&sweep_on_slurm, &["--collect", "--quiet"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        table_without_timing(&sweep_on_slurm.join("sweep.csv")),
        table_without_timing(&sweep_local.join("sweep.csv"))
    );
    requeued_task_resumes_from_its_checkpoint(&dir, &cluster, &case);
    drop(cluster);
    eprintln!(
        "Slurm test: cluster up in {:.1} s, total {:.1} s",
        cluster_up.as_secs_f64(),
        start.elapsed().as_secs_f64()
    );
}

/// Waits up to `seconds` for `ready`, then fails with `what` and the cluster's logs.
fn wait_until(cluster: &Cluster, seconds: u64, what: &str, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(
            start.elapsed() < Duration::from_secs(seconds),
            "{what} after {seconds} s\n{}",
            cluster.logs()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// One motion of the 2D El Centro tank submitted as a one-task array with one CPU per task,
/// requeued once its run is under way: the task's run stops with a checkpoint, the task runs
/// again, continues the run from the checkpoint (its summary lists the resumption) and ends
/// with the files of the same motion run locally, byte for byte.
fn requeued_task_resumes_from_its_checkpoint(dir: &Path, cluster: &Cluster, case: &Path) {
    let suite = dir.join("requeue-suite.csv");
    std::fs::write(&suite, "name,pga\nec_3,3.0\n").unwrap();
    let assess = |out: &Path, extra: &[&str]| -> Output {
        let mut args: Vec<String> = [
            "assess",
            case.to_str().unwrap(),
            "--motions",
            suite.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec();
        for set in [
            "dx=0.1",
            "dt=0.0005",
            "settle=0.5",
            "duration=8.5",
            "frame_interval=0",
        ] {
            args.extend(["--set".to_string(), set.to_string()]);
        }
        args.extend(extra.iter().map(|s| s.to_string()));
        Command::new(exe())
            .args(&args)
            .env("SLURM_CONF", &cluster.conf)
            .output()
            .unwrap()
    };
    let on_slurm = dir.join("requeue");
    let o = assess(&on_slurm, &["--slurm", "--submit", "--cpus-per-task", "1"]);
    assert!(o.status.success(), "{}\n{}", text(&o), cluster.logs());
    let job = text(&o)
        .lines()
        .find_map(|l| {
            l.strip_prefix("submitted: job ")
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| panic!("no job id in {}", text(&o)));
    let run = on_slurm.join("runs/ec_3");
    let lines = |f: &Path| std::fs::read_to_string(f).map_or(0, |t| t.lines().count());
    // An eighth of the 850 rows (0.01 s apart) written: the run is under way.
    wait_until(cluster, 120, "the run did not start", || {
        let summary = std::fs::read_to_string(run.join("summary.ron")).unwrap_or_default();
        assert!(
            !summary.contains("status: \"failed\""),
            "{}",
            std::fs::read_to_string(run.join("run.log")).unwrap_or_default()
        );
        lines(&run.join("series.csv")) > 100
    });
    let o = cluster_command("scontrol", &cluster.conf)
        .args(["requeue", &format!("{job}_0")])
        .output()
        .unwrap();
    assert!(o.status.success(), "scontrol requeue: {}", text(&o));
    let status = || std::fs::read_to_string(run.join("summary.ron")).unwrap_or_default();
    wait_until(cluster, 60, "the requeued run did not stop", || {
        status().contains("status: \"interrupted\"")
    });
    assert!(run.join("checkpoint/state.bin").exists());
    // Slurm holds a requeued job back for a while (its begin time is set ahead); let it
    // start now.
    let task = format!("{job}_0");
    wait_until(cluster, 60, "the requeued task is not pending", || {
        cluster_command("squeue", &cluster.conf)
            .args(["-h", "-o", "%T", "-j", &job])
            .output()
            .is_ok_and(|q| String::from_utf8_lossy(&q.stdout).trim() == "PENDING")
    });
    let o = cluster_command("scontrol", &cluster.conf)
        .args(["update", &format!("JobId={task}"), "StartTime=now"])
        .output()
        .unwrap();
    assert!(o.status.success(), "scontrol update: {}", text(&o));
    let stopped_at = lines(&run.join("series.csv"));
    assert!(
        stopped_at < 800,
        "stopped before its end: {stopped_at} lines"
    );

    // The local run of the same motion, while the task waits and runs again.
    let local = dir.join("requeue-local");
    let o = assess(&local, &["--jobs", "1", "--quiet"]);
    assert!(o.status.success(), "{}", text(&o));

    wait_until(cluster, 240, "the requeued task did not finish", || {
        cluster_command("squeue", &cluster.conf)
            .args(["-h", "-j", &job])
            .output()
            .is_ok_and(|q| {
                q.status.success() && String::from_utf8_lossy(&q.stdout).trim().is_empty()
            })
    });
    let summary = status();
    assert!(summary.contains("status: \"completed\""), "{summary}");
    assert!(
        summary.contains("from_step:"),
        "continued from its checkpoint: {summary}"
    );
    assert!(
        summary.contains("threads: 1,"),
        "$SLURM_CPUS_PER_TASK threads: {summary}"
    );
    for f in ["series.csv", "roof_pressure.csv"] {
        let (a, b) = (
            std::fs::read(run.join(f)).unwrap(),
            std::fs::read(local.join("runs/ec_3").join(f)).unwrap(),
        );
        assert!(
            a == b,
            "{f} of the requeued task differs from the local run's"
        );
    }
    let o = Command::new(exe())
        .args([
            "assess",
            "--collect",
            "--quiet",
            "--out",
            on_slurm.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        table_without_timing(&on_slurm.join("assessment.csv")),
        table_without_timing(&local.join("assessment.csv"))
    );
}
