#!/usr/bin/env bash
# Throughput of the geometry stages (viewxf, clipplane ×6, splitter, persp), binary →
# binary, file → /dev/null, best of REPS runs.
#
#   scripts/bench-geometry.sh [N] [REPS]      N four-vertex polygons (default 1000000)
#
# The scene: N quads of side ~1 scattered over x, y ∈ [−13, 13], z ∈ [−8, 8] (with the
# thesis camera z_e ∈ [12, 28], the pyramid is |x_e|, |y_e| ≤ 10 at z_e = 16), so a
# realistic share of them is cut by the side planes. It is written directly in the
# binary form (python3; verified through viewxf), viewed once by viewxf into an
# eye-space file for the clippers, and clipped once into the input of persp.
# Target: every stage ≥ 2 million polygons per second.
set -euo pipefail

N=${1:-1000000}
REPS=${2:-3}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=$ROOT/target/release
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-geometry.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" -p viewxf -p clipplane -p splitter -p persp

# The binary stream (proto/src/codec.rs, version 2): magic, bincode header {version u32,
# space tag u32}, then fixed-layout little-endian records: a polygon is the head
# {tag u8 0, colour [u8; 3], vertex count u32} and its vertices as 4 × f64; END is the
# head {tag 2, zeros}.
python3 - "$N" >"$TMP/world.bin" <<'PY'
import random, struct, sys
n = int(sys.argv[1])
rng = random.Random(1985)
out = sys.stdout.buffer
out.write(b"\x89PPIPE\r\n" + struct.pack("<II", 2, 0))  # version 2, world
poly = struct.Struct("<B3BI" + "d" * 16)
buf = []
for i in range(n):
    cx, cy, cz = rng.uniform(-13, 13), rng.uniform(-13, 13), rng.uniform(-8, 8)
    c = (i * 37 % 256, i * 101 % 256, i * 59 % 256)
    buf.append(poly.pack(0, *c, 4,
        cx - 0.5, cy - 0.5, cz, 1.0,
        cx + 0.5, cy - 0.4, cz + 0.1, 1.0,
        cx + 0.4, cy + 0.5, cz, 1.0,
        cx - 0.5, cy + 0.4, cz - 0.1, 1.0))
    if len(buf) == 65536:
        out.write(b"".join(buf)); buf.clear()
out.write(b"".join(buf))
out.write(struct.pack("<B3BI", 2, 0, 0, 0, 0))  # END
PY

# Check the generated stream against the codec before timing anything.
"$BIN/viewxf" --text <"$TMP/world.bin" | head -6 >"$TMP/check.txt"
grep -q '^polypipe 1 eye aspect 1 hither 1 yon 30$' "$TMP/check.txt" \
  || { echo "bench-geometry: generated scene not read as expected" >&2; cat "$TMP/check.txt" >&2; exit 1; }

"$BIN/viewxf" <"$TMP/world.bin" >"$TMP/eye.bin"
"$BIN/clipplane" left <"$TMP/eye.bin" | "$BIN/clipplane" right | "$BIN/clipplane" top \
  | "$BIN/clipplane" bottom | "$BIN/clipplane" hither | "$BIN/clipplane" yon >"$TMP/clipped.bin"

now() { date +%s.%N; }

# bench NAME INPUT CMD...: best wall time of REPS runs of CMD <INPUT >/dev/null.
bench() {
  local name=$1 input=$2
  shift 2
  local best=""
  for _ in $(seq "$REPS"); do
    local t0 t1
    t0=$(now)
    "$@" <"$input" >/dev/null
    t1=$(now)
    best=$(awk -v a="$t0" -v b="$t1" -v best="$best" \
      'BEGIN { t = b - a; if (best == "" || t < best) best = t; printf "%.3f", best }')
  done
  awk -v name="$name" -v n="$N" -v t="$best" \
    'BEGIN { printf "%-16s %10d %9.3f %14.0f\n", name, n, t, n / t }'
}

echo "input sizes: world $(stat -c %s "$TMP/world.bin") B, eye $(stat -c %s "$TMP/eye.bin") B, clipped $(stat -c %s "$TMP/clipped.bin") B"
printf "%-16s %10s %9s %14s\n" stage polygons seconds polygons/s
bench viewxf "$TMP/world.bin" "$BIN/viewxf"
for plane in left right top bottom hither yon; do
  bench "clipplane $plane" "$TMP/eye.bin" "$BIN/clipplane" "$plane"
done
# The root node of a splitter tree, both outputs to /dev/null.
bench "splitter x=0" "$TMP/clipped.bin" "$BIN/splitter" x=0 /dev/null /dev/null
bench "persp" "$TMP/clipped.bin" "$BIN/persp" --size 500x500
bench "persp eye-z" "$TMP/clipped.bin" "$BIN/persp" --size 500x500 --depth eye-z
# The whole chain as the thesis wires it: 8 processes on this machine's cores.
chain() {
  "$BIN/viewxf" | "$BIN/clipplane" left | "$BIN/clipplane" right | "$BIN/clipplane" top \
    | "$BIN/clipplane" bottom | "$BIN/clipplane" hither | "$BIN/clipplane" yon \
    | "$BIN/persp" --size 500x500
}
bench "chain (8 procs)" "$TMP/world.bin" chain
