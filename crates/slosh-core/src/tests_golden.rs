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

/// (configuration, 2D fingerprint, 3D fingerprint), recorded at the commit that added them.
const GOLDEN: &[(&str, [u64; 6], [u64; 6])] = &[
    (
        "modern preset",
        [
            4686121553211199224,
            4635241418203737044,
            4611079299599441817,
            4656914543698776283,
            4688489506134252634,
            4586236525931311177,
        ],
        [
            4687836070957578061,
            4635856588539725666,
            13834050612437764173,
            4652304139553016348,
            4702229740677004486,
            4579267716164931005,
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
            4686121554405091999,
            4635241853514390810,
            4611075849137827587,
            4656914486083864496,
            4688489506313280514,
            4586236521510568119,
        ],
        [
            4687836071139911075,
            4635856674892533167,
            13834054448811389706,
            4652304110603493006,
            4702229740693453302,
            4579267716645772481,
        ],
    ),
    (
        "modern + no-slip walls",
        [
            4686121553208128519,
            4635241418169904316,
            4611079144424694980,
            4656914542171233034,
            4688489506133544732,
            4586236525928800175,
        ],
        [
            4687836070953235705,
            4635856588554029481,
            13834050456229296602,
            4652304137948640582,
            4702229740676270674,
            4579267716237753027,
        ],
    ),
    (
        "modern without the wall-pressure floor",
        [
            4686121533432607323,
            4635241381745903938,
            4611120982130676004,
            4656911301460982773,
            4688489475087718791,
            4586236562766873945,
        ],
        [
            4687835976520691861,
            4635856749944335446,
            13833776122854113038,
            4652272311174172072,
            4702229653399429434,
            4579269734571842818,
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
