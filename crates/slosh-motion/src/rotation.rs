//! Recorded rotation of a tank: the angle about its pivot against time, with its rate and
//! angular acceleration, read from a plain-text table (a shake table's roll or pitch channel,
//! a rocking foundation's rotation, a laboratory experiment's measured motion).
//!
//! Columns: time (s), angle, and optionally its rate and angular acceleration, in `rad` or
//! `deg` (the rate per s, the acceleration per s²). Between samples the angle is the quintic
//! Hermite polynomial that matches angle, rate and acceleration at both ends, so the motion is
//! twice continuously differentiable and the angular acceleration the liquid feels is
//! continuous. A table without rate or acceleration gets them from the samples by central
//! differences (one-sided at the ends). Before the first sample the angle of the first is held
//! at rest; after the last, the last.

use crate::error::{MotionError, Result};
use crate::readers::{numeric_table, read_bytes, sha256_hex, NumericTable};
use std::path::Path;

/// Unit of a rotation table's angles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleUnit {
    /// Radians.
    Radian,
    /// Degrees.
    Degree,
}

impl AngleUnit {
    /// Radians per unit.
    pub fn to_rad(self) -> f64 {
        match self {
            AngleUnit::Radian => 1.0,
            AngleUnit::Degree => std::f64::consts::PI / 180.0,
        }
    }
}

impl std::str::FromStr for AngleUnit {
    type Err = MotionError;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "rad" | "radian" | "radians" => Ok(AngleUnit::Radian),
            "deg" | "degree" | "degrees" => Ok(AngleUnit::Degree),
            other => Err(MotionError::InvalidArgument(format!(
                "unknown angle unit \"{other}\"; use \"rad\" or \"deg\""
            ))),
        }
    }
}

impl std::fmt::Display for AngleUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            AngleUnit::Radian => "rad",
            AngleUnit::Degree => "deg",
        })
    }
}

/// A recorded rotation, in rad, rad/s and rad/s², on the record's own clock (its first sample
/// at time 0).
#[derive(Clone, Debug)]
pub struct RotationRecord {
    time: Vec<f64>,
    angle: Vec<f64>,
    rate: Vec<f64>,
    acceleration: Vec<f64>,
    /// SHA-256 of the file's bytes.
    pub sha256_hex: String,
    /// What the table held and what was derived, one sentence each.
    pub processing_log: Vec<String>,
}

/// Reads a rotation table (see the module docs) with angles in `unit`.
pub fn read_rotation(path: impl AsRef<Path>, unit: AngleUnit) -> Result<RotationRecord> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    parse_rotation(&bytes, &path.display().to_string(), unit)
}

/// [`read_rotation`] from the file's bytes; `source` names it in errors.
pub fn parse_rotation(bytes: &[u8], source: &str, unit: AngleUnit) -> Result<RotationRecord> {
    let text = String::from_utf8_lossy(bytes);
    let NumericTable {
        rows,
        columns,
        last_line,
        ..
    } = numeric_table(
        &text,
        source,
        4,
        "a rotation table has 2 to 4 columns: time (s), angle, and optionally its rate and \
         angular acceleration",
    )?;
    if columns < 2 || rows.len() < 2 {
        return Err(MotionError::ShortData {
            path: source.into(),
            line: last_line,
            message: "a rotation table needs a time and an angle column and at least 2 rows".into(),
        });
    }
    for w in rows.windows(2) {
        if w[1].1[0] <= w[0].1[0] {
            return Err(MotionError::NonMonotonicTime {
                path: source.into(),
                line: w[1].0,
                time_s: w[1].1[0],
                previous_s: w[0].1[0],
            });
        }
    }
    let k = unit.to_rad();
    let t0 = rows[0].1[0];
    let time: Vec<f64> = rows.iter().map(|(_, r)| r[0] - t0).collect();
    let angle: Vec<f64> = rows.iter().map(|(_, r)| r[1] * k).collect();
    let mut log = vec![format!(
        "read rotation table `{source}` ({} rows, {columns} columns, angles in {unit})",
        rows.len()
    )];
    if t0 != 0.0 {
        log.push(format!(
            "time column starts at {t0} s; re-zeroed to start at 0"
        ));
    }
    let rate = if columns >= 3 {
        rows.iter().map(|(_, r)| r[2] * k).collect()
    } else {
        log.push("rate from the angles by central differences".into());
        differences(&time, &angle)
    };
    let acceleration = if columns >= 4 {
        rows.iter().map(|(_, r)| r[3] * k).collect()
    } else {
        log.push("angular acceleration from the rates by central differences".into());
        differences(&time, &rate)
    };
    Ok(RotationRecord {
        time,
        angle,
        rate,
        acceleration,
        sha256_hex: sha256_hex(bytes),
        processing_log: log,
    })
}

/// dy/dt at each sample: central differences inside, one-sided at the ends.
fn differences(t: &[f64], y: &[f64]) -> Vec<f64> {
    let n = t.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            (y[b] - y[a]) / (t[b] - t[a])
        })
        .collect()
}

