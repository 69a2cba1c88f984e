//! The stages of the time step, each in its own file, chosen once per run ([`StepPlan`]).
//!
//! `Simulation::step` runs, in this order: sorting (re-sort and re-index the fluid),
//! the symplectic predictor, the density stage, the wall stage, the force stage, the load
//! evaluation, the integrator's update and shifting. Each stage is picked once, in
//! `Simulation::new`, from [`SphParams`]; a stage dispatches on its plan once per step,
//! never inside a pair loop. `docs/design.md` says how to add a stage (a wall model, a
//! density model).

mod continuity;
mod forces;
mod leapfrog;
mod shifting;
pub(crate) mod summation;
mod symplectic;
mod walls;
pub(crate) use continuity::*;

pub(crate) use walls::*;

use crate::params::{
    BoundaryMethod, DensityDiffusion, DensityMethod, Integrator, PairScheme, SphParams,
    ViscousOperator,
};

/// How the fluid pairs of a pass are visited.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PairSweep {
    /// Each pair once, over cell-sorted blocks, added to both particles
    /// (`sweep::colour_sweep`; cell grid only).
    Half,
    /// Each pair from both of its particles (any neighbour search).
    Full,
}

/// How the fluid arrays follow the cell order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Sorting {
    /// Every step, the arrays the summation step reads are gathered by cell and the sums of
    /// the density sweep zeroed in one loop (`Simulation::sort_and_index`).
    GatherEveryStep,
    /// Every step, every array the step reads (`Simulation::sort_all_and_index`).
    AllArraysEveryStep,
    /// Every `reorder_interval` steps for memory locality, the search rebuilt every step.
    Periodic,
}

/// The density model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DensityStage {
    /// Eq. 19 with the free-surface reset of Eq. 20, the EOS (Eq. 18) and the strain rate of
    /// Eq. 4–5 in the same pass (`summation.rs`).
    Summation { sweep: PairSweep },
    /// The density is integrated (`continuity.rs`); this stage computes the strain rate when
    /// the liquid is viscous, and the hydrostatic density of Fourtakas' diffusion.
    Continuity {
        velocity_gradient: Option<PairSweep>,
        hydrostatic: bool,
    },
}

/// The wall model (`walls.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WallStage {
    /// Wall particles with summation density and the EOS, as the fluid (paper §2.5). With
    /// summation density they are summed in the density pass, before the fluid's EOS.
    Dynamic,
    /// Pressure extrapolated from the fluid (Adami, Hu & Adams 2012); with no-slip walls and
    /// a viscous liquid the mirrored wall velocity enters the strain rate.
    Adami { no_slip_viscous: bool },
}

/// The force pass (`forces.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ForceStage {
    /// The momentum equation alone (Eq. 8–16), reading the density pass's neighbour lists.
    Momentum { sweep: PairSweep },
    /// The momentum equation with, in the same pair loop, the density rate, the wall force
    /// and the shifting sums of the run.
    Coupled(CoupledForce),
}

/// The parts of the coupled force pass; each becomes a type of the pass
/// ([`crate::terms::Coupled`]), so its pair loop is compiled for the run's parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct CoupledForce {
    pub(crate) sweep: PairSweep,
    pub(crate) density_rate: DensityRate,
    pub(crate) wall_force: WallForce,
    /// The shifting gradient ∇C and kernel sum are summed.
    pub(crate) shifting_sums: bool,
    /// The momentum and continuity pair.
    pub(crate) pair: MomentumPair,
}

/// The momentum and continuity pair of the coupled force pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MomentumPair {
    /// Eq. 8 with Monaghan's continuity equation (`terms::Eq8Pair`).
    Eq8,
    /// The Riemann-solver pair of Zhang, Hu & Adams 2017 (`terms::RiemannPair`).
    Riemann,
    /// Eq. 8 with the single-sum viscous operator of Colagrossi et al. 2011 in place of the
    /// strain-rate stress (`terms::Eq8MonaghanClearyPair`).
    Eq8MonaghanCleary,
}

