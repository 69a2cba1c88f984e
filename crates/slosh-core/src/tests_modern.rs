//! Checks of the switchable "modern" scheme parts against the paper scheme, and the
//! guard that the paper scheme (`SphParams::default()`) stays bit-for-bit what it was.

use crate::test_tank::box_tank_for;
use crate::{Simulation, SphParams, Vector};

/// Fingerprint of a run: serial sums (in original particle order) of density, position and
/// velocity, plus the largest wall pressure of the last recorded step, as raw bits.
pub(crate) fn fingerprint<const D: usize>(sim: &Simulation<D>) -> Vec<u64> {
    let f = sim.fluid();
    let mut order: Vec<usize> = (0..f.id.len()).collect();
    order.sort_by_key(|&i| f.id[i]);
    let (mut rho, mut x, mut v) = (0.0f64, 0.0f64, 0.0f64);
    for &i in &order {
        rho += f.density[i];
        x += f.position[i]
            .iter()
            .enumerate()
            .map(|(k, c)| (k + 1) as f64 * c)
            .sum::<f64>();
        v += f.velocity[i]
            .iter()
            .enumerate()
            .map(|(k, c)| (k + 1) as f64 * c)
            .sum::<f64>();
    }
    let pmax = sim
        .loads()
        .instantaneous_pressure()
        .iter()
        .fold(0.0f64, |a, &b| a.max(b));
    let wall_rho: f64 = sim.walls().density.iter().sum();
    vec![
        rho.to_bits(),
        x.to_bits(),
        v.to_bits(),
        pmax.to_bits(),
        wall_rho.to_bits(),
        sim.time().to_bits(),
    ]
}

fn paper_run_2d() -> Vec<u64> {
    let setup = box_tank_for::<2>(
        &SphParams::default().with_paper_stiffness(),
        [0.4, 0.4],
        0.2,
        0.02,
        0.02,
    );
    let mut sim = Simulation::new(setup, SphParams::default().with_paper_stiffness()).unwrap();
    for _ in 0..300 {
        let t = sim.time();
        sim.step(Vector::<2>::new(2.0 * (10.0 * t).sin(), 0.0))
            .unwrap();
    }
    fingerprint(&sim)
}

fn paper_run_3d() -> Vec<u64> {
    let setup = box_tank_for::<3>(
        &SphParams::default().with_paper_stiffness(),
        [0.2, 0.1, 0.2],
        0.1,
        0.01,
        0.02,
    );
    let mut sim = Simulation::new(setup, SphParams::default().with_paper_stiffness()).unwrap();
    for _ in 0..100 {
        let t = sim.time();
        sim.step(Vector::<3>::new(2.0 * (10.0 * t).sin(), 1.0, 0.0))
            .unwrap();
    }
    fingerprint(&sim)
}

/// The paper scheme must stay bit-for-bit what it was before the modern parts were added:
/// 300 steps of a sloshing 2D box and 100 steps of a 3D box under a varying ground
/// acceleration, compared by the raw bits of density, position and velocity sums, the largest
/// wall-load pressure, the summed wall density and the time (recorded with
/// `print_paper_fingerprints` on the code before the modern parts were added). Since the neighbour grid changed
/// (cells of h instead of 2h) the neighbours are summed in another order, so the results are
/// compared within round-off: 1e-9 relative after 300 steps (observed ≤ 2e-12; a change of
/// physics moves these sums by far more).
#[test]
fn paper_scheme_unchanged() {
    assert_within_roundoff(
        paper_run_2d(),
        vec![
            4686111422276112877,
            4635239767663433213,
            4620371257310559874,
            4656763910125384472,
            4688461039301316636,
            4589903455283922866,
        ],
    );
    assert_within_roundoff(
        paper_run_3d(),
        vec![
            4687821807634079451,
            4635822845646980168,
            4626863973515163110,
            4657567742936700002,
            4702199742855703306,
            4582663923102519742,
        ],
    );
}

fn assert_within_roundoff(measured: Vec<u64>, recorded: Vec<u64>) {
    assert_eq!(measured.len(), recorded.len());
    for (m, r) in measured.iter().zip(&recorded) {
        let (m, r) = (f64::from_bits(*m), f64::from_bits(*r));
        assert!(
            (m - r).abs() <= 1e-9 * r.abs().max(1e-300),
            "fingerprint {m} differs from the recorded {r} beyond round-off"
        );
    }
}

