//! `slosh converge SCRIPT --param dx --levels 3 --ratio 2`: a case at successive resolutions
//! and how far each result moves with them.
//!
//! The levels run as a sweep over the resolution parameter (their own folders, resumable,
//! `--jobs`, Slurm array jobs), and `convergence.csv` / `convergence.md` give, for every number
//! of the levels' `summary.ron` (the roof load's scalars included), the levels' values, the
//! observed order of convergence, the Richardson-extrapolated value and the grid convergence
//! index of the finest level by the procedure of Celik, Ghia, Roache, Freitas, Coleman & Raad
//! (2008), "Procedure for estimation and reporting of uncertainty due to discretization in CFD
//! applications", J. Fluids Eng. 130, 078001 (the procedure ASME V&V 20 uses), over the finest
//! three levels; `docs/roof-loads.md` says how to read them.

use crate::sweep::{cli_sweep_as, summary_columns, CaseStatus, SweepMode, SweepOutcome};
use anyhow::{bail, Context, Result};
use slosh_script::{list_params_with, load_case, parse_set_value, CaseOptions, ParamValue};
use slosh_validate::gci::{uncertainty, Uncertainty};
use std::path::{Path, PathBuf};

/// How a parameter makes the lattice finer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refinement {
    /// A length (dx): the next level divides it by the ratio.
    Divide,
    /// A count (particles per depth or radius): the next level multiplies it by the ratio.
    Multiply,
}

impl Refinement {
    /// The refinement a parameter's name implies: `dx`, `*_dx`, `spacing`, `h` divide;
    /// `particles_per_*`, `*_per_*` multiply; `None` for any other name.
    pub fn from_name(name: &str) -> Option<Refinement> {
        let n = name.to_ascii_lowercase();
        if n == "dx" || n.ends_with("_dx") || n.contains("spacing") || n == "h" {
            Some(Refinement::Divide)
        } else if n.contains("_per_") || n.starts_with("particles") {
            Some(Refinement::Multiply)
        } else {
            None
        }
    }

    /// Parses `divide` or `multiply`.
    pub fn parse(text: &str) -> Result<Refinement> {
        match text {
            "divide" => Ok(Refinement::Divide),
            "multiply" => Ok(Refinement::Multiply),
            other => bail!("--refine {other}: use divide (a spacing) or multiply (a count)"),
        }
    }
}

/// What `slosh converge` is asked to do.
#[derive(Clone, Debug)]
pub struct ConvergeRequest {
    /// The resolution parameter of the script.
    pub param: String,
    /// Number of levels (≥ 2; 3 or more for an order and a GCI).
    pub levels: usize,
    /// Refinement ratio between consecutive levels (> 1).
    pub ratio: f64,
    /// How the parameter refines; `None`: from its name.
    pub refine: Option<Refinement>,
    /// Other parameters, `NAME=VALUE`, the same at every level; the resolution parameter's
    /// own sets the coarsest level.
    pub sets: Vec<String>,
    /// The folder (default `out/<case-name>-converge`).
    pub out: Option<PathBuf>,
    /// Levels run at once (0: one per core, up to the levels).
    pub jobs: usize,
    /// Report failures only.
    pub quiet: bool,
    /// Folders the script may read from besides its own.
    pub allow_read: Vec<PathBuf>,
}

