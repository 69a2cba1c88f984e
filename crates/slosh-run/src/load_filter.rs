//! Loads as engineers read them: each raw force and moment column of `series.csv` beside a
//! low-pass filtered copy (`<column>_lp`), so that the design value is not one of the
//! step-to-step spikes of the SPH wall pressure.
//!
//! The filter is the zero-phase 4th-order Butterworth low-pass of `slosh-motion` (run forward
//! and backward: no phase shift, gain 1/2 at the cut-off), applied to the finished column at
//! the end of the run. Before filtering, each end of the column is extended by its end value
//! over the filter's transient length, so that a load that does not end at zero is not pulled
//! towards zero at the end of the run.

use serde::{Deserialize, Serialize};
use slosh_motion::filter::{butterworth_zero_phase, BUTTERWORTH_ORDER};

/// The raw load columns that get a filtered copy, where the run has them.
pub const FILTERED_COLUMNS: [&str; 6] = [
    "base_shear_x",
    "base_shear_y",
    "roof_force_up",
    "overturning_moment",
    "overturning_moment_y",
    "overturning_moment_x",
];

/// Whether `name` is a per-part force column, `<part>_force_x|y|z`.
fn is_part_force_column(name: &str) -> bool {
    ["_force_x", "_force_y", "_force_z"]
        .iter()
        .any(|s| name.len() > s.len() && name.ends_with(s))
}

/// Suffix of a filtered column's name.
pub const FILTERED_SUFFIX: &str = "_lp";

/// Default cut-off as a multiple of the first sloshing frequency: well above the convective
/// and impulsive response of the tank, below the acoustic ringing of the weakly compressible
/// liquid.
pub const DEFAULT_CUTOFF_OVER_F1: f64 = 10.0;

/// The filter as the summary and the units file state it.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LoadFilter {
    /// Cut-off frequency (Hz).
    pub cutoff_hz: f64,
    /// Where the cut-off comes from (`load_filter_hz` or ten times the first mode).
    pub cutoff_source: String,
    /// The filter in words.
    pub kind: String,
    /// Why the filtered columns equal the raw ones, when they do.
    pub note: Option<String>,
}

impl LoadFilter {
    /// The filter for a run: `requested_hz` from `run(#{ load_filter_hz })`, else ten times
    /// the first sloshing frequency `omega_1` (rad/s).
    pub fn new(requested_hz: Option<f64>, omega_1: f64) -> Self {
        let (cutoff_hz, cutoff_source) = match requested_hz {
            Some(f) => (f, "run(#{ load_filter_hz })".to_string()),
            None => {
                let f1 = omega_1 / (2.0 * std::f64::consts::PI);
                (
                    DEFAULT_CUTOFF_OVER_F1 * f1,
                    format!("{DEFAULT_CUTOFF_OVER_F1} × the first sloshing frequency {f1:.4} Hz"),
                )
            }
        };
        LoadFilter {
            cutoff_hz,
            cutoff_source,
            kind: format!(
                "zero-phase {BUTTERWORTH_ORDER}th-order Butterworth low-pass (forward and \
                 backward; gain 1/2 at the cut-off), applied to the finished column"
            ),
            note: None,
        }
    }

    /// The unit-file text of a filtered column: its unit and the filter.
    pub fn unit_of_filtered(&self, raw_unit: &str) -> String {
        format!(
            "{raw_unit} (low-pass {:.3} Hz, zero-phase 4th-order Butterworth)",
            self.cutoff_hz
        )
    }

    /// Filters `signal` sampled at the times `t` (s); the rows of `series.csv` are taken as
    /// uniform at their median interval. When the cut-off is not below the Nyquist frequency
    /// of the rows, or there are too few rows, the signal is returned unchanged and
    /// [`LoadFilter::note`] says so.
    pub fn apply(&mut self, t: &[f64], signal: &[f64]) -> Vec<f64> {
        let Some(dt) = median_interval(t) else {
            self.note = Some("fewer than 3 rows: the filtered columns equal the raw ones".into());
            return signal.to_vec();
        };
        let nyquist = 0.5 / dt;
        if self.cutoff_hz >= nyquist {
            self.note = Some(format!(
                "the cut-off {:.3} Hz is not below the Nyquist frequency {nyquist:.3} Hz of the \
                 output rows: the filtered columns equal the raw ones (lower load_filter_hz or \
                 output_interval)",
                self.cutoff_hz
            ));
            return signal.to_vec();
        }
        low_pass_held_ends(signal, dt, self.cutoff_hz)
    }
}

/// The median of the intervals between successive times, `None` for fewer than 3 times.
fn median_interval(t: &[f64]) -> Option<f64> {
    if t.len() < 3 {
        return None;
    }
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let dt = steps[steps.len() / 2];
    (dt > 0.0 && dt.is_finite()).then_some(dt)
}

