//! Fuzzing the script API with proptest: random short scripts of valid syntax that call the
//! host functions (`param`, `tank`, `numerics`, `run`, `gauge`, `load_record`, `sine`, record
//! methods, `ground_accel`, `post`) with random arguments, loaded through `load_case` as
//! `slosh run` loads them, then asked for the ground acceleration and the post-processing.
//! Every outcome must be a value or a `ScriptError`: no panic, no abort, no huge allocation.

#[path = "../../slosh-motion/tests/fuzz_support/mod.rs"]
mod fuzz_support;

use fuzz_support::{cases, fuzz, largest_allocation_of, LargestAllocation};
use proptest::prelude::*;
use slosh_script::{load_case, CaseOptions, RunData};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Scripts that loaded into a case (the others were refused with a `ScriptError`).
static LOADED: AtomicUsize = AtomicUsize::new(0);

#[global_allocator]
static ALLOCATOR: LargestAllocation = LargestAllocation;

/// Largest single allocation a script case may make (the records it can read are tiny).
const LARGEST_ALLOCATION: usize = 256 << 20;

/// A Rhai literal: numbers of every size and sign, booleans, strings, unit, arrays, maps.
fn literal() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        any::<i64>().prop_map(|i| format!("({i})")),
        (-3.0f64..3.0).prop_map(|x| format!("({x:.4})")),
        any::<f64>()
            .prop_filter("finite", |x| x.is_finite())
            .prop_map(|x| format!("({x:.3e})")),
        (0i64..5).prop_map(|i| i.to_string()),
        Just("0.0".to_string()),
        Just("true".to_string()),
        Just("()".to_string()),
        "[a-z_]{0,8}".prop_map(|s| format!("\"{s}\"")),
        prop_oneof![
            Just("rect"),
            Just("cylinder"),
            Just("box"),
            Just("paper"),
            Just("modern"),
            Just("dome"),
            Just("cone"),
            Just("flat"),
            Just("none"),
            Just("offset"),
        ]
        .prop_map(|s| format!("\"{s}\"")),
    ];
    leaf.prop_recursive(2, 8, 3, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..3).prop_map(|v| format!("[{}]", v.join(", "))),
            prop::collection::vec(("[a-z]{1,6}", inner), 0..3).prop_map(|kv| {
                let fields: Vec<String> =
                    kv.into_iter().map(|(k, v)| format!("{k}: {v}")).collect();
                format!("#{{{}}}", fields.join(", "))
            }),
        ]
    })
}

/// A map literal with some of `keys` (and now and then an unknown key).
fn options(keys: &'static [&'static str]) -> impl Strategy<Value = String> {
    prop::collection::vec((prop::sample::select(keys), literal()), 0..6).prop_map(|kv| {
        let mut seen = Vec::new();
        let fields: Vec<String> = kv
            .into_iter()
            .filter(|(k, _)| {
                let fresh = !seen.contains(k);
                seen.push(*k);
                fresh
            })
            .map(|(k, v)| format!("{k}: {v}"))
            .collect();
        format!("#{{{}}}", fields.join(", "))
    })
}

const TANK_KEYS: &[&str] = &[
    "shape",
    "width",
    "height",
    "depth",
    "roof",
    "layout",
    "tilt",
    "tilt_shape",
    "lattice",
    "radius",
    "roof_rise",
    "length",
    "breadth",
    "colour",
];
const NUMERICS_KEYS: &[&str] = &[
    "scheme",
    "dx",
    "dt",
    "h_over_dx",
    "cfl_number",
    "viscosity",
    "gravity",
    "smoothing_steps",
    "neighbour_search",
    "kernel",
    "eos_gamma",
];
const RUN_KEYS: &[&str] = &[
    "settle",
    "duration",
    "output_interval",
    "frame_interval",
    "speed",
];
const RECORD_KEYS: &[&str] = &["format", "units", "dt"];
const RECORD_PATHS: &[&str] = &[
    "small.at2",
    "small.csv",
    "missing.at2",
    "../small.at2",
    "/etc/passwd",
    "",
    ".",
    "sub/../small.at2",
];
const RECORD_METHODS: &[(&str, usize)] = &[
    ("scale", 1),
    ("scale_to_pga", 1),
    ("remove_mean", 0),
    ("detrend", 1),
    ("bandpass", 2),
    ("highpass", 1),
    ("lowpass", 1),
    ("trim", 2),
    ("shift", 1),
    ("pga", 0),
    ("duration", 0),
    ("npts", 0),
    ("at", 1),
];

