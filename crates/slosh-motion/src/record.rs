//! A recorded ground-acceleration time history with uniform sampling, its metadata, and the
//! processing steps (scaling, baseline correction, filtering, trimming, shifting).

use crate::error::{MotionError, Result};
use crate::filter;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The acceleration of gravity slosh uses everywhere, g = 9.81 m/s² (the solver's default,
/// the closed-form references, the data notes); records in g are converted with it.
pub const GRAVITY_M_S2: f64 = 9.81;

/// Acceleration units a record file can be written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum AccelUnit {
    /// Multiples of g (1 g = [`GRAVITY_M_S2`] = 9.81 m/s²).
    G,
    /// Gal = cm/s² (1 gal = 0.01 m/s²).
    Gal,
    /// m/s².
    MetersPerSecondSquared,
}

impl AccelUnit {
    /// Factor that converts a value in this unit to m/s².
    pub fn to_m_s2(self) -> f64 {
        match self {
            AccelUnit::G => GRAVITY_M_S2,
            AccelUnit::Gal => 0.01,
            AccelUnit::MetersPerSecondSquared => 1.0,
        }
    }
}

impl fmt::Display for AccelUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AccelUnit::G => "g",
            AccelUnit::Gal => "gal",
            AccelUnit::MetersPerSecondSquared => "m/s2",
        })
    }
}

impl FromStr for AccelUnit {
    type Err = MotionError;
    /// Accepts `g`, `gal`, `cm/s2`, `cm/s^2`, `m/s2`, `m/s^2`, `mps2` (case-insensitive).
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().replace('²', "2").as_str() {
            "g" => Ok(AccelUnit::G),
            "gal" | "cm/s2" | "cm/s^2" | "cm/s/s" => Ok(AccelUnit::Gal),
            "m/s2" | "m/s^2" | "m/s/s" | "mps2" => Ok(AccelUnit::MetersPerSecondSquared),
            other => Err(MotionError::InvalidArgument(format!(
                "unknown acceleration unit `{other}`; use `g`, `gal` (cm/s2) or `m/s2`"
            ))),
        }
    }
}

/// The file layout a record was read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RecordFormat {
    /// PEER NGA `.AT2` (4 header lines, values in g).
    PeerAt2,
    /// K-NET / KiK-net ASCII (17 header lines, integer counts with a scale factor).
    KnetAscii,
    /// Plain text: CSV or whitespace columns (time, accel) or one accel column.
    PlainText,
    /// Built in memory (no file).
    InMemory,
}

impl fmt::Display for RecordFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RecordFormat::PeerAt2 => "PEER AT2",
            RecordFormat::KnetAscii => "K-NET ASCII",
            RecordFormat::PlainText => "plain text",
            RecordFormat::InMemory => "in memory",
        })
    }
}

/// Where a record came from, as read (before any processing).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordMeta {
    /// The source file as given by the caller (`<memory>` when built in memory).
    pub source_file: String,
    /// The file layout.
    pub format: RecordFormat,
    /// The units the file's values were in (converted to m/s² on reading).
    pub original_units: AccelUnit,
    /// Number of samples in the file (before any resampling or trimming).
    pub original_npts: usize,
    /// Sample interval in the file, s (for non-uniform plain text: the smallest step).
    pub original_dt_s: f64,
    /// Station code when the format gives one (K-NET `Station Code`), else empty.
    pub station: String,
    /// The header text of the file (header lines joined by newlines).
    pub header: String,
    /// SHA-256 of the file's bytes, lowercase hex (empty when built in memory).
    pub sha256_hex: String,
}

/// A ground-acceleration time history: uniform samples `accel_m_s2[i]` at time
/// `start_time_s + i·dt_s`, plus where it came from and what was done to it.
///
/// Readers return records starting at time 0; [`Record::shift`] moves the start.
/// Between samples the record is linear; outside it, the acceleration is 0 (see [`Record::at`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// Sample interval, s.
    pub dt_s: f64,
    /// Time of the first sample, s.
    pub start_time_s: f64,
    /// Ground acceleration samples, m/s².
    pub accel_m_s2: Vec<f64>,
    /// Source metadata.
    pub meta: RecordMeta,
    /// Every operation applied since creation (reading included), in order, human-readable.
    pub processing_log: Vec<String>,
    /// What the reader found suspicious but not fatal (e.g. a header's stated duration that
    /// the data does not fill), one sentence each, for the user to see.
    #[serde(default)]
    pub warnings: Vec<String>,
}

