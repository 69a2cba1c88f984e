//! The time loop: every run of slosh, whatever its front end, advances the solver here.

use crate::motion::{to_vector, GroundMotion, MotionError};
use slosh_core::{SimError, Simulation, TankRotation};
use std::error::Error;

/// How far to advance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Until {
    /// Step while the simulation time is below this time (s).
    Time(f64),
    /// Take this many steps.
    Steps(u64),
}

/// The error of an observer or a step hook (a file that could not be written, a measurement
/// that failed), with its own message.
pub type HookError = Box<dyn Error + Send + Sync>;

/// Why the time loop stopped before its end.
#[derive(Debug, thiserror::Error)]
pub enum StepError {
    /// The ground motion could not give its acceleration.
    #[error("the ground motion failed at t = {time:.4} s: {error}")]
    Motion {
        /// Simulation time (s).
        time: f64,
        /// The motion's error.
        error: MotionError,
    },
    /// The solver refused the step (non-finite state, a blown-up time step).
    #[error(transparent)]
    Solver(#[from] SimError),
    /// The front end asked the loop to stop (an interrupt signal, for example).
    #[error("stopped on request at t = {time:.4} s")]
    Stopped {
        /// Simulation time (s).
        time: f64,
        /// The code the stop request gave (the signal number for a signal).
        code: i32,
    },
    /// A step hook failed.
    #[error(transparent)]
    Hook(HookError),
}

/// Work done around each step, without allocation of its own in the loop.
pub trait StepHooks<const D: usize> {
    /// Called before each step with the ground acceleration `[x, y, vertical]` (m/s²) that
    /// the step is about to apply.
    fn before_step(&mut self, _sim: &Simulation<D>, _accel: [f64; 3]) -> Result<(), HookError> {
        Ok(())
    }

    /// Called before each step in place of [`Self::before_step`], with the tank's rotation the
    /// step is about to apply as well (`None` when the tank only translates); by default
    /// [`Self::before_step`].
    fn before_step_turning(
        &mut self,
        sim: &Simulation<D>,
        accel: [f64; 3],
        _rotation: Option<&TankRotation>,
    ) -> Result<(), HookError> {
        self.before_step(sim, accel)
    }

    /// Called after each step.
    fn after_step(&mut self, _sim: &Simulation<D>) -> Result<(), HookError> {
        Ok(())
    }

    /// Whether the coming call of [`Self::before_step`] (`before` = true) or
    /// [`Self::after_step`] (`before` = false) reads the fluid particles, so that the loop
    /// makes the host's arrays current first ([`Simulation::sync_host`]: a copy from the
    /// device when one runs the step, nothing on the CPU). By default every call reads them.
    fn reads_particles(&mut self, _sim: &Simulation<D>, _before: bool) -> bool {
        true
    }
}

/// No work around the steps.
impl<const D: usize> StepHooks<D> for () {
    fn reads_particles(&mut self, _sim: &Simulation<D>, _before: bool) -> bool {
        false
    }
}

/// Where a step hook is called: before a step, with the ground acceleration `[x, y,
/// vertical]` (m/s²) it is about to apply, or after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepPhase {
    /// Before the step.
    Before([f64; 3]),
    /// After the step.
    After,
}

/// A closure called before and after each step is a step hook.
pub struct EachStep<F>(pub F);

impl<const D: usize, F: FnMut(StepPhase, &Simulation<D>) -> Result<(), HookError>> StepHooks<D>
    for EachStep<F>
{
    fn before_step(&mut self, sim: &Simulation<D>, accel: [f64; 3]) -> Result<(), HookError> {
        (self.0)(StepPhase::Before(accel), sim)
    }

    fn after_step(&mut self, sim: &Simulation<D>) -> Result<(), HookError> {
        (self.0)(StepPhase::After, sim)
    }
}

/// A closure called after each step is a step hook.
pub struct AfterEachStep<F>(pub F);

