//! Loading a case script into a [`Case`]: parameters, tank, numerics, run control, and the
//! script functions called during and after the run.

use crate::checks;
use crate::engine::{build_engine, Declared, Globals, PlotRequest, Shared};
use crate::error::ScriptError;
use crate::params::{ParamDecl, ParamValue};
use crate::sandbox::ReadSandbox;
use crate::spec::{
    numerics_from_map, GaugeSpec, PressureSensorSpec, Resolution, RunSpec, TankSpec,
};
use rhai::{CallFnOptions, Dynamic, Engine, Map, Scope, AST};
use slosh_core::SphParams;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, RwLock};

/// How to load a case.
#[derive(Clone, Debug, Default)]
pub struct CaseOptions {
    /// `--set NAME=VALUE` overrides, in command-line order.
    pub overrides: Vec<(String, ParamValue)>,
    /// `--allow-read DIR` folders the script may read below, beside its own and its project's.
    pub allow_read: Vec<PathBuf>,
    /// Cap on the memory one evaluation of the script may take, bytes (None:
    /// [`SCRIPT_MEMORY_BUDGET_BYTES`](crate::SCRIPT_MEMORY_BUDGET_BYTES)).
    pub script_memory_bytes: Option<u64>,
}

/// Largest |ground acceleration| a script may return (m/s²): 1000 g, two orders of magnitude
/// above the strongest recorded earthquake motions (≈ 4 g) and shake tables; anything larger
/// is a units or scaling mistake.
pub const MAX_GROUND_ACCEL: f64 = 9810.0;

/// The script functions called during and after a run.
pub struct Excitation {
    engine: Engine,
    ast: AST,
    scope: Scope<'static>,
    file: PathBuf,
    has_ground_accel: bool,
    /// The script's `fn ground_rotation(t)` with the axis and pivot of `run`, when it
    /// defines one.
    rotation: Option<RotationSetup>,
    has_post: bool,
    shared: Shared,
    /// Space dimension of the tank (2 or 3): how many components an array from
    /// `ground_accel` must have.
    dim: usize,
}

/// The axis and pivot of a turning tank.
#[derive(Clone, Copy, Debug)]
struct RotationSetup {
    /// Unit axis `[x, y, z]`.
    axis: [f64; 3],
    /// The pivot `[x, y, z]` (m, tank frame); `None` until [`Excitation::set_default_pivot`]
    /// when the script gives none.
    pivot: Option<[f64; 3]>,
}

/// Largest |angle| `fn ground_rotation(t)` may return (rad): a quarter turn; a larger value
/// is a tank on its side or a mistake of units (degrees for radians).
pub const MAX_TANK_ANGLE: f64 = std::f64::consts::FRAC_PI_2;

/// Time step of the differences that give the rate and angular acceleration of an
/// angle-only `fn ground_rotation(t)` (s): central differences, second-order accurate, of
/// relative error (ω δ)²/6 for the rate and (ω δ)²/12 for the acceleration, below 2e-4 for
/// motions below 5 Hz; within one step of the excitation's start, forward differences (the
/// function is not asked for negative times).
pub const ROTATION_DIFFERENCE_STEP: f64 = 1e-3;

/// The script's `fn ground_accel(t)` (and `fn ground_rotation(t)`) drive the run loop of
/// `slosh-run`: called once per step with the time since the excitation started.
impl slosh_run::GroundMotion for Excitation {
    fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], slosh_run::MotionError> {
        Excitation::ground_accel(self, t).map_err(Into::into)
    }

    fn ground_rotation(
        &mut self,
        t: f64,
    ) -> Result<Option<slosh_core::TankRotation>, slosh_run::MotionError> {
        Excitation::ground_rotation(self, t).map_err(Into::into)
    }
}

/// What `fn ground_rotation(t)` returned.
#[derive(Clone, Copy, Debug)]
enum RotationValue {
    /// The angle alone (rad).
    Angle(f64),
    /// Angle (rad), rate (rad/s), angular acceleration (rad/s²).
    Full(f64, f64, f64),
}

impl RotationValue {
    fn angle(self) -> f64 {
        match self {
            RotationValue::Angle(a) | RotationValue::Full(a, _, _) => a,
        }
    }
}