impl Record {
    /// Builds a record from samples in m/s² at interval `dt_s`, starting at time 0.
    pub fn from_samples(dt_s: f64, accel_m_s2: Vec<f64>) -> Result<Self> {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(MotionError::InvalidArgument(format!(
                "the sample interval must be a positive number of seconds, got {dt_s}"
            )));
        }
        let n = accel_m_s2.len();
        Ok(Record {
            dt_s,
            start_time_s: 0.0,
            accel_m_s2,
            meta: RecordMeta {
                source_file: "<memory>".into(),
                format: RecordFormat::InMemory,
                original_units: AccelUnit::MetersPerSecondSquared,
                original_npts: n,
                original_dt_s: dt_s,
                station: String::new(),
                header: String::new(),
                sha256_hex: String::new(),
            },
            processing_log: vec![format!("from samples ({n} samples, dt {dt_s} s)")],
            warnings: Vec::new(),
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.accel_m_s2.len()
    }

    /// True when the record has no samples.
    pub fn is_empty(&self) -> bool {
        self.accel_m_s2.is_empty()
    }

    /// Time of sample `i`, s.
    pub fn time_s(&self, i: usize) -> f64 {
        self.start_time_s + i as f64 * self.dt_s
    }

    /// Time of the last sample, s (equals `start_time_s` for an empty or one-sample record).
    pub fn end_time_s(&self) -> f64 {
        self.start_time_s + self.len().saturating_sub(1) as f64 * self.dt_s
    }

    /// Length of the record, s: `(len − 1)·dt`.
    pub fn duration_s(&self) -> f64 {
        self.len().saturating_sub(1) as f64 * self.dt_s
    }

    /// Ground acceleration at time `t_s`, m/s²: linear interpolation between samples, 0 before
    /// the first and after the last sample.
    pub fn at(&self, t_s: f64) -> f64 {
        let n = self.len();
        if n == 0 || !t_s.is_finite() {
            return 0.0;
        }
        let x = (t_s - self.start_time_s) / self.dt_s;
        // Tolerate rounding right at the ends so that at(end_time_s()) returns the last sample.
        let eps = 1e-9;
        if x < -eps || x > (n - 1) as f64 + eps {
            return 0.0;
        }
        let x = x.clamp(0.0, (n - 1) as f64);
        let i = (x.floor() as usize).min(n - 1);
        if i + 1 >= n {
            return self.accel_m_s2[n - 1];
        }
        let w = x - i as f64;
        self.accel_m_s2[i] * (1.0 - w) + self.accel_m_s2[i + 1] * w
    }

    /// Peak ground acceleration (largest absolute sample), m/s².
    pub fn pga_m_s2(&self) -> f64 {
        self.accel_m_s2.iter().fold(0.0_f64, |m, a| m.max(a.abs()))
    }

    /// The sample with the largest absolute value: (time s, signed value m/s²); `None` when empty.
    pub fn peak(&self) -> Option<(f64, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, &a) in self.accel_m_s2.iter().enumerate() {
            if best.is_none_or(|(_, b)| a.abs() > b.abs()) {
                best = Some((i, a));
            }
        }
        best.map(|(i, a)| (self.time_s(i), a))
    }

    /// Multiplies every sample by `factor`.
    pub fn scale(&mut self, factor: f64) -> &mut Self {
        for a in &mut self.accel_m_s2 {
            *a *= factor;
        }
        self.processing_log.push(format!("scale by {factor}"));
        self
    }

    /// Scales the record so that its PGA equals `target_pga_m_s2` (m/s²).
    ///
    /// Errors when the target is negative or not finite, or the record is all zeros.
    pub fn scale_to_pga(&mut self, target_pga_m_s2: f64) -> Result<&mut Self> {
        if !(target_pga_m_s2.is_finite() && target_pga_m_s2 >= 0.0) {
            return Err(MotionError::InvalidArgument(format!(
                "target PGA must be a non-negative number of m/s2, got {target_pga_m_s2}"
            )));
        }
        let pga = self.pga_m_s2();
        if pga == 0.0 {
            return Err(MotionError::InvalidArgument(format!(
                "cannot scale record `{}` to a PGA: all its samples are zero",
                self.meta.source_file
            )));
        }
        let factor = target_pga_m_s2 / pga;
        for a in &mut self.accel_m_s2 {
            *a *= factor;
        }
        self.processing_log.push(format!(
            "scale_to_pga {target_pga_m_s2} m/s2 (factor {factor:.6}, PGA was {pga:.6} m/s2)"
        ));
        Ok(self)
    }

