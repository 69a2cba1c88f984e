//! `slosh run` and `slosh resume`: a case run by `slosh-case` with the signals received by the
//! handlers of [`crate::interrupt`] as its stop request.

use anyhow::Result;
pub use slosh_case::{run_case_with_stop, RunOptions, Summary, TheoryNumbers, TEST_STOP_AT_ENV};
use slosh_script::Case;

/// Runs a case to the end (or to a blow-up, keeping what was written) and returns the summary.
/// SIGINT and SIGTERM stop it once [`crate::interrupt::install`] has installed the handlers.
pub fn run_case(case: Case, opts: &RunOptions) -> Result<Summary> {
    run_case_with_stop(case, opts, &mut crate::interrupt::received)
}
