//! Checkpoints of a run in `DIR/checkpoint/` and what `slosh resume DIR` reads back.
//!
//! - `run.ron`: what the run was started with (script, its checksum, the `--set` values, the
//!   folders it may read, the dimension), written once when the run starts;
//! - `state.bin`: the state to continue from (`slosh_run::RunCheckpoint`: the solver's
//!   particle arrays and load window, the series rows so far, the roof map) with the frame
//!   index and the run's interruptions, in the container of `slosh_io::write_checkpoint`
//!   (versioned, checksummed, written atomically: the previous checkpoint stays whole until
//!   the new one is complete).

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use slosh_run::RunCheckpoint;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The checkpoint folder inside a run folder.
pub const CHECKPOINT_DIR: &str = "checkpoint";
/// Default wall time between checkpoints.
pub const DEFAULT_CHECKPOINT_EVERY: Duration = Duration::from_secs(600);

/// What a run was started with: enough to build the same case again.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    /// Program version that wrote the checkpoint.
    pub version: String,
    /// The case script, as given on the command line.
    pub script: PathBuf,
    /// The working directory the run started in (relative paths are relative to it).
    pub working_dir: PathBuf,
    /// CRC-32 of the script's bytes when the run started.
    pub script_crc32: u32,
    /// The `--set NAME=VALUE` arguments, as given.
    pub sets: Vec<String>,
    /// The `--allow-read` folders.
    pub allow_read: Vec<PathBuf>,
    /// Space dimension of the case.
    pub dim: usize,
    /// Wall time between checkpoints (s).
    pub checkpoint_every_s: f64,
    /// The `--backend` the run was started with (`None`: the script's).
    #[serde(default)]
    pub backend: Option<String>,
}

impl RunRecord {
    /// The record of a run of `script` with `sets` and `allow_read`.
    pub fn new(
        script: &Path,
        sets: &[String],
        allow_read: &[PathBuf],
        every: Duration,
    ) -> Result<Self> {
        let text = std::fs::read(script)
            .with_context(|| format!("cannot read the script {}", script.display()))?;
        let working_dir =
            std::env::current_dir().context("cannot read the current working directory")?;
        Ok(RunRecord {
            version: env!("CARGO_PKG_VERSION").into(),
            script: script.to_path_buf(),
            working_dir,
            script_crc32: crc32fast::hash(&text),
            sets: sets.to_vec(),
            allow_read: allow_read.to_vec(),
            dim: 0,
            checkpoint_every_s: every.as_secs_f64(),
            backend: None,
        })
    }

    /// CRC-32 of what decides the run's physics: the version, script and its CRC, the
    /// working folder, the `--set`s, the `--allow-read` folders and the dimension (not the
    /// checkpoint interval or the backend, which a resumption may change). `state.bin` keeps
    /// it, so that a `run.ron` edited after the state was written is refused.
    pub fn inputs_crc32(&self) -> u32 {
        let inputs = (
            &self.version,
            &self.script,
            &self.working_dir,
            self.script_crc32,
            &self.sets,
            &self.allow_read,
            self.dim,
        );
        crc32fast::hash(format!("{inputs:?}").as_bytes())
    }

    /// Reads `DIR/checkpoint/run.ron` of the run folder `dir`, checking that the script is
    /// still the one the run started with.
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(CHECKPOINT_DIR).join("run.ron");
        if !path.exists() {
            bail!(
                "{} holds no checkpoint to resume from: a run writes one every \
                 --checkpoint-every (default 10 min), when it is interrupted (SIGINT, SIGTERM) \
                 and at its end, unless --checkpoint-every 0",
                dir.display()
            );
        }
        let record: RunRecord = slosh_io::read_ron(&path)?;
        let text = std::fs::read(record.working_dir.join(&record.script)).with_context(|| {
            format!(
                "cannot read the script the run started with, {}",
                record.script.display()
            )
        })?;
        if crc32fast::hash(&text) != record.script_crc32 {
            bail!(
                "the script {} changed since the run in {} started: a resumed run must be the \
                 same case (restore the script, or start the run again)",
                record.script.display(),
                dir.display()
            );
        }
        if record.version != env!("CARGO_PKG_VERSION") {
            bail!(
                "the checkpoint in {} was written by slosh {}; this is slosh {}: resume it with \
                 that version",
                dir.display(),
                record.version,
                env!("CARGO_PKG_VERSION")
            );
        }
        Ok(record)
    }
}

/// One interruption of a run and its resumption.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ResumeRecord {
    /// Simulated time of the checkpoint the run continued from (s).
    pub from_time: f64,
    /// Steps taken at that checkpoint.
    pub from_step: u64,
    /// When the run was resumed (seconds since 1970-01-01 UTC).
    pub resumed_at_unix_s: u64,
}

/// The contents of `state.bin`.
#[derive(Serialize, Deserialize)]
pub struct CheckpointFile<const D: usize> {
    /// The frame index so far (time, file).
    pub frames: Vec<(f64, String)>,
    /// The run's earlier interruptions and resumptions.
    pub resumes: Vec<ResumeRecord>,
    /// The run's state.
    pub state: RunCheckpoint<D>,
    /// [`RunRecord::inputs_crc32`] of the `run.ron` the state was written with.
    pub inputs_crc32: u32,
}