impl RotationRecord {
    /// The rocking of a tank on a flexible foundation under the ground acceleration `ground`
    /// (the record's samples, linear between): the rocking mode as a single-degree-of-freedom
    /// oscillator of period `period_s` and damping `damping_ratio`,
    /// θ̈ + 2ζω θ̇ + ω² θ = −λ a_g(t), λ = m h / I_θ (1/m: the tank's mass times the height of
    /// its centre of mass over the foundation's rocking inertia, `lever_per_m`), from rest
    /// (Veletsos & Tang 1990, Earthquake Eng. Struct. Dyn. 19, 379–395, with the liquid's
    /// feedback on the foundation left out). Exact at the samples (Nigam–Jennings); the
    /// angular acceleration follows from the equation. A positive ground acceleration (+x)
    /// tilts the tank's top towards −x: a negative angle about y.
    pub fn rocking(
        ground: &crate::Record,
        period_s: f64,
        damping_ratio: f64,
        lever_per_m: f64,
    ) -> Result<RotationRecord> {
        if !(lever_per_m.is_finite() && lever_per_m >= 0.0) {
            return Err(MotionError::InvalidArgument(format!(
                "the rocking lever m h / I_θ must be a number ≥ 0 (1/m), got {lever_per_m}"
            )));
        }
        let a = &ground.accel_m_s2;
        let dt = ground.dt_s;
        if a.len() < 2 {
            return Err(MotionError::InvalidArgument(format!(
                "the record `{}` holds {} sample(s); its rocking needs at least 2",
                ground.meta.source_file,
                a.len()
            )));
        }
        let history = crate::spectrum::sdof_history(a, dt, period_s, damping_ratio)?;
        let omega = 2.0 * std::f64::consts::PI / period_s;
        let start = ground.start_time_s;
        let time = (0..a.len()).map(|k| start + k as f64 * dt).collect();
        let angle = history.iter().map(|(u, _)| lever_per_m * u).collect();
        let rate = history.iter().map(|(_, v)| lever_per_m * v).collect();
        let acceleration = history
            .iter()
            .zip(a)
            .map(|((u, v), ag)| {
                lever_per_m * (-ag - 2.0 * damping_ratio * omega * v - omega * omega * u)
            })
            .collect();
        Ok(RotationRecord {
            time,
            angle,
            rate,
            acceleration,
            sha256_hex: ground.meta.sha256_hex.clone(),
            processing_log: vec![format!(
                "rocking of a foundation of period {period_s} s, damping {damping_ratio}, lever \
                 m h / I_θ = {lever_per_m} 1/m, under the record `{}`",
                ground.meta.source_file
            )],
        })
    }

    /// Samples in the record.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True when the record holds no sample (never, once read).
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Time of the last sample (s).
    pub fn duration_s(&self) -> f64 {
        self.time.last().copied().unwrap_or(0.0)
    }