/// One top-level statement calling a host function.
fn statement() -> impl Strategy<Value = String> {
    prop_oneof![
        ("[a-z]{1,5}", literal()).prop_map(|(n, v)| format!("let p_{n} = param(\"{n}\", {v});")),
        options(TANK_KEYS).prop_map(|m| format!("tank({m});")),
        options(NUMERICS_KEYS).prop_map(|m| format!("numerics({m});")),
        options(RUN_KEYS).prop_map(|m| format!("run({m});")),
        ("[a-z_]{0,6}", literal()).prop_map(|(n, x)| format!("gauge(\"{n}\", {x});")),
        ("[a-z_]{0,6}", literal(), literal())
            .prop_map(|(n, x, y)| format!("gauge(\"{n}\", {x}, {y});")),
        (prop::sample::select(RECORD_PATHS), options(RECORD_KEYS))
            .prop_map(|(p, m)| format!("let rec = load_record(\"{p}\", {m});")),
        (literal(), literal()).prop_map(|(a, w)| format!("let sn = sine({a}, {w});")),
        (literal(), literal(), literal())
            .prop_map(|(a, w, f)| format!("let sn = sine({a}, {w}, {f});")),
        (prop::sample::select(RECORD_METHODS), literal(), literal()).prop_map(
            |((m, arity), a, b)| {
                let args = [a, b];
                format!("let rec2 = rec.{m}({});", args[..arity].join(", "))
            }
        ),
    ]
}

/// The body of `fn ground_accel(t)`.
fn accel_body() -> impl Strategy<Value = String> {
    prop_oneof![
        literal(),
        Just("sn.at(t)".to_string()),
        Just("rec.at(t)".to_string()),
        Just("(sn + rec).at(t)".to_string()),
        (literal(), literal()).prop_map(|(a, b)| format!("[{a}, {b}]")),
        literal().prop_map(|a| format!("{a} * sin(t)")),
    ]
}

fn script() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(statement(), 0..8),
        prop::option::of(accel_body()),
        prop::option::of(literal()),
        any::<bool>(),
    )
        .prop_map(|(statements, accel, post, tank_first)| {
            let mut s = String::new();
            if tank_first {
                s.push_str("tank(#{ shape: \"rect\", width: 1.0, height: 1.0, depth: 0.5 });\n");
            }
            for st in statements {
                s.push_str(&st);
                s.push('\n');
            }
            if let Some(body) = accel {
                s.push_str(&format!("fn ground_accel(t) {{ {body} }}\n"));
            }
            if let Some(value) = post {
                s.push_str(&format!(
                    "fn post(run) {{ #{{ x: {value}, n: run.summary.len() }} }}\n"
                ));
            }
            s
        })
}

fn workspace(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(
        dir.join("small.at2"),
        "t\nt\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 6, DT= 0.01\n0 0.1 -0.2 0.3 -0.1 0\n",
    )
    .unwrap();
    std::fs::write(dir.join("small.csv"), "0 0.1\n0.01 0.2\n0.02 -0.1\n").unwrap();
}

/// Loads the script as `slosh run` does and exercises what it defines.
fn exercise(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| e.to_string())?;
    let options = CaseOptions {
        script_memory_bytes: Some(64 << 20),
        ..CaseOptions::default()
    };
    let (_, largest) = largest_allocation_of(|| {
        if let Ok(mut case) = load_case(path, &options) {
            LOADED.fetch_add(1, Ordering::Relaxed);
            for t in [0.0, 0.005, 1.0, -1.0, f64::MAX] {
                let _ = case.excitation.ground_accel(t);
            }
            let _ = case.excitation.post(&RunData::default());
        }
    });
    if largest > LARGEST_ALLOCATION {
        return Err(format!("an allocation of {largest} bytes"));
    }
    Ok(())
}

#[test]
fn fuzz_script_api() {
    let dir: PathBuf =
        std::env::temp_dir().join(format!("slosh-script-fuzz-{}", std::process::id()));
    workspace(&dir);
    let path = dir.join("case.rhai");
    fuzz("script API", cases(2000), script(), |text| {
        exercise(&path, &text)
    });
    eprintln!(
        "fuzz script API: {} scripts loaded into a case, the rest refused with a message",
        LOADED.load(Ordering::Relaxed)
    );
}

#[test]
fn deeply_nested_scripts_are_refused_not_aborted() {
    let dir = std::env::temp_dir().join(format!("slosh-script-deep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("deep.rhai");
    let n = 100_000;
    for text in [
        format!("let x = {}1{};", "(".repeat(n), ")".repeat(n)),
        format!("let x = {}{};", "[".repeat(n), "]".repeat(n)),
        format!("let x = {}1;", "- ".repeat(n)),
        format!("let x = 1{};", " + 1".repeat(n)),
        format!("if true {}{}", "{".repeat(n), "}".repeat(n)),
        "fn f(x) { f(x + 1) }\nlet y = f(0);".to_string(),
    ] {
        std::fs::write(&path, &text).unwrap();
        let message = match load_case(&path, &CaseOptions::default()) {
            Ok(_) => panic!("a deeply nested script was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(message.contains("deep.rhai:"), "{message}");
    }
}