/// The levels' values of the resolution parameter, coarsest first, and their representative
/// spacings h (the parameter for a spacing, its inverse for a count). A whole-number
/// parameter is rounded at each level, and the ratios then follow the rounded values.
pub fn level_values(
    base: &ParamValue,
    levels: usize,
    ratio: f64,
    refine: Refinement,
) -> Result<(Vec<ParamValue>, Vec<f64>)> {
    let start = match base {
        ParamValue::Float(x) => *x,
        ParamValue::Int(i) => *i as f64,
        other => bail!("the resolution parameter must be a number (its value is {other})"),
    };
    if !(start.is_finite() && start > 0.0) {
        bail!("the resolution parameter must be > 0 (it is {start})");
    }
    let mut values = Vec::with_capacity(levels);
    let mut h = Vec::with_capacity(levels);
    for k in 0..levels {
        let x = match refine {
            Refinement::Divide => start / ratio.powi(k as i32),
            Refinement::Multiply => start * ratio.powi(k as i32),
        };
        let value = match base {
            ParamValue::Int(_) => {
                let i = x.round() as i64;
                if values.last() == Some(&ParamValue::Int(i)) {
                    bail!(
                        "the levels {} and {} of a whole-number parameter round to the same \
                         value {i}: a larger --ratio or a larger starting value",
                        k,
                        k + 1
                    );
                }
                ParamValue::Int(i)
            }
            _ => ParamValue::Float(x),
        };
        let v = match value {
            ParamValue::Int(i) => i as f64,
            ParamValue::Float(x) => x,
            _ => unreachable!("numbers only"),
        };
        h.push(match refine {
            Refinement::Divide => v,
            Refinement::Multiply => 1.0 / v,
        });
        values.push(value);
    }
    Ok((values, h))
}

/// Summary numbers that are not results of the physics (bookkeeping and speed of the run,
/// inputs that do not change with the lattice).
const NOT_RESULTS: [&str; 15] = [
    "wall_time_s",
    "steps",
    "particles_fluid",
    "particles_wall",
    "checkpoints_written",
    "steps_above_mach_limit",
    "steps_above_dt_bound",
    "roof_impacts",
    "particle_steps_per_s",
    "fluid_particle_steps_per_s",
    "threads",
    "dim",
    "sim_time",
    "settle",
    "duration",
];

/// The series `convergence` overlays for all levels, when the runs have them.
const OVERLAID: [&str; 4] = [
    "eta_left",
    "base_shear_x_lp",
    "roof_force_up_lp",
    "roof_force_up",
];

/// One quantity of `convergence.csv`.
#[derive(Clone, Debug)]
pub struct QuantityRow {
    /// The summary number's name.
    pub name: String,
    /// Its value at each level, coarsest first.
    pub values: Vec<f64>,
    /// The finest level's uncertainty.
    pub uncertainty: Uncertainty,
}

/// What `slosh converge` produced.
#[derive(Clone, Debug)]
pub struct ConvergeOutcome {
    /// The sweep of the levels.
    pub sweep: SweepOutcome,
    /// The parameter's value at each level, coarsest first.
    pub values: Vec<ParamValue>,
    /// Representative spacing h of each level.
    pub spacings: Vec<f64>,
    /// The quantities (empty until every level has completed).
    pub rows: Vec<QuantityRow>,
    /// `convergence.csv`, when written.
    pub csv: Option<PathBuf>,
}

