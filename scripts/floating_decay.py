#!/usr/bin/python3
"""Natural period and log decrement of a floating body's heave or roll decay (body_NAME.csv).

    scripts/floating_decay.py --heave OUT/body_heave.csv --roll OUT/body_roll.csv \\
        [--heave-period 1.17 --roll-period 1.28] [--oscillations 4] [--png docs/images/floating_decay.png]

The heave displacement is the centre's z about its equilibrium; the roll angle is the turn about y
(the slice's periodic axis) from the quaternion. The equilibrium is found from the swings (the
body's equilibrium in SPH is not exactly Archimedes', and a decaying record's mean is not its
equilibrium): three successive extremes e0, e1, e2 of a geometric decay about L satisfy
(e1 - L)^2 = (e0 - L)(e2 - L); L is the median over the swings, the crossings found again about
it until it settles. From the successive zero up- and down-crossings (interpolated between steps)
over the first --oscillations periods, while the swings stay above --floor of the first: the
period is the mean time from a crossing to the next of the same sense; the log decrement the mean
of ln(a_k / a_{k+1}) over successive swings' peaks of the same sign, a period apart. The expected periods default to Sundsdal, Greco, Hanssen & Lugni
(2025)'s decay tests of their 2D ship section (heave 1.17 s, roll with sway restricted 1.28 s).
Debian's python3-numpy and python3-matplotlib (hence /usr/bin/python3: a pyenv on PATH hides them).
"""
import argparse
import csv
import math
import sys

import numpy as np


def read_body(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"floating_decay: cannot read {path}: {e.strerror}")
    need = ("time", "z", "qw", "qx", "qy", "qz")
    if not rows or any(k not in rows[0] for k in need):
        sys.exit(f"floating_decay: {path} is not a body_NAME.csv (time,x,y,z,qw,qx,qy,qz,...)")
    return {k: np.array([float(r[k]) for r in rows]) for k in need}


def roll_angle(b):
    """The turn about y: atan2(R_02, R_00) of the quaternion's rotation (exact for a turn about y)."""
    w, x, y, z = b["qw"], b["qx"], b["qy"], b["qz"]
    return np.arctan2(2 * (x * z + w * y), 1 - 2 * (y * y + z * z))


def crossings(t, s, level, skip):
    """Times where s crosses level (interpolated), with +1 (up) or -1 (down), after t = skip."""
    d = s - level
    out = []
    for i in range(1, len(t)):
        if t[i - 1] < skip:
            continue
        if d[i - 1] < 0 <= d[i] or d[i - 1] > 0 >= d[i]:
            if d[i] == d[i - 1]:
                continue
            tc = t[i - 1] + (0 - d[i - 1]) / (d[i] - d[i - 1]) * (t[i] - t[i - 1])
            sense = 1 if d[i] > d[i - 1] else -1
            if out and out[-1][1] == sense:  # noise at a crossing: keep the first of a run
                continue
            out.append((tc, sense))
    return out


def extremes(t, s, cr):
    """(time, value) of the extreme of s between each pair of successive crossings: one a swing."""
    out = []
    for (a, sense), (b, _) in zip(cr, cr[1:]):
        seg = (t >= a) & (t <= b)
        if seg.any():
            k = np.argmax(s[seg]) if sense > 0 else np.argmin(s[seg])
            out.append((t[seg][k], s[seg][k]))
    return out


def analyse(t, s, skip, oscillations, floor):
    """Equilibrium, crossings used, periods, swings and log decrements of one decay record."""
    level = float(np.mean(s[t >= skip]))
    for _ in range(20):
        cr = crossings(t, s, level, skip)
        ext = extremes(t, s, cr)
        # The crossings whose swings stay above the floor (all of them set the level; the first
        # 2 * oscillations + 1 are used below).
        n = 1
        while n < len(cr) and n - 1 < len(ext) and abs(ext[n - 1][1] - level) >= floor * abs(ext[0][1] - level):
            n += 1
        cr, ext = cr[:n], ext[: n - 1]
        if len(cr) < 3:
            return None
        # Three successive extremes of a geometric decay about L: (e1 - L)^2 = (e0 - L)(e2 - L).
        levels = []
        for (_, e0), (_, e1), (_, e2) in zip(ext, ext[1:], ext[2:]):
            d = e0 + e2 - 2 * e1
            if d != 0:
                levels.append((e0 * e2 - e1 * e1) / d)
        new = float(np.median(levels)) if levels else level
        settled = abs(new - level) <= 1e-9 + 1e-6 * abs(ext[0][1] - level)
        level = new
        if settled:
            break
    cr = crossings(t, s, level, skip)[: min(len(cr), 2 * oscillations + 1)]
    ext = [(te, e - level) for te, e in extremes(t, s, cr)]
    periods = [cr[k + 2][0] - cr[k][0] for k in range(len(cr) - 2)]
    decrements = [math.log(ext[k][1] / ext[k + 2][1]) for k in range(len(ext) - 2) if ext[k][1] * ext[k + 2][1] > 0]
    return {"level": level, "crossings": cr, "periods": periods, "swings": ext, "decrements": decrements}


