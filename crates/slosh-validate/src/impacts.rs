//! Impact pressures against measured ones: SPHERIC Benchmark Test 10 (Souto-Iglesias &
//! Botia-Vera, CEHINAV UPM), water, driven by the measured roll of the experiment — the roof
//! impact (`scripts/spheric10_roof_impact.rhai`, sensor 3 on the roof) and the lateral impact
//! (`scripts/spheric10_lateral_impact.rhai`, sensor 1 on the left wall). The first impact's peak
//! at the sensor is judged against the spread of 102 repeats of the experiment (mean ± 2
//! standard deviations, as repeated sloshing impacts scatter); for the roof impact its time is
//! judged against the representative run and its pressure impulse set beside that run's (the
//! lateral case's data hold no trace). The modern preset is judged at every level run; the
//! paper preset is reported.

use super::run::Context;
use super::scripts::{particle_steps, run_script};
use super::{condition, failed_run, info_row, open_if_failed, GroupResult};
use anyhow::{Context as _, Result};

/// Group title of the roof impact.
pub const GROUP: &str =
    "Impact pressure against experiment: SPHERIC Test 10 roof impact, water (spheric10_roof_impact.rhai)";
/// Group title of the lateral impact.
pub const LATERAL_GROUP: &str =
    "Impact pressure against experiment: SPHERIC Test 10 lateral impact, water (spheric10_lateral_impact.rhai)";

/// First four impact peaks at sensor 3 of 102 repeats (mbar), the experimenters' file.
const REPEATS: &str = include_str!(
    "../../../data/impact_SPHERIC10_Water_4first_peak_roof_impact_tto_1_H355_5_B1X.txt"
);
/// Sensor 3's pressure through the first impact of the representative run (t s, mbar).
const REPRESENTATIVE: &str =
    include_str!("../../../data/impact_SPHERIC10_roof_water_first_impact_pressure.csv");
/// First four impact peaks at sensor 1 of 102 repeats of the lateral case (mbar).
const LATERAL_REPEATS: &str = include_str!(
    "../../../data/impact_SPHERIC10_Water_4first_peak_lateral_impact_tto_0_85_H93_B1X.txt"
);
/// The roll period of the roof case (s).
const PERIOD: f64 = 1.1676;
/// The roll period of the lateral case (s).
const LATERAL_PERIOD: f64 = 1.6295;
/// Pa per mbar.
const PA_PER_MBAR: f64 = 100.0;

