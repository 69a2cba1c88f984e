//! Loads of the liquid on the tank (paper §2.6): a pressure per innermost-layer wall particle
//! every step, a centred rectangular time window of ±N steps, and the force and peak pressure
//! of every part.
//!
//! The window is centred, so the smoothed pressure of step n is known only at step n + N:
//! [`LoadEvaluator::centred`] always describes the step N steps before the last one recorded
//! (for the first N steps the window is cut at the start of the run, and
//! [`LoadEvaluator::flush_tail`] evaluates the last N steps with the window cut at the end).

use crate::kernel::Kernel;
use crate::neighbours::NeighbourSearch;
use crate::params::{SphParams, WallPressureMethod};
use crate::setup::PART_ROOF;
use crate::sim::{Fluid, Vector, Walls};
use rayon::prelude::*;

/// Loads on every part at one step.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PartLoads<const D: usize> {
    /// The step these loads belong to.
    pub step: u64,
    /// Simulated time of that step (s).
    pub time: f64,
    /// Force of the liquid on each part, Σ p A n (N; 2D: N per m of depth).
    pub force: Vec<Vector<D>>,
    /// Largest pressure on each part (Pa); 0 for an empty or dry part.
    pub peak_pressure: Vec<f64>,
}

/// Running extremes of the loads over a run (from time-windowed pressures).
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct LoadPeaks {
    /// Largest roof pressure (Pa).
    pub max_roof_p: f64,
    /// Time of the largest roof pressure (s).
    pub t_max_roof_p: f64,
    /// Largest upward roof force (N; 2D: N/m).
    pub max_roof_force_up: f64,
    /// Time of the largest upward roof force (s).
    pub t_max_roof_force_up: f64,
    /// Largest |base shear| along x (N; 2D: N/m).
    pub max_abs_base_shear_x: f64,
}

/// The evolving state of a [`LoadEvaluator`], for checkpoints.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct LoadState<const D: usize> {
    history: Vec<f64>,
    history_time: Vec<f64>,
    history_step: Vec<u64>,
    running_sum: Vec<f64>,
    recorded: u64,
    instantaneous: Vec<f64>,
    centred_pressure: Vec<f64>,
    centred: Option<PartLoads<D>>,
    peaks: LoadPeaks,
}

/// Evaluates wall pressures for loads and keeps their time window.
pub struct LoadEvaluator<const D: usize> {
    /// Wall particle index of each load point (innermost layer, area > 0).
    wall_index: Vec<u32>,
    part: Vec<u16>,
    area: Vec<f64>,
    normal: Vec<Vector<D>>,
    position: Vec<Vector<D>>,
    n_parts: usize,
    roof_part: Option<usize>,
    half_window: usize,
    window: usize,
    /// Ring of per-step pressures: slot-major, `window` slots of `n` values.
    history: Vec<f64>,
    history_time: Vec<f64>,
    history_step: Vec<u64>,
    running_sum: Vec<f64>,
    recorded: u64,
    instantaneous: Vec<f64>,
    centred_pressure: Vec<f64>,
    centred: Option<PartLoads<D>>,
    peaks: LoadPeaks,
}

impl<const D: usize> LoadEvaluator<D> {
    /// Load points = wall particles with a non-zero area; `smoothing_steps` = N.
    pub fn new(walls: &Walls<D>, n_parts: usize, smoothing_steps: usize) -> Self {
        let wall_index: Vec<u32> = (0..walls.position.len())
            .filter(|&w| walls.area[w] > 0.0)
            .map(|w| w as u32)
            .collect();
        let n = wall_index.len();
        let window = 2 * smoothing_steps + 1;
        LoadEvaluator {
            part: wall_index.iter().map(|&w| walls.part[w as usize]).collect(),
            area: wall_index.iter().map(|&w| walls.area[w as usize]).collect(),
            normal: wall_index
                .iter()
                .map(|&w| walls.normal[w as usize])
                .collect(),
            position: wall_index
                .iter()
                .map(|&w| walls.position[w as usize])
                .collect(),
            wall_index,
            n_parts,
            roof_part: if n_parts > 2 { Some(2) } else { None },
            half_window: smoothing_steps,
            window,
            history: vec![0.0; window * n],
            history_time: vec![0.0; window],
            history_step: vec![0; window],
            running_sum: vec![0.0; n],
            recorded: 0,
            instantaneous: vec![0.0; n],
            centred_pressure: vec![0.0; n],
            centred: None,
            peaks: LoadPeaks::default(),
        }
    }

