//! `slosh validate`: runs the solver (paper scheme, `SphParams::default()`) on a fixed list of
//! cases, compares each with its reference (closed forms of `slosh-theory`, published
//! experiments in `data/`) and writes `report.md` with plots.
//!
//! Every check carries its tolerance and the reason for it; a check whose reference is only
//! informative (no tolerance) is reported as INFO and never fails the suite.

mod dambreak;
mod report;
mod resolution;
mod run;
mod sloshing;

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use report::write_report;

/// What to run and where to write.
#[derive(Clone, Debug)]
pub struct ValidateOptions {
    /// The quick subset (about 2 minutes): shorter runs, the finest resolution skipped.
    pub quick: bool,
    /// Output folder for `report.md` and the plots.
    pub out: PathBuf,
    /// Print one line per case to stderr.
    pub verbose: bool,
}

/// Outcome of one check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Within tolerance.
    Pass,
    /// Outside tolerance.
    Fail,
    /// Reported for information only (no tolerance).
    Info,
}

impl Verdict {
    /// The word the report prints.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Pass => "PASS",
            Verdict::Fail => "FAIL",
            Verdict::Info => "INFO",
        }
    }
}

/// One row of the report.
#[derive(Clone, Debug)]
pub struct Check {
    /// Group (section of the report), e.g. "Free sloshing".
    pub group: String,
    /// What is compared, e.g. "period T₁, tank 1.0 × 0.5 m".
    pub name: String,
    /// The measured value, formatted with its unit.
    pub measured: String,
    /// The reference value, formatted with its unit.
    pub reference: String,
    /// The error (relative or absolute, as stated).
    pub error: String,
    /// The tolerance, formatted.
    pub tolerance: String,
    /// Why this tolerance (or why no tolerance).
    pub reason: String,
    /// PASS / FAIL / INFO.
    pub verdict: Verdict,
}

/// A check of a relative error |m/r − 1| against a tolerance.
pub(crate) fn relative_check(
    group: &str,
    name: &str,
    measured: f64,
    reference: f64,
    unit: &str,
    tolerance: f64,
    reason: &str,
) -> Check {
    let err = measured / reference - 1.0;
    let pass = err.is_finite() && err.abs() <= tolerance;
    Check {
        group: group.into(),
        name: name.into(),
        measured: format!("{} {unit}", fmt_num(measured)),
        reference: format!("{} {unit}", fmt_num(reference)),
        error: format!("{:+.1} %", 100.0 * err),
        tolerance: format!("± {:.0} %", 100.0 * tolerance),
        reason: reason.into(),
        verdict: if pass { Verdict::Pass } else { Verdict::Fail },
    }
}

/// A check of a ratio m/r against a band [lo, hi].
#[allow(clippy::too_many_arguments)]
pub(crate) fn ratio_band_check(
    group: &str,
    name: &str,
    measured: f64,
    reference: f64,
    unit: &str,
    band: (f64, f64),
    reason: &str,
) -> Check {
    let ratio = measured / reference;
    let pass = ratio.is_finite() && ratio >= band.0 && ratio <= band.1;
    Check {
        group: group.into(),
        name: name.into(),
        measured: format!("{} {unit}", fmt_num(measured)),
        reference: format!("{} {unit}", fmt_num(reference)),
        error: format!("ratio {ratio:.3}"),
        tolerance: format!("ratio in [{:.2}, {:.2}]", band.0, band.1),
        reason: reason.into(),
        verdict: if pass { Verdict::Pass } else { Verdict::Fail },
    }
}

/// An informative row without tolerance.
pub(crate) fn info_row(
    group: &str,
    name: &str,
    measured: String,
    reference: String,
    error: String,
    reason: &str,
) -> Check {
    Check {
        group: group.into(),
        name: name.into(),
        measured,
        reference,
        error,
        tolerance: "—".into(),
        reason: reason.into(),
        verdict: Verdict::Info,
    }
}

/// A check that could not be evaluated (the run failed or gave no data): a FAIL with the cause.
pub(crate) fn failed_run(group: &str, name: &str, cause: &str) -> Check {
    Check {
        group: group.into(),
        name: name.into(),
        measured: "—".into(),
        reference: "—".into(),
        error: "—".into(),
        tolerance: "—".into(),
        reason: format!("not evaluated: {cause}"),
        verdict: Verdict::Fail,
    }
}

