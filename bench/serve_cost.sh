#!/usr/bin/env bash
# The cost of the live view (issue 31): the dam break as written, synchronous without --serve and
# with --serve while one client pulls 1280 x 720 JPEGs at up to 30 per second, three alternated
# pairs (wall seconds; stats.csv compared), then frames per second delivered to one client for the
# bunny at each dp given. Uses curl and python3.
#   bench/serve_cost.sh CLSPH [--devices SPEC] [dp ...]     e.g. bench/serve_cost.sh build/host/app/clsph --devices platform:nvidia 0.0019
set -euo pipefail
C=$1; shift
devices=(); if [ "${1:-}" = --devices ]; then devices=(--devices "$2"); shift 2; fi
now() { python3 -c 'import time; print(time.time())'; }
"$C" run scenes/dam_break.json --synchronous "${devices[@]}" --no-checkpoint --force --until 0.01 --out /tmp/clsph-serve0 >/dev/null 2>&1
for i in 1 2 3; do
  a=$(now); "$C" run scenes/dam_break.json --synchronous "${devices[@]}" --no-checkpoint --force --out /tmp/clsph-serve1 >/dev/null 2>&1; b=$(now)
  echo "dam break, synchronous, no serve: $(python3 -c "print(round($b - $a, 2))") s"
  ( sleep 1.5; for k in $(seq 1 400); do curl -s -o /dev/null -m 2 "http://127.0.0.1:8080/frame.jpg?w=1280&h=720" || true; sleep 0.033; done ) &
  client=$!
  a=$(now); "$C" run scenes/dam_break.json --serve 8080 "${devices[@]}" --no-checkpoint --force --out /tmp/clsph-serve2 >/dev/null 2>&1; b=$(now)
  kill $client 2>/dev/null || true; wait $client 2>/dev/null || true
  echo "dam break, --serve with a client at up to 30 frames/s: $(python3 -c "print(round($b - $a, 2))") s"
done
cmp /tmp/clsph-serve1/stats.csv /tmp/clsph-serve2/stats.csv && echo "stats.csv identical"
port=8090
for dp in "$@"; do
  port=$((port + 1))
  "$C" run scenes/bunny.json --set physics.dp="$dp" --serve $port "${devices[@]}" --no-checkpoint --until 10 --force --out /tmp/clsph-serve3 >/dev/null 2>&1 &
  run=$!
  sleep 14
  python3 - "$port" "$dp" <<'P'
import json, sys, time, urllib.request
port, dp = sys.argv[1], sys.argv[2]
base = "http://127.0.0.1:" + port
urllib.request.urlopen(base + "/frame.jpg?w=1280&h=720", timeout=30).read()
s0 = json.load(urllib.request.urlopen(base + "/api/status"))
t0, n = time.time(), 0
while time.time() - t0 < 8:
    urllib.request.urlopen(base + "/frame.jpg?w=1280&h=720", timeout=30).read()
    n += 1
s1 = json.load(urllib.request.urlopen(base + "/api/status"))
dt = time.time() - t0
print(f"bunny dp {dp}: {s1['particles']} particles, {n / dt:.1f} frames/s delivered, {(s1['step'] - s0['step']) / dt:.1f} steps/s while serving")
P
  kill -INT $run; wait $run || true
done