    /// The evolving part of the evaluator: the ring of past pressures and its running sums,
    /// the last evaluation and the peaks.
    pub(crate) fn state(&self) -> LoadState<D> {
        LoadState {
            history: self.history.clone(),
            history_time: self.history_time.clone(),
            history_step: self.history_step.clone(),
            running_sum: self.running_sum.clone(),
            recorded: self.recorded,
            instantaneous: self.instantaneous.clone(),
            centred_pressure: self.centred_pressure.clone(),
            centred: self.centred.clone(),
            peaks: self.peaks,
        }
    }

    /// Puts back a state taken by [`Self::state`] from an evaluator of the same load points
    /// and window; `Err` names what does not match.
    pub(crate) fn set_state(&mut self, s: LoadState<D>) -> Result<(), String> {
        let n = self.wall_index.len();
        if s.history.len() != self.history.len()
            || s.history_time.len() != self.window
            || s.history_step.len() != self.window
            || s.running_sum.len() != n
            || s.instantaneous.len() != n
            || s.centred_pressure.len() != n
        {
            return Err(format!(
                "the load window holds {} load points × {} steps, the checkpoint {} values",
                n,
                self.window,
                s.history.len()
            ));
        }
        self.history = s.history;
        self.history_time = s.history_time;
        self.history_step = s.history_step;
        self.running_sum = s.running_sum;
        self.recorded = s.recorded;
        self.instantaneous = s.instantaneous;
        self.centred_pressure = s.centred_pressure;
        self.centred = s.centred;
        self.peaks = s.peaks;
        Ok(())
    }

    /// Number of load points.
    pub fn len(&self) -> usize {
        self.wall_index.len()
    }
    /// True when the tank has no load point.
    pub fn is_empty(&self) -> bool {
        self.wall_index.is_empty()
    }
    /// Positions of the load points (m).
    pub fn positions(&self) -> &[Vector<D>] {
        &self.position
    }
    /// Part index of each load point.
    pub fn parts(&self) -> &[u16] {
        &self.part
    }
    /// Area of each load point (m²; 2D m per m).
    pub fn areas(&self) -> &[f64] {
        &self.area
    }
    /// Outward normal of each load point.
    pub fn normals(&self) -> &[Vector<D>] {
        &self.normal
    }
    /// Pressures of the last recorded step, before the time window (Pa).
    pub fn instantaneous_pressure(&self) -> &[f64] {
        &self.instantaneous
    }
    /// Time-windowed pressures of the step [`Self::centred`] describes (Pa).
    pub fn centred_pressure(&self) -> &[f64] {
        &self.centred_pressure
    }
    /// Part loads of the latest step whose centred window is complete (or cut at the start).
    pub fn centred(&self) -> Option<&PartLoads<D>> {
        self.centred.as_ref()
    }
    /// Steps recorded so far.
    pub fn recorded_steps(&self) -> u64 {
        self.recorded
    }
    /// Time of the latest recorded step (s; the label given to [`Self::record_step`]), `None`
    /// before the first.
    pub fn latest_time(&self) -> Option<f64> {
        (self.recorded > 0)
            .then(|| self.history_time[((self.recorded - 1) % self.window as u64) as usize])
    }
    /// Extremes so far.
    pub fn peaks(&self) -> LoadPeaks {
        self.peaks
    }
    /// N, the half width of the time window (steps).
    pub fn smoothing_steps(&self) -> usize {
        self.half_window
    }
    /// Overrides which part index is the roof (default: index 2, `roof`).
    pub fn set_roof_part(&mut self, names: &[String]) {
        self.roof_part = names.iter().position(|n| n == PART_ROOF);
    }

