#!/usr/bin/env python3
"""Wave height and period at a height gauge of a clsph run (probe_NAME.csv), by zero up-crossings.

    scripts/wave_height.py OUTDIR --gauge h_far --start 7.4 --end 11.5 [--expect 0.05 --period 1.6]

Each wave runs from one up-crossing of the mean level to the next; its height is its crest minus
its trough. Prints every wave, their mean height and period, and with --expect / --period the
difference from the expected (Biesel's) height and the paddle's period. Plain Python (no numpy).
"""
import argparse
import csv
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", help="the run's output directory (holds probe_NAME.csv)")
    ap.add_argument("--gauge", required=True, help="the height probe's name (probe_NAME.csv: time,value)")
    ap.add_argument("--start", type=float, default=0.0, help="first time used, s")
    ap.add_argument("--end", type=float, default=float("inf"), help="last time used, s")
    ap.add_argument("--expect", type=float, help="expected wave height, m")
    ap.add_argument("--period", type=float, help="expected period, s")
    a = ap.parse_args()
    path = os.path.join(a.out, f"probe_{a.gauge}.csv")
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"wave_height: cannot read {path}: {e.strerror}")
    if not rows or "time" not in rows[0] or "value" not in rows[0]:
        sys.exit(f"wave_height: {path} is not a probe's time,value table")
    t, h = [], []
    for r in rows:
        ti, v = float(r["time"]), float(r["value"])
        if a.start <= ti <= a.end and v == v:  # nan: no water at the gauge
            t.append(ti)
            h.append(v)
    if len(t) < 4:
        sys.exit(f"wave_height: fewer than 4 samples of {a.gauge} in [{a.start}, {a.end}] s")
    mean = sum(h) / len(h)
    ups = [i for i in range(1, len(h)) if h[i - 1] < mean <= h[i]]
    # Up-crossing times interpolated between samples.
    def cross(i):
        return t[i - 1] + (mean - h[i - 1]) / (h[i] - h[i - 1]) * (t[i] - t[i - 1])
    waves = []
    for k in range(len(ups) - 1):
        seg = h[ups[k]:ups[k + 1] + 1]
        waves.append((cross(ups[k]), cross(ups[k + 1]) - cross(ups[k]), max(seg) - min(seg)))
    if not waves:
        sys.exit(f"wave_height: no whole wave of {a.gauge} in [{a.start}, {a.end}] s")
    for start, period, height in waves:
        print(f"wave from t = {start:.3f} s: period {period:.4f} s, height {height:.5f} m")
    H = sum(w[2] for w in waves) / len(waves)
    T = sum(w[1] for w in waves) / len(waves)
    print(f"{a.gauge}: {len(waves)} waves, mean height {H:.5f} m, mean period {T:.4f} s, mean level {mean:.5f} m")
    if a.expect:
        print(f"height against {a.expect} m: {100 * (H / a.expect - 1):+.1f} %")
    if a.period:
        print(f"period against {a.period} s: {100 * (T / a.period - 1):+.2f} %")


if __name__ == "__main__":
    main()
