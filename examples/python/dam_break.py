#!/usr/bin/env python3
"""A dam break built in Python, run with clsph, its surge front plotted against the experiment of
Koshizuka & Oka (1996).

    PYTHONPATH=build/python python3 examples/python/dam_break.py [--coarse] [--until 0.4] [--out DIR]

The scene is a dict in the schema of docs/scenes.md: a water column L wide and 2L high against the
wall at x = 0 of a tank 4L long, as a thin slice periodic in y. The front is the largest x of any
fluid particle; Z = x_front / L against T = t sqrt(2 g / L). Writes surge_front.csv and
surge_front.png into --out.
"""
import argparse
import math
import os
import sys

import numpy as np

import clsph

L = 0.146  # the experiment's column width (m)


def dam_break(dp, coefsound):
    """The dam break as a scene dict: the column fills x in [0, L], z in [0, 2L]."""
    depth = 13 * dp  # periodic slice: at least three kernel supports deep
    return {
        "name": "dam_break_python",
        "physics": {"dp": dp, "hdp": 2.0, "coefsound": coefsound, "gravity": [0, 0, -9.81]},
        "domain": {"min": [-0.04, 0, -0.04], "max": [4 * L + 0.04, depth, 2.2 * L + 0.13],
                   "periodic": [False, True, False], "split_axis": "x"},
        "fluid": [{"min": [0, 0, 0], "max": [L, depth - 0.5 * dp, 2 * L]}],
        "boundaries": {"walls": [{"min": [0, 0, 0], "max": [4 * L, depth - 0.5 * dp, 2.5 * L],
                                  "faces": ["x-", "x+", "z-"], "layers": 3}]},
        "run": {"end_time": 0.4, "output_every": 0.01},
    }


def read_experiment(path):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#") or line[0].isalpha():
                continue
            t, z = line.split(",")[:2]
            rows.append((float(t), float(z)))
    return rows


def progress(fraction, text):
    width = 30
    done = int(round(width * fraction))
    sys.stderr.write("\r[" + "#" * done + "-" * (width - done) + "] %3.0f %% %s" % (100 * fraction, text))
    sys.stderr.flush()


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--coarse", action="store_true", help="L/dp = 10 and c0 = 10 sqrt(gH): a quick run")
    ap.add_argument("--until", type=float, default=0.4, help="simulated seconds (default 0.4)")
    ap.add_argument("--out", default="out/dam_break_python", help="output directory")
    ap.add_argument("--devices", default="", help="device selection, as clsph --devices (default: every GPU, else every CPU)")
    ap.add_argument("--experiment", default=os.path.join(here, "..", "..", "tests", "data", "dam_break_koshizuka_oka_1996.csv"))
    args = ap.parse_args()

    dp, coefsound = (L / 10, 10.0) if args.coarse else (L / 20, 20.0)
    scene = clsph.scene(dam_break(dp, coefsound))
    sim = clsph.Simulation(scene, devices=args.devices)
    print("clsph %s: %d particles on %s (interaction %s)" % (clsph.__version__, sim.info.particles,
          ", ".join(sim.devices()), ", ".join(sim.interaction_forms())))

    g = 9.81
    t_scale = math.sqrt(2 * g / L)
    series = []

    def front():
        p = sim.particles()
        return float(p["position"][p["type"] == 0, 0].max()) / L

    every = 0.01
    series.append((0.0, front()))
    while sim.time < args.until - 1e-12:
        target = min(args.until, (round(sim.time / every) + 1) * every)
        sim.run_until(target, lambda s: progress(s.time / args.until, "t = %.3f s, step %d" % (s.time, s.step)))
        series.append((sim.time * t_scale, front()))
    sys.stderr.write("\n")

    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "surge_front.csv"), "w") as f:
        f.write("T,Z\n")
        for T, Z in series:
            f.write("%.6g,%.6g\n" % (T, Z))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = read_experiment(args.experiment)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ax.plot([T for T, _ in series], [Z for _, Z in series], "-", label="clsph from Python (L/dp = %.0f)" % (L / dp))
    ax.plot([T for T, _ in data], [Z for _, Z in data], "o", color="black", label="Koshizuka & Oka (1996)")
    ax.set_xlabel(r"$T = t\,\sqrt{2g/L}$")
    ax.set_ylabel(r"$Z = x_\mathrm{front}/L$")
    ax.set_title("Dam break from Python: surge front")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "surge_front.png"))
    # RMS of the front against the experiment, where both exist
    Ts, Zs = np.array([T for T, _ in series]), np.array([Z for _, Z in series])
    pts = [(T, Z) for T, Z in data if T <= Ts[-1]]
    rms = math.sqrt(sum((np.interp(T, Ts, Zs) - Z) ** 2 for T, Z in pts) / len(pts)) if pts else float("nan")
    print("surge front: %s (RMS %.3f in Z against the experiment up to T = %.2f)" %
          (os.path.join(args.out, "surge_front.png"), rms, Ts[-1]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
