#!/usr/bin/env python3
"""Kernel launches per step from the per-kernel table that `clsph run ... --profile` prints.

Usage: scripts/launches_per_step.py SHORT.txt LONG.txt
  the saved output of two runs of one scene that differ only in length (--steps N1 and N2, or
  --until T1 and T2): each kernel's calls in the longer run less those in the shorter, over the
  difference in steps, so that the set-up's launches (the first upload's sort and tables, the
  first step) drop out exactly. Transfers (transfer.*) are not launches and are left out.
With one file: its calls over its steps (set-up included).
"""
import re
import sys


def table(path):
    text = open(path).read()
    m = re.search(r"per-kernel device time \((\d+) steps\):", text)
    if not m:
        sys.exit(f"{path}: no per-kernel table (was the run given --profile?)")
    rows = {}
    for line in text[m.end():].splitlines()[2:]:
        parts = line.split()
        if len(parts) < 2 or not parts[1].isdigit() or parts[0] == "total":
            break
        rows[parts[0]] = int(parts[1])
    return int(m.group(1)), rows


def main() -> int:
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    s1, r1 = table(sys.argv[1]) if len(sys.argv) == 3 else (0, {})
    s2, r2 = table(sys.argv[-1])
    if s2 <= s1:
        sys.exit("the second run must take more steps than the first")
    per = {k: (c - r1.get(k, 0)) / (s2 - s1) for k, c in r2.items() if not k.startswith("transfer.")}
    per = {k: v for k, v in per.items() if v > 0}
    print(f"{sum(per.values()):.2f} kernel launches per step ({s2 - s1} steps)")
    for k, v in sorted(per.items(), key=lambda kv: (-kv[1], kv[0])):
        print(f"  {k:28s} {v:6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