    /// Evaluates the pressure at every load point for the current state (step `step`, time
    /// `time`, the body force `body` of the step), pushes it into the window and updates the
    /// centred loads and the peaks.
    #[allow(clippy::too_many_arguments)]
    pub fn record_step<S: NeighbourSearch<D>>(
        &mut self,
        search: &S,
        fluid: &Fluid<D>,
        walls: &Walls<D>,
        kernel: &Kernel,
        mass: f64,
        params: &SphParams,
        body: &crate::frame::BodyForce<D>,
        step: u64,
        time: f64,
        spacing: f64,
    ) {
        let n = self.wall_index.len();
        if n == 0 {
            return;
        }
        let support_sq = kernel.support() * kernel.support();
        let eps = params.pressure_smoothing_eps;
        let method = params.wall_pressure;
        // Adami walls: the wall particle's extrapolated pressure moved to the wall face
        // (dx/2 inside along −n) by the same hydrostatic correction: p − ρ_w b·n dx/2.
        let adami = params.boundary == crate::params::BoundaryMethod::Adami;
        let wall_index = &self.wall_index;
        let normal = &self.normal;
        self.instantaneous
            .par_iter_mut()
            .enumerate()
            .with_min_len(64)
            .for_each(|(k, p_out)| {
                let w = wall_index[k] as usize;
                *p_out = match method {
                    WallPressureMethod::WallParticle if adami => {
                        let pw = walls.pressure[w];
                        if pw == 0.0 {
                            0.0
                        } else {
                            pw - walls.density[w]
                                * body.at(&walls.position[w]).dot(&normal[k])
                                * (0.5 * spacing)
                        }
                    }
                    WallPressureMethod::WallParticle => walls.pressure[w],
                    WallPressureMethod::NearestFluid => {
                        let j = walls.nearest_fluid[w];
                        if j == u32::MAX {
                            0.0
                        } else {
                            smoothed_pressure(search, fluid, kernel, mass, eps, j as usize)
                        }
                    }
                    WallPressureMethod::KernelExtrapolation => {
                        let face = walls.position[w] - normal[k] * (0.5 * spacing);
                        let body_force = body.at(&face);
                        let mut weighted = 0.0;
                        let mut weight = 0.0;
                        search.for_each_fluid_candidate(&face, |j| {
                            let d = face - fluid.position[j];
                            let r2 = d.norm_squared();
                            if r2 < support_sq {
                                let wv = kernel.value(r2.sqrt()) * mass / fluid.density[j];
                                weight += wv;
                                // Hydrostatic transfer from x_j to the face: p + ρ f·(x − x_j).
                                weighted += wv
                                    * (fluid.pressure[j] + fluid.density[j] * body_force.dot(&d));
                            }
                        });
                        if weight > 1e-3 {
                            weighted / weight
                        } else {
                            0.0
                        }
                    }
                };
            });
        // Push into the ring and update the running sums.
        let slot = (self.recorded % self.window as u64) as usize;
        let row = &mut self.history[slot * n..(slot + 1) * n];
        for ((sum, old), &new) in self
            .running_sum
            .iter_mut()
            .zip(row.iter_mut())
            .zip(&self.instantaneous)
        {
            *sum += new - *old;
            *old = new;
        }
        self.history_time[slot] = time;
        self.history_step[slot] = step;
        self.recorded += 1;
        // Re-add the window exactly once per turn of the ring, so the running sums carry no
        // round-off drift (a dry wall must read exactly 0 Pa again).
        if slot == self.window - 1 {
            self.running_sum.iter_mut().for_each(|s| *s = 0.0);
            for row in self.history.chunks(n) {
                for (s, v) in self.running_sum.iter_mut().zip(row) {
                    *s += v;
                }
            }
        }
        if self.recorded > self.half_window as u64 {
            let count = self.recorded.min(self.window as u64) as f64;
            for (c, s) in self.centred_pressure.iter_mut().zip(&self.running_sum) {
                *c = s / count;
            }
            let centre_slot =
                ((self.recorded - 1 - self.half_window as u64) % self.window as u64) as usize;
            let (cs, ct) = (
                self.history_step[centre_slot],
                self.history_time[centre_slot],
            );
            self.update_centred(cs, ct);
        }
    }

