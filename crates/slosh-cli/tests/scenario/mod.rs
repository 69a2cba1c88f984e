//! Scenarios that need something a developer's machine may lack (a Vulkan device, Slurm):
//! on such a machine the test passes and says, on the terminal, what it skipped and how to
//! run it; where `CI` is set (as `.ci/run` and CI services set it) the scenario is required
//! and its absence fails the test.

use std::io::Write;

/// Skips the scenario `what` (the test returns after this call), or fails the test under
/// `CI`. `why` says what is missing, `how` how to get it.
///
/// The line is written to the process's standard error directly, not through `eprintln!`,
/// which the test harness captures for passing tests: a skip must be seen.
pub fn skip_or_require(what: &str, why: &str, how: &str) {
    let ci = std::env::var_os("CI").is_some_and(|v| !v.is_empty() && v != "0" && v != "false");
    if ci {
        panic!("{what} is required where CI is set: {why}; {how}");
    }
    let line = format!("\nSKIPPED {what}: {why}. To run it: {how}\n");
    let _ = std::io::stderr().write_all(line.as_bytes());
}
