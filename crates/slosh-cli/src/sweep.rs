//! `slosh sweep CASE.rhai --vary NAME=V1,V2,... [--vary ...] [--out DIR] [--jobs N]`:
//! a case run over the cartesian product of parameter values.
//!
//! - **Values**: `--vary NAME=V1,V2,...` reads each value like `--set` does (number,
//!   `true`/`false`, or text; quotes optional, and a quoted value may contain commas). An item
//!   `START:STOP:STEP` is a numeric range with STOP included when it falls on the grid, e.g.
//!   `tank_height=0.56:0.66:0.02` (integers when all three are integers, otherwise numbers
//!   rounded to the decimals written). Lists and ranges mix: `dx=0.01,0.02:0.04:0.01`.
//!   A single value (`--vary duration=4`) fixes a parameter for every case.
//! - **Order**: the first `--vary` varies slowest.
//! - **Folders**: each case runs in `DIR/<name>-<value>__<name>-<value>...` (characters other
//!   than letters, digits, `.`, `+`, `-`, `_` become `_`), with the child's messages kept in
//!   `run.log` there.
//! - **Execution**: one child process per case (`slosh run CASE --set ... --out ... --quiet
//!   --threads T`), at most `jobs` at once, `T = max(1, cores / jobs)`. Processes isolate a
//!   crash or blow-up of one case from the others and give each case its own worker pool.
//! - **Resumable**: a case whose folder holds a `summary.ron` with status `"completed"` and
//!   the same parameter values (the varied ones, and the script's other parameters at the
//!   defaults it gives them with the case's values set) is not run again; its row is read
//!   from that summary. Changes to the script's code, not its
//!   parameters, are not detected: delete the folder (or `DIR`) to rerun. A case stopped
//!   part way with a checkpoint continues from it (`slosh resume`): one a signal stopped
//!   (`"interrupted"`), and one killed outright, whose summary still says `"running"`,
//!   when its checkpoint was started with the same `--set` values and script (one killed
//!   after the checkpoint of its end, which cannot be resumed, runs again from the start).
//! - **Table**: `DIR/sweep.csv`, one row per case in sweep order: `case` (the folder), the
//!   varied values, `status` (`completed`/`failed`), `error`, then every number at the top
//!   level of the summary, `theory_<name>` and `post_<name>` (the script's `post` results).

use anyhow::{bail, Context, Result};
use serde::de::{Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use slosh_script::{list_params_with, load_case, parse_set_value, CaseOptions, ParamValue};
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// Largest number of values one `--vary` range may produce (guards against a wrong step).
const MAX_RANGE_VALUES: usize = 10_000;
/// Largest number of cases of one sweep (the product of its `--vary` counts): each case is a
/// run folder, and three ranges at the single-range limit would make 10¹² of them.
const MAX_CASES: usize = 100_000;

/// How a case of a sweep ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CaseStatus {
    /// Run now and completed.
    Completed,
    /// Completed in an earlier sweep; not run again.
    Skipped,
    /// Failed (the error says why); the other cases went on.
    Failed,
    /// Stopped by SIGINT/SIGTERM (while running, or not started): run the sweep again.
    Interrupted,
    /// Not run yet (`--collect` of a sweep run as a Slurm job array).
    Missing,
}

impl CaseStatus {
    /// The word written in `sweep.csv` (a skipped case is `completed` there).
    pub fn csv_word(self) -> &'static str {
        match self {
            CaseStatus::Completed | CaseStatus::Skipped => "completed",
            CaseStatus::Failed => "failed",
            CaseStatus::Interrupted => "interrupted",
            CaseStatus::Missing => "missing",
        }
    }
}

impl fmt::Display for CaseStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CaseStatus::Completed => "completed",
            CaseStatus::Skipped => "skipped (done before)",
            CaseStatus::Failed => "failed",
            CaseStatus::Interrupted => "interrupted",
            CaseStatus::Missing => "missing (not run yet)",
        })
    }
}

/// One case of a sweep.
#[derive(Clone, Debug)]
pub struct CaseOutcome {
    /// Sub-folder name (also the `case` column of `sweep.csv`).
    pub folder: String,
    /// The varied parameters with this case's values, in `--vary` order.
    pub values: Vec<(String, ParamValue)>,
    /// How it ended.
    pub status: CaseStatus,
    /// The error message of a failed case.
    pub error: Option<String>,
    /// Wall time of the case (s): the child process for a run case, the summary's
    /// `wall_time_s` for a skipped one (NaN when unknown).
    pub wall_time_s: f64,
}

/// The result of [`cli_sweep`].
#[derive(Clone, Debug)]
pub struct SweepOutcome {
    /// The sweep folder.
    pub out_dir: PathBuf,
    /// `out_dir/sweep.csv`.
    pub csv: PathBuf,
    /// Every case, in sweep order (first `--vary` slowest).
    pub cases: Vec<CaseOutcome>,
}

impl SweepOutcome {
    fn count(&self, status: CaseStatus) -> usize {
        self.cases.iter().filter(|c| c.status == status).count()
    }
    /// Cases that failed.
    pub fn failed(&self) -> usize {
        self.count(CaseStatus::Failed)
    }
    /// Cases run and completed in this call.
    pub fn completed(&self) -> usize {
        self.count(CaseStatus::Completed)
    }
    /// Cases found completed from an earlier sweep and not run again.
    pub fn skipped(&self) -> usize {
        self.count(CaseStatus::Skipped)
    }
}

/// One `--vary` argument: a parameter name and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Vary {
    /// Parameter name.
    pub name: String,
    /// Values, in the order given.
    pub values: Vec<ParamValue>,
}

/// Parses `NAME=V1,V2,...` (items may be `START:STOP:STEP` ranges); see the module docs.
pub fn parse_vary(arg: &str) -> Result<Vary> {
    let Some((name, list)) = arg.split_once('=') else {
        bail!("--vary {arg}: expected NAME=V1,V2,... (e.g. --vary tank_height=0.56,0.6) or NAME=START:STOP:STEP");
    };
    let name = name.trim();
    if name.is_empty() {
        bail!("--vary {arg}: the parameter name before '=' is empty");
    }
    let mut values = Vec::new();
    for item in split_items(list) {
        let item = item.trim();
        if item.is_empty() {
            bail!("--vary {arg}: an empty value (two commas in a row, or a comma at an end); write the values as NAME=V1,V2,...");
        }
        match parse_range(item) {
            Some(range) => values.extend(range.with_context(|| format!("--vary {arg}"))?),
            None => values.push(parse_set_value(item)),
        }
    }
    if values.is_empty() {
        bail!("--vary {arg}: no values after '='; write them as NAME=V1,V2,...");
    }
    for (i, v) in values.iter().enumerate() {
        if values[..i].contains(v) {
            bail!("--vary {arg}: the value {v} appears twice; list each value once");
        }
    }
    Ok(Vary {
        name: name.to_string(),
        values,
    })
}

