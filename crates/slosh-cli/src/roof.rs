//! Roof loads beyond the part totals: the roof pressure map over time, the roof impacts with
//! Kurihara's and Malhotra's formulas beside the SPH peak (paper §3.2), and pressure-field
//! snapshots around the largest impact (paper Fig. 7).

use anyhow::Result;
use serde::{Deserialize, Serialize};
use slosh_core::{Simulation, Vector};
use slosh_io::{Field2d, PlotSpec, PointArray};
use slosh_theory::roof::{kurihara_roof_pressure, malhotra_roof_pressure, MALHOTRA_DEFAULT_ANGLE};
use std::path::Path;

/// One roof impact: a run of output rows with liquid on the roof.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoofImpact {
    /// First row with roof pressure (s).
    pub t_start: f64,
    /// Time of the largest roof pressure (s).
    pub t_peak: f64,
    /// Largest roof pressure, SPH, time-windowed (Pa).
    pub p_max_sph: f64,
    /// Largest upward roof force (N; 2D N/m).
    pub force_max: f64,
    /// Impulse ∫ F dt of the upward roof force over the impact (N·s; 2D N·s/m).
    pub impulse: f64,
    /// Upward velocity of the wave crest at the last row before contact (m/s).
    pub crest_velocity: f64,
    /// Horizontal extent of the wetted roof from the wall at the peak, x_f (m).
    pub contact_extent: f64,
    /// Kurihara (1991) Eq. 28 with that crest velocity (Pa).
    pub p_kurihara: f64,
    /// Malhotra (2005) Eq. 27 with that x_f, θ = π/4 (Pa).
    pub p_malhotra: f64,
}

/// The tank numbers Kurihara's formula needs.
#[derive(Clone, Copy, Debug)]
pub struct RoofTank {
    /// Liquid density (kg/m³).
    pub density: f64,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Still depth H (m).
    pub depth: f64,
    /// Freeboard H′ (m): roof height at the wall minus the depth.
    pub freeboard: f64,
    /// Half-width l (2D) or radius (m).
    pub half_width: f64,
    /// Sloshing circular frequency ω (rad/s), the first mode.
    pub omega: f64,
}

/// A particle snapshot of a 2D run (positions and pressure), for Fig. 7.
struct Snapshot {
    time: f64,
    position: Vec<[f64; 2]>,
    pressure: Vec<f64>,
}

/// Collects the roof pressure map and the 2D snapshots during a run.
pub struct RoofMonitor<const D: usize> {
    /// Load-point indices of the roof, ordered along x.
    points: Vec<usize>,
    positions: Vec<Vector<D>>,
    areas: Vec<f64>,
    /// Distance of each roof point from the side wall (m).
    wall_distance: Vec<f64>,
    times: Vec<f64>,
    map: Vec<f64>,
    snapshots: Vec<Snapshot>,
    keep_snapshots: bool,
    interior: (Vector<D>, Vector<D>),
    spacing: f64,
}

/// Pressure (Pa) above which a roof point counts as wetted (≈ 0.1 mm of water head): the
/// time window leaves no residue on a dry wall, but the threshold also ignores a single
/// particle grazing the roof.
pub const WET_PRESSURE: f64 = 1.0;

/// Largest number of particle values kept in memory for Fig. 7 snapshots.
const SNAPSHOT_BUDGET: usize = 8_000_000;

impl<const D: usize> RoofMonitor<D> {
    /// Finds the roof load points of `sim`; `expected_rows` sizes the snapshot budget.
    pub fn new(sim: &Simulation<D>, expected_rows: usize) -> Self {
        let loads = sim.loads();
        let roof = sim.part_names().iter().position(|n| n == "roof");
        let (lo, hi) = sim.interior_bounds();
        let mut points: Vec<usize> = (0..loads.len())
            .filter(|&k| Some(loads.parts()[k] as usize) == roof)
            .collect();
        points.sort_by(|&a, &b| loads.positions()[a][0].total_cmp(&loads.positions()[b][0]));
        let positions: Vec<Vector<D>> = points.iter().map(|&k| loads.positions()[k]).collect();
        let wall_distance = positions
            .iter()
            .map(|p| {
                if D == 2 {
                    (p[0] - lo[0]).min(hi[0] - p[0]).max(0.0)
                } else {
                    // Cylinder about the vertical axis through the interior centre.
                    let cx = 0.5 * (lo[0] + hi[0]);
                    let cy = 0.5 * (lo[1] + hi[1]);
                    let r = ((p[0] - cx).powi(2) + (p[1] - cy).powi(2)).sqrt();
                    (0.5 * (hi[0] - lo[0]) - r).max(0.0)
                }
            })
            .collect();
        let n_fluid = sim.fluid().position.len();
        RoofMonitor {
            areas: points.iter().map(|&k| loads.areas()[k]).collect(),
            points,
            positions,
            wall_distance,
            times: Vec::new(),
            map: Vec::new(),
            snapshots: Vec::new(),
            keep_snapshots: D == 2
                && roof.is_some()
                && n_fluid * 3 * expected_rows <= SNAPSHOT_BUDGET,
            interior: (lo, hi),
            spacing: sim.spacing(),
        }
    }

