//! Free runs of the long stages (hours on 2 cores) that survive an interruption: the run's
//! state goes into `OUT/checkpoint/<stem>.ckpt` every `--checkpoint-every` of wall time, and
//! the same stage run again with the same `--out` continues from it instead of starting over.
//! The checkpoint holds the simulation's state ([`SimState`]), the centre-of-mass record so
//! far and what identifies the run (stage, particle counts, every solver parameter, the slosh
//! build that wrote it); one of another run or another build is set aside with a message, so
//! that a record is never made of two builds' steps. A finished run deletes its checkpoint.

use crate::run::Context;
use crate::three_d::{ComHistory, FreeRun};
use anyhow::Result;
use serde::{Deserialize, Serialize};
use slosh_core::{SimState, Simulation};
use std::path::PathBuf;
use std::time::Instant;

/// A free run's state between two steps, as written to disk.
#[derive(Serialize, Deserialize)]
struct FreeRunCheckpoint<const D: usize> {
    /// What run this is (stage stem, particle counts, sampling, solver parameters).
    key: String,
    /// The simulation's evolving state.
    sim: SimState<D>,
    /// Sample times of the centre of mass so far (s).
    t: Vec<f64>,
    /// Centre of mass x at those times (m).
    x: Vec<f64>,
    /// Time of the next sample (s).
    next_sample: f64,
    /// Particle-steps taken so far.
    particle_steps: f64,
    /// Wall time of the run before this call (s).
    wall_time_s: f64,
}

fn checkpoint_path(ctx: &Context, stem: &str) -> PathBuf {
    ctx.out.join("checkpoint").join(format!("{stem}.ckpt"))
}

/// What identifies a free run: resuming is allowed only into the same stage, tank, sampling
/// and parameters, by the same build of slosh.
fn run_key<const D: usize>(stem: &str, sim: &Simulation<D>, sample: f64) -> String {
    format!(
        "{stem}; {D}D; {} fluid + {} wall particles; sample every {sample:e} s; {:?}; {}",
        sim.fluid().position.len(),
        sim.walls().position.len(),
        sim.params(),
        build_identity()
    )
}

/// The build of slosh that is running: its version and the size and modification time of its
/// executable. A rebuild after a change of the code gives another identity (a copy of the
/// executable may too, which costs only a fresh start); where the executable cannot be read,
/// the version alone.
fn build_identity() -> String {
    let version = env!("CARGO_PKG_VERSION");
    let exe = std::env::current_exe().and_then(std::fs::metadata);
    match exe.and_then(|m| Ok((m.len(), m.modified()?))) {
        Ok((len, modified)) => {
            let since_epoch = modified
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_nanos())
                .unwrap_or(0);
            format!("slosh {version}, executable of {len} bytes modified at {since_epoch} ns")
        }
        Err(_) => format!("slosh {version}"),
    }
}

/// [`crate::three_d::free_run`] for a run of hours: resumes from the stage's checkpoint in
/// the output folder when there is one of this run, checkpoints every
/// `ctx.checkpoint_every` of wall time, and deletes the checkpoint when the run is complete.
/// Returns the centre-of-mass record from the start of the run, its particle-steps and its
/// wall time (s) over every call that worked on it.
pub(crate) fn free_run_resumable<const D: usize>(
    ctx: &Context,
    stem: &str,
    sim: &mut Simulation<D>,
    t_end: f64,
    sample: f64,
) -> Result<(ComHistory, f64, f64)> {
    let path = checkpoint_path(ctx, stem);
    let key = run_key(stem, sim, sample);
    let mut run = FreeRun::start(sim, sim.time() + sample);
    // Wall time of the run before this call (s).
    let mut wall_before = 0.0;
    if ctx.checkpoint_every.is_some() && path.exists() {
        match slosh_io::read_checkpoint::<FreeRunCheckpoint<D>>(&path) {
            Ok(c) if c.key == key => {
                sim.restore(c.sim)?;
                run = FreeRun {
                    history: ComHistory { t: c.t, x: c.x },
                    next_sample: c.next_sample,
                    particle_steps: c.particle_steps,
                };
                wall_before = c.wall_time_s;
                ctx.say(&format!(
                    "continuing from {} at t = {:.3} s ({:.0} s of wall time before)",
                    path.display(),
                    sim.time(),
                    c.wall_time_s
                ));
            }
            Ok(_) => ctx.say(&format!(
                "{} is of another run (tank, resolution, parameters or slosh build differ): starting afresh",
                path.display()
            )),
            Err(e) => ctx.say(&format!("{e}: starting afresh")),
        }
    }
    let started = Instant::now();
    let mut last_write = Instant::now();
    run.advance(sim, t_end, sample, |sim, p| {
        let Some(every) = ctx.checkpoint_every else {
            return;
        };
        if last_write.elapsed() < every {
            return;
        }
        last_write = Instant::now();
        let checkpoint = FreeRunCheckpoint {
            key: key.clone(),
            sim: sim.state(),
            t: p.history.t.clone(),
            x: p.history.x.clone(),
            next_sample: p.next_sample,
            particle_steps: p.particle_steps,
            wall_time_s: wall_before + started.elapsed().as_secs_f64(),
        };
        // A checkpoint that cannot be written costs only the resume: the run goes on.
        match slosh_io::write_checkpoint(&path, &checkpoint) {
            Ok(_) => ctx.say(&format!(
                "checkpoint at t = {:.2} s of {t_end:.2} s ({:.0} s of wall time)",
                sim.time(),
                checkpoint.wall_time_s
            )),
            Err(e) => ctx.say(&format!("no checkpoint written: {e}")),
        }
    })?;
    let wall_time_s = wall_before + started.elapsed().as_secs_f64();
    if path.exists() {
        if let Err(e) = std::fs::remove_file(&path) {
            ctx.say(&format!(
                "cannot delete the finished run's {}: {e}",
                path.display()
            ));
        }
    }
    if wall_before > 0.0 {
        ctx.say(&format!(
            "run complete: {wall_time_s:.0} s of wall time in all"
        ));
    }
    Ok((run.history, run.particle_steps, wall_time_s))
}

