//! The assessment report: `assessment.md`, `assessment.csv` (one row per motion) and
//! `plots/`, written from the `summary.ron` of each finished run.
//!
//! Per motion: the peak ground acceleration and S_a(T_c) at 0.5 % damping of the applied
//! motion, the SPH peaks (largest wall elevation, roof contact and impacts, roof pressure,
//! force and impulse, base shear, overturning moment) and the code estimates from the same
//! spectrum (circular tanks: API 650 Annex E E.7.2 and ACI 350.3-06 Eq. 7-2; rectangular:
//! ACI 350.3-06 Eq. 7-1; both: EN 1998-4 Annex A wave heights; Malhotra's 2005 roof pressure
//! for a wave above the freeboard, see `docs/`). The freeboard is the tank's as simulated
//! (fitted to the particle lattice), as the runs' summaries report it.
//! Over the suite: median, 84th percentile and maximum of each number, and one verdict line
//! per criterion (freeboard, roof).

use super::Manifest;
use crate::sweep::Planned;
use anyhow::{Context, Result};
use serde::Deserialize;
use slosh_case::spectrum::SpectrumSummary;
use slosh_io::{PlotSpec, Series};
use slosh_run::LoadPeak;
use slosh_run::RoofImpact;
use slosh_script::ParamValue;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What [`write_report`] wrote and found.
#[derive(Clone, Debug)]
pub struct Collected {
    /// `assessment.md`.
    pub report: PathBuf,
    /// `assessment.csv`.
    pub csv: PathBuf,
    /// Motions with a completed run.
    pub completed: usize,
    /// Motions without a run (not run yet, still running, or run with other parameters).
    pub missing: Vec<String>,
    /// Motions whose run failed or was interrupted, with the error.
    pub failed: Vec<(String, String)>,
    /// The verdict lines of the report.
    pub verdicts: Vec<String>,
}

/// The first convective period of the summary's closed forms.
#[derive(Debug, Deserialize)]
struct TheoryPeriod {
    period_1: f64,
}

/// The fields of a run's `summary.ron` the report uses.
#[derive(Debug, Deserialize)]
struct RunPeaks {
    case: String,
    dim: usize,
    #[serde(default)]
    wall_time_s: f64,
    max_roof_force_up: f64,
    max_roof_p: f64,
    max_eta_left: f64,
    max_eta_right: f64,
    max_abs_base_shear_x: f64,
    lost_particles: usize,
    theory: TheoryPeriod,
    /// The tank as simulated (a `TankSpec`), read for its sizes.
    tank: ron::Value,
    /// The tank as the script gave it (before the lattice fit), read for its freeboard.
    #[serde(default = "no_tank")]
    tank_requested: ron::Value,
    #[serde(default)]
    impacts: Vec<RoofImpact>,
    #[serde(default)]
    load_peaks: Vec<LoadPeak>,
    #[serde(default)]
    roof_contact: bool,
    #[serde(default)]
    input_spectrum: Option<SpectrumSummary>,
    #[serde(default)]
    roof_load: Option<slosh_run::RoofLoadSummary>,
}

impl RunPeaks {
    fn max_eta(&self) -> f64 {
        self.max_eta_left.max(self.max_eta_right)
    }
    /// Largest roof impulse of one impact.
    fn max_roof_impulse(&self) -> f64 {
        self.impacts.iter().map(|i| i.impulse).fold(0.0, f64::max)
    }
    /// Largest |overturning moment| about the horizontal axis across the excitation
    /// (`overturning_moment` in 2D, `overturning_moment_y` in 3D); NaN when not recorded.
    fn max_overturning_moment(&self) -> f64 {
        let column = if self.dim == 2 {
            "overturning_moment"
        } else {
            "overturning_moment_y"
        };
        self.load_peaks
            .iter()
            .find(|p| p.column == column)
            .map_or(f64::NAN, |p| p.max_abs)
    }
    /// The freeboard of the tank as simulated (fitted to the particle lattice, with the fill
    /// depth the lattice holds), which the run's code estimates also use.
    fn freeboard(&self) -> Option<f64> {
        self.input_spectrum.as_ref().and_then(|s| s.freeboard_m)
    }
    /// The freeboard of the tank as the script gave it, when it differs from [`Self::freeboard`]
    /// by more than a micrometre.
    fn requested_freeboard(&self) -> Option<f64> {
        let simulated = self.freeboard()?;
        freeboard_of(&self.tank_requested).filter(|f| (f - simulated).abs() > 1e-6)
    }
    /// How the verdict names the freeboard: "0.06 m" or "2.8 m (tank as simulated; 3 m as
    /// specified)".
    fn freeboard_text(&self) -> Option<String> {
        let f = self.freeboard()?;
        Some(match self.requested_freeboard() {
            Some(n) => format!(
                "{} m (tank as simulated, fitted to the particle lattice; {} m as specified)",
                sig3(f),
                sig3(n)
            ),
            None => format!("{} m", sig3(f)),
        })
    }
}

fn no_tank() -> ron::Value {
    ron::Value::Unit
}