/// Mean and sample standard deviation of the first peaks of the repeats in the experimenters'
/// file `repeats` (Pa), and their count.
fn first_peak_statistics(repeats: &str) -> Result<(f64, f64, usize)> {
    let peaks: Vec<f64> = repeats
        .lines()
        .filter_map(|l| l.split_whitespace().next()?.parse::<f64>().ok())
        .map(|mbar| mbar * PA_PER_MBAR)
        .collect();
    anyhow::ensure!(
        peaks.len() > 10,
        "the repeats' file holds {} peaks",
        peaks.len()
    );
    let n = peaks.len() as f64;
    let mean = peaks.iter().sum::<f64>() / n;
    let sd = (peaks.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    Ok((mean, sd, peaks.len()))
}

/// Pressure above which sensor 3 (roof) is wetted by an impact (Pa): 2 % of the repeats' mean
/// first peak, above the experiment's baseline drift (a few tenths of a mbar before the impact).
const WETTED_PA: f64 = 86.0;

/// Pressure above which sensor 1 (left wall, at the still level) takes an impact (Pa): above
/// the slow sloshing pressure there (the run-up of the first swings, ≈ 3.5 cm of water,
/// 0.35 kPa), 27 % of the repeats' mean first peak.
const LATERAL_ONSET_PA: f64 = 1000.0;

/// The first impact at the sensor in an SPH run's sensor column `p`(`t`) (Pa, the ±N-step
/// mean the column holds, a transducer's finite response): from the first row above `onset`
/// (Pa) after 1 s, its largest value within 50 ms (the experiment's impact lasts about
/// 20 ms), that value's time, and the impulse of the positive pressure over the window
/// `window` around it (s before, s after).
fn first_sensor_impact(
    t: &[f64],
    p: &[f64],
    onset: f64,
    window: (f64, f64),
) -> Result<(f64, f64, f64)> {
    let start = t
        .iter()
        .zip(p)
        .position(|(ti, pi)| *ti > 1.0 && *pi > onset)
        .with_context(|| format!("the sensor's pressure never exceeds {onset} Pa after 1 s"))?;
    let (t_peak, peak) = t[start..]
        .iter()
        .zip(&p[start..])
        .take_while(|(ti, _)| **ti <= t[start] + 0.05)
        .fold(
            (t[start], p[start]),
            |m, (ti, pi)| if *pi > m.1 { (*ti, *pi) } else { m },
        );
    let impulse = positive_impulse(t, p, t_peak - window.0, t_peak + window.1);
    Ok((peak, t_peak, impulse))
}

/// ∫ max(p, 0) dt (Pa·s) of the samples `p`(`t`) over the intervals within [`from`, `to`] s,
/// by the trapezoidal rule.
fn positive_impulse(t: &[f64], p: &[f64], from: f64, to: f64) -> f64 {
    t.windows(2)
        .zip(p.windows(2))
        .filter(|(tw, _)| tw[0] >= from && tw[1] <= to)
        .map(|(tw, pw)| 0.5 * (pw[0].max(0.0) + pw[1].max(0.0)) * (tw[1] - tw[0]))
        .sum()
}

/// The representative run's peak (Pa), its time (s) and the impulse of its positive pressure
/// over the file's span (Pa·s), and that span's start and end relative to the peak (s before,
/// s after).
fn representative_impact() -> Result<(f64, f64, f64, (f64, f64))> {
    let rows: Vec<(f64, f64)> = REPRESENTATIVE
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let (t, p) = l.split_once(',')?;
            Some((
                t.trim().parse().ok()?,
                p.trim().parse::<f64>().ok()? * PA_PER_MBAR,
            ))
        })
        .collect();
    anyhow::ensure!(
        rows.len() > 10,
        "the representative trace holds {} rows",
        rows.len()
    );
    let peak = rows
        .iter()
        .copied()
        .fold((0.0, 0.0), |m, r| if r.1 > m.1 { r } else { m });
    let (t, p): (Vec<f64>, Vec<f64>) = rows.iter().copied().unzip();
    let (first, last) = (t[0], t[t.len() - 1]);
    let impulse = positive_impulse(&t, &p, first, last);
    let span = (peak.0 - first, last - peak.0);
    Ok((peak.1, peak.0, impulse, span))
}

/// The rows of the group.
pub fn roof_impact(ctx: &Context) -> GroupResult {
    let mut result = GroupResult::default();
    let (stats, representative) =
        match first_peak_statistics(REPEATS).and_then(|s| Ok((s, representative_impact()?))) {
            Ok(v) => v,
            Err(e) => {
                result.checks.push(failed_run(
                    GROUP,
                    "the experiment's data",
                    &format!("{e:#}"),
                ));
                return result;
            }
        };
    let (mean, sd, repeats) = stats;
    let (rep_peak, rep_time, rep_impulse, rep_window) = representative;
    let levels: &[f64] = if ctx.quick { &[0.008] } else { &[0.008, 0.004] };
    for scheme in ["modern", "paper"] {
        for &dx in levels {
            if scheme == "paper" && dx < 0.008 {
                continue;
            }
            level_rows(
                ctx,
                &mut result,
                scheme,
                dx,
                (mean, sd, repeats),
                (rep_time, rep_impulse),
                rep_window,
            );
        }
    }
    result.notes.push(format!(
        "Experiment: tank 0.9 × 0.508 m (62 mm thick), water 355.5 mm deep, rolled about the \
         centre of its bottom by the measured motion (period {PERIOD} s); sensor 3 on the roof \
         25 mm from the left wall, its face taken as 5 mm (the source does not state it). \
         {repeats} repeats: first peak {:.0} ± {:.0} Pa; the representative run (the repeat \
         closest to the mean) peaks at {:.0} Pa at {:.4} s with {:.1} Pa·s over 1.880–1.905 s. \
         The SPH tank is a one-phase 2D section: no air under the roof and no side walls. The \
         finer level (dx = 0.002 m, about 80,000 particles, some 20 minutes on 2 cores) is not \
         run in the suite.",
        mean, sd, rep_peak, rep_time, rep_impulse
    ));
    result
}