/// Records the fingerprints (run once before the modern parts were added; the constants of
/// `paper_scheme_unchanged` come from it).
#[test]
#[ignore]
fn print_paper_fingerprints() {
    eprintln!("2D {:?}", paper_run_2d());
    eprintln!("3D {:?}", paper_run_3d());
}

// ----- measurements: paper vs modern -----

use crate::{BoundaryMethod, DensityDiffusion, DensityMethod, Integrator, KernelKind};

/// The modern preset.
pub(crate) fn modern_params() -> SphParams {
    SphParams::modern().with_paper_stiffness()
}

/// First-mode circular frequency of a rectangular tank of width L, depth H (potential theory).
fn omega1(width: f64, depth: f64, g: f64) -> f64 {
    let k = std::f64::consts::PI / width;
    (g * k * (k * depth).tanh()).sqrt()
}

/// Free sloshing from a tilted surface (tilt at the left wall): the period of the fluid's
/// centre-of-mass oscillation along x, from its crossings of the tank centre line (the first
/// crossing skipped). Returns (period, theory, relative error).
pub(crate) fn free_sloshing_period(
    params: SphParams,
    width: f64,
    depth: f64,
    dx: f64,
) -> (f64, f64, f64) {
    let setup = box_tank_for::<2>(&params, [width, 2.0 * depth], depth, 0.02, dx);
    let mut sim = Simulation::new(setup, params).unwrap();
    let h_still = sim.still_level();
    let theory = 2.0 * std::f64::consts::PI / omega1(width, h_still, sim.params().gravity);
    let centre = 0.5 * width;
    let com = |s: &Simulation<2>| {
        s.fluid().position.iter().map(|x| x[0]).sum::<f64>() / s.fluid().position.len() as f64
            - centre
    };
    let mut crossings = Vec::new();
    let (mut t_prev, mut c_prev) = (sim.time(), com(&sim));
    while sim.time() < 2.3 * theory {
        sim.step(Vector::<2>::zeros()).unwrap();
        let (t, c) = (sim.time(), com(&sim));
        if c_prev.signum() != c.signum() && c != 0.0 {
            crossings.push(t_prev + (t - t_prev) * c_prev / (c_prev - c));
        }
        (t_prev, c_prev) = (t, c);
    }
    assert_eq!(
        sim.fluid_inside(),
        sim.fluid().position.len(),
        "particles left the tank"
    );
    assert!(crossings.len() >= 4, "too few crossings: {crossings:?}");
    let k = crossings.len() - 1;
    let period = 2.0 * (crossings[k] - crossings[1]) / (k - 1) as f64;
    (period, theory, period / theory - 1.0)
}

/// Hydrostatics after `t_end` s of settling in a 1.0 m × 1.0 m tank filled to 0.5 m:
/// least-squares slope of p against ρ0 g d (d below the still level) and the RMS of
/// p − ρ0 g d over all fluid particles, normalised by ρ0 g H.
pub(crate) fn hydrostatics(params: SphParams, t_end: f64) -> (f64, f64) {
    let setup = box_tank_for::<2>(&params, [1.0, 1.0], 0.5, 0.0, 0.02);
    let mut sim = Simulation::new(setup, params).unwrap();
    while sim.time() < t_end {
        sim.step(Vector::<2>::zeros()).unwrap();
    }
    let (rho0, g, level) = (
        sim.params().rest_density,
        sim.params().gravity,
        sim.still_level(),
    );
    let (mut sxy, mut sxx, mut s2) = (0.0, 0.0, 0.0);
    let n = sim.fluid().position.len() as f64;
    for (x, p) in sim.fluid().position.iter().zip(&sim.fluid().pressure) {
        let theory = rho0 * g * (level - x[1]);
        sxy += theory * p;
        sxx += theory * theory;
        s2 += (p - theory) * (p - theory);
    }
    (sxy / sxx, (s2 / n).sqrt() / (rho0 * g * level))
}