/// Height from the floor to the roof minus the fill depth of a summary's tank (a `TankSpec`
/// map with `height`, `depth` and a `roof`), when it has a roof.
fn freeboard_of(tank: &ron::Value) -> Option<f64> {
    let ron::Value::Map(map) = tank else {
        return None;
    };
    let get = |key: &str| {
        map.iter()
            .find(|(k, _)| matches!(k, ron::Value::String(s) if s == key))
            .map(|(_, v)| v)
    };
    let number = |key: &str| match get(key) {
        Some(ron::Value::Number(n)) => Some(n.into_f64()),
        _ => None,
    };
    let roofed = match get("roof") {
        Some(ron::Value::Bool(b)) => *b,
        Some(ron::Value::String(s)) => s != "none",
        _ => false,
    };
    if !roofed {
        return None;
    }
    Some(number("height")? - number("depth")?)
}

/// How a motion's run stands.
enum RunState {
    Completed(Box<RunPeaks>),
    Failed(String),
    Missing(String),
}

/// One motion with its run.
struct MotionRun<'a> {
    name: &'a str,
    values: &'a [(String, ParamValue)],
    dir: &'a Path,
    state: RunState,
}

/// The motion whose design load is the largest among the finished runs, with why: the
/// largest equivalent static roof force at the middle roof period when a run reached the
/// roof, else the largest wave at the walls. `None` before any run has finished.
pub(crate) fn worst_motion(manifest: &Manifest, plans: &[Planned]) -> Option<(String, String)> {
    let finished: Vec<(&str, Box<RunPeaks>)> = manifest
        .motions
        .iter()
        .zip(plans)
        .filter_map(|(m, p)| match run_state(p) {
            RunState::Completed(r) => Some((m.name.as_str(), r)),
            _ => None,
        })
        .collect();
    let roof = |r: &RunPeaks| {
        r.roof_load
            .as_ref()
            .filter(|_| r.roof_contact)
            .and_then(|l| {
                let k = l.periods.len() / 2;
                Some((*l.roof.design.get(k)?, *l.periods.get(k)?))
            })
    };
    if let Some((name, (f, t))) = finished
        .iter()
        .filter_map(|(n, r)| roof(r).map(|x| (*n, x)))
        .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
    {
        return Some((
            name.to_string(),
            format!(
                "the largest equivalent static roof force, {} at T_r = {} s",
                sig3(f),
                sig3(t)
            ),
        ));
    }
    finished
        .iter()
        .max_by(|a, b| a.1.max_eta().total_cmp(&b.1.max_eta()))
        .map(|(n, r)| {
            (
                n.to_string(),
                format!(
                    "the largest wave at the walls, {} m (no run reached the roof)",
                    sig3(r.max_eta())
                ),
            )
        })
}

/// The folder of the convergence study of motion `name` in an assessment.
pub(crate) fn converge_dir(out_dir: &Path, name: &str) -> std::path::PathBuf {
    out_dir.join("converge").join(name)
}

