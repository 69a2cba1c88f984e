//! Roof loads beyond the part totals: the roof pressure map over time, the roof impacts with
//! Kurihara's and Malhotra's formulas beside the SPH peak (paper §3.2), and pressure-field
//! snapshots around the largest impact (paper Fig. 7).

use crate::roof_load::RoofLoadResult;
use serde::{Deserialize, Serialize};
use slosh_core::{Simulation, Vector};
use slosh_theory::roof::{kurihara_roof_pressure, malhotra_roof_pressure, MALHOTRA_DEFAULT_ANGLE};

/// One roof impact: a contact episode of the roof force (see [`crate::roof_load`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoofImpact {
    /// Start of the contact (s): the output row before the roof force rose above the impact
    /// threshold.
    pub t_start: f64,
    /// End of the contact (s).
    #[serde(default)]
    pub t_end: f64,
    /// Time of the largest roof pressure (s).
    pub t_peak: f64,
    /// Largest roof pressure, SPH, time-windowed (Pa).
    pub p_max_sph: f64,
    /// Largest upward roof force (N; 2D N/m).
    pub force_max: f64,
    /// Impulse ∫ F dt of the upward roof force over the impact, from every step's wall
    /// pressures (N·s; 2D N·s/m).
    pub impulse: f64,
    /// Equivalent static roof force F_eq at each design period T_r, from the start of the
    /// impact to the start of the next (N; 2D N/m).
    #[serde(default)]
    pub f_eq: Vec<f64>,
    /// Each roof sensor's largest mean pressure over the impact, per step (Pa).
    #[serde(default)]
    pub sensor_peak: Vec<f64>,
    /// Each roof sensor's pressure impulse ∫ p dt over the impact (Pa·s).
    #[serde(default)]
    pub sensor_impulse: Vec<f64>,
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

/// A particle snapshot of a 2D run (positions and pressure), for paper Fig. 7.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoofSnapshot {
    /// Simulation time (s).
    pub time: f64,
    /// Fluid positions (x, vertical) (m).
    pub position: Vec<[f64; 2]>,
    /// Fluid pressures (Pa).
    pub pressure: Vec<f64>,
}

/// Collects the roof pressure map and the 2D snapshots during a run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoofMonitor<const D: usize> {
    /// Load-point indices of the roof, ordered along x.
    points: Vec<usize>,
    positions: Vec<Vector<D>>,
    areas: Vec<f64>,
    /// Distance of each roof point from the side wall (m).
    wall_distance: Vec<f64>,
    times: Vec<f64>,
    map: Vec<f64>,
    snapshots: Vec<RoofSnapshot>,
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
        self.snapshots.push(RoofSnapshot {
            time: sim.time(),
            position: fluid.position.iter().map(|p| [p[0], p[D - 1]]).collect(),
            pressure: fluid.pressure.clone(),
        });
    }

    /// Peak pressure of each roof point and its time.
    pub fn peaks(&self) -> (Vec<f64>, Vec<f64>) {
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

    /// Roof load points: their positions (ordered along x) and areas (m², 2D m).
    pub fn points(&self) -> (&[Vector<D>], &[f64]) {
        (&self.positions, &self.areas)
    }

    /// Times of the rows of the pressure map (s).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The pressure map, row-major: one row per output row, one column per roof point (Pa).
    pub fn map(&self) -> &[f64] {
        &self.map
    }

    /// The 2D fluid snapshots kept for the pressure-field plots of paper Fig. 7.
    pub fn snapshots(&self) -> &[RoofSnapshot] {
        &self.snapshots
    }

    /// The interior of the tank (lower and upper corners, m) and the lattice spacing (m).
    pub fn interior(&self) -> ((Vector<D>, Vector<D>), f64) {
        (self.interior, self.spacing)
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

/// The roof impacts of a run: the contact episodes of `loads` (see
/// [`crate::roof_load`]), each with its time-windowed peaks from the series rows, the crest's
/// speed before contact and Kurihara's and Malhotra's pressures.
pub fn find_impacts(
    loads: &RoofLoadResult,
    t: &[f64],
    roof_force: &[f64],
    roof_p: &[f64],
    crest_vz: &[f64],
    contact: &[f64],
    tank: &RoofTank,
) -> Vec<RoofImpact> {
    let row = |time: f64| t.partition_point(|&x| x < time - 1e-12).min(t.len());
    let mut impacts = Vec::new();
    for e in &loads.episodes {
        let (start, end) = (row(e.t_start), (row(e.t_end) + 1).min(t.len()));
        if start >= end {
            continue;
        }
        let (k_peak, p_peak) = (start..end)
            .map(|k| (k, roof_p[k]))
            .fold((start, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let force_max = roof_force[start..end].iter().copied().fold(0.0, f64::max);
        // The crest's upward speed at the last row before the roof took load (the episode
        // starts at that row).
        let v = crest_vz[start].max(0.0);
        let x_f = contact[k_peak];
        impacts.push(RoofImpact {
            t_start: e.t_start,
            t_end: e.t_end,
            t_peak: t[k_peak],
            p_max_sph: p_peak,
            force_max,
            impulse: e.impulse[0],
            f_eq: e.f_eq[0].clone(),
            sensor_peak: e.peak[1..].to_vec(),
            sensor_impulse: e.impulse[1..].to_vec(),
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