    /// True when the tank has a roof with load points.
    pub fn has_roof(&self) -> bool {
        !self.points.is_empty()
    }

    /// Adds a row of the pressure map from the time-windowed load-point pressures and returns
    /// the wetted extent of the roof from the wall (m).
    pub fn record(&mut self, time: f64, centred_pressure: &[f64]) -> f64 {
        if self.points.is_empty() {
            return 0.0;
        }
        self.times.push(time);
        let mut extent: f64 = 0.0;
        for (i, &k) in self.points.iter().enumerate() {
            let p = centred_pressure[k];
            self.map.push(p);
            if p > WET_PRESSURE {
                extent = extent.max(self.wall_distance[i] + 0.5 * self.spacing);
            }
        }
        extent
    }

    /// Keeps a snapshot of the fluid (2D runs with a roof, within a memory budget).
    pub fn snapshot(&mut self, sim: &Simulation<D>) {
        if !self.keep_snapshots {
            return;
        }
        let fluid = sim.fluid();
        self.snapshots.push(Snapshot {
            time: sim.time(),
            position: fluid.position.iter().map(|p| [p[0], p[D - 1]]).collect(),
            pressure: fluid.pressure.clone(),
        });
    }

    /// Writes `roof_pressure.csv` (2D: rows = time, columns = x along the roof; 3D: columns =
    /// roof point index, with `roof_points.csv` and `roof_points.vtp` giving the points, their
    /// peak pressure and its time) and the 2D map plot.
    pub fn write(&self, out: &Path, plots: bool) -> Result<()> {
        if self.points.is_empty() || self.times.is_empty() {
            return Ok(());
        }
        let n = self.points.len();
        if D == 2 {
            let xs: Vec<f64> = self.positions.iter().map(|p| p[0]).collect();
            slosh_io::write_grid_csv(
                out.join("roof_pressure.csv"),
                "t",
                &self.times,
                &xs,
                &self.map,
            )?;
            if plots {
                slosh_io::heatmap(
                    out.join("plots").join("roof_pressure_map"),
                    &PlotSpec::new(
                        "Roof pressure (time-windowed)",
                        "time t [s]",
                        "x along the roof [m]",
                    ),
                    &Field2d {
                        xs: &self.times,
                        ys: &xs,
                        values: &self.map,
                        value_label: "p [Pa]".into(),
                    },
                )?;
            }
        } else {
            let idx: Vec<f64> = (0..n).map(|i| i as f64).collect();
            slosh_io::write_grid_csv(
                out.join("roof_pressure.csv"),
                "t",
                &self.times,
                &idx,
                &self.map,
            )?;
            let mut table = slosh_io::TableWriter::create_whole(
                out.join("roof_points.csv"),
                &["index", "x", "y", "z", "area", "p_peak", "t_peak"],
            )?;
            let (peak, t_peak) = self.peaks();
            for i in 0..n {
                let p = self.positions[i];
                table.write_row(&[
                    i as f64,
                    p[0],
                    p[1],
                    p[2],
                    self.areas[i],
                    peak[i],
                    t_peak[i],
                ])?;
            }
            table.finish()?;
            let points: Vec<[f64; 3]> = self.positions.iter().map(|p| [p[0], p[1], p[2]]).collect();
            slosh_io::write_vtp(
                out.join("roof_points.vtp"),
                &points,
                &[
                    PointArray::scalar("p_peak", &peak),
                    PointArray::scalar("t_peak", &t_peak),
                    PointArray::scalar("area", &self.areas),
                ],
            )?;
        }
        Ok(())
    }

    /// Peak pressure of each roof point and its time.
    fn peaks(&self) -> (Vec<f64>, Vec<f64>) {
        let n = self.points.len();
        let mut peak = vec![0.0; n];
        let mut t_peak = vec![0.0; n];
        for (r, t) in self.times.iter().enumerate() {
            for i in 0..n {
                let p = self.map[r * n + i];
                if p > peak[i] {
                    peak[i] = p;
                    t_peak[i] = *t;
                }
            }
        }
        (peak, t_peak)
    }

    /// Rows of the pressure map (one per output row), for `post(run)`.
    pub fn map_rows(&self) -> Vec<Vec<f64>> {
        let n = self.points.len();
        if n == 0 {
            return Vec::new();
        }
        self.map.chunks(n).map(|c| c.to_vec()).collect()
    }