/// The report's section on resolution: for each finished `slosh assess --converge` study in
/// `DIR/converge/<motion>/`, the design loads' values at the levels and their GCI.
fn resolution_section(out_dir: &Path, manifest: &Manifest) -> Option<String> {
    let mut s = String::new();
    for m in &manifest.motions {
        let csv_path = converge_dir(out_dir, &m.name).join("convergence.csv");
        let Ok(mut reader) = csv::Reader::from_path(&csv_path) else {
            continue;
        };
        let Ok(header) = reader
            .headers()
            .map(|h| h.iter().map(String::from).collect::<Vec<_>>())
        else {
            continue;
        };
        let levels: Vec<&String> = header
            .iter()
            .skip(1)
            .take_while(|h| h.contains('='))
            .collect();
        let col = |name: &str| header.iter().position(|h| h == name);
        let (Some(behaviour), Some(gci), Some(change)) =
            (col("behaviour"), col("gci_fine"), col("relative_change"))
        else {
            continue;
        };
        let _ = writeln!(
            s,
            "Motion `{}` at {} (`{}`):\n",
            m.name,
            levels
                .iter()
                .map(|l| l.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            csv_path.display()
        );
        let _ = writeln!(
            s,
            "| quantity | {} | behaviour | GCI fine | change fine |",
            levels
                .iter()
                .map(|l| l.as_str())
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(s, "|{}", "---|".repeat(levels.len() + 4));
        for record in reader.records().flatten() {
            let name = record.get(0).unwrap_or_default();
            let design = name.starts_with("roof_f_eq_")
                || name == "roof_impulse"
                || name.starts_with("roof_impact_impulse")
                || name.starts_with("max_eta_")
                || name == "max_abs_base_shear_x_lp";
            if !design {
                continue;
            }
            let values: Vec<String> = (1..=levels.len())
                .map(|k| {
                    sig3(
                        record
                            .get(k)
                            .and_then(|v| v.parse().ok())
                            .unwrap_or(f64::NAN),
                    )
                })
                .collect();
            let percent = |k: usize| {
                let x: f64 = record
                    .get(k)
                    .and_then(|v| v.parse().ok())
                    .unwrap_or(f64::NAN);
                if x.is_finite() {
                    format!("{:.1} %", 100.0 * x)
                } else {
                    "–".into()
                }
            };
            let _ = writeln!(
                s,
                "| {name} | {} | {} | {} | {} |",
                values.join(" | "),
                record.get(behaviour).unwrap_or_default(),
                percent(gci),
                percent(change)
            );
        }
        let _ = writeln!(s);
    }
    (!s.is_empty()).then(|| {
        format!(
            "\n## Resolution\n\nThe motion with the largest design load run again at successive \
             resolutions (`slosh assess --converge`): the grid convergence index of the finest \
             level (Celik et al. 2008; `docs/roof-loads.md`). A *divergent* load is not \
             converged at these levels.\n\n{s}"
        )
    })
}

/// Reads the state of a planned run from its folder.
fn run_state(plan: &Planned) -> RunState {
    let summary_path = plan.dir.join("summary.ron");
    if crate::sweep::done_before(plan).is_some() {
        return match slosh_io::read_ron::<RunPeaks>(&summary_path) {
            Ok(p) => RunState::Completed(Box::new(p)),
            Err(e) => RunState::Failed(format!("cannot read {}: {e}", summary_path.display())),
        };
    }
    #[derive(Deserialize)]
    struct Head {
        status: String,
        #[serde(default)]
        error: Option<String>,
    }
    match slosh_io::read_ron::<Head>(&summary_path) {
        Err(_) => RunState::Missing("not run yet (no summary.ron)".into()),
        Ok(h) if h.status == "completed" => {
            RunState::Missing("its summary.ron is from a run with other parameters".into())
        }
        Ok(h) if h.status == "running" => RunState::Missing("still running".into()),
        Ok(h) => {
            let log = std::fs::read_to_string(plan.dir.join("run.log")).unwrap_or_default();
            let why = h
                .error
                .or_else(|| crate::sweep::error_message(&log))
                .unwrap_or_else(|| "no error message".into());
            RunState::Failed(format!("{}: {why}", h.status))
        }
    }
}

/// Median, 84th percentile and maximum of the finite values (NaN when there are none). The
/// percentile interpolates linearly between order statistics (Hyndman and Fan's definition 7,
/// the default of NumPy and R).
fn statistics(values: &[f64]) -> [f64; 3] {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return [f64::NAN; 3];
    }
    v.sort_by(f64::total_cmp);
    let quantile = |p: f64| {
        let h = (v.len() - 1) as f64 * p;
        let lo = h.floor() as usize;
        let hi = (lo + 1).min(v.len() - 1);
        v[lo] + (h - lo as f64) * (v[hi] - v[lo])
    };
    [quantile(0.5), quantile(0.84), v[v.len() - 1]]
}

/// A number with 3 significant digits for the report's tables.
fn sig3(x: f64) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x.abs() >= 1e5 {
        return format!("{x:.2e}");
    }
    if x.fract() == 0.0 {
        return format!("{x:.0}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).clamp(0, 6) as usize;
    format!("{x:.decimals$}")
}

/// Short name of a code (`API 650`, `EN 1998-4`, `ACI 350.3-06`): its first two words.
fn code_short(code: &str) -> String {
    code.split_whitespace()
        .take(2)
        .collect::<Vec<_>>()
        .join(" ")
}

/// Column-name form of a code's short name (`api_650`, `en_1998_4`, `aci_350_3_06`).
fn code_slug(code: &str) -> String {
    let s: String = code_short(code)
        .to_ascii_lowercase()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    s.trim_matches('_').to_string()
}

/// One numeric column of `assessment.csv`: name, unit, and its value for a run.
struct Column {
    name: String,
    unit: String,
    /// Shown in the report's tables.
    label: String,
    value: Box<dyn Fn(&RunPeaks) -> f64>,
}

fn column(
    name: impl Into<String>,
    unit: impl Into<String>,
    label: impl Into<String>,
    value: impl Fn(&RunPeaks) -> f64 + 'static,
) -> Column {
    Column {
        name: name.into(),
        unit: unit.into(),
        label: label.into(),
        value: Box::new(value),
    }
}

/// The numeric columns for these runs; the code columns are those the runs' spectra name.
fn numeric_columns(runs: &[&RunPeaks], dim: usize) -> Vec<Column> {
    let (force, moment, impulse) = if dim == 2 {
        ("N/m", "N·m/m", "N·s/m")
    } else {
        ("N", "N·m", "N·s")
    };
    let spectrum = |r: &RunPeaks, f: fn(&SpectrumSummary) -> f64| {
        r.input_spectrum.as_ref().map_or(f64::NAN, f)
    };
    let mut columns = vec![
        column("pga_m_s2", "m/s²", "PGA", move |r| {
            spectrum(r, |s| s.input_pga_m_s2)
        }),
        column("sa_tc_0p5pct_g", "g", "S_a(T_c, 0.5 %)", move |r| {
            spectrum(r, |s| s.sa_tc_0p5pct_g)
        }),
        column("max_eta_m", "m", "SPH wave height", RunPeaks::max_eta),
        column("roof_impacts", "1", "roof impacts", |r| {
            r.impacts.len() as f64
        }),
        column("max_roof_p", "Pa", "SPH roof pressure", |r| r.max_roof_p),
        column("max_roof_force_up", force, "SPH roof force", |r| {
            r.max_roof_force_up
        }),
        column(
            "max_roof_impulse",
            impulse,
            "SPH roof impulse",
            RunPeaks::max_roof_impulse,
        ),
        column(
            "roof_impact_impulse_median",
            impulse,
            "SPH roof impulse, median of the impacts",
            |r| {
                r.roof_load
                    .as_ref()
                    .map_or(f64::NAN, |l| l.impact_impulse.median)
            },
        ),
        column("max_abs_base_shear_x", force, "SPH base shear", |r| {
            r.max_abs_base_shear_x
        }),
        column(
            "max_abs_overturning_moment",
            moment,
            "SPH overturning moment",
            RunPeaks::max_overturning_moment,
        ),
    ];
    // The equivalent static roof force at each roof period of the runs (the design load of a
    // roof of that period, `docs/roof-loads.md`).
    let periods: Vec<f64> = runs
        .iter()
        .find_map(|r| r.roof_load.as_ref().map(|l| l.periods.clone()))
        .unwrap_or_default();
    for (k, &t) in periods.iter().enumerate() {
        columns.push(column(
            format!("roof_f_eq_{}", slosh_run::roof_load::period_tag(t)),
            force,
            format!("SPH roof F_eq (T_r = {} s)", sig3(t)),
            move |r| {
                r.roof_load
                    .as_ref()
                    .filter(|l| l.periods.get(k).is_some_and(|p| (p - t).abs() < 1e-12))
                    .and_then(|l| l.roof.design.get(k).copied())
                    .unwrap_or(f64::NAN)
            },
        ));
    }
    let mut codes: Vec<String> = Vec::new();
    for r in runs {
        for w in r.input_spectrum.iter().flat_map(|s| &s.code_wave_heights) {
            if !codes.contains(&w.code) {
                codes.push(w.code.clone());
            }
        }
    }
    for code in &codes {
        let c = code.clone();
        columns.push(column(
            format!("wave_height_{}_m", code_slug(code)),
            "m",
            format!("{} wave height", code_short(code)),
            move |r| {
                r.input_spectrum
                    .iter()
                    .flat_map(|s| &s.code_wave_heights)
                    .find(|w| w.code == c)
                    .map_or(f64::NAN, |w| w.wave_height_m)
            },
        ));
    }
    if runs.iter().any(|r| r.freeboard().is_some()) {
        for code in &codes {
            let c = code.clone();
            columns.push(column(
                format!("malhotra_roof_p_{}_pa", code_slug(code)),
                "Pa",
                format!("Malhotra roof pressure ({} wave)", code_short(code)),
                move |r| {
                    r.input_spectrum
                        .iter()
                        .flat_map(|s| &s.malhotra_roof_pressures)
                        .find(|p| p.wave_from == c)
                        .map_or(f64::NAN, |p| p.pressure_pa)
                },
            ));
        }
    }
    columns
}

/// Writes `assessment.md`, `assessment.csv` and `plots/` into `out_dir` from the runs of
/// `plans` (one per motion of `manifest`, in order).
pub(crate) fn write_report(
    manifest: &Manifest,
    out_dir: &Path,
    plans: &[Planned],
) -> Result<Collected> {
    let motions: Vec<MotionRun> = manifest
        .motions
        .iter()
        .zip(plans)
        .map(|(m, p)| MotionRun {
            name: &m.name,
            values: &m.values,
            dir: &p.dir,
            state: run_state(p),
        })
        .collect();
    let completed: Vec<(&MotionRun, &RunPeaks)> = motions
        .iter()
        .filter_map(|m| match &m.state {
            RunState::Completed(p) => Some((m, p.as_ref())),
            _ => None,
        })
        .collect();
    let missing: Vec<String> = motions
        .iter()
        .filter_map(|m| match &m.state {
            RunState::Missing(why) => Some(format!("{} ({why})", m.name)),
            _ => None,
        })
        .collect();
    let failed: Vec<(String, String)> = motions
        .iter()
        .filter_map(|m| match &m.state {
            RunState::Failed(e) => Some((m.name.to_string(), e.clone())),
            _ => None,
        })
        .collect();

    let dim = completed.first().map_or(2, |(_, r)| r.dim);
    let runs: Vec<&RunPeaks> = completed.iter().map(|(_, r)| *r).collect();
    let columns = numeric_columns(&runs, dim);
    let parameter_names: Vec<String> = {
        let mut names: Vec<String> = Vec::new();
        for m in &manifest.motions {
            for (n, _) in &m.values {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
        }
        names
    };

    let csv = out_dir.join("assessment.csv");
    write_csv(&csv, &motions, &parameter_names, &columns)?;

    let plots_dir = out_dir.join("plots");
    std::fs::create_dir_all(&plots_dir)
        .with_context(|| format!("cannot create {}", plots_dir.display()))?;
    let mut plots: Vec<(String, String)> = Vec::new();
    let mut plot_errors: Vec<String> = Vec::new();
    if !completed.is_empty() {
        let mut record = |result: Result<Option<(String, String)>>| match result {
            Ok(Some(p)) => plots.push(p),
            Ok(None) => {}
            Err(e) => plot_errors.push(format!("{e:#}")),
        };
        record(plot_wave_heights(&plots_dir, &completed, &columns).map(Some));
        record(plot_worst_roof_forces(&plots_dir, &completed));
        record(plot_spectra(&plots_dir, &completed));
    }

    let verdicts = verdict_lines(&completed, &columns, motions.len());
    let report = out_dir.join("assessment.md");
    let mut text = markdown(
        manifest,
        &motions,
        &completed,
        &columns,
        &verdicts,
        &plots,
        &plot_errors,
        (&missing, &failed),
    );
    if let Some(section) = resolution_section(out_dir, manifest) {
        text.push_str(&section);
    }
    // Created afresh, never through a link planted at its name.
    slosh_io::error::create_fresh(&report)
        .and_then(|mut f| std::io::Write::write_all(&mut f, text.as_bytes()))
        .with_context(|| format!("cannot write {}", report.display()))?;
    Ok(Collected {
        report,
        csv,
        completed: completed.len(),
        missing,
        failed,
        verdicts,
    })
}

fn write_csv(
    path: &Path,
    motions: &[MotionRun],
    parameter_names: &[String],
    columns: &[Column],
) -> Result<()> {
    let mut header: Vec<String> = vec!["name".into()];
    header.extend(parameter_names.iter().cloned());
    header.extend(["status".into(), "error".into()]);
    header.extend(["convective_period_s".into(), "freeboard_m".into()]);
    header.extend(columns.iter().map(|c| c.name.clone()));
    header.extend([
        "roof_contact".into(),
        "freeboard_exceeded".into(),
        "lost_particles".into(),
        "wall_time_s".into(),
        "freeboard_specified_m".into(),
    ]);
    let mut table = slosh_io::TableWriter::create_whole(path, &header)
        .with_context(|| format!("cannot write {}", path.display()))?;
    let number = |x: f64| {
        if x.is_finite() {
            slosh_io::format_f64(x)
        } else {
            String::new()
        }
    };
    for m in motions {
        let mut row = vec![m.name.to_string()];
        for n in parameter_names {
            row.push(
                m.values
                    .iter()
                    .find(|(k, _)| k == n)
                    .map(|(_, v)| match v {
                        ParamValue::Str(s) => s.clone(),
                        other => other.to_string(),
                    })
                    .unwrap_or_default(),
            );
        }
        match &m.state {
            RunState::Completed(r) => {
                row.extend(["completed".into(), String::new()]);
                row.push(number(r.theory.period_1));
                row.push(r.freeboard().map(number).unwrap_or_default());
                row.extend(columns.iter().map(|c| number((c.value)(r))));
                row.push(r.roof_contact.to_string());
                row.push(
                    r.freeboard()
                        .map(|f| (r.max_eta() > f).to_string())
                        .unwrap_or_default(),
                );
                row.push(r.lost_particles.to_string());
                row.push(number(r.wall_time_s));
                row.push(
                    r.freeboard()
                        .and(freeboard_of(&r.tank_requested))
                        .map(number)
                        .unwrap_or_default(),
                );
            }
            RunState::Failed(e) | RunState::Missing(e) => {
                let word = if matches!(m.state, RunState::Failed(_)) {
                    "failed"
                } else {
                    "missing"
                };
                row.extend([word.to_string(), e.clone()]);
                row.resize(header.len(), String::new());
            }
        }
        table
            .write_text_row(&row)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    table
        .finish()
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// The values of a column over the completed runs.
fn values_of(completed: &[(&MotionRun, &RunPeaks)], column: &Column) -> Vec<f64> {
    completed.iter().map(|(_, r)| (column.value)(r)).collect()
}

fn find<'c>(columns: &'c [Column], name: &str) -> Option<&'c Column> {
    columns.iter().find(|c| c.name == name)
}

/// One line per criterion: freeboard (SPH wave height against the freeboard and the codes),
/// roof (contact, pressure against Malhotra's), and the runs that are missing or failed.
fn verdict_lines(
    completed: &[(&MotionRun, &RunPeaks)],
    columns: &[Column],
    total: usize,
) -> Vec<String> {
    let n = completed.len();
    let mut lines = Vec::new();
    if n < total {
        lines.push(format!(
            "Runs: {n} of {total} motions finished; the statistics below cover those {n} only."
        ));
    }
    if n == 0 {
        return lines;
    }
    let eta = values_of(
        completed,
        find(columns, "max_eta_m").expect("wave height column"),
    );
    let [eta_median, eta_84, eta_max] = statistics(&eta);
    let code_medians: Vec<String> = columns
        .iter()
        .filter(|c| c.name.starts_with("wave_height_"))
        .map(|c| {
            let [median, ..] = statistics(&values_of(completed, c));
            format!(
                "{}'s {} m",
                c.label.trim_end_matches(" wave height"),
                sig3(median)
            )
        })
        .collect();
    let against = if code_medians.is_empty() {
        String::new()
    } else {
        format!(" against {} (medians)", code_medians.join(" and "))
    };
    let freeboard = completed.iter().find_map(|(_, r)| r.freeboard());
    let freeboard_text = completed.iter().find_map(|(_, r)| r.freeboard_text());
    match freeboard {
        Some(f) => {
            let exceeded = eta.iter().filter(|&&e| e > f).count();
            lines.push(format!(
                "Freeboard {}: exceeded in {exceeded} of {n} motions; SPH median wave height {} m \
                 (84th percentile {} m, maximum {} m){against}.",
                freeboard_text.unwrap_or_default(),
                sig3(eta_median),
                sig3(eta_84),
                sig3(eta_max)
            ));
        }
        None => lines.push(format!(
            "Wave height (open tank, no freeboard criterion): SPH median {} m (84th percentile \
             {} m, maximum {} m){against}.",
            sig3(eta_median),
            sig3(eta_84),
            sig3(eta_max)
        )),
    }
    if freeboard.is_some() {
        let reached = completed.iter().filter(|(_, r)| r.roof_contact).count();
        let impacts: usize = completed.iter().map(|(_, r)| r.impacts.len()).sum();
        let p = values_of(completed, find(columns, "max_roof_p").expect("roof column"));
        let [p_median, p_84, p_max] = statistics(&p);
        let malhotra: Vec<String> = columns
            .iter()
            .filter(|c| c.name.starts_with("malhotra_roof_p_"))
            .map(|c| {
                let [median, _, max] = statistics(&values_of(completed, c));
                let code = c
                    .label
                    .trim_start_matches("Malhotra roof pressure (")
                    .trim_end_matches(" wave)");
                format!(
                    "from {code}'s wave median {} kPa, maximum {} kPa",
                    sig3(median / 1e3),
                    sig3(max / 1e3)
                )
            })
            .collect();
        lines.push(format!(
            "Roof: reached in {reached} of {n} motions ({impacts} impacts in all); SPH peak roof \
             pressure median {} kPa (84th percentile {} kPa, maximum {} kPa); Malhotra (2005) \
             {}.",
            sig3(p_median / 1e3),
            sig3(p_84 / 1e3),
            sig3(p_max / 1e3),
            if malhotra.is_empty() {
                "from the code waves: not available".to_string()
            } else {
                malhotra.join("; ")
            }
        ));
    }
    lines
}

/// Peak wave height per motion against the freeboard and the code values.
fn plot_wave_heights(
    dir: &Path,
    completed: &[(&MotionRun, &RunPeaks)],
    columns: &[Column],
) -> Result<(String, String)> {
    // The SPH point at the motion's number, each code's a little to its right, so that codes
    // with equal values (API 650 and EN 1998-4 for a cylinder) stay visible.
    let numbers =
        |offset: f64| -> Vec<f64> { (1..=completed.len()).map(|i| i as f64 + offset).collect() };
    let mut data: Vec<(String, Vec<f64>, Vec<f64>)> = vec![(
        "SPH peak wave height".into(),
        numbers(0.0),
        values_of(
            completed,
            find(columns, "max_eta_m").expect("wave height column"),
        ),
    )];
    for (k, c) in columns
        .iter()
        .filter(|c| c.name.starts_with("wave_height_"))
        .enumerate()
    {
        let offset = 0.12 * (k + 1) as f64;
        data.push((c.label.clone(), numbers(offset), values_of(completed, c)));
    }
    let freeboard = completed.iter().find_map(|(_, r)| r.freeboard());
    let band = [0.5, completed.len() as f64 + 0.5];
    let level = freeboard.map(|f| [f, f]);
    let mut series: Vec<Series> = data
        .iter()
        .map(|(label, xs, ys)| Series::points(label.clone(), xs, ys))
        .collect();
    if let Some(level) = &level {
        series.push(
            Series::dashed(format!("freeboard {} m", sig3(level[0])), &band, level)
                .with_color(0, 0, 0),
        );
    }
    let stem = dir.join("wave_heights");
    slosh_io::line_plot(
        &stem,
        &PlotSpec::new(
            "Peak wave height at the wall per motion",
            "motion (number in the report's table)",
            "wave height above the still level [m]",
        ),
        &series,
    )?;
    Ok((
        "Peak wave height per motion against the freeboard and the codes".into(),
        "plots/wave_heights.png".into(),
    ))
}

/// Roof force time histories of the three motions with the largest roof force (none when the
/// liquid reached the roof in no motion).
fn plot_worst_roof_forces(
    dir: &Path,
    completed: &[(&MotionRun, &RunPeaks)],
) -> Result<Option<(String, String)>> {
    let mut order: Vec<&(&MotionRun, &RunPeaks)> = completed
        .iter()
        .filter(|(_, r)| r.max_roof_force_up > 0.0)
        .collect();
    if order.is_empty() {
        return Ok(None);
    }
    order.sort_by(|a, b| b.1.max_roof_force_up.total_cmp(&a.1.max_roof_force_up));
    order.truncate(3);
    let mut histories = Vec::new();
    for (m, _) in &order {
        let path = m.dir.join("series.csv");
        let table = slosh_io::read_table(&path)?;
        let (Some(t), Some(f)) = (table.column("t"), table.column("roof_force_up")) else {
            anyhow::bail!("{} has no t or roof_force_up column", path.display());
        };
        histories.push((m.name.to_string(), t, f));
    }
    let force = if completed[0].1.dim == 2 { "N/m" } else { "N" };
    let series: Vec<Series> = histories
        .iter()
        .map(|(name, t, f)| Series::line(name.clone(), t, f))
        .collect();
    slosh_io::line_plot(
        dir.join("roof_force_worst"),
        &PlotSpec::new(
            format!("Upward roof force, the {} worst motions", order.len()),
            "t [s]",
            format!("roof force [{force}]"),
        ),
        &series,
    )?;
    Ok(Some((
        format!(
            "Roof force time histories of the {} worst motions",
            order.len()
        ),
        "plots/roof_force_worst.png".into(),
    )))
}

/// The 0.5 %-damped spectra of the motions with the tank's convective period marked.
fn plot_spectra(
    dir: &Path,
    completed: &[(&MotionRun, &RunPeaks)],
) -> Result<Option<(String, String)>> {
    let mut spectra = Vec::new();
    for (m, _) in completed {
        let path = m.dir.join("input_spectrum.csv");
        if !path.is_file() {
            continue;
        }
        let table = slosh_io::read_table(&path)?;
        let (Some(t), Some(sa)) = (table.column("period_s"), table.column("sa_0p5pct_g")) else {
            anyhow::bail!("{} has no period_s or sa_0p5pct_g column", path.display());
        };
        spectra.push((m.name.to_string(), t, sa));
    }
    if spectra.is_empty() {
        return Ok(None);
    }
    let tc = completed[0].1.theory.period_1;
    let top = spectra
        .iter()
        .flat_map(|(_, _, sa)| sa.iter().copied())
        .fold(0.0, f64::max);
    let marker_t = [tc, tc];
    let marker_sa = [0.0, top];
    let mut series: Vec<Series> = spectra
        .iter()
        .map(|(name, t, sa)| Series::line(name.clone(), t, sa))
        .collect();
    series.push(
        Series::dashed(format!("T_c = {} s", sig3(tc)), &marker_t, &marker_sa).with_color(0, 0, 0),
    );
    slosh_io::line_plot(
        dir.join("spectra"),
        &PlotSpec::new(
            "Response spectra of the suite, 0.5 % damping (convective)",
            "period T [s]",
            "S_a [g]",
        ),
        &series,
    )?;
    Ok(Some((
        "Spectra of the suite with the tank's convective period".into(),
        "plots/spectra.png".into(),
    )))
}

/// The sizes of a tank description, in m.
const SIZES: [&str; 7] = [
    "width",
    "length",
    "breadth",
    "radius",
    "height",
    "depth",
    "roof_rise",
];

/// A short description of the simulated tank from the summary's `tank` (its sizes in m).
fn tank_text(tank: &ron::Value) -> String {
    let ron::Value::Map(map) = tank else {
        return String::new();
    };
    map.iter()
        .filter_map(|(k, v)| match (k, v) {
            (ron::Value::String(k), ron::Value::Number(n)) if SIZES.contains(&k.as_str()) => {
                Some(format!("{k} {} m", sig3(n.into_f64())))
            }
            (ron::Value::String(k), ron::Value::String(s)) if k == "roof" => {
                Some(format!("roof {s}"))
            }
            (ron::Value::String(k), ron::Value::Bool(true)) if k == "roof" => {
                Some("flat roof".into())
            }
            _ => None,
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[allow(clippy::too_many_arguments)]
fn markdown(
    manifest: &Manifest,
    motions: &[MotionRun],
    completed: &[(&MotionRun, &RunPeaks)],
    columns: &[Column],
    verdicts: &[String],
    plots: &[(String, String)],
    plot_errors: &[String],
    (missing, failed): (&[String], &[(String, String)]),
) -> String {
    let mut s = String::new();
    let case_file = manifest.case.display();
    let _ = writeln!(s, "# Tank assessment: {case_file}\n");
    let _ = writeln!(
        s,
        "Suite: {} ({} motions).",
        manifest.suite.display(),
        manifest.motions.len()
    );
    if !manifest.overrides.is_empty() {
        let sets: Vec<String> = manifest
            .overrides
            .iter()
            .map(|(n, v)| format!("`{n}={v}`"))
            .collect();
        let _ = writeln!(s, "Set for every motion: {}.", sets.join(", "));
    }
    if let Some((_, r)) = completed.first() {
        let _ = writeln!(
            s,
            "\n## Tank\n\nCase `{}`, {}D; simulated tank: {}.\n\nFirst convective period T_c = {} s \
             (potential theory){}.",
            r.case,
            r.dim,
            tank_text(&r.tank),
            sig3(r.theory.period_1),
            r.freeboard()
                .map(|f| format!(
                    "; freeboard from the still level to the roof {} m in the tank as simulated \
                     (its sizes fitted to the particle lattice and the fill depth whole rows of \
                     particles, as the run's summary reports them; the verdicts and code \
                     estimates use it){}",
                    sig3(f),
                    r.requested_freeboard()
                        .map(|n| format!(", {} m in the tank as specified", sig3(n)))
                        .unwrap_or_default()
                ))
                .unwrap_or_else(|| "; no roof".into())
        );
        if r.dim == 2 {
            let _ = writeln!(
                s,
                "\nForces and moments of a 2D tank are per metre of depth."
            );
        }
    }
    let _ = writeln!(s, "\n## Verdict\n");
    for v in verdicts {
        let _ = writeln!(s, "- {v}");
    }
    if verdicts.is_empty() {
        let _ = writeln!(s, "- No motion has a finished run yet.");
    }

    // Per-motion table.
    let _ = writeln!(s, "\n## Motions\n");
    let mut header = vec!["#".to_string(), "motion".into()];
    header.extend(columns.iter().map(|c| format!("{} [{}]", c.label, c.unit)));
    let _ = writeln!(s, "| {} |", header.join(" | "));
    let _ = writeln!(s, "|{}", "---|".repeat(header.len()));
    for (i, (m, r)) in completed.iter().enumerate() {
        let mut row = vec![(i + 1).to_string(), m.name.to_string()];
        row.extend(columns.iter().map(|c| sig3((c.value)(r))));
        let _ = writeln!(s, "| {} |", row.join(" | "));
    }
    if !completed.is_empty() {
        let stats: Vec<[f64; 3]> = columns
            .iter()
            .map(|c| statistics(&values_of(completed, c)))
            .collect();
        for (k, label) in ["median", "84th percentile", "maximum"].iter().enumerate() {
            let mut row = vec![String::new(), format!("**{label}**")];
            row.extend(stats.iter().map(|st| sig3(st[k])));
            let _ = writeln!(s, "| {} |", row.join(" | "));
        }
    }
    let params: Vec<String> = motions
        .iter()
        .map(|m| {
            let values: Vec<String> = m.values.iter().map(|(n, v)| format!("{n}={v}")).collect();
            format!("- `{}`: {}", m.name, values.join(", "))
        })
        .collect();
    let _ = writeln!(s, "\nThe motions' parameters:\n\n{}", params.join("\n"));
    let _ = writeln!(
        s,
        "\nS_a(T_c, 0.5 %) is the pseudo-acceleration of the applied motion's own response \
         spectrum at the tank's convective period with the codes' convective damping; the code \
         wave heights use it (API 650 Annex E E.7.2: 0.42 D A_f; ACI 350.3-06 Eq. 7-1: (L/2) A_f, \
         Eq. 7-2: (D/2) A_f; \
         EN 1998-4 Annex A: 0.84 R S_e or 0.5 L S_e). Malhotra's (2005) roof pressure \
         P = ρ g x_f tan θ with θ = π/4 takes the part of each code wave above the freeboard. \
         The SPH wave height is the largest elevation at the walls on the excitation axis. The \
         84th percentile interpolates linearly between the sorted values."
    );

    if !missing.is_empty() || !failed.is_empty() {
        let _ = writeln!(s, "\n## Runs missing or failed\n");
        for m in missing {
            let _ = writeln!(s, "- missing: {m}");
        }
        for (name, e) in failed {
            let _ = writeln!(s, "- failed: {name}: {e}");
        }
    }
    if !plots.is_empty() || !plot_errors.is_empty() {
        let _ = writeln!(s, "\n## Plots\n");
        for (title, path) in plots {
            let _ = writeln!(s, "{title}:\n\n![{title}]({path})\n");
        }
        for e in plot_errors {
            let _ = writeln!(s, "- plot not written: {e}");
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_are_median_84th_percentile_and_maximum() {
        let [m, p, x] = statistics(&[3.0, 1.0, 2.0, f64::NAN, 4.0, 5.0]);
        assert_eq!(m, 3.0);
        // h = 4 × 0.84 = 3.36 between 4 and 5.
        assert!((p - 4.36).abs() < 1e-12, "{p}");
        assert_eq!(x, 5.0);
        assert!(statistics(&[]).iter().all(|v| v.is_nan()));
    }

    #[test]
    fn code_names_become_columns() {
        assert_eq!(code_slug("API 650 Annex E (E.7.2)"), "api_650");
        assert_eq!(code_slug("EN 1998-4 Annex A (A.9)"), "en_1998_4");
        assert_eq!(code_slug("ACI 350.3-06 (7-1)"), "aci_350_3_06");
        assert_eq!(sig3(0.012345), "0.0123");
        assert_eq!(sig3(2345.6), "2346");
        assert_eq!(sig3(9.0), "9");
        assert_eq!(sig3(137270910.0), "1.37e8");
    }
}
