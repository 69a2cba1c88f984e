//! The script's total memory is capped, not only each array: a map of 40 arrays of 9M
//! numbers (each array within Rhai's per-value limit) stops with a clear message.

use slosh_script::{load_case, CaseOptions};
use std::time::Instant;

#[test]
fn a_map_of_forty_large_arrays_is_stopped_with_a_message() {
    let dir = std::env::temp_dir().join(format!("slosh-script-memory-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("hog.rhai");
    std::fs::write(
        &path,
        "let m = #{};\n\
         for i in 0..40 { let a = []; a.pad(9000000, 0.0); m[`a${i}`] = a; }\n\
         tank(#{ shape: \"rect\", width: 1.0, height: 1.0, depth: 0.5 });\n",
    )
    .unwrap();
    // A budget of 512 MiB keeps the test light; the default (2 GiB) stops it the same way.
    let options = CaseOptions {
        script_memory_bytes: Some(512 << 20),
        ..CaseOptions::default()
    };
    let start = Instant::now();
    let message = match load_case(&path, &options) {
        Ok(_) => panic!("the script should have been stopped"),
        Err(e) => e.to_string(),
    };
    eprintln!(
        "stopped after {:.2} s: {message}",
        start.elapsed().as_secs_f64()
    );
    assert!(message.contains("hog.rhai:2:"), "{message}");
    assert!(message.contains("more than 512 MiB of memory"), "{message}");
}
