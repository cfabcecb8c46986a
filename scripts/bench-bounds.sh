#!/usr/bin/env bash
# bench-bounds.sh: the bounds every method must keep on the scenes a user makes in a
# minute to break it, and whether it keeps them.
#
# Usage: scripts/bench-bounds.sh [--quick] [--reps N]
#   --quick    a tenth of the polygons: a check that it works (the bounds are not for it)
#   --reps N   runs of each command (default 1); the table gives the one of least CPU
#
# 1. On `scene stack 20000`, `scene slivers 10000` and `scene pinhead 100000` at
#    500x500, every hidden-surface method (render's --hse), painter --split, the
#    hidden-line drawing and the a-buffer: under 256 MB of peak resident memory and 30 s.
# 2. painter --split on `scene planes N` (N = 5, 50, 400): within 0.5% of the z-buffer's
#    pixels, or saying on stderr that it could not order the planes.
#
# Each method runs as a leaf alone, the screen-space stream (scene | viewxf | clipbatch |
# persp, made once) in and its output to /dev/null, under `timeout 120`: wall and CPU
# seconds (user + system) and peak resident memory. On a loaded machine the wall time
# can be several times the CPU time; the bound is checked on both, and a row says which
# it misses.
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

quick=0 reps=1
bench_options "$@"
((${#args[@]} == 0)) || bench_usage "no arguments but options, not '${args[*]}'"
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-bounds.XXXXXX")
trap 'rm -rf "$work"' EXIT
d=$((quick ? 10 : 1))

# The methods: render's, then the painter's splitting, the hidden lines and the a-buffer.
mapfile -t methods < <(methods_list hse)
methods+=("painter --split"$'\t'"$(method_leaf hse painter) --split")
mapfile -t -O ${#methods[@]} methods < <(methods_list lines)
methods+=("abuf"$'\t'"$(method_leaf aa abuf)")

cmd=()
# over CMD…: CMD under `timeout 120`, status 124 when the time ran out.
over() { timeout 120 "$@"; }

echo "$(bench_stamp): each leaf alone, 500x500; the run of least CPU of $reps."
echo
echo "| scene | method | wall s | CPU s | peak MB | CPU / zbuf | within 256 MB and 30 s |"
echo "|---|---|---|---|---|---|---|"
for scene in "stack $((20000 / d))" "slivers $((10000 / d))" "pinhead $((100000 / d))"; do
    in=$work/${scene// /-}
    read -ra words <<<"$scene"
    "$bindir/scene" "${words[@]}" | to_screen 500x500 >"$in"
    zcpu=''
    for method in "${methods[@]}"; do
        IFS=$'\t' read -r name leaf <<<"$method"
        echo "$bench_me: $scene, $name" >&2
        leaf_words cmd "$leaf"
        status=0
        cpu=$(best_of "$reps" cpu_seconds reading "$in" over "${cmd[@]}") || status=$?
        if ((status == 124)); then
            echo "| $scene | $name | over 120 | — | — | — | no: over 120 s |"
            continue
        fi
        ((status == 0)) || exit "$status"
        wall=$(seconds reading "$in" "${cmd[@]}")
        mb=$(($(peak_kib "${cmd[@]}" <"$in") / 1024))
        zcpu=${zcpu:-$cpu}
        ok=yes
        if ((mb >= 256)); then
            ok="no: memory"
        elif ((${cpu%.*} >= 30)); then
            ok="no: CPU time"
        elif ((${wall%.*} >= 30)); then
            ok="CPU yes, wall no"
        fi
        echo "| $scene | $name | ${wall%???} | $cpu | $mb | $(quotient "$cpu" "$zcpu" 1) | $ok |"
    done
done

echo
echo "| scene planes N, 500x500 | pixels unlike the z-buffer | share | painter --split said it could not order | within 0.5% or said |"
echo "|---|---|---|---|---|"
zbuf=() split=()
leaf_words zbuf "$(method_leaf hse zbuf)"
leaf_words split "$(method_leaf hse painter) --split"
for n in 5 50 400; do
    in=$work/planes-$n
    "$bindir/scene" planes "$n" | to_screen 500x500 >"$in"
    "${zbuf[@]}" <"$in" | "$bindir/zbuf" >"$work/z.ppm"
    "${split[@]}" <"$in" 2>"$work/err" | "$bindir/zbuf" >"$work/p.ppm"
    differ=$(differing "$work/z.ppm" "$work/p.ppm")
    said=no
    grep -q "could not order" "$work/err" && said=yes
    ok=no
    ((differ * 200 < 250000)) || [[ $said == yes ]] && ok=yes
    share=$((differ * 10000 / 250000)) # hundredths of a per cent
    printf '| %d | %d | %d.%02d%% | %s | %s |\n' "$n" "$differ" $((share / 100)) $((share % 100)) "$said" "$ok"
done
