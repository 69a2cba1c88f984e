//! `slosh validate [--quick] [--out DIR] [--only TEXT] [--checkpoint-every D]`: runs the validation suite of
//! `slosh-validate` with progress lines on stderr and prints one line per check.

use anyhow::Result;
use slosh_validate::{run_validation, ValidateOptions, ValidationReport};
use std::path::PathBuf;

/// The `slosh validate` command: runs the suite, prints the table and where the report is;
/// returns true when every check passed. `checkpoint_every`: wall time between checkpoints
/// of the longest runs (`None`: none).
pub fn cli_validate(
    quick: bool,
    out: PathBuf,
    only: Option<String>,
    checkpoint_every: Option<std::time::Duration>,
) -> Result<bool> {
    let report = run_validation(&ValidateOptions {
        quick,
        out,
        progress: Some(|line| eprintln!("{line}")),
        only,
        checkpoint_every,
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