/// The density rate the coupled force pass sums.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DensityRate {
    /// None: summation density.
    None,
    /// The continuity equation (Monaghan 1992).
    Continuity,
    /// With the δ-SPH diffusion of Molteni & Colagrossi (2009).
    MolteniColagrossi,
    /// With the δ-SPH diffusion of Fourtakas et al. (2019), hydrostatic part removed.
    Fourtakas,
}

/// What a wall particle adds to the coupled pass's momentum besides its pressure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WallForce {
    /// As a fluid particle at rest: artificial viscosity and viscous stress (paper §2.5).
    Dynamic,
    /// Adami walls, free slip: pressure only.
    AdamiFreeSlip,
    /// Adami walls, no slip, viscous liquid: the viscous force of the mirrored velocity.
    AdamiNoSlip,
}

/// The time integrator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TimeIntegration {
    /// Eq. 21–22 (`leapfrog.rs`).
    LeapFrog,
    /// Position Verlet (`symplectic.rs`).
    Symplectic,
}

/// The stages of one run's step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StepPlan {
    pub(crate) sorting: Sorting,
    pub(crate) density: DensityStage,
    pub(crate) walls: WallStage,
    pub(crate) forces: ForceStage,
    pub(crate) integration: TimeIntegration,
    /// Particle shifting after the update (`shifting.rs`).
    pub(crate) shifting: bool,
}

impl StepPlan {
    /// The stages for `params`, with the cell grid (`grid`) or the k-d tree as search.
    ///
    /// The paper's scheme on the cell grid sweeps each pair once in both passes and sums the
    /// wall particles in the density sweep. With any other part switched on, the density
    /// pass of summation density visits every pair from both sides, and the force pass
    /// reads the neighbour lists only when the strain-rate sweep of continuity density
    /// filled them on the same positions.
    pub(crate) fn choose(params: &SphParams, grid: bool) -> Self {
        let coupled = params.uses_modern_step();
        let sweep = if grid {
            PairSweep::Half
        } else {
            PairSweep::Full
        };
        let viscous = params.dynamic_viscosity > 0.0;
        // The strain rate of Eq. 4–5 feeds the paper's viscous operator and the no-slip wall
        // velocity's share of it; the single-sum operator reads the velocities alone.
        let strain_rate = viscous
            && (params.viscous_operator == ViscousOperator::StrainRate || params.wall_no_slip);
        let density = match params.density {
            DensityMethod::Summation => DensityStage::Summation {
                sweep: if coupled { PairSweep::Full } else { sweep },
            },
            DensityMethod::Continuity => DensityStage::Continuity {
                velocity_gradient: strain_rate.then_some(sweep),
                hydrostatic: matches!(
                    params.density_diffusion,
                    DensityDiffusion::Fourtakas { delta } if delta > 0.0
                ),
            },
        };
        StepPlan {
            sorting: match (grid, coupled) {
                (true, false) => Sorting::GatherEveryStep,
                (true, true) => Sorting::AllArraysEveryStep,
                (false, _) => Sorting::Periodic,
            },
            density,
            walls: match params.boundary {
                BoundaryMethod::Dynamic => WallStage::Dynamic,
                BoundaryMethod::Adami => WallStage::Adami {
                    no_slip_viscous: params.wall_no_slip && viscous,
                },
            },
            forces: if coupled {
                let continuity = params.density == DensityMethod::Continuity;
                ForceStage::Coupled(CoupledForce {
                    sweep,
                    density_rate: match params.density_diffusion {
                        _ if !continuity => DensityRate::None,
                        DensityDiffusion::MolteniColagrossi { delta } if delta > 0.0 => {
                            DensityRate::MolteniColagrossi
                        }
                        DensityDiffusion::Fourtakas { delta } if delta > 0.0 => {
                            DensityRate::Fourtakas
                        }
                        _ => DensityRate::Continuity,
                    },
                    wall_force: match params.boundary {
                        BoundaryMethod::Dynamic => WallForce::Dynamic,
                        BoundaryMethod::Adami if params.wall_no_slip && viscous => {
                            WallForce::AdamiNoSlip
                        }
                        BoundaryMethod::Adami => WallForce::AdamiFreeSlip,
                    },
                    shifting_sums: params.shifting.is_some_and(|a| a > 0.0),
                    pair: match (params.pair_scheme, params.viscous_operator) {
                        (PairScheme::Standard, ViscousOperator::StrainRate) => MomentumPair::Eq8,
                        (PairScheme::Standard, ViscousOperator::MonaghanCleary) => {
                            MomentumPair::Eq8MonaghanCleary
                        }
                        // Simulation::new refuses the single-sum operator with the Riemann pair.
                        (PairScheme::Riemann, _) => MomentumPair::Riemann,
                    },
                })
            } else {
                ForceStage::Momentum { sweep }
            },
            integration: match params.integrator {
                Integrator::LeapFrog => TimeIntegration::LeapFrog,
                Integrator::Symplectic => TimeIntegration::Symplectic,
            },
            shifting: params.shifting.is_some_and(|a| a > 0.0),
        }
    }

