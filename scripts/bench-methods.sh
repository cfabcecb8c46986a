#!/usr/bin/env bash
# bench-methods.sh: each hidden-surface method (render.sh --hse) at depth 0 and at its best
# depth of 0-4, on the four scene classes of scripts/bench.sh, whole process, wall seconds,
# median of N, in one run. Not part of CI.
#
# Usage: scripts/bench-methods.sh [--quick] [--reps N]
#   --quick    smaller scenes (20,000 quads, the fill scene at 960x540, 20 frames)
#   --reps N   timed runs of each command (default 3)
# Needs: cargo (builds the binaries), bash 5.1.
set -euo pipefail
export LC_ALL=C

quick=0 reps=3
while (($#)); do
    case $1 in
        --quick) quick=1; shift ;;
        --reps) reps=${2:?--reps needs N}; shift 2 ;;
        -h | --help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "bench-methods.sh: unknown argument $1" >&2; exit 2 ;;
    esac
done
[[ $reps =~ ^[1-9][0-9]*$ ]] || { echo "bench-methods.sh: --reps must be a positive integer" >&2; exit 2; }

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
B=${CARGO_TARGET_DIR:-$root/target}/release
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release --quiet --bins

if ((quick)); then
    geo_n=20000 fill_n=2000 fill_size=960x540 movie_frames=20
else
    geo_n=100000 fill_n=10000 fill_size=1920x1080 movie_frames=100
fi
scenes=(env geo fill movie)
declare -A size label
size[env]=500x500 label[env]="(a) 1,024 quads"
size[geo]=500x500 label[geo]="(b) $geo_n quads, Dc≈2"
size[fill]=$fill_size label[fill]="(c) $fill_n quads, Dc≈10, $fill_size"
size[movie]=500x500 label[movie]="(d) 1,024 quads × $movie_frames frames"
"$B/scene" environment --seed 1 --polygons 1024 --size 500x500 > "$work/env.pp"
"$B/scene" environment --seed 3 --polygons "$geo_n" --depth-complexity 2 --size 500x500 > "$work/geo.pp"
"$B/scene" environment --seed 2 --polygons "$fill_n" --depth-complexity 10 --size "$fill_size" > "$work/fill.pp"
"$B/scene" environment --seed 4 --polygons 1024 --frames "$movie_frames" --size 500x500 > "$work/movie.pp"

methods=(zbuf scanline warnock painter)

# seconds COMMAND…: wall seconds of one run, its output thrown away.
seconds() {
    local t0=$EPOCHREALTIME
    "$@" > /dev/null
    awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.6f\n", b - a }'
}
median() { sort -g | awk '{ t[NR] = $1 } END { printf "%.3f", NR % 2 ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2 }'; }

declare -A t
for s in "${scenes[@]}"; do
    for m in "${methods[@]}"; do
        for d in 0 1 2 3 4; do
            echo "bench-methods.sh: $s $m depth $d" >&2
            t[$s.$m.$d]=$(for ((r = 0; r < reps; r++)); do
                seconds scripts/render.sh --size "${size[$s]}" --hse "$m" --depth "$d" "$work/$s.pp"
            done | median)
        done
    done
done

echo
echo "Measured by \`scripts/bench-methods.sh$( ((quick)) && echo ' --quick')\` at commit" \
    "$(git rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) cores," \
    "$(date -u +%Y-%m-%d): render.sh whole process, wall seconds, median of $reps, one run." \
    "The last column is the method's best time over zbuf's best."
echo
echo "| scene | method | depth 0 s | best depth | best s | best / zbuf best |"
echo "|---|---|---|---|---|---|"
for s in "${scenes[@]}"; do
    zbest=
    for d in 0 1 2 3 4; do
        v=${t[$s.zbuf.$d]}
        if [[ -z $zbest ]] || awk -v a="$v" -v b="$zbest" 'BEGIN { exit !(a < b) }'; then zbest=$v; fi
    done
    for m in "${methods[@]}"; do
        best= bd=
        for d in 0 1 2 3 4; do
            v=${t[$s.$m.$d]}
            if [[ -z $best ]] || awk -v a="$v" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$v bd=$d; fi
        done
        ratio=$(awk -v a="$best" -v b="$zbest" 'BEGIN { printf "%.2f", a / b }')
        echo "| ${label[$s]} | $m | ${t[$s.$m.0]} | $bd | $best | $ratio |"
    done
done
