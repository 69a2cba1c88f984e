//! A cap on the memory a script may take, in total: Rhai limits each array, map and string
//! (nested values counted), but a script may hold many of them at once. While a script runs,
//! the process's resident memory is read at most once a millisecond and the evaluation is
//! stopped when it has grown by more than the budget since the evaluation started.
//!
//! One operation can add at most one value of the largest size Rhai allows (and filling it
//! takes longer than the interval between checks), so the overshoot is bounded by about one
//! such value. The resident memory is read from `/proc/self/status`; where that file does not
//! exist (not Linux) only Rhai's per-value limits apply.

use rhai::{Dynamic, Engine};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// Set by the front end's signal handler (SIGINT, SIGTERM): a script evaluation that has run
/// longer than [`STOPPABLE_AFTER`] stops at its next operation, and the sampling of the
/// excitation before a run stops. A run's per-step `ground_accel` calls are far shorter, so a
/// signal during the run still ends it at a step with its checkpoint.
pub fn stop_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    Arc::clone(FLAG.get_or_init(|| Arc::new(AtomicBool::new(false))))
}

/// True once [`stop_flag`] is set.
pub fn stop_requested() -> bool {
    stop_flag().load(Ordering::Relaxed)
}

/// An evaluation this old (its top level, `post`) is stopped by a signal.
const STOPPABLE_AFTER: Duration = Duration::from_millis(200);

/// Default cap on the memory one evaluation of a script (its top level, one `ground_accel`
/// call or `post`) may add to the process: 2 GiB.
pub const SCRIPT_MEMORY_BUDGET_BYTES: u64 = 2 << 30;

/// Interval between two readings of the resident memory during an evaluation.
const CHECK_INTERVAL: Duration = Duration::from_millis(1);

/// The start of the memory being watched in the current evaluation.
struct Watch {
    /// Operations counted by the previous call (a smaller count starts a new evaluation).
    last_operations: u64,
    /// Resident memory at the first reading of this evaluation, bytes.
    baseline_bytes: Option<u64>,
    /// Time of the previous reading (or of the start of the evaluation).
    last_check: Instant,
    /// Start of the evaluation.
    started: Instant,
}

/// Stops any evaluation by `engine` whose resident memory grows by more than `budget_bytes`,
/// or that has run longer than [`STOPPABLE_AFTER`] when a signal asked the process to stop.
pub(crate) fn cap_script_memory(engine: &mut Engine, budget_bytes: u64) {
    let watch = Arc::new(Mutex::new(Watch {
        last_operations: 0,
        baseline_bytes: None,
        last_check: Instant::now(),
        started: Instant::now(),
    }));
    let stop = stop_flag();
    engine.on_progress(move |operations| {
        let mut w = watch.lock().ok()?;
        let now = Instant::now();
        if operations <= w.last_operations {
            w.baseline_bytes = None;
            w.last_check = now;
            w.started = now;
        }
        w.last_operations = operations;
        if now.duration_since(w.last_check) < CHECK_INTERVAL {
            return None;
        }
        if stop.load(Ordering::Relaxed) && now.duration_since(w.started) >= STOPPABLE_AFTER {
            return Some(Dynamic::from(
                "the script's evaluation was stopped by a signal (SIGINT or SIGTERM)".to_string(),
            ));
        }
        w.last_check = now;
        let resident = resident_bytes()?;
        let baseline = *w.baseline_bytes.get_or_insert(resident);
        let grown = resident.saturating_sub(baseline);
        (grown > budget_bytes).then(|| Dynamic::from(over_budget_message(grown, budget_bytes)))
    });
}

fn over_budget_message(grown_bytes: u64, budget_bytes: u64) -> String {
    const MIB: f64 = (1u64 << 20) as f64;
    format!(
        "the script takes more than {:.0} MiB of memory ({:.0} MiB so far in this evaluation): \
         scripts are capped so that a case cannot exhaust the machine; build fewer or smaller \
         arrays, maps and strings",
        budget_bytes as f64 / MIB,
        grown_bytes as f64 / MIB
    )
}

/// The process's resident memory, bytes (`VmRSS` of `/proc/self/status`), when known.
fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
