//! The Rhai API for ground motion: recorded accelerograms (`load_record`) and sines.
//!
//! ```rhai
//! let gm = load_record("records/elcentro_1940_ns.at2").scale_to_pga(3.0);  // m/s²
//! fn ground_accel(t) { gm.at(t) }
//! ```
//!
//! * `load_record(path)` / `load_record(path, #{units, dt, format})` → `Record`. The path is
//!   looked up below the script's folder, then its project folder and the `--allow-read`
//!   folders ([`ReadSandbox`]); a path that leaves them is refused.
//!   `format`: `"at2"` (PEER NGA, in g), `"knet"` (K-NET / KiK-net ASCII, in gal) or `"csv"`
//!   (plain text: two columns time, accel — or one column with `dt`); without `format` the
//!   reader is chosen from the file (`.at2` name, K-NET header) and anything else is plain
//!   text. `units` (`"g"`, `"gal"`, `"m/s2"`) is required for plain text; for AT2 and K-NET
//!   files the format fixes the units and a different `units` is an error. 1 g = 9.81 m/s².
//! * Processing, each returning a new `Record` (the original is unchanged): `scale(f)`,
//!   `scale_to_pga(a_m_s2)`, `remove_mean()`, `detrend(order)` (least-squares polynomial of
//!   order 0–3), `bandpass(lo_hz, hi_hz)`, `highpass(hz)`, `lowpass(hz)` (zero-phase 4th-order
//!   Butterworth), `trim(t0, t1)` (keeps [t0, t1], re-zeroed to start at 0), `shift(s)`
//!   (starts `s` later).
//! * Queries: `at(t)` (m/s², linear between samples, 0 outside the record), `pga()` (m/s²),
//!   `duration()` (s), `dt()` (s), `npts()`.
//! * Sines, as the paper writes its excitation: `sine(A, ω)` and `sine(A, ω, φ)` give the
//!   ground acceleration **a_g(t) = +A ω² sin(ωt + φ)** (m/s²), so that the liquid feels the
//!   inertial body force −a_g = −A ω² sin(ωt + φ) of the paper (Ono et al. 2007, §3.1). The
//!   ground displacement is therefore x_g(t) = −A sin(ωt + φ); A in m, ω in rad/s, φ in rad.
//!   `sines([[A1, ω1], [A2, ω2, φ2], ...])` is their sum. Both are `Excitation` values with
//!   `at(t)` and `scale(f)`.
//! * `load_rotation(path, #{units: "deg"})` → `RotationRecord`: a recorded rotation of the
//!   tank, a plain-text table of time (s), angle and optionally its rate and angular
//!   acceleration (`units` `"rad"` or `"deg"`, required), interpolated twice continuously
//!   differentiable (`slosh_motion::rotation`); `at(t)` gives `[angle (rad), rate (rad/s),
//!   angular acceleration (rad/s²)]`, the form `fn ground_rotation(t)` returns; `duration()`,
//!   `npts()`, `peak_angle()` (rad).
//! * `record.rocking(period, damping, lever)` → `RotationRecord`: the rocking of a tank on a
//!   flexible foundation under the record, θ̈ + 2ζω θ̇ + ω² θ = −λ a_g (λ = m h / I_θ, 1/m;
//!   `slosh_motion::RotationRecord::rocking`).
//! * `+` adds any two of `Record` and `Excitation` into an `Excitation` (e.g. a record plus a
//!   sine); three components are returned by the script as `[gx.at(t), gy.at(t), gz.at(t)]`.
//!
//! Every record read is logged ([`MotionInfo`]: file, hash, samples, scaling and processing);
//! when a record is processed further, its log entry follows the newest record derived from
//! it, and a second branch derived from an older stage gets an entry of its own.