/// Runs (or, in the Slurm modes, plans or collects) the levels and writes the convergence
/// report once every level has completed.
pub fn cli_converge(
    exe: &Path,
    case: &Path,
    request: &ConvergeRequest,
    mode: &SweepMode,
) -> Result<ConvergeOutcome> {
    if request.levels < 2 {
        bail!(
            "--levels {}: at least 2 (3 or more for an order and a GCI)",
            request.levels
        );
    }
    if request.levels > 8 {
        bail!(
            "--levels {}: at most 8 (each level costs 2^D times the one before at --ratio 2)",
            request.levels
        );
    }
    if !(request.ratio.is_finite() && request.ratio > 1.0) {
        bail!(
            "--ratio {}: the refinement ratio must be > 1 (Celik et al. recommend ≥ 1.3)",
            request.ratio
        );
    }
    let mut sets: Vec<(String, ParamValue)> = Vec::new();
    for s in &request.sets {
        let Some((name, value)) = s.split_once('=') else {
            bail!("--set {s}: expected NAME=VALUE");
        };
        sets.push((name.to_string(), parse_set_value(value)));
    }
    let options = CaseOptions {
        allow_read: request.allow_read.clone(),
        overrides: sets.clone(),
        ..CaseOptions::default()
    };
    let declared = list_params_with(case, &options)
        .with_context(|| format!("cannot read the parameters of {}", case.display()))?;
    let Some(decl) = declared.iter().find(|p| p.name == request.param) else {
        let known: Vec<String> = declared
            .iter()
            .map(|p| format!("  {} = {}", p.name, p.default))
            .collect();
        bail!(
            "--param {}: {} declares no parameter of that name; its parameters are:\n{}",
            request.param,
            case.display(),
            known.join("\n")
        );
    };
    let refine = match request
        .refine
        .or_else(|| Refinement::from_name(&request.param))
    {
        Some(r) => r,
        None => bail!(
            "--param {}: say whether a finer level divides it (a spacing) or multiplies it (a \
             count): --refine divide or --refine multiply",
            request.param
        ),
    };
    let (values, spacings) = level_values(&decl.value, request.levels, request.ratio, refine)?;
    let list: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    let mut vary = vec![format!("{}={}", request.param, list.join(","))];
    // The other parameters as one-value sweeps (a string quoted, so that a comma or a colon
    // in it stays one value); `--set <param>=V` gave the coarsest level.
    for (name, value) in &sets {
        if *name != request.param {
            let item = format!("{name}={value}");
            let parsed = crate::sweep::parse_vary(&item)?;
            if parsed.values.len() != 1 {
                bail!("--set {name}={value}: give one value (a string with commas in quotes)");
            }
            vary.push(item);
        }
    }
    let out = match &request.out {
        Some(d) => d.clone(),
        None => {
            let name = load_case(case, &options)
                .map(|c| c.name)
                .unwrap_or_else(|_| {
                    case.file_stem()
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_else(|| "case".into())
                });
            PathBuf::from("out").join(format!("{name}-converge"))
        }
    };
    let sweep = cli_sweep_as(
        exe,
        case,
        &vary,
        Some(out.clone()),
        request.jobs,
        request.quiet,
        &request.allow_read,
        mode,
    )?;
    let mut outcome = ConvergeOutcome {
        sweep,
        values,
        spacings,
        rows: Vec::new(),
        csv: None,
    };
    if !matches!(mode, SweepMode::Run | SweepMode::Collect) {
        return Ok(outcome);
    }
    let done = |s: CaseStatus| matches!(s, CaseStatus::Completed | CaseStatus::Skipped);
    if outcome.sweep.cases.len() != request.levels
        || !outcome.sweep.cases.iter().all(|c| done(c.status))
    {
        return Ok(outcome);
    }
    let folders: Vec<PathBuf> = outcome
        .sweep
        .cases
        .iter()
        .map(|c| out.join(&c.folder))
        .collect();
    let mut per_level: Vec<Vec<(String, String)>> = Vec::new();
    for f in &folders {
        let path = f.join("summary.ron");
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        per_level.push(summary_columns(&text, &path.display().to_string())?);
    }
    let mut rows = Vec::new();
    for (name, _) in &per_level[per_level.len() - 1] {
        if NOT_RESULTS.contains(&name.as_str()) || *name == request.param {
            continue;
        }
        let values: Vec<f64> = per_level
            .iter()
            .map(|level| {
                level
                    .iter()
                    .find(|(k, _)| k == name)
                    .and_then(|(_, v)| v.parse::<f64>().ok())
                    .unwrap_or(f64::NAN)
            })
            .collect();
        rows.push(QuantityRow {
            name: name.clone(),
            uncertainty: uncertainty(&values, &outcome.spacings),
            values,
        });
    }
    outcome.rows = rows;
    let csv = out.join("convergence.csv");
    write_csv(&csv, &request.param, &outcome)?;
    write_markdown(&out.join("convergence.md"), case, request, &outcome)?;
    if let Err(e) = overlay_plots(&out, &request.param, &outcome.values, &folders) {
        eprintln!("warning: the convergence plots were not drawn: {e:#}");
    }
    outcome.csv = Some(csv);
    Ok(outcome)
}

