#!/usr/bin/env bash
# bench-merge.sh: leaves that see against the thesis's PAR.BUFF.
#
#   1. wall time of render.sh at splitter depths 0..4 with --merge tiles (each leaf
#      resolves its region, zbuf places runs) and --merge buffer (every fragment to one
#      z-buffer), on the fill-heavy scene (10,000 quads, Dc 10, 1920x1080) and the
#      geometry-heavy one (100,000 small polygons, 500x500); best of REPS runs (default
#      5; the machine is shared, and the fastest run is the one least disturbed), whole
#      process, each depth's speed-up over depth 0 of the same mode, and render.sh's own
#      cost at each depth (two polygons at 8x8: the processes, pipes and script)
#   2. the leaves and the merger alone, file to file: CPU seconds and peak resident
#      memory of the largest leaf's scanconv and of zbuf, per depth and mode
#
# Compare figures within one run of the script: the machine is shared.
#
# Usage: scripts/bench-merge.sh [SECTION...]   (sections 1-2; default both)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet --bins
B=$root/target/release
# render.sh rebuilds when any source under a stage's crate (tests included) is newer than
# its binary, and cargo does not relink a binary for a change to its tests: mark the
# binaries just built as current, or every run below would time a cargo build too.
touch "$B"/{viewxf,clipplane,splitter,persp,scanconv,zbuf}
REPS=${REPS:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sections=("$@")
((${#sections[@]})) || sections=(1 2)
want() { [[ " ${sections[*]} " == *" $1 "* ]]; }

"$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 > "$work/fill.pp"
"$B/scene" environment --polygons 100000 --depth-complexity 1 --seed 3 > "$work/geo.pp"

# best CMD: the smallest wall time of REPS runs, in seconds.
best() {
    local i
    for ((i = 0; i < REPS; i++)); do
        /usr/bin/time -f %e -o "$work/time" bash -c "$1" >/dev/null 2>&1
        tail -n 1 "$work/time"
    done | sort -n | head -n 1
}

ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", (b > 0 ? a / b : 0) }'; }

if want 1; then
    echo "## 1. render.sh wall seconds (best of $REPS) and speed-up over depth 0"
    echo
    echo "| depth | fill tiles | fill buffer | geometry tiles | geometry buffer | render.sh alone |"
    echo "|---|---|---|---|---|---|"
    declare -A base=()
    for d in 0 1 2 3 4; do
        row="| $d |"
        for s in fill:1920x1080 geo:500x500; do
            for m in tiles buffer; do
                t=$(best "$root/scripts/render.sh --merge $m --depth $d --size ${s#*:} $work/${s%%:*}.pp")
                [[ -n ${base[$s$m]-} ]] || base[$s$m]=$t
                row+=" $t ($(ratio "${base[$s$m]}" "$t")x) |"
            done
        done
        row+=" $(best "$root/scripts/render.sh --depth $d --size 8x8 $root/examples/penetrating.txt") |"
        echo "$row"
    done
    echo
fi

if want 2; then
    echo "## 2. Leaves and merger alone, file to file, fill-heavy scene (CPU s, best of $REPS; peak KiB)"
    echo
    echo "| depth | mode | slowest leaf scanconv s | largest leaf scanconv KiB | zbuf s | zbuf KiB | bytes to zbuf |"
    echo "|---|---|---|---|---|---|---|"
    source "$root/scripts/tree-planes.sh"
    size=1920x1080
    clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"
    "$B/viewxf" --size $size < "$work/fill.pp" | bash -c "$clip" > "$work/node1"
    # cpu_rss CMD: "seconds KiB", the smallest CPU time (user + system, to the
    # millisecond) of REPS runs, and the peak resident memory of one more.
    cpu_rss() {
        local i best= t
        for ((i = 0; i < REPS; i++)); do
            t=$( { TIMEFORMAT='%3U %3S'; time bash -c "exec $1" >/dev/null 2>&1; } 2>&1 | awk '{ printf "%.3f", $1 + $2 }')
            if [[ -z $best ]] || awk -v a="$t" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$t; fi
        done
        /usr/bin/time -f %M -o "$work/rss" bash -c "exec $1" >/dev/null 2>&1
        echo "$best $(tail -n 1 "$work/rss")"
    }
    for d in 0 1 2 3 4; do
        leaves=$((1 << d))
        tree_planes 1920 1080 "$d"
        for ((node = 1; node < leaves; node++)); do
            "$B/splitter" "${plane_of[$node]}" "$work/node$((2 * node))" "$work/node$((2 * node + 1))" < "$work/node$node"
        done
        for m in tiles buffer; do
            flag=; [[ $m == tiles ]] && flag=--resolve
            slow=0 big=0 frags=() bytes=0
            for ((leaf = leaves; leaf < 2 * leaves; leaf++)); do
                "$B/persp" --size $size < "$work/node$leaf" > "$work/screen$leaf"
                "$B/scanconv" $flag < "$work/screen$leaf" > "$work/frag$leaf"
                read -r s k < <(cpu_rss "$B/scanconv $flag < $work/screen$leaf")
                slow=$(awk -v a="$s" -v b="$slow" 'BEGIN { print (a > b ? a : b) }')
                ((k > big)) && big=$k
                bytes=$((bytes + $(stat -c %s "$work/frag$leaf")))
                frags+=("$work/frag$leaf")
            done
            read -r zs zk < <(cpu_rss "$B/zbuf ${frags[*]}")
            echo "| $d | $m | $slow | $big | $zs | $zk | $bytes |"
        done
        for ((node = 2; node < 2 * leaves; node++)); do rm -f "$work/node$node"; done
        rm -f "$work"/screen* "$work"/frag*
    done
    echo
fi
