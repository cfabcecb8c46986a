#!/usr/bin/env bash
# bench-adaptive.sh: what adaptive supersampling saves: `render --aa ssK` against
# `render --aa adaptiveK` (docs/antialiasing.md, "Adaptive supersampling"), the whole
# pipeline and the supersample leaf alone, in interleaved rounds.
#
# Usage: scripts/bench-adaptive.sh [--quick] [--reps N] [K [POLYGONS [WxH]]]
#   K          samples a side, 2, 4, 8 or 16 (default 4)
#   POLYGONS   the environment's polygons (default 1024)
#   WxH        the screen (default 500x500)
#   --quick    one round: a check that it works
#   --reps N   rounds (default 11)
#
# The scene is `scene environment --polygons N --size WxH --seed 1` (thesis chapter 5.2:
# half the quads outside the view, depth complexity 1) in a file. Each round runs, one
# after the other, render at depth 0 with --aa ssK and --aa adaptiveK, then the leaf
# alone on the screen-space stream (`supersample --samples K`, then with --adaptive), so
# that a change in load falls on both alike. CPU seconds (user + system, the processes' own and their
# children's) are the medians of the rounds; the machine's other work shows in wall time,
# not in these. Run it on one core to compare as CI's machine would:
# `taskset -c 0 scripts/bench-adaptive.sh`.
set -euo pipefail
export LC_ALL=C
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

quick=0 reps=''
bench_options "$@"
((${#args[@]} <= 3)) || bench_usage "K, POLYGONS and WxH at most, not '${args[*]}'"
k=${args[0]:-4} n=${args[1]:-1024} size=${args[2]:-500x500}
[[ $k =~ ^(2|4|8|16)$ ]] || bench_usage "K must be 2, 4, 8 or 16, not '$k'"
[[ $n =~ ^[1-9][0-9]*$ ]] || bench_usage "POLYGONS must be a whole number above 0, not '$n'"
[[ $size =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || bench_usage "the size must be WxH, not '$size'"
reps=${reps:-$((quick ? 1 : 11))}
bench_build
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-adaptive.XXXXXX")
trap 'rm -rf "$work"' EXIT

"$bindir/scene" environment --polygons "$n" --size "$size" --seed 1 >"$work/world"
to_screen "$size" <"$work/world" >"$work/screen"
"$bindir/render" --size "$size" --depth 0 --aa "ss$k" "$work/world" >"$work/ss.ppm"
"$bindir/render" --size "$size" --depth 0 --aa "adaptive$k" "$work/world" >"$work/adaptive.ppm"
same=$(differing "$work/ss.ppm" "$work/adaptive.ppm")
stats=$("$bindir/supersample" --samples "$k" --adaptive --stats <"$work/screen" 2>&1 >/dev/null)

declare -A cpu=()
for ((i = 0; i < reps; i++)); do
    cpu[render_ss]+=$(cpu_seconds "$bindir/render" --size "$size" --depth 0 --aa "ss$k" "$work/world")$'\n'
    cpu[render_adaptive]+=$(cpu_seconds "$bindir/render" --size "$size" --depth 0 --aa "adaptive$k" "$work/world")$'\n'
    cpu[leaf_ss]+=$(cpu_seconds reading "$work/screen" "$bindir/supersample" --samples "$k")$'\n'
    cpu[leaf_adaptive]+=$(cpu_seconds reading "$work/screen" "$bindir/supersample" --samples "$k" --adaptive)$'\n'
done
med() { printf '%s' "${cpu[$1]}" | median; }

echo "$(bench_stamp): \`scene environment --polygons $n --size $size --seed 1\`;" \
    "CPU seconds, median of $reps interleaved rounds."
echo
echo "adaptive$k's frame against ss$k's: $same pixels differ;" \
    "$(stat_count "$stats" "sampled") of $(stat_count "$stats" "pixels out") pixels sampled."
echo
echo "| what | ss$k CPU s | adaptive$k CPU s | ratio |"
echo "|---|---|---|---|"
for what in render leaf; do
    a=$(med "${what}_ss") b=$(med "${what}_adaptive")
    echo "| $what | $a | $b | $(ratio "$b" "$a") |"
done
