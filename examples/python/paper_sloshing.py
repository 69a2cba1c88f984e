# %% [markdown]
# # Paper §3.1 from Python: resonant sloshing in a 2D tank
#
# The 1.0 m wide tank with 0.5 m of water of Ono, Iwamoto & Scawthorn (2007), §3.1, shaken
# at resonance after settling under gravity (`scripts/paper_2d_sloshing.rhai`). This script
# runs it from Python, compares the wall elevation η with linear potential theory, and
# compares the paper's scheme with the modern one (symplectic integrator, δ-SPH, Adami
# walls). Run it from the repository's root after `pip install ./crates/slosh-py`:
#
#     python examples/python/paper_sloshing.py [--duration 6] [--dx 0.02]
#
# Cells are marked `# %%`, so editors that know Jupyter cells can run it a cell at a time.

# %%
import argparse
from pathlib import Path

import slosh

parser = argparse.ArgumentParser(description="Paper §3.1 from Python, two schemes")
parser.add_argument("--duration", type=float, default=6.0, help="simulated time, s (paper: 12)")
parser.add_argument("--dx", type=float, default=0.02, help="particle spacing, m")
parser.add_argument("--out", type=Path, default=Path("out/python-example"), help="plots go here")
args, _ = parser.parse_known_args()

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "paper_2d_sloshing.rhai"

# %% [markdown]
# The parameters the script declares, with their defaults and units.

# %%
for name, p in slosh.params(SCRIPT).items():
    print(f"{name:<18} {p['default']!s:<10} {p['unit'] or '-':<6} {p['description'] or ''}")

# %% [markdown]
# Closed forms: the first sloshing period of the tank and the linear resonance.

# %%
width, depth = 1.0, 0.5
report = slosh.theory.rect(width, depth, amplitude=0.0093, omega=5.311)
mode1 = report["modes"][0]
print(f"first mode: ω1 = {mode1['omega']:.4f} rad/s, T1 = {mode1['period']:.4f} s")

# %% [markdown]
# Both schemes on the same case (shortened: `duration` seconds in all, settling included).

# %%
runs = {}
for scheme in ("paper", "modern"):
    runs[scheme] = slosh.run(
        SCRIPT, scheme=scheme, duration=args.duration, dx=args.dx, frame_interval=0,
        progress=True,
    )
    s = runs[scheme].summary
    print(
        f"{scheme:>6}: {s['steps']} steps in {s['wall_time_s']:.1f} s, "
        f"max η_left = {s['max_eta_left']:.4f} m, max |base shear x| = "
        f"{s['max_abs_base_shear_x']:.1f} N/m"
    )

# %% [markdown]
# Linear theory for η at the left wall: the undamped modal response of potential theory to
# the ground displacement x_g = −A sin ωt from rest, which grows linearly in time at
# resonance until nonlinearity takes over (the reference of `slosh validate`'s resonant
# case, paper Fig. 3).

# %%
A, omega = 0.0093, 5.311
settle = slosh.params(SCRIPT)["settle"]["default"]

# %%
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
    print("matplotlib is not installed: no plot (pip install matplotlib)")

if plt is not None:
    args.out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(9, 4))
    for scheme, run in runs.items():
        ax.plot(run.series["t"], run.series["eta_left"], label=f"SPH, {scheme} scheme")
    t = runs["paper"].series["t"]
    eta_lin = slosh.theory.rect_sine_elevation(width, depth, A, omega, t - settle)
    ax.plot(t, eta_lin, "k--", label="linear potential theory")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("η at the left wall [m]")
    ax.set_title("Paper §3.1: resonant sloshing, 1.0 m tank, 0.5 m of water")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "eta_vs_theory.png", dpi=120)
    print(f"plot: {args.out / 'eta_vs_theory.png'}")

# %% [markdown]
# The two schemes side by side as a table (pandas when it is installed).

# %%
try:
    frames = {scheme: run.to_pandas()["eta_left"] for scheme, run in runs.items()}
    import pandas as pd

    print(pd.DataFrame(frames).describe())
except ImportError:
    for scheme, run in runs.items():
        eta = run.series["eta_left"]
        print(f"{scheme:>6}: η_left mean {eta.mean():+.4f} m, std {eta.std():.4f} m")
