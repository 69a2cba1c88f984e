//! `slosh assess CASE.rhai --motions SUITE.csv|SUITE.ron`: a tank under a suite of ground
//! motions, with a report on freeboard and roof loads against the codes.
//!
//! - **Suite**: one row per motion (see [`suite`]); each row is one run of the case with the
//!   row's parameters (and the `--set` ones), in `DIR/runs/<name>/`.
//! - **Manifest**: `DIR/assess.ron` records the case, the suite's rows and the `--set`
//!   values, so that Slurm array tasks (`--task I`) and `--collect` need only `--out DIR`.
//! - **Local**: runs as `slosh sweep` does (child `slosh run` processes, `--jobs` at once,
//!   resumable: a run completed before with the same parameters is not run again), then
//!   writes the report.
//! - **Slurm**: `--slurm` writes `DIR/assess.sbatch`, a job array with one task per motion,
//!   and prints (or with `--submit` runs) the `sbatch` command; `--collect` writes the report
//!   from the finished runs and lists the missing and failed ones.
//! - **Report**: `DIR/assessment.md`, `DIR/assessment.csv` and `DIR/plots/` (see [`report`]).

pub mod cli;
pub mod report;
pub mod suite;

use crate::slurm::{JobArray, SlurmOptions};
use crate::sweep::{CaseStatus, Planned};
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use slosh_script::{list_params_with, load_case, CaseOptions, ParamDecl, ParamValue};
use std::path::{Path, PathBuf};

/// File name of the manifest in the assessment folder.
pub const MANIFEST: &str = "assess.ron";
/// File name of the Slurm batch script in the assessment folder.
pub const BATCH_SCRIPT: &str = "assess.sbatch";

/// What an assessment runs: written by `slosh assess CASE --motions SUITE`, read by the
/// array tasks and by `--collect`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Version of slosh that wrote it.
    pub version: String,
    /// The case script (absolute path).
    pub case: PathBuf,
    /// The suite file it was read from (absolute path).
    pub suite: PathBuf,
    /// Folders the script may also read (`--allow-read`).
    pub allow_read: Vec<PathBuf>,
    /// `--set` values, applied to every motion.
    pub overrides: Vec<(String, ParamValue)>,
    /// The motions in suite order.
    pub motions: Vec<Motion>,
}

/// One ground motion of the suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// Name and run folder (`runs/<name>`).
    pub name: String,
    /// The row's parameter values.
    pub values: Vec<(String, ParamValue)>,
}

impl Manifest {
    /// Reads `DIR/assess.ron`.
    pub fn read(out_dir: &Path) -> Result<Manifest> {
        let path = out_dir.join(MANIFEST);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "cannot read {}: is {} the --out folder of a `slosh assess CASE --motions SUITE` \
                 (which writes it)?",
                path.display(),
                out_dir.display()
            )
        })?;
        let manifest: Manifest = ron::from_str(&text)
            .with_context(|| format!("{} is not an assessment manifest", path.display()))?;
        // Every name becomes a folder under `runs/`: one plain folder each, no two alike.
        for (k, m) in manifest.motions.iter().enumerate() {
            crate::sweep::check_folder_name(&m.name)
                .with_context(|| format!("{} is not an assessment manifest", path.display()))?;
            if manifest.motions[..k].iter().any(|o| o.name == m.name) {
                bail!(
                    "{}: the motion name {:?} appears twice; each motion needs its own folder",
                    path.display(),
                    m.name
                );
            }
        }
        Ok(manifest)
    }

    fn write(&self, out_dir: &Path) -> Result<()> {
        let path = out_dir.join(MANIFEST);
        let text = ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())?;
        slosh_io::write_atomic(&path, text.as_bytes()).map_err(anyhow::Error::from)
    }

    fn read_options(&self) -> CaseOptions {
        CaseOptions {
            allow_read: self.allow_read.clone(),
            ..CaseOptions::default()
        }
    }

    /// The parameters the case script declares.
    pub fn declared(&self) -> Result<Vec<ParamDecl>> {
        list_params_with(&self.case, &self.read_options())
            .with_context(|| format!("cannot read the parameters of {}", self.case.display()))
    }

    /// The `--set` values of motion `m`: the `--set` ones, then the row's.
    fn values_of(&self, m: &Motion) -> Vec<(String, ParamValue)> {
        self.overrides.iter().chain(&m.values).cloned().collect()
    }

    /// One planned run per motion, in `out_dir/runs/`.
    pub(crate) fn plans(&self, out_dir: &Path, declared: &[ParamDecl]) -> Vec<Planned> {
        let runs = out_dir.join("runs");
        let options = self.read_options();
        self.motions
            .iter()
            .map(|m| {
                Planned::new(
                    m.name.clone(),
                    &runs,
                    self.values_of(m),
                    (&self.case, &options),
                    declared,
                )
            })
            .collect()
    }
}

