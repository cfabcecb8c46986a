#!/usr/bin/env bash
# bench-codec.sh: the stream codec measured, printed as tables.
#
#   scripts/bench-codec.sh [POLYGONS] [REPS]     (defaults 200000 and 5)
#
#   1. binary records in memory: stream version 1 (serde + bincode) against version 2
#      (fixed layout), encode and decode, four-vertex eye-space polygons and fragment
#      spans (proto/examples/codec_bench.rs)
#   2. the text form in memory: read (the environment scene's text) and write, MB/s;
#      float parsers on that text's numbers (str::parse, fast-float2, lexical-core)
#   3. the text form through a stage: `viewxf < scene.txt > /dev/null`, whole process
#   4. every geometry stage binary → binary, polygons/s (scripts/bench-geometry.sh with
#      1,000,000 polygons)
#
# Each figure is the best of REPS runs on whatever else the machine is doing: compare
# figures within one run of the script, not across machines. Targets: every
# geometry stage ≥ 5 million four-vertex polygons/s, the text reader ≥ 200 MB/s.
set -euo pipefail

N=${1:-200000}
REPS=${2:-5}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet -p proto --example codec_bench
cargo build --release --quiet -p scene -p viewxf
B=$root/target/release
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-codec.XXXXXX")
trap 'rm -rf "$work"' EXIT

# The environment scene of thesis 5.2 as text: 100,000 quads, Dc 2.
"$B/scene" environment --polygons 100000 --depth-complexity 2 --seed 1 --text >"$work/scene.txt"
bytes=$(stat -c %s "$work/scene.txt")

echo "## 1-2. Codec in one process ($N polygons; text: scene environment --polygons 100000)"
echo
"$B/examples/codec_bench" "$N" "$REPS" "$work/scene.txt"
echo

echo "## 3. Text through a stage: viewxf < scene.txt > /dev/null ($bytes bytes, best of $REPS)"
echo
best=
for ((i = 0; i < REPS; i++)); do
    t0=$(date +%s.%N)
    "$B/viewxf" <"$work/scene.txt" >/dev/null
    t1=$(date +%s.%N)
    best=$(awk -v a="$t0" -v b="$t1" -v best="$best" \
        'BEGIN { t = b - a; if (best == "" || t < best) best = t; printf "%.3f", best }')
done
echo "| stage | wall s | MB/s |"
echo "|---|---|---|"
awk -v t="$best" -v b="$bytes" 'BEGIN { printf "| viewxf (text in, binary out) | %s | %.0f |\n", t, (t > 0 ? b / t / 1e6 : 0) }'
echo

echo "## 4. Geometry stages, binary to binary (scripts/bench-geometry.sh 1000000 $REPS)"
echo
echo '```'
"$root/scripts/bench-geometry.sh" 1000000 "$REPS"
echo '```'
