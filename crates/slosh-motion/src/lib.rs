//! Ground-motion input for slosh: the ground acceleration a tank is shaken with.
//!
//! * [`Record`]: a recorded ground acceleration (uniform samples, m/s²) read by
//!   [`read_at2`] (PEER NGA), [`read_knet`] (K-NET / KiK-net ASCII), [`read_plain_text`]
//!   (CSV / columns) or [`read_record`] (detects the format), with processing steps (scaling,
//!   baseline correction, zero-phase Butterworth filtering, trimming, shifting) logged in
//!   [`Record::processing_log`].
//! * [`Sine`], [`Excitation`], [`Motion`]: analytic and recorded excitations, up to three
//!   components, evaluated at any time.
//! * [`RotationRecord`]: a recorded rotation of the tank (angle, rate, angular acceleration)
//!   read by [`read_rotation`], interpolated twice continuously differentiable.
//! * [`response_spectrum`]: pseudo-acceleration spectrum by the exact piecewise-linear
//!   (Nigam–Jennings) solution of the damped oscillator.
//!
//! Units are SI throughout (s, m, m/s²) unless a name says otherwise. Records in g are
//! converted with [`GRAVITY_M_S2`] = 9.81 m/s², the g used throughout slosh.
//!
//! ```
//! use slosh_motion::{Motion, Record, Sine};
//! let mut rec = Record::from_samples(0.01, vec![0.0, 1.0, -2.0, 0.5, 0.0])?;
//! rec.scale_to_pga(3.0)?.shift(2.0); // m/s², then start 2 s later (after settling)
//! let motion = Motion::along_x(rec).with_z(Sine::new(0.005, 6.0));
//! let [ax, _ay, az] = motion.at(2.015);
//! assert!((ax + 0.75).abs() < 1e-12); // samples ×1.5: halfway between 1.5 and −3.0
//! assert!(az.abs() <= 0.005 * 36.0);
//! # Ok::<(), slosh_motion::MotionError>(())
//! ```

#![warn(missing_docs)]

pub mod error;
pub mod filter;
pub mod motion;
pub mod readers;
pub mod record;
pub mod rotation;
pub mod spectrum;

pub use error::{MotionError, Result};
pub use motion::{Excitation, Motion, Sine};
pub use readers::{
    parse_at2, parse_knet, parse_plain_text, read_at2, read_knet, read_plain_text, read_record,
    sha256_hex, PlainTextOptions,
};
pub use record::{AccelUnit, Record, RecordFormat, RecordMeta, GRAVITY_M_S2};
pub use rotation::{parse_rotation, read_rotation, AngleUnit, RotationRecord};
pub use spectrum::{
    default_periods_s, log_spaced_periods, response_spectrum, sdof_displacement_history,
    sdof_history, ResponseSpectrum, DEFAULT_DAMPING_RATIO,
};
