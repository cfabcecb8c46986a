#!/usr/bin/env bash
# bench-stages.sh: the stages and the stream between them measured, one mode a run:
#
#   scripts/bench-stages.sh geometry [N] [REPS]   throughput of viewxf, clipplane ×6,
#                                                 splitter, persp, binary to binary
#   scripts/bench-stages.sh clip [N] [REPS]       clipbatch against the clipplane chain
#                                                 and Theoharis & Page's DAP figure
#   scripts/bench-stages.sh codec [POLYGONS] [REPS]  the stream codec, binary and text
#   scripts/bench-stages.sh fused [REPS]          render.sh's pipes against the same
#                                                 libraries in one process (`fused`)
#   scripts/bench-stages.sh fill [REPS]           zbuf's depth tests per CPU second on
#                                                 the fill-heavy scene, and the span
#                                                 z-test alone (scan's example ztest)
#   scripts/bench-stages.sh shading [REPS]        flat, Gouraud and Phong shading of one
#                                                 sphere: zbuf's CPU and render.sh's
#
# Each mode's own notes are at its function below. They share scripts/lib/bench.sh.

# The modes are functions of their own (each a subshell), and some reuse a name for an
# array in one and a string in another, which shellcheck reads as one variable.
# shellcheck disable=SC2128,SC2154,SC2178
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

# --- geometry ------------------------------------------------------------------
mode_geometry() (
# Throughput of the geometry stages (viewxf, clipplane ×6, splitter, persp), binary →
# binary, file → /dev/null, best of REPS runs.
#
#   scripts/bench-stages.sh geometry [N] [REPS]      N four-vertex polygons (default 1000000)
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
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-geometry.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" -p viewxf -p clipplane -p splitter -p persp
BIN=$(release_bin "$ROOT")

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
  || { echo "bench-stages.sh geometry: generated scene not read as expected" >&2; cat "$TMP/check.txt" >&2; exit 1; }

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
bench "persp eye-z" "$TMP/clipped.bin" "$BIN/persp" --size 500x500 --zmode eye-z
# The whole chain as the thesis wires it: 8 processes on this machine's cores.
chain() {
  "$BIN/viewxf" | "$BIN/clipplane" left | "$BIN/clipplane" right | "$BIN/clipplane" top \
    | "$BIN/clipplane" bottom | "$BIN/clipplane" hither | "$BIN/clipplane" yon \
    | "$BIN/persp" --size 500x500
}
bench "chain (8 procs)" "$TMP/world.bin" chain
)

# --- clip ----------------------------------------------------------------------
mode_clip() (
# Clipping throughput: clipbatch (Theoharis & Page's batch clipper, the six planes in one
# process) against the six-process chain clipplane left | right | top | bottom | hither
# | yon, and against the paper's DAP figure of 25,000 polygons a second (Theoharis & Page 1989,
# §4.3). Binary to binary, eye-space file → /dev/null, median of REPS runs, all in one
# run of this script.
#
#   scripts/bench-stages.sh clip [N] [REPS]     N four-vertex polygons (default 1000000), REPS 5
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
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-clip.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipplane -p clipbatch
BIN=$(release_bin "$ROOT")

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
      || { echo "bench-stages.sh clip: clipbatch --batch $b differs from the chain on $scene" >&2; exit 1; }
  done
  chain_rate='' chain_cpu_rate=
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
)

# --- codec ---------------------------------------------------------------------
mode_codec() (
# The stream codec measured, printed as tables.
#
#   scripts/bench-stages.sh codec [POLYGONS] [REPS]     (defaults 200000 and 5)
#
#   1. binary records in memory: stream version 1 (serde + bincode) against version 2
#      (fixed layout), encode and decode, four-vertex eye-space polygons and fragment
#      spans (proto/examples/codec_bench.rs)
#   2. the text form in memory: read (the environment scene's text) and write, MB/s;
#      float parsers on that text's numbers (str::parse, fast-float2, lexical-core)
#   3. the text form through a stage: `viewxf < scene.txt > /dev/null`, whole process
#   4. every geometry stage binary → binary, polygons/s (scripts/bench-stages.sh geometry with
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
B=$(release_bin "$root")
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

echo "## 4. Geometry stages, binary to binary (scripts/bench-stages.sh geometry 1000000 $REPS)"
echo
echo '```'
"$root/scripts/bench-stages.sh" geometry 1000000 "$REPS"
echo '```'
)