/// The options of `slosh assess CASE --motions SUITE`.
#[derive(Clone, Debug, Default)]
pub struct AssessRequest {
    /// The case script.
    pub case: PathBuf,
    /// The suite file (CSV or RON).
    pub motions: PathBuf,
    /// Assessment folder (default `out/<case>-assess`).
    pub out: Option<PathBuf>,
    /// `--set NAME=VALUE` for every motion, as (name, value).
    pub overrides: Vec<(String, ParamValue)>,
    /// Folders the script may also read.
    pub allow_read: Vec<PathBuf>,
}

/// Checks the case and the suite (every row is loaded as the run will load it, so a missing
/// record or a wrong value stops here, before anything runs), writes the manifest into the
/// assessment folder and returns it with that folder and the folder's hold
/// ([`crate::sweep::hold_folder`]; keep it while the folder is in use, `None` on a file
/// system without locks).
pub fn prepare(request: &AssessRequest) -> Result<(Manifest, PathBuf, Option<std::fs::File>)> {
    let absolute = |p: &Path| -> Result<PathBuf> {
        std::path::absolute(p).with_context(|| format!("cannot resolve {}", p.display()))
    };
    if !request.case.is_file() {
        bail!("the case script {} does not exist", request.case.display());
    }
    let options = CaseOptions {
        allow_read: request.allow_read.clone(),
        ..CaseOptions::default()
    };
    let declared = list_params_with(&request.case, &options)
        .with_context(|| format!("cannot read the parameters of {}", request.case.display()))?;
    let rows = suite::read_suite(&request.motions, &declared)?;
    // --set names and types, with the script's own message for unknown names.
    let mut typed_overrides = Vec::new();
    for (name, value) in &request.overrides {
        if let Some(row) = rows
            .iter()
            .find(|r| r.values.iter().any(|(n, _)| n == name))
        {
            bail!(
                "--set {name}: the suite {} sets `{name}` itself (line {}); give it in the suite \
                 or with --set, not both",
                request.motions.display(),
                row.line
            );
        }
        let value = match declared.iter().find(|p| &p.name == name) {
            Some(decl) => value
                .coerce_to(&decl.default)
                .map_err(|e| anyhow::anyhow!("--set {name}: {e}"))?,
            // The script's own message, which lists the parameters it declares.
            None => match load_case(&request.case, &set_only(request)) {
                Err(e) => bail!("{e}"),
                Ok(_) => value.clone(),
            },
        };
        typed_overrides.push((name.clone(), value));
    }
    let mut case_name = None;
    for row in &rows {
        let overrides = typed_overrides.iter().chain(&row.values).cloned().collect();
        let row_options = CaseOptions {
            overrides,
            allow_read: request.allow_read.clone(),
            ..CaseOptions::default()
        };
        let case = load_case(&request.case, &row_options).map_err(|e| {
            anyhow::anyhow!(
                "{}:{}: motion `{}`: {e}",
                request.motions.display(),
                row.line,
                row.name
            )
        })?;
        case_name.get_or_insert(case.name);
    }
    let out_dir = match &request.out {
        Some(d) => d.clone(),
        None => PathBuf::from("out").join(format!(
            "{}-assess",
            case_name.unwrap_or_else(|| "case".into())
        )),
    };
    std::fs::create_dir_all(out_dir.join("runs"))
        .with_context(|| format!("cannot create the assessment folder {}", out_dir.display()))?;
    // Held from before the manifest is written until the caller is done with the folder: a
    // second assessment into it is refused before it replaces the running one's manifest.
    let held = crate::sweep::hold_folder(&out_dir, "an assessment")?;
    let manifest = Manifest {
        version: env!("CARGO_PKG_VERSION").to_string(),
        case: absolute(&request.case)?,
        suite: absolute(&request.motions)?,
        allow_read: request
            .allow_read
            .iter()
            .map(|p| absolute(p))
            .collect::<Result<_>>()?,
        overrides: typed_overrides,
        motions: rows
            .into_iter()
            .map(|r| Motion {
                name: r.name,
                values: r.values,
            })
            .collect(),
    };
    manifest.write(&out_dir)?;
    Ok((manifest, out_dir, held))
}

/// The case options of the `--set` values alone.
fn set_only(request: &AssessRequest) -> CaseOptions {
    CaseOptions {
        overrides: request.overrides.clone(),
        allow_read: request.allow_read.clone(),
        ..CaseOptions::default()
    }
}

