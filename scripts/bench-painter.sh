#!/usr/bin/env bash
# bench-painter.sh: the depth sort (`painter`, with and without --split) and the hidden
# lines (`hiddenline`) against the z-buffer leaf (`scanconv --resolve`), each leaf alone:
# the screen-space stream of a scene (viewxf | clipbatch | persp at 500x500, made once)
# in, the leaf's output to /dev/null.
#
# Usage: scripts/bench-painter.sh [--quick] [--reps N] [hostile]
#   hostile    the hostile scenes instead (below)
#   --quick    smaller scenes and one run each: a check that it works
#   --reps N   runs of each command (default 5, hostile 3)
#
# Scenes: the thesis's penetrating scene, and its test environment (chapter 5.2) of
# 1,000, 10,000 and 100,000 polygons at depth complexity 3. Per scene and method: the
# least wall seconds of N runs (the machine is shared), the peak resident KiB of one
# more, and for the painter the pixels unlike the z-buffer's frame and, from --stats,
# the cycles it met and those it painted out of order (Newell, Newell and Sancha's
# depth sort, as Sutherland, Sproull and Schumacker describe it).
#
# hostile: `scene stack`, `slivers`, `pinhead`, `strips` and `planes`, where the painter
# and the a-buffer are run under `timeout 120`: the least wall seconds of N, peak
# resident MB, both over the z-buffer's, and for the painter the pixels unlike the
# z-buffer's and whether it said it could not order the polygons.
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

quick=0 reps=''
bench_options "$@"
hostile=0
case "${args[*]}" in
    '') ;;
    hostile) hostile=1 ;;
    *) bench_usage "no argument but hostile, not '${args[*]}'" ;;
esac
reps=${reps:-$((quick ? 1 : hostile ? 3 : 5))}
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-painter.XXXXXX")
trap 'rm -rf "$work"' EXIT
d=$((quick ? 10 : 1))
echo "$(bench_stamp): each leaf alone, 500x500, the least wall seconds of $reps."
echo

cmd=()
zbuf=$(method_leaf hse zbuf) painter=$(method_leaf hse painter)
lines=$(method_leaf lines hiddenline) abuf=$(method_leaf aa abuf)

# frame IN WORDS FRAME: the frame the leaf WORDS draws from IN into FRAME; its stderr in
# $work/err.
frame() {
    local cmd
    leaf_words cmd "$2"
    "${cmd[@]}" <"$1" 2>"$work/err" | "$bindir/zbuf" >"$3"
}

if ((!hostile)); then
    "$bindir/scene" penetrating | to_screen 500x500 >"$work/penetrating"
    scenes=(penetrating)
    for n in $((1000 / d)) $((10000 / d)) $((100000 / d)); do
        "$bindir/scene" environment --polygons "$n" --depth-complexity 3 --seed 4 |
            to_screen 500x500 >"$work/env$n"
        scenes+=("env$n")
    done
    echo "| scene | method | wall s | peak KiB | pixels ≠ zbuf | cycles | painted out of order |"
    echo "|---|---|---|---|---|---|---|"
    for scene in "${scenes[@]}"; do
        in=$work/$scene
        frame "$in" "$zbuf" "$work/z.ppm"
        for method in "$zbuf" "$painter" "$painter --split" "$lines"; do
            echo "$bench_me: $scene, $method" >&2
            leaf_words cmd "$method"
            t=$(best_of "$reps" seconds reading "$in" "${cmd[@]}")
            kib=$(peak_kib "${cmd[@]}" <"$in")
            differ=— cycles=— given_up=—
            if [[ $method == "$painter"* ]]; then
                frame "$in" "$method --stats" "$work/m.ppm"
                differ=$(differing "$work/z.ppm" "$work/m.ppm")
                stats=$(<"$work/err")
                cycles=$(stat_count "$stats" "cycles,")
                given_up=$(stat_count "$stats" "cycles painted out of order")
            fi
            echo "| $scene | $method | ${t%???} | $kib | $differ | $cycles | $given_up |"
        done
    done
    exit 0
fi

over() { timeout 120 "$@"; } # status 124 when the time ran out
echo "| scene, 500x500 | method | wall s | peak MB | time / zbuf | memory / zbuf | pixels ≠ zbuf | said it could not order |"
echo "|---|---|---|---|---|---|---|---|"
for scene in "stack $((20000 / d))" "slivers $((10000 / d))" "pinhead $((100000 / d))" \
    "strips $((3000 / d))" "stack $((2000 / d))" "planes $((2000 / d))" "planes 5" \
    "planes 50" "planes $((400 / d))"; do
    in=$work/${scene// /-}
    read -ra words <<<"$scene"
    "$bindir/scene" "${words[@]}" | to_screen 500x500 >"$in"
    frame "$in" "$zbuf" "$work/z.ppm"
    zt='' zk=''
    for method in "$zbuf" "$painter" "$painter --split" "$abuf"; do
        echo "$bench_me: $scene, $method" >&2
        leaf_words cmd "$method"
        status=0
        t=$(best_of "$reps" seconds reading "$in" over "${cmd[@]}") || status=$?
        if ((status == 124)); then
            echo "| $scene | $method | over 120 | — | — | — | — | — |"
            continue
        fi
        ((status == 0)) || exit "$status"
        kib=$(peak_kib "${cmd[@]}" <"$in")
        zt=${zt:-$t} zk=${zk:-$kib}
        differ=— said=—
        if [[ $method == "$painter"* ]]; then
            frame "$in" "$method" "$work/m.ppm"
            differ=$(differing "$work/z.ppm" "$work/m.ppm")
            said=no
            grep -q "could not order" "$work/err" && said=yes
        fi
        echo "| $scene | $method | ${t%???} | $((kib / 1024)) | $(ratio "$t" "$zt") | $(ratio "$kib" "$zk")" \
            "| $differ | $said |"
    done
done