/// Extra results of `fn post(run)`.
#[derive(Debug, Default)]
pub struct PostResult {
    /// Scalars returned by `post` (name → value as text for non-numbers).
    pub values: Vec<(String, ParamValue)>,
    /// Tables to write as CSV: (file stem, header, rows).
    pub tables: Vec<(String, Vec<String>, Vec<Vec<f64>>)>,
    /// Line plots to draw.
    pub plots: Vec<PlotRequest>,
}

impl Excitation {
    /// True when the script defines `fn ground_accel(t)`.
    pub fn has_ground_accel(&self) -> bool {
        self.has_ground_accel
    }

    /// True when the script defines `fn post(run)`.
    pub fn has_post(&self) -> bool {
        self.has_post
    }

    /// True when the script defines `fn ground_rotation(t)`: the tank turns about a pivot.
    pub fn turns(&self) -> bool {
        self.rotation.is_some()
    }

    /// The pivot `[x, y, z]` (m) a turning tank turns about: the script's `rotation_pivot`, or
    /// the default set by [`Self::set_default_pivot`].
    pub fn rotation_pivot(&self) -> Option<[f64; 3]> {
        self.rotation.and_then(|r| r.pivot)
    }

    /// The axis `[x, y, z]` a turning tank turns about.
    pub fn rotation_axis(&self) -> Option<[f64; 3]> {
        self.rotation.map(|r| r.axis)
    }

    /// Sets the pivot of a turning tank whose script gave none (the centre of the tank's
    /// base, from the built tank).
    pub fn set_default_pivot(&mut self, pivot: [f64; 3]) {
        if let Some(r) = self.rotation.as_mut() {
            r.pivot.get_or_insert(pivot);
        }
    }

    /// The script's `fn ground_rotation(t)` at `t` (s since the excitation started): the
    /// angle (rad) about the axis, its rate and acceleration from central differences of
    /// step [`ROTATION_DIFFERENCE_STEP`], or all three when the function returns
    /// `[angle, rate, acceleration]`. `None` when the script defines no rotation.
    pub fn ground_rotation(
        &mut self,
        t: f64,
    ) -> Result<Option<slosh_core::TankRotation>, ScriptError> {
        let Some(setup) = self.rotation else {
            return Ok(None);
        };
        let Some(pivot) = setup.pivot else {
            return Err(ScriptError::case(
                &self.file,
                "the tank's pivot is not known: the script gives no rotation_pivot and the \
                 tank was not built (the case runner sets the default, the centre of the \
                 tank's base)",
            ));
        };
        let Some((angle, rate, acceleration)) = self.rotation_state(t)? else {
            return Ok(None);
        };
        Ok(Some(slosh_core::TankRotation {
            axis: setup.axis,
            pivot,
            angle,
            rate,
            acceleration,
        }))
    }

    /// The angle (rad), rate (rad/s) and angular acceleration (rad/s²) of
    /// [`Self::ground_rotation`] at `t`, whatever the pivot; `None` without a rotation.
    pub(crate) fn rotation_state(
        &mut self,
        t: f64,
    ) -> Result<Option<(f64, f64, f64)>, ScriptError> {
        if self.rotation.is_none() {
            return Ok(None);
        }
        let first = self.call_rotation(t)?;
        Ok(Some(match first {
            RotationValue::Angle(angle) => {
                let d = ROTATION_DIFFERENCE_STEP;
                if t >= d {
                    let before = self.call_rotation(t - d)?.angle();
                    let after = self.call_rotation(t + d)?.angle();
                    (
                        angle,
                        (after - before) / (2.0 * d),
                        (after - 2.0 * angle + before) / (d * d),
                    )
                } else {
                    let next = self.call_rotation(t + d)?.angle();
                    let second = self.call_rotation(t + 2.0 * d)?.angle();
                    (
                        angle,
                        (-3.0 * angle + 4.0 * next - second) / (2.0 * d),
                        (angle - 2.0 * next + second) / (d * d),
                    )
                }
            }
            RotationValue::Full(a, r, acc) => (a, r, acc),
        }))
    }

