//! `slosh._slosh`: the compiled part of the Python package `slosh`.
//!
//! It runs case scripts through the same code as `slosh run`, the case runner of
//! `slosh-case` (so a run from Python writes the same output folder, bit for bit), lists a
//! script's parameters, evaluates the closed forms of `slosh theory` and reads ground-motion
//! records. The pure-Python part of the package (`python/slosh`) reads a run's folder back
//! into numpy arrays and dictionaries.
#![warn(missing_docs)]

use numpy::PyArray1;
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use slosh_case::{run_case_with_stop, RunOptions};
use slosh_motion::{AccelUnit, PlainTextOptions, RecordFormat};
use slosh_script::{parse_sets, ParamValue, ScriptError as CaseScriptError};
use std::path::PathBuf;
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

create_exception!(
    slosh,
    ScriptError,
    PyException,
    "An error in a case script or in the parameters given to it; `file`, `line` and `column` \
     (1-based; None when the error has no place in the script) say where."
);

/// How often the waiting Python thread looks for signals (Ctrl-C) while a run goes on.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The signal number a run stopped from Python reports (SIGINT).
const SIGINT: i32 = 2;

/// A script error as `slosh.ScriptError` with its place.
fn script_error(py: Python<'_>, error: &CaseScriptError) -> PyErr {
    let err = ScriptError::new_err(error.to_string());
    let (file, line, column) = match error {
        CaseScriptError::At {
            file, line, column, ..
        } => (file.clone(), Some(*line), Some(*column)),
        CaseScriptError::Case { file, .. } | CaseScriptError::Io { file, .. } => {
            (file.clone(), None, None)
        }
    };
    let value = err.value(py);
    // Setting attributes on a fresh exception object cannot fail short of memory exhaustion;
    // the message carries the place in any case.
    let _ = value.setattr("file", file);
    let _ = value.setattr("line", line);
    let _ = value.setattr("column", column);
    err
}

/// An error of the case runner as a Python exception: a script error keeps its
/// type and place, anything else is a `RuntimeError` with the whole chain of causes.
fn anyhow_error(py: Python<'_>, error: &anyhow::Error) -> PyErr {
    match error.downcast_ref::<CaseScriptError>() {
        Some(e) => script_error(py, e),
        None => PyRuntimeError::new_err(format!("{error:#}")),
    }
}

