//! The `slosh assess` command line.

use super::{collect, prepare, run_local, run_task, write_slurm_job, AssessRequest};
use crate::slurm::SlurmArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use slosh_script::ParamValue;
use std::path::{Path, PathBuf};

/// Arguments of `slosh assess`.
#[derive(Args, Debug)]
pub struct AssessArgs {
    /// The case script (.rhai); its parameters are the suite's columns.
    pub case: Option<PathBuf>,
    /// The suite: a CSV or RON table with one ground motion per row, columns named after
    /// the script's parameters (e.g. record, pga) plus an optional `name`.
    #[arg(long, value_name = "SUITE.csv|SUITE.ron")]
    pub motions: Option<PathBuf>,
    /// Assessment folder (default: out/<case-name>-assess); runs go to DIR/runs/<name>/.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Motions run at once, each with cores/jobs threads (default 0: one per core, up to the
    /// number of motions).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Override a parameter for every motion (one the suite does not set).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Also let the script read files below DIR (repeatable), as `slosh run --allow-read`.
    #[arg(long = "allow-read", value_name = "DIR")]
    pub allow_read: Vec<PathBuf>,
    /// Report failures only: no progress lines.
    #[arg(long)]
    pub quiet: bool,
    /// After the suite, run the motion with the largest design load at successive
    /// resolutions (`slosh converge`, into DIR/converge/<motion>/) and put each design load's
    /// grid convergence index beside the report's loads.
    #[arg(long, conflicts_with_all = ["slurm", "task"])]
    pub converge: bool,
    /// The resolution parameter of --converge (its value for the motion is the coarsest
    /// level).
    #[arg(long, value_name = "NAME", default_value = "dx", requires = "converge")]
    pub converge_param: String,
    /// Levels of --converge.
    #[arg(long, value_name = "N", default_value_t = 3, requires = "converge")]
    pub converge_levels: usize,
    /// Slurm: write DIR/assess.sbatch (one array task per motion) and the manifest it reads.
    #[command(flatten)]
    pub slurm: SlurmArgs,
    /// Run one motion of the assessment in --out DIR: task I (default: $SLURM_ARRAY_TASK_ID).
    #[arg(long, value_name = "I", num_args = 0..=1,
          conflicts_with_all = ["case", "motions", "slurm", "collect", "set"])]
    pub task: Option<Option<usize>>,
    /// Threads of the task's run (with --task; default: $SLURM_CPUS_PER_TASK when set, else
    /// all cores).
    #[arg(long, value_name = "N", requires = "task", value_parser = crate::thread_count)]
    pub threads: Option<usize>,
    /// Write the report of the assessment in --out DIR from its finished runs and list the
    /// missing and failed ones.
    #[arg(long, conflicts_with_all = ["case", "motions", "slurm", "set"])]
    pub collect: bool,
    /// Where the runs' steps run: cpu, gpu or gpu_f32 (as `slosh run --backend`; passed to each run,
    /// and to the array tasks of a Slurm job, as SLOSH_BACKEND).
    #[arg(long, value_parser = slosh_core::Backend::NAMES)]
    pub backend: Option<String>,
}

/// Runs `slosh assess` with `overrides`, the parsed `--set` values.
pub fn cli_assess(args: AssessArgs, overrides: Vec<(String, ParamValue)>) -> Result<()> {
    let exe = std::env::current_exe()
        .context("cannot find the slosh executable that runs the motions")?;
    if let Some(task) = args.task {
        let out = needs_out(&args.out, "--task")?;
        let index = crate::slurm::task_index(task)?;
        let status = run_task(&exe, out, index, args.threads)?;
        if !args.quiet {
            eprintln!("assess: task {index} {status}");
        }
        return Ok(());
    }
    if args.collect {
        let out = needs_out(&args.out, "--collect")?;
        let collected = collect(out)?;
        if args.converge {
            let manifest = super::Manifest::read(out)?;
            return converge_worst(&exe, &manifest, out, &args).and_then(|c| finish(c, args.quiet));
        }
        return finish(collected, args.quiet);
    }
    let (Some(case), Some(motions)) = (args.case.clone(), args.motions.clone()) else {
        bail!(
            "slosh assess needs a case script and a suite: slosh assess CASE.rhai --motions \
             SUITE.csv [--out DIR]; or --task I --out DIR, or --collect --out DIR"
        );
    };
    let slurm = args.slurm.options();
    if args.slurm.slurm {
        slurm.check()?;
        if let Some(out) = &args.out {
            // Before anything is created: the folder is written into the batch script.
            crate::slurm::check_plain("--out", &out.display().to_string())?;
        }
    }
    // `_held`: the assessment folder, held (against a second assessment into it) until this
    // command is done with it.
    let (manifest, out_dir, _held) = prepare(&AssessRequest {
        case,
        motions,
        out: args.out.clone(),
        overrides,
        allow_read: args.allow_read.clone(),
    })?;
    if args.slurm.slurm {
        let collect = crate::slurm::command_line(&[
            exe.display().to_string(),
            "assess".into(),
            "--collect".into(),
            "--out".into(),
            out_dir.display().to_string(),
        ]);
        write_slurm_job(
            &exe,
            &manifest,
            &out_dir,
            &slurm,
            args.slurm.submit,
            &collect,
        )?;
        return Ok(());
    }
    let collected = run_local(&exe, &manifest, &out_dir, args.jobs, args.quiet)?;
    if args.converge {
        return converge_worst(&exe, &manifest, &out_dir, &args)
            .and_then(|c| finish(c, args.quiet));
    }
    finish(collected, args.quiet)
}

