//! The state a run continues from: everything the next step reads that the construction of
//! a [`Simulation`] from the same tank and parameters does not give back. Restoring it into
//! such a simulation continues the run bit for bit (`tests_checkpoint.rs`).
//!
//! What is not kept is rebuilt before it is read: the neighbour search, the sweep blocks and
//! neighbour lists (every step after the first re-indexes and re-lists), the scattered wall
//! sums (empty between steps), the strain rate and hydrostatic density of continuity density
//! (recomputed by the density stage), the shifting sums (by the force stage).

use crate::error::SimError;
use crate::loads::LoadState;
use crate::sim::*;

/// A simulation's evolving state (serde), as [`Simulation::state`] takes it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SimState<const D: usize> {
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    dt_previous: f64,
    dt_last: f64,
    stats: StepStats,
    phase_times: PhaseTimes,
    fluid_position: Vec<Vector<D>>,
    fluid_velocity: Vec<Vector<D>>,
    fluid_velocity_half: Vec<Vector<D>>,
    fluid_acceleration: Vec<Vector<D>>,
    fluid_density: Vec<f64>,
    fluid_inverse_density: Vec<f64>,
    fluid_pressure: Vec<f64>,
    fluid_kernel_sum: Vec<f64>,
    fluid_strain_rate: Vec<Tensor<D>>,
    fluid_density_rate: Vec<f64>,
    fluid_id: Vec<u32>,
    wall_density: Vec<f64>,
    wall_inverse_density: Vec<f64>,
    wall_pressure: Vec<f64>,
    wall_nearest_fluid: Vec<u32>,
    density_start: Vec<f64>,
    wall_velocity: Vec<Vector<D>>,
    loads: LoadState<D>,
}

impl<const D: usize> Simulation<D> {
    /// The state to continue this run from later ([`Self::restore`]); taken between steps.
    pub fn state(&self) -> SimState<D> {
        let (f, w, b) = (&self.fluid, &self.walls, &self.buffers);
        SimState {
            time: self.time,
            step: self.step,
            dt_previous: self.dt_previous,
            dt_last: self.dt_last,
            stats: self.stats,
            phase_times: self.phase_times,
            fluid_position: f.position.clone(),
            fluid_velocity: f.velocity.clone(),
            fluid_velocity_half: f.velocity_half.clone(),
            fluid_acceleration: f.acceleration.clone(),
            fluid_density: f.density.clone(),
            fluid_inverse_density: f.inverse_density.clone(),
            fluid_pressure: f.pressure.clone(),
            fluid_kernel_sum: f.kernel_sum.clone(),
            fluid_strain_rate: f.strain_rate.clone(),
            fluid_density_rate: f.density_rate.clone(),
            fluid_id: f.id.clone(),
            wall_density: w.density.clone(),
            wall_inverse_density: w.inverse_density.clone(),
            wall_pressure: w.pressure.clone(),
            wall_nearest_fluid: w.nearest_fluid.clone(),
            density_start: b.density_start.clone(),
            wall_velocity: b.wall_velocity.clone(),
            loads: self.loads.state(),
        }
    }

    /// Continues from `state`, taken by [`Self::state`] from a simulation built from the same
    /// particles and parameters; the next [`Self::step`] is the one the original run took
    /// next. A state of another tank (particle counts, load points) is refused and leaves
    /// this simulation unchanged.
    pub fn restore(&mut self, state: SimState<D>) -> Result<(), SimError> {
        let (n, n_wall) = (self.fluid.position.len(), self.walls.position.len());
        let mismatch = |what: &str, got: usize, want: usize| {
            SimError::InvalidSetup(format!(
                "the checkpoint does not belong to this tank: {got} {what} where the case \
                 builds {want}"
            ))
        };
        for (what, got, want) in [
            ("fluid positions", state.fluid_position.len(), n),
            ("fluid velocities", state.fluid_velocity.len(), n),
            ("half-step velocities", state.fluid_velocity_half.len(), n),
            ("accelerations", state.fluid_acceleration.len(), n),
            ("fluid densities", state.fluid_density.len(), n),
            ("inverse densities", state.fluid_inverse_density.len(), n),
            ("fluid pressures", state.fluid_pressure.len(), n),
            ("kernel sums", state.fluid_kernel_sum.len(), n),
            ("strain rates", state.fluid_strain_rate.len(), n),
            ("density rates", state.fluid_density_rate.len(), n),
            ("particle ids", state.fluid_id.len(), n),
            ("wall densities", state.wall_density.len(), n_wall),
            (
                "wall inverse densities",
                state.wall_inverse_density.len(),
                n_wall,
            ),
            ("wall pressures", state.wall_pressure.len(), n_wall),
            (
                "wall nearest-fluid links",
                state.wall_nearest_fluid.len(),
                n_wall,
            ),
            (
                "symplectic start densities",
                state.density_start.len(),
                self.buffers.density_start.len(),
            ),
            (
                "wall velocities",
                state.wall_velocity.len(),
                self.buffers.wall_velocity.len(),
            ),
        ] {
            if got != want {
                return Err(mismatch(what, got, want));
            }
        }
        if state.fluid_id.iter().any(|&id| id as usize >= n) {
            return Err(SimError::InvalidSetup(
                "the checkpoint's particle ids do not belong to this tank".into(),
            ));
        }
        self.loads.set_state(state.loads).map_err(|e| {
            SimError::InvalidSetup(format!("the checkpoint does not belong to this tank: {e}"))
        })?;
        self.time = state.time;
        self.step = state.step;
        self.dt_previous = state.dt_previous;
        self.dt_last = state.dt_last;
        self.stats = state.stats;
        self.phase_times = state.phase_times;
        let f = &mut self.fluid;
        f.position = state.fluid_position;
        f.velocity = state.fluid_velocity;
        f.velocity_half = state.fluid_velocity_half;
        f.acceleration = state.fluid_acceleration;
        f.density = state.fluid_density;
        f.inverse_density = state.fluid_inverse_density;
        f.pressure = state.fluid_pressure;
        f.kernel_sum = state.fluid_kernel_sum;
        f.strain_rate = state.fluid_strain_rate;
        f.density_rate = state.fluid_density_rate;
        f.id = state.fluid_id;
        let w = &mut self.walls;
        w.density = state.wall_density;
        w.inverse_density = state.wall_inverse_density;
        w.pressure = state.wall_pressure;
        w.nearest_fluid = state.wall_nearest_fluid;
        self.buffers.density_start = state.density_start;
        self.buffers.wall_velocity = state.wall_velocity;
        // The search and the lists follow the restored positions before the next step
        // reads them; at step 0 the state is that of `new` and the lists are its own.
        if self.step > 0 {
            self.rebuild_search();
        }
        self.upload_to_device()
    }
}
