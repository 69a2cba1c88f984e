//! The data handed to a script's `post(run)` and the extra files it asks for.

use crate::summary::Summary;
use anyhow::Result;
use slosh_io::{PlotSpec, Series, TableWriter};
use slosh_script::{PostResult, RunData};
use std::path::Path;

/// Builds the `run` argument of `post(run)` from the summary and the series.
pub fn run_data(summary: &Summary, names: &[(String, String)], history: &[Vec<f64>]) -> RunData {
    let scalars = vec![
        ("max_roof_force_up".to_string(), summary.max_roof_force_up),
        ("t_max_roof_force_up".into(), summary.t_max_roof_force_up),
        ("max_roof_p".into(), summary.max_roof_p),
        ("t_max_roof_p".into(), summary.t_max_roof_p),
        ("max_eta_left".into(), summary.max_eta_left),
        ("max_eta_right".into(), summary.max_eta_right),
        ("max_abs_base_shear_x".into(), summary.max_abs_base_shear_x),
        ("settle".into(), summary.settle),
        ("sim_time".into(), summary.sim_time),
        ("dx".into(), summary.dx),
        ("omega_1".into(), summary.theory.omega_1),
        ("period_1".into(), summary.theory.period_1),
        ("lost_particles".into(), summary.lost_particles as f64),
        ("kurihara_at_max".into(), summary.kurihara_at_max),
        ("malhotra_at_max".into(), summary.malhotra_at_max),
        ("impacts".into(), summary.impacts.len() as f64),
        (
            "max_abs_base_shear_x_lp".into(),
            summary.max_abs_base_shear_x_lp,
        ),
        ("max_roof_force_up_lp".into(), summary.max_roof_force_up_lp),
        ("load_filter_hz".into(), summary.load_filter.cutoff_hz),
        (
            "roof_contact".into(),
            f64::from(u8::from(summary.roof_contact)),
        ),
    ];
    RunData {
        scalars,
        series: names
            .iter()
            .zip(history)
            .map(|((n, _), v)| (n.clone(), v.clone()))
            .collect(),
        params: summary.parameters.clone(),
        maps: Vec::new(),
    }
}

/// Writes the tables and plots a `post` asked for into `out/post/`. One that cannot be written
/// does not stop the others: every failure is named in the error.
pub fn write_post_outputs(out: &Path, result: &PostResult) -> Result<()> {
    if result.tables.is_empty() && result.plots.is_empty() {
        return Ok(());
    }
    let dir = out.join("post");
    std::fs::create_dir_all(&dir)?;
    let mut failures = Vec::new();
    for (name, header, rows) in &result.tables {
        let written = (|| -> Result<()> {
            crate::run_folder::record_output(out, &format!("post/{name}"))?;
            let mut w = TableWriter::create_whole(dir.join(format!("{name}.csv")), header)?;
            for r in rows {
                w.write_row(r)?;
            }
            w.finish()?;
            Ok(())
        })();
        if let Err(e) = written {
            failures.push(format!("table '{name}': {e:#}"));
        }
    }
    for p in &result.plots {
        let written = (|| -> Result<()> {
            crate::run_folder::record_output(out, &format!("post/{}", p.name))?;
            slosh_io::line_plot(
                dir.join(&p.name),
                &PlotSpec::new(&p.title, &p.x_label, &p.y_label),
                &[Series::line(p.name.clone(), &p.xs, &p.ys)],
            )?;
            Ok(())
        })();
        if let Err(e) = written {
            failures.push(format!("plot '{}': {e:#}", p.name));
        }
    }
    if failures.is_empty() {
        Ok(())
    } else {
        anyhow::bail!("{}", failures.join("; "))
    }
}
