//! The 2D foundation (paper §3.1) run through its case script: the paper's particle layout.
//! The physics of the same script (free-sloshing periods, the resonant 12 s case) is judged
//! by `slosh validate` (its stage "shipped scripts: the paper's §3.1 case").

use slosh_validation::{out_dir, run_script};

/// The paper's layout reproduces its particle count: 51 × 26 fluid + a closed 3-layer ring
/// of 57² − 51² = 648 wall particles = 1,974 (exact, a count).
#[test]
fn paper_layout_has_1974_particles() {
    let out = out_dir("paper_layout_count");
    let s = run_script(
        "paper_2d_sloshing.rhai",
        &["layout=paper", "duration=0.002", "frame_interval=0"],
        &out,
    )
    .unwrap();
    assert_eq!(s.particles_fluid, 1326);
    assert_eq!(s.particles_fluid + s.particles_wall, 1974);
}
