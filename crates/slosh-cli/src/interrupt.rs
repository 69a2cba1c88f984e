//! SIGINT and SIGTERM (a cluster's time limit sends SIGTERM): the run finishes its step, keeps
//! its outputs and says it was interrupted; a second SIGINT stops at once.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// The signal received (0 = none), set by the handler.
static RECEIVED: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

/// Installs the handlers (once per process): the first SIGINT or SIGTERM is recorded for
/// [`received`]; a second SIGINT ends the process at once with exit code 130.
pub fn install() -> std::io::Result<()> {
    if RECEIVED.get().is_some() {
        return Ok(());
    }
    let received = Arc::new(AtomicUsize::new(0));
    let seen = Arc::new(AtomicBool::new(false));
    // Registered first, so that a second SIGINT finds the flag the first one set.
    signal_hook::flag::register_conditional_shutdown(libc::SIGINT, 130, Arc::clone(&seen))?;
    for signal in [libc::SIGINT, libc::SIGTERM] {
        signal_hook::flag::register_usize(signal, Arc::clone(&received), signal as usize)?;
        signal_hook::flag::register(signal, Arc::clone(&seen))?;
        // A script evaluation (the top level, `post`) and the sampling of the excitation
        // before a run stop on it too.
        signal_hook::flag::register(signal, slosh_script::stop_flag())?;
    }
    let _ = RECEIVED.set(received);
    Ok(())
}

/// The signal (SIGINT = 2, SIGTERM = 15) received since [`install`], if any.
pub fn received() -> Option<i32> {
    RECEIVED
        .get()
        .map(|r| r.load(Ordering::SeqCst) as i32)
        .filter(|&s| s != 0)
}

/// A run or sweep stopped by a signal; its exit code is 128 + the signal (130, 143).
pub use slosh_case::Interrupted;