/// Runs the motions of `manifest` not completed before, `jobs` at once (0: one per core),
/// then writes the report. Returns the report's outcome. The caller holds the folder (the
/// hold [`prepare`] returns).
pub fn run_local(
    exe: &Path,
    manifest: &Manifest,
    out_dir: &Path,
    jobs: usize,
    quiet: bool,
) -> Result<report::Collected> {
    let declared = manifest.declared()?;
    let plans = manifest.plans(out_dir, &declared);
    let results = crate::sweep::run_planned(
        exe,
        &manifest.case,
        &plans,
        &out_dir.join("runs"),
        jobs,
        None,
        quiet,
        &manifest.allow_read,
        "assess",
    );
    let collected = report::write_report(manifest, out_dir, &plans)?;
    if let Some(signal) = crate::interrupt::received() {
        let done = results
            .iter()
            .filter(|d| d.outcome.status != CaseStatus::Interrupted)
            .count();
        return Err(
            anyhow::Error::new(crate::interrupt::Interrupted { signal }).context(format!(
                "the assessment stopped after {done} of {} motions; run the same command again \
                 to run the rest",
                plans.len()
            )),
        );
    }
    Ok(collected)
}

/// Runs motion `index` of the assessment in `out_dir` (one Slurm array task) with `threads`
/// threads (`None`: [`crate::slurm::task_threads`]'s choice, `$SLURM_CPUS_PER_TASK` in an
/// array task); a run completed before is not run again, one interrupted (a time limit, a
/// requeue) continues from its checkpoint.
pub fn run_task(
    exe: &Path,
    out_dir: &Path,
    index: usize,
    threads: Option<usize>,
) -> Result<CaseStatus> {
    let threads = crate::slurm::task_threads(threads)?;
    let manifest = Manifest::read(out_dir)?;
    let n = manifest.motions.len();
    if index >= n {
        bail!(
            "task {index}: the assessment in {} has {n} motions (tasks 0 to {})",
            out_dir.display(),
            n.saturating_sub(1)
        );
    }
    let declared = manifest.declared()?;
    let plans = manifest.plans(out_dir, &declared);
    let plan = &plans[index..=index];
    let results = crate::sweep::run_planned(
        exe,
        &manifest.case,
        plan,
        &out_dir.join("runs"),
        1,
        Some(threads),
        false,
        &manifest.allow_read,
        "assess",
    );
    let outcome = &results[0].outcome;
    match outcome.status {
        CaseStatus::Failed => bail!(
            "motion {} failed: {} (log: {})",
            outcome.folder,
            outcome.error.as_deref().unwrap_or("unknown error"),
            plan[0].dir.join("run.log").display()
        ),
        CaseStatus::Interrupted => {
            let signal = crate::interrupt::received().unwrap_or(libc::SIGTERM);
            Err(anyhow::Error::new(crate::interrupt::Interrupted { signal })
                .context(format!("motion {} was interrupted", outcome.folder)))
        }
        status => Ok(status),
    }
}

/// Writes the report of the assessment in `out_dir` from the runs finished so far.
pub fn collect(out_dir: &Path) -> Result<report::Collected> {
    let manifest = Manifest::read(out_dir)?;
    let declared = manifest.declared()?;
    let plans = manifest.plans(out_dir, &declared);
    report::write_report(&manifest, out_dir, &plans)
}

/// Writes `DIR/assess.sbatch` for the assessment in `out_dir`, then submits it or prints
/// the `sbatch` command (see [`crate::slurm::write_and_submit`]).
pub fn write_slurm_job(
    exe: &Path,
    manifest: &Manifest,
    out_dir: &Path,
    options: &SlurmOptions,
    submit: bool,
    collect: &str,
) -> Result<()> {
    let out_abs = std::path::absolute(out_dir)
        .with_context(|| format!("cannot resolve {}", out_dir.display()))?;
    let stem = manifest
        .case
        .file_stem()
        .map_or("case".into(), |s| s.to_string_lossy().into_owned());
    let job = JobArray {
        job_name: format!("slosh-assess-{}", crate::sweep::folder_safe(&stem)),
        tasks: manifest.motions.len(),
        exe: std::path::absolute(exe)?,
        task_args: vec![
            "assess".into(),
            "--out".into(),
            out_abs.display().to_string(),
        ],
        log_dir: out_abs.join("slurm"),
    };
    crate::slurm::write_and_submit(&out_abs.join(BATCH_SCRIPT), &job, options, submit, collect)
}
