#!/usr/bin/env bash
# bench-depth-auto.sh: render.sh --depth auto against every fixed depth 0-4 on the
# fill-heavy scene of scripts/bench.sh (10,000 quads, Dc≈10, 1920×1080) and on two
# polygons: whole-process wall seconds, median of N, in one run, and auto over the best
# fixed depth (the aim: within 10%). Not part of CI.
#
# Usage: scripts/bench-depth-auto.sh [--reps N]
set -euo pipefail
export LC_ALL=C
reps=5
case ${1-} in
    --reps) reps=${2:?--reps needs N} ;;
    -h | --help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    '') ;;
    *) echo "bench-depth-auto.sh: unknown argument $1" >&2; exit 2 ;;
esac
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
B=${CARGO_TARGET_DIR:-$root/target}/release
cargo build --release --quiet --bins
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$B/scene" environment --text --seed 2 --polygons 10000 --depth-complexity 10 --size 1920x1080 > "$work/fill.txt"

seconds() {
    local t0=$EPOCHREALTIME
    "$@" > /dev/null 2>&1
    awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.6f\n", b - a }'
}
median() { sort -g | awk '{ t[NR] = $1 } END { printf "%.3f", NR % 2 ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2 }'; }

table() { # SCENE SIZE LABEL
    local scene=$1 size=$2 label=$3 d best= bestd= auto choice
    declare -A t
    for d in 0 1 2 3 4 auto; do
        t[$d]=$(for ((r = 0; r < reps; r++)); do
            seconds scripts/render.sh --size "$size" --depth "$d" "$scene"
        done | median)
    done
    for d in 0 1 2 3 4; do
        if [[ -z $best ]] || awk -v a="${t[$d]}" -v b="$best" 'BEGIN { exit !(a < b) }'; then
            best=${t[$d]} bestd=$d
        fi
    done
    choice=$(scripts/render.sh --size "$size" --depth auto --stats "$scene" 2>&1 >/dev/null |
        sed -n 's/^render.sh: depth auto chose //p')
    auto=$(awk -v a="${t[auto]}" -v b="$best" 'BEGIN { printf "%.2f", a / b }')
    echo "| $label | ${t[0]} | ${t[1]} | ${t[2]} | ${t[3]} | ${t[4]} | $bestd | ${t[auto]} | **$auto** | ${choice%% (*} |"
}

echo
echo "Measured by \`scripts/bench-depth-auto.sh\` at commit $(git rev-parse --short HEAD)," \
    "$(nproc) cores, $(date -u +%Y-%m-%d): render.sh wall seconds, median of $reps, one run."
echo
echo "| scene | depth 0 | 1 | 2 | 3 | 4 | best | auto | auto / best | auto chose |"
echo "|---|---|---|---|---|---|---|---|---|---|"
table "$work/fill.txt" 1920x1080 "10,000 quads, Dc≈10, 1920×1080"
table examples/penetrating.txt 500x500 "2 polygons, 500×500"