/// Splits at commas outside single or double quotes.
fn split_items(list: &str) -> Vec<&str> {
    let mut items = Vec::new();
    let mut quote: Option<char> = None;
    let mut start = 0;
    for (i, c) in list.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, ',') => {
                items.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&list[start..]);
    items
}

/// `START:STOP:STEP` when the item has that form with three numbers, else None.
fn parse_range(item: &str) -> Option<Result<Vec<ParamValue>>> {
    let parts: Vec<&str> = item.split(':').map(str::trim).collect();
    if parts.len() != 3 {
        return None;
    }
    let nums: Vec<f64> = parts.iter().filter_map(|p| p.parse::<f64>().ok()).collect();
    if nums.len() != 3 {
        return None;
    }
    let (start, stop, step) = (nums[0], nums[1], nums[2]);
    Some((|| {
        if !(start.is_finite() && stop.is_finite() && step.is_finite()) || step == 0.0 {
            bail!("range {item}: START:STOP:STEP needs finite numbers and a non-zero step");
        }
        if (stop - start) * step < 0.0 {
            bail!(
                "range {item}: the step {step} goes away from STOP; use a step of the other sign"
            );
        }
        let n = ((stop - start) / step + 1e-9).floor() as usize + 1;
        if n > MAX_RANGE_VALUES {
            bail!("range {item}: {n} values (at most {MAX_RANGE_VALUES}); check the step");
        }
        let ints: Vec<i64> = parts.iter().filter_map(|p| p.parse::<i64>().ok()).collect();
        if ints.len() == 3 {
            return Ok((0..n as i64)
                .map(|i| ParamValue::Int(ints[0] + i * ints[2]))
                .collect());
        }
        // Round to the decimals written so that 0.56:0.66:0.02 gives 0.58, not 0.58000000001.
        let decimals = parts
            .iter()
            .map(|p| {
                if p.contains(['e', 'E']) {
                    None
                } else {
                    Some(p.split_once('.').map_or(0, |(_, d)| d.len()))
                }
            })
            .try_fold(0usize, |acc, d| d.map(|d| acc.max(d)));
        Ok((0..n)
            .map(|i| {
                let x = start + i as f64 * step;
                let x = match decimals {
                    Some(d) if d <= 15 => {
                        let scale = 10f64.powi(d as i32);
                        (x * scale).round() / scale
                    }
                    _ => x,
                };
                ParamValue::Float(x)
            })
            .collect())
    })())
}

/// A parameter value as text for a folder name (no quotes).
fn value_text(v: &ParamValue) -> String {
    match v {
        ParamValue::Str(s) => s.clone(),
        other => other.to_string(),
    }
}

/// `text` with characters other than letters, digits, `.`, `+`, `-`, `_` replaced by `_`.
pub(crate) fn folder_safe(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '+' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Makes the case's process receive SIGTERM when the sweep that started it dies, even by
/// SIGKILL (Linux's `PR_SET_PDEATHSIG`): it then stops as on a cluster's time limit, with a
/// checkpoint, instead of running on unwatched and holding its folder against a rerun.
/// Elsewhere a no-op.
fn end_with_the_parent(cmd: &mut Command) {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: the closure runs in the forked child before exec and calls only
        // async-signal-safe functions (prctl, getppid, _exit); it allocates nothing.
        let parent = std::process::id() as libc::pid_t;
        unsafe {
            cmd.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                // The sweep died between the fork and the prctl: end now.
                if libc::getppid() != parent {
                    libc::_exit(143);
                }
                Ok(())
            });
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = cmd;
}

/// Refuses a name that is to become one run's folder unless it is a plain single path
/// component of [`folder_safe`] characters: not empty, not `.` or `..`, at most 255 bytes. A
/// name read back from a file (`assess.ron`, a suite) is data and never leads outside the
/// folder it belongs in.
pub(crate) fn check_folder_name(name: &str) -> Result<()> {
    if name.is_empty() || name == "." || name == ".." || folder_safe(name) != name {
        bail!(
            "the run name {name:?} is not a plain folder name: use letters, digits, '.', '+', \
             '-' and '_', and not \".\" or \"..\""
        );
    }
    if name.len() > 255 {
        bail!("the run name {name:?} is longer than a folder name may be (255 bytes)");
    }
    Ok(())
}

/// The sub-folder name of a case: `name-value__name-value`, sanitised.
pub fn case_folder_name(values: &[(String, ParamValue)]) -> String {
    let name = values
        .iter()
        .map(|(n, v)| format!("{}-{}", folder_safe(n), folder_safe(&value_text(v))))
        .collect::<Vec<_>>()
        .join("__");
    if name.is_empty() {
        "case".into()
    } else {
        name
    }
}

/// A parameter value as read back from `summary.ron` (ParamValue's serialised form).
#[derive(Clone, Debug, Deserialize)]
enum SummaryValue {
    Float(f64),
    Int(i64),
    Bool(bool),
    Str(String),
}

impl From<SummaryValue> for ParamValue {
    fn from(v: SummaryValue) -> Self {
        match v {
            SummaryValue::Float(x) => ParamValue::Float(x),
            SummaryValue::Int(i) => ParamValue::Int(i),
            SummaryValue::Bool(b) => ParamValue::Bool(b),
            SummaryValue::Str(s) => ParamValue::Str(s),
        }
    }
}

/// The part of `summary.ron` a sweep needs with its types.
#[derive(Debug, Deserialize)]
struct SummaryHead {
    status: String,
    #[serde(default)]
    error: Option<String>,
    /// Not written (yet) by `slosh run`; a post(run) error recorded here marks the case
    /// as not completed.
    #[serde(default)]
    post_error: Option<String>,
    #[serde(default)]
    parameters: Vec<(String, SummaryValue)>,
    #[serde(default)]
    post: Vec<(String, SummaryValue)>,
    /// The roof load's scalars become columns too.
    #[serde(default)]
    roof_load: Option<slosh_run::RoofLoadSummary>,
}