/// `--converge`: the worst motion through `slosh converge`, then the report again with its
/// resolution section.
fn converge_worst(
    exe: &Path,
    manifest: &super::Manifest,
    out_dir: &Path,
    args: &AssessArgs,
) -> Result<super::report::Collected> {
    let declared = manifest.declared()?;
    let plans = manifest.plans(out_dir, &declared);
    let Some((name, why)) = super::report::worst_motion(manifest, &plans) else {
        bail!("--converge: no motion has a finished run to study");
    };
    let motion = manifest
        .motions
        .iter()
        .find(|m| m.name == name)
        .context("the worst motion is in the manifest")?;
    // Strings print quoted, so that a comma in a record's path stays one value.
    let sets: Vec<String> = manifest
        .overrides
        .iter()
        .chain(&motion.values)
        .map(|(n, v)| format!("{n}={v}"))
        .collect();
    if !args.quiet {
        eprintln!(
            "assess: --converge runs motion {name} ({why}) at {} levels of {}",
            args.converge_levels, args.converge_param
        );
    }
    let request = crate::converge::ConvergeRequest {
        param: args.converge_param.clone(),
        levels: args.converge_levels,
        ratio: 2.0,
        refine: None,
        sets,
        out: Some(super::report::converge_dir(out_dir, &name)),
        jobs: args.jobs,
        quiet: args.quiet,
        allow_read: manifest.allow_read.clone(),
    };
    let outcome = crate::converge::cli_converge(
        exe,
        &manifest.case,
        &request,
        &crate::sweep::SweepMode::Run,
    )?;
    if outcome.csv.is_none() {
        bail!(
            "--converge: not every level of motion {name} completed (see {})",
            super::report::converge_dir(out_dir, &name).display()
        );
    }
    collect(out_dir)
}

fn needs_out<'a>(out: &'a Option<PathBuf>, what: &str) -> Result<&'a Path> {
    out.as_deref().ok_or_else(|| {
        anyhow::anyhow!("{what} needs --out DIR, the folder of the assessment (holding assess.ron)")
    })
}

/// Prints the verdicts and the report's path; an error when motions are missing or failed.
fn finish(c: super::report::Collected, quiet: bool) -> Result<()> {
    for v in &c.verdicts {
        println!("{v}");
    }
    if !quiet {
        println!(
            "report: {} (table: {})",
            c.report.display(),
            c.csv.display()
        );
    }
    if c.missing.is_empty() && c.failed.is_empty() {
        return Ok(());
    }
    let mut text = format!(
        "the report covers {} motion{} only",
        c.completed,
        if c.completed == 1 { "" } else { "s" }
    );
    if !c.missing.is_empty() {
        text.push_str(&format!("; missing: {}", c.missing.join(", ")));
    }
    if !c.failed.is_empty() {
        let failed: Vec<String> = c.failed.iter().map(|(n, e)| format!("{n} ({e})")).collect();
        text.push_str(&format!("; failed: {}", failed.join(", ")));
    }
    text.push_str(
        "; rerun the same command (or the missing array tasks) to run them, each failed run's \
         run.log says why",
    );
    bail!(text)
}
