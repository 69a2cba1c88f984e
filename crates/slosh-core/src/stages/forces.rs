//! The force stage: the momentum equation (Eq. 8–16) alone, or coupled with the
//! continuity equation, the density diffusion and the shifting sums
//! ([`crate::terms::Momentum`], [`crate::terms::Coupled`]), over the pairs of the half or
//! the full sweep ([`crate::sweep::half_sweep`], [`crate::sweep::full_sweep`]).

use super::{CoupledForce, DensityRate, MomentumPair, PairSweep, WallForce};
use crate::sim::*;
use crate::sweep::{full_sweep, half_sweep, Sweep};
use crate::terms::*;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// The momentum equation alone (Eq. 8–16) with the body force `body_force` (m/s²): the
    /// paper's force pass. The half sweep reads the density sweep's half lists; the full
    /// sweep the density pass's lists.
    pub(crate) fn momentum_stage(&mut self, sweep: PairSweep, body_force: Vector<D>) {
        let c = self.constants;
        // The acceleration leaves the fluid while the pass reads the rest of it (no
        // allocation: an empty Vec stands in).
        let mut acceleration = std::mem::take(&mut self.fluid.acceleration);
        let half_grid = match (sweep, &self.search) {
            (PairSweep::Half, Search::Grid(grid)) => Some(grid),
            _ => None,
        };
        if half_grid.is_some() {
            // The half sweep adds each pair to both particles: start from the body force.
            acceleration
                .par_iter_mut()
                .with_min_len(PAR_CHUNK)
                .for_each(|a| *a = body_force);
        }
        let (fluid, walls, blocks, search) = (&self.fluid, &self.walls, &self.blocks, &self.search);
        Sweep::scope(fluid.position.len(), |sweep| {
            let acceleration = sweep.slots(&mut acceleration);
            let pass = Momentum::new(&c, fluid, walls, acceleration, body_force);
            let lists = Some(&fluid.neighbours);
            match half_grid {
                Some(grid) => half_sweep(sweep, grid, blocks, lists, c.support_sq, &pass),
                None => with_search!(search, s => full_sweep(sweep, s, lists, c.support_sq, &pass)),
            }
        });
        self.fluid.acceleration = acceleration;
    }

    /// The momentum equation coupled with the density rate, the wall force and the
    /// shifting sums of the plan. With `lists` (the strain-rate sweep's half lists of these
    /// positions) the half sweep reads its pairs from them, otherwise from the grid; the
    /// full sweep searches.
    pub(crate) fn coupled_stage(
        &mut self,
        force: CoupledForce,
        lists: bool,
        body_force: Vector<D>,
    ) {
        let run = CoupledRun {
            sweep: force.sweep,
            lists,
            body_force,
            wall_force: force.wall_force,
            shifting_sums: force.shifting_sums,
            pair: force.pair,
        };
        // The pass's 36 variants per dimension (24 with Eq. 8, 12 with the Riemann pair) are
        // compiled once, here, by the two functions below, rather than again in every crate
        // that steps a simulation.
        let sim: &mut dyn std::any::Any = self;
        if let Some(sim) = sim.downcast_mut::<Simulation<2>>() {
            coupled_pass_2d(sim, &run.in_dimension(), force.density_rate);
        } else if let Some(sim) = sim.downcast_mut::<Simulation<3>>() {
            coupled_pass_3d(sim, &run.in_dimension(), force.density_rate);
        } else {
            unreachable!("Simulation::new accepts two and three dimensions only");
        }
    }
}

/// The coupled pass of a 2D simulation.
fn coupled_pass_2d(sim: &mut Simulation<2>, run: &CoupledRun<2>, density_rate: DensityRate) {
    run.with_density_rate(sim, density_rate)
}

/// The coupled pass of a 3D simulation.
fn coupled_pass_3d(sim: &mut Simulation<3>, run: &CoupledRun<3>, density_rate: DensityRate) {
    run.with_density_rate(sim, density_rate)
}

/// The choices of a coupled force pass, turned into the types of its pair terms one at a
/// time (density rate, wall force, shifting sums), so that the pair loop is compiled for
/// the run's parts.
struct CoupledRun<const D: usize> {
    sweep: PairSweep,
    lists: bool,
    body_force: Vector<D>,
    wall_force: WallForce,
    shifting_sums: bool,
    pair: MomentumPair,
}

impl<const D: usize> CoupledRun<D> {
    /// The same choices in dimension `E` (the body force's components copied: `E` = `D`).
    fn in_dimension<const E: usize>(&self) -> CoupledRun<E> {
        let mut body_force = Vector::<E>::zeros();
        for (b, f) in body_force.iter_mut().zip(self.body_force.iter()) {
            *b = *f;
        }
        CoupledRun {
            sweep: self.sweep,
            lists: self.lists,
            body_force,
            wall_force: self.wall_force,
            shifting_sums: self.shifting_sums,
            pair: self.pair,
        }
    }