/// The top level of a RON struct with its fields in file order.
struct OrderedFields(Vec<(String, ron::Value)>);

impl<'de> Deserialize<'de> for OrderedFields {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = OrderedFields;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a struct of named fields")
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<Self::Value, A::Error> {
                let mut fields = Vec::new();
                while let Some((k, v)) = map.next_entry::<String, ron::Value>()? {
                    fields.push((k, v));
                }
                Ok(OrderedFields(fields))
            }
        }
        d.deserialize_any(V)
    }
}

/// A summary read back: its typed head and its scalars flattened to (column, text).
pub(crate) struct ReadSummary {
    head: SummaryHead,
    scalars: Vec<(String, String)>,
}

impl ReadSummary {
    fn completed(&self) -> bool {
        self.head.status == "completed" && self.head.post_error.is_none()
    }
    fn wall_time(&self) -> f64 {
        self.scalars
            .iter()
            .find(|(k, _)| k == "wall_time_s")
            .and_then(|(_, v)| v.parse().ok())
            .unwrap_or(f64::NAN)
    }
}

fn number_text(v: &ron::Value) -> Option<String> {
    match v {
        ron::Value::Number(n) => Some(slosh_io::format_f64(n.into_f64())),
        _ => None,
    }
}

fn read_summary(path: &Path) -> Result<ReadSummary> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_summary(&text, &path.display().to_string())
}

/// The `sweep.csv` columns of a `summary.ron` text with their values as text (numbers of the
/// summary, `theory_*` and `post_*`); `source` names it in errors.
pub fn summary_columns(text: &str, source: &str) -> Result<Vec<(String, String)>> {
    parse_summary(text, source).map(|s| s.scalars)
}

fn parse_summary(text: &str, source: &str) -> Result<ReadSummary> {
    let head: SummaryHead = ron::from_str(text)
        .with_context(|| format!("{source} is not a summary written by slosh run"))?;
    let fields: OrderedFields = ron::from_str(text)
        .with_context(|| format!("{source} is not a summary written by slosh run"))?;
    let mut scalars = numeric_fields(&fields);
    if let Some(load) = &head.roof_load {
        for (k, v) in load.scalars() {
            scalars.push((k, slosh_io::format_f64(v)));
        }
    }
    for (k, v) in &head.post {
        let t = match v {
            SummaryValue::Float(x) => slosh_io::format_f64(*x),
            SummaryValue::Int(i) => i.to_string(),
            SummaryValue::Bool(b) => b.to_string(),
            SummaryValue::Str(s) => s.clone(),
        };
        scalars.push((format!("post_{k}"), t));
    }
    Ok(ReadSummary { head, scalars })
}

/// The numbers of a summary: its numeric top-level fields and `theory_<name>` for the numbers
/// of its `theory` map, as (column, text).
fn numeric_fields(fields: &OrderedFields) -> Vec<(String, String)> {
    let mut scalars = Vec::new();
    for (key, value) in &fields.0 {
        if let Some(t) = number_text(value) {
            scalars.push((key.clone(), t));
        } else if key == "theory" {
            if let ron::Value::Map(m) = value {
                for (k, v) in m.iter() {
                    if let (ron::Value::String(k), Some(t)) = (k, number_text(v)) {
                        scalars.push((format!("theory_{k}"), t));
                    }
                }
            }
        }
    }
    scalars
}

/// The first columns of `sweep.csv`: the case folder, the varied parameters, status and error.
fn fixed_columns(varied: &[String]) -> Vec<String> {
    let mut header: Vec<String> = vec!["case".into()];
    header.extend(varied.iter().cloned());
    header.push("status".into());
    header.push("error".into());
    header
}

/// The column of a summary scalar: its name, or `summary_<name>` when a fixed column (a
/// varied `duration`, say) has that name.
fn scalar_column(fixed: &[String], name: &str) -> String {
    if fixed.iter().any(|h| h == name) {
        format!("summary_{name}")
    } else {
        name.to_string()
    }
}

/// The columns `sweep.csv` has for these varied parameters, known before any case runs: the
/// fixed columns and the numbers of `summary.ron`. Not included: the `post_<name>` columns,
/// which hold what the script's `post(run)` returns and are known only after a run.
pub fn known_columns(varied: &[String]) -> Vec<String> {
    let fixed = fixed_columns(varied);
    let blank = ron::to_string(&slosh_case::Summary::default()).unwrap_or_default();
    let fields = ron::from_str::<OrderedFields>(&blank).unwrap_or(OrderedFields(Vec::new()));
    let mut columns = fixed.clone();
    for (name, _) in numeric_fields(&fields) {
        let column = scalar_column(&fixed, &name);
        if !columns.contains(&column) {
            columns.push(column);
        }
    }
    columns
}

/// True when the summary's parameters agree with `expected` (every varied parameter must be
/// present; the script's other parameters are compared when the summary lists them).
fn same_parameters(
    summary: &SummaryHead,
    expected: &[(String, ParamValue)],
    varied: &[(String, ParamValue)],
) -> bool {
    let used: HashMap<&str, ParamValue> = summary
        .parameters
        .iter()
        .map(|(k, v)| (k.as_str(), v.clone().into()))
        .collect();
    varied.iter().all(|(k, v)| used.get(k.as_str()) == Some(v))
        && expected
            .iter()
            .all(|(k, v)| used.get(k.as_str()).is_none_or(|u| u == v))
}

/// Everything about one case before it runs.
pub(crate) struct Planned {
    /// Sub-folder name.
    pub(crate) folder: String,
    /// The run folder.
    pub(crate) dir: PathBuf,
    /// The parameters passed with `--set`.
    pub(crate) values: Vec<(String, ParamValue)>,
    /// The script's parameters with this case's values.
    pub(crate) expected: Vec<(String, ParamValue)>,
}