/// Zero-phase Butterworth low-pass of `signal` (interval `dt` s, cut-off `cutoff_hz`), with
/// each end extended by its end value over the filter's transient length. Non-finite samples
/// are filtered as the previous finite value and stay non-finite in the output.
pub fn low_pass_held_ends(signal: &[f64], dt: f64, cutoff_hz: f64) -> Vec<f64> {
    if signal.is_empty() {
        return Vec::new();
    }
    let mut held = Vec::with_capacity(signal.len());
    let mut last = signal
        .iter()
        .copied()
        .find(|x| x.is_finite())
        .unwrap_or(0.0);
    for &x in signal {
        if x.is_finite() {
            last = x;
        }
        held.push(last);
    }
    // Twice the filter's own zero padding: its transient has decayed before the signal.
    let pad = (3.0 * BUTTERWORTH_ORDER as f64 / cutoff_hz / dt).ceil() as usize;
    let first = held[0];
    let end = held[held.len() - 1];
    let mut extended = vec![first; pad];
    extended.extend_from_slice(&held);
    extended.extend(std::iter::repeat_n(end, pad));
    let filtered = butterworth_zero_phase(&extended, dt, None, Some(cutoff_hz));
    filtered[pad..pad + signal.len()]
        .iter()
        .zip(signal)
        .map(|(&f, &x)| if x.is_finite() { f } else { x })
        .collect()
}

/// The peaks of one raw load column and of its filtered copy.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LoadPeak {
    /// Raw column name (the filtered one is `<column>_lp`).
    pub column: String,
    /// Unit of both.
    pub unit: String,
    /// Largest |raw value| over the output rows.
    pub max_abs: f64,
    /// Its time (s).
    pub t_max_abs: f64,
    /// Largest |filtered value|.
    pub max_abs_lp: f64,
    /// Its time (s).
    pub t_max_abs_lp: f64,
}

/// Appends `<column>_lp` after the existing columns for each of [`FILTERED_COLUMNS`] the run
/// has, then for each per-part force column (`<part>_force_<axis>`, internal solids and parts
/// named by the user) (`names` = (name, unit), `history` = the columns, the first being `t`),
/// and returns the peaks of each raw and filtered pair.
pub fn add_filtered_columns(
    filter: &mut LoadFilter,
    names: &mut Vec<(String, String)>,
    history: &mut Vec<Vec<f64>>,
) -> Vec<LoadPeak> {
    let t = history[0].clone();
    let mut peaks = Vec::new();
    let part_forces: Vec<String> = names
        .iter()
        .filter(|(n, _)| is_part_force_column(n))
        .map(|(n, _)| n.clone())
        .collect();
    let wanted = FILTERED_COLUMNS
        .iter()
        .map(|c| c.to_string())
        .chain(part_forces);
    for column in wanted {
        let column = column.as_str();
        let Some(i) = names.iter().position(|(n, _)| n == column) else {
            continue;
        };
        let unit = names[i].1.clone();
        let filtered = filter.apply(&t, &history[i]);
        let time_of = |at: Option<usize>| at.map(|k| t[k]).unwrap_or(0.0);
        let (max_raw, at_raw) = max_abs(&history[i]);
        let (max_lp, at_lp) = max_abs(&filtered);
        peaks.push(LoadPeak {
            column: column.to_string(),
            unit: unit.clone(),
            max_abs: max_raw,
            t_max_abs: time_of(at_raw),
            max_abs_lp: max_lp,
            t_max_abs_lp: time_of(at_lp),
        });
        names.push((
            format!("{column}{FILTERED_SUFFIX}"),
            filter.unit_of_filtered(&unit),
        ));
        history.push(filtered);
    }
    peaks
}

/// Largest |x| over the finite values and its index (0 and `None` for none).
pub fn max_abs(values: &[f64]) -> (f64, Option<usize>) {
    values
        .iter()
        .enumerate()
        .filter(|(_, x)| x.is_finite())
        .fold((0.0, None), |(m, at), (i, x)| {
            if x.abs() > m {
                (x.abs(), Some(i))
            } else {
                (m, at)
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn sampled(f: impl Fn(f64) -> f64, dt: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let x = t.iter().map(|&t| f(t)).collect();
        (t, x)
    }

    #[test]
    fn keeps_the_sloshing_and_removes_the_spikes() {
        // 1 Hz sloshing load with 30 Hz ringing on top; cut-off 10 Hz.
        let (t, x) = sampled(
            |t| 100.0 * (2.0 * PI * t).sin() + 30.0 * (2.0 * PI * 30.0 * t).sin(),
            0.005,
            2000,
        );
        let mut filter = LoadFilter::new(Some(10.0), 2.0 * PI);
        let y = filter.apply(&t, &x);
        assert!(filter.note.is_none());
        for i in 200..1800 {
            let slow = 100.0 * (2.0 * PI * t[i]).sin();
            assert!(
                (y[i] - slow).abs() < 1.0,
                "t = {}: {} vs {slow}",
                t[i],
                y[i]
            );
        }
    }

    #[test]
    fn a_constant_load_stays_constant_to_the_ends() {
        let (t, x) = sampled(|_| 250.0, 0.01, 300);
        let y = LoadFilter::new(Some(5.0), 1.0).apply(&t, &x);
        assert!(y.iter().all(|v| (v - 250.0).abs() < 1e-6), "{:?}", &y[..5]);
    }

    #[test]
    fn default_cut_off_is_ten_times_the_first_mode() {
        let filter = LoadFilter::new(None, 2.0 * PI * 0.845);
        assert!((filter.cutoff_hz - 8.45).abs() < 1e-12);
    }

    #[test]
    fn a_cut_off_above_nyquist_leaves_the_signal_and_says_so() {
        let (t, x) = sampled(|t| t.sin(), 0.1, 50);
        let mut filter = LoadFilter::new(Some(8.0), 1.0);
        assert_eq!(filter.apply(&t, &x), x);
        assert!(filter.note.as_deref().unwrap().contains("Nyquist"));
    }
}
