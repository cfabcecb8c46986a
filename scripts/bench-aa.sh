#!/usr/bin/env bash
# What anti-aliasing costs at a leaf: time and peak memory of the leaf's method alone on
# one screen-space frame, point sampling (scanconv --resolve) against supersampling 4×4
# and 8×8 and the a-buffer (docs/antialiasing.md). The scene is `scene environment`
# (thesis ch. 5.2) of N quadrilaterals at WxH, run once through viewxf | clipbatch |
# persp into a file; each method then reads that file, so only the method is timed.
# Wall and CPU seconds are the median of REPS runs; peak RSS (/usr/bin/time -v's
# "Maximum resident set size") the largest of them.
#
#   scripts/bench-aa.sh [N] [WxH] [REPS]      (defaults 100000 1920x1080 3)
set -euo pipefail

N=${1:-100000}
SIZE=${2:-1920x1080}
REPS=${3:-3}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
B=$ROOT/target/release
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-aa.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipbatch -p persp -p scanconv -p supersample -p abuf

"$B/scene" environment --polygons "$N" --size "$SIZE" --seed 1 \
  | "$B/viewxf" --size "$SIZE" | "$B/clipbatch" | "$B/persp" --size "$SIZE" >"$TMP/screen.bin"
polygons=$("$B/scanconv" --resolve --stats <"$TMP/screen.bin" 2>&1 >/dev/null \
  | sed -n 's/^scanconv: \([0-9]*\) polygons in.*/\1/p')

# measure NAME CMD...: one row, median wall and CPU seconds of REPS runs, largest RSS.
measure() {
  local name=$1 walls=() cpus=() rss=0 r
  shift
  for _ in $(seq "$REPS"); do
    /usr/bin/time -v -o "$TMP/time" "$@" <"$TMP/screen.bin" >"$TMP/out" 2>/dev/null
    walls+=("$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, t, ":"); s = 0;
      for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.2f", s }' "$TMP/time")")
    cpus+=("$(awk -F': ' '/User time/ { u = $2 } /System time/ { s = $2 }
      END { printf "%.2f", u + s }' "$TMP/time")")
    r=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$TMP/time")
    ((r > rss)) && rss=$r
  done
  local mid=$(((REPS + 1) / 2))
  printf '%-14s %8s %8s %12s %10s\n' "$name" \
    "$(printf '%s\n' "${walls[@]}" | sort -g | sed -n "${mid}p")" \
    "$(printf '%s\n' "${cpus[@]}" | sort -g | sed -n "${mid}p")" \
    "$rss" "$(stat -c %s "$TMP/out")"
}

echo "scene environment --polygons $N --size $SIZE --seed 1: $polygons polygons into the leaf"
echo "one leaf (depth 0), median of $REPS runs"
printf '%-14s %8s %8s %12s %10s\n' method wall_s cpu_s max_rss_kib out_bytes
measure point "$B/scanconv" --resolve
measure ss4 "$B/supersample" --samples 4
measure ss8 "$B/supersample" --samples 8
measure abuf "$B/abuf"
