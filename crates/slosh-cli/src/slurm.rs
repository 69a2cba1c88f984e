//! Slurm job arrays: a batch script with one array task per run, and its submission.
//!
//! Each array task runs one `slosh` command with the task's index (`$SLURM_ARRAY_TASK_ID`);
//! nothing is needed on the cluster but the `slosh` binary and a file system shared by the
//! nodes. The script asks Slurm to requeue a task whose node fails (`--requeue`); a requeued
//! task continues its case from the checkpoint the case wrote when it was stopped (a time
//! limit's or a preemption's SIGTERM), runs it again when there is none, and skips it when its
//! run folder already holds the completed result. A task's run takes `$SLURM_CPUS_PER_TASK`
//! threads (`--threads` overrides).

use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The `#SBATCH` options a user may choose (the rest follow from the job).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SlurmOptions {
    /// Partition (`--partition`); the cluster's default when `None`.
    pub partition: Option<String>,
    /// Time limit of each array task, `[D-]HH:MM:SS` (`--time`).
    pub time: Option<String>,
    /// CPUs of each array task (`--cpus-per-task`); the case runs with that many threads.
    pub cpus_per_task: Option<usize>,
}

impl SlurmOptions {
    /// Checks the values before anything is written.
    pub fn check(&self) -> Result<()> {
        if let Some(t) = &self.time {
            if !is_time_limit(t) {
                bail!("--time {t}: expected HH:MM:SS or D-HH:MM:SS (e.g. --time 04:00:00)");
            }
        }
        if let Some(p) = &self.partition {
            if p.is_empty()
                || p.chars()
                    .any(|c| c.is_whitespace() || c == '\'' || c == '"')
            {
                bail!("--partition {p:?}: a partition name has no spaces or quotes");
            }
        }
        if self.cpus_per_task == Some(0) {
            bail!("--cpus-per-task must be at least 1");
        }
        Ok(())
    }
}

/// The `--slurm` options of `slosh assess` and `slosh sweep`.
#[derive(Args, Clone, Debug, Default)]
pub struct SlurmArgs {
    /// Write a Slurm job array with one task per run into the output folder instead of
    /// running here, and print the sbatch command.
    #[arg(long)]
    pub slurm: bool,
    /// Slurm partition of the array tasks.
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// Time limit of each array task.
    #[arg(long, requires = "slurm", value_name = "HH:MM:SS")]
    pub time: Option<String>,
    /// CPUs of each array task (the run's threads).
    #[arg(long, requires = "slurm", value_name = "N")]
    pub cpus_per_task: Option<usize>,
    /// Submit the job array with sbatch after writing it.
    #[arg(long, requires = "slurm")]
    pub submit: bool,
}

impl SlurmArgs {
    /// The `#SBATCH` options.
    pub fn options(&self) -> SlurmOptions {
        SlurmOptions {
            partition: self.partition.clone(),
            time: self.time.clone(),
            cpus_per_task: self.cpus_per_task,
        }
    }
}

/// True for `HH:MM:SS` and `D-HH:MM:SS` with minutes and seconds below 60.
fn is_time_limit(text: &str) -> bool {
    let (days, clock) = match text.split_once('-') {
        Some((d, c)) => (Some(d), c),
        None => (None, text),
    };
    let digits = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
    let parts: Vec<&str> = clock.split(':').collect();
    days.is_none_or(digits)
        && parts.len() == 3
        && parts.iter().all(|p| digits(p))
        && parts[1].parse::<u32>().is_ok_and(|m| m < 60)
        && parts[2].parse::<u32>().is_ok_and(|s| s < 60)
}

/// A job array to write: `tasks` array tasks, each running `exe` with `task_args` and
/// `--task $SLURM_ARRAY_TASK_ID`, its log in `log_dir/<job>_<task>.out`.
#[derive(Clone, Debug)]
pub struct JobArray {
    /// Job name shown by `squeue`.
    pub job_name: String,
    /// Number of array tasks (indices 0 to tasks − 1).
    pub tasks: usize,
    /// The `slosh` executable (an absolute path on the shared file system).
    pub exe: PathBuf,
    /// Arguments before `--task` (e.g. `assess --out DIR`).
    pub task_args: Vec<String>,
    /// Folder of the tasks' logs.
    pub log_dir: PathBuf,
}