/// The resonant paper case (§3.1: 1.0 m × 1.0 m tank, H = 0.5 m, A = 0.0093 m,
/// ω = 5.311 rad/s) after `settle` s at rest: largest crest at the left wall during each
/// of the excitation windows ending at `marks` (s of excitation).
fn resonant_crests(params: SphParams, settle: f64, marks: &[f64]) -> Vec<f64> {
    let setup = box_tank_for::<2>(&params, [1.0, 1.0], 0.5, 0.0, 0.02);
    let mut sim = Simulation::new(setup, params).unwrap();
    let level = sim.still_level();
    let (a, w) = (0.0093, 5.311);
    let mut crest: f64 = 0.0;
    let mut out = Vec::new();
    let mut next = 0;
    let end = settle + marks[marks.len() - 1];
    while sim.time() < end {
        let t = sim.time() - settle;
        let ag = if t < 0.0 {
            0.0
        } else {
            // the paper's convention (as `slosh validate`): ground acceleration +Aω² sin ωt,
            // the liquid feels −Aω² sin ωt
            a * w * w * (w * t).sin()
        };
        sim.step(Vector::<2>::new(ag, 0.0)).unwrap();
        if sim.time() > settle {
            if let Some(z) = sim.surface_level_at(&[0.02]) {
                crest = crest.max(z - level);
            }
        }
        if sim.time() - settle >= marks[next] {
            out.push(crest);
            next += 1;
        }
    }
    assert_eq!(
        sim.fluid_inside(),
        sim.fluid().position.len(),
        "particles left the tank"
    );
    out
}

/// Modern preset: first-mode period within 1.5 % of potential theory in two tanks of aspect
/// ratio 2:1 (1.0 × 0.5 m and 0.6 × 0.3 m, dx = 0.02 m, 0.02 m initial tilt).
#[test]
fn modern_free_sloshing_period() {
    for (w, d) in [(1.0, 0.5), (0.6, 0.3)] {
        let (t, th, err) = free_sloshing_period(modern_params(), w, d, 0.02);
        eprintln!(
            "modern {w}x{d}: T = {t:.4} s, theory {th:.4} s, error {:+.2} %",
            100.0 * err
        );
        assert!(err.abs() < 0.015, "period error {err}");
    }
}

/// Modern preset: hydrostatic slope within 2 % of ρg and a pressure scatter about the
/// hydrostatic line below 2 % of ρ g H (the paper scheme's is ≈ 10–20 %, see
/// `explore_paper_vs_modern`).
#[test]
fn modern_hydrostatics() {
    let (slope, scatter) = hydrostatics(modern_params(), 1.0);
    eprintln!(
        "modern hydrostatics: slope {slope:.4}, scatter {:.3} % of rho g H",
        100.0 * scatter
    );
    assert!((slope - 1.0).abs() < 0.02, "slope {slope}");
    assert!(scatter < 0.02, "scatter {scatter}");
}

/// Continuity density starts the liquid in its own Tait compression: the volume the particles
/// occupy, Σ m/ρ, is the width times the compressed height H' of the column (closed form,
/// `TaitColumn::compressed_depth`), within 1e-6 (the midpoint rule over each particle's slab, an error of
/// order (dx/H)² (ρ0 g H/B)², far below); the top row stands dx/2 of compressed liquid under
/// the still level, and each particle's pressure is ρ0 g times the fill depth above its
/// lattice row (the weight above it). The paper's stiffness in a 0.5 m tank compresses it by
/// ≈ 0.24 %, ≈ 1.2 mm, well above round-off.
#[test]
fn liquid_starts_in_its_own_compression() {
    let (width, depth, dx) = (0.4, 0.2, 0.02);
    let setup = box_tank_for::<2>(&modern_params(), [width, 0.4], depth, 0.0, dx);
    let sim = Simulation::new(setup, modern_params()).unwrap();
    let p = sim.params();
    let column = crate::sound_speed::TaitColumn::of(p);
    let compressed = |d: f64| column.compressed_depth(d);
    let f = sim.fluid();
    let volume: f64 = f.density.iter().map(|rho| sim.particle_mass() / rho).sum();
    let expected = width * compressed(depth);
    assert!(
        (volume / expected - 1.0).abs() < 1e-6,
        "{volume} vs {expected}"
    );
    assert!(
        depth - compressed(depth) > 1e-4,
        "the test needs a visible compression"
    );
    let still = sim.still_level();
    let floor = sim.interior_bounds().0.y;
    assert!((still - floor - compressed(depth)).abs() < 1e-12);
    let top = f.position.iter().map(|x| x.y).fold(f64::MIN, f64::max);
    assert!(
        (still - top - compressed(0.5 * dx)).abs() < 1e-12,
        "top row at {top}"
    );
    for (x, pressure) in f.position.iter().zip(&f.pressure) {
        // The lattice row this particle came from: its compressed depth inverted.
        let row = ((still - x.y) / dx - 0.5).round();
        let weight = p.rest_density * p.gravity * (row + 0.5) * dx;
        assert!(
            (pressure / weight - 1.0).abs() < 1e-9,
            "{pressure} vs {weight}"
        );
    }
}