    /// Baseline correction: subtracts the mean of the samples.
    pub fn remove_mean(&mut self) -> &mut Self {
        let n = self.len();
        if n > 0 {
            let mean = self.accel_m_s2.iter().sum::<f64>() / n as f64;
            for a in &mut self.accel_m_s2 {
                *a -= mean;
            }
            self.processing_log
                .push(format!("remove_mean (mean was {mean:.6e} m/s2)"));
        }
        self
    }

    /// Baseline correction: subtracts the least-squares straight line in time.
    pub fn detrend_linear(&mut self) -> &mut Self {
        self.detrend_polynomial(1)
            .expect("order 1 is always a valid detrend order");
        self
    }

    /// Baseline correction: subtracts the least-squares polynomial in time of degree `order`
    /// (0 ≤ order ≤ 3; 0 is mean removal). The fit uses time mapped to [−1, 1] for conditioning.
    pub fn detrend_polynomial(&mut self, order: usize) -> Result<&mut Self> {
        if order > 3 {
            return Err(MotionError::InvalidArgument(format!(
                "polynomial detrend order must be 0..=3, got {order}"
            )));
        }
        let n = self.len();
        if n <= order {
            // Too few samples to fit: the fitted polynomial passes through them all.
            for a in &mut self.accel_m_s2 {
                *a = 0.0;
            }
            self.processing_log.push(format!(
                "detrend_polynomial order {order} (record too short: zeroed)"
            ));
            return Ok(self);
        }
        let m = order + 1;
        let x_of = |i: usize| {
            if n == 1 {
                0.0
            } else {
                2.0 * i as f64 / (n - 1) as f64 - 1.0
            }
        };
        // Normal equations (Vᵀ V) c = Vᵀ y with V the Vandermonde matrix in x.
        let mut ata = [[0.0_f64; 4]; 4];
        let mut aty = [0.0_f64; 4];
        for (i, &y) in self.accel_m_s2.iter().enumerate() {
            let x = x_of(i);
            let mut pow = [1.0_f64; 4];
            for k in 1..m {
                pow[k] = pow[k - 1] * x;
            }
            for r in 0..m {
                aty[r] += pow[r] * y;
                for c in 0..m {
                    ata[r][c] += pow[r] * pow[c];
                }
            }
        }
        let coef = solve_small(ata, aty, m);
        for (i, a) in self.accel_m_s2.iter_mut().enumerate() {
            let x = x_of(i);
            let mut p = 0.0;
            for k in (0..m).rev() {
                p = p * x + coef[k];
            }
            *a -= p;
        }
        let what = match order {
            0 => "mean",
            1 => "linear",
            2 => "quadratic",
            _ => "cubic",
        };
        self.processing_log.push(format!(
            "detrend_polynomial order {order} ({what} least-squares fit removed)"
        ));
        Ok(self)
    }

    /// Zero-phase band-pass filter: a 4th-order Butterworth high-pass at `low_hz` cascaded with
    /// a 4th-order Butterworth low-pass at `high_hz`, run forward and backward (see
    /// [`crate::filter`]). Requires 0 < low_hz < high_hz < Nyquist (0.5/dt).
    pub fn bandpass(&mut self, low_hz: f64, high_hz: f64) -> Result<&mut Self> {
        let nyquist = 0.5 / self.dt_s;
        if !(low_hz > 0.0 && low_hz < high_hz && high_hz < nyquist) {
            return Err(MotionError::InvalidArgument(format!(
                "band-pass corners must satisfy 0 < low < high < Nyquist ({nyquist} Hz), got low {low_hz} Hz, high {high_hz} Hz"
            )));
        }
        self.accel_m_s2 = filter::butterworth_zero_phase(
            &self.accel_m_s2,
            self.dt_s,
            Some(low_hz),
            Some(high_hz),
        );
        self.processing_log.push(format!(
            "bandpass {low_hz}-{high_hz} Hz (4th-order Butterworth, zero phase)"
        ));
        Ok(self)
    }