    /// One call of `fn ground_rotation(t)`, checked.
    fn call_rotation(&mut self, t: f64) -> Result<RotationValue, ScriptError> {
        let options = CallFnOptions::new().eval_ast(false).rewind_scope(true);
        let value: Dynamic = self
            .engine
            .call_fn_with_options(options, &mut self.scope, &self.ast, "ground_rotation", (t,))
            .map_err(|e| ScriptError::from_eval(&self.file, &e))?;
        let out = if let Some(a) = crate::spec::dynamic_to_f64(&value) {
            RotationValue::Angle(a)
        } else {
            match crate::engine::dynamic_to_vec(&value) {
                Some(v) if v.len() == 3 => RotationValue::Full(v[0], v[1], v[2]),
                _ => {
                    return Err(ScriptError::case(
                        &self.file,
                        format!(
                            "ground_rotation({t}) returned {value} ({}); return the angle in \
                             rad, or [angle (rad), rate (rad/s), angular acceleration (rad/s²)]",
                            value.type_name()
                        ),
                    ))
                }
            }
        };
        let values = match out {
            RotationValue::Angle(a) => [a, 0.0, 0.0],
            RotationValue::Full(a, r, acc) => [a, r, acc],
        };
        if values.iter().any(|v| !v.is_finite()) {
            return Err(ScriptError::case(
                &self.file,
                format!(
                    "ground_rotation({t}) returned a non-finite value {values:?}; the rotation \
                     must be finite (check divisions and records)"
                ),
            ));
        }
        if values[0].abs() > MAX_TANK_ANGLE {
            return Err(ScriptError::case(
                &self.file,
                format!(
                    "ground_rotation({t}) returned {} rad, beyond a quarter turn; the angle is in \
                     radians (deg × π/180)",
                    values[0]
                ),
            ));
        }
        Ok(out)
    }

    /// Ground acceleration (m/s², components x, y, z; in 2D x and vertical) at time `t` (s)
    /// since the excitation started. The script function may return one number (the x
    /// component) or an array of 2 or 3 numbers. The AST is not re-run (`eval_ast(false)`).
    pub fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], ScriptError> {
        if !self.has_ground_accel {
            return Ok([0.0; 3]);
        }
        let options = CallFnOptions::new().eval_ast(false).rewind_scope(true);
        let value: Dynamic = self
            .engine
            .call_fn_with_options(options, &mut self.scope, &self.ast, "ground_accel", (t,))
            .map_err(|e| ScriptError::from_eval(&self.file, &e))?;
        let bad = |what: String| {
            ScriptError::case(
                &self.file,
                format!("ground_accel({t}) returned {what}; return a number (m/s² along x) or an array [ax, ay(, az)]"),
            )
        };
        let mut out = [0.0; 3];
        if let Some(x) = crate::spec::dynamic_to_f64(&value) {
            out[0] = x;
        } else if let Some(v) = crate::engine::dynamic_to_vec(&value) {
            // In 2D [ax, a_vertical]; in 3D [ax, ay, az]: an array of another length would
            // drop a component or read one as another.
            if v.len() != self.dim {
                return Err(ScriptError::case(
                    &self.file,
                    format!(
                        "ground_accel({t}) returned an array of {} values for a {}D tank; return \
                         a number (m/s² along x) or {}",
                        v.len(),
                        self.dim,
                        if self.dim == 2 {
                            "[ax, a_vertical]"
                        } else {
                            "[ax, ay, az]"
                        }
                    ),
                ));
            }
            out[..v.len()].copy_from_slice(&v);
        } else {
            return Err(bad(format!("{value} ({})", value.type_name())));
        }
        if out.iter().any(|a| !a.is_finite()) {
            return Err(ScriptError::case(
                &self.file,
                format!(
                    "ground_accel({t}) returned a non-finite value {out:?}; the excitation \
                     function must return finite accelerations (check divisions and records)"
                ),
            ));
        }
        if let Some(a) = out.iter().find(|a| a.abs() > MAX_GROUND_ACCEL) {
            return Err(ScriptError::case(
                &self.file,
                format!(
                    "ground_accel({t}) returned {a:e} m/s², beyond any ground motion or shake \
                     table (at most {MAX_GROUND_ACCEL:e} m/s², 1000 g); check the units (m/s², \
                     not mm/s² or g·1000) and the scaling"
                ),
            ));
        }
        Ok(out)
    }

    /// Runs `fn post(run)` with the run's results and collects what it returns and writes.
    pub fn post(&mut self, data: &RunData) -> Result<PostResult, ScriptError> {
        let mut result = PostResult::default();
        if !self.has_post {
            return Ok(result);
        }
        let run = data.to_map();
        let options = CallFnOptions::new().eval_ast(false).rewind_scope(true);
        let value: Dynamic = self
            .engine
            .call_fn_with_options(options, &mut self.scope, &self.ast, "post", (run,))
            .map_err(|e| ScriptError::from_eval(&self.file, &e))?;
        if !value.is_unit() {
            let map = value.try_cast::<Map>().ok_or_else(|| {
                ScriptError::case(
                    &self.file,
                    "post(run) must return a map of results (or nothing)",
                )
            })?;
            for (k, v) in map {
                let pv = ParamValue::from_dynamic(&v).unwrap_or(ParamValue::Str(v.to_string()));
                result.values.push((k.to_string(), pv));
            }
        }
        let mut d = self.shared.lock().expect("script state");
        result.tables = std::mem::take(&mut d.tables);
        result.plots = std::mem::take(&mut d.plots);
        Ok(result)
    }
}

