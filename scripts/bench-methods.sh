#!/usr/bin/env bash
# bench-methods.sh: each hidden-surface method of render.sh (--hse) at every splitter
# depth, on the four scene classes of bench llvmpipe: whole process, wall seconds.
#
# Usage: scripts/bench-methods.sh [--quick] [--reps N]
#   --quick    smaller scenes, depths 0 and 2, one run each: a check that it works
#   --reps N   runs of each command (default 3)
#
# Scenes (`scene environment`, thesis chapter 5.2): (a) 1,024 quads at 500x500; (b)
# 100,000 quads at depth complexity 2; (c) the fill-heavy scene, 10,000 quads at depth
# complexity 10 at 1920x1080; (d) a movie of 1,024 quads, 100 frames. Each cell is the
# median of N runs of `render.sh --hse METHOD --depth D`; the table gives each method's
# time at depth 0, its best depth of 0-4 and the time there, and that best over the
# z-buffer's best.
#
# The leaf methods alone are measured by `bench painter`, `bench scanline`,
# `bench warnock` and bench-aa.sh; their bounds on hostile scenes by `bench bounds`.
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

# The modes this script had once are scripts of their own now.
case ${1-} in
    painter | scanline | warnock | aa | bounds)
        echo "$bench_me: the $1 mode is scripts/bench-$1.sh now" >&2
        exit 2
        ;;
    methods) shift ;;
esac
quick=0 reps=''
bench_options "$@"
((${#args[@]} == 0)) || bench_usage "no arguments but options, not '${args[*]}'"
reps=${reps:-$((quick ? 1 : 3))}
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-methods.XXXXXX")
trap 'rm -rf "$work"' EXIT

if ((quick)); then
    env_n=256 geo_n=5000 fill_n=1000 fill_size=480x270 frames=5 depths=(0 2)
else
    env_n=1024 geo_n=100000 fill_n=10000 fill_size=1920x1080 frames=100 depths=(0 1 2 3 4)
fi
scenes=(env geo fill movie)
declare -A size label
size[env]=500x500 label[env]="(a) $env_n quads"
size[geo]=500x500 label[geo]="(b) $geo_n quads, Dc≈2"
size[fill]=$fill_size label[fill]="(c) $fill_n quads, Dc≈10, $fill_size"
size[movie]=500x500 label[movie]="(d) $env_n quads × $frames frames"
scene() { "$bindir/scene" environment "$@"; }
scene --seed 1 --polygons "$env_n" --size 500x500 >"$work/env"
scene --seed 3 --polygons "$geo_n" --depth-complexity 2 --size 500x500 >"$work/geo"
scene --seed 2 --polygons "$fill_n" --depth-complexity 10 --size "$fill_size" >"$work/fill"
scene --seed 4 --polygons "$env_n" --frames "$frames" --size 500x500 >"$work/movie"
mapfile -t methods < <(methods_list hse)
methods=("${methods[@]%%$'\t'*}")

# The median of each method at each depth, in `t[scene.method.depth]`.
declare -A t
for s in "${scenes[@]}"; do
    for m in "${methods[@]}"; do
        for d in "${depths[@]}"; do
            echo "$bench_me: $s $m depth $d" >&2
            t[$s.$m.$d]=$(timed "$reps" "$bench_root/scripts/render.sh" --size "${size[$s]}" \
                --hse "$m" --depth "$d" "$work/$s")
        done
    done
done

# best_depth S M: "seconds depth", the best time of method M on scene S and its depth.
best_depth() {
    local d
    for d in "${depths[@]}"; do echo "${t[$1.$2.$d]} $d"; done | sort -g | head -n 1
}

echo
echo "$(bench_stamp): render.sh whole process, wall seconds, median of $reps. The last" \
    "column is the method's best time over the z-buffer's best."
echo
echo "| scene | method | depth 0 s | best depth | best s | best / zbuf best |"
echo "|---|---|---|---|---|---|"
for s in "${scenes[@]}"; do
    read -r zbest _ <<<"$(best_depth "$s" zbuf)"
    for m in "${methods[@]}"; do
        read -r mbest d <<<"$(best_depth "$s" "$m")"
        echo "| ${label[$s]} | $m | ${t[$s.$m.0]} | $d | $mbest | $(ratio "$mbest" "$zbest") |"
    done
done