# --- fused ---------------------------------------------------------------------
mode_fused() (
# What the pipes and the codec cost: scripts/render.sh (one process per stage, every
# polygon encoded and decoded between stages) against `fused` (tests/src/bin/fused.rs:
# the same stage libraries called one after the other in one process), on the same scene
# file, writing the same PPM bytes (checked before anything is timed). Wall time, median
# of REPS runs, all in one run of this script; the goal is pipes ≤ 1.3 × fused.
#
#   scripts/bench-stages.sh fused [REPS]      (default 5)
#
# Scenes (`scene environment`, thesis ch. 5.2), each as scene writes it (binary) and as
# text:
#   environment  100,000 quads, Dc 2, 500x500 (geometry-heavy)
#   fill-heavy   10,000 quads, Dc 10, 1920x1080 (as `bench tree pipeline` makes it)
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
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-fused.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipplane -p clipbatch -p splitter -p persp -p scanconv -p zbuf \
  -p pipeline-tests --bins
B=$(release_bin "$ROOT")

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
        || { echo "bench-stages.sh fused: \`$cmd\` does not write render.sh's frame" >&2; exit 1; }
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
)

# --- fill ------------------------------------------------------------------------
mode_fill() (
# The fill rate: `zbuf --stats` on the screen stream of the fill-heavy scene (bench.sh's
# (c): 10,000 quads, Dc≈10, 1920×1080), made once to a file, so that zbuf's scan
# conversion and depth tests are all that is timed. CPU time is user + system of the
# process (bash's `time`), the median of REPS runs (default 9); the rate is the pixels
# zbuf says it tested over it. BASE=path/to/another/zbuf measures that one too,
# interleaved run for run, and gives this zbuf's CPU over its. Then the span z-test alone:
# `cargo run --release -p scan --example ztest` (each kernel on spans of 8-256 pixels in
# the L2 cache).
set -euo pipefail
REPS=${1:-9}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-fill.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" -p scene -p viewxf -p clipbatch -p persp -p zbuf
B=$(release_bin "$ROOT")
fill_scene "$B" |
    "$B/viewxf" --size 1920x1080 | "$B/clipbatch" | "$B/persp" --size 1920x1080 > "$TMP/fill.screen"
tested=$("$B/zbuf" --stats "$TMP/fill.screen" 2>&1 >/dev/null | sed -n 's/.* \([0-9]*\) pixels tested.*/\1/p')
[[ -n $tested ]] || { echo "bench-stages.sh fill: zbuf --stats gave no pixel count" >&2; exit 1; }
zbufs=("$B/zbuf")
[[ -z ${BASE-} ]] || zbufs+=("$BASE")
if ((${#zbufs[@]} == 2)); then
    "$BASE" "$TMP/fill.screen" | cmp -s - <("$B/zbuf" "$TMP/fill.screen") ||
        { echo "bench-stages.sh fill: $BASE draws another frame" >&2; exit 1; }
fi
declare -A cpu
for ((r = 0; r < REPS; r++)); do
    for z in "${zbufs[@]}"; do cpu[$z]+="$(cpu_seconds "$z" "$TMP/fill.screen") "; done
done
echo "| zbuf | pixels tested | CPU s (median of $REPS) | M tests per CPU s |"
echo "|---|---|---|---|"
for z in "${zbufs[@]}"; do
    c=$(tr ' ' '\n' <<< "${cpu[$z]}" | grep . | median)
    echo "| $z | $tested | $c | $(awk -v n="$tested" -v c="$c" 'BEGIN { printf "%.0f", n / c / 1e6 }') |"
done
if ((${#zbufs[@]} == 2)); then
    a=$(tr ' ' '\n' <<< "${cpu[$B/zbuf]}" | grep . | median)
    b=$(tr ' ' '\n' <<< "${cpu[$BASE]}" | grep . | median)
    echo
    echo "CPU of this zbuf over BASE's: $(ratio "$a" "$b")"
fi
echo
cargo run --release --quiet --manifest-path "$ROOT/Cargo.toml" -p scan --example ztest
)

mode_shading() (
# What shading costs and what it buys: one sphere lit by the same light with a highlight
# (`--specular 0.5,30`), per face (flat), per vertex (`--gouraud`) and per pixel
# (`--phong`), at 1000×1000. Cost, on the sphere of 18,432 polygons (`--stacks 96 --slices
# 192`): zbuf alone on the sphere's screen stream (made once to a file: scan conversion,
# depth tests and shading), and the whole of `render.sh --depth 0` (every process's CPU);
# user + system (bash's `time`), the median of REPS interleaved runs (default 9), ratios
# against flat. Error: each frame against Phong's (`zspec compare --metrics`: RMSE and
# the largest difference in levels), on that sphere and on one of 288 polygons
# (`--stacks 12 --slices 24`), where the vertices sample the highlight too coarsely. Every
# frame is checked against zspec's first.
set -euo pipefail
REPS=${1:-9}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-shading.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" -p scene -p viewxf -p clipbatch -p persp -p zbuf -p zspec
B=$(release_bin "$ROOT")
export POLYPIPE_LOAD=0
kinds=(flat gouraud phong)
declare -A option=([flat]="" [gouraud]=--gouraud [phong]=--phong)
for fine in 96 12; do
    for k in "${kinds[@]}"; do
        # shellcheck disable=SC2086
        "$B/scene" sphere --stacks "$fine" --slices $((2 * fine)) ${option[$k]} --specular 0.5,30 \
            > "$TMP/$k-$fine.world"
        "$B/viewxf" --size 1000x1000 < "$TMP/$k-$fine.world" | "$B/clipbatch" |
            "$B/persp" --size 1000x1000 > "$TMP/$k-$fine.screen"
        "$B/zspec" --size 1000x1000 < "$TMP/$k-$fine.world" > "$TMP/$k-$fine.ppm"
        "$B/zbuf" "$TMP/$k-$fine.screen" | cmp -s - "$TMP/$k-$fine.ppm" ||
            { echo "bench-stages.sh shading: $k: zbuf's frame is not zspec's" >&2; exit 1; }
    done
done
# "RMSE / max" of a frame against Phong's.
error() {
    "$B/zspec" compare --metrics "$TMP/$1.ppm" "$TMP/phong-${1#*-}.ppm" |
        awk '/^overall/ { for (i = 1; i < NF; i++) { if ($i == "rmse") r = $(i + 1); if ($i == "max") m = $(i + 1) } printf "%.2f / %d", r, m }'
}
declare -A zbuf render
for ((r = 0; r < REPS; r++)); do
    for k in "${kinds[@]}"; do
        zbuf[$k]+="$(cpu_seconds "$B/zbuf" "$TMP/$k-96.screen") "
        render[$k]+="$(cpu_seconds "$ROOT/scripts/render.sh" --size 1000x1000 --depth 0 "$TMP/$k-96.world") "
    done
done
echo "| shading | zbuf CPU ms | ratio | render.sh --depth 0 CPU ms | ratio | error against Phong, 18,432 polygons | the same, 288 polygons |"
echo "|---|---:|---:|---:|---:|---:|---:|"
z0=$(tr ' ' '\n' <<< "${zbuf[flat]}" | grep . | median)
w0=$(tr ' ' '\n' <<< "${render[flat]}" | grep . | median)
for k in "${kinds[@]}"; do
    z=$(tr ' ' '\n' <<< "${zbuf[$k]}" | grep . | median)
    w=$(tr ' ' '\n' <<< "${render[$k]}" | grep . | median)
    printf '| %s | %.1f | %s | %.1f | %s | %s | %s |\n' "$k" \
        "$(awk -v s="$z" 'BEGIN { print s * 1000 }')" "$(ratio "$z" "$z0")" \
        "$(awk -v s="$w" 'BEGIN { print s * 1000 }')" "$(ratio "$w" "$w0")" \
        "$(error "$k-96")" "$(error "$k-12")"
done
)

case ${1-} in
    geometry) shift; mode_geometry "$@" ;;
    fill) shift; mode_fill "$@" ;;
    clip) shift; mode_clip "$@" ;;
    codec) shift; mode_codec "$@" ;;
    fused) shift; mode_fused "$@" ;;
    shading) shift; mode_shading "$@" ;;
    -h | --help | "") sed -n '2,/^$/{s/^# \{0,1\}//;p}' "${BASH_SOURCE[0]}"; [[ -n ${1-} ]] ;;
    *) echo "bench-stages.sh: no mode '$1' (modes: geometry clip codec fused fill shading)" >&2; exit 2 ;;
esac