#[cfg(test)]
mod tests {
    use super::*;
    use slosh_core::SphParams;
    use slosh_geometry::{InitialSurface, RectTank2};
    use std::time::Duration;

    fn tank() -> Simulation<2> {
        let params = SphParams::modern();
        let setup = RectTank2::new(0.4, 0.3, 0.2)
            .with_roof(false)
            .with_initial_tilt(0.02)
            .with_initial_shape(InitialSurface::FirstMode)
            .with_layers(params.wall_layers())
            .build(0.02)
            .expect("tank");
        Simulation::new(setup, params).expect("simulation")
    }

    /// A run interrupted half way and continued from its checkpoint gives the record of the
    /// uninterrupted run bit for bit (the state restores every quantity the next step reads),
    /// and the finished run leaves no checkpoint behind.
    #[test]
    fn resumed_free_run_follows_the_uninterrupted_one() {
        let dir = std::env::temp_dir().join(format!("slosh-resume-{}", std::process::id()));
        let ctx = Context {
            quick: true,
            out: dir.clone(),
            progress: None,
            checkpoint_every: Some(Duration::ZERO),
            stage: 0,
        };
        let (t_mid, t_end, sample) = (0.25, 0.5, 0.01);
        let mut whole = tank();
        let (reference, reference_steps, _) =
            free_run_resumable(&ctx, "decay", &mut whole, t_end, sample).expect("whole run");
        assert!(!checkpoint_path(&ctx, "decay").exists());

        // The first half, as an interrupted run leaves it: its last checkpoint on disk.
        let mut first = tank();
        let key = run_key("decay", &first, sample);
        let mut progress = FreeRun::start(&first, sample);
        progress
            .advance(&mut first, t_mid, sample, |_, _| {})
            .expect("first half");
        let checkpoint = FreeRunCheckpoint {
            key,
            sim: first.state(),
            t: progress.history.t.clone(),
            x: progress.history.x.clone(),
            next_sample: progress.next_sample,
            particle_steps: progress.particle_steps,
            wall_time_s: 1.0,
        };
        slosh_io::write_checkpoint(&checkpoint_path(&ctx, "decay"), &checkpoint).expect("write");

        let mut resumed = tank();
        let (history, steps, wall_s) =
            free_run_resumable(&ctx, "decay", &mut resumed, t_end, sample).expect("resumed run");
        // The wall time counts the interrupted part (1 s in its checkpoint) as well.
        assert!(wall_s >= 1.0, "{wall_s}");
        assert_eq!(history.t, reference.t);
        assert_eq!(history.x, reference.x);
        assert_eq!(steps, reference_steps);
        assert!(!checkpoint_path(&ctx, "decay").exists());

        // A checkpoint of another run (another stem's key) is set aside: the run starts afresh.
        let mut other = checkpoint;
        other.key = "another run".into();
        slosh_io::write_checkpoint(&checkpoint_path(&ctx, "decay"), &other).expect("write");
        let mut afresh = tank();
        let (history, _, _) =
            free_run_resumable(&ctx, "decay", &mut afresh, t_end, sample).expect("afresh");
        assert_eq!(history.x, reference.x);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
