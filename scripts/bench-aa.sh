#!/usr/bin/env bash
# bench-aa.sh: what anti-aliasing costs at a leaf: each anti-aliasing leaf of render.sh
# (--aa: point sampling, supersampling 2x2 to 16x16, the a-buffer; docs/antialiasing.md)
# alone on one screen-space frame, its time, memory and output.
#
# Usage: scripts/bench-aa.sh [--quick] [--reps N] [POLYGONS [WxH]]
#   POLYGONS   the scene's polygons (default 100000)
#   WxH        the screen (default 1920x1080)
#   --quick    5,000 polygons at 480x270, one run each: a check that it works
#   --reps N   runs of each command (default 3)
#
# The scene is `scene environment` (thesis chapter 5.2) through viewxf, clipbatch and
# persp into a file, once; each leaf then reads that file, so that only the leaf is
# timed. Wall and CPU seconds are the medians of N runs each, peak resident KiB that of
# one more run, and the output bytes what the leaf sends to the merger.
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

quick=0 reps=''
bench_options "$@"
((${#args[@]} <= 2)) || bench_usage "POLYGONS and WxH at most, not '${args[*]}'"
if ((quick)); then n=5000 size=480x270; else n=100000 size=1920x1080; fi
n=${args[0]:-$n} size=${args[1]:-$size}
[[ $n =~ ^[1-9][0-9]*$ ]] || bench_usage "POLYGONS must be a whole number above 0, not '$n'"
[[ $size =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || bench_usage "the size must be WxH, not '$size'"
reps=${reps:-$((quick ? 1 : 3))}
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-aa.XXXXXX")
trap 'rm -rf "$work"' EXIT

screen=$work/screen
"$bindir/scene" environment --polygons "$n" --size "$size" --seed 1 | to_screen "$size" >"$screen"
polygons=$(stat_count "$("$bindir/scanconv" --stats <"$screen" 2>&1 >/dev/null)" "polygons in")

echo "$(bench_stamp): \`scene environment --polygons $n --size $size --seed 1\`, $polygons" \
    "polygons into one leaf (depth 0); wall and CPU seconds the median of $reps."
echo
echo "| method | leaf | wall s | CPU s | peak KiB | output bytes |"
echo "|---|---|---|---|---|---|"
cmd=()
mapfile -t methods < <(methods_list aa)
for method in "${methods[@]}"; do
    IFS=$'\t' read -r name leaf <<<"$method"
    echo "$bench_me: $name" >&2
    leaf_words cmd "$leaf"
    walls='' cpus=''
    for ((i = 0; i < reps; i++)); do
        walls+=$(seconds reading "$screen" "${cmd[@]}")$'\n'
        cpus+=$(cpu_seconds reading "$screen" "${cmd[@]}")$'\n'
    done
    kib=$(peak_kib "${cmd[@]}" <"$screen")
    "${cmd[@]}" <"$screen" >"$work/out"
    echo "| $name | \`$leaf\` | $(printf '%s' "$walls" | median) | $(printf '%s' "$cpus" | median)" \
        "| $kib | $(stat -c %s "$work/out") |"
done