    /// Draws the 2D pressure field at t_peak − 0.06 s, t_peak, t_peak + 0.06 s (paper Fig. 7
    /// shows 1.55, 1.61 and 1.67 s after the excitation start) as `plots/fig7_*.png`.
    pub fn write_fig7(&self, out: &Path, t_peak: f64, settle: f64) -> Result<()> {
        if self.snapshots.is_empty() || D != 2 {
            return Ok(());
        }
        let dir = out.join("plots");
        std::fs::create_dir_all(&dir)?;
        let (lo, hi) = self.interior;
        let dx = self.spacing;
        let nx = ((hi[0] - lo[0]) / dx).round().max(1.0) as usize;
        let ny = ((hi[D - 1] - lo[D - 1]) / dx).round().max(1.0) as usize;
        let xs: Vec<f64> = (0..nx).map(|i| lo[0] + (i as f64 + 0.5) * dx).collect();
        let ys: Vec<f64> = (0..ny).map(|j| lo[D - 1] + (j as f64 + 0.5) * dx).collect();
        for (label, offset) in [("a", -0.06), ("b", 0.0), ("c", 0.06)] {
            let target = t_peak + offset;
            let Some(snap) = self
                .snapshots
                .iter()
                .min_by(|a, b| (a.time - target).abs().total_cmp(&(b.time - target).abs()))
            else {
                continue;
            };
            let mut values = vec![f64::NAN; nx * ny];
            for (p, &pr) in snap.position.iter().zip(&snap.pressure) {
                let i = ((p[0] - lo[0]) / dx).floor();
                let j = ((p[1] - lo[D - 1]) / dx).floor();
                if i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny {
                    values[i as usize * ny + j as usize] = pr;
                }
            }
            slosh_io::heatmap(
                dir.join(format!("fig7_{label}")),
                &PlotSpec::new(
                    format!(
                        "Pressure field at {:.2} s after the excitation start",
                        snap.time - settle
                    ),
                    "x [m]",
                    "y [m]",
                ),
                &Field2d {
                    xs: &xs,
                    ys: &ys,
                    values: &values,
                    value_label: "p [Pa]".into(),
                },
            )?;
        }
        Ok(())
    }
}

/// Upward velocity (m/s) and height (m) of the wave crest: the mean vertical velocity of the
/// fluid particles within one spacing of the highest one.
pub fn crest<const D: usize>(sim: &Simulation<D>) -> (f64, f64) {
    let fluid = sim.fluid();
    let top = fluid
        .position
        .iter()
        .map(|p| p[D - 1])
        .fold(f64::NEG_INFINITY, f64::max);
    let dx = sim.spacing();
    let (mut sum, mut n) = (0.0, 0usize);
    for (p, v) in fluid.position.iter().zip(&fluid.velocity) {
        if p[D - 1] >= top - dx {
            sum += v[D - 1];
            n += 1;
        }
    }
    (if n > 0 { sum / n as f64 } else { 0.0 }, top)
}

/// Splits the output rows into roof impacts and evaluates Kurihara and Malhotra for each.
/// An impact is a run of rows with roof pressure above [`WET_PRESSURE`] (runs closer than
/// 0.05 s are merged);
/// impacts whose peak is below 5 % of the largest are dropped as splashes.
pub fn find_impacts(
    t: &[f64],
    roof_force: &[f64],
    roof_p: &[f64],
    crest_vz: &[f64],
    contact: &[f64],
    tank: &RoofTank,
) -> Vec<RoofImpact> {
    let n = t.len();
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut i = 0;
    while i < n {
        if roof_p[i] > WET_PRESSURE {
            let start = i;
            while i < n && roof_p[i] > WET_PRESSURE {
                i += 1;
            }
            match runs.last_mut() {
                Some(last) if t[start] - t[last.1 - 1] < 0.05 => last.1 = i,
                _ => runs.push((start, i)),
            }
        } else {
            i += 1;
        }
    }
    let overall = roof_p.iter().copied().fold(0.0, f64::max);
    let mut impacts = Vec::new();
    for (start, end) in runs {
        let (k_peak, p_peak) = (start..end)
            .map(|k| (k, roof_p[k]))
            .fold((start, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        if p_peak < 0.05 * overall {
            continue;
        }
        let force_max = roof_force[start..end].iter().copied().fold(0.0, f64::max);
        let mut impulse = 0.0;
        for k in start.max(1)..end {
            impulse += 0.5 * (roof_force[k] + roof_force[k - 1]).max(0.0) * (t[k] - t[k - 1]);
        }
        let v = if start > 0 {
            crest_vz[start - 1].max(0.0)
        } else {
            0.0
        };
        let x_f = contact[k_peak];
        impacts.push(RoofImpact {
            t_start: t[start],
            t_peak: t[k_peak],
            p_max_sph: p_peak,
            force_max,
            impulse,
            crest_velocity: v,
            contact_extent: x_f,
            p_kurihara: if tank.freeboard > 0.0 {
                kurihara_roof_pressure(
                    tank.density,
                    tank.depth,
                    tank.freeboard,
                    tank.half_width,
                    v,
                    tank.omega,
                )
            } else {
                f64::NAN
            },
            p_malhotra: malhotra_roof_pressure(
                tank.density,
                tank.gravity,
                x_f,
                MALHOTRA_DEFAULT_ANGLE,
            ),
        });
    }
    impacts
}
