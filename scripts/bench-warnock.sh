#!/usr/bin/env bash
# bench-warnock.sh: where Warnock's area subdivision and the hidden-line drawing slow
# down, against the z-buffer leaf: each leaf alone on screen-space scenes (`scene
# screen`) that make one cost grow at a time, file to /dev/null.
#
# Usage: scripts/bench-warnock.sh [--quick] [--reps N] [WxH]
#   WxH        the screen (default 500x500)
#   --quick    a tenth of the polygons and one run each: a check that it works
#   --reps N   runs of each command (default 3)
#
# CPU seconds (user + system) of `scanconv --resolve` (the z-buffer leaf render.sh runs),
# `warnock` and `hiddenline` (SVG): the least of N runs, the machine being shared;
# hiddenline runs once where one run takes over 5 s. Peak resident KiB from one more
# run. "pixels ≠ zbuf" is the pixels of warnock's frame unlike the z-buffer's; from
# warnock --stats, the windows it visited, those decided pixel by pixel and the polygons
# its Looker looked at; from hiddenline --stats, the visible edge pieces it draws (the
# visible complexity). Newman and Sproull, 14.3.4, on what Warnock's cost follows.
#
# Scenes (`scene screen KIND N`):
#   stack-N      N full-screen squares at distinct depths, shuffled (depth complexity N)
#   slivers-N    N triangles across the screen, 0.4 px wide at the base, crossing
#   pinhead-N    N triangles 0.24-0.6 px around one pixel's centre: N fragments in it
#   tiles-K      K x K tiles in front of 2,000 squares: the visible edges grow with K
#   hidden-N     8 x 8 tiles in front of N squares: the hidden polygons grow
#   penetrate    two full-screen planes crossing along a line
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

quick=0 reps=''
bench_options "$@"
((${#args[@]} <= 1)) || bench_usage "one size at most, not '${args[*]}'"
size=${args[0]:-500x500}
[[ $size =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || bench_usage "the size must be WxH, not '$size'"
reps=${reps:-$((quick ? 1 : 3))}
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-warnock.XXXXXX")
trap 'rm -rf "$work"' EXIT

d=$((quick ? 10 : 1))
scenes=("stack-$((1000 / d))" "stack-$((20000 / d))" "slivers-$((1000 / d))"
    "slivers-$((10000 / d))" "pinhead-$((10000 / d))" "pinhead-$((100000 / d))"
    tiles-2 tiles-8 tiles-32 tiles-128 "hidden-$((1000 / d))" "hidden-$((10000 / d))"
    "hidden-$((100000 / d))" penetrate)

# The `scene screen` words of a scene's name.
scene_words() {
    case $1 in
        tiles-*) echo "tiles ${1#tiles-} --behind $((2000 / d))" ;;
        hidden-*) echo "tiles 8 --behind ${1#hidden-}" ;;
        penetrate) echo penetrate ;;
        *) echo "${1%-*} ${1##*-}" ;;
    esac
}

# The windows warnock visited: the sum of its "windows by depth: N N …" list.
windows() {
    local re='windows by depth: ([0-9 ]+);' n t=0
    [[ $1 =~ $re ]] || { echo "$bench_me: no windows by depth in: $1" >&2 && return 1; }
    for n in ${BASH_REMATCH[1]}; do ((t += n)); done
    echo "$t"
}

z=() w=() h=()
leaf_words z "$(method_leaf hse zbuf)"
leaf_words w "$(method_leaf hse warnock)"
leaf_words h "$(method_leaf lines hiddenline)"
echo "## warnock and hiddenline against the z-buffer leaf, $size (CPU s, best of $reps; peak KiB)"
echo
echo "$(bench_stamp): each leaf alone, file to /dev/null."
echo
echo "| scene | polygons | visible edges | zbuf s | warnock s | hiddenline s | zbuf KiB | warnock KiB | hiddenline KiB | windows | pixel windows | looked at | pixels ≠ zbuf |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for name in "${scenes[@]}"; do
    echo "$bench_me: $name" >&2
    f=$work/$name.pp
    read -ra words <<<"$(scene_words "$name")"
    "$bindir/scene" screen "${words[@]}" --size "$size" >"$f"
    zs=$(best_of "$reps" cpu_seconds reading "$f" "${z[@]}")
    ws=$(best_of "$reps" cpu_seconds reading "$f" "${w[@]}")
    hs=$(cpu_seconds reading "$f" "${h[@]}")
    ((${hs%.*} >= 5)) || hs=$(best_of "$reps" cpu_seconds reading "$f" "${h[@]}")
    zk=$(peak_kib "${z[@]}" <"$f")
    wk=$(peak_kib "${w[@]}" <"$f")
    hk=$(peak_kib "${h[@]}" <"$f")
    wstats=$("${w[@]}" --stats <"$f" 2>&1 >"$work/w.runs")
    hstats=$("${h[@]}" --stats <"$f" 2>&1 >/dev/null)
    "${z[@]}" <"$f" | "$bindir/zbuf" >"$work/z.ppm"
    "$bindir/zbuf" <"$work/w.runs" >"$work/w.ppm"
    polygons=$(stat_count "$wstats" "polygons in")
    edges=$(stat_count "$hstats" "pieces drawn;")
    visited=$(windows "$wstats")
    pixel_windows=$(stat_count "$wstats" "single pixels")
    looked=$(stat_count "$wstats" "polygons looked at")
    differ=$(differing "$work/z.ppm" "$work/w.ppm")
    echo "| $name | $polygons | $edges | $zs | $ws | $hs | $zk | $wk | $hk | $visited" \
        "| $pixel_windows | $looked | $differ |"
done
