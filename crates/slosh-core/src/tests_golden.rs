//! Golden fingerprints: the modern preset and each part of it switched on alone on top of the
//! paper scheme, in 2D and 3D, recorded bit for bit (`print_golden_fingerprints`) so that a
//! reorganisation of the solver that must not change its results can be checked exactly.
//! A change that is meant to change results records them again and says why.

use crate::test_tank::box_tank;
use crate::tests_modern::fingerprint;
use crate::{
    BoundaryMethod, DensityDiffusion, DensityMethod, Integrator, KernelKind, Simulation, SphParams,
    Vector, WallPressureMethod,
};

/// The configurations: a name and its parameters (all at the paper's stiffness).
pub(crate) fn configurations() -> Vec<(&'static str, SphParams)> {
    let paper = SphParams::paper().with_paper_stiffness();
    vec![
        ("modern preset", SphParams::modern().with_paper_stiffness()),
        (
            "continuity density",
            SphParams {
                density: DensityMethod::Continuity,
                ..paper.clone()
            },
        ),
        (
            "continuity + Molteni-Colagrossi diffusion",
            SphParams {
                density: DensityMethod::Continuity,
                density_diffusion: DensityDiffusion::MolteniColagrossi { delta: 0.1 },
                ..paper.clone()
            },
        ),
        (
            "continuity + Fourtakas diffusion",
            SphParams {
                density: DensityMethod::Continuity,
                density_diffusion: DensityDiffusion::Fourtakas { delta: 0.1 },
                ..paper.clone()
            },
        ),
        (
            "Adami walls",
            SphParams {
                boundary: BoundaryMethod::Adami,
                ..paper.clone()
            },
        ),
        (
            "symplectic integrator",
            SphParams {
                integrator: Integrator::Symplectic,
                ..paper.clone()
            },
        ),
        (
            "Wendland C2",
            SphParams {
                kernel: KernelKind::WendlandC2,
                smoothing_ratio: 1.5,
                ..paper.clone()
            },
        ),
        (
            "kernel-extrapolated wall pressure",
            SphParams {
                wall_pressure: WallPressureMethod::KernelExtrapolation,
                ..paper.clone()
            },
        ),
        (
            "modern + shifting",
            SphParams {
                shifting: Some(2.0),
                ..SphParams::modern().with_paper_stiffness()
            },
        ),
        (
            "modern + no-slip walls",
            SphParams {
                wall_no_slip: true,
                ..SphParams::modern().with_paper_stiffness()
            },
        ),
        (
            "modern without the wall-pressure floor",
            SphParams {
                wall_separation: false,
                ..SphParams::modern().with_paper_stiffness()
            },
        ),
    ]
}

/// 150 steps of a sloshing 2D box under a varying ground acceleration.
fn run_2d(params: &SphParams) -> Vec<u64> {
    let setup = box_tank::<2>([0.4, 0.4], 0.2, 0.02, 0.02);
    let mut sim = Simulation::new(setup, params.clone()).unwrap();
    for _ in 0..150 {
        let t = sim.time();
        sim.step(Vector::<2>::new(2.0 * (10.0 * t).sin(), 0.0))
            .unwrap();
    }
    fingerprint(&sim)
}

/// 50 steps of a 3D box under a varying ground acceleration.
fn run_3d(params: &SphParams) -> Vec<u64> {
    let setup = box_tank::<3>([0.2, 0.1, 0.2], 0.1, 0.01, 0.02);
    let mut sim = Simulation::new(setup, params.clone()).unwrap();
    for _ in 0..50 {
        let t = sim.time();
        sim.step(Vector::<3>::new(2.0 * (10.0 * t).sin(), 1.0, 0.0))
            .unwrap();
    }
    fingerprint(&sim)
}

/// Prints the table of [`GOLDEN`] (run with `--ignored --nocapture` to record it again).
#[test]
#[ignore]
fn print_golden_fingerprints() {
    for (name, p) in configurations() {
        eprintln!("(\"{name}\", {:?}, {:?}),", run_2d(&p), run_3d(&p));
    }
}