impl Planned {
    /// A case of script `case` (read with `options`) run in `parent/folder` with `values`
    /// set. Its other parameters are expected at the defaults the script gives them with
    /// these values set (a default may follow another parameter, as an excitation frequency
    /// follows the tank's width); `declared`, the script's defaults with nothing set, stands
    /// in when the script refuses these values (the case then fails on its own).
    pub(crate) fn new(
        folder: String,
        parent: &Path,
        values: Vec<(String, ParamValue)>,
        (case, options): (&Path, &CaseOptions),
        declared: &[slosh_script::ParamDecl],
    ) -> Planned {
        let with_values = CaseOptions {
            overrides: values.clone(),
            ..options.clone()
        };
        let own = list_params_with(case, &with_values).ok();
        let expected = own
            .as_deref()
            .unwrap_or(declared)
            .iter()
            .map(|p| {
                let v = values
                    .iter()
                    .find(|(n, _)| *n == p.name)
                    .map_or_else(|| p.default.clone(), |(_, v)| v.clone());
                (p.name.clone(), v)
            })
            .collect();
        Planned {
            dir: parent.join(&folder),
            folder,
            values,
            expected,
        }
    }

    /// The `--set NAME=VALUE` arguments of the case's run, as its checkpoint records them.
    /// ParamValue's Display quotes strings, which `--set` strips: the text round-trips.
    fn set_args(&self) -> Vec<String> {
        self.values
            .iter()
            .map(|(name, value)| format!("{name}={value}"))
            .collect()
    }
}

/// The result of one case: its outcome and, when readable, its summary.
pub(crate) struct Done {
    /// How it ended.
    pub(crate) outcome: CaseOutcome,
    summary: Option<ReadSummary>,
}

/// Runs `case` over the cartesian product of the `--vary` values (see the module docs) and
/// writes `DIR/sweep.csv`. `exe` is the `slosh` executable the cases run with (the CLI passes
/// `std::env::current_exe()`); `jobs` is the number of cases run at once (0: one per core, up
/// to the number of cases). Failed cases do not stop the others: they are reported on stderr
/// and in the outcome, and the caller decides the exit status. Errors are returned only for
/// bad arguments or when the sweep's own files cannot be written.
pub fn cli_sweep(
    exe: &Path,
    case: &Path,
    vary: &[String],
    out: Option<PathBuf>,
    jobs: usize,
    quiet: bool,
) -> Result<SweepOutcome> {
    cli_sweep_reading(exe, case, vary, out, jobs, quiet, &[])
}

/// [`cli_sweep`] whose cases may also read files below the `allow_read` folders (`slosh
/// sweep --allow-read DIR`, passed on to each case's `slosh run`).
pub fn cli_sweep_reading(
    exe: &Path,
    case: &Path,
    vary: &[String],
    out: Option<PathBuf>,
    jobs: usize,
    quiet: bool,
    allow_read: &[PathBuf],
) -> Result<SweepOutcome> {
    cli_sweep_as(
        exe,
        case,
        vary,
        out,
        jobs,
        quiet,
        allow_read,
        &SweepMode::Run,
    )
}

/// What `slosh sweep` does with its cases.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepMode {
    /// Run them here and write `sweep.csv`.
    Run,
    /// Write `DIR/sweep.sbatch`, a Slurm job array with one task per case whose command is
    /// this sweep's with `--task $SLURM_ARRAY_TASK_ID`; submit it with `sbatch` when `submit`.
    Slurm {
        /// The `#SBATCH` options.
        options: crate::slurm::SlurmOptions,
        /// Run `sbatch` after writing.
        submit: bool,
    },
    /// Run case `index` only (an array task; `None`: `$SLURM_ARRAY_TASK_ID`) with `threads`
    /// threads (`None`: [`crate::slurm::task_threads`]'s choice); `sweep.csv` is left to
    /// `Collect`.
    Task {
        /// The case index.
        index: Option<usize>,
        /// The run's threads.
        threads: Option<usize>,
    },
    /// Write `sweep.csv` from the cases finished so far (the others `missing` or `failed`).
    Collect,
}

