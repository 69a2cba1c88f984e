//! Excitations: sines, sums of sines, records, and their sums, combined into a
//! three-component ground motion.

use crate::record::Record;
use serde::{Deserialize, Serialize};

/// A harmonic ground motion in the paper's convention: ground displacement
/// `A sin(ω t + phase)`, hence ground acceleration `−A ω² sin(ω t + phase)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sine {
    /// Displacement amplitude A, m.
    pub amplitude_m: f64,
    /// Angular frequency ω, rad/s.
    pub omega_rad_s: f64,
    /// Phase, rad.
    pub phase: f64,
}

impl Sine {
    /// A sine of displacement amplitude `amplitude_m` (m), angular frequency `omega_rad_s`
    /// (rad/s) and phase 0.
    pub fn new(amplitude_m: f64, omega_rad_s: f64) -> Self {
        Sine {
            amplitude_m,
            omega_rad_s,
            phase: 0.0,
        }
    }

    /// Ground displacement at `t_s`, m: A sin(ω t + phase).
    pub fn displacement_m(&self, t_s: f64) -> f64 {
        self.amplitude_m * (self.omega_rad_s * t_s + self.phase).sin()
    }

    /// Ground velocity at `t_s`, m/s: A ω cos(ω t + phase).
    pub fn velocity_m_s(&self, t_s: f64) -> f64 {
        self.amplitude_m * self.omega_rad_s * (self.omega_rad_s * t_s + self.phase).cos()
    }

    /// Ground acceleration at `t_s`, m/s²: −A ω² sin(ω t + phase).
    pub fn accel_m_s2(&self, t_s: f64) -> f64 {
        -self.amplitude_m
            * self.omega_rad_s
            * self.omega_rad_s
            * (self.omega_rad_s * t_s + self.phase).sin()
    }

    /// Peak ground acceleration A ω², m/s².
    pub fn peak_accel_m_s2(&self) -> f64 {
        (self.amplitude_m * self.omega_rad_s * self.omega_rad_s).abs()
    }
}

/// One component of ground acceleration as a function of time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub enum Excitation {
    /// No motion (0 m/s² at all times).
    #[default]
    Zero,
    /// A recorded motion (linear between samples, 0 outside the record).
    Record(Box<Record>),
    /// One sine (see [`Sine`]).
    Sine(Sine),
    /// A sum of sines.
    SineSum(Vec<Sine>),
    /// A sum of excitations.
    Sum(Vec<Excitation>),
}

impl Excitation {
    /// Ground acceleration at `t_s`, m/s².
    pub fn at(&self, t_s: f64) -> f64 {
        match self {
            Excitation::Zero => 0.0,
            Excitation::Record(r) => r.at(t_s),
            Excitation::Sine(s) => s.accel_m_s2(t_s),
            Excitation::SineSum(sines) => sines.iter().map(|s| s.accel_m_s2(t_s)).sum(),
            Excitation::Sum(parts) => parts.iter().map(|e| e.at(t_s)).sum(),
        }
    }

    /// Time after which the excitation is 0, s: the latest record end; `None` when a sine is
    /// involved (never ends) and `Some(0.0)` for [`Excitation::Zero`].
    pub fn end_time_s(&self) -> Option<f64> {
        match self {
            Excitation::Zero => Some(0.0),
            Excitation::Record(r) => Some(r.end_time_s()),
            Excitation::Sine(_) | Excitation::SineSum(_) => None,
            Excitation::Sum(parts) => parts
                .iter()
                .try_fold(0.0_f64, |m, e| e.end_time_s().map(|t| m.max(t))),
        }
    }

    /// The processing logs of the records involved (empty for sines).
    pub fn processing_logs(&self) -> Vec<String> {
        match self {
            Excitation::Record(r) => r.processing_log.clone(),
            Excitation::Sum(parts) => parts.iter().flat_map(|e| e.processing_logs()).collect(),
            _ => Vec::new(),
        }
    }
}

impl From<Record> for Excitation {
    fn from(r: Record) -> Self {
        Excitation::Record(Box::new(r))
    }
}

impl From<Sine> for Excitation {
    fn from(s: Sine) -> Self {
        Excitation::Sine(s)
    }
}

impl From<Vec<Sine>> for Excitation {
    fn from(s: Vec<Sine>) -> Self {
        Excitation::SineSum(s)
    }
}

/// Ground acceleration in up to three components: `x` and `y` horizontal, `z` vertical
/// (the vertical is the last coordinate, as everywhere in slosh; a 2D case uses `x` and `z`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Motion {
    /// Horizontal x component.
    pub x: Excitation,
    /// Horizontal y component.
    pub y: Excitation,
    /// Vertical z component (positive up).
    pub z: Excitation,
}

impl Motion {
    /// A motion along x only.
    pub fn along_x(e: impl Into<Excitation>) -> Self {
        Motion {
            x: e.into(),
            ..Default::default()
        }
    }

    /// Replaces the x component.
    pub fn with_x(mut self, e: impl Into<Excitation>) -> Self {
        self.x = e.into();
        self
    }

    /// Replaces the y component.
    pub fn with_y(mut self, e: impl Into<Excitation>) -> Self {
        self.y = e.into();
        self
    }

    /// Replaces the z (vertical) component.
    pub fn with_z(mut self, e: impl Into<Excitation>) -> Self {
        self.z = e.into();
        self
    }

    /// Ground acceleration `[a_x, a_y, a_z]` at `t_s`, m/s².
    pub fn at(&self, t_s: f64) -> [f64; 3] {
        [self.x.at(t_s), self.y.at(t_s), self.z.at(t_s)]
    }

    /// Time after which every component is 0, s; `None` when a sine is involved.
    pub fn end_time_s(&self) -> Option<f64> {
        let ends = [
            self.x.end_time_s()?,
            self.y.end_time_s()?,
            self.z.end_time_s()?,
        ];
        Some(ends.into_iter().fold(0.0, f64::max))
    }
}