use crate::sandbox::ReadSandbox;
use crate::spec::{dynamic_to_f64, MapReader};
use rhai::{Array, Dynamic, Engine, EvalAltResult, Map, Position};
use serde::Serialize;
use slosh_motion::{AccelUnit, Excitation, PlainTextOptions, Record, RecordFormat, Sine};
use std::str::FromStr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// One ground-motion record a script read, as written to `summary.ron`.
#[derive(Clone, Debug, Serialize)]
pub struct MotionInfo {
    /// The path as the script wrote it (relative to the script's folder).
    pub file: String,
    /// The path read.
    pub path: String,
    /// File layout (`PEER AT2`, `K-NET ASCII`, `plain text`).
    pub format: String,
    /// SHA-256 of the file's bytes, lowercase hex.
    pub sha256: String,
    /// Samples in the file.
    pub npts: usize,
    /// Sample interval in the file, s.
    pub dt_s: f64,
    /// Units of the file's values (converted to m/s² on reading, 1 g = 9.81 m/s²).
    pub units: String,
    /// Product of the factors of `scale` and `scale_to_pga` applied after reading.
    pub scale_factor: f64,
    /// Peak |acceleration| after processing, m/s².
    pub pga_m_s2: f64,
    /// Length after processing, s.
    pub duration_s: f64,
    /// Time of the first sample after processing (moved by `shift`), s.
    pub start_time_s: f64,
    /// Time of the last sample after processing, s, on the clock of `ground_accel(t)` (time
    /// since the excitation started): the motion is zero after it.
    pub end_time_s: f64,
    /// What the reader found suspicious in the file (e.g. a stated duration the data does
    /// not fill), one sentence each.
    pub warnings: Vec<String>,
    /// Every operation applied, reading included, in order.
    pub processing: Vec<String>,
    /// Version of the newest record derived from this entry (see the module docs).
    #[serde(skip)]
    newest_version: u64,
}

/// The log of records read by a script, shared with the host.
pub(crate) type MotionLog = Arc<Mutex<Vec<MotionInfo>>>;

/// A record as a script holds it (Rhai type `Record`).
#[derive(Clone)]
struct ScriptRecord {
    record: Arc<Record>,
    /// The path as the script wrote it.
    file: Arc<str>,
    /// Product of the scale factors applied since reading.
    scale_factor: f64,
    /// Index of this record's entry in the log, and its version.
    log_slot: usize,
    version: u64,
}

/// The `format` of a rotation table's entry in the log of records.
pub(crate) const ROTATION_TABLE: &str = "rotation table";

/// A recorded rotation as a script holds it (Rhai type `RotationRecord`).
#[derive(Clone)]
struct ScriptRotation(Arc<slosh_motion::RotationRecord>);

/// Sines, sums, and records combined with them (Rhai type `Excitation`).
#[derive(Clone)]
struct ScriptExcitation(Arc<Excitation>);

static NEXT_VERSION: AtomicU64 = AtomicU64::new(1);

fn next_version() -> u64 {
    NEXT_VERSION.fetch_add(1, Ordering::Relaxed)
}

fn runtime_error(message: impl Into<String>) -> Box<EvalAltResult> {
    Box::new(EvalAltResult::ErrorRuntime(
        message.into().into(),
        Position::NONE,
    ))
}

/// A script number (float or integer) as f64.
fn number(value: &Dynamic, what: &str) -> Result<f64, Box<EvalAltResult>> {
    dynamic_to_f64(value)
        .filter(|x| x.is_finite())
        .ok_or_else(|| runtime_error(format!("{what} must be a finite number, got {value}")))
}

