//! The files of a run folder written while the case runs, as an observer of the run loop
//! ([`RunFiles`]: `series.csv` row by row, frames, checkpoints, progress), and at its end
//! (`series.csv` again with the low-pass load columns, the plots of the time histories).

use crate::progress::Progress;
use crate::summary::Summary;
use anyhow::Result;
use slosh_core::{Simulation, Vector};
use slosh_io::{FrameSeries, PlotSpec, PointArray, Series, SeriesWriter};
use slosh_run::{HookError, Observer};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The files a run writes while it runs, as an observer of the run loop: `series.csv`
/// streamed row by row (written again at the end with the low-pass load columns), the
/// particle frames, and the progress display.
pub(crate) struct RunFiles {
    /// The run folder.
    pub(crate) out: PathBuf,
    /// `series.csv`, open from the first row on.
    pub(crate) series: Option<SeriesWriter>,
    /// The particle frames, when the case asks for them.
    pub(crate) frames: Option<FrameSeries>,
    /// The progress display, when the run shows one.
    pub(crate) progress: Option<Progress>,
    /// When the time loop started.
    pub(crate) started: Instant,
    /// The checkpoint writer, when checkpoints are on.
    pub(crate) checkpoints: Option<crate::checkpoint::CheckpointWriter>,
    /// Rows a resumed run wrote before its checkpoint, written again after the header.
    pub(crate) earlier_rows: Vec<Vec<f64>>,
    /// A checkpoint that could not be written (the run goes on; the summary says so).
    pub(crate) checkpoint_error: Option<String>,
    /// Simulated time after the last step (s), for [`crate::stop::RunStop`].
    pub(crate) time_reached: std::rc::Rc<std::cell::Cell<f64>>,
}

impl<const D: usize> Observer<D> for RunFiles {
    fn columns(&mut self, columns: &[(String, String)]) -> Result<(), HookError> {
        let mut writer = SeriesWriter::create(self.out.join("series.csv"), columns)?;
        for row in std::mem::take(&mut self.earlier_rows) {
            writer.write_row(&row)?;
        }
        self.series = Some(writer);
        Ok(())
    }

    fn checkpoint_due(&mut self, _time: f64, _steps: u64) -> bool {
        self.checkpoints.as_ref().is_some_and(|c| c.due())
    }

    fn checkpoint(&mut self, state: &slosh_run::RunCheckpoint<D>) -> Result<(), HookError> {
        let Some(writer) = self.checkpoints.as_mut() else {
            return Ok(());
        };
        // The rows so far must be on disk before a checkpoint that counts them.
        if let Some(series) = self.series.as_mut() {
            series.flush()?;
        }
        let frames = self
            .frames
            .as_ref()
            .map(|f| f.index().entries().to_vec())
            .unwrap_or_default();
        if let Err(e) = writer.write(&frames, state) {
            let message = format!("{e:#}");
            eprintln!("warning: checkpoint not written: {message}");
            self.checkpoint_error = Some(message);
        }
        Ok(())
    }

    fn row(&mut self, values: &[f64]) -> Result<(), HookError> {
        if let Some(writer) = self.series.as_mut() {
            writer.write_row(values)?;
        }
        Ok(())
    }

    fn frame(&mut self, sim: &Simulation<D>, time: f64) -> Result<(), HookError> {
        if let Some(frames) = self.frames.as_mut() {
            write_frame(frames, sim, time)?;
        }
        Ok(())
    }

    fn progress(&mut self, time: f64, steps: u64) {
        self.time_reached.set(time);
        if let Some(progress) = self.progress.as_mut() {
            progress.update(time, steps, self.started);
        }
    }

    fn series(
        &mut self,
        columns: &[(String, String)],
        series: &[Vec<f64>],
    ) -> Result<(), HookError> {
        if let Some(progress) = &self.progress {
            progress.finish();
        }
        if let Some(mut writer) = self.series.take() {
            writer.flush()?;
        }
        rewrite_series(&self.out.join("series.csv"), columns, series)?;
        Ok(())
    }
}

/// Writes `series.csv` (and its units file) again with every column, the filtered load
/// columns appended after the raw ones.
pub(crate) fn rewrite_series(
    path: &Path,
    names: &[(String, String)],
    history: &[Vec<f64>],
) -> Result<()> {
    // Written in a folder of its own beside the series, then both files renamed into place:
    // the streamed series stays whole until the new one is complete.
    let dir = path.parent().unwrap_or(Path::new("."));
    let staging = dir.join(".series-rewrite");
    if std::fs::symlink_metadata(&staging).is_ok_and(|m| !m.is_dir()) {
        anyhow::bail!(
            "{} is a link or a file; slosh writes no file through a link",
            staging.display()
        );
    }
    std::fs::create_dir_all(&staging)?;
    let staged = staging.join(path.file_name().unwrap_or("series.csv".as_ref()));
    let staged_units = slosh_io::units_path_for(&staged);
    let written = (|| -> Result<()> {
        let mut writer = SeriesWriter::create(&staged, names)?;
        let rows = history.first().map_or(0, Vec::len);
        let mut row = Vec::with_capacity(history.len());
        for r in 0..rows {
            row.clear();
            row.extend(history.iter().map(|c| c[r]));
            writer.write_row(&row)?;
        }
        writer.flush()?;
        drop(writer);
        std::fs::rename(&staged_units, slosh_io::units_path_for(path))?;
        std::fs::rename(&staged, path)?;
        Ok(())
    })();
    if written.is_err() {
        // A full disk: the staged copies (slosh's own two files) must not hold its space;
        // the streamed series.csv stays as it was.
        let _ = std::fs::remove_file(&staged);
        let _ = std::fs::remove_file(&staged_units);
    }
    let _ = std::fs::remove_dir(&staging);
    written
}