    /// Whether a pass of this plan lists each particle's neighbours for a later pass to read
    /// (the density summation, and the half strain-rate sweep of continuity density on the
    /// cell grid). The other
    /// plans take every pair from the search and need no list memory: the lists hold 48
    /// (2D) or 128 (3D) entries of 4 B per fluid particle.
    pub(crate) fn lists_neighbours(&self) -> bool {
        matches!(
            self.density,
            DensityStage::Summation { .. }
                | DensityStage::Continuity {
                    velocity_gradient: Some(PairSweep::Half),
                    ..
                }
        )
    }

    /// One line naming the stages, for run summaries.
    pub(crate) fn describe(&self) -> String {
        let sweep = |s: PairSweep| match s {
            PairSweep::Half => "each pair once",
            PairSweep::Full => "each pair from both sides",
        };
        let density = match self.density {
            DensityStage::Summation { sweep: s } => format!("summation ({})", sweep(s)),
            DensityStage::Continuity {
                velocity_gradient,
                hydrostatic,
            } => format!(
                "continuity{}{}",
                match velocity_gradient {
                    Some(s) => format!(", strain rate ({})", sweep(s)),
                    None => String::new(),
                },
                if hydrostatic {
                    ", hydrostatic diffusion"
                } else {
                    ""
                }
            ),
        };
        let walls = match self.walls {
            WallStage::Dynamic => "dynamic",
            WallStage::Adami {
                no_slip_viscous: true,
            } => "Adami, no-slip",
            WallStage::Adami { .. } => "Adami",
        };
        let forces = match self.forces {
            ForceStage::Momentum { sweep: s } => format!("momentum ({})", sweep(s)),
            ForceStage::Coupled(CoupledForce {
                sweep: s,
                density_rate,
                shifting_sums,
                pair,
                ..
            }) => format!(
                "{}momentum with {}{} ({})",
                match pair {
                    MomentumPair::Eq8 => "",
                    MomentumPair::Riemann => "Riemann-solver ",
                    MomentumPair::Eq8MonaghanCleary => "single-sum viscous ",
                },
                match density_rate {
                    DensityRate::None => "no density rate",
                    DensityRate::Continuity => "continuity",
                    DensityRate::MolteniColagrossi => "continuity, Molteni–Colagrossi diffusion",
                    DensityRate::Fourtakas => "continuity, Fourtakas diffusion",
                },
                if shifting_sums { ", shifting sums" } else { "" },
                sweep(s)
            ),
        };
        let integration = match self.integration {
            TimeIntegration::LeapFrog => "leap-frog",
            TimeIntegration::Symplectic => "symplectic",
        };
        let sorting = match self.sorting {
            Sorting::GatherEveryStep | Sorting::AllArraysEveryStep => "every step",
            Sorting::Periodic => "periodically",
        };
        format!(
            "sorting: {sorting}; density: {density}; walls: {walls}; forces: {forces}; \
             integrator: {integration}{}",
            if self.shifting { "; shifting" } else { "" }
        )
    }
}