fn write_csv(path: &Path, param: &str, outcome: &ConvergeOutcome) -> Result<()> {
    let mut header = vec!["quantity".to_string()];
    header.extend(outcome.values.iter().map(|v| format!("{param}={v}")));
    header.extend(
        [
            "behaviour",
            "order",
            "extrapolated",
            "relative_change",
            "extrapolated_error",
            "gci_fine",
            "gci_band",
        ]
        .map(String::from),
    );
    let mut table = slosh_io::TableWriter::create_whole(path, &header)
        .with_context(|| format!("cannot write {}", path.display()))?;
    for r in &outcome.rows {
        let u = &r.uncertainty;
        let mut row = vec![r.name.clone()];
        row.extend(r.values.iter().map(|v| slosh_io::format_f64(*v)));
        row.push(u.behaviour.word().to_string());
        for x in [
            u.order,
            u.extrapolated,
            u.relative_change,
            u.extrapolated_error,
            u.gci_fine,
            u.band,
        ] {
            row.push(slosh_io::format_f64(x));
        }
        table.write_text_row(&row)?;
    }
    table.finish()?;
    Ok(())
}

/// The quantities `convergence.md` lists first: the design loads and the wave.
fn headline(name: &str) -> bool {
    name.starts_with("roof_")
        || name.starts_with("p_")
        || name.starts_with("max_eta")
        || name.starts_with("max_abs_base_shear")
        || name == "max_roof_p"
}

fn percent(x: f64) -> String {
    if x.is_finite() {
        format!("{:.2} %", 100.0 * x)
    } else {
        "–".into()
    }
}

fn number(x: f64) -> String {
    if !x.is_finite() {
        "–".into()
    } else if x != 0.0 && (x.abs() < 1e-2 || x.abs() >= 1e6) {
        format!("{x:.4e}")
    } else {
        format!("{x:.4}")
    }
}

fn write_markdown(
    path: &Path,
    case: &Path,
    request: &ConvergeRequest,
    outcome: &ConvergeOutcome,
) -> Result<()> {
    use std::fmt::Write as _;
    let mut md = String::new();
    let levels: Vec<String> = outcome.values.iter().map(|v| v.to_string()).collect();
    let _ = writeln!(md, "# Convergence of {}\n", case.display());
    let _ = writeln!(
        md,
        "Levels: {} = {} (coarsest first, ratio {}){}.\n",
        request.param,
        levels.join(", "),
        request.ratio,
        if request.sets.is_empty() {
            String::new()
        } else {
            format!("; with {}", request.sets.join(", "))
        }
    );
    let _ = writeln!(
        md,
        "Order p, Richardson extrapolation and the fine-grid convergence index GCI (factor of \
         safety 1.25) over the finest three levels, after Celik et al. (2008), J. Fluids Eng. \
         130, 078001. *monotone*: the changes shrink with one sign; *oscillatory*: they shrink \
         and alternate (the GCI column is then half the levels' range over the finest value, \
         after Stern et al. 2001, J. Fluids Eng. 123, 793); *divergent*: they do not shrink (no GCI: refine \
         further or read the quantity as not converged). The GCI band is in the quantity's \
         unit; `docs/roof-loads.md` says which quantities are design loads.\n"
    );
    for (title, pick) in [
        ("Design loads and the wave", true),
        ("Every other number of summary.ron", false),
    ] {
        let _ = writeln!(md, "## {title}\n");
        let mut head = "| quantity |".to_string();
        for l in &levels {
            let _ = write!(head, " {}={l} |", request.param);
        }
        head.push_str(" behaviour | p | extrapolated | GCI fine | change fine |");
        let _ = writeln!(md, "{head}");
        let cols = levels.len() + 6;
        let _ = writeln!(md, "|{}", "---|".repeat(cols));
        for r in outcome.rows.iter().filter(|r| headline(&r.name) == pick) {
            let u = &r.uncertainty;
            let mut line = format!("| {} |", r.name);
            for v in &r.values {
                let _ = write!(line, " {} |", number(*v));
            }
            let _ = write!(
                line,
                " {} | {} | {} | {} | {} |",
                u.behaviour.word(),
                if u.order.is_finite() {
                    format!("{:.2}", u.order)
                } else {
                    "–".into()
                },
                number(u.extrapolated),
                percent(u.gci_fine),
                percent(u.relative_change)
            );
            let _ = writeln!(md, "{line}");
        }
        let _ = writeln!(md);
    }
    slosh_io::error::create_fresh(path)
        .and_then(|mut f| {
            use std::io::Write;
            f.write_all(md.as_bytes())?;
            Ok(())
        })
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Reads the columns `wanted` of a `series.csv` (those it has).
fn read_series(path: &Path, wanted: &[&str]) -> Result<Vec<(String, Vec<f64>)>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let header: Vec<String> = reader.headers()?.iter().map(String::from).collect();
    let index: Vec<(usize, &str)> = wanted
        .iter()
        .filter_map(|w| header.iter().position(|h| h == w).map(|i| (i, *w)))
        .collect();
    let t = header.iter().position(|h| h == "t");
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); index.len() + 1];
    for record in reader.records() {
        let record = record?;
        let num = |i: usize| {
            record
                .get(i)
                .and_then(|s| s.parse::<f64>().ok())
                .unwrap_or(f64::NAN)
        };
        cols[0].push(t.map_or(f64::NAN, num));
        for (k, (i, _)) in index.iter().enumerate() {
            cols[k + 1].push(num(*i));
        }
    }
    let mut out = vec![("t".to_string(), cols.remove(0))];
    out.extend(index.iter().map(|(_, w)| w.to_string()).zip(cols));
    Ok(out)
}