    /// Zero-phase 4th-order Butterworth high-pass at `corner_hz` (0 < corner < Nyquist).
    pub fn highpass(&mut self, corner_hz: f64) -> Result<&mut Self> {
        let nyquist = 0.5 / self.dt_s;
        if !(corner_hz > 0.0 && corner_hz < nyquist) {
            return Err(MotionError::InvalidArgument(format!(
                "high-pass corner must satisfy 0 < corner < Nyquist ({nyquist} Hz), got {corner_hz} Hz"
            )));
        }
        self.accel_m_s2 =
            filter::butterworth_zero_phase(&self.accel_m_s2, self.dt_s, Some(corner_hz), None);
        self.processing_log.push(format!(
            "highpass {corner_hz} Hz (4th-order Butterworth, zero phase)"
        ));
        Ok(self)
    }

    /// Zero-phase 4th-order Butterworth low-pass at `corner_hz` (0 < corner < Nyquist).
    pub fn lowpass(&mut self, corner_hz: f64) -> Result<&mut Self> {
        let nyquist = 0.5 / self.dt_s;
        if !(corner_hz > 0.0 && corner_hz < nyquist) {
            return Err(MotionError::InvalidArgument(format!(
                "low-pass corner must satisfy 0 < corner < Nyquist ({nyquist} Hz), got {corner_hz} Hz"
            )));
        }
        self.accel_m_s2 =
            filter::butterworth_zero_phase(&self.accel_m_s2, self.dt_s, None, Some(corner_hz));
        self.processing_log.push(format!(
            "lowpass {corner_hz} Hz (4th-order Butterworth, zero phase)"
        ));
        Ok(self)
    }

    /// Keeps the samples with time in [`t_from_s`, `t_to_s`] (record time) and re-zeroes the
    /// time so that the first kept sample is at `start_time_s = 0`.
    pub fn trim(&mut self, t_from_s: f64, t_to_s: f64) -> Result<&mut Self> {
        if !(t_from_s.is_finite() && t_to_s.is_finite() && t_from_s < t_to_s) {
            return Err(MotionError::InvalidArgument(format!(
                "trim window must have start < end, got [{t_from_s}, {t_to_s}] s"
            )));
        }
        let n = self.len();
        let eps = 1e-9;
        let first = ((t_from_s - self.start_time_s) / self.dt_s - eps)
            .ceil()
            .max(0.0) as usize;
        let last_f = ((t_to_s - self.start_time_s) / self.dt_s + eps).floor();
        if n == 0 || last_f < 0.0 || first >= n || (last_f as usize) < first {
            return Err(MotionError::InvalidArgument(format!(
                "trim window [{t_from_s}, {t_to_s}] s holds no sample of record `{}` ({} to {} s)",
                self.meta.source_file,
                self.start_time_s,
                self.end_time_s()
            )));
        }
        let last = (last_f as usize).min(n - 1);
        let t_first = self.time_s(first);
        self.accel_m_s2 = self.accel_m_s2[first..=last].to_vec();
        self.start_time_s = 0.0;
        self.processing_log.push(format!(
            "trim [{t_from_s}, {t_to_s}] s (kept samples {first}..={last}, first kept at {t_first} s, re-zeroed to 0)"
        ));
        Ok(self)
    }

    /// Shifts the record in time: afterwards `at(t + delay_s)` equals the old `at(t)`.
    /// A positive delay makes the motion start later (zero before it).
    pub fn shift(&mut self, delay_s: f64) -> &mut Self {
        self.start_time_s += delay_s;
        self.processing_log.push(format!(
            "shift by {delay_s} s (starts at {} s)",
            self.start_time_s
        ));
        self
    }
}

/// Solves the m×m (m ≤ 4) linear system `a x = b` by Gaussian elimination with partial pivoting.
fn solve_small(mut a: [[f64; 4]; 4], mut b: [f64; 4], m: usize) -> [f64; 4] {
    for col in 0..m {
        let pivot = (col..m)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        a.swap(col, pivot);
        b.swap(col, pivot);
        let d = a[col][col];
        if d == 0.0 {
            continue;
        }
        for row in col + 1..m {
            let f = a[row][col] / d;
            let pivot_row = a[col];
            for (k, x) in a[row].iter_mut().enumerate().take(m).skip(col) {
                *x -= f * pivot_row[k];
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 4];
    for row in (0..m).rev() {
        let mut s = b[row];
        for k in row + 1..m {
            s -= a[row][k] * x[k];
        }
        x[row] = if a[row][row] == 0.0 {
            0.0
        } else {
            s / a[row][row]
        };
    }
    x
}
