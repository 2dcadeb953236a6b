#!/usr/bin/env bash
# The live view in a real browser: starts a long pocl run of the tiny dam break with --serve,
# opens its page in headless Chromium (Debian `chromium`), and checks the screenshot: the image area
# holds the rendered surface (pixels that are neither the page's background nor black) and the
# status bar has text. Run by scripts/test.sh --browser; alone: scripts/browser_check.sh [BUILD_DIR].
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-${CLSPH_BUILD_DIR:-build}}
export POCL_DEVICES=${POCL_DEVICES:-"basic pthread"}
export RUSTICL_ENABLE=${RUSTICL_ENABLE:-llvmpipe}
# Chromium is large (not in scripts/deps.sh: CI does not run this check): installed here when missing.
if ! command -v chromium >/dev/null; then
  if [ "$(id -u)" -eq 0 ]; then
    echo "browser_check: installing chromium"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends chromium >/dev/null
  else
    echo "browser_check: chromium is not installed: sudo apt-get install -y chromium" >&2
    exit 1
  fi
fi
work=$(mktemp -d)
port=${CLSPH_BROWSER_PORT:-8765}
"$build/host/app/clsph" run scenes/dam_break.json --set physics.dp=0.0146 --set physics.coefsound=10 \
  --set 'domain.max=[0.624,0.1898,0.45]' --set 'fluid[0].max=[0.146,0.1752,0.292]' \
  --set 'boundaries.walls[0].max=[0.584,0.1752,0.365]' --until 100 --every 50 --no-checkpoint \
  --devices platform:pocl --out "$work/out" --serve "$port" >"$work/run.log" 2>&1 &
run=$!
trap 'kill -TERM $run 2>/dev/null || true; wait $run 2>/dev/null || true; rm -rf "$work"' EXIT
# Until the run steps and an image has been rendered once (the first builds the render kernels).
for _ in $(seq 120); do
  curl -sf -o /dev/null "http://127.0.0.1:$port/frame.jpg?w=64&h=36" && break
  sleep 0.5
done
shot=${CLSPH_BROWSER_SHOT:-$work/page.png}
# The page's load (and so the screenshot) waits for its first image, the scene camera's.
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1280,800 --screenshot="$shot" "http://127.0.0.1:$port/" >"$work/chromium.log" 2>&1
python3 - "$shot" <<'PY'
import sys, zlib, struct
# A PNG reader for Chromium's 8-bit RGB(A) screenshots (no imaging library needed).
data = open(sys.argv[1], "rb").read()
pos, idat, w, h, ctype = 8, b"", 0, 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8]); body = data[pos + 8:pos + 8 + n]; pos += 12 + n
    if kind == b"IHDR": w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
    elif kind == b"IDAT": idat += body
bpp = 4 if ctype == 6 else 3
raw, rows, prev = zlib.decompress(idat), [], bytearray(w * bpp)
for y in range(h):
    f, line = raw[y * (w * bpp + 1)], bytearray(raw[y * (w * bpp + 1) + 1:(y + 1) * (w * bpp + 1)])
    for x in range(len(line)):
        a = line[x - bpp] if x >= bpp else 0; b = prev[x]; c = prev[x - bpp] if x >= bpp else 0
        if f == 1: line[x] = (line[x] + a) & 255
        elif f == 2: line[x] = (line[x] + b) & 255
        elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line); prev = line
def px(x, y): r = rows[y]; return tuple(r[x * bpp:x * bpp + 3])
# The image area: left of the 380 px probe column, between the header and the status bar.
lit = sum(1 for y in range(60, h - 60, 4) for x in range(20, w - 400, 4) if max(px(x, y)) > 40)
# The status bar: light text on the dark bar in the last 30 rows.
text = sum(1 for y in range(h - 28, h - 4) for x in range(0, w, 2) if min(px(x, y)) > 120)
print(f"browser_check: {lit} lit pixels in the image area, {text} in the status bar ({w} x {h})")
sys.exit(0 if lit > 500 and text > 20 else 1)
PY
echo "browser_check: the live view shows the stream and the status in headless Chromium"