/// Whether `word` needs no quotes, for a shell or for sbatch's own option lines: not empty,
/// and only letters, digits and `/._-+=:,@%`.
fn is_bare_word(word: &str) -> bool {
    !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@%".contains(c))
}

/// Quotes a word for a POSIX shell.
fn shell_quote(word: &str) -> String {
    if is_bare_word(word) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

/// Refuses a value bound for the batch script that holds a control character (a newline
/// would end an `#SBATCH` line or a command and start another one of the value's choosing).
pub(crate) fn check_plain(what: &str, value: &str) -> Result<()> {
    if let Some(c) = value.chars().find(|c| c.is_control()) {
        bail!(
            "{what} {value:?} holds the control character {c:?}, which a Slurm batch script \
             cannot carry; choose a name or folder without it"
        );
    }
    Ok(())
}

/// Quotes a value of an `#SBATCH` line, which sbatch reads itself, not through a shell: it
/// splits on blanks, takes `"…"` as one word, `\` as an escape and an unquoted `#` as the
/// start of a comment (Slurm's `sbatch/opt.c`, `_get_argument`). Control characters are
/// refused before ([`check_plain`]).
fn sbatch_quote(word: &str) -> String {
    if is_bare_word(word) {
        word.to_string()
    } else {
        let mut quoted = String::from("\"");
        for c in word.chars() {
            if c == '"' || c == '\\' {
                quoted.push('\\');
            }
            quoted.push(c);
        }
        quoted.push('"');
        quoted
    }
}

/// The text of the batch script of `job` with `options`; every value written into it is
/// checked ([`check_plain`]) and quoted for the line that reads it.
pub fn batch_script(job: &JobArray, options: &SlurmOptions) -> Result<String> {
    let log_dir = job.log_dir.display().to_string();
    check_plain("the output folder", &log_dir)?;
    // In `--output` Slurm expands `%` patterns (a literal `%` is `%%`) and a `\` turns the
    // expansion off for the whole name, which would send every task into one log.
    if log_dir.contains('\\') {
        bail!(
            "the output folder {log_dir:?} holds a backslash, which Slurm's --output cannot \
             carry; choose a folder without it"
        );
    }
    let log = format!("{}/%A_%a.out", log_dir.replace('%', "%%"));
    let exe = job.exe.display().to_string();
    check_plain("the job name", &job.job_name)?;
    check_plain("the slosh executable", &exe)?;
    for a in &job.task_args {
        check_plain("the argument", a)?;
    }
    if let Some(p) = &options.partition {
        check_plain("--partition", p)?;
    }
    if let Some(t) = &options.time {
        check_plain("--time", t)?;
    }
    let backend = std::env::var(crate::BACKEND_ENV).ok();
    if let Some(b) = &backend {
        check_plain(crate::BACKEND_ENV, b)?;
    }
    // sbatch removes the words "hetjob" and "packjob" from every `#SBATCH` line, quoted or not.
    for (what, value) in [
        ("the job name", job.job_name.as_str()),
        ("the output folder", &log_dir),
    ] {
        let lower = value.to_lowercase();
        if lower.contains("hetjob") || lower.contains("packjob") {
            bail!(
                "{what} {value:?} holds the word \"hetjob\" or \"packjob\", which sbatch \
                 removes from its option lines; choose another name"
            );
        }
    }
    let mut s = String::from("#!/bin/bash\n");
    s.push_str(&format!(
        "#SBATCH --job-name={}\n",
        sbatch_quote(&job.job_name)
    ));
    s.push_str(&format!(
        "#SBATCH --array=0-{}\n",
        job.tasks.saturating_sub(1)
    ));
    s.push_str(&format!("#SBATCH --output={}\n", sbatch_quote(&log)));
    s.push_str("#SBATCH --ntasks=1\n");
    if let Some(p) = &options.partition {
        s.push_str(&format!("#SBATCH --partition={}\n", sbatch_quote(p)));
    }
    if let Some(t) = &options.time {
        s.push_str(&format!("#SBATCH --time={}\n", sbatch_quote(t)));
    }
    if let Some(n) = options.cpus_per_task {
        s.push_str(&format!("#SBATCH --cpus-per-task={n}\n"));
    }
    s.push_str("#SBATCH --requeue\n");
    s.push_str("#SBATCH --open-mode=append\n\n");
    if let Some(backend) = &backend {
        // `--backend` of the sweep or assessment that wrote the job: its runs step there.
        s.push_str(&format!(
            "export {}={}\n",
            crate::BACKEND_ENV,
            shell_quote(backend)
        ));
    }
    s.push_str("# One array task per run; each writes only its own run folder.\n");
    let mut command = vec![shell_quote(&exe)];
    command.extend(job.task_args.iter().map(|a| shell_quote(a)));
    command.push("--task".into());
    command.push("\"$SLURM_ARRAY_TASK_ID\"".into());
    s.push_str(&format!("exec {}\n", command.join(" ")));
    Ok(s)
}

/// Writes the batch script of `job` to `path` (executable) and returns the `sbatch`
/// command that submits it.
pub fn write_batch_script(path: &Path, job: &JobArray, options: &SlurmOptions) -> Result<String> {
    options.check()?;
    let text = batch_script(job, options)?;
    std::fs::create_dir_all(&job.log_dir)
        .with_context(|| format!("cannot create {}", job.log_dir.display()))?;
    slosh_io::write_atomic(path, text.as_bytes())?;
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
        .with_context(|| format!("cannot make {} executable", path.display()))?;
    Ok(format!(
        "sbatch {}",
        shell_quote(&path.display().to_string())
    ))
}

/// Writes the batch script of `job` to `path`, then submits it when `submit` (printing the
/// job id as `submitted: job ID`) or prints the `sbatch` command; `collect` is the command
/// that gathers the results once the job has ended.
pub fn write_and_submit(
    path: &Path,
    job: &JobArray,
    options: &SlurmOptions,
    submit: bool,
    collect: &str,
) -> Result<()> {
    let command = write_batch_script(path, job, options)?;
    println!(
        "wrote {} ({} array task{}, one per run)",
        path.display(),
        job.tasks,
        if job.tasks == 1 { "" } else { "s" }
    );
    if submit {
        println!("submitted: job {}", self::submit(path)?);
    } else {
        println!("submit with: {command}");
    }
    println!("when the job has ended: {collect}");
    Ok(())
}

/// The words of a command line as one line a POSIX shell reads back.
pub fn command_line(words: &[String]) -> String {
    words
        .iter()
        .map(|w| shell_quote(w))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Submits a batch script with `sbatch --parsable` and returns the job id.
pub fn submit(path: &Path) -> Result<String> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .arg(path)
        .output()
        .map_err(|e| {
            anyhow::anyhow!(
                "cannot run sbatch ({e}): submit from a machine of the Slurm cluster, or run `sbatch {}` there",
                path.display()
            )
        })?;
    if !output.status.success() {
        bail!(
            "sbatch {} failed ({}): {}",
            path.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&output.stdout);
    // `--parsable` prints `jobid` or `jobid;cluster`.
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() {
        bail!("sbatch {} printed no job id", path.display());
    }
    Ok(id)
}

/// The array task index: `explicit`, else `$SLURM_ARRAY_TASK_ID`.
pub fn task_index(explicit: Option<usize>) -> Result<usize> {
    if let Some(i) = explicit {
        return Ok(i);
    }
    let text = std::env::var("SLURM_ARRAY_TASK_ID").map_err(|_| {
        anyhow::anyhow!("--task needs an index (e.g. --task 0) outside a Slurm job array ($SLURM_ARRAY_TASK_ID is not set)")
    })?;
    text.trim()
        .parse()
        .map_err(|_| anyhow::anyhow!("$SLURM_ARRAY_TASK_ID is `{text}`, not a task index"))
}

/// Threads of an array task's run: `explicit` (`--threads`), else `$SLURM_CPUS_PER_TASK`
/// (the CPUs Slurm gave the task), else every core this process may use.
pub fn task_threads(explicit: Option<usize>) -> Result<usize> {
    if let Some(n) = explicit {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        return Ok(n);
    }
    match std::env::var("SLURM_CPUS_PER_TASK") {
        Ok(text) => match text.trim().parse::<usize>() {
            Ok(n) if n > 0 => Ok(n),
            _ => bail!("$SLURM_CPUS_PER_TASK is `{text}`, not a number of CPUs ≥ 1"),
        },
        Err(_) => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_limits_and_options_are_checked() {
        for ok in ["04:00:00", "1-12:30:00", "00:00:59"] {
            assert!(is_time_limit(ok), "{ok}");
        }
        for bad in ["4h", "04:60:00", "1-:00:00:00", "12:00", "a-01:00:00"] {
            assert!(!is_time_limit(bad), "{bad}");
        }
        let bad = SlurmOptions {
            partition: Some("two words".into()),
            ..SlurmOptions::default()
        };
        assert!(bad.check().is_err());
    }

    #[test]
    fn batch_script_runs_one_task_per_index() {
        let job = JobArray {
            job_name: "slosh-assess".into(),
            tasks: 7,
            exe: "/opt/slosh/bin/slosh".into(),
            task_args: vec!["assess".into(), "--out".into(), "/shared/my run".into()],
            log_dir: "/shared/my run/slurm".into(),
        };
        let options = SlurmOptions {
            partition: Some("long".into()),
            time: Some("02:00:00".into()),
            cpus_per_task: Some(8),
        };
        let s = batch_script(&job, &options).unwrap();
        for line in [
            "#SBATCH --output=\"/shared/my run/slurm/%A_%a.out\"\n",
            "#SBATCH --array=0-6\n",
            "#SBATCH --partition=long\n",
            "#SBATCH --time=02:00:00\n",
            "#SBATCH --cpus-per-task=8\n",
            "exec /opt/slosh/bin/slosh assess --out '/shared/my run' --task \"$SLURM_ARRAY_TASK_ID\"\n",
        ] {
            assert!(s.contains(line), "{line} not in\n{s}");
        }
    }

    /// A name or folder never becomes a line of its own or a command: a newline is refused,
    /// and the sbatch-read lines quote what they carry (sbatch ends an unquoted value at a
    /// blank and takes an unquoted `#` as a comment).
    #[test]
    fn names_in_the_batch_script_are_data() {
        let job = |log: &str, name: &str| JobArray {
            job_name: name.into(),
            tasks: 2,
            exe: "/opt/slosh".into(),
            task_args: vec!["assess".into(), "--out".into(), log.into()],
            log_dir: log.into(),
        };
        let options = SlurmOptions::default();
        for (log, name) in [
            ("SN7\ntouch pwned #", "slosh-assess-x"),
            ("/shared/run", "a\nb"),
            ("/shared/run\r", "x"),
        ] {
            let err = batch_script(&job(log, name), &options).unwrap_err();
            assert!(err.to_string().contains("control character"), "{err}");
        }
        let s = batch_script(&job("/s/a \"b\" #c%d", "n m"), &options).unwrap();
        assert!(
            s.contains("#SBATCH --output=\"/s/a \\\"b\\\" #c%%d/%A_%a.out\"\n"),
            "{s}"
        );
        assert!(s.contains("#SBATCH --job-name=\"n m\"\n"), "{s}");
        assert!(s.contains("--out '/s/a \"b\" #c%d' --task"), "{s}");
        for (log, name) in [("/s/a\\b", "x"), ("/s/hetjob", "x"), ("/s/a", "PackJob-1")] {
            assert!(
                batch_script(&job(log, name), &options).is_err(),
                "{log} {name}"
            );
        }
        assert_eq!(s.lines().filter(|l| l.starts_with("exec ")).count(), 1);
    }
}
