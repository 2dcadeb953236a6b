#!/usr/bin/env python3
"""SPHERIC-2 (Kleefsman et al. 2005) against the experiment's event times, from a run's probe files.

Usage: scripts/spheric2_validation.py OUTDIR [OUTDIR ...]

Reads OUTDIR/probe_P1.csv (the pressure sensor on the obstacle's face, written by
scripts/spheric2_validation.sh) and the water-height gauges OUTDIR/probe_H2.csv, probe_H3.csv, and
prints, per run: when P1 first exceeds 500 Pa, its peak (value and time), and when each gauge
wets (the first reading above 0.01 m: a thin film reads nothing, a gauge reads the first
fall of the fluid fraction through 1/2 from the bottom up). The experiment's figures
(the issue's, from the published data) are printed beside them. Standard library only.
"""
import csv
import math
import os
import sys

EXPERIMENT = {"P1 > 500 Pa": 0.393, "P1 peak time": 0.415, "P1 peak (Pa)": 11200.0, "H3 wets": 0.218, "H2 wets": 0.368}
WET = 0.01  # m


def series(path):
    out = []
    with open(path) as f:
        for row in csv.reader(f):
            if not row or row[0] == "time":
                continue
            t, v = float(row[0]), float(row[1])
            out.append((t, v))
    return out


def first_above(rows, level):
    for t, v in rows:
        if not math.isnan(v) and v > level:
            return t
    return float("nan")


def summary(out):
    r = {}
    p1 = series(os.path.join(out, "probe_P1.csv"))
    r["P1 > 500 Pa"] = first_above(p1, 500.0)
    valid = [(t, v) for t, v in p1 if not math.isnan(v)]
    if valid:
        t, v = max(valid, key=lambda x: x[1])
        r["P1 peak time"], r["P1 peak (Pa)"] = t, v
    for g in ("H3", "H2"):
        path = os.path.join(out, "probe_%s.csv" % g)
        r["%s wets" % g] = first_above(series(path), WET) if os.path.exists(path) else float("nan")
    return r


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 1
    runs = [(d, summary(d)) for d in sys.argv[1:]]
    keys = list(EXPERIMENT)
    print("| quantity | experiment | " + " | ".join(os.path.basename(d.rstrip("/")) for d, _ in runs) + " |")
    print("|---|---|" + "---|" * len(runs))
    for k in keys:
        fmt = "%.0f" if k.endswith("(Pa)") else "%.4f"
        cells = [fmt % r.get(k, float("nan")) for _, r in runs]
        print("| %s | %s | %s |" % (k, fmt % EXPERIMENT[k], " | ".join(cells)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
