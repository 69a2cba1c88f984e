"""Tests of the Python package `slosh` against the `slosh` command line and closed forms.

The command-line binary is `target/release/slosh` of the repository (or $SLOSH_BIN); build it
first with `cargo build --release -p slosh-cli`. Every case is short (about a second).
"""

from __future__ import annotations

import csv
import math
import os
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import slosh
from slosh import _ron

ROOT = Path(__file__).resolve().parents[3]
PAPER_SCRIPT = ROOT / "scripts" / "paper_2d_sloshing.rhai"
ELCENTRO = ROOT / "data" / "elcentro_1940_ns.at2"

# A short, coarse §3.1 case: 0.2 s of settling and 0.4 s of resonant excitation at
# dx = 0.04 m (300 fluid particles), about a second of wall time.
SHORT = {"duration": 0.6, "settle": 0.2, "dx": 0.04, "frame_interval": 0}


def slosh_bin() -> Path:
    exe = Path(os.environ.get("SLOSH_BIN", ROOT / "target" / "release" / "slosh"))
    if not exe.exists():
        pytest.fail(f"{exe} is missing: build it with `cargo build --release -p slosh-cli`")
    return exe


def cli(*args: str) -> str:
    done = subprocess.run(
        [str(slosh_bin()), *args], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def cli_run(out: Path, sets: dict) -> Path:
    args = ["run", str(PAPER_SCRIPT), "--out", str(out), "--quiet", "--threads", "1"]
    for name, value in sets.items():
        args += ["--set", f"{name}={value}"]
    cli(*args)
    return out


def read_csv(path: Path) -> dict:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names, values = rows[0], rows[1:]
    return {n: np.array([float(r[k]) for r in values]) for k, n in enumerate(names)}


@pytest.fixture(scope="module")
def cli_folder(tmp_path_factory) -> Path:
    return cli_run(tmp_path_factory.mktemp("cli") / "run", SHORT)


def test_out_folder_series_is_the_command_lines_byte_for_byte(cli_folder, tmp_path):
    out = tmp_path / "py"
    run = slosh.run(PAPER_SCRIPT, out=out, threads=1, **SHORT)
    assert run.status == "completed" and run.error is None
    for name in ("series.csv", "series_units.csv", "roof_pressure.csv"):
        assert (out / name).read_bytes() == (cli_folder / name).read_bytes(), name
    assert (out / "plots" / "eta.png").exists()


def test_series_in_memory_equal_the_command_lines_csv(cli_folder):
    # A run into a temporary folder on two threads: the solver's sums do not depend on the
    # thread count (docs/design.md), so the series equal the one-thread CLI run exactly.
    run = slosh.run(str(PAPER_SCRIPT), threads=2, **SHORT)
    expected = read_csv(cli_folder / "series.csv")
    assert list(run.series) == list(expected)
    for name, column in expected.items():
        got = run.series[name]
        assert got.dtype == np.float64 and got.ndim == 1
        assert np.array_equal(got, column), name
    assert run.folder is None
    assert run.units["t"] == "s"
    assert run.units["eta_left"] == "m"


def test_summary_impacts_and_roof_map(cli_folder):
    run = slosh.Run.load(cli_folder)
    s = run.summary
    assert s["status"] == "completed" and s["dim"] == 2
    assert isinstance(s["steps"], int) and isinstance(s["dx"], float)
    assert s["parameters"]["dx"] == 0.04 and s["parameters"]["scheme"] == "paper"
    assert s["numerics"]["boundary"] == "Dynamic"
    assert set(s["parts"]) == {"bottom", "wall", "roof"}
    assert s["max_eta_left"] == run.series["eta_left"].max()
    assert isinstance(run.impacts, list)
    roof = run.roof_pressure
    assert roof is not None
    assert roof["p"].shape == (len(roof["t"]), len(roof["x"]))
    # The roof points of the 1 m wide tank lie across it.
    assert 0.0 < roof["x"].min() and roof["x"].max() < 1.0
    # The roof load: F_eq at the default roof periods, the spectrum from 5 ms to 2 s.
    load = run.roof_load
    assert load is not None and load["periods"] == [0.02, 0.05, 0.1, 0.2]
    assert len(load["roof"]["design"]) == 4 and load["damping_ratio"] == 0.02
    spectrum = run.roof_spectrum
    assert spectrum is not None
    assert spectrum["period"][0] == pytest.approx(0.005) and spectrum["period"][-1] == pytest.approx(2.0)
    assert len(spectrum["roof_f_eq"]) == len(spectrum["period"])


def test_to_pandas(cli_folder):
    pd = pytest.importorskip("pandas")
    frame = slosh.Run.load(cli_folder).to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert frame.index.name == "t" and "eta_left" in frame.columns


def test_overrides_follow_set_rules():
    run = slosh.run(PAPER_SCRIPT, **{**SHORT, "smoothing_steps": 5, "scheme": "modern"})
    p = run.summary["parameters"]
    assert p["smoothing_steps"] == 5 and isinstance(p["smoothing_steps"], int)
    assert p["scheme"] == "modern"
    assert run.summary["scheme"] == "modern"
    assert run.summary["dx"] == 0.04


def test_unknown_parameter_is_a_script_error():
    with pytest.raises(slosh.ScriptError) as info:
        slosh.run(PAPER_SCRIPT, duration=0.3, no_such_parameter=1)
    assert "no_such_parameter" in str(info.value)
    assert info.value.file.endswith("paper_2d_sloshing.rhai")
    assert info.value.line is None


def test_script_error_has_line_and_column(tmp_path):
    script = tmp_path / "broken.rhai"
    script.write_text('let width = param("width", 1.0);\nlet depth = width +* 2;\n')
    with pytest.raises(slosh.ScriptError) as info:
        slosh.run(script)
    assert info.value.line == 2
    assert isinstance(info.value.column, int) and info.value.column >= 1
    assert str(script) in str(info.value)


def test_params_match_list_params():
    params = slosh.params(PAPER_SCRIPT)
    assert params["dx"] == {
        "type": "number",
        "default": 0.02,
        "unit": "m",
        "description": "particle spacing",
    }
    assert params["scheme"]["default"] == "paper"
    assert params["smoothing_steps"]["default"] == 20
    # The table of `--list-params`: parameter, type, default, unit, description.
    listed = cli("run", str(PAPER_SCRIPT), "--list-params").split("\n\n")[0]
    rows = [line.split(None, 4) for line in listed.splitlines()[1:]]
    assert [r[0] for r in rows] == list(params)
    for name, kind, default, unit, *_ in rows:
        p = params[name]
        assert (kind, unit) == (p["type"], p["unit"] or "-")
        if default.startswith('"'):
            assert p["default"] == default.strip('"')
        elif default in ("true", "false"):
            assert p["default"] is (default == "true")
        else:
            assert p["default"] == float(default)


def test_failed_run_raises_simulation_error_with_partial_run(tmp_path):
    text = PAPER_SCRIPT.read_text()
    script = tmp_path / "fails.rhai"
    script.write_text(
        text.replace(
            "fn ground_accel(t) {",
            'fn ground_accel(t) {\n    if t > 0.1 { throw "the shaker broke"; }',
        )
    )
    with pytest.raises(slosh.SimulationError) as info:
        slosh.run(script, **SHORT)
    run = info.value.run
    assert run.status == "failed"
    assert "the shaker broke" in run.error
    # Rows up to the failure: 0.2 s of settling and 0.1 s of excitation at 0.01 s a row.
    t = run.series["t"]
    assert 0.29 <= t[-1] < 0.35


def test_theory_matches_the_command_line():
    py = slosh.theory.rect(1.0, 0.5, sa=0.2, tank_height=1.0, pga=2.0)
    ron = _ron.loads(
        cli(
            "theory", "rect", "--width", "1", "--depth", "0.5", "--sa", "0.2",
            "--tank-height", "1", "--pga", "2", "--ron",
        )
    )
    assert py == ron
    py = slosh.theory.cylinder(12.0, 9.0, sa=0.15, amplitude=0.01, omega=1.2)
    ron = _ron.loads(
        cli(
            "theory", "cylinder", "--radius", "12", "--depth", "9", "--sa", "0.15",
            "--amplitude", "0.01", "--omega", "1.2", "--ron",
        )
    )
    assert py == ron


def test_theory_natural_periods_are_the_closed_forms():
    g = 9.81
    # Rectangular tank, first mode: ω² = g k tanh(k H), k = π / (2l) (Lamb, Hydrodynamics
    # §229); the report evaluates the same expression, so only rounding separates them.
    k = math.pi / 1.0
    omega = math.sqrt(g * k * math.tanh(k * 0.5))
    assert slosh.theory.rect(1.0, 0.5)["modes"][0]["omega"] == pytest.approx(omega, rel=1e-12)
    # Upright cylinder: ω² = g ξ/R tanh(ξ H/R), ξ = 1.841184 the first zero of J1'
    # (Abramowitz & Stegun table 9.5); 1e-6 covers the seven digits of ξ.
    xi, r, h = 1.841184, 12.0, 9.0
    omega = math.sqrt(g * xi / r * math.tanh(xi * h / r))
    report = slosh.theory.cylinder(r, h)
    assert report["modes"][0]["omega"] == pytest.approx(omega, rel=1e-6)
    with pytest.raises(ValueError):
        slosh.theory.rect(-1.0, 0.5)


def test_linear_elevation_is_the_hydrostatic_tilt_under_slow_shaking():
    # Shaken far below the first mode (ω = 0.1 rad/s, ω1 = 5.32 rad/s) the surface stays
    # the plane tilted by the body force −a_g: η(0) = a_g L / (2 g) at the left wall (the
    # quasi-static limit of the modal equations; the free oscillation it starts is
    # (ω/ω1) ≈ 2 % of it, hence the 3 % tolerance).
    width, depth, amplitude, omega = 1.0, 0.5, 2.0, 0.1
    t = np.array([0.5 * math.pi / omega, 1.5 * math.pi / omega])
    eta = slosh.theory.rect_sine_elevation(width, depth, amplitude, omega, t)
    a_g = amplitude * omega**2 * np.sin(omega * t)
    assert eta == pytest.approx(a_g * width / (2 * 9.81), rel=0.03)
    assert slosh.theory.rect_sine_elevation(width, depth, amplitude, omega, [-1.0])[0] == 0.0


def test_load_record_el_centro():
    record = slosh.load_record(ELCENTRO)
    # The file's header: 1559 values at 0.02 s, in g; its peak is −0.31882 g at t = 2.02 s
    # (data/README.md), converted with g = 9.81 m/s².
    assert len(record) == 1559 and record.dt == 0.02
    assert record.units == "g" and record.format == "PEER AT2"
    assert record.t.shape == record.accel.shape == (1559,)
    k = int(np.argmax(np.abs(record.accel)))
    assert record.accel[k] == pytest.approx(-0.31882 * 9.81, rel=1e-12)
    assert record.t[k] == pytest.approx(2.02, abs=1e-12)
    same = slosh.load_record(ELCENTRO, format="at2", units="g")
    assert np.array_equal(same.accel, record.accel)
    assert record.scale_to_pga(1.0) is record
    assert np.abs(record.accel).max() == pytest.approx(1.0, rel=1e-12)
    # A very stiff oscillator follows the ground: S_a(T → 0) = PGA (Chopra, Dynamics of
    # Structures §6.6). At T = 0.02 s, far below the record's strong-motion periods (0.1–1
    # s), the peak response is within 5 % of the peak input.
    sa = record.spectrum([0.02, 0.5, 1.0], 0.05)
    assert sa.shape == (3,)
    assert sa[0] == pytest.approx(1.0, rel=0.05)
    # Between 0.1 and 1 s the 5 % spectrum of El Centro is amplified ~2-3× over its PGA.
    assert sa[1] > 1.5
    with pytest.raises(ValueError):
        slosh.load_record(ELCENTRO, units="gal")


def test_record_plain_text_needs_units(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("t,a\n0,0\n0.01,0.5\n0.02,-1.0\n0.03,0\n")
    with pytest.raises(ValueError, match="units"):
        slosh.load_record(path)
    record = slosh.load_record(path, units="g")
    assert record.dt == pytest.approx(0.01)
    assert np.allclose(record.accel, [0.0, 0.5 * 9.81, -9.81, 0.0], rtol=0, atol=1e-12)


def interrupted_after(seconds: float, **kwargs) -> float:
    """Runs the 12 s §3.1 case at dx = 0.02 m (many seconds of wall time), sends SIGINT to
    this process after `seconds`, and returns how long after the signal KeyboardInterrupt
    came. Python turns SIGINT into KeyboardInterrupt only when it starts with SIGINT at its
    default; a test runner started as a background job of a non-interactive shell starts it
    ignored, so the handler an interactive session has is put in place for the test."""
    sent = {}
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)

    def interrupt():
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(seconds, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            slosh.run(PAPER_SCRIPT, threads=1, dx=0.02, frame_interval=0, **kwargs)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    return time.monotonic() - sent["at"]


def test_ctrl_c_raises_keyboard_interrupt_within_a_second():
    elapsed = interrupted_after(1.5)
    assert elapsed < 1.0, f"KeyboardInterrupt came {elapsed:.2f} s after SIGINT"


def test_ctrl_c_stops_the_run_cleanly(tmp_path):
    # With an output folder the run completes its outputs (plots included) before the
    # exception, as `slosh run` does on SIGINT.
    out = tmp_path / "interrupted"
    elapsed = interrupted_after(1.5, out=out)
    assert elapsed < 5.0, f"KeyboardInterrupt came {elapsed:.2f} s after SIGINT"
    run = slosh.Run.load(out)
    assert run.status == "interrupted"
    assert "interrupted by SIGINT" in run.error
    assert 0.0 < run.series["t"][-1] < 12.0
    assert len(run.series["t"]) == len(run.series["eta_left"])