impl<const D: usize, F: FnMut(&Simulation<D>) -> Result<(), HookError>> StepHooks<D>
    for AfterEachStep<F>
{
    fn after_step(&mut self, sim: &Simulation<D>) -> Result<(), HookError> {
        (self.0)(sim)
    }
}

/// Asked after every step whether the front end wants the run to stop; `Some(code)` stops it
/// (the code, a signal number for example, comes back in [`StepError::Stopped`]).
pub trait StopRequest {
    /// The stop code when a stop was asked for.
    fn stop_requested(&mut self) -> Option<i32>;
}

/// Never stops.
impl StopRequest for () {
    fn stop_requested(&mut self) -> Option<i32> {
        None
    }
}

/// A closure is a stop request.
impl<F: FnMut() -> Option<i32>> StopRequest for F {
    fn stop_requested(&mut self) -> Option<i32> {
        self()
    }
}

/// Advances `sim` under `motion` until `until`: each step asks the motion for the ground
/// acceleration at the current time, calls `hooks.before_step`, steps, calls
/// `hooks.after_step`, then checks `stop` (so that a stopped run has measured its last step
/// as one that goes on does). The state reached stays in `sim` when an error ends the loop.
pub fn advance<const D: usize, M, H, S>(
    sim: &mut Simulation<D>,
    motion: &mut M,
    until: Until,
    hooks: &mut H,
    stop: &mut S,
) -> Result<(), StepError>
where
    M: GroundMotion + ?Sized,
    H: StepHooks<D> + ?Sized,
    S: StopRequest + ?Sized,
{
    let result = advance_steps(sim, motion, until, hooks, stop);
    // The loop leaves the host's particle arrays current whatever ended it (a device that
    // ran the steps copies them back once here).
    let synced = sim.sync_host();
    result?;
    synced?;
    Ok(())
}

/// The loop of [`advance`].
fn advance_steps<const D: usize, M, H, S>(
    sim: &mut Simulation<D>,
    motion: &mut M,
    until: Until,
    hooks: &mut H,
    stop: &mut S,
) -> Result<(), StepError>
where
    M: GroundMotion + ?Sized,
    H: StepHooks<D> + ?Sized,
    S: StopRequest + ?Sized,
{
    let first_step = sim.steps();
    loop {
        let more = match until {
            Until::Time(end) => sim.time() < end,
            Until::Steps(n) => sim.steps() - first_step < n,
        };
        if !more {
            return Ok(());
        }
        let t = sim.time();
        let accel = motion
            .ground_accel(t)
            .map_err(|error| StepError::Motion { time: t, error })?;
        let rotation = motion
            .ground_rotation(t)
            .map_err(|error| StepError::Motion { time: t, error })?;
        if hooks.reads_particles(sim, true) {
            sim.sync_host()?;
        }
        hooks
            .before_step_turning(sim, accel, rotation.as_ref())
            .map_err(StepError::Hook)?;
        sim.step_turning(to_vector::<D>(accel), rotation.as_ref())?;
        // The step's measurements are complete before a stop: a run stopped here and
        // continued from its state takes the same measurements as one that goes on.
        if hooks.reads_particles(sim, false) {
            sim.sync_host()?;
        }
        hooks.after_step(sim).map_err(StepError::Hook)?;
        if let Some(code) = stop.stop_requested() {
            return Err(StepError::Stopped {
                time: sim.time(),
                code,
            });
        }
    }
}

/// [`advance`] with a closure called after each step, no stop request: the form the
/// measurement loops of the validation suite use.
pub fn advance_with<const D: usize, M, F>(
    sim: &mut Simulation<D>,
    motion: &mut M,
    until: Until,
    after_step: F,
) -> Result<(), StepError>
where
    M: GroundMotion + ?Sized,
    F: FnMut(&Simulation<D>) -> Result<(), HookError>,
{
    advance(sim, motion, until, &mut AfterEachStep(after_step), &mut ())
}