    /// Largest |angle| (rad).
    pub fn peak_angle_rad(&self) -> f64 {
        self.angle.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// `[angle (rad), rate (rad/s), angular acceleration (rad/s²)]` at `t` (s): the quintic
    /// Hermite interpolant between the samples around `t`; the first sample's angle at rest
    /// before the record, the last's after it.
    pub fn at(&self, t: f64) -> [f64; 3] {
        let n = self.time.len();
        if n < 2 {
            // Never built so (the readers and `rocking` refuse fewer than 2 samples).
            return [self.angle.first().copied().unwrap_or(0.0), 0.0, 0.0];
        }
        if t < self.time[0] {
            return [self.angle[0], 0.0, 0.0];
        }
        if t > self.time[n - 1] {
            return [self.angle[n - 1], 0.0, 0.0];
        }
        let j = self.time.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        let h = self.time[j + 1] - self.time[j];
        let s = (t - self.time[j]) / h;
        quintic_hermite(
            [
                self.angle[j],
                self.rate[j] * h,
                self.acceleration[j] * h * h,
            ],
            [
                self.angle[j + 1],
                self.rate[j + 1] * h,
                self.acceleration[j + 1] * h * h,
            ],
            s,
        )
        .per_second(h)
    }
}

/// Value, first and second derivative in s ∈ [0, 1] of the quintic with value, derivative and
/// second derivative `a` at 0 and `b` at 1 (derivatives per unit s).
fn quintic_hermite(a: [f64; 3], b: [f64; 3], s: f64) -> Scaled {
    let (s2, s3, s4, s5) = (s * s, s * s * s, s.powi(4), s.powi(5));
    // The standard quintic Hermite basis (value, slope, curvature at each end).
    let h0 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
    let h1 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
    let h2 = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5;
    let h3 = 0.5 * s3 - s4 + 0.5 * s5;
    let h4 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
    let h5 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
    let d = |c: [f64; 6]| {
        c[0] * a[0] + c[1] * a[1] + c[2] * a[2] + c[3] * b[2] + c[4] * b[1] + c[5] * b[0]
    };
    let value = d([h0, h1, h2, h3, h4, h5]);
    let first = d([
        -30.0 * s2 + 60.0 * s3 - 30.0 * s4,
        1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4,
        s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4,
        1.5 * s2 - 4.0 * s3 + 2.5 * s4,
        -12.0 * s2 + 28.0 * s3 - 15.0 * s4,
        30.0 * s2 - 60.0 * s3 + 30.0 * s4,
    ]);
    let second = d([
        -60.0 * s + 180.0 * s2 - 120.0 * s3,
        -36.0 * s + 96.0 * s2 - 60.0 * s3,
        1.0 - 9.0 * s + 18.0 * s2 - 10.0 * s3,
        3.0 * s - 12.0 * s2 + 10.0 * s3,
        -24.0 * s + 84.0 * s2 - 60.0 * s3,
        60.0 * s - 180.0 * s2 + 120.0 * s3,
    ]);
    Scaled([value, first, second])
}

/// Value and derivatives per unit of the interval's parameter s.
struct Scaled([f64; 3]);

impl Scaled {
    /// Back to derivatives per second over an interval of `h` seconds.
    fn per_second(self, h: f64) -> [f64; 3] {
        [self.0[0], self.0[1] / h, self.0[2] / (h * h)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine sampled every 50 ms with its derivatives is reproduced between the samples to
    /// the quintic's error, (ω h)⁶/… ≈ 1e-6 of the amplitude at ω = 5 rad/s.
    #[test]
    fn quintic_interpolation_reproduces_a_smooth_motion() {
        let w = 5.0;
        let text: String = (0..=40)
            .map(|i| {
                let t = i as f64 * 0.05;
                format!(
                    "{t},{},{},{}\n",
                    (w * t).sin(),
                    w * (w * t).cos(),
                    -w * w * (w * t).sin()
                )
            })
            .collect();
        let r = parse_rotation(text.as_bytes(), "<sine>", AngleUnit::Radian).unwrap();
        for k in 0..400 {
            let t = 0.0049 * k as f64;
            let [a, v, acc] = r.at(t);
            assert!((a - (w * t).sin()).abs() < 2e-6, "{t}");
            assert!((v - w * (w * t).cos()).abs() < 1e-4 * w, "{t}");
            assert!((acc + w * w * (w * t).sin()).abs() < 5e-3 * w * w, "{t}");
        }
        // Outside the record: at rest at the end samples.
        assert_eq!(r.at(-1.0), [0.0, 0.0, 0.0]);
        assert_eq!(r.at(10.0)[1], 0.0);
    }

    /// Degrees are converted; angle-only tables get their derivatives by differences.
    #[test]
    fn degrees_and_derived_rates() {
        let text = "time angle\n0 0\n1 10\n2 20\n3 30\n";
        let r = parse_rotation(text.as_bytes(), "<ramp>", AngleUnit::Degree).unwrap();
        let [a, v, acc] = r.at(1.5);
        let rad = std::f64::consts::PI / 180.0;
        assert!((a - 15.0 * rad).abs() < 1e-12);
        assert!((v - 10.0 * rad).abs() < 1e-12);
        assert!(acc.abs() < 1e-12);
    }

    /// The rocking of a foundation: a slow ground acceleration gives the static tilt
    /// θ = −λ a_g / ω² (the oscillator's quasi-static response), and a record of one sample is
    /// refused.
    #[test]
    fn rocking_follows_its_oscillator() {
        let period = 0.3;
        let w = 2.0 * std::f64::consts::PI / period;
        // A ramp to 1 m/s² over 20 s, then held (quasi-static for a 0.3 s oscillator).
        let samples: Vec<f64> = (0..=3000)
            .map(|k| (k as f64 * 0.01 / 20.0).min(1.0))
            .collect();
        let rec = crate::Record::from_samples(0.01, samples).unwrap();
        let r = RotationRecord::rocking(&rec, period, 0.1, 0.07).unwrap();
        let [angle, rate, _] = r.at(29.0);
        assert!(
            (angle + 0.07 * 1.0 / (w * w)).abs() < 1e-3 * 0.07 / (w * w),
            "{angle}"
        );
        assert!(rate.abs() < 1e-6);
        let one = crate::Record::from_samples(0.01, vec![1.0]).unwrap();
        assert!(RotationRecord::rocking(&one, period, 0.1, 0.07).is_err());
    }

    /// Bad tables name the file and line.
    #[test]
    fn bad_tables_are_refused() {
        let e = parse_rotation(b"0 0\n0 1\n", "<dup>", AngleUnit::Radian).unwrap_err();
        assert!(e.to_string().contains("<dup>:2"), "{e}");
        let e = parse_rotation(b"0 0 0 0 0\n", "<wide>", AngleUnit::Radian).unwrap_err();
        assert!(e.to_string().contains("2 to 4 columns"), "{e}");
        let e = parse_rotation(b"0\n1\n", "<one>", AngleUnit::Radian).unwrap_err();
        assert!(e.to_string().contains("time and an angle"), "{e}");
        assert!("grad".parse::<AngleUnit>().is_err());
    }
}
