//! Stopping a run before its end: the caller's stop request (signals, Ctrl-C), the testing
//! aid `SLOSH_TEST_STOP_AT`, and the error a stopped run ends with.

use anyhow::Result;
use slosh_run::StopRequest;

/// A run stopped by a signal (SIGINT = 2, SIGTERM = 15, or the code a caller's stop request
/// gave); the command line exits with 128 + the signal (130, 143).
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

/// Environment variable of a testing aid: `SLOSH_TEST_STOP_AT=T` stops the run as a SIGTERM
/// would (checkpoint, `status: "interrupted"`, exit code 143) after the first step that ends
/// at or past the simulated time T (s). It makes an interruption land on a chosen step, so
/// that tests can check a resumed run against an uninterrupted one at set points; it applies
/// to the process it is set for (unset it before `slosh resume`).
pub const TEST_STOP_AT_ENV: &str = "SLOSH_TEST_STOP_AT";

/// The stop request of a run: the caller's (a SIGINT or SIGTERM received, Ctrl-C in Python),
/// or the time of [`TEST_STOP_AT_ENV`] reached.
pub(crate) struct RunStop<'s> {
    caller: &'s mut dyn StopRequest,
    stop_at_s: Option<f64>,
    time_reached: std::rc::Rc<std::cell::Cell<f64>>,
}

impl<'s> RunStop<'s> {
    /// The caller's stop request with the stop time of [`TEST_STOP_AT_ENV`] when it is set.
    pub(crate) fn from_env(
        caller: &'s mut dyn StopRequest,
        time_reached: std::rc::Rc<std::cell::Cell<f64>>,
    ) -> Result<Self> {
        let stop_at_s = match std::env::var(TEST_STOP_AT_ENV) {
            Ok(text) => match text.trim().parse::<f64>() {
                Ok(t) if t.is_finite() => Some(t),
                _ => {
                    anyhow::bail!("{TEST_STOP_AT_ENV}={text}: expected a simulated time in seconds")
                }
            },
            Err(_) => None,
        };
        Ok(RunStop {
            caller,
            stop_at_s,
            time_reached,
        })
    }
}

impl slosh_run::StopRequest for RunStop<'_> {
    fn stop_requested(&mut self) -> Option<i32> {
        self.caller.stop_requested().or_else(|| {
            self.stop_at_s
                .filter(|&t| self.time_reached.get() >= t)
                .map(|_| libc::SIGTERM)
        })
    }
}