def report(name, unit, scale, res, expect):
    if res is None:
        print(f"{name}: fewer than 3 crossings: no period")
        return
    T = float(np.mean(res["periods"]))
    print(f"{name}: equilibrium {res['level'] * scale:.4f} {unit}; crossings at "
          + ", ".join(f"{c:.3f}" for c, _ in res["crossings"]) + " s")
    print(f"{name}: swings " + ", ".join(f"{a * scale:+.3f}" for _, a in res["swings"]) + f" {unit}")
    print(f"{name}: periods, crossing to crossing of the same sense: " + ", ".join(f"{p:.4f}" for p in res["periods"]) + " s")
    print(f"{name}: period {T:.4f} s (their mean)", end="")
    if expect:
        print(f"; against {expect} s: {100 * (T / expect - 1):+.1f} %")
    else:
        print()
    if res["decrements"]:
        d = float(np.mean(res["decrements"]))
        print(f"{name}: log decrement {d:.3f} (damping ratio {d / math.sqrt(4 * math.pi ** 2 + d * d):.3f}) over "
              f"{len(res['decrements'])} periods")


def plot(ax, t, s, res, expect, label, unit, scale, source, reflections):
    ax.plot(t, (s - (res["level"] if res else 0.0)) * scale, color="tab:blue", lw=1.2, label="clsph")
    ax.axhline(0, color="0.6", lw=0.6)
    if reflections:
        ax.axvspan(reflections, t[-1], color="0.9", label="waves back from the tank's ends")
    if res:
        for c, _ in res["crossings"]:
            ax.plot([c], [0], "o", color="tab:blue", ms=4)
        T = float(np.mean(res["periods"]))
        label = f"{label}: T = {T:.3f} s"
        if expect:
            # Where the crossings fall at the experiment's period, from the first one used.
            c0 = res["crossings"][0][0]
            n = int((t[-1] - c0) / (0.5 * expect)) + 1
            for k in range(n):
                ax.axvline(c0 + 0.5 * k * expect, color="tab:red", lw=0.8, ls="--",
                           label=f"{source}: T = {expect} s" if k == 0 else None)
            label += f" ({100 * (T / expect - 1):+.1f} %)"
    ax.set_ylabel(unit)
    ax.set_title(label, fontsize=10)
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(alpha=0.3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--heave", help="body_NAME.csv of a heave decay (z free)")
    ap.add_argument("--roll", help="body_NAME.csv of a roll decay (turning about y)")
    ap.add_argument("--heave-period", type=float, default=1.17, help="expected heave period, s (default 1.17)")
    ap.add_argument("--roll-period", type=float, default=1.28, help="expected roll period, s (default 1.28)")
    ap.add_argument("--oscillations", type=int, default=4, help="periods used from the first crossing (default 4)")
    ap.add_argument("--floor", type=float, default=0.05, help="stop at a swing below this fraction of the first")
    ap.add_argument("--skip", type=float, default=0.05,
                    help="crossings before this time (s) are not used: a started body crosses at t = 0")
    ap.add_argument("--source", default="Sundsdal et al. 2025", help="the experiment's name in the plot")
    ap.add_argument("--reflections", type=float,
                    help="shade the plot from this time (s): the first waves reflected from the tank's ends are back")
    ap.add_argument("--png", help="write the decay curves here")
    a = ap.parse_args()
    if not a.heave and not a.roll:
        ap.error("give --heave and/or --roll")
    cases = []
    if a.heave:
        b = read_body(a.heave)
        cases.append(("heave", b["time"], b["z"], a.heave_period, "heave (mm)", 1000.0))
    if a.roll:
        b = read_body(a.roll)
        cases.append(("roll", b["time"], roll_angle(b), a.roll_period, "roll (degrees)", 180.0 / math.pi))
    results = []
    for name, t, s, expect, unit, scale in cases:
        res = analyse(t, s, a.skip, a.oscillations, a.floor)
        report(name, unit.split()[1].strip("()"), scale, res, expect)
        results.append(res)
    if a.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(len(cases), 1, figsize=(8, 3 * len(cases)), sharex=True, squeeze=False)
        for ax, (name, t, s, expect, unit, scale), res in zip(axes[:, 0], cases, results):
            plot(ax, t, s, res, expect, name, unit, scale, a.source, a.reflections)
        axes[-1, 0].set_xlabel("time (s)")
        fig.tight_layout()
        fig.savefig(a.png, dpi=120)
        print(f"wrote {a.png}")


if __name__ == "__main__":
    main()
