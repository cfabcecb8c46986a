#!/usr/bin/env bash
# What the pipes and the codec cost: scripts/render.sh (one process per stage, every
# polygon encoded and decoded between stages) against `fused` (tests/src/bin/fused.rs:
# the same stage libraries called one after the other in one process), on the same scene
# file, writing the same PPM bytes (checked before anything is timed). Wall time, median
# of REPS runs, all in one run of this script; the goal of issue 9 is pipes ≤ 1.3 × fused.
#
#   scripts/bench-fused.sh [REPS]      (default 5)
#
# Scenes (`scene environment`, thesis ch. 5.2), each as scene writes it (binary) and as
# text:
#   environment  100,000 quads, Dc 2, 500x500 (geometry-heavy)
#   fill-heavy   10,000 quads, Dc 10, 1920x1080 (as scripts/bench-pipeline.sh makes it)
# Columns: render.sh --depth 0; the same processes as one shell pipe line (viewxf |
# clipplane ×6 | persp | scanconv | zbuf: render.sh less its script); that pipe line with
# clipbatch for the six clipplane processes; fused with the six planes; fused with
# clipbatch's batch clipper; and the ratios render.sh ÷ fused, pipes ÷ fused and
# pipes-with-clipbatch ÷ fused-with-clipbatch.
set -euo pipefail

REPS=${1:-5}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
B=$ROOT/target/release
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-fused.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipplane -p clipbatch -p splitter -p persp -p scanconv -p zbuf \
  -p pipeline-tests --bins

# render.sh rebuilds when a source, Cargo.toml or Cargo.lock is newer than a stage
# binary; cargo, having nothing to do, leaves the binaries' times alone, and render.sh
# would then run cargo (a ~0.1 s no-op) on every run. cargo has just said they are
# current: make their times say so.
for b in viewxf clipplane splitter persp scanconv zbuf; do touch "$B/$b"; done

# median CMD: the median wall time (seconds) of REPS runs of a shell command.
median() {
  local times=() t0 t1
  for _ in $(seq "$REPS"); do
    t0=$EPOCHREALTIME
    bash -c "$1" >/dev/null
    t1=$EPOCHREALTIME
    times+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')")
  done
  printf '%s\n' "${times[@]}" | sort -g | sed -n "$(((REPS + 1) / 2))p"
}

"$B/scene" environment --polygons 100000 --depth-complexity 2 --seed 1 >"$TMP/environment.bin"
"$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 >"$TMP/fill-heavy.bin"
"$B/scene" environment --polygons 100000 --depth-complexity 2 --seed 1 --text >"$TMP/environment.txt"
"$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 --text >"$TMP/fill-heavy.txt"

echo "render.sh against the same stages in one process, wall seconds, median of $REPS"
echo
echo "| scene | form | size | render.sh | pipes | pipes, clipbatch | fused | fused, clipbatch | render.sh ÷ fused | pipes ÷ fused | pipes ÷ fused (clipbatch) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
for scene in environment fill-heavy; do
  size=500x500
  [[ $scene == fill-heavy ]] && size=1920x1080
  for form in bin txt; do
    file=$TMP/$scene.$form
    render="$ROOT/scripts/render.sh --size $size $file"
    clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"
    pipes="$B/viewxf --size $size < $file | $clip | $B/persp --size $size | $B/scanconv | $B/zbuf"
    pipes_batch="$B/viewxf --size $size < $file | $B/clipbatch | $B/persp --size $size | $B/scanconv | $B/zbuf"
    fused="$B/fused --size $size $file"
    fused_batch="$B/fused --clipper batch --size $size $file"
    bash -c "$render" >"$TMP/expected.ppm"
    for cmd in "$pipes" "$pipes_batch" "$fused" "$fused_batch"; do
      bash -c "$cmd" | cmp -s - "$TMP/expected.ppm" \
        || { echo "bench-fused: \`$cmd\` does not write render.sh's frame" >&2; exit 1; }
    done
    t_render=$(median "$render")
    t_pipes=$(median "$pipes")
    t_pipes_batch=$(median "$pipes_batch")
    t_fused=$(median "$fused")
    t_batch=$(median "$fused_batch")
    echo "| $scene | $([[ $form == bin ]] && echo binary || echo text) | $size | $t_render | $t_pipes | $t_pipes_batch | $t_fused | $t_batch" \
      "| $(ratio "$t_render" "$t_fused") | $(ratio "$t_pipes" "$t_fused") | $(ratio "$t_pipes_batch" "$t_batch") |"
  done
done