/// Modern preset: the resonant paper case's crest at the left wall (gauge at x = 0.02 m)
/// during the first 2 s of excitation against linear theory (0.052 m, the crest at 1.77 s),
/// within 25 %. (An earlier version of this harness applied the excitation with the
/// opposite sign, so its first large left-wall crest came half a period earlier, at ≈ 1.2 s,
/// and read 0.036 m against a theory value of the other sign's timing.)
#[test]
fn modern_resonant_crest() {
    let crests = resonant_crests(modern_params(), 0.5, &[2.0]);
    eprintln!(
        "modern resonant crest at 2 s: {:.4} m (linear theory 0.052 m)",
        crests[0]
    );
    assert!(
        (crests[0] / 0.052 - 1.0).abs() < 0.25,
        "crest {}",
        crests[0]
    );
}

/// Exploration (prints the figures of the report): paper vs modern side by side.
#[test]
#[ignore]
fn explore_paper_vs_modern() {
    for (name, p) in [
        ("paper", SphParams::default().with_paper_stiffness()),
        ("modern", modern_params()),
    ] {
        for (w, d) in [(1.0, 0.5), (0.6, 0.3)] {
            let (t, th, err) = free_sloshing_period(p.clone(), w, d, 0.02);
            eprintln!(
                "{name} period {w}x{d}: {t:.4} s vs {th:.4} s ({:+.2} %)",
                100.0 * err
            );
        }
        let (slope, scatter) = hydrostatics(p.clone(), 1.0);
        eprintln!(
            "{name} hydrostatics: slope {slope:.4}, scatter {:.2} %",
            100.0 * scatter
        );
        let crests = resonant_crests(p.clone(), 2.0, &[2.0, 5.0, 10.0]);
        eprintln!("{name} resonant crests at 2/5/10 s: {crests:.4?} (linear 0.052/0.144/0.288)");
    }
}

/// Exploration: hydrostatic state of single switches, to see each part's effect.
#[test]
#[ignore]
fn explore_switches_hydrostatic() {
    let base = SphParams::default().with_paper_stiffness();
    let m = modern_params();
    let variants: Vec<(&str, SphParams)> = vec![
        ("modern", m.clone()),
        (
            "modern leapfrog",
            SphParams {
                integrator: Integrator::LeapFrog,
                ..m.clone()
            },
        ),
        (
            "modern dynamic walls",
            SphParams {
                boundary: BoundaryMethod::Dynamic,
                ..m.clone()
            },
        ),
        (
            "modern no diffusion",
            SphParams {
                density_diffusion: DensityDiffusion::None,
                ..m.clone()
            },
        ),
        (
            "modern summation",
            SphParams {
                density: DensityMethod::Summation,
                clamp_negative_pressure: true,
                ..m.clone()
            },
        ),
        (
            "paper + adami",
            SphParams {
                boundary: BoundaryMethod::Adami,
                ..base.clone()
            },
        ),
        (
            "paper + symplectic",
            SphParams {
                integrator: Integrator::Symplectic,
                ..base.clone()
            },
        ),
    ];
    for (name, p) in variants {
        let setup = box_tank_for::<2>(&p, [1.0, 1.0], 0.5, 0.0, 0.02);
        let mut sim = Simulation::new(setup, p).unwrap();
        while sim.time() < 0.6 {
            sim.step(Vector::<2>::zeros()).unwrap();
        }
        let f = sim.fluid();
        let n = f.position.len() as f64;
        let ymin = f
            .position
            .iter()
            .map(|x| x[1])
            .fold(f64::INFINITY, f64::min);
        let xmin = f
            .position
            .iter()
            .map(|x| x[0])
            .fold(f64::INFINITY, f64::min);
        let ymax = f.position.iter().map(|x| x[1]).fold(0.0, f64::max);
        let rho_mean = f.density.iter().sum::<f64>() / n;
        let level = sim.still_level();
        let (rho0, g) = (1000.0, 9.81);
        let (mut sxy, mut sxx, mut s2) = (0.0, 0.0, 0.0);
        for (x, p) in f.position.iter().zip(&f.pressure) {
            let th = rho0 * g * (level - x[1]);
            sxy += th * p;
            sxx += th * th;
            s2 += (p - th) * (p - th);
        }
        eprintln!(
            "{name:24} slope {:.4} scatter {:.2}% KE {:.2e} ymin {ymin:.4} xmin {xmin:.4} ymax {ymax:.4} rho_mean {rho_mean:.3} vmax {:.3} steps {}",
            sxy / sxx,
            100.0 * (s2 / n).sqrt() / (rho0 * g * level),
            sim.kinetic_energy(),
            sim.max_speed(),
            sim.steps()
        );
    }
}