/// Registers `load_record`, the `Record` and `Excitation` types with their methods, `sine`,
/// `sines` and `+`. Files are read through `sandbox`; every record read goes to `log`.
pub(crate) fn register_motion_api(engine: &mut Engine, sandbox: Arc<ReadSandbox>, log: MotionLog) {
    engine.register_type_with_name::<ScriptRecord>("Record");
    engine.register_type_with_name::<ScriptExcitation>("Excitation");
    engine.register_type_with_name::<ScriptRotation>("RotationRecord");

    let (dir, lg) = (sandbox.clone(), log.clone());
    engine.register_fn(
        "load_record",
        move |file: &str| -> Result<ScriptRecord, Box<EvalAltResult>> {
            load_record(&dir, &lg, file, &Map::new())
        },
    );
    let (dir, lg) = (sandbox.clone(), log.clone());
    engine.register_fn(
        "load_record",
        move |file: &str, options: Map| -> Result<ScriptRecord, Box<EvalAltResult>> {
            load_record(&dir, &lg, file, &options)
        },
    );
    let (dir, lg) = (sandbox, log.clone());
    engine.register_fn(
        "load_rotation",
        move |file: &str, options: Map| -> Result<ScriptRotation, Box<EvalAltResult>> {
            load_rotation(&dir, &lg, file, &options)
        },
    );
    engine.register_fn("at", |r: &mut ScriptRotation, t: f64| -> Array {
        r.0.at(t).iter().map(|v| Dynamic::from_float(*v)).collect()
    });
    engine.register_fn("at", |r: &mut ScriptRotation, t: rhai::INT| -> Array {
        r.0.at(t as f64)
            .iter()
            .map(|v| Dynamic::from_float(*v))
            .collect()
    });
    engine.register_fn(
        "rocking",
        |r: &mut ScriptRecord,
         period: Dynamic,
         damping: Dynamic,
         lever: Dynamic|
         -> Result<ScriptRotation, Box<EvalAltResult>> {
            let what = "rocking(period, damping, lever)";
            let period = number(&period, &format!("{what}: period (s)"))?;
            let damping = number(&damping, &format!("{what}: damping ratio"))?;
            let lever = number(&lever, &format!("{what}: lever m h / I (1/m)"))?;
            slosh_motion::RotationRecord::rocking(&r.record, period, damping, lever)
                .map(|rot| ScriptRotation(Arc::new(rot)))
                .map_err(|e| runtime_error(format!("{what} of the record \"{}\": {e}", r.file)))
        },
    );
    engine.register_fn("duration", |r: &mut ScriptRotation| r.0.duration_s());
    engine.register_fn("npts", |r: &mut ScriptRotation| r.0.len() as rhai::INT);
    engine.register_fn("peak_angle", |r: &mut ScriptRotation| r.0.peak_angle_rad());

    // Processing: each returns a new record and keeps the log up to date.
    let lg = log.clone();
    engine.register_fn(
        "scale",
        move |r: &mut ScriptRecord, factor: Dynamic| -> Result<ScriptRecord, Box<EvalAltResult>> {
            let factor = number(&factor, "scale(factor): factor")?;
            derive(&lg, r, "scale", |rec| {
                rec.scale(factor);
                Ok(factor)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "scale_to_pga",
        move |r: &mut ScriptRecord, pga: Dynamic| -> Result<ScriptRecord, Box<EvalAltResult>> {
            let target = number(&pga, "scale_to_pga(pga): the target PGA (m/s²)")?;
            derive(&lg, r, "scale_to_pga", |rec| {
                let before = rec.pga_m_s2();
                rec.scale_to_pga(target)?;
                Ok(target / before)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "remove_mean",
        move |r: &mut ScriptRecord| -> Result<ScriptRecord, Box<EvalAltResult>> {
            derive(&lg, r, "remove_mean", |rec| {
                rec.remove_mean();
                Ok(1.0)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "detrend",
        move |r: &mut ScriptRecord, order: Dynamic| -> Result<ScriptRecord, Box<EvalAltResult>> {
            let order = number(&order, "detrend(order): order")?;
            if order < 0.0 || order.fract() != 0.0 {
                return Err(runtime_error(format!(
                    "detrend(order): order must be a whole number 0..=3, got {order}"
                )));
            }
            derive(&lg, r, "detrend", |rec| {
                rec.detrend_polynomial(order as usize)?;
                Ok(1.0)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "bandpass",
        move |r: &mut ScriptRecord,
              low_hz: Dynamic,
              high_hz: Dynamic|
              -> Result<ScriptRecord, Box<EvalAltResult>> {
            let low = number(&low_hz, "bandpass(low_hz, high_hz): low_hz")?;
            let high = number(&high_hz, "bandpass(low_hz, high_hz): high_hz")?;
            derive(&lg, r, "bandpass", |rec| {
                rec.bandpass(low, high)?;
                Ok(1.0)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "highpass",
        move |r: &mut ScriptRecord, hz: Dynamic| -> Result<ScriptRecord, Box<EvalAltResult>> {
            let hz = number(&hz, "highpass(hz): hz")?;
            derive(&lg, r, "highpass", |rec| {
                rec.highpass(hz)?;
                Ok(1.0)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "lowpass",
        move |r: &mut ScriptRecord, hz: Dynamic| -> Result<ScriptRecord, Box<EvalAltResult>> {
            let hz = number(&hz, "lowpass(hz): hz")?;
            derive(&lg, r, "lowpass", |rec| {
                rec.lowpass(hz)?;
                Ok(1.0)
            })
        },
    );
    let lg = log.clone();
    engine.register_fn(
        "trim",
        move |r: &mut ScriptRecord,
              t0: Dynamic,
              t1: Dynamic|
              -> Result<ScriptRecord, Box<EvalAltResult>> {
            let t0 = number(&t0, "trim(t0, t1): t0")?;
            let t1 = number(&t1, "trim(t0, t1): t1")?;
            derive(&lg, r, "trim", |rec| {
                rec.trim(t0, t1)?;
                Ok(1.0)
            })
        },
    );
    let lg = log;
    engine.register_fn(
        "shift",
        move |r: &mut ScriptRecord, delay: Dynamic| -> Result<ScriptRecord, Box<EvalAltResult>> {
            let delay = number(&delay, "shift(seconds): seconds")?;
            derive(&lg, r, "shift", |rec| {
                rec.shift(delay);
                Ok(1.0)
            })
        },
    );

    // Queries. `at` is called once per time step: typed fast paths for floats and integers.
    engine.register_fn("at", |r: &mut ScriptRecord, t: f64| r.record.at(t));
    engine.register_fn("at", |r: &mut ScriptRecord, t: rhai::INT| {
        r.record.at(t as f64)
    });
    engine.register_fn("pga", |r: &mut ScriptRecord| r.record.pga_m_s2());
    engine.register_fn("duration", |r: &mut ScriptRecord| r.record.duration_s());
    engine.register_fn("dt", |r: &mut ScriptRecord| r.record.dt_s);
    engine.register_fn("npts", |r: &mut ScriptRecord| r.record.len() as rhai::INT);
    engine.register_fn("to_string", |r: &mut ScriptRecord| describe_record(r));
    engine.register_fn("to_debug", |r: &mut ScriptRecord| describe_record(r));

    // Sines (paper sign: a_g = +A ω² sin(ωt + φ)) and their sums.
    engine.register_fn(
        "sine",
        |a: Dynamic, omega: Dynamic| -> Result<ScriptExcitation, Box<EvalAltResult>> {
            let sine = paper_sine(&[a, omega], "sine(A, omega)")?;
            Ok(ScriptExcitation(Arc::new(Excitation::Sine(sine))))
        },
    );
    engine.register_fn(
        "sine",
        |a: Dynamic,
         omega: Dynamic,
         phase: Dynamic|
         -> Result<ScriptExcitation, Box<EvalAltResult>> {
            let sine = paper_sine(&[a, omega, phase], "sine(A, omega, phase)")?;
            Ok(ScriptExcitation(Arc::new(Excitation::Sine(sine))))
        },
    );
    engine.register_fn(
        "sines",
        |list: Array| -> Result<ScriptExcitation, Box<EvalAltResult>> {
            let mut sines = Vec::with_capacity(list.len());
            for (i, item) in list.iter().enumerate() {
                let what = format!("sines(list): item {i}");
                let parts = item
                    .read_lock::<Array>()
                    .map(|a| a.clone())
                    .filter(|a| a.len() == 2 || a.len() == 3)
                    .ok_or_else(|| {
                        runtime_error(format!(
                            "{what} must be [A, omega] or [A, omega, phase], got {item}"
                        ))
                    })?;
                sines.push(paper_sine(&parts, &what)?);
            }
            Ok(ScriptExcitation(Arc::new(Excitation::SineSum(sines))))
        },
    );
    engine.register_fn("at", |e: &mut ScriptExcitation, t: f64| e.0.at(t));
    engine.register_fn("at", |e: &mut ScriptExcitation, t: rhai::INT| {
        e.0.at(t as f64)
    });
    engine.register_fn(
        "scale",
        |e: &mut ScriptExcitation,
         factor: Dynamic|
         -> Result<ScriptExcitation, Box<EvalAltResult>> {
            let factor = number(&factor, "scale(factor): factor")?;
            Ok(ScriptExcitation(Arc::new(scaled(&e.0, factor))))
        },
    );
    engine.register_fn("to_string", |e: &mut ScriptExcitation| {
        describe_excitation(&e.0)
    });
    engine.register_fn("to_debug", |e: &mut ScriptExcitation| {
        describe_excitation(&e.0)
    });

    // Sums.
    engine.register_fn("+", |a: ScriptRecord, b: ScriptRecord| {
        sum(record_part(&a), record_part(&b))
    });
    engine.register_fn("+", |a: ScriptRecord, b: ScriptExcitation| {
        sum(record_part(&a), (*b.0).clone())
    });
    engine.register_fn("+", |a: ScriptExcitation, b: ScriptRecord| {
        sum((*a.0).clone(), record_part(&b))
    });
    engine.register_fn("+", |a: ScriptExcitation, b: ScriptExcitation| {
        sum((*a.0).clone(), (*b.0).clone())
    });
}

/// Reads a record for `load_record` and logs it.
fn load_record(
    sandbox: &ReadSandbox,
    log: &MotionLog,
    file: &str,
    options: &Map,
) -> Result<ScriptRecord, Box<EvalAltResult>> {
    let fail = |message: String| runtime_error(format!("load_record(\"{file}\"): {message}"));
    let mut reader = MapReader::new("load_record options", options);
    let units = reader.str_or("units", "").map_err(fail)?;
    let dt = reader.opt_f64("dt").map_err(fail)?;
    let format = reader.str_or("format", "").map_err(fail)?;
    reader.finish().map_err(fail)?;

    let units = if units.is_empty() {
        None
    } else {
        Some(AccelUnit::from_str(&units).map_err(|e| fail(e.to_string()))?)
    };
    let path = sandbox.resolve(file).map_err(fail)?;
    let plain = PlainTextOptions {
        units: units.unwrap_or(AccelUnit::MetersPerSecondSquared),
        dt_s: dt,
    };
    let record = match format.to_ascii_lowercase().as_str() {
        "" => slosh_motion::read_record(&path, &plain),
        "at2" | "peer" => slosh_motion::read_at2(&path),
        "knet" | "kiknet" | "k-net" | "kik-net" => slosh_motion::read_knet(&path),
        "csv" | "text" | "txt" => slosh_motion::read_plain_text(&path, &plain),
        other => {
            return Err(fail(format!(
                "unknown format \"{other}\"; use \"at2\", \"knet\" or \"csv\""
            )))
        }
    }
    .map_err(|e| fail(e.to_string()))?;

    let file_units = record.meta.original_units;
    match (record.meta.format, units) {
        (RecordFormat::PlainText, None) => {
            return Err(fail(format!(
                "{} is read as plain text: state its units, e.g. load_record(\"{file}\", #{{units: \"g\"}}) (\"g\", \"gal\" or \"m/s2\")",
                path.display()
            )))
        }
        (RecordFormat::PeerAt2 | RecordFormat::KnetAscii, Some(u)) if u != file_units => {
            return Err(fail(format!(
                "{} is a {} file, whose values are in {file_units}; remove `units: \"{u}\"` or convert the file",
                path.display(),
                record.meta.format
            )))
        }
        _ => {}
    }

    let version = next_version();
    let info = MotionInfo {
        file: file.to_string(),
        path: path.display().to_string(),
        format: record.meta.format.to_string(),
        sha256: record.meta.sha256_hex.clone(),
        npts: record.meta.original_npts,
        dt_s: record.meta.original_dt_s,
        units: file_units.to_string(),
        scale_factor: 1.0,
        pga_m_s2: record.pga_m_s2(),
        duration_s: record.duration_s(),
        start_time_s: record.start_time_s,
        end_time_s: record.end_time_s(),
        warnings: record.warnings.clone(),
        processing: record.processing_log.clone(),
        newest_version: version,
    };
    let mut entries = log.lock().map_err(|_| runtime_error("internal lock"))?;
    entries.push(info);
    Ok(ScriptRecord {
        record: Arc::new(record),
        file: Arc::from(file),
        scale_factor: 1.0,
        log_slot: entries.len() - 1,
        version,
    })
}

/// Reads a rotation table for `load_rotation` (`units`: `"rad"` or `"deg"`, required) and
/// logs it beside the acceleration records (its peak angle in the processing log).
fn load_rotation(
    sandbox: &ReadSandbox,
    log: &MotionLog,
    file: &str,
    options: &Map,
) -> Result<ScriptRotation, Box<EvalAltResult>> {
    let fail = |message: String| runtime_error(format!("load_rotation(\"{file}\"): {message}"));
    let mut reader = MapReader::new("load_rotation options", options);
    let units = reader.str_or("units", "").map_err(fail)?;
    reader.finish().map_err(fail)?;
    if units.is_empty() {
        return Err(fail(format!(
            "state the angles' unit, e.g. load_rotation(\"{file}\", #{{units: \"deg\"}}) (\"rad\" or \"deg\")"
        )));
    }
    let unit = slosh_motion::AngleUnit::from_str(&units).map_err(|e| fail(e.to_string()))?;
    let path = sandbox.resolve(file).map_err(fail)?;
    let record = slosh_motion::read_rotation(&path, unit).map_err(|e| fail(e.to_string()))?;
    let mut processing = record.processing_log.clone();
    processing.push(format!("peak angle {:.6} rad", record.peak_angle_rad()));
    let duration = record.duration_s();
    let info = MotionInfo {
        file: file.to_string(),
        path: path.display().to_string(),
        format: ROTATION_TABLE.into(),
        sha256: record.sha256_hex.clone(),
        npts: record.len(),
        dt_s: duration / (record.len().max(2) - 1) as f64,
        units: unit.to_string(),
        scale_factor: 1.0,
        pga_m_s2: 0.0,
        duration_s: duration,
        start_time_s: 0.0,
        end_time_s: duration,
        warnings: Vec::new(),
        processing,
        newest_version: next_version(),
    };
    log.lock()
        .map_err(|_| runtime_error("internal lock"))?
        .push(info);
    Ok(ScriptRotation(Arc::new(record)))
}

/// Applies `op` to a copy of `from` (`op` returns the scale factor it applied, 1 when none)
/// and updates the log: in place when `from` is the newest record of its entry, else as a new
/// entry (a second branch of processing).
fn derive(
    log: &MotionLog,
    from: &ScriptRecord,
    method: &str,
    op: impl FnOnce(&mut Record) -> slosh_motion::Result<f64>,
) -> Result<ScriptRecord, Box<EvalAltResult>> {
    let mut record = (*from.record).clone();
    let factor = op(&mut record)
        .map_err(|e| runtime_error(format!("{method} on the record \"{}\": {e}", from.file)))?;
    let scale_factor = from.scale_factor * factor;
    let version = next_version();
    let mut entries = log.lock().map_err(|_| runtime_error("internal lock"))?;
    let slot = match entries.get(from.log_slot) {
        Some(e) if e.newest_version == from.version => from.log_slot,
        Some(e) => {
            let branch = e.clone();
            entries.push(branch);
            entries.len() - 1
        }
        None => return Err(runtime_error("internal: record log entry missing")),
    };
    let entry = &mut entries[slot];
    entry.scale_factor = scale_factor;
    entry.pga_m_s2 = record.pga_m_s2();
    entry.duration_s = record.duration_s();
    entry.start_time_s = record.start_time_s;
    entry.end_time_s = record.end_time_s();
    entry.processing = record.processing_log.clone();
    entry.newest_version = version;
    Ok(ScriptRecord {
        record: Arc::new(record),
        file: from.file.clone(),
        scale_factor,
        log_slot: slot,
        version,
    })
}

/// A sine with the paper's sign from `[A, ω]` or `[A, ω, φ]`: a_g = +A ω² sin(ωt + φ), i.e.
/// slosh_motion's [`Sine`] (displacement +A sin, acceleration −A ω² sin) with amplitude −A.
fn paper_sine(parts: &[Dynamic], what: &str) -> Result<Sine, Box<EvalAltResult>> {
    let amplitude = number(&parts[0], &format!("{what}: A"))?;
    let omega = number(&parts[1], &format!("{what}: omega"))?;
    let phase = match parts.get(2) {
        Some(p) => number(p, &format!("{what}: phase"))?,
        None => 0.0,
    };
    Ok(Sine {
        amplitude_m: -amplitude,
        omega_rad_s: omega,
        phase,
    })
}

/// `e` with every acceleration multiplied by `factor`.
fn scaled(e: &Excitation, factor: f64) -> Excitation {
    match e {
        Excitation::Zero => Excitation::Zero,
        Excitation::Record(r) => {
            let mut r = r.clone();
            r.scale(factor);
            Excitation::Record(r)
        }
        Excitation::Sine(s) => Excitation::Sine(Sine {
            amplitude_m: s.amplitude_m * factor,
            ..*s
        }),
        Excitation::SineSum(list) => Excitation::SineSum(
            list.iter()
                .map(|s| Sine {
                    amplitude_m: s.amplitude_m * factor,
                    ..*s
                })
                .collect(),
        ),
        Excitation::Sum(parts) => {
            Excitation::Sum(parts.iter().map(|p| scaled(p, factor)).collect())
        }
    }
}

fn record_part(r: &ScriptRecord) -> Excitation {
    Excitation::Record(Box::new((*r.record).clone()))
}

fn sum(a: Excitation, b: Excitation) -> ScriptExcitation {
    let mut parts = Vec::new();
    for e in [a, b] {
        match e {
            Excitation::Sum(inner) => parts.extend(inner),
            other => parts.push(other),
        }
    }
    ScriptExcitation(Arc::new(Excitation::Sum(parts)))
}

fn describe_record(r: &ScriptRecord) -> String {
    let rec = &r.record;
    format!(
        "Record(\"{}\": {} samples, dt {} s, {} to {} s, PGA {:.4} m/s2)",
        r.file,
        rec.len(),
        rec.dt_s,
        rec.start_time_s,
        rec.end_time_s(),
        rec.pga_m_s2()
    )
}

fn describe_excitation(e: &Excitation) -> String {
    match e {
        Excitation::Zero => "0".into(),
        Excitation::Record(r) => format!(
            "record \"{}\" ({} samples, PGA {:.4} m/s2)",
            r.meta.source_file,
            r.len(),
            r.pga_m_s2()
        ),
        Excitation::Sine(s) => describe_sine(s),
        Excitation::SineSum(list) => list
            .iter()
            .map(describe_sine)
            .collect::<Vec<_>>()
            .join(" + "),
        Excitation::Sum(parts) => parts
            .iter()
            .map(describe_excitation)
            .collect::<Vec<_>>()
            .join(" + "),
    }
}

fn describe_sine(s: &Sine) -> String {
    format!(
        "sine(A = {} m, omega = {} rad/s, phase = {} rad)",
        -s.amplitude_m, s.omega_rad_s, s.phase
    )
}
