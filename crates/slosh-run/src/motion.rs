//! Ground motions: the ground acceleration a_g(t) that acts on the liquid as the body force
//! −a_g(t) in the tank frame (`docs/ground-motion.md`, *Sign conventions*).

use slosh_core::TankRotation;
use std::error::Error;

/// The error of a ground motion that could not give its acceleration (a script function that
/// failed, for example), with the motion's own message.
pub type MotionError = Box<dyn Error + Send + Sync>;

/// The ground acceleration as a function of time, asked once per time step.
///
/// The components are `[x, y, vertical]` (m/s²): the vertical is the last one, as everywhere
/// in slosh; a 2D case uses `x` and the vertical.
pub trait GroundMotion {
    /// Ground acceleration `[a_x, a_y, a_z]` (m/s²) at time `t` (s), in the world frame.
    fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], MotionError>;

    /// The tank's rotation about its pivot at time `t` (s) (angle, rate and angular
    /// acceleration: `slosh_core::frame`); `None` when the ground only translates the tank,
    /// the default.
    fn ground_rotation(&mut self, _t: f64) -> Result<Option<TankRotation>, MotionError> {
        Ok(None)
    }
}

/// Any closure `t → [a_x, a_y, a_z]` is a ground motion.
impl<F: FnMut(f64) -> [f64; 3]> GroundMotion for F {
    fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], MotionError> {
        Ok(self(t))
    }
}

/// A three-component excitation of `slosh-motion` (sines, records and their sums).
impl GroundMotion for slosh_motion::Motion {
    fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], MotionError> {
        Ok(self.at(t))
    }
}

/// No ground motion: the tank stands still.
#[derive(Clone, Copy, Debug, Default)]
pub struct AtRest;

impl GroundMotion for AtRest {
    fn ground_accel(&mut self, _t: f64) -> Result<[f64; 3], MotionError> {
        Ok([0.0; 3])
    }
}

/// A ground motion that starts after a settling time: zero before `settle`, then `motion`
/// at the time since the excitation started (`t − settle`), the convention of the case
/// scripts (a time within 1e-9 s before `settle` counts as the start).
pub struct AfterSettling<'m, M: ?Sized> {
    /// Settling time (s).
    settle: f64,
    /// The motion, in time since the excitation started.
    motion: &'m mut M,
    /// The rotation held during settling, asked of the motion once.
    rest: Option<Option<TankRotation>>,
}

impl<'m, M: GroundMotion + ?Sized> AfterSettling<'m, M> {
    /// `motion` started after `settle` seconds.
    pub fn new(settle: f64, motion: &'m mut M) -> Self {
        AfterSettling {
            settle,
            motion,
            rest: None,
        }
    }
}

/// Tolerance (s) of the time comparisons of a case run.
pub(crate) const TIME_EPS: f64 = 1e-9;

impl<M: GroundMotion + ?Sized> GroundMotion for AfterSettling<'_, M> {
    fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], MotionError> {
        if t >= self.settle - TIME_EPS {
            self.motion.ground_accel(t - self.settle)
        } else {
            Ok([0.0; 3])
        }
    }

    /// The motion's rotation after settling; before it, the rotation of the excitation's start
    /// held still (its angle, no rate).
    fn ground_rotation(&mut self, t: f64) -> Result<Option<TankRotation>, MotionError> {
        if t >= self.settle - TIME_EPS {
            self.motion.ground_rotation(t - self.settle)
        } else {
            if self.rest.is_none() {
                self.rest = Some(self.motion.ground_rotation(0.0)?.map(|r| TankRotation {
                    rate: 0.0,
                    acceleration: 0.0,
                    ..r
                }));
            }
            Ok(self.rest.flatten())
        }
    }
}

/// The `[x, y, vertical]` acceleration as the solver's vector: in 2D `(x, vertical)`.
pub fn to_vector<const D: usize>(accel: [f64; 3]) -> slosh_core::Vector<D> {
    let mut ground = slosh_core::Vector::<D>::zeros();
    if D == 2 {
        ground[0] = accel[0];
        ground[1] = accel[2];
    } else {
        for (k, a) in accel.iter().enumerate().take(D) {
            ground[k] = *a;
        }
    }
    ground
}
