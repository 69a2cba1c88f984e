//! The sandboxed Rhai engine and the host functions a case script may call.

use crate::params::{split_unit, trailing_comment, ParamDecl, ParamValue};
use crate::sandbox::ReadSandbox;
use crate::spec::{dynamic_to_f64, GaugeSpec, PressureSensorSpec};
use rhai::{Dynamic, Engine, EvalAltResult, Map, NativeCallContext, Position};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, RwLock};

/// Everything the script declared through host functions.
#[derive(Default)]
pub(crate) struct Declared {
    /// `--set` overrides not yet claimed by a `param` call.
    pub overrides: BTreeMap<String, ParamValue>,
    /// Declared parameters in declaration order.
    pub params: Vec<ParamDecl>,
    /// The script's source lines, for the trailing comments that document parameters.
    pub source_lines: Vec<String>,
    /// The case's name from `case_name("…")`, as a map `#{ name }`.
    pub case: Option<Map>,
    /// `tank(#{...})` map.
    pub tank: Option<Map>,
    /// `numerics(#{...})` map.
    pub numerics: Option<Map>,
    /// `run(#{...})` map.
    pub run: Option<Map>,
    /// Extra wave gauges.
    pub gauges: Vec<GaugeSpec>,
    /// Pressure sensors on the roof.
    pub pressure_sensors: Vec<PressureSensorSpec>,
    /// Extra files written by `post` (name → rows).
    pub tables: Vec<(String, Vec<String>, Vec<Vec<f64>>)>,
    /// Line plots requested by `post`.
    pub plots: Vec<PlotRequest>,
    /// Ground-motion records read by the script.
    pub motions: crate::motion_api::MotionLog,
}

/// A line plot asked for by a script (`line_plot(name, title, xlabel, ylabel, xs, ys)`).
#[derive(Clone, Debug)]
pub struct PlotRequest {
    /// File stem.
    pub name: String,
    /// Title.
    pub title: String,
    /// X-axis label with unit.
    pub x_label: String,
    /// Y-axis label with unit.
    pub y_label: String,
    /// Abscissae.
    pub xs: Vec<f64>,
    /// Ordinates.
    pub ys: Vec<f64>,
}

pub(crate) type Shared = Arc<Mutex<Declared>>;
pub(crate) type Globals = Arc<RwLock<HashMap<String, Dynamic>>>;

fn runtime_error(message: impl Into<String>) -> Box<EvalAltResult> {
    Box::new(EvalAltResult::ErrorRuntime(
        message.into().into(),
        Position::NONE,
    ))
}