/// Writes the checkpoints of a running case.
pub struct CheckpointWriter {
    dir: PathBuf,
    /// [`RunRecord::inputs_crc32`] of the run's record, written with every state.
    inputs_crc32: u32,
    every: Duration,
    last: Instant,
    /// The run's interruptions so far, carried from checkpoint to checkpoint.
    pub resumes: Vec<ResumeRecord>,
    /// Checkpoints written by this process.
    pub written: u64,
    /// The simulated time (s) of the last checkpoint this process wrote.
    pub last_time: Option<f64>,
}

impl CheckpointWriter {
    /// Checkpoints of the run folder `out` every `every` of wall time, after writing
    /// `record` (with the case's dimension `dim`) into `checkpoint/run.ron`.
    pub fn start(out: &Path, record: &RunRecord, dim: usize, every: Duration) -> Result<Self> {
        let dir = out.join(CHECKPOINT_DIR);
        let record = RunRecord {
            dim,
            ..record.clone()
        };
        slosh_io::write_ron(dir.join("run.ron"), &record)?;
        Ok(CheckpointWriter {
            dir,
            inputs_crc32: record.inputs_crc32(),
            every,
            last: Instant::now(),
            resumes: Vec::new(),
            written: 0,
            last_time: None,
        })
    }

    /// True once `every` has passed since the last checkpoint.
    pub fn due(&self) -> bool {
        self.last.elapsed() >= self.every
    }

    /// Writes `state` with the frame index `frames`.
    pub fn write<const D: usize>(
        &mut self,
        frames: &[(f64, String)],
        state: &RunCheckpoint<D>,
    ) -> Result<()> {
        #[derive(Serialize)]
        struct Borrowed<'a, const D: usize> {
            frames: &'a [(f64, String)],
            resumes: &'a [ResumeRecord],
            state: &'a RunCheckpoint<D>,
            inputs_crc32: u32,
        }
        // A failed write (a full disk) is tried again after `every`, not at every step.
        self.last = Instant::now();
        slosh_io::write_checkpoint(
            &self.dir.join("state.bin"),
            &Borrowed {
                frames,
                resumes: &self.resumes,
                state,
                inputs_crc32: self.inputs_crc32,
            },
        )?;
        self.written += 1;
        self.last_time = Some(state.sim.time);
        Ok(())
    }
}

/// Reads `DIR/checkpoint/state.bin` of the run folder `dir`.
/// Refuses the state when `checkpoint/run.ron` no longer holds the inputs the state was
/// written with (its `sets` edited, say): the run would jump to another case at the resume.
pub fn read_state<const D: usize>(dir: &Path) -> Result<CheckpointFile<D>> {
    let path = dir.join(CHECKPOINT_DIR).join("state.bin");
    let file: CheckpointFile<D> = slosh_io::read_checkpoint(&path)
        .map_err(|e| anyhow::anyhow!(e))
        .with_context(|| format!("cannot resume the run in {}", dir.display()))?;
    let record_path = dir.join(CHECKPOINT_DIR).join("run.ron");
    let record: RunRecord = slosh_io::read_ron(&record_path)?;
    if record.inputs_crc32() != file.inputs_crc32 {
        bail!(
            "{} was changed after the run's state was written (its script, --set values or \
             folders differ from the run's): a resumed run must be the same case; restore the \
             file, or start the run again",
            record_path.display()
        );
    }
    Ok(file)
}

/// A duration of wall time: `600`, `30s`, `10m`, `1.5h`; `0` means never.
pub fn parse_every(text: &str) -> Result<Option<Duration>, String> {
    let t = text.trim();
    let (number, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c),
        _ => (t, 's'),
    };
    let scale = match unit {
        's' => 1.0,
        'm' => 60.0,
        'h' => 3600.0,
        _ => {
            return Err(format!(
                "{text}: use seconds (600, 30s), minutes (10m) or hours (1h)"
            ))
        }
    };
    // A year: beyond it a checkpoint interval means none (and a duration far beyond it
    // cannot be added to a clock reading).
    const LONGEST_S: f64 = 365.0 * 86_400.0;
    match number.trim().parse::<f64>() {
        Ok(0.0) => Ok(None),
        Ok(x) if x.is_finite() && x > 0.0 && x * scale > LONGEST_S => Err(format!(
            "{text}: longer than a year between checkpoints; give 0 for none"
        )),
        Ok(x) if x.is_finite() && x > 0.0 => Ok(Some(Duration::from_secs_f64(x * scale))),
        _ => Err(format!(
            "{text}: expected a positive duration such as 600, 30s, 10m or 1h, or 0 for none"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_every("600"), Ok(Some(Duration::from_secs(600))));
        assert_eq!(parse_every("30s"), Ok(Some(Duration::from_secs(30))));
        assert_eq!(parse_every("10m"), Ok(Some(Duration::from_secs(600))));
        assert_eq!(parse_every("1.5h"), Ok(Some(Duration::from_secs(5400))));
        assert_eq!(parse_every("0"), Ok(None));
        assert!(parse_every("-1m").is_err());
        assert!(parse_every("10d").is_err());
        assert!(parse_every("soon").is_err());
        // Beyond any clock: refused, not a panic.
        for huge in ["1e20", "1e300s", "1e17h", "366d", "9000h"] {
            assert!(parse_every(huge).is_err(), "{huge}");
        }
        assert!(parse_every("8000h").is_ok());
    }
}
