#!/usr/bin/env python3
"""Surge front of a dam-break run against Koshizuka & Oka (1996).

Reads a `clsph run --csv` output directory: run.json (the resolved scene: the fluid column's width
L and its wall x0, gravity) and the frames listed in the .pvd (their CSV twins). The front is the
largest x of any fluid particle; Z = (x_front - x0) / L against T = t sqrt(2 g / L). Writes
surge_front.csv (T, Z) and surge_front.png into the same directory.

usage: plot_surge.py OUT_DIR [EXPERIMENT_CSV]
"""
import csv
import glob
import json
import math
import os
import sys
import xml.etree.ElementTree as ET


def read_experiment(path):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#") or line[0].isalpha():
                continue  # comments and the T,Z header
            t, z = line.split(",")[:2]
            rows.append((float(t), float(z)))
    return rows


def front_x(csv_path):
    """Largest x of a fluid particle (type 0) in one CSV frame."""
    best = -math.inf
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            if row["type"] == "0":
                best = max(best, float(row["x"]))
    return best


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    here = os.path.dirname(os.path.abspath(__file__))
    experiment = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "..", "tests", "data", "dam_break_koshizuka_oka_1996.csv")

    with open(os.path.join(out, "run.json")) as f:
        scene = json.load(f)["scene"]
    column = scene["fluid"][0]
    x0 = column["min"][0]
    L = column["max"][0] - x0
    g = math.sqrt(sum(c * c for c in scene["physics"]["gravity"]))
    t_scale = math.sqrt(2.0 * g / L)

    # The frames' collection (surface.pvd, written beside it by --surface/--render, lists surfaces).
    pvds = [p for p in glob.glob(os.path.join(out, "*.pvd")) if os.path.basename(p) != "surface.pvd"]
    if len(pvds) != 1:
        sys.exit(f"plot_surge: expected one frame collection (.pvd) in {out}, found {len(pvds)}")
    series = []
    for ds in ET.parse(pvds[0]).getroot().iter("DataSet"):
        frame = os.path.join(out, os.path.splitext(ds.get("file"))[0] + ".csv")
        if not os.path.exists(frame):
            sys.exit(f"plot_surge: {frame} is missing; run clsph with --csv")
        series.append((float(ds.get("timestep")) * t_scale, (front_x(frame) - x0) / L))

    with open(os.path.join(out, "surge_front.csv"), "w") as f:
        f.write("T,Z\n")
        for T, Z in series:
            f.write(f"{T:.6g},{Z:.6g}\n")

    import matplotlib
    matplotlib.use("Agg")  # no display needed
    import matplotlib.pyplot as plt

    data = read_experiment(experiment)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ax.plot([T for T, _ in series], [Z for _, Z in series], "-", color="tab:blue",
            label=f"clsph ({scene['name']}, L/dp = {L / scene['physics']['dp']:.0f})")
    ax.plot([T for T, _ in data], [Z for _, Z in data], "o", color="black", label="Koshizuka & Oka (1996)")
    ax.set_xlabel(r"$T = t\,\sqrt{2g/L}$")
    ax.set_ylabel(r"$Z = x_\mathrm{front}/L$")
    ax.set_title(f"Dam break: surge front (L = {L:g} m)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    png = os.path.join(out, "surge_front.png")
    fig.savefig(png)
    print(f"plot_surge: {png} ({len(series)} frames)")


if __name__ == "__main__":
    main()