/// [`cli_sweep_reading`] in one of the [`SweepMode`]s. The outcome of `Slurm` has no cases,
/// that of `Task` the one case run.
#[allow(clippy::too_many_arguments)]
pub fn cli_sweep_as(
    exe: &Path,
    case: &Path,
    vary: &[String],
    out: Option<PathBuf>,
    jobs: usize,
    quiet: bool,
    allow_read: &[PathBuf],
    mode: &SweepMode,
) -> Result<SweepOutcome> {
    let read_options = CaseOptions {
        allow_read: allow_read.to_vec(),
        ..CaseOptions::default()
    };
    if vary.is_empty() {
        bail!("slosh sweep needs at least one --vary NAME=V1,V2,... (e.g. --vary tank_height=0.56,0.6,0.66)");
    }
    if !exe.is_file() {
        bail!(
            "the slosh executable {} that runs the cases was not found",
            exe.display()
        );
    }
    let varies: Vec<Vary> = vary.iter().map(|a| parse_vary(a)).collect::<Result<_>>()?;
    for (i, v) in varies.iter().enumerate() {
        if matches!(v.name.as_str(), "case" | "status" | "error") {
            bail!(
                "--vary {}: a parameter named `{}` cannot be swept because sweep.csv uses that column name itself; rename the parameter in the script",
                v.name,
                v.name
            );
        }
        if varies[..i].iter().any(|w| w.name == v.name) {
            bail!(
                "--vary {} is given twice; put all its values in one --vary {}=V1,V2,...",
                v.name,
                v.name
            );
        }
    }

    let cases = varies
        .iter()
        .try_fold(1usize, |n, v| n.checked_mul(v.values.len()))
        .filter(|&n| n <= MAX_CASES);
    if cases.is_none() {
        let counts: Vec<String> = varies
            .iter()
            .map(|v| format!("{} {}", v.values.len(), v.name))
            .collect();
        bail!(
            "the sweep would run {} cases (at most {MAX_CASES}): fewer values, or several \
             sweeps",
            counts.join(" × ")
        );
    }

    // Check the names and types against the script's declarations before running anything.
    let declared = list_params_with(case, &read_options)
        .with_context(|| format!("cannot read the parameters of {}", case.display()))?;
    let known = || {
        declared
            .iter()
            .map(|p| format!("  {} = {}", p.name, p.default))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let mut typed: Vec<Vary> = Vec::new();
    for v in &varies {
        let Some(decl) = declared.iter().find(|p| p.name == v.name) else {
            bail!(
                "--vary {}: {} declares no parameter of that name; its parameters are:\n{}",
                v.name,
                case.display(),
                known()
            );
        };
        let values = v
            .values
            .iter()
            .map(|x| {
                x.coerce_to(&decl.default)
                    .map_err(|e| anyhow::anyhow!("--vary {}: {e}", v.name))
            })
            .collect::<Result<Vec<_>>>()?;
        typed.push(Vary {
            name: v.name.clone(),
            values,
        });
    }

    let out_dir = match out {
        Some(d) => d,
        None => {
            let name = load_case(case, &read_options)
                .map(|c| c.name)
                .unwrap_or_else(|_| {
                    case.file_stem()
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_else(|| "case".into())
                });
            PathBuf::from("out").join(format!("{name}-sweep"))
        }
    };
    if matches!(mode, SweepMode::Slurm { .. }) {
        // Before anything is created: the folder is written into the batch script.
        crate::slurm::check_plain("the sweep folder", &out_dir.display().to_string())?;
    }
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create the sweep folder {}", out_dir.display()))?;

    // The cartesian product, first --vary slowest.
    let total: usize = typed.iter().map(|v| v.values.len()).product();
    let mut planned: Vec<Planned> = Vec::with_capacity(total);
    let mut folders: HashMap<String, usize> = HashMap::new();
    for k in 0..total {
        let mut rest = k;
        let mut values = vec![(String::new(), ParamValue::Int(0)); typed.len()];
        for (j, v) in typed.iter().enumerate().rev() {
            values[j] = (v.name.clone(), v.values[rest % v.values.len()].clone());
            rest /= v.values.len();
        }
        let folder = case_folder_name(&values);
        if let Some(&other) = folders.get(&folder) {
            bail!(
                "two cases get the same folder name {folder} ({} and {}): values that differ only in characters other than letters, digits, '.', '+', '-' and '_' cannot be told apart; change one of them",
                fmt_values(&planned[other].values),
                fmt_values(&values)
            );
        }
        folders.insert(folder.clone(), k);
        planned.push(Planned::new(
            folder,
            &out_dir,
            values,
            (case, &read_options),
            &declared,
        ));
    }

    let csv = out_dir.join("sweep.csv");
    // Held while this sweep runs or collects its cases in `out_dir`.
    let _held = match mode {
        SweepMode::Run | SweepMode::Collect => hold_folder(&out_dir, "a sweep")?,
        _ => None,
    };
    let results = match mode {
        SweepMode::Run => run_planned(
            exe, case, &planned, &out_dir, jobs, None, quiet, allow_read, "sweep",
        ),
        SweepMode::Collect => planned.iter().map(collected_case).collect(),
        SweepMode::Slurm { options, submit } => {
            write_sweep_job(
                exe,
                case,
                vary,
                &out_dir,
                allow_read,
                planned.len(),
                options,
                *submit,
            )?;
            return Ok(SweepOutcome {
                out_dir,
                csv,
                cases: Vec::new(),
            });
        }
        SweepMode::Task { index, threads } => {
            let i = crate::slurm::task_index(*index)?;
            let threads = crate::slurm::task_threads(*threads)?;
            if i >= planned.len() {
                bail!(
                    "task {i}: the sweep has {} cases (tasks 0 to {})",
                    planned.len(),
                    planned.len().saturating_sub(1)
                );
            }
            let done = run_planned(
                exe,
                case,
                &planned[i..=i],
                &out_dir,
                1,
                Some(threads),
                quiet,
                allow_read,
                "sweep",
            );
            let cases = done.into_iter().map(|d| d.outcome).collect();
            return Ok(SweepOutcome {
                out_dir,
                csv,
                cases,
            });
        }
    };

    write_table(&csv, &typed, &results)?;
    let cases: Vec<CaseOutcome> = results.into_iter().map(|d| d.outcome).collect();
    let outcome = SweepOutcome {
        out_dir,
        csv,
        cases,
    };
    if !quiet {
        print_table(&outcome);
    }
    if let Some(signal) = crate::interrupt::received() {
        let done = outcome
            .cases
            .iter()
            .filter(|c| c.status != CaseStatus::Interrupted)
            .count();
        return Err(
            anyhow::Error::new(crate::interrupt::Interrupted { signal }).context(format!(
                "the sweep stopped after {done} of {} cases (sweep.csv lists them); run the \
                 same command again to run the rest",
                outcome.cases.len()
            )),
        );
    }
    Ok(outcome)
}

/// A case as `--collect` finds it: completed (with the same parameters), failed, or missing.
fn collected_case(p: &Planned) -> Done {
    let outcome = |status, error: Option<String>, wall_time_s| CaseOutcome {
        folder: p.folder.clone(),
        values: p.values.clone(),
        status,
        error,
        wall_time_s,
    };
    if let Some(s) = done_before(p) {
        return Done {
            outcome: outcome(CaseStatus::Skipped, None, s.wall_time()),
            summary: Some(s),
        };
    }
    match read_summary(&p.dir.join("summary.ron")) {
        Ok(s) if s.head.status == "failed" || s.head.status == "interrupted" => {
            let log = std::fs::read_to_string(p.dir.join("run.log")).unwrap_or_default();
            let error = s.head.error.clone().or_else(|| error_message(&log));
            Done {
                outcome: outcome(CaseStatus::Failed, error, s.wall_time()),
                summary: Some(s),
            }
        }
        _ => Done {
            outcome: outcome(CaseStatus::Missing, Some("not run yet".into()), f64::NAN),
            summary: None,
        },
    }
}

/// Writes `DIR/sweep.sbatch`: one array task per case, each running this sweep's command
/// with `--task $SLURM_ARRAY_TASK_ID`.
#[allow(clippy::too_many_arguments)]
fn write_sweep_job(
    exe: &Path,
    case: &Path,
    vary: &[String],
    out_dir: &Path,
    allow_read: &[PathBuf],
    cases: usize,
    options: &crate::slurm::SlurmOptions,
    submit: bool,
) -> Result<()> {
    let absolute = |p: &Path| -> Result<String> {
        Ok(std::path::absolute(p)
            .with_context(|| format!("cannot resolve {}", p.display()))?
            .display()
            .to_string())
    };
    let out_abs = absolute(out_dir)?;
    let mut args = vec!["sweep".to_string(), absolute(case)?];
    for v in vary {
        args.extend(["--vary".to_string(), v.clone()]);
    }
    args.extend(["--out".to_string(), out_abs.clone()]);
    for dir in allow_read {
        args.extend(["--allow-read".to_string(), absolute(dir)?]);
    }
    let stem = case
        .file_stem()
        .map_or("case".into(), |s| s.to_string_lossy().into_owned());
    let job = crate::slurm::JobArray {
        job_name: format!("slosh-sweep-{}", folder_safe(&stem)),
        tasks: cases,
        exe: std::path::absolute(exe)?,
        task_args: args.clone(),
        log_dir: Path::new(&out_abs).join("slurm"),
    };
    let mut collect = vec![job.exe.display().to_string()];
    collect.extend(args);
    collect.push("--collect".into());
    crate::slurm::write_and_submit(
        &Path::new(&out_abs).join("sweep.sbatch"),
        &job,
        options,
        submit,
        &crate::slurm::command_line(&collect),
    )
}

/// The summary of a case completed before with the same parameters, if its folder holds one.
pub(crate) fn done_before(p: &Planned) -> Option<ReadSummary> {
    read_summary(&p.dir.join("summary.ron"))
        .ok()
        .filter(|s| s.completed() && same_parameters(&s.head, &p.expected, &p.values))
}

/// A case whose run was killed before it could write its summary (which still says
/// "running") was started with this case's `--set` arguments, and its checkpoint can be
/// resumed (the script unchanged, the same program version).
fn killed_with_same_sets(p: &Planned) -> bool {
    slosh_case::checkpoint::RunRecord::read(&p.dir).is_ok_and(|record| record.sets == p.set_args())
}

/// Runs the planned cases of a sweep or an assessment (`what` names it in messages), at most
/// `jobs` at once (0: one per core), each as a child `slosh run` with `threads` threads
/// (`None`: cores / jobs); a case whose folder already
/// holds a completed summary with the same parameters is not run again, and one interrupted
/// with the same parameters and a checkpoint continues from it (`slosh resume`). Returns one result
/// per planned case, in order; cases a SIGINT/SIGTERM kept from starting are `Interrupted`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_planned(
    exe: &Path,
    case: &Path,
    planned: &[Planned],
    out_dir: &Path,
    jobs: usize,
    threads: Option<usize>,
    quiet: bool,
    allow_read: &[PathBuf],
    what: &str,
) -> Vec<Done> {
    let total = planned.len();
    // Resume: cases already completed with these parameters are not run again.
    let mut results: Vec<Option<Done>> = Vec::with_capacity(total);
    let mut to_run = Vec::new();
    for (k, p) in planned.iter().enumerate() {
        match done_before(p) {
            Some(s) => results.push(Some(Done {
                outcome: CaseOutcome {
                    folder: p.folder.clone(),
                    values: p.values.clone(),
                    status: CaseStatus::Skipped,
                    error: None,
                    wall_time_s: s.wall_time(),
                },
                summary: Some(s),
            })),
            None => {
                results.push(None);
                to_run.push(k);
            }
        }
    }

    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = if jobs == 0 { cores } else { jobs }
        .min(to_run.len())
        .max(1);
    let threads = threads.unwrap_or((cores / jobs).max(1));
    if !quiet {
        eprintln!(
            "{what}: {total} case{} into {}: {} to run ({} done before), {jobs} at a time with {threads} thread{} each",
            if total == 1 { "" } else { "s" },
            out_dir.display(),
            to_run.len(),
            total - to_run.len(),
            if threads == 1 { "" } else { "s" }
        );
    }

    let results = Mutex::new(results);
    let next = AtomicUsize::new(0);
    let finished = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                if crate::interrupt::received().is_some() {
                    break;
                }
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(&k) = to_run.get(i) else { break };
                let p = &planned[k];
                let done = run_one(exe, case, p, threads, allow_read);
                let n = finished.fetch_add(1, Ordering::SeqCst) + 1;
                let o = &done.outcome;
                if o.status == CaseStatus::Failed {
                    eprintln!(
                        "{what}: case {} failed: {} (log: {})",
                        o.folder,
                        o.error.as_deref().unwrap_or("unknown error"),
                        p.dir.join("run.log").display()
                    );
                } else if !quiet {
                    eprintln!(
                        "{what}: [{n}/{}] {} {} in {:.1} s",
                        to_run.len(),
                        o.folder,
                        o.status,
                        o.wall_time_s
                    );
                }
                results.lock().expect("case results")[k] = Some(done);
            });
        }
    });
    // Cases a signal kept from starting.
    let results: Vec<Done> = results
        .into_inner()
        .expect("case results")
        .into_iter()
        .zip(planned)
        .map(|(d, p)| {
            d.unwrap_or_else(|| Done {
                outcome: CaseOutcome {
                    folder: p.folder.clone(),
                    values: p.values.clone(),
                    status: CaseStatus::Interrupted,
                    error: Some(format!("not started: the {what} was interrupted")),
                    wall_time_s: 0.0,
                },
                summary: None,
            })
        })
        .collect();
    results
}