/// Appends the particles of `sim` at time `t` (s) to the frame series: positions, velocity,
/// pressure, density, kind (0 fluid, 1 wall), wall part (−1 for fluid) and particle id.
pub(crate) fn write_frame<const D: usize>(
    frames: &mut FrameSeries,
    sim: &Simulation<D>,
    t: f64,
) -> Result<()> {
    let fluid = sim.fluid();
    let walls = sim.walls();
    let pad = |p: &Vector<D>| {
        let mut a = [0.0; 3];
        a[..D].copy_from_slice(p.as_slice());
        a
    };
    let points: Vec<[f64; 3]> = fluid
        .position
        .iter()
        .chain(&walls.position)
        .map(pad)
        .collect();
    let velocity: Vec<[f64; 3]> = fluid
        .velocity
        .iter()
        .map(pad)
        .chain(walls.position.iter().map(|_| [0.0; 3]))
        .collect();
    let pressure: Vec<f64> = fluid
        .pressure
        .iter()
        .chain(&walls.pressure)
        .copied()
        .collect();
    let density: Vec<f64> = fluid
        .density
        .iter()
        .chain(&walls.density)
        .copied()
        .collect();
    let kind: Vec<i32> = std::iter::repeat_n(0, fluid.position.len())
        .chain(std::iter::repeat_n(1, walls.position.len()))
        .collect();
    let part: Vec<i32> = std::iter::repeat_n(-1, fluid.position.len())
        .chain(walls.part.iter().map(|&p| p as i32))
        .collect();
    let id: Vec<i32> = fluid
        .id
        .iter()
        .map(|&i| i as i32)
        .chain((0..walls.position.len()).map(|w| w as i32))
        .collect();
    frames.write_frame(
        t,
        &points,
        &[
            PointArray::vector3("velocity", &velocity),
            PointArray::scalar("pressure", &pressure),
            PointArray::scalar("density", &density),
            PointArray::int32("kind", &kind),
            PointArray::int32("part", &part),
            PointArray::int32("id", &id),
        ],
    )?;
    Ok(())
}

/// Draws the main time histories of a run into `out/plots/` (PNG and SVG): elevations, base
/// shear, roof force and pressure when the liquid touched the roof, ground acceleration.
pub(crate) fn write_plots(
    out: &Path,
    names: &[(String, String)],
    history: &[Vec<f64>],
    dim: usize,
    summary: &Summary,
) -> Result<()> {
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots)?;
    let find = |n: &str| names.iter().position(|(c, _)| c == n);
    let t = &history[0];
    let force_unit = if dim == 2 { "N/m" } else { "N" };
    let plot = |file: &str, title: &str, ylabel: String, series: Vec<Series>| -> Result<()> {
        if series.is_empty() {
            return Ok(());
        }
        slosh_io::line_plot(
            plots.join(file),
            &PlotSpec::new(title, "time t [s]", &ylabel),
            &series,
        )?;
        Ok(())
    };
    let lines = |cols: &[&str]| -> Vec<Series> {
        cols.iter()
            .filter_map(|c| find(c).map(|i| Series::line(c.to_string(), t, &history[i])))
            .collect()
    };
    let gauges: Vec<&str> = names
        .iter()
        .map(|(n, _)| n.as_str())
        .filter(|n| n.starts_with("eta_"))
        .collect();
    plot(
        "eta",
        "Free-surface elevation at the walls and gauges",
        "elevation η [m]".into(),
        lines(&gauges),
    )?;
    plot(
        "base_shear",
        "Base shear (fluid on walls and bottom)",
        format!("base shear [{force_unit}]"),
        raw_and_filtered(
            &["base_shear_x", "base_shear_y"],
            &find,
            t,
            history,
            summary.load_filter.cutoff_hz,
        ),
    )?;
    if summary.roof_contact {
        plot(
            "roof_force",
            "Upward force on the roof",
            format!("roof force [{force_unit}]"),
            raw_and_filtered(
                &["roof_force_up"],
                &find,
                t,
                history,
                summary.load_filter.cutoff_hz,
            ),
        )?;
        plot(
            "roof_pressure",
            "Largest roof pressure",
            "pressure [Pa]".into(),
            lines(&["roof_p_max"]),
        )?;
    }
    plot(
        "ground_accel",
        "Ground acceleration",
        "acceleration [m/s²]".into(),
        lines(&["accel_x"]),
    )?;
    Ok(())
}

/// Each raw column (light) with its low-pass copy (dark) on top, labelled for the legend.
fn raw_and_filtered<'a>(
    columns: &[&str],
    find: &dyn Fn(&str) -> Option<usize>,
    t: &'a [f64],
    history: &'a [Vec<f64>],
    cutoff_hz: f64,
) -> Vec<Series<'a>> {
    const RAW: [(u8, u8, u8); 2] = [(160, 190, 230), (240, 190, 150)];
    const FILTERED: [(u8, u8, u8); 2] = [(20, 60, 160), (190, 80, 10)];
    let mut raw = Vec::new();
    let mut filtered = Vec::new();
    for (k, column) in columns.iter().enumerate() {
        let (Some(i), Some(j)) = (find(column), find(&format!("{column}_lp"))) else {
            continue;
        };
        let (r, g, b) = RAW[k % 2];
        raw.push(Series::line(format!("{column} (raw)"), t, &history[i]).with_color(r, g, b));
        let (r, g, b) = FILTERED[k % 2];
        filtered.push(
            Series::line(
                format!("{column}_lp (low-pass {cutoff_hz:.2} Hz)"),
                t,
                &history[j],
            )
            .with_color(r, g, b),
        );
    }
    raw.extend(filtered);
    raw
}
