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
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

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
}

/// Stops any evaluation by `engine` whose resident memory grows by more than `budget_bytes`.
pub(crate) fn cap_script_memory(engine: &mut Engine, budget_bytes: u64) {
    if resident_bytes().is_none() {
        return;
    }
    let watch = Arc::new(Mutex::new(Watch {
        last_operations: 0,
        baseline_bytes: None,
        last_check: Instant::now(),
    }));
    engine.on_progress(move |operations| {
        let mut w = watch.lock().ok()?;
        let now = Instant::now();
        if operations <= w.last_operations {
            w.baseline_bytes = None;
            w.last_check = now;
        }
        w.last_operations = operations;
        if now.duration_since(w.last_check) < CHECK_INTERVAL {
            return None;
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
