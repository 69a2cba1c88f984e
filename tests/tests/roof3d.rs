//! 3D roof impacts: a cone-roof cylinder (`cylinder_3d.rhai`) and a mesh-roof
//! cylinder (`cylinder_mesh_roof.rhai`, the cone roof of `geometry/`) under a resonant sine
//! report a roof impact when the freeboard is small, and none when the roof is far above the
//! wave. Coarse lattice (8 particles per radius) and short runs: the test is about the roof
//! being found and loaded, not about the pressure's value.

use slosh_validation::{out_dir, run_script};

/// Common overrides: coarse, paper scheme (the fastest), 0.3 s settling + 1.7 s of a 2 cm
/// resonant sine (the wall crest passes 5 cm within the first two periods), no frames.
const COMMON: [&str; 6] = [
    "dx=0.0625",
    "scheme=paper",
    "settle=0.3",
    "duration=2.0",
    "amplitude=0.02",
    "frame_interval=0",
];

fn max_roof_p(script: &str, name: &str, extra: &[&str]) -> f64 {
    let out = out_dir(name);
    let mut sets: Vec<&str> = COMMON.to_vec();
    sets.extend_from_slice(extra);
    let s = run_script(script, &sets, &out).unwrap();
    eprintln!(
        "{name}: max roof p {:.0} Pa at t = {:.2} s, max roof force {:.1} N, {} impact(s)",
        s.max_roof_p,
        s.t_max_roof_p,
        s.max_roof_force_up,
        s.impacts.len()
    );
    s.max_roof_p
}

/// Cone roof: freeboard 0.0625 m (one lattice row) against 0.7 m.
#[test]
fn cone_roof_impact_only_with_small_freeboard() {
    let near = max_roof_p(
        "cylinder_3d.rhai",
        "cone_near",
        &["roof=cone", "depth=0.5", "tank_height=0.5625"],
    );
    let far = max_roof_p(
        "cylinder_3d.rhai",
        "cone_far",
        &["roof=cone", "depth=0.5", "tank_height=1.2"],
    );
    assert!(near > 0.0, "no roof impact with a 6 cm freeboard");
    assert_eq!(far, 0.0, "a roof 0.7 m above the still level was hit");
}

/// Mesh roof (cone-roofed cylinder mesh, shell 1.0 m): depth 0.9375 m against 0.375 m.
#[test]
fn mesh_roof_impact_only_with_small_freeboard() {
    let near = max_roof_p("cylinder_mesh_roof.rhai", "mesh_near", &["depth=0.9375"]);
    let far = max_roof_p("cylinder_mesh_roof.rhai", "mesh_far", &["depth=0.375"]);
    assert!(near > 0.0, "no roof impact with a 6 cm freeboard");
    assert_eq!(far, 0.0, "a roof 0.6 m above the still level was hit");
}