#[allow(clippy::too_many_arguments)]
fn level_rows(
    ctx: &Context,
    result: &mut GroupResult,
    scheme: &str,
    dx: f64,
    (mean, sd, repeats): (f64, f64, usize),
    (rep_time, rep_impulse): (f64, f64),
    rep_window: (f64, f64),
) {
    let name = format!("{scheme} preset, dx = {dx} m");
    let measured = sensor_run(
        ctx,
        result,
        (
            "spheric10_roof_impact.rhai",
            &format!("spheric10_{scheme}_{dx}"),
        ),
        (scheme, dx),
        "p_s3",
        WETTED_PA,
        rep_window,
    );
    let judged = scheme == "modern";
    match measured {
        Ok(((peak, t_peak, impulse), mach)) => {
            let peak_row = peak_row(GROUP, &name, 3, peak, (mean, sd, repeats));
            let lead = t_peak - rep_time;
            let time_row = condition(
                GROUP,
                &format!("{name}: time of the first impact's peak"),
                format!("{t_peak:.4} s"),
                format!("{rep_time:.4} s (the representative run)"),
                lead.abs() <= 0.05 * PERIOD,
                &format!("± {:.3} s (5 % of the period)", 0.05 * PERIOD),
                "the wave that meets the roof, and the roof's clearance as the liquid sees it, \
                 set when the crest arrives",
            );
            if judged {
                let gap = "the modern preset's impact at the coarse levels: the roof is felt \
                           about 2 dx before contact (docs/roof-loads.md), the crest arrives \
                           early and hard";
                result.checks.push(open_if_failed(peak_row, gap));
                result.checks.push(open_if_failed(time_row, gap));
            } else {
                for mut row in [peak_row, time_row] {
                    row.verdict = super::Verdict::Info;
                    row.reason =
                        format!("{} — the paper preset is reported, not judged", row.reason);
                    result.checks.push(row);
                }
            }
            result.checks.push(info_row(
                GROUP,
                &format!("{name}: pressure impulse of the first impact at sensor 3"),
                format!("{impulse:.1} Pa·s"),
                format!(
                    "{rep_impulse:.1} Pa·s (the representative run, {:.1} ms before its peak to {:.1} ms after)",
                    1e3 * rep_window.0,
                    1e3 * rep_window.1
                ),
                format!("ratio {:.2}", impulse / rep_impulse),
                "over the same span around the peak as the measured trace; the experimenters \
                 give the repeats' peaks, not their impulses, so one run's impulse is the only \
                 measured one",
            ));
            result.checks.push(mach_row(GROUP, &name, mach));
        }
        Err(e) => result
            .checks
            .push(failed_run(GROUP, &name, &format!("{e:#}"))),
    }
}

/// The rows of the lateral-impact group: the first impact's peak at sensor 1 against the
/// repeats, its time and the largest Mach number reported (the data hold the repeats' peaks,
/// not their times or traces).
pub fn lateral_impact(ctx: &Context) -> GroupResult {
    let mut result = GroupResult::default();
    let (mean, sd, repeats) = match first_peak_statistics(LATERAL_REPEATS) {
        Ok(v) => v,
        Err(e) => {
            result.checks.push(failed_run(
                LATERAL_GROUP,
                "the experiment's data",
                &format!("{e:#}"),
            ));
            return result;
        }
    };
    // The quick suite runs the judged preset at its coarse level (≈ 100 s on one core); the
    // full suite adds dx = 2 mm (≈ 7 min on 2 cores) and the paper preset.
    let runs: &[(&str, f64)] = if ctx.quick {
        &[("modern", 0.004)]
    } else {
        &[("modern", 0.004), ("modern", 0.002), ("paper", 0.004)]
    };
    for &(scheme, dx) in runs {
        lateral_level_rows(ctx, &mut result, scheme, dx, (mean, sd, repeats));
    }
    result.notes.push(format!(
        "Experiment: the roof case's tank (0.9 × 0.508 m, 62 mm thick), water 93 mm deep, \
         rolled about the centre of its bottom by the measured motion (period \
         {LATERAL_PERIOD} s = 0.85 T₁, about 4°); sensor 1 on the left wall at the still level, \
         its face taken as 5 mm. {repeats} repeats: first peak {mean:.0} ± {sd:.0} Pa. The \
         data found hold the repeats' peaks only (no time or trace of the water case), so the \
         impact's time and impulse are reported, not judged. The SPH tank is a one-phase 2D \
         section: no air in the breaking wave and no side walls."
    ));
    result
}