/// What a run hands to `fn post(run)`: `run.summary.NAME` (numbers), `run.series.COLUMN`
/// (arrays over the output rows), `run.params.NAME`, and `run.maps.NAME` (arrays of arrays,
/// e.g. the roof pressure map: one array per output row).
#[derive(Clone, Debug, Default)]
pub struct RunData {
    /// Scalar results of the run.
    pub scalars: Vec<(String, f64)>,
    /// Time series by column name.
    pub series: Vec<(String, Vec<f64>)>,
    /// Script parameters with the values used.
    pub params: Vec<(String, ParamValue)>,
    /// Two-dimensional results (rows of values).
    pub maps: Vec<(String, Vec<Vec<f64>>)>,
}

impl RunData {
    fn to_map(&self) -> Map {
        let mut run = Map::new();
        let mut summary = Map::new();
        for (k, v) in &self.scalars {
            summary.insert(k.as_str().into(), (*v).into());
        }
        let mut series = Map::new();
        for (k, v) in &self.series {
            let arr: rhai::Array = v.iter().map(|&x| Dynamic::from(x)).collect();
            series.insert(k.as_str().into(), arr.into());
        }
        let mut params = Map::new();
        for (k, v) in &self.params {
            params.insert(k.as_str().into(), v.to_dynamic());
        }
        let mut maps = Map::new();
        for (k, rows) in &self.maps {
            let arr: rhai::Array = rows
                .iter()
                .map(|r| {
                    let a: rhai::Array = r.iter().map(|&x| Dynamic::from(x)).collect();
                    Dynamic::from(a)
                })
                .collect();
            maps.insert(k.as_str().into(), arr.into());
        }
        run.insert("summary".into(), summary.into());
        run.insert("series".into(), series.into());
        run.insert("params".into(), params.into());
        run.insert("maps".into(), maps.into());
        run
    }
}

/// A loaded case: everything needed to build and run the simulation.
pub struct Case {
    /// Case name (the script's file stem unless `case_name("…")` says otherwise).
    pub name: String,
    /// The script file.
    pub script: PathBuf,
    /// Declared parameters with the values used.
    pub params: Vec<ParamDecl>,
    /// The tank.
    pub tank: TankSpec,
    /// Solver parameters.
    pub sph: SphParams,
    /// Scheme preset name.
    pub scheme: String,
    /// Lattice spacing dx (m) the script asks for (before the lattice is fitted to the tank).
    pub dx: f64,
    /// How the script gave the resolution (dx, particles per depth or per radius).
    pub resolution: Resolution,
    /// Run control.
    pub run: RunSpec,
    /// Extra wave gauges.
    pub gauges: Vec<GaugeSpec>,
    /// Pressure sensors on the roof.
    pub pressure_sensors: Vec<PressureSensorSpec>,
    /// Script functions for the run.
    pub excitation: Excitation,
    /// Ground-motion records the script read (for `summary.ron`).
    pub motions: Vec<crate::MotionInfo>,
    /// The folders the script and its tank (roof meshes) may read files from.
    pub sandbox: ReadSandbox,
    /// What may make the run not what the script's author meant (no excitation, a record
    /// that ends before the run or disagrees with its header), one sentence each; front ends
    /// show them before the run and record them in the summary.
    pub warnings: Vec<String>,
}

