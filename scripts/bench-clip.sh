#!/usr/bin/env bash
# Clipping throughput: clipbatch (Theoharis & Page's batch clipper, the six planes in one
# process) against the six-process chain clipplane left | right | top | bottom | hither
# | yon, and against the paper's DAP figure of 25,000 polygons a second (Theoharis and Page (1989),
# §4.3). Binary to binary, eye-space file → /dev/null, median of REPS runs, all in one
# run of this script.
#
#   scripts/bench-clip.sh [N] [REPS]     N four-vertex polygons (default 1000000), REPS 5
#
# Two scenes of N quadrilaterals from `scene environment` (thesis ch. 5.2), half of them
# wholly outside one plane of the pyramid:
#   environment  the rest wholly inside (Dc 1): no polygon is cut, so this is the cost of
#                the inside tests and of the stream itself
#   cut-heavy    the rest large (Dc N/10: each covers a fifth of the screen) and viewed
#                with s = 5 instead of 10 (viewxf --s 5, half the field of view), so that
#                nearly every one of them is cut by the side planes: intersections and
#                the insert/compact step
# Both outputs are checked byte for byte against the chain's before anything is timed.
# Columns: wall seconds and CPU seconds (user + system, all processes: the chain runs on
# both cores), polygons per second of wall time and per CPU second, those rates over the
# chain's, and the wall rate over the DAP's.
set -euo pipefail

N=${1:-1000000}
REPS=${2:-5}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=$ROOT/target/release
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-clip.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipplane -p clipbatch

"$BIN/scene" environment --polygons "$N" --clipped 0.5 --depth-complexity 1 --seed 1985 \
  | "$BIN/viewxf" >"$TMP/environment.eye"
"$BIN/scene" environment --polygons "$N" --clipped 0.5 --depth-complexity "$((N / 10 > 0 ? N / 10 : 1))" \
  --seed 1985 | "$BIN/viewxf" --s 5 >"$TMP/cut-heavy.eye"

CHAIN="$BIN/clipplane left | $BIN/clipplane right | $BIN/clipplane top | $BIN/clipplane bottom | $BIN/clipplane hither | $BIN/clipplane yon"

# median_of CMD INPUT: "wall cpu" medians (seconds) of REPS runs of CMD <INPUT >/dev/null.
median_of() {
  local cmd=$1 input=$2 walls=() cpus=()
  for _ in $(seq "$REPS"); do
    /usr/bin/time -f "%e %U %S" -o "$TMP/time" bash -c "$cmd" <"$input" >/dev/null
    read -r e u s <"$TMP/time"
    walls+=("$e")
    cpus+=("$(awk -v u="$u" -v s="$s" 'BEGIN { printf "%.2f", u + s }')")
  done
  local mid=$(((REPS + 1) / 2))
  echo "$(printf '%s\n' "${walls[@]}" | sort -g | sed -n "${mid}p") $(printf '%s\n' "${cpus[@]}" | sort -g | sed -n "${mid}p")"
}

echo "clipping $N four-vertex polygons, binary to binary, median of $REPS (wall and CPU seconds)"
echo
printf '| %-11s | %-24s | %6s | %6s | %10s | %10s | %13s | %12s | %6s |\n' \
  scene clipper wall cpu polygons/s "per cpu-s" "÷ chain, wall" "÷ chain, cpu" "÷ DAP"
echo "|-------------|--------------------------|--------|--------|------------|------------|---------------|--------------|--------|"
for scene in environment cut-heavy; do
  input=$TMP/$scene.eye
  bash -c "$CHAIN" <"$input" >"$TMP/chain.out"
  for b in 1024 4096; do
    "$BIN/clipbatch" --batch "$b" <"$input" | cmp -s - "$TMP/chain.out" \
      || { echo "bench-clip: clipbatch --batch $b differs from the chain on $scene" >&2; exit 1; }
  done
  chain_rate= chain_cpu_rate=
  row() { # row NAME CMD
    local name=$1 cmd=$2 wall cpu rate cpu_rate
    read -r wall cpu < <(median_of "$cmd" "$input")
    rate=$(awk -v n="$N" -v t="$wall" 'BEGIN { printf "%.0f", n / t }')
    cpu_rate=$(awk -v n="$N" -v t="$cpu" 'BEGIN { printf "%.0f", n / t }')
    [[ -n $chain_rate ]] || { chain_rate=$rate; chain_cpu_rate=$cpu_rate; }
    printf '| %-11s | %-24s | %6.2f | %6.2f | %10s | %10s | %13.2f | %12.2f | %6.0f |\n' \
      "$scene" "$name" "$wall" "$cpu" "$rate" "$cpu_rate" \
      "$(awk -v a="$rate" -v b="$chain_rate" 'BEGIN { print a / b }')" \
      "$(awk -v a="$cpu_rate" -v b="$chain_cpu_rate" 'BEGIN { print a / b }')" \
      "$(awk -v a="$rate" 'BEGIN { print a / 25000 }')"
  }
  row "chain (6 x clipplane)" "$CHAIN"
  row "clipbatch --batch 1024" "$BIN/clipbatch --batch 1024"
  row "clipbatch --batch 4096" "$BIN/clipbatch --batch 4096"
  row "clipplane left (1 plane)" "$BIN/clipplane left"
done
echo
echo "per cpu-s: polygons per CPU second (user + system of every process), the figure that a busy"
echo "machine disturbs least. ÷ DAP: polygons/s (wall) over the paper's 25,000/s (the 64×64 ICL"
echo "DAP in DAP Fortran, §4.3)."