/// Exploration: hydrostatic drift over time of the modern preset and variants.
#[test]
#[ignore]
fn explore_drift() {
    let m = modern_params();
    let which = std::env::var("SLOSH_VARIANT").unwrap_or_default();
    let p = match which.as_str() {
        "noslip" => SphParams {
            wall_no_slip: true,
            ..m
        },
        "mc" => SphParams {
            density_diffusion: DensityDiffusion::MolteniColagrossi { delta: 0.1 },
            ..m
        },
        "dyn" => SphParams {
            boundary: BoundaryMethod::Dynamic,
            ..m
        },
        _ => m,
    };
    let setup = box_tank_for::<2>(&p, [1.0, 1.0], 0.5, 0.0, 0.02);
    let mut sim = Simulation::new(setup, p).unwrap();
    let mut next = 0.0;
    while sim.time() < 2.0 {
        sim.step(Vector::<2>::zeros()).unwrap();
        if sim.time() >= next {
            next += 0.2;
            let f = sim.fluid();
            let n = f.position.len() as f64;
            let level = sim.still_level();
            let (mut sxy, mut sxx) = (0.0, 0.0);
            for (x, p) in f.position.iter().zip(&f.pressure) {
                let th = 9810.0 * (level - x[1]);
                sxy += th * p;
                sxx += th * th;
            }
            let ymin = f
                .position
                .iter()
                .map(|x| x[1])
                .fold(f64::INFINITY, f64::min);
            let ymean = f.position.iter().map(|x| x[1]).sum::<f64>() / n;
            eprintln!(
                "{which} t {:.2} slope {:.4} rho_mean {:.3} ymean {ymean:.5} ymin {ymin:.4} KE {:.2e} wall_p_bottom_mid {:.1}",
                sim.time(),
                sxy / sxx,
                f.density.iter().sum::<f64>() / n,
                sim.kinetic_energy(),
                sim.walls().pressure.iter().zip(&sim.walls().position).filter(|(_, x)| (x[1] + 0.01).abs() < 1e-6 && (x[0] - 0.51).abs() < 1e-6).map(|(p, _)| *p).sum::<f64>()
            );
        }
    }
}