/// A script parameter value as a Python object.
fn param_value(py: Python<'_>, value: &ParamValue) -> PyResult<Py<PyAny>> {
    Ok(match value {
        ParamValue::Float(x) => x.into_pyobject(py)?.into_any().unbind(),
        ParamValue::Int(i) => i.into_pyobject(py)?.into_any().unbind(),
        ParamValue::Bool(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        ParamValue::Str(s) => s.into_pyobject(py)?.into_any().unbind(),
    })
}

/// Runs the case script `script` into the folder `out`, as `slosh run SCRIPT --out OUT
/// --set S...` does, and returns `None` when it completed or the error message when it did
/// not (the folder then holds what was written up to the failure).
///
/// The script is read and checked first (a `ScriptError` is raised there); the run then goes
/// on in a thread of its own while this thread waits without the GIL and looks for signals
/// every 50 ms: Ctrl-C stops the run after its current step, its outputs are completed, and
/// `KeyboardInterrupt` is raised.
#[pyfunction]
#[pyo3(signature = (script, out, sets, threads=None, progress=false, plots=true, checkpoint_every=None))]
#[allow(clippy::too_many_arguments)]
fn run_case(
    py: Python<'_>,
    script: PathBuf,
    out: PathBuf,
    sets: Vec<String>,
    threads: Option<usize>,
    progress: bool,
    plots: bool,
    checkpoint_every: Option<String>,
) -> PyResult<Option<String>> {
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads must be at least 1"));
    }
    let options = parse_sets(&sets).map_err(|e| ScriptError::new_err(format!("{e:#}")))?;
    let case = slosh_script::load_case(&script, &options).map_err(|e| script_error(py, &e))?;
    let checkpoints = match checkpoint_every {
        Some(text) => {
            let every = slosh_case::checkpoint::parse_every(&text)
                .map_err(|e| PyValueError::new_err(format!("checkpoint_every {e}")))?;
            match every {
                Some(every) => Some((
                    slosh_case::checkpoint::RunRecord::new(&script, &sets, &[], every)
                        .map_err(|e| anyhow_error(py, &e))?,
                    every,
                )),
                None => None,
            }
        }
        None => None,
    };
    let opts = RunOptions {
        out_dir: out,
        progress,
        verbose: progress,
        plots,
        max_memory_bytes: None,
        checkpoints,
        resume: false,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let stop_flag = Arc::clone(&stop);
    let (done, mut result) = mpsc::channel();
    let worker = std::thread::Builder::new()
        .name("slosh-run".into())
        .spawn(move || {
            let mut stop_request = move || stop_flag.load(Ordering::Relaxed).then_some(SIGINT);
            let work = move || run_case_with_stop(case, &opts, &mut stop_request);
            // Run inside the pool (default: one worker per core), so that the step's parallel
            // passes start on a worker instead of being handed over from this thread on every
            // pass, which for a small case costs as much as the step (`slosh run` does the same).
            let outcome = match rayon::ThreadPoolBuilder::new()
                .num_threads(threads.unwrap_or(0))
                .build()
            {
                Ok(pool) => pool.install(work),
                Err(e) => Err(anyhow::anyhow!("cannot start the worker threads: {e}")),
            };
            // The receiver is gone only when the waiting thread itself failed.
            let _ = done.send(outcome);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the run's thread: {e}")))?;
    loop {
        // The receiver goes into the GIL-free closure and comes back (it is not `Sync`).
        let (received, receiver) = py.detach(move || (result.recv_timeout(SIGNAL_POLL), result));
        result = receiver;
        match received {
            Ok(outcome) => {
                let _ = py.detach(move || worker.join());
                return match outcome {
                    Ok(_) => Ok(None),
                    Err(e) if e.downcast_ref::<CaseScriptError>().is_some() => {
                        Err(anyhow_error(py, &e))
                    }
                    Err(e) => Ok(Some(format!("{e:#}"))),
                };
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    stop.store(true, Ordering::Relaxed);
                    let _ = py.detach(move || worker.join());
                    return Err(interrupt);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let _ = py.detach(move || worker.join());
                return Err(PyRuntimeError::new_err(
                    "the run's thread ended without a result (a panic: see stderr)",
                ));
            }
        }
    }
}

/// The parameters a script declares, in order: a list of dicts with `name`, `type`,
/// `default`, `unit` (None without one) and `description` (None without one), as
/// `slosh run SCRIPT --list-params` prints them.
#[pyfunction]
fn list_params<'py>(py: Python<'py>, script: PathBuf) -> PyResult<Bound<'py, PyList>> {
    let declared = slosh_script::list_params_with(&script, &slosh_script::CaseOptions::default())
        .map_err(|e| script_error(py, &e))?;
    let list = PyList::empty(py);
    for p in declared {
        let d = PyDict::new(py);
        d.set_item("name", &p.name)?;
        d.set_item("type", p.default.type_name())?;
        d.set_item("default", param_value(py, &p.default)?)?;
        d.set_item("unit", &p.unit)?;
        d.set_item("description", &p.description)?;
        list.append(d)?;
    }
    Ok(list)
}

/// The closed-form report of `slosh theory SHAPE ... --ron` as RON text: `shape` is `rect`
/// (size = inner width 2l, m) or `cylinder` (size = inner radius R, m), `depth` the still
/// liquid depth (m); the optional numbers are those of the command's options.
#[pyfunction]
#[pyo3(signature = (shape, size, depth, tank_height=None, pga=None, sa=None, amplitude=None, omega=None, gravity=9.81))]
#[allow(clippy::too_many_arguments)]
fn theory_ron(
    shape: &str,
    size: f64,
    depth: f64,
    tank_height: Option<f64>,
    pga: Option<f64>,
    sa: Option<f64>,
    amplitude: Option<f64>,
    omega: Option<f64>,
    gravity: f64,
) -> PyResult<String> {
    use slosh_theory::{tank_report, SineExcitation, TankInput};
    let mut input = match shape {
        "rect" => TankInput::rectangular(size, depth),
        "cylinder" => TankInput::cylindrical(size, depth),
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown tank shape \"{other}\": use rect or cylinder"
            )))
        }
    };
    input.gravity = gravity;
    input.tank_height = tank_height;
    input.peak_ground_accel = pga;
    input.spectral_accel_g = sa;
    input.sine = match (amplitude, omega) {
        // The duration of the command line's sine response.
        (Some(amplitude), Some(omega)) => Some(SineExcitation {
            amplitude,
            omega,
            duration: 10.0,
        }),
        (None, None) => None,
        _ => {
            return Err(PyValueError::new_err(
                "a sine excitation needs both amplitude and omega",
            ))
        }
    };
    input
        .check()
        .map_err(|problems| PyValueError::new_err(format!("theory: {problems}")))?;
    ron::ser::to_string_pretty(&tank_report(&input), ron::ser::PrettyConfig::default())
        .map_err(|e| PyRuntimeError::new_err(format!("cannot write the report: {e}")))
}