impl Case {
    /// Space dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.tank.dim()
    }

    /// U_ref of the sound-speed rule (m/s): an upper estimate of the liquid's speed relative
    /// to the tank that the excitation can cause, the smaller of two bounds:
    /// - half the peak-to-peak of the ground velocity (the excitation integrated from rest,
    ///   per component): the tank cannot outrun the liquid at rest by more (A ω for a sine
    ///   A ω² sin ωt);
    /// - √(2 a_max L), L the tank's largest horizontal size and a_max the largest ground
    ///   acceleration: the speed the liquid gains falling across the tank under the largest
    ///   body force (a drifting or step excitation has no velocity bound).
    ///
    /// Samples `ground_accel` every 5 ms or finer over the excitation.
    pub fn excitation_speed(&mut self) -> Result<f64, ScriptError> {
        let span = (self.run.duration - self.run.settle).max(0.0);
        let turns = self.excitation.turns();
        if !(self.excitation.has_ground_accel() || turns) || span <= 0.0 {
            return Ok(0.0);
        }
        let n = ((span / 0.005).ceil() as usize).clamp(1, 2_000_000);
        let dt = span / n as f64;
        let mut velocity = [0.0f64; 3];
        let mut low = [0.0f64; 3];
        let mut high = [0.0f64; 3];
        // A turning tank: the walls' speed about the pivot, |θ̇| times the tank's size, and the
        // acceleration that drives the liquid across, g |θ| (gravity turned) plus |θ̈| times
        // the size.
        let size = self.tank.horizontal_size();
        // The lever of the walls about the pivot: the tank's size, plus the pivot's distance
        // from the tank's origin when the script places it (far below a tank on a tall
        // foundation, say).
        let lever = size
            + self
                .run
                .rotation_pivot
                .as_ref()
                .map_or(0.0, |p| p.iter().map(|v| v * v).sum::<f64>().sqrt());
        let (mut wall_speed, mut turning_accel) = (0.0f64, 0.0f64);
        let mut turning = |e: &mut Excitation, t: f64| -> Result<(), ScriptError> {
            if let Some((angle, rate, acceleration)) = e.rotation_state(t)? {
                wall_speed = wall_speed.max(rate.abs() * lever);
                turning_accel = turning_accel.max(9.81 * angle.abs() + acceleration.abs() * lever);
            }
            Ok(())
        };
        if turns {
            turning(&mut self.excitation, 0.0)?;
        }
        let mut previous = self.excitation.ground_accel(0.0)?;
        let mut a_max = previous.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        for i in 1..=n {
            if i % 1024 == 0 && crate::memory::stop_requested() {
                return Err(ScriptError::case(
                    &self.script,
                    "stopped by a signal (SIGINT or SIGTERM) while sampling ground_accel for \
                     the sound speed, before the run",
                ));
            }
            let a = self.excitation.ground_accel(i as f64 * dt)?;
            if turns {
                turning(&mut self.excitation, i as f64 * dt)?;
            }
            for k in 0..3 {
                velocity[k] += 0.5 * dt * (a[k] + previous[k]);
                low[k] = low[k].min(velocity[k]);
                high[k] = high[k].max(velocity[k]);
                a_max = a_max.max(a[k].abs());
            }
            previous = a;
        }
        let ground = (0..3)
            .map(|k| 0.5 * (high[k] - low[k]))
            .fold(wall_speed, f64::max);
        let across = (2.0 * (a_max + turning_accel) * size).sqrt();
        Ok(ground.min(across))
    }
}

/// Evaluates a script's top level and returns the declared parameters only
/// (`slosh run CASE --list-params`).
pub fn list_params(path: &Path) -> Result<Vec<ParamDecl>, ScriptError> {
    list_params_with(path, &CaseOptions::default())
}