fn lateral_level_rows(
    ctx: &Context,
    result: &mut GroupResult,
    scheme: &str,
    dx: f64,
    (mean, sd, repeats): (f64, f64, usize),
) {
    let name = format!("{scheme} preset, dx = {dx} m");
    // The impulse over the experiment's impact duration (≈ 20 ms) around the peak.
    let measured = sensor_run(
        ctx,
        result,
        (
            "spheric10_lateral_impact.rhai",
            &format!("spheric10_lateral_{scheme}_{dx}"),
        ),
        (scheme, dx),
        "p_s1",
        LATERAL_ONSET_PA,
        (0.01, 0.01),
    );
    match measured {
        Ok(((peak, t_peak, impulse), mach)) => {
            let mut peak_row = peak_row(LATERAL_GROUP, &name, 1, peak, (mean, sd, repeats));
            if scheme == "modern" {
                peak_row = open_if_failed(
                    peak_row,
                    "the one-phase 2D model's breaking wave meets the wall without the air \
                     it entraps in the experiment, and the jets pass Mach 0.1 (see the Mach \
                     row): the peak is the model's, not yet the experiment's",
                );
            } else {
                peak_row.verdict = super::Verdict::Info;
                peak_row.reason = format!(
                    "{} — the paper preset is reported, not judged",
                    peak_row.reason
                );
            }
            result.checks.push(peak_row);
            result.checks.push(info_row(
                LATERAL_GROUP,
                &format!("{name}: time of the first impact's peak, and its impulse ±10 ms"),
                format!("{t_peak:.4} s, {impulse:.2} Pa·s"),
                "—".into(),
                format!("{:.3} roll periods", t_peak / LATERAL_PERIOD),
                "the data found give the repeats' peaks, not their times or traces: reported \
                 for the resolution study",
            ));
            result.checks.push(mach_row(LATERAL_GROUP, &name, mach));
        }
        Err(e) => result
            .checks
            .push(failed_run(LATERAL_GROUP, &name, &format!("{e:#}"))),
    }
}

/// A run of `script` (its run folder named `label`) with the preset `scheme` at the lattice
/// `dx` (m): the first impact in its sensor column `column` ([`first_sensor_impact`], with
/// `onset` in Pa and the impulse's `window` in s before and after the peak) and the run's
/// largest Mach number; the run's particle-steps counted in `result`.
fn sensor_run(
    ctx: &Context,
    result: &mut GroupResult,
    (script, label): (&str, &str),
    (scheme, dx): (&str, f64),
    column: &str,
    onset: f64,
    window: (f64, f64),
) -> Result<((f64, f64, f64), f64)> {
    let sets = vec![format!("scheme={scheme}"), format!("dx={dx}")];
    let run = run_script(ctx, script, label, &sets)?;
    result.particle_steps += particle_steps(&run.summary);
    let [t, p] = run.columns(["t", column])?;
    let first = first_sensor_impact(&t, &p, onset, window)?;
    Ok((first, run.summary.max_mach))
}

/// The row that judges a first impact's peak at sensor `sensor` (Pa) against the repeats'
/// first peaks (mean and standard deviation in Pa, count): within the mean ± 2 standard
/// deviations, as one draw of a scattering process.
fn peak_row(
    group: &str,
    name: &str,
    sensor: u32,
    peak: f64,
    (mean, sd, repeats): (f64, f64, usize),
) -> super::Check {
    let (lo, hi) = (mean - 2.0 * sd, mean + 2.0 * sd);
    condition(
        group,
        &format!("{name}: first impact's peak at sensor {sensor}"),
        format!("{peak:.0} Pa"),
        format!("{mean:.0} ± 2 × {sd:.0} Pa ({repeats} repeats)"),
        peak >= lo && peak <= hi,
        &format!("[{lo:.0}, {hi:.0}] Pa"),
        &format!(
            "repeated sloshing impacts scatter (here by {:.0} % of the mean): a computed peak \
             is one draw, judged against the repeats' mean ± 2 standard deviations",
            100.0 * sd / mean
        ),
    )
}

/// The run's largest Mach number, reported beside the weakly compressible liquid's limit.
fn mach_row(group: &str, name: &str, mach: f64) -> super::Check {
    info_row(
        group,
        &format!("{name}: largest Mach number"),
        format!("{mach:.3}"),
        "0.1".into(),
        "—".into(),
        "the weakly compressible liquid's own limit",
    )
}
