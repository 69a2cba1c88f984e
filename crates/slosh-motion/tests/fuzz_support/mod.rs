//! The fuzzing harness shared by the crates' `fuzz` tests (included with `#[path]`): runs a
//! bounded number of proptest cases of a target, catches panics (a panic fails the case and is
//! shrunk to a small input), measures the largest single allocation each case makes, and prints
//! the case count and time. `SLOSH_FUZZ_CASES=N` runs N cases per target instead of the default.
//! The cases are drawn from a fixed seed per target, so that the test suite gives the same
//! verdict on every run; `SLOSH_FUZZ_SEED=N` draws other cases and `SLOSH_FUZZ_SEED=random`
//! fresh ones (a fuzzing session rather than a regression test).

#![allow(dead_code)] // each test binary uses only some helpers

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::time::Instant;

/// The system allocator, noting the largest allocation each thread asks for.
pub struct LargestAllocation;

thread_local! {
    static LARGEST: Cell<usize> = const { Cell::new(0) };
}

fn note(size: usize) {
    let _ = LARGEST.try_with(|l| l.set(l.get().max(size)));
}

unsafe impl GlobalAlloc for LargestAllocation {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Runs `f` and returns the largest single allocation it made on this thread, bytes.
pub fn largest_allocation_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    LARGEST.with(|l| l.set(0));
    let out = f();
    (out, LARGEST.with(|l| l.get()))
}

/// Cases per target: `SLOSH_FUZZ_CASES` or `default`.
pub fn cases(default: u32) -> u32 {
    std::env::var("SLOSH_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Runs `target` on `cases` inputs drawn from `strategy`; fails with the (shrunk) input on a
/// panic or an `Err`. Prints `fuzz NAME: N cases in T s`.
pub fn fuzz<S: Strategy>(
    name: &str,
    cases: u32,
    strategy: S,
    target: impl Fn(S::Value) -> Result<(), String>,
) {
    let seed = match std::env::var("SLOSH_FUZZ_SEED").ok().as_deref() {
        Some("random") => RngSeed::Random,
        Some(n) => n.parse().map(RngSeed::Fixed).unwrap_or(RngSeed::Random),
        // The target's name, hashed (FNV-1a): a fixed stream of cases per target.
        None => RngSeed::Fixed(name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })),
    };
    let config = Config {
        cases,
        failure_persistence: None,
        rng_seed: seed,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let start = Instant::now();
    let result = runner.run(&strategy, |input| {
        target(input).map_err(TestCaseError::fail)
    });
    let seconds = start.elapsed().as_secs_f64();
    eprintln!("fuzz {name}: {cases} cases in {seconds:.2} s (seed {seed:?})");
    if let Err(e) = result {
        panic!("fuzz {name}: {e}");
    }
}

/// Checks that one call made no allocation larger than `per_input_byte` × the input length
/// plus `slack` bytes: what a reader reserves must follow the file, not a count it announces.
pub fn allocation_follows_input(
    largest: usize,
    input_len: usize,
    per_input_byte: usize,
    slack: usize,
) -> Result<(), String> {
    let bound = per_input_byte * input_len + slack;
    if largest > bound {
        Err(format!(
            "an allocation of {largest} bytes from an input of {input_len} bytes (bound {bound})"
        ))
    } else {
        Ok(())
    }
}