/// Exploration: first-mode period of single switches in the 0.6 × 0.3 m tank.
#[test]
#[ignore]
fn explore_switches_period() {
    let base = SphParams::default().with_paper_stiffness();
    let m = modern_params();
    let which = std::env::var("SLOSH_VARIANT").unwrap_or_default();
    let variants: Vec<(&str, SphParams)> = vec![
        ("paper", base.clone()),
        ("modern", m.clone()),
        (
            "modern dynamic walls",
            SphParams {
                boundary: BoundaryMethod::Dynamic,
                ..m.clone()
            },
        ),
        (
            "modern leapfrog",
            SphParams {
                integrator: Integrator::LeapFrog,
                ..m.clone()
            },
        ),
        (
            "modern cubic",
            SphParams {
                kernel: KernelKind::CubicSpline,
                ..m.clone()
            },
        ),
        (
            "modern alpha0.01",
            SphParams {
                av_alpha: 0.01,
                ..m.clone()
            },
        ),
        (
            "paper wendland",
            SphParams {
                kernel: KernelKind::WendlandC2,
                ..base.clone()
            },
        ),
        (
            "modern wendland h1.4",
            SphParams {
                smoothing_ratio: 1.4,
                ..m.clone()
            },
        ),
        (
            "modern wendland h1.5",
            SphParams {
                smoothing_ratio: 1.5,
                ..m.clone()
            },
        ),
        (
            "modern cubic hydro",
            SphParams {
                kernel: KernelKind::CubicSpline,
                ..m.clone()
            },
        ),
        ("paper hydro", base.clone()),
    ];
    for (name, p) in variants {
        if !which.is_empty() && !name.contains(which.as_str()) {
            continue;
        }
        if name.ends_with("hydro") {
            let (slope, scatter) = hydrostatics(p, 1.0);
            eprintln!("{name:24} slope {slope:.4} scatter {:.2}%", 100.0 * scatter);
            continue;
        }
        let (t, th, err) = free_sloshing_period(p, 0.6, 0.3, 0.02);
        eprintln!("{name:24} T {t:.4} theory {th:.4} err {:+.2}%", 100.0 * err);
    }
}

/// Exploration: the whole battery for a preset candidate (SLOSH_VARIANT = cubic | wendland15).
#[test]
#[ignore]
fn explore_candidate() {
    let m = modern_params();
    let which = std::env::var("SLOSH_VARIANT").unwrap_or_default();
    let p = match which.as_str() {
        "cubic" => SphParams {
            kernel: KernelKind::CubicSpline,
            smoothing_ratio: 1.3,
            ..m
        },
        "wendland15" => SphParams {
            kernel: KernelKind::WendlandC2,
            smoothing_ratio: 1.5,
            ..m
        },
        "w15a01" => SphParams {
            kernel: KernelKind::WendlandC2,
            smoothing_ratio: 1.5,
            av_alpha: 0.01,
            ..m
        },
        "paper" => SphParams::default().with_paper_stiffness(),
        _ => m,
    };
    if std::env::var("SLOSH_CREST_ONLY").is_ok() {
        let crests = resonant_crests(p, 2.0, &[2.0]);
        eprintln!("{which} resonant crest at 2 s: {crests:.4?}");
        return;
    }
    for (w, d) in [(1.0, 0.5), (0.6, 0.3)] {
        let (t, th, err) = free_sloshing_period(p.clone(), w, d, 0.02);
        eprintln!(
            "{which} period {w}x{d}: {t:.4} s vs {th:.4} s ({:+.2} %)",
            100.0 * err
        );
    }
    let (slope, scatter) = hydrostatics(p.clone(), 1.0);
    eprintln!(
        "{which} hydrostatics: slope {slope:.4}, scatter {:.2} %",
        100.0 * scatter
    );
    let crests = resonant_crests(p, 0.5, &[2.0]);
    eprintln!("{which} resonant crest at 2 s: {crests:.4?}");
}

/// A fluid particle half a spacing from a wall needs wall particles over its whole support
/// 2h: three layers for the paper's h = 1.3 dx and for h = 1.5 dx, four for the modern
/// preset's h = 2 dx, five for h = 2.2 dx; a tank whose walls are thinner than that is refused
/// with the number of layers to build, not run with a wall the liquid can pass through.
#[test]
fn walls_thinner_than_the_kernel_support_are_refused() {
    let with_h = |r: f64| SphParams {
        smoothing_ratio: r,
        ..SphParams::modern()
    };
    assert_eq!(SphParams::paper().wall_layers(), 3);
    assert_eq!(with_h(1.5).wall_layers(), 3);
    assert_eq!(SphParams::modern().wall_layers(), 4);
    assert_eq!(with_h(2.2).wall_layers(), 5);
    let thin = crate::test_tank::box_tank::<2>([0.4, 0.4], 0.2, 0.0, 0.02);
    match Simulation::new(thin, modern_params()) {
        Err(crate::SimError::InvalidSetup(msg)) => {
            assert!(
                msg.contains("3 particle layers") && msg.contains("at least 4"),
                "{msg}"
            )
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("walls of 3 layers were accepted with a support of 4 dx"),
    }
    let thick = box_tank_for::<2>(&modern_params(), [0.4, 0.4], 0.2, 0.0, 0.02);
    assert!(Simulation::new(thick, modern_params()).is_ok());
}