    fn with_density_rate(&self, sim: &mut Simulation<D>, density_rate: DensityRate) {
        match self.pair {
            MomentumPair::Eq8 => match density_rate {
                DensityRate::None => self.with_walls::<NoDensityRate>(sim),
                DensityRate::Continuity => self.with_walls::<ContinuityOnly>(sim),
                DensityRate::MolteniColagrossi => {
                    self.with_walls::<MolteniColagrossiDiffusion>(sim)
                }
                DensityRate::Fourtakas => self.with_walls::<FourtakasDiffusion>(sim),
            },
            // The single-sum viscous operator runs with the modern step's Adami walls
            // (Simulation::new refuses it otherwise).
            MomentumPair::Eq8MonaghanCleary => match density_rate {
                DensityRate::None => {
                    self.with_adami_walls::<NoDensityRate, Eq8MonaghanClearyPair>(sim)
                }
                DensityRate::Continuity => {
                    self.with_adami_walls::<ContinuityOnly, Eq8MonaghanClearyPair>(sim)
                }
                DensityRate::MolteniColagrossi => {
                    self.with_adami_walls::<MolteniColagrossiDiffusion, Eq8MonaghanClearyPair>(sim)
                }
                DensityRate::Fourtakas => {
                    self.with_adami_walls::<FourtakasDiffusion, Eq8MonaghanClearyPair>(sim)
                }
            },
            // The Riemann pair integrates the density against Adami walls (Simulation::new
            // refuses it otherwise).
            MomentumPair::Riemann => match density_rate {
                DensityRate::None => {
                    unreachable!("Simulation::new refuses the Riemann pair without continuity")
                }
                DensityRate::Continuity => {
                    self.with_adami_walls::<ContinuityOnly, RiemannPair>(sim)
                }
                DensityRate::MolteniColagrossi => {
                    self.with_adami_walls::<MolteniColagrossiDiffusion, RiemannPair>(sim)
                }
                DensityRate::Fourtakas => {
                    self.with_adami_walls::<FourtakasDiffusion, RiemannPair>(sim)
                }
            },
        }
    }

    fn with_walls<R: DensityRateTerm>(&self, sim: &mut Simulation<D>) {
        match self.wall_force {
            WallForce::Dynamic => self.with_shifting::<R, DynamicWallForce, Eq8Pair>(sim),
            WallForce::AdamiFreeSlip => self.with_shifting::<R, AdamiFreeSlipForce, Eq8Pair>(sim),
            WallForce::AdamiNoSlip => self.with_shifting::<R, AdamiNoSlipForce, Eq8Pair>(sim),
        }
    }

    fn with_adami_walls<R: DensityRateTerm, F: MomentumContinuityPair<D>>(
        &self,
        sim: &mut Simulation<D>,
    ) {
        match self.wall_force {
            WallForce::Dynamic => unreachable!(
                "Simulation::new refuses the Riemann pair and the single-sum viscous operator \
                 with dynamic walls"
            ),
            WallForce::AdamiFreeSlip => self.with_shifting::<R, AdamiFreeSlipForce, F>(sim),
            WallForce::AdamiNoSlip => self.with_shifting::<R, AdamiNoSlipForce, F>(sim),
        }
    }

    fn with_shifting<R: DensityRateTerm, W: WallForceTerm, F: MomentumContinuityPair<D>>(
        &self,
        sim: &mut Simulation<D>,
    ) {
        if self.shifting_sums {
            self.pass::<R, W, F, true>(sim)
        } else {
            self.pass::<R, W, F, false>(sim)
        }
    }

    fn pass<
        R: DensityRateTerm,
        W: WallForceTerm,
        F: MomentumContinuityPair<D>,
        const SHIFT: bool,
    >(
        &self,
        sim: &mut Simulation<D>,
    ) {
        let c = sim.constants;
        let body_force = self.body_force;
        let mut out = ForceOutputs::take(&mut sim.fluid, &mut sim.buffers);
        let half_grid = match (self.sweep, &sim.search) {
            (PairSweep::Half, Search::Grid(grid)) => Some(grid),
            _ => None,
        };
        if half_grid.is_some() {
            // The half sweep adds each pair to both particles: start from the body force
            // and zero sums.
            out.acceleration
                .par_iter_mut()
                .zip(out.density_rate.par_iter_mut())
                .with_min_len(PAR_CHUNK)
                .for_each(|(a, d)| {
                    *a = body_force;
                    *d = 0.0;
                });
            out.shift_gradient
                .par_iter_mut()
                .zip(out.shift_kernel_sum.par_iter_mut())
                .with_min_len(PAR_CHUNK)
                .for_each(|(g, s)| {
                    *g = Vector::<D>::zeros();
                    *s = 0.0;
                });
        }
        let lists = self.lists.then_some(&sim.fluid.neighbours);
        Sweep::scope(sim.fluid.position.len(), |sweep| {
            let pass = Coupled::<D, R, W, F, SHIFT>::new(
                &c,
                &sim.fluid,
                &sim.walls,
                &sim.buffers,
                &mut out,
                sweep,
                body_force,
            );
            match half_grid {
                Some(grid) => half_sweep(sweep, grid, &sim.blocks, lists, c.support_sq, &pass),
                None => {
                    with_search!(&sim.search, s => full_sweep(sweep, s, None, c.support_sq, &pass))
                }
            }
        });
        out.restore(&mut sim.fluid, &mut sim.buffers);
    }
}
