#!/usr/bin/env bash
# bench-plan.sh: the cost model's checks on this machine (docs/model.md, "The model against
# this machine"), on the fill-heavy scene of scripts/bench.sh (10,000 quads, Dc≈10,
# 1920×1080), in one run:
#   1. render.sh --depth auto against fixed depths 0-3, interleaved (every round runs each
#      once, in turn), median of N rounds, and auto over the best;
#   2. the model's 1-core and 2-core predictions (`plan predict --cores C`) against
#      `taskset -c 0` and `taskset -c 0,1` measurements of depths 0-2, median of N;
#   3. the tree's per-level work: the polygons each level's splitters read (render.sh
#      --stats) against the model's (every polygon at the root, P_r/2^l below);
#   4. a live source: the first frame's delay from being written to coming out of
#      `render.sh -` (a frame, then the source waits a second).
# Prints markdown tables. Not part of CI. The machine's load is printed with them.
#
# Usage: scripts/bench-plan.sh [--reps N]
set -euo pipefail
export LC_ALL=C
reps=5
case ${1-} in
    --reps) reps=${2:?--reps needs N} ;;
    -h | --help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    '') ;;
    *) echo "bench-plan.sh: unknown argument $1" >&2; exit 2 ;;
esac
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
B=${CARGO_TARGET_DIR:-$root/target}/release
[[ $B == /* ]] || B=$root/$B
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
size=1920x1080
scene=$work/fill.txt
"$B/scene" environment --text --seed 2 --polygons 10000 --depth-complexity 10 --size $size > "$scene"
scripts/render.sh --depth 0 --size $size "$scene" > /dev/null # binaries current

seconds() {
    local t0=$EPOCHREALTIME
    "$@" > /dev/null 2>&1
    awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.6f\n", b - a }'
}
median() { sort -g | awk '{ t[NR] = $1 } END { printf "%.3f", NR % 2 ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2 }'; }

echo
echo "Measured by \`scripts/bench-plan.sh\` at commit $(git rev-parse --short HEAD), $(nproc) cores" \
    "($(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')), $(date -u '+%Y-%m-%d %H:%M') UTC," \
    "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $("$B/plan" status | head -1)."

# 1. auto against fixed depths, interleaved.
declare -A times
depths=(auto 0 1 2 3)
for ((r = 0; r < reps; r++)); do
    for ((i = 0; i < ${#depths[@]}; i++)); do
        d=${depths[(i + r) % ${#depths[@]}]}
        times[$d]+="$(seconds scripts/render.sh --size $size --depth "$d" "$scene") "
    done
done
declare -A med
best= bestd=
for d in "${depths[@]}"; do
    med[$d]=$(tr ' ' '\n' <<<"${times[$d]}" | grep . | median)
    if [[ $d != auto ]] && { [[ -z $best ]] || awk -v a="${med[$d]}" -v b="$best" 'BEGIN { exit !(a < b) }'; }; then
        best=${med[$d]} bestd=$d
    fi
done
choice=$(scripts/render.sh --size $size --depth auto --stats "$scene" 2>&1 >/dev/null |
    sed -n 's/^render.sh: depth auto chose //p')
echo
echo "| fill scene, wall s, median of $reps interleaved | depth 0 | 1 | 2 | 3 | best | auto | auto / best | auto chose |"
echo "|---|---|---|---|---|---|---|---|---|"
echo "| render.sh | ${med[0]} | ${med[1]} | ${med[2]} | ${med[3]} | $bestd | ${med[auto]} | **$(awk -v a="${med[auto]}" -v b="$best" 'BEGIN { printf "%.2f", a / b }')** | ${choice%% (*} |"
echo
echo "auto's line: $choice"

# 2. 1 and 2 cores: the model against taskset.
echo
echo "| cores | depth | predicted s | measured s (taskset) | error |"
echo "|---|---|---|---|---|"
for cpus in 0 0,1; do
    cores=$(tr ',' '\n' <<<"$cpus" | wc -l)
    for d in 0 1 2; do
        predicted=$("$B/plan" predict --size $size --cores "$cores" --max-depth 2 "$scene" |
            awk -F'|' -v d="$d" '$2 ~ "^ "d"( |$)" { gsub(/ /, "", $3); print $3 }')
        measured=$(for ((r = 0; r < reps; r++)); do
            seconds taskset -c "$cpus" scripts/render.sh --size $size --depth "$d" "$scene"
        done | median)
        echo "| $cores | $d | $predicted | $measured | $(awk -v p="$predicted" -v m="$measured" 'BEGIN { printf "%+.0f%%", (p - m) / m * 100 }') |"
    done
done

# 3. The tree's per-level work at depth 3: the polygons in view each node of a level reads
# (its parent's output to it, split polygons counted on both sides; the root reads every
# polygon of the scene, those the clipper emptied as skips), against the model's P_r/2^l.
echo
echo "| level | nodes | polygons in view read, all nodes (measured) | largest node | model, each node |"
echo "|---|---|---|---|---|"
stats=$(scripts/render.sh --size $size --depth 3 --stats "$scene" 2>&1 >/dev/null)
relevant=$("$B/plan" predict --size $size --max-depth 0 "$scene" | sed -n 's/^\([0-9]*\) polygons in view of \([0-9]*\).*/\1 \2/p')
read -r pr pt <<<"$relevant"
for level in 1 2 3; do
    first=$((1 << level)) last=$(((2 << level) - 1))
    sum=0 most=0
    for ((node = first; node <= last; node++)); do
        parent=$((node / 2)) side=$((node % 2 + 1))
        n=$(sed -n "s/.*(node $parent): [0-9]* polygons in; out1 \([0-9]*\) polygons, [0-9]* vertices; out2 \([0-9]*\) polygons.*/\1 \2/p" <<<"$stats" |
            awk -v k="$side" '{ print $k }')
        sum=$((sum + n))
        ((n > most)) && most=$n
    done
    echo "| $level | $((1 << level)) | $sum | $most | $((pr >> level)) |"
done
echo "(the root reads all $pt polygons of the scene; $pr of them are in view)"

# 4. A live source: the first frame out after it was written.
frame_bytes=$((15 + 320 * 240 * 3))
body=$(sed '/^END/d' examples/penetrating.txt)
mkfifo "$work/in"
{
    scripts/render.sh --size 320x240 - < "$work/in" |
        { head -c $frame_bytes > /dev/null; echo "$EPOCHREALTIME" > "$work/out"; cat > /dev/null; }
} &
exec 4> "$work/in"
sleep 0.5
printf '%s\nNEXT.FRAME\n' "$body" >&4
t0=$EPOCHREALTIME
sleep 1
printf '%s\nEND\n' "$(sed 1d <<<"$body")" >&4
exec 4>&-
wait
echo
echo "live source: the first frame came out $(awk -v a="$t0" -v b="$(cat "$work/out")" 'BEGIN { printf "%.3f", b - a }') s after it was written (the source then waited 1 s)"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
