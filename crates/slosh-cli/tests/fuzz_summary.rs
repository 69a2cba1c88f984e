//! Fuzzing the reading of `summary.ron` (what `slosh sweep` reads back from each case) with
//! proptest: a real summary with random edits (cut, spliced, duplicated, bytes changed),
//! deeply nested brackets and random bytes. Every outcome is columns or an error: no panic,
//! no stack overflow, no huge allocation.

#[path = "../../slosh-motion/tests/fuzz_support/mod.rs"]
mod fuzz_support;

use fuzz_support::{
    allocation_follows_input, cases, fuzz, largest_allocation_of, LargestAllocation,
};
use proptest::prelude::*;
use slosh_cli::sweep::summary_columns;

#[global_allocator]
static ALLOCATOR: LargestAllocation = LargestAllocation;

/// A summary as `slosh run` writes it, with a parameter and a post value.
fn real_summary() -> String {
    let mut summary = slosh_cli::Summary {
        status: "completed".into(),
        parameters: vec![("depth".into(), slosh_script::ParamValue::Float(0.5))],
        post: vec![("x".into(), slosh_script::ParamValue::Str("a".into()))],
        ..Default::default()
    };
    summary.max_roof_p = 1234.5;
    ron::ser::to_string_pretty(&summary, ron::ser::PrettyConfig::default()).unwrap()
}

#[derive(Debug, Clone)]
enum Edit {
    Cut(usize, usize),
    Insert(usize, String),
    Duplicate(usize, usize),
    Byte(usize, u8),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 0usize..200).prop_map(|(a, n)| Edit::Cut(a, n)),
        (any::<usize>(), "[\\[\\](){}:,\"a-z0-9. -]{0,20}").prop_map(|(a, s)| Edit::Insert(a, s)),
        (any::<usize>(), 0usize..300).prop_map(|(a, n)| Edit::Duplicate(a, n)),
        (any::<usize>(), any::<u8>()).prop_map(|(a, b)| Edit::Byte(a, b)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut bytes = text.as_bytes().to_vec();
    for e in edits {
        let len = bytes.len().max(1);
        match e {
            Edit::Cut(a, n) => {
                let a = a % len;
                let b = (a + n).min(bytes.len());
                if a < b {
                    bytes.drain(a..b);
                }
            }
            Edit::Insert(a, s) => {
                let a = (a % len).min(bytes.len());
                bytes.splice(a..a, s.bytes());
            }
            Edit::Duplicate(a, n) => {
                let a = (a % len).min(bytes.len());
                let b = (a + n).min(bytes.len());
                let copy = bytes[a..b].to_vec();
                bytes.splice(b..b, copy);
            }
            Edit::Byte(a, v) => {
                if !bytes.is_empty() {
                    let a = a % bytes.len();
                    bytes[a] = *v;
                }
            }
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

fn check(text: &str) -> Result<(), String> {
    let (_, largest) = largest_allocation_of(|| summary_columns(text, "summary.ron"));
    allocation_follows_input(largest, text.len(), 4096, 1 << 20)
}

#[test]
fn the_real_summary_gives_its_columns() {
    let columns = summary_columns(&real_summary(), "summary.ron").unwrap();
    assert!(
        columns
            .iter()
            .any(|(k, v)| k == "max_roof_p" && v.starts_with("1234.5")),
        "{columns:?}"
    );
    assert!(columns.iter().any(|(k, _)| k == "post_x"), "{columns:?}");
}

#[test]
fn fuzz_summary_reader() {
    let real = real_summary();
    let n = cases(20_000);
    fuzz(
        "summary.ron (edited)",
        n,
        prop::collection::vec(edit(), 1..6),
        |edits| check(&apply(&real, &edits)),
    );
    fuzz(
        "summary.ron (nested)",
        n / 10,
        (
            1usize..5000,
            prop::sample::select(vec!["[", "(", "{", "Some("]),
        ),
        |(depth, open)| check(&format!("{}{}", open.repeat(depth), real)),
    );
    fuzz(
        "summary.ron (random bytes)",
        n,
        prop::collection::vec(any::<u8>(), 0..600),
        |b| check(&String::from_utf8_lossy(&b)),
    );
}
