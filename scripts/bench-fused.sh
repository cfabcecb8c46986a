#!/usr/bin/env bash
# What the pipes and the codec cost: scripts/render.sh (one process per stage, every
# polygon encoded and decoded between stages) against `fused` (tests/src/bin/fused.rs:
# the same stage libraries called one after the other in one process), on the same scene
# file, writing the same PPM bytes (checked before anything is timed). Wall time, median
# of REPS runs, all in one run of this script; the goal is pipes ≤ 1.3 × fused.
#
#   scripts/bench-fused.sh [REPS]      (default 5)
#
# Scenes (`scene environment`, thesis ch. 5.2), each as scene writes it (binary) and as
# text:
#   environment  100,000 quads, Dc 2, 500x500 (geometry-heavy)
#   fill-heavy   10,000 quads, Dc 10, 1920x1080 (as scripts/bench-pipeline.sh makes it)
# Rows: render.sh --depth 0; the same processes as one shell pipe line (viewxf |
# clipplane ×6 | persp | scanconv | zbuf: render.sh less its script); that pipe line with
# clipbatch for the six clipplane processes; fused with the six planes; fused with
# clipbatch's batch clipper. Columns: median wall and CPU seconds, and each over fused's.
# On a machine shared with other work the CPU seconds are the steadier figure; the pipes
# can beat the single-threaded fused run on wall time when one stage (the text parser)
# sets the pace and the others run beside it on the second core.
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

# median CMD: "wall cpu", the median wall and CPU seconds (user + system of every
# process) of REPS runs of a shell command.
median() {
  local walls=() cpus=() t0 t1 u s
  for _ in $(seq "$REPS"); do
    t0=$EPOCHREALTIME
    /usr/bin/time -f "%U %S" -o "$TMP/time" bash -c "$1" >/dev/null
    t1=$EPOCHREALTIME
    read -r u s <"$TMP/time"
    walls+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')")
    cpus+=("$(awk -v u="$u" -v s="$s" 'BEGIN { printf "%.2f", u + s }')")
  done
  local mid=$(((REPS + 1) / 2))
  echo "$(printf '%s\n' "${walls[@]}" | sort -g | sed -n "${mid}p") $(printf '%s\n' "${cpus[@]}" | sort -g | sed -n "${mid}p")"
}

"$B/scene" environment --polygons 100000 --depth-complexity 2 --seed 1 >"$TMP/environment.bin"
"$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 >"$TMP/fill-heavy.bin"
"$B/scene" environment --polygons 100000 --depth-complexity 2 --seed 1 --text >"$TMP/environment.txt"
"$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 --text >"$TMP/fill-heavy.txt"

echo "render.sh against the same stages in one process: median of $REPS, wall and CPU seconds"
echo "(user + system of every process); ratios over fused (six planes) in the same scene and form"
echo
echo "| scene | form | run | wall s | cpu s | wall ÷ fused | cpu ÷ fused |"
echo "|---|---|---|---|---|---|---|"
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
for scene in environment fill-heavy; do
  size=500x500
  [[ $scene == fill-heavy ]] && size=1920x1080
  for form in bin txt; do
    file=$TMP/$scene.$form
    clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"
    names=("render.sh" "pipes" "pipes, clipbatch" "fused" "fused, clipbatch")
    cmds=(
      "$ROOT/scripts/render.sh --size $size $file"
      "$B/viewxf --size $size < $file | $clip | $B/persp --size $size | $B/scanconv | $B/zbuf"
      "$B/viewxf --size $size < $file | $B/clipbatch | $B/persp --size $size | $B/scanconv | $B/zbuf"
      "$B/fused --size $size $file"
      "$B/fused --clipper batch --size $size $file"
    )
    bash -c "${cmds[0]}" >"$TMP/expected.ppm"
    for cmd in "${cmds[@]:1}"; do
      bash -c "$cmd" | cmp -s - "$TMP/expected.ppm" \
        || { echo "bench-fused: \`$cmd\` does not write render.sh's frame" >&2; exit 1; }
    done
    walls=() cpus=()
    for i in "${!cmds[@]}"; do
      read -r w c < <(median "${cmds[$i]}")
      walls+=("$w") cpus+=("$c")
    done
    for i in "${!cmds[@]}"; do
      echo "| $scene $size | $([[ $form == bin ]] && echo binary || echo text) | ${names[$i]} | ${walls[$i]} | ${cpus[$i]}" \
        "| $(ratio "${walls[$i]}" "${walls[3]}") | $(ratio "${cpus[$i]}" "${cpus[3]}") |"
    done
  done
done
echo
echo "pipes: render.sh's processes as one shell pipe line (no script, no named pipes)."
