//! Fuzzing the mesh readers (OBJ, ASCII and binary STL) with proptest: random bytes and random
//! files of the right shape. No input may panic or allocate out of proportion to its size; a
//! mesh that is read can be checked, measured and oriented without a panic.

#[path = "../../slosh-motion/tests/fuzz_support/mod.rs"]
mod fuzz_support;

use fuzz_support::{
    allocation_follows_input, cases, fuzz, largest_allocation_of, LargestAllocation,
};
use proptest::prelude::*;
use slosh_geometry::SurfaceMesh;

#[global_allocator]
static ALLOCATOR: LargestAllocation = LargestAllocation;

const PER_BYTE: usize = 8192;
const SLACK: usize = 1 << 20;

fn coordinate() -> impl Strategy<Value = String> {
    prop_oneof![
        (-10.0f64..10.0).prop_map(|x| format!("{x}")),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        Just("nan".to_string()),
        Just("1e400".to_string()),
        "[ -~]{0,10}",
    ]
}

fn index() -> impl Strategy<Value = String> {
    prop_oneof![
        (-8i64..12).prop_map(|i| i.to_string()),
        any::<i64>().prop_map(|i| i.to_string()),
        (1i64..12, 1i64..5).prop_map(|(i, t)| format!("{i}/{t}/{t}")),
        "[ -~]{0,6}",
    ]
}

fn obj_file() -> impl Strategy<Value = Vec<u8>> {
    let line = prop_oneof![
        4 => prop::collection::vec(coordinate(), 0..5).prop_map(|c| format!("v {}", c.join(" "))),
        4 => prop::collection::vec(index(), 0..7).prop_map(|i| format!("f {}", i.join(" "))),
        1 => Just("# comment".to_string()),
        1 => Just("vn 0 0 1".to_string()),
        1 => "[ -~]{0,30}",
    ];
    prop::collection::vec(line, 0..60).prop_map(|lines| lines.join("\n").into_bytes())
}

fn ascii_stl_file() -> impl Strategy<Value = Vec<u8>> {
    let facet = (
        prop::collection::vec(prop::collection::vec(coordinate(), 3), 0..5),
        any::<bool>(),
    )
        .prop_map(|(corners, close)| {
            let mut s = String::from(" facet normal 0 0 1\n  outer loop\n");
            for c in corners {
                s.push_str(&format!("   vertex {}\n", c.join(" ")));
            }
            if close {
                s.push_str("  endloop\n endfacet\n");
            }
            s
        });
    prop::collection::vec(facet, 0..30)
        .prop_map(|f| format!("solid fuzz\n{}endsolid fuzz\n", f.concat()).into_bytes())
}

fn binary_stl_file() -> impl Strategy<Value = Vec<u8>> {
    (
        0u32..40,
        prop::collection::vec(any::<u8>(), 0..2000),
        any::<bool>(),
        any::<u32>(),
    )
        .prop_map(|(n, noise, honest, claimed)| {
            let mut bytes = vec![b' '; 80];
            bytes.extend_from_slice(&(if honest { n } else { claimed }).to_le_bytes());
            for k in 0..(50 * n as usize) {
                bytes.push(noise.get(k).copied().unwrap_or((k % 7) as u8));
            }
            bytes
        })
}

fn check(bytes: &[u8], extension: &str) -> Result<(), String> {
    let (result, largest) = largest_allocation_of(|| {
        let mut mesh = SurfaceMesh::parse(bytes, extension, "fuzz")?;
        let _ = mesh.check_closed("fuzz");
        let _ = (mesh.signed_volume(), mesh.area(), mesh.bounds());
        mesh.orient_outwards();
        Ok::<_, slosh_geometry::GeometryError>(mesh)
    });
    allocation_follows_input(largest, bytes.len(), PER_BYTE, SLACK)?;
    if let Err(e) = result {
        let message = e.to_string();
        if message.len() > 400 {
            return Err(format!(
                "an error message of {} bytes: {message}",
                message.len()
            ));
        }
    }
    Ok(())
}

#[test]
fn fuzz_obj_reader() {
    let n = cases(5000);
    fuzz("OBJ (shaped)", n, obj_file(), |bytes| check(&bytes, "obj"));
    fuzz(
        "OBJ (random bytes)",
        n,
        prop::collection::vec(any::<u8>(), 0..600),
        |bytes| check(&bytes, "obj"),
    );
}

#[test]
fn fuzz_stl_reader() {
    let n = cases(5000);
    fuzz("STL (ASCII shaped)", n, ascii_stl_file(), |bytes| {
        check(&bytes, "stl")
    });
    fuzz("STL (binary shaped)", n, binary_stl_file(), |bytes| {
        check(&bytes, "stl")
    });
    fuzz(
        "STL (random bytes)",
        n,
        prop::collection::vec(any::<u8>(), 0..600),
        |bytes| check(&bytes, "STL"),
    );
}
