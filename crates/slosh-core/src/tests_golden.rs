//! Golden fingerprints: the modern preset and each part of it switched on alone on top of the
//! paper scheme, in 2D and 3D, recorded bit for bit (`print_golden_fingerprints`) so that a
//! reorganisation of the solver that must not change its results can be checked exactly.
//! A change that is meant to change results records them again and says why.

use crate::test_tank::box_tank_for;
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
    let setup = box_tank_for::<2>(params, [0.4, 0.4], 0.2, 0.02, 0.02);
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
    let setup = box_tank_for::<3>(params, [0.2, 0.1, 0.2], 0.1, 0.01, 0.02);
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
/// β = 3 (low dissipation, `docs/validation.md`), and the seven with continuity density again
/// when the liquid began to start in its own Tait compression (`docs/scheme.md`, *Continuity
/// density*, *Starting at rest*); the four others were unchanged by it. The four built on the
/// modern preset recorded again when its smoothing length became h = 2 dx with four wall
/// layers (`docs/validation.md`, *Damping of free sloshing*), and again when it took the
/// single-sum viscous operator; the seven others unchanged by either. The five with Fourtakas'
/// diffusion recorded again when its hydrostatic density became one power of the column's
/// pressure base instead of the pressure and the inverse EOS (a change in round-off,
/// `docs/performance.md`); the six others unchanged by it.
const GOLDEN: &[(&str, [u64; 6], [u64; 6])] = &[
    (
        "modern preset",
        [
            4686121665794032276,
            4635237573312198030,
            4610280310380967694,
            4656993244315023534,
            4690347798474455732,
            4588260414230954481,
        ],
        [
            4687836205863621987,
            4635854346989897774,
            4585866532964184324,
            4652376731049503268,
            4705228728819190466,
            4581065244298073730,
        ],
    ),
    (
        "continuity density",
        [
            4686114189261516770,
            4635236144273407912,
            4613542769586011232,
            4657987761105471709,
            4688461035831548310,
            4585421028804706668,
        ],
        [
            4687838120022412508,
            4635836370732109808,
            13851132581799157716,
            4658910704729343531,
            4702198871396782123,
            4578167655694801427,
        ],
    ),
    (
        "continuity + Molteni-Colagrossi diffusion",
        [
            4686118999076843114,
            4635234594734669024,
            4604583377768254425,
            4654560608830509120,
            4688461471216130346,
            4585423669795176945,
        ],
        [
            4687842581376286582,
            4635833306807588236,
            13852849547280827031,
            4656755954164394583,
            4702198942596064724,
            4578169163340157840,
        ],
    ),
    (
        "continuity + Fourtakas diffusion",
        [
            4686119011343972653,
            4635235388018270944,
            4605031489818906260,
            4654696841351555477,
            4688461485939362433,
            4585423575511097662,
        ],
        [
            4687843016947602742,
            4635833595089246655,
            13852713995707511757,
            4656769258982510611,
            4702198953649911304,
            4578168976592415158,
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
            4686121667969632905,
            4635237979122746024,
            4610291283708560933,
            4656993167644046638,
            4690347798755409526,
            4588260418936663440,
        ],
        [
            4687836207100198555,
            4635854575392848119,
            4586321387593302180,
            4652377126177580765,
            4705228727467537023,
            4581065245059166265,
        ],
    ),
    (
        "modern + no-slip walls",
        [
            4686121665788294901,
            4635237573255357816,
            4610280117619346240,
            4656993242036899104,
            4690347798471137908,
            4588260414228468805,
        ],
        [
            4687836205859359064,
            4635854347000382534,
            4585865450015432000,
            4652376729752885960,
            4705228728818426078,
            4581065244375337171,
        ],
    ),
    (
        "modern without the wall-pressure floor",
        [
            4686121635410701155,
            4635237492170490772,
            4610044146018090748,
            4656986507179788896,
            4690347653458902301,
            4588260491388857647,
        ],
        [
            4687836138709993541,
            4635854413250047555,
            13816919788481702906,
            4652382225467057685,
            4705228583063711897,
            4581067269754789404,
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