/// Builds the sandboxed engine with the host functions bound to `shared`, and a variable
/// resolver that lets script functions read the script's top-level variables (`globals`).
/// Host functions read files only through `sandbox`; an evaluation is stopped when it adds more
/// than `memory_budget_bytes` to the process's memory.
pub(crate) fn build_engine(
    shared: Shared,
    globals: Globals,
    sandbox: Arc<ReadSandbox>,
    memory_budget_bytes: u64,
) -> Engine {
    let mut engine = Engine::new();
    let motions = shared.lock().expect("script state").motions.clone();
    // Sandbox: limits against runaway scripts (operations, depth, the size of each value and
    // the memory of all of them); no eval; modules are compiled out.
    engine.set_max_operations(20_000_000);
    engine.set_max_call_levels(64);
    engine.set_max_expr_depths(128, 64);
    engine.set_max_string_size(1 << 20);
    engine.set_max_array_size(10_000_000);
    engine.set_max_map_size(100_000);
    engine.disable_symbol("eval");
    crate::memory::cap_script_memory(&mut engine, memory_budget_bytes);
    engine.on_print(|text| eprintln!("[script] {text}"));
    engine.on_debug(|text, _source, pos| eprintln!("[script {pos}] {text}"));

    // Script functions are pure in Rhai; this resolver lets them read the top-level
    // variables of the script (parameters, derived constants) after it has run.
    let g = globals.clone();
    // `on_var` is marked volatile (not deprecated) by Rhai; it is the documented resolver hook.
    #[allow(deprecated)]
    engine.on_var(move |name, _index, context| {
        if context.scope().contains(name) {
            return Ok(None);
        }
        Ok(g.read().ok().and_then(|m| m.get(name).cloned()))
    });

    let s = shared.clone();
    engine.register_fn(
        "param",
        move |ctx: NativeCallContext,
              name: &str,
              default: Dynamic|
              -> Result<Dynamic, Box<EvalAltResult>> {
            declare_param(&s, name, default, None, ctx.call_position())
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "param",
        move |ctx: NativeCallContext,
              name: &str,
              default: Dynamic,
              doc: &str|
              -> Result<Dynamic, Box<EvalAltResult>> {
            declare_param(&s, name, default, Some(doc), ctx.call_position())
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "param",
        move |name: &str| -> Result<Dynamic, Box<EvalAltResult>> {
            let d = s.lock().map_err(|_| runtime_error("internal lock"))?;
            d.params
                .iter()
                .find(|p| p.name == name)
                .map(|p| p.value.to_dynamic())
                .ok_or_else(|| {
                    runtime_error(format!(
                        "parameter \"{name}\" is not declared; declare it with param(\"{name}\", default)"
                    ))
                })
        },
    );
    // `case_name("…")`: the case's name (Rhai reserves the keyword `case`, so no script could
    // call a function of that name).
    let s = shared.clone();
    engine.register_fn(
        "case_name",
        move |name: &str| -> Result<(), Box<EvalAltResult>> {
            let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
            if d.case.is_some() {
                return Err(runtime_error("case_name(…) is called twice"));
            }
            let mut map = Map::new();
            map.insert("name".into(), name.into());
            d.case = Some(map);
            Ok(())
        },
    );
    for key in ["tank", "numerics", "run"] {
        let s = shared.clone();
        let files = sandbox.clone();
        engine.register_fn(key, move |map: Map| -> Result<(), Box<EvalAltResult>> {
            let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
            let slot = match key {
                "tank" => &mut d.tank,
                "numerics" => &mut d.numerics,
                _ => &mut d.run,
            };
            if slot.is_some() {
                return Err(runtime_error(format!("{key}(…) is called twice")));
            }
            if key == "tank" {
                // a bad shape is reported at this call (file:line:column)
                // and a mesh file that is missing, open or badly oriented too
                crate::spec::TankSpec::from_map_checked(&map)
                    .and_then(|mut tank| tank.read_mesh(&files))
                    .map_err(runtime_error)?;
            }
            *slot = Some(map);
            Ok(())
        });
    }
    let s = shared.clone();
    engine.register_fn(
        "gauge",
        move |name: &str, x: Dynamic| -> Result<(), Box<EvalAltResult>> {
            let x = dynamic_to_f64(&x).ok_or_else(|| runtime_error("gauge: x must be a number"))?;
            add_gauge(&s, name, vec![x])
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "gauge",
        move |name: &str, x: Dynamic, y: Dynamic| -> Result<(), Box<EvalAltResult>> {
            let (x, y) = (dynamic_to_f64(&x), dynamic_to_f64(&y));
            match (x, y) {
                (Some(x), Some(y)) => add_gauge(&s, name, vec![x, y]),
                _ => Err(runtime_error("gauge: x and y must be numbers")),
            }
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "roof_sensor",
        move |name: &str, x: Dynamic, diameter: Dynamic| -> Result<(), Box<EvalAltResult>> {
            match (dynamic_to_f64(&x), dynamic_to_f64(&diameter)) {
                (Some(x), Some(d)) => add_sensor(&s, name, vec![x], None, d),
                _ => Err(runtime_error(
                    "roof_sensor: x and the length must be numbers",
                )),
            }
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "roof_sensor",
        move |name: &str,
              x: Dynamic,
              y: Dynamic,
              diameter: Dynamic|
              -> Result<(), Box<EvalAltResult>> {
            match (
                dynamic_to_f64(&x),
                dynamic_to_f64(&y),
                dynamic_to_f64(&diameter),
            ) {
                (Some(x), Some(y), Some(d)) => add_sensor(&s, name, vec![x, y], None, d),
                _ => Err(runtime_error(
                    "roof_sensor: x, y and the diameter must be numbers",
                )),
            }
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "wall_sensor",
        move |name: &str,
              x: Dynamic,
              z: Dynamic,
              length: Dynamic|
              -> Result<(), Box<EvalAltResult>> {
            match (
                dynamic_to_f64(&x),
                dynamic_to_f64(&z),
                dynamic_to_f64(&length),
            ) {
                (Some(x), Some(z), Some(d)) => add_sensor(&s, name, vec![x], Some(z), d),
                _ => Err(runtime_error(
                    "wall_sensor: x, z and the length must be numbers",
                )),
            }
        },
    );
    let s = shared.clone();
    engine.register_fn(
        "wall_sensor",
        move |name: &str,
              x: Dynamic,
              y: Dynamic,
              z: Dynamic,
              diameter: Dynamic|
              -> Result<(), Box<EvalAltResult>> {
            match (
                dynamic_to_f64(&x),
                dynamic_to_f64(&y),
                dynamic_to_f64(&z),
                dynamic_to_f64(&diameter),
            ) {
                (Some(x), Some(y), Some(z), Some(d)) => {
                    add_sensor(&s, name, vec![x, y], Some(z), d)
                }
                _ => Err(runtime_error(
                    "wall_sensor: x, y, z and the diameter must be numbers",
                )),
            }
        },
    );
    // Post-processing output: extra CSV tables and line plots.
    let s = shared.clone();
    engine.register_fn(
        "write_table",
        move |name: &str, columns: Map| -> Result<(), Box<EvalAltResult>> {
            let mut header = Vec::new();
            let mut cols: Vec<Vec<f64>> = Vec::new();
            for (k, v) in columns.iter() {
                header.push(k.to_string());
                cols.push(dynamic_to_vec(v).ok_or_else(|| {
                    runtime_error(format!(
                        "write_table: column '{k}' must be an array of numbers"
                    ))
                })?);
            }
            if cols.is_empty() {
                return Err(runtime_error(format!(
                    "write_table: table '{name}' has no columns (give a map of column name → \
                     array of numbers)"
                )));
            }
            let n = cols.first().map(|c| c.len()).unwrap_or(0);
            if cols.iter().any(|c| c.len() != n) {
                return Err(runtime_error(
                    "write_table: all columns must have the same length",
                ));
            }
            check_file_stem(name)?;
            let rows = (0..n)
                .map(|i| cols.iter().map(|c| c[i]).collect())
                .collect();
            let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
            check_post_name_unused(&d, name, PostOutput::Table)?;
            d.tables.push((name.to_string(), header, rows));
            Ok(())
        },
    );
    let s = shared;
    engine.register_fn(
        "line_plot",
        move |name: &str,
              title: &str,
              x_label: &str,
              y_label: &str,
              xs: Dynamic,
              ys: Dynamic|
              -> Result<(), Box<EvalAltResult>> {
            let xs = dynamic_to_vec(&xs)
                .ok_or_else(|| runtime_error("line_plot: xs must be an array of numbers"))?;
            let ys = dynamic_to_vec(&ys)
                .ok_or_else(|| runtime_error("line_plot: ys must be an array of numbers"))?;
            if xs.len() != ys.len() {
                return Err(runtime_error(
                    "line_plot: xs and ys must have the same length",
                ));
            }
            check_file_stem(name)?;
            let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
            check_post_name_unused(&d, name, PostOutput::Plot)?;
            d.plots.push(PlotRequest {
                name: name.into(),
                title: title.into(),
                x_label: x_label.into(),
                y_label: y_label.into(),
                xs,
                ys,
            });
            Ok(())
        },
    );
    // File access for later host functions: through the sandbox only.
    crate::motion_api::register_motion_api(&mut engine, sandbox, motions);
    engine
}

/// `param(name, default[, doc])`: declares a parameter (once; later calls return its value),
/// applies a `--set` override, and documents it from `doc` or the trailing comment of the
/// script line at `position`.
fn declare_param(
    s: &Shared,
    name: &str,
    default: Dynamic,
    doc: Option<&str>,
    position: Position,
) -> Result<Dynamic, Box<EvalAltResult>> {
    let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
    if let Some(p) = d.params.iter().find(|p| p.name == name) {
        return Ok(p.value.to_dynamic());
    }
    let default = ParamValue::from_dynamic(&default).ok_or_else(|| {
        runtime_error(format!(
            "param(\"{name}\", …): the default must be a number, true/false or a string"
        ))
    })?;
    let (value, overridden) = match d.overrides.remove(name) {
        Some(v) => (
            v.coerce_to(&default)
                .map_err(|e| runtime_error(format!("--set {name}: {e}")))?,
            true,
        ),
        None => (default.clone(), false),
    };
    let doc = doc.map(str::to_string).or_else(|| {
        let line = d.source_lines.get(position.line()?.checked_sub(1)?)?;
        trailing_comment(line).map(str::to_string)
    });
    let (unit, description) = match doc {
        Some(text) => {
            let (unit, description) = split_unit(&text);
            (unit, (!description.is_empty()).then_some(description))
        }
        None => (None, None),
    };
    d.params.push(ParamDecl {
        name: name.to_string(),
        default,
        value: value.clone(),
        overridden,
        unit,
        description,
    });
    Ok(value.to_dynamic())
}

fn add_gauge(s: &Shared, name: &str, horizontal: Vec<f64>) -> Result<(), Box<EvalAltResult>> {
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(runtime_error(format!(
            "gauge name \"{name}\" must be letters, digits or _ (it becomes the column eta_{name})"
        )));
    }
    let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
    if d.gauges.iter().any(|g| g.name == name) {
        return Err(runtime_error(format!("gauge \"{name}\" is declared twice")));
    }
    d.gauges.push(GaugeSpec {
        name: name.to_string(),
        horizontal,
    });
    Ok(())
}

/// Declares a pressure sensor: on the roof above `horizontal` (`height` None, `roof_sensor`)
/// or on a wall at (`horizontal`, `height`) (`wall_sensor`). Roof and wall sensors share one
/// list of names (each becomes the column `p_<name>`).
fn add_sensor(
    s: &Shared,
    name: &str,
    horizontal: Vec<f64>,
    height: Option<f64>,
    diameter: f64,
) -> Result<(), Box<EvalAltResult>> {
    let sensor = PressureSensorSpec {
        name: name.to_string(),
        horizontal,
        diameter,
        height,
    };
    let (kind, horizontal, height) = (sensor.kind(), &sensor.horizontal, &sensor.height);
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(runtime_error(format!(
            "{kind} name \"{name}\" must be letters, digits or _ (it becomes the column \
             p_{name})"
        )));
    }
    if horizontal.iter().chain(height).any(|x| !x.is_finite()) {
        let position: Vec<f64> = horizontal.iter().chain(height).copied().collect();
        return Err(runtime_error(format!(
            "{kind} \"{name}\": its position must be finite numbers (got {position:?})"
        )));
    }
    if !(diameter.is_finite() && diameter > 0.0) {
        return Err(runtime_error(format!(
            "{kind} \"{name}\": the diameter (2D: length) must be > 0 m (got {diameter})"
        )));
    }
    let mut d = s.lock().map_err(|_| runtime_error("internal lock"))?;
    if d.pressure_sensors.iter().any(|g| g.name == name) {
        return Err(runtime_error(format!(
            "{kind} \"{name}\": a sensor of that name is already declared"
        )));
    }
    d.pressure_sensors.push(sensor);
    Ok(())
}

fn check_file_stem(name: &str) -> Result<(), Box<EvalAltResult>> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(runtime_error(format!(
            "output name \"{name}\" must be letters, digits, _ or - (no folders)"
        )));
    }
    Ok(())
}

/// Refuses a second table (`post/NAME.csv`) or a second plot (`post/NAME.png`) with one
/// name, which would replace the first file.
fn check_post_name_unused(
    d: &Declared,
    name: &str,
    kind: PostOutput,
) -> Result<(), Box<EvalAltResult>> {
    let (used, what) = match kind {
        PostOutput::Table => (d.tables.iter().any(|t| t.0 == name), "write_table"),
        PostOutput::Plot => (d.plots.iter().any(|p| p.name == name), "line_plot"),
    };
    if used {
        return Err(runtime_error(format!(
            "{what}: the name \"{name}\" is used twice (the second file would replace the \
             first); give each its own name"
        )));
    }
    Ok(())
}

/// The two kinds of file `post` writes.
#[derive(Clone, Copy)]
enum PostOutput {
    Table,
    Plot,
}

/// An array of numbers as Vec<f64>.
pub(crate) fn dynamic_to_vec(d: &Dynamic) -> Option<Vec<f64>> {
    let arr = d.read_lock::<rhai::Array>()?;
    arr.iter().map(dynamic_to_f64).collect()
}

/// Resolves a path given by a script in `script_dir` with the default sandbox (the script's
/// folder and its project folder, see [`ReadSandbox`]): refused when it leaves them through
/// `..`, an absolute path or a symlink.
pub fn resolve_script_path(script_dir: &Path, relative: &str) -> Result<PathBuf, String> {
    ReadSandbox::for_script(script_dir, &[])?.resolve(relative)
}