/// The free-surface elevation (m) of linear potential theory in a rectangular tank (2D) of
/// width `width` and liquid depth `depth` (m), at `x` (m from the left wall), under the ground
/// displacement x_g = −A sin ωt from rest (ground acceleration A ω² sin ωt, the paper's §3.1
/// excitation and that of `slosh theory --amplitude A --omega ω`), at the times `t` (s since
/// the excitation started; 0 before it): the undamped modal sum of the first `modes`
/// antisymmetric modes (Ibrahim 2005, ch. 2; Faltinsen & Timokha 2009, ch. 5), as the
/// validation suite compares with paper Fig. 3.
#[pyfunction]
#[pyo3(signature = (width, depth, amplitude, omega, t, x=0.0, modes=10, gravity=9.81))]
#[allow(clippy::too_many_arguments)]
fn rect_sine_elevation<'py>(
    py: Python<'py>,
    width: f64,
    depth: f64,
    amplitude: f64,
    omega: f64,
    t: Vec<f64>,
    x: f64,
    modes: usize,
    gravity: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    use slosh_theory::{linear::RectangularTank, modal::sine_response};
    if !(width > 0.0 && depth > 0.0 && gravity > 0.0 && modes > 0) {
        return Err(PyValueError::new_err(
            "width, depth and gravity must be positive and modes at least 1",
        ));
    }
    let tank = RectangularTank {
        gravity,
        ..RectangularTank::water(width, depth)
    };
    // The liquid feels the body force −a_g(t) = −A ω² sin ωt in the tank's frame.
    let body_force = -amplitude * omega * omega;
    let eta = t.iter().map(|&t| {
        if t <= 0.0 {
            0.0
        } else {
            tank.elevation(&sine_response(&tank, body_force, omega, t, modes), x)
        }
    });
    Ok(PyArray1::from_iter(py, eta))
}

/// A ground-acceleration record: uniform samples in m/s², read by `slosh.load_record`.
#[pyclass(module = "slosh._slosh")]
struct Record {
    inner: slosh_motion::Record,
}

#[pymethods]
impl Record {
    /// Sample times (s), one per sample.
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let n = self.inner.len();
        PyArray1::from_iter(py, (0..n).map(|i| self.inner.time_s(i)))
    }

    /// Ground acceleration samples (m/s²), a copy.
    #[getter]
    fn accel<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.accel_m_s2)
    }

    /// Sample interval (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.dt_s
    }

    /// Peak ground acceleration max |a| (m/s²).
    #[getter]
    fn pga(&self) -> f64 {
        self.inner.pga_m_s2()
    }

    /// The file the record was read from.
    #[getter]
    fn source(&self) -> String {
        self.inner.meta.source_file.clone()
    }

    /// The file layout: "PEER AT2", "K-NET ASCII" or "plain text".
    #[getter]
    fn format(&self) -> String {
        self.inner.meta.format.to_string()
    }

    /// The units of the file's values ("g", "gal", "m/s2"), converted to m/s² on reading.
    #[getter]
    fn units(&self) -> String {
        self.inner.meta.original_units.to_string()
    }

    /// Every operation applied to the record since it was read, in order.
    #[getter]
    fn processing_log(&self) -> Vec<String> {
        self.inner.processing_log.clone()
    }

    /// Scales the record in place so that its peak |a| is `pga` (m/s²); returns the record.
    fn scale_to_pga(mut slf: PyRefMut<'_, Self>, pga: f64) -> PyResult<PyRefMut<'_, Self>> {
        slf.inner
            .scale_to_pga(pga)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(slf)
    }

    /// Pseudo-acceleration response spectrum S_a (m/s²) of the record at the natural periods
    /// `periods` (s) for the damping ratio `damping` (fraction of critical; 0.05 = 5 %).
    #[pyo3(signature = (periods, damping=0.05))]
    fn spectrum<'py>(
        &self,
        py: Python<'py>,
        periods: Vec<f64>,
        damping: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let spectrum = py
            .detach(|| self.inner.response_spectrum(&periods, damping))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(PyArray1::from_vec(py, spectrum.pseudo_accel_m_s2))
    }

    /// Number of samples.
    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Record({:?}, {}, {} samples, dt = {} s, pga = {:.4} m/s²)",
            self.inner.meta.source_file,
            self.inner.meta.format,
            self.inner.len(),
            self.inner.dt_s,
            self.inner.pga_m_s2()
        )
    }
}