/// Four significant digits, plain notation for ordinary magnitudes.
pub(crate) fn fmt_num(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if a == 0.0 || (1e-3..1e5).contains(&a) {
        let digits = if a == 0.0 {
            0
        } else {
            (3 - a.log10().floor() as i32).max(0) as usize
        };
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}

/// A plot written by a check group (file stem under the output folder, caption).
#[derive(Clone, Debug)]
pub struct PlotRef {
    /// File name of the PNG, relative to the output folder.
    pub file: String,
    /// One-line caption.
    pub caption: String,
}

/// The checks of one group with their plots and notes.
#[derive(Clone, Debug, Default)]
pub struct GroupResult {
    /// The rows.
    pub checks: Vec<Check>,
    /// Plots written.
    pub plots: Vec<PlotRef>,
    /// Notes for the report (set-up, how the value is measured).
    pub notes: Vec<String>,
    /// Simulated particle-steps, for the timing line.
    pub particle_steps: f64,
}

/// Everything the suite produced.
#[derive(Clone, Debug)]
pub struct ValidationReport {
    /// Whether the quick subset was run.
    pub quick: bool,
    /// Groups in report order: (title, result).
    pub groups: Vec<(String, GroupResult)>,
    /// Wall-clock time of the whole suite (s).
    pub wall_time_s: f64,
    /// Where `report.md` was written.
    pub report_path: PathBuf,
}

impl ValidationReport {
    /// All rows of all groups.
    pub fn checks(&self) -> impl Iterator<Item = &Check> {
        self.groups.iter().flat_map(|(_, g)| g.checks.iter())
    }
    /// True when no check failed.
    pub fn all_pass(&self) -> bool {
        self.checks().all(|c| c.verdict != Verdict::Fail)
    }
    /// Rows that failed.
    pub fn failures(&self) -> Vec<&Check> {
        self.checks()
            .filter(|c| c.verdict == Verdict::Fail)
            .collect()
    }
}

/// Runs the suite and writes `report.md` and the plots into `opts.out`.
pub fn run_validation(opts: &ValidateOptions) -> Result<ValidationReport> {
    let start = Instant::now();
    std::fs::create_dir_all(&opts.out)
        .with_context(|| format!("cannot create the output folder {}", opts.out.display()))?;
    let ctx = run::Context {
        quick: opts.quick,
        out: opts.out.clone(),
        verbose: opts.verbose,
    };
    let mut groups: Vec<(String, GroupResult)> = Vec::new();
    let stage = |name: &str| {
        if opts.verbose {
            eprintln!("[validate {:6.1} s] {name}", start.elapsed().as_secs_f64());
        }
    };
    stage("paper case §3.1: hydrostatic, resonant response, Housner pressure, base shear");
    groups.extend(sloshing::paper_forced_case(&ctx));
    stage("off-resonance forced response");
    groups.push((
        "Linear forced response, off resonance".into(),
        sloshing::off_resonance(&ctx),
    ));
    stage("free sloshing, three tanks");
    groups.push(("Free-sloshing period".into(), sloshing::free_sloshing(&ctx)));
    stage("dam break: front");
    groups.push(("Dam break: surge front".into(), dambreak::front(&ctx)));
    stage("dam break: wall pressure");
    groups.push((
        "Dam break: wall pressure".into(),
        dambreak::wall_pressure(&ctx),
    ));
    stage("resolution study");
    groups.push(("Resolution study".into(), resolution::study(&ctx)));
    stage("writing the report");
    let wall_time_s = start.elapsed().as_secs_f64();
    let report_path = opts.out.join("report.md");
    let report = ValidationReport {
        quick: opts.quick,
        groups,
        wall_time_s,
        report_path: report_path.clone(),
    };
    write_report(&report, &report_path)?;
    Ok(report)
}

/// The `slosh validate [--quick] [--out DIR]` command: runs the suite, prints the table and
/// where the report is; returns true when every check passed.
pub fn cli_validate(quick: bool, out: PathBuf) -> Result<bool> {
    let report = run_validation(&ValidateOptions {
        quick,
        out,
        verbose: true,
    })?;
    print_summary(&report);
    Ok(report.all_pass())
}

/// One line per check on stdout, then the verdict.
fn print_summary(report: &ValidationReport) {
    for c in report.checks() {
        println!(
            "{:4}  {} / {}: {} vs {} ({}; tolerance {})",
            c.verdict.label(),
            c.group,
            c.name,
            c.measured,
            c.reference,
            c.error,
            c.tolerance
        );
    }
    let failures = report.failures();
    println!(
        "{} checks, {} failed, {:.0} s; report: {}",
        report.checks().count(),
        failures.len(),
        report.wall_time_s,
        report.report_path.display()
    );
}

/// Path of a plot stem in the output folder.
pub(crate) fn plot_path(out: &Path, stem: &str) -> PathBuf {
    out.join(stem)
}
