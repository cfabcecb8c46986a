#!/usr/bin/env bash
# bench-scanline.sh: how Watkins's scan-line method (`scanline`) grows against the
# z-buffer leaf (`scanconv --resolve`) on the same screen-space streams, each leaf alone,
# file to /dev/null. Newman and Sproull, 14.4.3: "its dependence on complexity of the
# scene is difficult to analyze ... the computation grows roughly as the *visible*
# complexity increases".
#
# Usage: scripts/bench-scanline.sh [--quick] [--reps N] [SECTION...]
#   SECTION    1 to 6 (default all)
#   --quick    smaller scenes, fewer frames and one run each: a check that it works
#   --reps N   runs of each command (default 3)
#
#   1. crossings K: K columns across a 1024x1024 screen, each two full-height quads
#      whose planes cross down its middle (`scene screen crossings`): depth complexity 2,
#      K crossings of the visible polygon a scan line
#   2. parallel D: D full-screen planes at random depths (`scene screen parallel`): depth
#      complexity D, no crossing
#   3. tilted D: D full-screen planes tilted at random (`scene screen tilted`): depth
#      complexity D, the front changing along every line
#   4. environment Dc: the thesis's test environment (chapter 5.2), 10,000 quads at
#      500x500, 10 frames, through viewxf, clipbatch and persp
#   5. Archuleta's building (his figures 2 and 3) at 256 and 1024 scan lines, 1000
#      frames, against his 7.2 s and 23.7 s on a DECsystem-10 (3.3 times for 4 times
#      the lines)
#   6. what coherence from line to line buys: `scanline` (the segment list kept in X
#      order by the minor sort, the line above's front and crossings tried first)
#      against `scanline --sort-afresh`, on scenes with much coherence (Archuleta's
#      spheres, 20,000 stacked squares) and little (10,000 slivers, 1,000 strips whose
#      order reverses from top to bottom, 400 planes all crossing), 500x500: the
#      instructions counted by callgrind (steady on a loaded machine; `-` without
#      valgrind), CPU seconds, and the counters per scan line
#
# Sections 1-3 are 10 frames of one scene, so that the times are measurable. Times are
# the least CPU seconds (user + system) of N runs, the machine being shared; `ratio` is
# scanline's over the z-buffer's; the counters come from `scanline --stats`: segments,
# sample spans, depth comparisons and crossings (splits of a sample span where another
# segment comes in front), per scan line.
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