fn fmt_values(values: &[(String, ParamValue)]) -> String {
    values
        .iter()
        .map(|(n, v)| format!("{n}={v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Waits for a case's process, passing on a SIGINT or SIGTERM the sweep receives (once), so
/// that the case ends its step, keeps its outputs and exits; no case outlives the sweep.
fn wait_forwarding_signals(
    mut child: std::process::Child,
) -> std::io::Result<std::process::ExitStatus> {
    let mut forwarded = false;
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(status);
        }
        if let (Some(signal), false) = (crate::interrupt::received(), forwarded) {
            if let Ok(pid) = i32::try_from(child.id()) {
                // SAFETY: kill(2) with the id of a child this process has not reaped yet.
                unsafe {
                    libc::kill(pid, signal);
                }
            }
            forwarded = true;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// Runs one case as a child `slosh run` (or `slosh resume`, for a case stopped part way) and
/// reads its summary back.
fn run_one(exe: &Path, case: &Path, p: &Planned, threads: usize, allow_read: &[PathBuf]) -> Done {
    let resumed = resumable(p);
    let done = run_child(exe, case, p, threads, allow_read, resumed);
    // A case killed after its last checkpoint, while it wrote its summary and plots, left the
    // checkpoint of a complete run, which `slosh resume` refuses: it runs again from the start.
    let complete_checkpoint = done.outcome.status == CaseStatus::Failed
        && done
            .outcome
            .error
            .as_deref()
            .is_some_and(|e| e.contains(slosh_case::NOTHING_TO_RESUME));
    if resumed && complete_checkpoint {
        return run_child(exe, case, p, threads, allow_read, false);
    }
    done
}

/// Whether the case stopped part way with these parameters and continues from its
/// checkpoint: one stopped by a signal (a cluster's time limit and requeue) says
/// "interrupted"; one killed outright (SIGKILL, the machine or its session gone) still says
/// "running", and its last checkpoint holds the state and the series up to that point. Were
/// such a case still running elsewhere, `slosh resume` would refuse its locked folder.
fn resumable(p: &Planned) -> bool {
    p.dir
        .join(slosh_case::checkpoint::CHECKPOINT_DIR)
        .join("state.bin")
        .exists()
        && read_summary(&p.dir.join("summary.ron"))
            .ok()
            .is_some_and(|s| match s.head.status.as_str() {
                "interrupted" => same_parameters(&s.head, &p.expected, &p.values),
                "running" => killed_with_same_sets(p),
                _ => false,
            })
}

/// Holds the folder `dir` of a sweep (or an assessment: `what`, "a sweep", "an assessment")
/// run on this machine: the
/// system's advisory lock on the open folder, released when the process ends in any way. A
/// second sweep into the same folder is refused before it touches a case (its cases would
/// share folders, one's outputs replacing the other's). `None` on a file system without locks.
/// A Slurm job's array tasks share the folder and do not take it; each case's own folder lock
/// keeps them apart.
pub(crate) fn hold_folder(dir: &Path, what: &str) -> Result<Option<std::fs::File>> {
    use slosh_case::run_folder::{try_lock_folder, FolderLock};
    match try_lock_folder(dir) {
        FolderLock::Held(folder) => Ok(Some(folder)),
        FolderLock::Busy => bail!(
            "{} is in use by another slosh command ({what}, or a run writing into this \
             folder, holds it); wait for it to end, stop it, or choose another --out folder",
            dir.display()
        ),
        FolderLock::Unsupported => Ok(None),
    }
}

/// Whether a live slosh run holds the case folder `dir` (its lock on the open folder): its
/// `run.log` and `summary.ron` are not this sweep's to replace. A lock taken to look is
/// released at once.
fn held_by_a_run(dir: &Path) -> bool {
    matches!(
        slosh_case::run_folder::try_lock_folder(dir),
        slosh_case::run_folder::FolderLock::Busy
    )
}

/// [`run_one`]'s child process: `slosh resume` with `resumable`, else `slosh run`.
fn run_child(
    exe: &Path,
    case: &Path,
    p: &Planned,
    threads: usize,
    allow_read: &[PathBuf],
    resumable: bool,
) -> Done {
    let start = Instant::now();
    let fail = |error: String, summary: Option<ReadSummary>| Done {
        outcome: CaseOutcome {
            folder: p.folder.clone(),
            values: p.values.clone(),
            status: CaseStatus::Failed,
            error: Some(error),
            wall_time_s: start.elapsed().as_secs_f64(),
        },
        summary,
    };
    if let Err(e) = check_folder_name(&p.folder) {
        return fail(format!("{e:#}"), None);
    }
    if let Err(e) = std::fs::create_dir_all(&p.dir) {
        return fail(format!("cannot create {}: {e}", p.dir.display()), None);
    }
    if held_by_a_run(&p.dir) {
        // Another run writes there now: its log and summary stay as they are.
        return fail(
            format!(
                "{} is being written by another slosh run; this case was not started (run the \
                 command again when that run has ended)",
                p.dir.display()
            ),
            None,
        );
    }
    let summary_path = p.dir.join("summary.ron");
    if !resumable {
        // A stale summary must not stand in for this run if the run fails before writing one.
        let _ = std::fs::remove_file(&summary_path);
    }
    let log_path = p.dir.join("run.log");
    let log = match slosh_io::open_no_follow(
        &log_path,
        std::fs::OpenOptions::new()
            .create(true)
            .append(resumable)
            .write(true)
            .truncate(!resumable),
    ) {
        Ok(f) => f,
        Err(e) => return fail(format!("cannot create {}: {e}", log_path.display()), None),
    };
    let log_err = match log.try_clone() {
        Ok(f) => f,
        Err(e) => return fail(format!("cannot write {}: {e}", log_path.display()), None),
    };
    let mut cmd = Command::new(exe);
    if resumable {
        cmd.arg("resume")
            .arg(&p.dir)
            .arg("--quiet")
            .arg("--threads")
            .arg(threads.to_string());
    } else {
        cmd.arg("run")
            .arg(case)
            .arg("--out")
            .arg(&p.dir)
            .arg("--quiet")
            .arg("--threads")
            .arg(threads.to_string());
        for dir in allow_read {
            cmd.arg("--allow-read").arg(dir);
        }
        for set in p.set_args() {
            cmd.arg("--set").arg(set);
        }
    }
    // In a process group of its own, so that a terminal's Ctrl-C reaches the sweep only,
    // which passes it on once (a second SIGINT would stop the case at once).
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    end_with_the_parent(&mut cmd);
    let child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::from(log))
        .stderr(Stdio::from(log_err))
        .spawn();
    let status = match child.and_then(wait_forwarding_signals) {
        Ok(s) => s,
        Err(e) => return fail(format!("cannot start {}: {e}", exe.display()), None),
    };
    let elapsed = start.elapsed().as_secs_f64();
    if let Some(signal) = crate::interrupt::received() {
        let summary = read_summary(&summary_path).ok();
        return Done {
            outcome: CaseOutcome {
                folder: p.folder.clone(),
                values: p.values.clone(),
                status: CaseStatus::Interrupted,
                error: Some(format!(
                    "{} (exit status {status})",
                    crate::interrupt::Interrupted { signal }
                )),
                wall_time_s: elapsed,
            },
            summary,
        };
    }
    let summary = read_summary(&summary_path).ok();
    if status.success() && summary.as_ref().is_some_and(ReadSummary::completed) {
        return Done {
            outcome: CaseOutcome {
                folder: p.folder.clone(),
                values: p.values.clone(),
                status: CaseStatus::Completed,
                error: None,
                wall_time_s: elapsed,
            },
            summary,
        };
    }
    let log_text = std::fs::read_to_string(&log_path).unwrap_or_default();
    let error = error_message(&log_text)
        .or_else(|| summary.as_ref().and_then(|s| s.head.error.clone()))
        .or_else(|| summary.as_ref().and_then(|s| s.head.post_error.clone()))
        .unwrap_or_else(|| {
            if status.success() {
                "the run wrote no completed summary.ron".into()
            } else {
                format!("slosh run exited with {status}")
            }
        });
    fail(error, summary)
}

/// The error paragraph of a `slosh run` log (after `error: `, or a panic message), on one line.
pub(crate) fn error_message(log: &str) -> Option<String> {
    let start = log
        .rfind("error: ")
        .map(|i| i + "error: ".len())
        .or_else(|| log.find("panicked at"))?;
    let text = log[start..]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    (!text.is_empty()).then_some(text)
}

/// Writes `sweep.csv`: case, varied values, status, error, then the union of the summaries'
/// scalar columns in first-seen order.
fn write_table(path: &Path, varies: &[Vary], results: &[Done]) -> Result<()> {
    let names: Vec<String> = varies.iter().map(|v| v.name.clone()).collect();
    let mut header = fixed_columns(&names);
    let fixed = header.len();
    let fixed_names = header.clone();
    let column_of = |k: &str| scalar_column(&fixed_names, k);
    let mut scalar_columns: Vec<String> = Vec::new();
    for d in results {
        for (k, _) in d.summary.iter().flat_map(|s| &s.scalars) {
            let c = column_of(k);
            if !scalar_columns.contains(&c) && !fixed_names.contains(&c) {
                scalar_columns.push(c);
            }
        }
    }
    header.extend(scalar_columns);
    let index: HashMap<String, usize> = header
        .iter()
        .enumerate()
        .skip(fixed)
        .map(|(i, k)| (k.clone(), i))
        .collect();
    let mut table = slosh_io::TableWriter::create_whole(path, &header)
        .with_context(|| format!("cannot write the sweep table {}", path.display()))?;
    for d in results {
        let mut row = vec![String::new(); header.len()];
        row[0] = d.outcome.folder.clone();
        for (j, (_, v)) in d.outcome.values.iter().enumerate() {
            row[1 + j] = value_text(v);
        }
        row[fixed - 2] = d.outcome.status.csv_word().into();
        row[fixed - 1] = d.outcome.error.clone().unwrap_or_default();
        for (k, v) in d.summary.iter().flat_map(|s| &s.scalars) {
            if let Some(&i) = index.get(&column_of(k)) {
                row[i] = v.clone();
            }
        }
        table
            .write_text_row(&row)
            .with_context(|| format!("cannot write the sweep table {}", path.display()))?;
    }
    table
        .finish()
        .with_context(|| format!("cannot write the sweep table {}", path.display()))?;
    Ok(())
}

/// The closing table: case, status, wall time.
fn print_table(outcome: &SweepOutcome) {
    let width = outcome
        .cases
        .iter()
        .map(|c| c.folder.len())
        .max()
        .unwrap_or(4)
        .max(4);
    println!("{:<width$}  {:<22}  wall time", "case", "status");
    for c in &outcome.cases {
        println!(
            "{:<width$}  {:<22}  {:>7.1} s",
            c.folder,
            c.status.to_string(),
            c.wall_time_s
        );
    }
    println!(
        "{} cases: {} completed, {} skipped (done before), {} failed; table: {}",
        outcome.cases.len(),
        outcome.completed(),
        outcome.skipped(),
        outcome.failed(),
        outcome.csv.display()
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_ranges_and_quotes() {
        let v = parse_vary("tank_height=0.56:0.62:0.02,0.7").unwrap();
        assert_eq!(v.name, "tank_height");
        assert_eq!(
            v.values,
            [0.56, 0.58, 0.6, 0.62, 0.7].map(ParamValue::Float).to_vec()
        );
        let v = parse_vary("n=8:40:16").unwrap();
        assert_eq!(v.values, [8, 24, 40].map(ParamValue::Int).to_vec());
        let v = parse_vary("x=1:0:-0.5").unwrap();
        assert_eq!(v.values, [1.0, 0.5, 0.0].map(ParamValue::Float).to_vec());
        let v = parse_vary(r#"roof="a,b",cone"#).unwrap();
        assert_eq!(
            v.values,
            vec![
                ParamValue::Str("a,b".into()),
                ParamValue::Str("cone".into())
            ]
        );
        let v = parse_vary("mesh=C:/tanks/roof.obj").unwrap();
        assert_eq!(v.values, vec![ParamValue::Str("C:/tanks/roof.obj".into())]);
    }

    #[test]
    fn bad_vary_arguments_say_how_to_fix() {
        for (arg, words) in [
            ("tank_height", "NAME=V1,V2"),
            ("=1,2", "name"),
            ("a=1,,2", "empty value"),
            ("a=", "empty value"),
            ("a=1,1", "twice"),
            ("a=0:1:0", "non-zero step"),
            ("a=0:1:-0.1", "other sign"),
            ("a=0:1e9:1", "at most"),
        ] {
            let e = format!("{:#}", parse_vary(arg).unwrap_err());
            assert!(e.contains(words), "{arg}: {e}");
        }
    }

    #[test]
    fn folder_names_are_sanitised() {
        let values = vec![
            ("tank_height".to_string(), ParamValue::Float(0.58)),
            ("smoothing_steps".to_string(), ParamValue::Int(8)),
            ("roof".to_string(), ParamValue::Str("meshes/a b.obj".into())),
        ];
        assert_eq!(
            case_folder_name(&values),
            "tank_height-0.58__smoothing_steps-8__roof-meshes_a_b.obj"
        );
    }

    #[test]
    fn error_message_takes_the_last_error_paragraph() {
        let log = "case: 2D\nerror: depth 0.6 m is above\n  the tank height 0.4 m\n";
        assert_eq!(
            error_message(log).unwrap(),
            "depth 0.6 m is above the tank height 0.4 m"
        );
        assert!(error_message("all fine\n").is_none());
    }
}