/// Draws `plots/converge_<column>.png`: a series of every level overlaid.
fn overlay_plots(
    out: &Path,
    param: &str,
    values: &[ParamValue],
    folders: &[PathBuf],
) -> Result<()> {
    let series: Vec<Vec<(String, Vec<f64>)>> = folders
        .iter()
        .map(|f| read_series(&f.join("series.csv"), &OVERLAID))
        .collect::<Result<_>>()?;
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for column in OVERLAID {
        let lines: Vec<slosh_io::Series> = series
            .iter()
            .zip(values)
            .filter_map(|(s, v)| {
                let ys = s.iter().find(|(n, _)| n == column)?;
                Some(slosh_io::Series::line(
                    format!("{param}={v}"),
                    &s[0].1,
                    &ys.1,
                ))
            })
            .collect();
        if lines.len() != folders.len() {
            continue;
        }
        slosh_io::line_plot(
            dir.join(format!("converge_{column}")),
            &slosh_io::PlotSpec::new(format!("{column} at each level"), "time t [s]", column),
            &lines,
        )?;
    }
    Ok(())
}

/// Prints the headline rows of a finished convergence study.
pub fn print_table(outcome: &ConvergeOutcome, param: &str) {
    let levels: Vec<String> = outcome
        .values
        .iter()
        .map(|v| format!("{param}={v}"))
        .collect();
    eprintln!(
        "{:<28} {:>14} {:>12} {:>10}",
        "quantity",
        levels.join(" → "),
        "behaviour",
        "GCI fine"
    );
    for r in outcome.rows.iter().filter(|r| headline(&r.name)) {
        let vals: Vec<String> = r.values.iter().map(|v| format!("{v:.4}")).collect();
        eprintln!(
            "{:<28} {:>14} {:>12} {:>10}",
            r.name,
            vals.join(" → "),
            r.uncertainty.behaviour.word(),
            percent(r.uncertainty.gci_fine)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_of_a_spacing_and_of_a_count() {
        let (v, h) = level_values(&ParamValue::Float(0.02), 3, 2.0, Refinement::Divide).unwrap();
        assert_eq!(
            v,
            vec![
                ParamValue::Float(0.02),
                ParamValue::Float(0.01),
                ParamValue::Float(0.005)
            ]
        );
        assert_eq!(h, vec![0.02, 0.01, 0.005]);
        let (v, h) = level_values(&ParamValue::Int(16), 3, 1.5, Refinement::Multiply).unwrap();
        assert_eq!(
            v,
            vec![
                ParamValue::Int(16),
                ParamValue::Int(24),
                ParamValue::Int(36)
            ]
        );
        assert!((h[0] / h[1] - 1.5).abs() < 1e-12);
        assert!(level_values(&ParamValue::Int(2), 3, 1.2, Refinement::Multiply).is_err());
        assert_eq!(
            Refinement::from_name("particles_per_radius"),
            Some(Refinement::Multiply)
        );
        assert_eq!(Refinement::from_name("dx"), Some(Refinement::Divide));
        assert_eq!(Refinement::from_name("amplitude"), None);
    }
}