    /// Evaluates the last N recorded steps (whose windows can no longer be completed) with
    /// the window cut at the end of the run, calling `emit` for each, oldest first.
    pub fn flush_tail<F: FnMut(&PartLoads<D>, &[f64])>(&mut self, mut emit: F) {
        let n = self.wall_index.len();
        let recorded = self.recorded;
        let hw = self.half_window as u64;
        let first = recorded.saturating_sub(hw);
        for centre in first..recorded {
            let lo = centre.saturating_sub(hw);
            let hi = recorded - 1;
            let count = (hi - lo + 1) as f64;
            let mut mean = vec![0.0; n];
            for s in lo..=hi {
                let slot = (s % self.window as u64) as usize;
                for (m, v) in mean.iter_mut().zip(&self.history[slot * n..(slot + 1) * n]) {
                    *m += v / count;
                }
            }
            self.centred_pressure.copy_from_slice(&mean);
            let slot = (centre % self.window as u64) as usize;
            let (cs, ct) = (self.history_step[slot], self.history_time[slot]);
            self.update_centred(cs, ct);
            if let Some(c) = &self.centred {
                emit(c, &self.centred_pressure);
            }
        }
    }

    fn update_centred(&mut self, step: u64, time: f64) {
        let mut loads = self.centred.take().unwrap_or_else(|| PartLoads {
            step,
            time,
            force: vec![Vector::<D>::zeros(); self.n_parts],
            peak_pressure: vec![0.0; self.n_parts],
        });
        loads.step = step;
        loads.time = time;
        loads
            .force
            .iter_mut()
            .for_each(|f| *f = Vector::<D>::zeros());
        loads.peak_pressure.iter_mut().for_each(|p| *p = 0.0);
        for k in 0..self.wall_index.len() {
            let part = self.part[k] as usize;
            let p = self.centred_pressure[k];
            loads.force[part] += self.normal[k] * (p * self.area[k]);
            if p > loads.peak_pressure[part] {
                loads.peak_pressure[part] = p;
            }
        }
        if let Some(roof) = self.roof_part {
            if roof < self.n_parts {
                let p = loads.peak_pressure[roof];
                if p > self.peaks.max_roof_p {
                    self.peaks.max_roof_p = p;
                    self.peaks.t_max_roof_p = time;
                }
                let up = loads.force[roof][D - 1];
                if up > self.peaks.max_roof_force_up {
                    self.peaks.max_roof_force_up = up;
                    self.peaks.t_max_roof_force_up = time;
                }
            }
        }
        let shear = base_shear_x(&loads, self.roof_part);
        self.peaks.max_abs_base_shear_x = self.peaks.max_abs_base_shear_x.max(shear.abs());
        self.centred = Some(loads);
    }
}

/// Horizontal (x) force of the liquid on every part except the roof (N; 2D N/m).
pub fn base_shear_x<const D: usize>(loads: &PartLoads<D>, roof_part: Option<usize>) -> f64 {
    loads
        .force
        .iter()
        .enumerate()
        .filter(|(k, _)| Some(*k) != roof_part)
        .map(|(_, f)| f[0])
        .sum()
}

/// Eq. 23: spatial pressure smoothing p'_i = p_i − ε Σ_j (m_j/ρ_j)(p_i − p_j) W_ij over the
/// fluid neighbours of fluid particle `i`.
fn smoothed_pressure<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    fluid: &Fluid<D>,
    kernel: &Kernel,
    mass: f64,
    eps: f64,
    i: usize,
) -> f64 {
    let xi = fluid.position[i];
    let pi = fluid.pressure[i];
    let support_sq = kernel.support() * kernel.support();
    let mut correction = 0.0;
    search.for_each_fluid_candidate(&xi, |j| {
        let r2 = (xi - fluid.position[j]).norm_squared();
        if r2 < support_sq {
            correction +=
                mass / fluid.density[j] * (pi - fluid.pressure[j]) * kernel.value(r2.sqrt());
        }
    });
    pi - eps * correction
}