/// Reads a ground-motion record as a case script's `load_record(path, #{format, units, dt})`
/// does: `format` "at2" (PEER NGA, in g), "knet" (K-NET / KiK-net ASCII, in gal) or "csv"
/// (plain text: time and acceleration columns, or one acceleration column with `dt`);
/// without it the reader follows the file's content and name. `units` ("g", "gal", "m/s2")
/// is required for plain text; AT2 and K-NET files fix their own.
#[pyfunction]
#[pyo3(signature = (path, format=None, units=None, dt=None))]
fn load_record(
    path: PathBuf,
    format: Option<&str>,
    units: Option<&str>,
    dt: Option<f64>,
) -> PyResult<Record> {
    let file = path.display().to_string();
    let fail = |message: String| PyValueError::new_err(format!("load_record({file:?}): {message}"));
    let units = units
        .map(AccelUnit::from_str)
        .transpose()
        .map_err(|e| fail(e.to_string()))?;
    let plain = PlainTextOptions {
        units: units.unwrap_or(AccelUnit::MetersPerSecondSquared),
        dt_s: dt,
    };
    let record = match format.unwrap_or("").to_ascii_lowercase().as_str() {
        "" => slosh_motion::read_record(&path, &plain),
        "at2" => slosh_motion::read_at2(&path),
        "knet" => slosh_motion::read_knet(&path),
        "csv" => slosh_motion::read_plain_text(&path, &plain),
        other => {
            return Err(fail(format!(
                "unknown format \"{other}\"; use \"at2\", \"knet\" or \"csv\""
            )))
        }
    }
    .map_err(|e| fail(e.to_string()))?;
    let file_units = record.meta.original_units;
    match (record.meta.format, units) {
        (RecordFormat::PlainText, None) => {
            return Err(fail(
                "a plain-text record needs its units: units=\"g\", \"gal\" or \"m/s2\"".into(),
            ))
        }
        (RecordFormat::PeerAt2 | RecordFormat::KnetAscii, Some(u)) if u != file_units => {
            return Err(fail(format!(
                "this is a {} file, whose values are in {file_units}; leave units out",
                record.meta.format
            )))
        }
        _ => {}
    }
    Ok(Record { inner: record })
}

/// Reads a comma-separated table of numbers with one header line (`series.csv`,
/// `roof_pressure.csv`): the header's names and the columns as float64 arrays.
#[pyfunction]
fn read_csv_columns<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Vec<String>, Vec<Bound<'py, PyArray1<f64>>>)> {
    let text = std::fs::read_to_string(&path)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot read {}: {e}", path.display())))?;
    let mut lines = text.lines();
    let names: Vec<String> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(|s| s.trim().to_string())
        .collect();
    let mut columns = vec![Vec::new(); names.len()];
    for (row, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != names.len() {
            return Err(PyRuntimeError::new_err(format!(
                "{} row {}: {} values for {} columns",
                path.display(),
                row + 1,
                fields.len(),
                names.len()
            )));
        }
        for (column, field) in columns.iter_mut().zip(fields) {
            let value: f64 = field.trim().parse().map_err(|_| {
                PyRuntimeError::new_err(format!(
                    "{} row {}: `{field}` is not a number",
                    path.display(),
                    row + 1
                ))
            })?;
            column.push(value);
        }
    }
    let arrays = columns
        .into_iter()
        .map(|c| PyArray1::from_vec(py, c))
        .collect();
    Ok((names, arrays))
}

/// The compiled module.
#[pymodule]
fn _slosh(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ScriptError", m.py().get_type::<ScriptError>())?;
    m.add_class::<Record>()?;
    m.add_function(wrap_pyfunction!(run_case, m)?)?;
    m.add_function(wrap_pyfunction!(list_params, m)?)?;
    m.add_function(wrap_pyfunction!(theory_ron, m)?)?;
    m.add_function(wrap_pyfunction!(rect_sine_elevation, m)?)?;
    m.add_function(wrap_pyfunction!(load_record, m)?)?;
    m.add_function(wrap_pyfunction!(read_csv_columns, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
