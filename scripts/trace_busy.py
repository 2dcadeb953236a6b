#!/usr/bin/env python3
"""Where a GPU opened as several slabs spends a step, from `clsph-bench-sph --trace FILE`.

    trace_busy.py TRACE.csv[.gz] [--steps-command sph.kick_drift]

The bench's own summary gives each slab's idle time, but slabs of one GPU share it: while one slab's
queue waits, the GPU may be running another's. This joins the slabs of each physical device (their
names differ only by " slab i/n") and prints, per step: the wall time from first to last command,
the time some queue of the device was busy (the union of every command's span), the time the whole
device stood idle (the union's gaps, summed by the command that ends each gap: what the device was
waiting to be given), and the union of the force passes alone, so that busy minus forces is the
step's other work where no force pass hides it.
"""
import argparse
import collections
import csv
import gzip
import re


def union(spans):
    """Total length of the union of (start, end) spans, and its gaps as (gap, index of the span after it)."""
    total, gaps = 0, []
    cur_s = cur_e = None
    for i, (s, e) in enumerate(spans):
        if cur_s is None:
            cur_s, cur_e = s, e
        elif s <= cur_e:
            cur_e = max(cur_e, e)
        else:
            total += cur_e - cur_s
            gaps.append((s - cur_e, i))
            cur_s, cur_e = s, e
    if cur_s is not None:
        total += cur_e - cur_s
    return total, gaps


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trace")
    ap.add_argument("--steps-command", default="sph.kick_drift", help="a command run once a step by each slab")
    args = ap.parse_args()
    opener = gzip.open if args.trace.endswith(".gz") else open
    with opener(args.trace, "rt") as f:
        rows = list(csv.DictReader(f))
    by_device = collections.defaultdict(list)
    for r in rows:
        physical = re.sub(r" slab \d+/\d+$", "", r["device"])
        by_device[physical].append((int(r["start_ns"]), int(r["end_ns"]), r["device"], r["command"]))
    for device, cmds in by_device.items():
        cmds.sort()
        slabs = sorted({c[2] for c in cmds})
        steps = sum(1 for c in cmds if c[3] == args.steps_command and c[2] == slabs[0])
        if steps == 0:
            raise SystemExit(f"{args.trace}: no {args.steps_command} on {slabs[0]}: name a command every step runs")
        busy, gaps = union([(s, e) for s, e, _, _ in cmds])
        forces, _ = union([(s, e) for s, e, _, c in cmds if c == "sph.forces"])
        wall = max(e for _, e, _, _ in cmds) - cmds[0][0]
        idle_before = collections.Counter()
        for gap, i in gaps:
            idle_before[cmds[i][3]] += gap
        ms = lambda ns: ns / 1e6 / steps  # noqa: E731 (ms per step)
        print(f"{device}: {len(slabs)} slab(s), {steps} steps")
        print(f"  wall {ms(wall):.3f} ms/step, busy (any slab) {ms(busy):.3f}, idle {ms(wall - busy):.3f}")
        print(f"  force passes (union) {ms(forces):.3f}; other work outside them {ms(busy - forces):.3f}")
        print("  the whole device idle before:")
        for name, gap in idle_before.most_common(8):
            print(f"    {name}: {ms(gap):.3f}")


if __name__ == "__main__":
    main()