/// [`list_params`] with `options` (the `--allow-read` folders the top level may need to
/// read its records; `--set` values are applied).
pub fn list_params_with(path: &Path, options: &CaseOptions) -> Result<Vec<ParamDecl>, ScriptError> {
    let (_, declared, ..) = evaluate(path, options)?;
    let d = declared.lock().expect("script state");
    Ok(d.params.clone())
}

type Evaluated = (Engine, Shared, AST, String, Arc<ReadSandbox>);

fn evaluate(path: &Path, options: &CaseOptions) -> Result<Evaluated, ScriptError> {
    let source = std::fs::read_to_string(path).map_err(|e| ScriptError::Io {
        file: path.display().to_string(),
        source: e,
    })?;
    let mut declared = Declared {
        source_lines: source.lines().map(str::to_string).collect(),
        ..Declared::default()
    };
    for (name, value) in &options.overrides {
        if let Some(first) = declared.overrides.insert(name.clone(), value.clone()) {
            return Err(ScriptError::case(
                path,
                format!(
                    "--set {name} is given twice ({name}={first} and {name}={value}); \
                     give each parameter once"
                ),
            ));
        }
    }
    let shared: Shared = Arc::new(Mutex::new(declared));
    let globals: Globals = Arc::new(RwLock::new(Default::default()));
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let sandbox = ReadSandbox::for_script(&dir, &options.allow_read)
        .map(Arc::new)
        .map_err(|m| ScriptError::case(path, m))?;
    let budget = options
        .script_memory_bytes
        .unwrap_or(crate::memory::SCRIPT_MEMORY_BUDGET_BYTES);
    let engine = build_engine(shared.clone(), globals.clone(), sandbox.clone(), budget);
    let ast = engine.compile(&source).map_err(|e| {
        let text = e.0.to_string();
        ScriptError::at(path, e.1, text)
    })?;
    let mut scope = Scope::new();
    engine
        .run_ast_with_scope(&mut scope, &ast)
        .map_err(|e| ScriptError::from_eval(path, &e))?;
    // Make the top-level variables visible to script functions.
    {
        let mut g = globals.write().expect("globals");
        for (name, _constant, value) in scope.iter() {
            g.insert(name.to_string(), value);
        }
    }
    Ok((engine, shared, ast, source, sandbox))
}

