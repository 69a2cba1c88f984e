//! `report.md`: a summary table of every check, then one section per group with its rows,
//! notes and plots.

use super::{Check, ValidationReport, Verdict};
use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;

/// Markdown-safe cell text (no pipes, no line breaks).
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

fn row(c: &Check) -> String {
    format!(
        "| {} | {} | {} | {} | {} | **{}** | {} |\n",
        cell(&c.name),
        cell(&c.measured),
        cell(&c.reference),
        cell(&c.error),
        cell(&c.tolerance),
        c.verdict.label(),
        cell(&c.reason)
    )
}

const HEADER: &str = "| check | measured | reference | error | tolerance | verdict | why this tolerance |\n|---|---|---|---|---|---|---|\n";

/// Writes the report as markdown to `path`.
pub fn write_report(report: &ValidationReport, path: &Path) -> Result<()> {
    let mut md = String::new();
    let n = report.checks().count();
    let failed = report.failures().len();
    let count = |v: Verdict| report.checks().filter(|c| c.verdict == v).count();
    let (passed, open) = (count(Verdict::Pass), count(Verdict::Open));
    let _ = writeln!(md, "# slosh validation report\n");
    let _ = writeln!(
        md,
        "Command: `slosh validate{}{} --out {}` · scheme: the paper's, unless a group's rows or \
         notes name another preset · {} checks: {passed} PASS, {failed} FAIL, {open} OPEN, {} INFO · \
         wall time {:.0} s · slosh {}\n",
        if report.quick { " --quick" } else { "" },
        report
            .only
            .as_ref()
            .map(|o| format!(" --only \"{o}\""))
            .unwrap_or_default(),
        path.parent()
            .map(|p| p.display().to_string())
            .unwrap_or_default(),
        n,
        n - passed - failed - open,
        report.wall_time_s,
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        md,
        "**Verdict: {}**\n",
        if failed == 0 && open == 0 {
            "all checks pass".to_string()
        } else if failed == 0 {
            format!(
                "no check fails; {open} OPEN (targets of open work not met yet, each with what \
                 is known of the gap)"
            )
        } else {
            format!("{failed} check(s) FAIL — see the rows marked FAIL and their reasons")
        }
    );
    let _ = writeln!(md, "## Summary\n");
    md.push_str("| group | check | measured | reference | error | tolerance | verdict |\n|---|---|---|---|---|---|---|\n");
    for (title, g) in &report.groups {
        for c in &g.checks {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | **{}** |",
                cell(title),
                cell(&c.name),
                cell(&c.measured),
                cell(&c.reference),
                cell(&c.error),
                cell(&c.tolerance),
                c.verdict.label()
            );
        }
    }
    md.push('\n');
    for (title, g) in &report.groups {
        let _ = writeln!(md, "## {title}\n");
        for note in &g.notes {
            let _ = writeln!(md, "{note}\n");
        }
        md.push_str(HEADER);
        for c in &g.checks {
            md.push_str(&row(c));
        }
        md.push('\n');
        for p in &g.plots {
            let _ = writeln!(md, "![{}]({})\n", cell(&p.caption), p.file);
        }
        if g.particle_steps > 0.0 {
            let _ = writeln!(md, "_{:.2e} particle-steps._\n", g.particle_steps);
        }
    }
    slosh_io::write_atomic(path, md.as_bytes())?;
    Ok(())
}