quick=0 reps=''
bench_options "$@"
sections=("${args[@]}")
((${#sections[@]})) || sections=(1 2 3 4 5 6)
for s in "${sections[@]}"; do
    [[ $s =~ ^[1-6]$ ]] || bench_usage "no section '$s' (sections 1 to 6)"
done
reps=${reps:-$((quick ? 1 : 3))}
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-scanline.XXXXXX")
trap 'rm -rf "$work"' EXIT
want() { [[ " ${sections[*]} " == *" $1 "* ]]; }
scanline=() zbuf=()
leaf_words scanline "$(method_leaf hse scanline)"
leaf_words zbuf "$(method_leaf hse zbuf)"

if ((quick)); then
    frames=2 counts=(1 16 64) env_n=1000 building_frames=20 d=10
else
    frames=10 counts=(1 4 16 64 256) env_n=10000 building_frames=1000 d=1
fi

# per A B PLACES: A / B to PLACES places (0 when B is 0).
per() { awk -v a="$1" -v b="$2" -v p="$3" 'BEGIN { printf "%.*f", p, (b > 0 ? a / b : 0) }'; }

# row LABEL FILE: the table row of sections 1-5 for the screen-space stream FILE.
row() {
    local s z stats polygons frames lines
    s=$(best_of "$reps" cpu_seconds reading "$2" "${scanline[@]}")
    z=$(best_of "$reps" cpu_seconds reading "$2" "${zbuf[@]}")
    stats=$("${scanline[@]}" --stats <"$2" 2>&1 >/dev/null)
    polygons=$(stat_count "$stats" "polygons in")
    frames=$(stat_count "$stats" frames)
    lines=$(stat_count "$stats" "scan lines")
    local counters=''
    for c in "segments," "sample spans" "depth comparisons" "crossings;"; do
        counters+=" $(per "$(stat_count "$stats" "$c")" "$lines" 1) |"
    done
    echo "| $1 | $((polygons / frames)) |$counters $s | $z | $(ratio "$s" "$z") |"
}

header() {
    echo "## $1"
    echo
    echo "| $2 | polygons a frame | segments/line | sample spans/line | depth comparisons/line | crossings/line | scanline s | z-buffer s | ratio |"
    echo "|---|---|---|---|---|---|---|---|---|"
}

echo "$(bench_stamp): each leaf alone, CPU seconds, the least of $reps."
echo
if want 1; then
    header "1. Crossings per scan line (depth complexity 2, 1024x1024, $frames frames)" K
    for k in "${counts[@]}" 512; do
        "$bindir/scene" screen crossings "$k" --size 1024x1024 --frames "$frames" >"$work/cross$k"
        row "$k" "$work/cross$k"
    done
    echo
fi
for section in 2 3; do
    want $section || continue
    kind=parallel what="no crossing"
    ((section == 2)) || kind=tilted what="the front changing along each line"
    header "$section. $kind full-screen planes (depth complexity D, $what, 1024x1024, $frames frames)" D
    for n in "${counts[@]}"; do
        "$bindir/scene" screen $kind "$n" --seed "$n" --size 1024x1024 --frames "$frames" >"$work/$kind$n"
        row "$n" "$work/$kind$n"
    done
    echo
done
if want 4; then
    header "4. The test environment, $env_n quads at 500x500, a 10-frame movie" Dc
    for dc in 1 4 16; do
        "$bindir/scene" environment --polygons "$env_n" --depth-complexity $dc --seed 5 \
            --size 500x500 --frames 10 | to_screen 500x500 >"$work/env$dc"
        row "$dc" "$work/env$dc"
    done
    echo
fi
if want 5; then
    header "5. Archuleta's building at 256 and 1024 scan lines, $building_frames frames" lines
    for n in 256 1024; do
        "$bindir/scene" building --frames "$building_frames" | to_screen "${n}x$n" >"$work/building$n"
        row "$n" "$work/building$n"
    done
    echo
fi
if want 6; then
    echo "## 6. What the coherence from line to line buys, 500x500 (instructions: callgrind)"
    echo
    echo "| scene | segments/line | merged in/line | re-sorted/line | swaps/line | fronts predicted held / failed | crossings predicted held / failed | midpoint subdivisions/line | instructions, coherent | instructions, --sort-afresh | ratio | CPU s, coherent | CPU s, --sort-afresh |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    # instructions FILE ARGS…: callgrind's count of scanline's instructions, or `-`.
    instructions() {
        local f=$1 out re='Collected : ([0-9]+)'
        shift
        command -v valgrind >/dev/null || { echo -; return; }
        out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "${scanline[@]}" "$@" <"$f" 2>&1 >/dev/null)
        [[ $out =~ $re ]] || { echo "$bench_me: callgrind counted nothing: $out" >&2 && return 1; }
        echo "${BASH_REMATCH[1]}"
    }
    "$bindir/scene" spheres | to_screen 500x500 >"$work/spheres"
    "$bindir/scene" stack $((20000 / d)) | to_screen 500x500 >"$work/stack"
    "$bindir/scene" slivers $((10000 / d)) | to_screen 500x500 >"$work/slivers"
    "$bindir/scene" planes $((400 / d)) | to_screen 500x500 >"$work/planes"
    "$bindir/scene" screen reversing $((1000 / d)) >"$work/reversing"
    for name in spheres stack slivers reversing planes; do
        f=$work/$name
        stats=$("${scanline[@]}" --stats <"$f" 2>&1 >/dev/null)
        lines=$(stat_count "$stats" "scan lines")
        cells=''
        for c in "segments," "segments merged in" "re-sorted" "swaps"; do
            cells+=" $(per "$(stat_count "$stats" "$c")" "$lines" 2) |"
        done
        cells+=" $(stat_count "$stats" "fronts held") / $(stat_count "$stats" "failed, [0-9]+ crossings held") |"
        cells+=" $(stat_count "$stats" "crossings held") / $(stat_count "$stats" "failed; [0-9]+ midpoint") |"
        cells+=" $(per "$(stat_count "$stats" "midpoint subdivisions")" "$lines" 2) |"
        ic=$(instructions "$f")
        ia=$(instructions "$f" --sort-afresh)
        cc=$(best_of "$reps" cpu_seconds reading "$f" "${scanline[@]}")
        ca=$(best_of "$reps" cpu_seconds reading "$f" "${scanline[@]}" --sort-afresh)
        echo "| $name |$cells $ic | $ia | $(quotient "$ic" "$ia" 3) | $cc | $ca |"
    done
    echo
fi