/// (configuration, 2D fingerprint, 3D fingerprint), recorded at the commit that added them; the
/// four built on the modern preset recorded again when its artificial viscosity became α = 0,
/// β = 3 (low dissipation, `docs/validation.md`).
const GOLDEN: &[(&str, [u64; 6], [u64; 6])] = &[
    (
        "modern preset",
        [
            4686121562926082373,
            4635241427034096517,
            4611106204868067372,
            4656912743374984965,
            4688489506221317467,
            4586236010558673554,
        ],
        [
            4687836074511580227,
            4635856584357578008,
            13834146900050165223,
            4652302689069583989,
            4702229740459016949,
            4579267654903636500,
        ],
    ),
    (
        "continuity density",
        [
            4686110610908646953,
            4635242038447090182,
            4617347621413517044,
            4660066827588757022,
            4688460780348017440,
            4585419936177181426,
        ],
        [
            4687837144940613914,
            4635838372992243456,
            13851166886804058594,
            4658965459032467610,
            4702198897697458843,
            4578167401857564425,
        ],
    ),
    (
        "continuity + Molteni-Colagrossi diffusion",
        [
            4686118653950760639,
            4635239663255839952,
            4606162946338528601,
            4653685907559075984,
            4688461340618107966,
            4585423081231859203,
        ],
        [
            4687842034265330626,
            4635835184269406972,
            13853118496223245969,
            4656668331608945370,
            4702198942105378881,
            4578169027494218091,
        ],
    ),
    (
        "continuity + Fourtakas diffusion",
        [
            4686118675125726708,
            4635240467524093161,
            4606186977463371188,
            4653888584447537147,
            4688461344514946562,
            4585423005086683161,
        ],
        [
            4687842519425654011,
            4635835471105357752,
            13853033250217966511,
            4656682776145923117,
            4702198953736116028,
            4578168839528132725,
        ],
    ),
    (
        "Adami walls",
        [
            4686110780788000469,
            4635238594383285708,
            13822077104632965062,
            4659337477266186517,
            4688487410137944372,
            4585412779376215123,
        ],
        [
            4687835005814068460,
            4635834602418740669,
            13850265411712310708,
            4656810028335739644,
            4702230217491916222,
            4578173830006953008,
        ],
    ),
    (
        "symplectic integrator",
        [
            4686107830807327261,
            4635238179525635687,
            4614053400478390020,
            4651969039471473721,
            4688461099299123540,
            4585412836081337413,
        ],
        [
            4687827995161303137,
            4635828231109657910,
            13854128500080125776,
            4658838913653530410,
            4702198473864669442,
            4578171858421046580,
        ],
    ),
    (
        "Wendland C2",
        [
            4686113770420866982,
            4635248860090102406,
            13841975261083419518,
            4661312572819325189,
            4688445860070850597,
            4586209127229616699,
        ],
        [
            4687823398145545651,
            4635872552267449710,
            13844618027862647118,
            4655637831209528998,
            4702184955911954115,
            4579242631089874700,
        ],
    ),
    (
        "kernel-extrapolated wall pressure",
        [
            4686107907374617740,
            4635238168960029543,
            4614021548875776529,
            4651338061942883599,
            4688461099229939710,
            4585412829886224609,
        ],
        [
            4687827849347920623,
            4635828224165261516,
            13854131250723347272,
            4657316314659255705,
            4702198436346598905,
            4578171848567820880,
        ],
    ),
    (
        "modern + shifting",
        [
            4686121564097005864,
            4635241864943321966,
            4611103110471579107,
            4656912693851915385,
            4688489506405281872,
            4586236004731560288,
        ],
        [
            4687836074698365170,
            4635856670767386824,
            13834150643499306719,
            4652302664135943431,
            4702229737033353253,
            4579267655392863278,
        ],
    ),
    (
        "modern + no-slip walls",
        [
            4686121562922737020,
            4635241427000323646,
            4611106049558680897,
            4656912741832294303,
            4688489506220544054,
            4586236010556029637,
        ],
        [
            4687836074507075982,
            4635856584371994540,
            13834146741480857099,
            4652302687446342982,
            4702229740458269406,
            4579267654978286423,
        ],
    ),
    (
        "modern without the wall-pressure floor",
        [
            4686121542517890124,
            4635241389587124720,
            4611148904687572418,
            4656909510419010702,
            4688489475323394614,
            4586236043969778705,
        ],
        [
            4687835979025792917,
            4635856746213465345,
            13833855836558218486,
            4652271367333628879,
            4702229653498371634,
            4579269702442136989,
        ],
    ),
];

#[test]
fn golden_fingerprints_unchanged() {
    let configurations = configurations();
    assert_eq!(configurations.len(), GOLDEN.len(), "record the table again");
    for ((name, params), (golden_name, g2, g3)) in configurations.iter().zip(GOLDEN) {
        assert_eq!(name, golden_name);
        assert_eq!(run_2d(params), g2.to_vec(), "{name}, 2D");
        assert_eq!(run_3d(params), g3.to_vec(), "{name}, 3D");
    }
}
