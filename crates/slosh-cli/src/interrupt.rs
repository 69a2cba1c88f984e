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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Interrupted {
    /// The signal number.
    pub signal: i32,
}

impl Interrupted {
    /// The conventional exit code, 128 + signal.
    pub fn exit_code(&self) -> u8 {
        (128 + self.signal).clamp(0, 255) as u8
    }

    /// The signal's name.
    pub fn name(&self) -> &'static str {
        match self.signal {
            libc::SIGINT => "SIGINT",
            libc::SIGTERM => "SIGTERM",
            _ => "a signal",
        }
    }
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted by {}", self.name())
    }
}

impl std::error::Error for Interrupted {}