/// Loads a case script: evaluates its top level once (declaring parameters and the case),
/// applies `--set` overrides, and keeps the compiled script for `ground_accel`/`post`.
pub fn load_case(path: &Path, options: &CaseOptions) -> Result<Case, ScriptError> {
    let (engine, shared, ast, source, sandbox) = evaluate(path, options)?;
    let mut d = shared.lock().expect("script state");
    if !d.overrides.is_empty() {
        let unknown: Vec<String> = d.overrides.keys().cloned().collect();
        let known: Vec<String> = d
            .params
            .iter()
            .map(|p| format!("{} = {}", p.name, p.default))
            .collect();
        return Err(ScriptError::case(
            path,
            format!(
                "unknown parameter(s) for --set: {}. The script declares: {}",
                unknown.join(", "),
                if known.is_empty() {
                    "(none)".to_string()
                } else {
                    known.join(", ")
                }
            ),
        ));
    }
    let err = |m: String| ScriptError::case(path, m);
    let tank_map = d.tank.take().ok_or_else(|| {
        err("the script does not describe a tank: call tank(#{ shape: \"rect\", width: …, height: …, depth: … })".into())
    })?;
    let mut tank = TankSpec::from_map(&tank_map).map_err(err)?;
    tank.read_mesh(&sandbox).map_err(err)?;
    let numerics = d.numerics.take().unwrap_or_default();
    let (sph, scheme, resolution) = numerics_from_map(&numerics).map_err(err)?;
    let dx = resolution.spacing_for(&tank).map_err(err)?;
    let run = match d.run.take() {
        Some(m) => RunSpec::from_map(&m).map_err(err)?,
        None => RunSpec::default(),
    };
    let mut name = path
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "case".into());
    if let Some(case) = d.case.take() {
        let mut r = crate::spec::MapReader::new("case", &case);
        name = r.str_or("name", &name).map_err(err)?;
        r.finish().map_err(err)?;
        // The name becomes the default output folder `out/<name>`: one plain folder.
        if name.is_empty()
            || name == "."
            || name == ".."
            || name
                .chars()
                .any(|c| c == '/' || c == '\\' || c.is_control())
        {
            return Err(err(format!(
                "case_name: {name:?} must be a plain folder name (no '/', '\\', control \
                 characters, and not \".\" or \"..\"): it becomes the output folder out/<name>"
            )));
        }
    }
    for g in &d.gauges {
        if g.horizontal.len() + 1 != tank.dim() {
            return Err(err(format!(
                "gauge \"{}\" gives {} horizontal coordinate(s) for a {}D tank",
                g.name,
                g.horizontal.len(),
                tank.dim()
            )));
        }
    }
    for g in &d.pressure_sensors {
        let coordinates = g.horizontal.len() + usize::from(g.height.is_some());
        let wanted = if g.height.is_some() {
            tank.dim()
        } else {
            tank.dim() - 1
        };
        if coordinates != wanted {
            return Err(err(format!(
                "{} \"{}\" gives {coordinates} coordinate(s) for a {}D tank (wants {wanted})",
                g.kind(),
                g.name,
                tank.dim()
            )));
        }
    }
    let has_ground_accel = checks::defines(path, &source, &ast, &checks::GROUND_ACCEL)?;
    let has_post = checks::defines(path, &source, &ast, &checks::POST)?;
    let rotation = if checks::defines(path, &source, &ast, &checks::GROUND_ROTATION)? {
        let dim = tank.dim();
        let axis = run.rotation_axis.unwrap_or([0.0, 1.0, 0.0]);
        if dim == 2 && (axis[0] != 0.0 || axis[2] != 0.0) {
            return Err(err(format!(
                "run: rotation_axis {axis:?} for a 2D tank, which turns about y only (the axis \
                 out of its x–z section); leave rotation_axis out"
            )));
        }
        let pivot =
            match &run.rotation_pivot {
                None => None,
                Some(p) if p.len() == dim && p.iter().all(|v| v.is_finite()) => Some(if dim == 2 {
                    [p[0], 0.0, p[1]]
                } else {
                    [p[0], p[1], p[2]]
                }),
                Some(p) => {
                    return Err(err(format!(
                    "run: rotation_pivot must be {} finite numbers for a {dim}D tank (got {p:?})",
                    if dim == 2 { "[x, z]: two" } else { "[x, y, z]: three" }
                )))
                }
            };
        Some(RotationSetup { axis, pivot })
    } else {
        for (given, key) in [
            (run.rotation_pivot.is_some(), "rotation_pivot"),
            (run.rotation_axis.is_some(), "rotation_axis"),
        ] {
            if given {
                return Err(err(format!(
                    "run: {key} is given but the script defines no fn ground_rotation(t); \
                     define it (the tank's angle in rad) or remove {key}"
                )));
            }
        }
        None
    };
    let params = d.params.clone();
    let gauges = d.gauges.clone();
    let pressure_sensors = d.pressure_sensors.clone();
    let motions = d.motions.lock().expect("motion log").clone();
    drop(d);
    let mut warnings = checks::record_coverage(path, &motions, &run)?;
    if !has_ground_accel && rotation.is_none() {
        warnings.push(format!(
            "{}: the script defines no fn ground_accel(t): the tank is not shaken (gravity and \
             the initial tilt only); define fn ground_accel(t) to apply a ground motion",
            path.display()
        ));
    }
    let dim = tank.dim();
    Ok(Case {
        name,
        script: path.to_path_buf(),
        params,
        tank,
        sph,
        scheme,
        dx,
        resolution,
        run,
        gauges,
        pressure_sensors,
        motions,
        sandbox: (*sandbox).clone(),
        warnings,
        excitation: Excitation {
            engine,
            ast,
            scope: Scope::new(),
            file: path.to_path_buf(),
            has_ground_accel,
            rotation,
            has_post,
            shared,
            dim,
        },
    })
}
