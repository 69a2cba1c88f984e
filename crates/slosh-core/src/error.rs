//! Errors of the solver: bad set-up and runs that blow up.

use thiserror::Error;

/// Why a simulation could not be set up or could not go on.
#[derive(Debug, Error)]
pub enum SimError {
    /// The setup or a parameter is unusable.
    #[error("invalid simulation setup: {0}")]
    InvalidSetup(String),
    /// A fixed time step above the stability bound.
    #[error(
        "the fixed time step dt = {dt:.3e} s is above the stability bound {bound:.3e} s \
         (C·h/c0 with C = {cfl}, h = {h:.4} m, c0 = {c0:.2} m/s); use a variable time step \
         (dt = 0), a smaller dt, or set allow_unstable_dt = true to run it anyway"
    )]
    DtAboveBound {
        /// The requested time step (s).
        dt: f64,
        /// The bound (s).
        bound: f64,
        /// The Courant number.
        cfl: f64,
        /// Smoothing length (m).
        h: f64,
        /// EOS sound speed (m/s).
        c0: f64,
    },
    /// An explicitly chosen EOS stiffness that squeezes the still liquid by more than 3 %.
    #[error(
        "the EOS is too soft for this tank: the still liquid would be compressed by \
         {percent:.1} % of its depth under its own weight (c0 = {sound_speed:.1} m/s, \
         B = {eos_stiffness:.4e} Pa), which turns sloshing into an acoustic oscillation; \
         remove eos_b / sound_speed to let the sound speed follow the tank (10 √(g H_ref) = \
         {suggested_sound_speed:.1} m/s here), or set allow_compressible = true to run it anyway"
    )]
    TooCompressible {
        /// Compression of the still liquid (% of its depth).
        percent: f64,
        /// EOS sound speed (m/s).
        sound_speed: f64,
        /// Tait stiffness B (Pa).
        eos_stiffness: f64,
        /// The sound speed of the default rule (m/s).
        suggested_sound_speed: f64,
    },
    /// A non-finite value appeared.
    #[error(
        "the simulation blew up at t = {time:.4} s (step {step}): {count} fluid particle(s) \
         have a non-finite position or velocity; reduce the time step (cfl_number) or check \
         the excitation"
    )]
    NonFinite {
        /// Simulated time (s).
        time: f64,
        /// Step number.
        step: u64,
        /// Number of bad particles.
        count: usize,
    },
    /// Particles left the computational domain around the tank.
    #[error(
        "the simulation blew up at t = {time:.4} s (step {step}): {count} fluid particle(s) \
         left the domain around the tank (first at {position}); the flow is too violent for \
         this resolution/time step, or the wall lets particles through (check dx and h/dx)"
    )]
    LeftDomain {
        /// Simulated time (s).
        time: f64,
        /// Step number.
        step: u64,
        /// Number of particles outside.
        count: usize,
        /// Where the first one is (m), formatted.
        position: String,
    },
    /// The body force given for a step is not finite.
    #[error("the ground acceleration at t = {time:.4} s is not finite ({value}); check the excitation function")]
    BadExcitation {
        /// Simulated time (s).
        time: f64,
        /// The offending value, formatted.
        value: String,
    },
}
