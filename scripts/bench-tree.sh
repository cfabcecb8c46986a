#!/usr/bin/env bash
# bench-tree.sh: the splitter tree and its merge measured, one mode a run:
#
#   scripts/bench-tree.sh pipeline [OPTIONS]      the whole pipeline's tables: depths
#                                                 0-4, fragment encodings, accuracy,
#                                                 memory, a processor per process
#   scripts/bench-tree.sh merge [OPTIONS]         leaves that resolve (--merge tiles)
#                                                 against PAR.BUFF (--merge buffer)
#   scripts/bench-tree.sh depth-auto [--reps N]   --depth auto against every fixed depth
#                                                 on 1 and all cores, and render's
#                                                 start-up against the stages by hand
#   scripts/bench-tree.sh plan [--reps N]         the cost model against this machine
#                                                 (docs/model.md)
#   scripts/bench-tree.sh work [MAX-DEPTH]        the instructions each process of the
#                                                 depth-0..N graphs runs (cachegrind):
#                                                 the tree's own work, free of the
#                                                 machine's noise
#   scripts/bench-tree.sh farm [--reps N] [--hosts N,…]
#                                                 a movie by frames over 1, 2, 4 hosts
#                                                 (GNU parallel, a stand-in ssh) beside
#                                                 the cost model's prediction (plan movie)
#
# Each mode's own notes are at its function below. They share scripts/lib/bench.sh.

# The modes are functions of their own (each a subshell), and some reuse a name for an
# array in one and a string in another, which shellcheck reads as one variable.
# shellcheck disable=SC2128,SC2154,SC2178
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

# --- pipeline ------------------------------------------------------------------
mode_pipeline() (
# The whole pipeline measured, printed as tables.
#
#   1. wall time of the linear pipeline (render.sh --depth 0) on 100,000 polygons at 500x500
#   2. wall time for splitter depths 0..4 on a fill-heavy scene (10,000 polygons, depth
#      complexity 10, 1920x1080) and a geometry-heavy one (100,000 small polygons, 500x500)
#   3. scanconv's fragment encodings: spans against the thesis's per-pixel records
#   4. accuracy against the exact reference (zspec) for projective depth and the occam
#      code's eye-z depth, on scenes of tilted, interpenetrating polygons
#   5. peak resident memory of every stage on 10,000 and on 1,000,000 polygons
#   6. what the splitter tree would buy with a processor per process: every process of
#      the depth-0..4 graphs run alone, file to file, and its CPU seconds measured; a
#      streaming pipeline with one processor per process can go no faster than its
#      slowest process (thesis 6.1), so that process's time bounds the wall time
#
# Times are the best of REPS runs (default 3) on whatever else the machine is doing:
# compare the figures within one run of the script, not across machines.
#
# Usage: scripts/bench-tree.sh pipeline [SECTION...]   (sections 1-6; default all)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet --bins
B=$(release_bin "$root")
REPS=${REPS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sections=("$@")
((${#sections[@]})) || sections=(1 2 3 4 5 6)
want() { [[ " ${sections[*]} " == *" $1 "* ]]; }

# wall CMD: the least wall seconds of REPS runs of the shell command CMD, to the ms
# (lib/bench.sh: a failing run fails it).
wall() { local t; t=$(best_of "$REPS" seconds bash -o pipefail -c "$1") && echo "${t%???}"; }

clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"

if want 1; then
    echo "## 1. Linear pipeline, 100,000 polygons, 500x500"
    "$B/scene" environment --polygons 100000 --depth-complexity 10 --seed 1 > "$work/geo.pp"
    t=$(wall "$root/scripts/render.sh $work/geo.pp")
    printf '| scene | wall s |\n|---|---|\n| environment 100000 polygons, Dc 10 | %s |\n\n' "$t"
fi

if want 2; then
    echo "## 2. Splitter depth (wall seconds, best of $REPS)"
    "$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 > "$work/fill.pp"
    "$B/scene" environment --polygons 100000 --depth-complexity 1 --seed 3 > "$work/geo.pp"
    echo "| depth | fill-heavy (10k, Dc 10, 1920x1080) | geometry-heavy (100k small, 500x500) |"
    echo "|---|---|---|"
    for d in 0 1 2 3 4; do
        tf=$(wall "$root/scripts/render.sh --depth $d --size 1920x1080 $work/fill.pp")
        tg=$(wall "$root/scripts/render.sh --depth $d $work/geo.pp")
        echo "| $d | $tf | $tg |"
    done
    echo
    echo "Leaf balance at depth 2 (fill-heavy scene), from --stats:"
    "$root/scripts/render.sh" --depth 2 --size 1920x1080 --stats "$work/fill.pp" 2>&1 >/dev/null \
        | grep -E '^(scanconv|zbuf)' || true
    echo
fi

if want 3; then
    echo "## 3. Fragment encoding: spans against per-pixel records (fill-heavy scene)"
    [[ -f $work/fill.pp ]] || "$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 > "$work/fill.pp"
    "$B/viewxf" --size 1920x1080 < "$work/fill.pp" | bash -c "$clip" | "$B/persp" --size 1920x1080 > "$work/fill.screen"
    echo "| encoding | scanconv bytes | scanconv s | scanconv + zbuf s |"
    echo "|---|---|---|---|"
    for mode in spans pixels; do
        flag=; [[ $mode == pixels ]] && flag=--pixels
        bytes=$("$B/scanconv" $flag < "$work/fill.screen" | wc -c)
        ts=$(wall "$B/scanconv $flag < $work/fill.screen")
        tz=$(wall "$B/scanconv $flag < $work/fill.screen | $B/zbuf")
        echo "| $mode | $bytes | $ts | $tz |"
    done
    echo
fi

if want 4; then
    echo "## 4. Accuracy against the exact reference (pixels that differ from zspec)"
    echo "| scene | pixels | projective depth | eye-z depth (occam) |"
    echo "|---|---|---|---|"
    acc() { # name, scene file, size
        local size=$3 p e
        "$B/zspec" --size "$size" "$2" > "$work/ref.ppm"
        "$root/scripts/render.sh" --size "$size" "$2" > "$work/proj.ppm"
        "$root/scripts/render.sh" --size "$size" --zmode eye-z "$2" > "$work/eyez.ppm"
        p=$("$B/zspec" compare --min-agreement 0 "$work/ref.ppm" "$work/proj.ppm" | awk '{ px += $3; d += $5 } END { print d }')
        e=$("$B/zspec" compare --min-agreement 0 "$work/ref.ppm" "$work/eyez.ppm" | awk '{ px += $3; d += $5 } END { print d }')
        local total
        total=$("$B/zspec" compare --min-agreement 0 "$work/ref.ppm" "$work/ref.ppm" | awk '{ px += $3 } END { print px }')
        echo "| $1 | $total | $p | $e |"
    }
    "$B/scene" penetrating > "$work/pen.pp"
    acc "penetrating" "$work/pen.pp" 500x500
    "$B/scene" spheres > "$work/spheres.pp"
    acc "spheres" "$work/spheres.pp" 500x500
    "$B/scene" triangle-square > "$work/ts.pp"
    acc "triangle-square" "$work/ts.pp" 500x500
    "$B/scene" environment --polygons 1000 --depth-complexity 3 --seed 4 > "$work/tilt.pp"
    acc "environment 1000, Dc 3" "$work/tilt.pp" 500x500
    "$B/scene" environment --polygons 100000 --depth-complexity 10 --seed 5 > "$work/tilt.pp"
    acc "environment 100000, Dc 10" "$work/tilt.pp" 500x500
    echo
fi

if want 5; then
    echo "## 5. Peak resident memory (KiB) by number of polygons"
    echo "| stage | 10,000 polygons | 1,000,000 polygons |"
    echo "|---|---|---|"
    for n in 10000 1000000; do
        "$B/scene" environment --polygons "$n" --depth-complexity 1 --clipped 0.2 --seed 6 > "$work/w$n"
        "$B/viewxf" < "$work/w$n" > "$work/e$n"
        bash -c "$clip" < "$work/e$n" > "$work/c$n"
        "$B/persp" --size 500x500 < "$work/c$n" > "$work/s$n"
        "$B/scanconv" < "$work/s$n" > "$work/f$n"
    done
    rss() { /usr/bin/time -f %M -o "$work/rss" bash -c "exec $1 > /dev/null" && tail -n 1 "$work/rss"; }
    row() { echo "| $1 | $(rss "${2//N/10000}") | $(rss "${2//N/1000000}") |"; }
    row scene "$B/scene environment --polygons N --depth-complexity 1 --clipped 0.2 --seed 6"
    row viewxf "$B/viewxf < $work/wN"
    row "clipplane left" "$B/clipplane left < $work/eN"
    row "splitter x=0" "$B/splitter x=0 - /dev/null < $work/cN"
    row persp "$B/persp --size 500x500 < $work/cN"
    row scanconv "$B/scanconv < $work/sN"
    row zbuf "$B/zbuf < $work/fN"
    row zspec "$B/zspec $work/wN"
    echo
fi

if want 6; then
    echo "## 6. What the tree would buy with one processor per process (CPU seconds, best of $REPS)"
    echo
    echo "Each process of render.sh's graph run alone, file to file (no pipes). On one processor"
    echo "the wall time is at least the sum; with one processor per process, streaming, at least"
    echo "the slowest process's time."
    echo
    # cpu CMD: the least user + system seconds of REPS runs of a shell command.
    cpu() { best_of "$REPS" cpu_seconds bash -o pipefail -c "$1"; }
    # tree_cost NAME SCENE SIZE: one table row per depth.
    tree_cost() {
        local name=$1 scene=$2 size=$3 d t prev total slowest slowest_name base=
        local -a chain_names=() chain_times=()
        "$B/viewxf" --size "$size" < "$scene" > "$work/t.view"
        chain_names+=(viewxf) chain_times+=("$(cpu "$B/viewxf --size $size < $scene")")
        prev=$work/t.view
        for plane in left right top bottom hither yon; do
            "$B/clipplane" "$plane" < "$prev" > "$work/t.$plane"
            chain_names+=("clipplane $plane")
            chain_times+=("$(cpu "$B/clipplane $plane < $prev")")
            prev=$work/t.$plane
        done
        echo "$name:"
        echo
        echo "| depth | processes | sum of CPU s | slowest upstream (viewxf, clippers, splitters) | slowest leaf (persp, scanconv) | zbuf | slowest of all | bound on speedup over depth 0 |"
        echo "|---|---|---|---|---|---|---|---|"
        for d in 0 1 2 3 4; do
            local -a names=("${chain_names[@]}") times=("${chain_times[@]}") fragments=()
            local leaves=$((1 << d)) node leaf
            cp "$work/t.yon" "$work/t.node1"
            for ((node = 1; node < leaves; node++)); do
                # The node works out its own plane, as in render.sh's tree.
                local -a tree=(--node "$node" --depth "$d" --size "$size")
                "$B/splitter" "${tree[@]}" "$work/t.node$((2 * node))" "$work/t.node$((2 * node + 1))" < "$work/t.node$node"
                names+=("splitter node $node")
                times+=("$(cpu "$B/splitter ${tree[*]} /dev/null /dev/null < $work/t.node$node")")
            done
            for ((leaf = leaves; leaf < 2 * leaves; leaf++)); do
                "$B/persp" --size "$size" < "$work/t.node$leaf" > "$work/t.screen$leaf"
                "$B/scanconv" < "$work/t.screen$leaf" > "$work/t.frag$leaf"
                names+=("persp leaf $((leaf - leaves))" "scanconv leaf $((leaf - leaves))")
                times+=("$(cpu "$B/persp --size $size < $work/t.node$leaf")")
                times+=("$(cpu "$B/scanconv < $work/t.screen$leaf")")
                fragments+=("$work/t.frag$leaf")
            done
            names+=(zbuf)
            times+=("$(cpu "$B/zbuf ${fragments[*]}")")
            # The slowest process of each group: upstream of the leaves, the leaves, zbuf.
            total=0 slowest=0 slowest_name=
            local -A group_time=([upstream]=0 [leaf]=0 [zbuf]=0) group_name=()
            local group
            for i in "${!times[@]}"; do
                total=$(awk -v a="$total" -v b="${times[$i]}" 'BEGIN { print a + b }')
                case ${names[$i]} in
                    *leaf*) group=leaf ;;
                    zbuf) group=zbuf ;;
                    *) group=upstream ;;
                esac
                if awk -v a="${times[$i]}" -v b="${group_time[$group]}" 'BEGIN { exit !(a > b) }'; then
                    group_time[$group]=${times[$i]} group_name[$group]=${names[$i]}
                fi
                if awk -v a="${times[$i]}" -v b="$slowest" 'BEGIN { exit !(a > b) }'; then
                    slowest=${times[$i]} slowest_name=${names[$i]}
                fi
            done
            [[ -n $base ]] || base=$slowest
            printf '| %s | %s | %.3f | %s %.3f | %s %.3f | %.3f | %s | %s |\n' "$d" "${#times[@]}" "$total" \
                "${group_name[upstream]}" "${group_time[upstream]}" \
                "${group_name[leaf]}" "${group_time[leaf]}" "${group_time[zbuf]}" "$slowest_name" \
                "$(awk -v a="$base" -v b="$slowest" 'BEGIN { printf "%.2f", a / b }')"
            rm -f "$work"/t.node[0-9]* "$work"/t.screen* "$work"/t.frag*
        done
        echo
    }
    [[ -f $work/fill.pp ]] || "$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 > "$work/fill.pp"
    [[ -f $work/geo.pp ]] || "$B/scene" environment --polygons 100000 --depth-complexity 1 --seed 3 > "$work/geo.pp"
    tree_cost "Fill-heavy (10,000 polygons, Dc 10, 1920x1080)" "$work/fill.pp" 1920x1080
    tree_cost "Geometry-heavy (100,000 small polygons, 500x500)" "$work/geo.pp" 500x500
fi
)

# --- merge ---------------------------------------------------------------------
mode_merge() (
# Leaves that see against the thesis's PAR.BUFF.
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
# Usage: scripts/bench-tree.sh merge [SECTION...]   (sections 1-2; default both)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet --bins
B=$(release_bin "$root")
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

# wall CMD: the least wall seconds of REPS runs of the shell command CMD, to the ms
# (lib/bench.sh: a failing run fails it).
wall() { local t; t=$(best_of "$REPS" seconds bash -o pipefail -c "$1") && echo "${t%???}"; }


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
                t=$(wall "$root/scripts/render.sh --merge $m --depth $d --size ${s#*:} $work/${s%%:*}.pp")
                [[ -n ${base[$s$m]-} ]] || base[$s$m]=$t
                row+=" $t ($(ratio "${base[$s$m]}" "$t")x) |"
            done
        done
        row+=" $(wall "$root/scripts/render.sh --depth $d --size 8x8 $root/examples/penetrating.txt") |"
        echo "$row"
    done
    echo
fi

if want 2; then
    echo "## 2. Leaves and merger alone, file to file, fill-heavy scene (CPU s, best of $REPS; peak KiB)"
    echo
    echo "| depth | mode | slowest leaf scanconv s | largest leaf scanconv KiB | zbuf s | zbuf KiB | bytes to zbuf |"
    echo "|---|---|---|---|---|---|---|"
    size=1920x1080
    clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"
    "$B/viewxf" --size $size < "$work/fill.pp" | bash -c "$clip" > "$work/node1"
    # cpu_rss CMD: "seconds KiB", the smallest CPU time (user + system, to the
    # millisecond) of REPS runs, and the peak resident memory of one more.
    cpu_rss() {
        local t k
        t=$(best_of "$REPS" cpu_seconds bash -c "exec $1") && k=$(peak_kib bash -c "exec $1") &&
            echo "$t $k"
    }
    for d in 0 1 2 3 4; do
        leaves=$((1 << d))
        for ((node = 1; node < leaves; node++)); do
            "$B/splitter" --node "$node" --depth "$d" --size $size "$work/node$((2 * node))" \
                "$work/node$((2 * node + 1))" < "$work/node$node"
        done
        for m in tiles buffer; do
            flag=; [[ $m == tiles ]] && flag=--resolve
            slow=0 big=0 frags=() bytes=0
            for ((leaf = leaves; leaf < 2 * leaves; leaf++)); do
                "$B/persp" --size $size < "$work/node$leaf" > "$work/screen$leaf"
                "$B/scanconv" $flag < "$work/screen$leaf" > "$work/frag$leaf"
                sk=$(cpu_rss "$B/scanconv $flag < $work/screen$leaf")
                read -r s k <<<"$sk"
                slow=$(awk -v a="$s" -v b="$slow" 'BEGIN { print (a > b ? a : b) }')
                ((k > big)) && big=$k
                bytes=$((bytes + $(stat -c %s "$work/frag$leaf")))
                frags+=("$work/frag$leaf")
            done
            zsk=$(cpu_rss "$B/zbuf ${frags[*]}")
            read -r zs zk <<<"$zsk"
            echo "| $d | $m | $slow | $big | $zs | $zk | $bytes |"
        done
        for ((node = 2; node < 2 * leaves; node++)); do rm -f "$work/node$node"; done
        rm -f "$work"/screen* "$work"/frag*
    done
    echo
fi
)

# --- depth-auto ---------------------------------------------------------------------
mode_depth_auto() (
# render --depth auto against every fixed depth 0-3 on the fill-heavy scene of
# scripts/bench.sh (10,000 quads, Dc≈10, 1920×1080), on one core (`taskset -c 0`) and on
# all of them, and render's start-up against the four stages composed by hand (two
# polygons at 64×64, examples/triangle-square.txt: `viewxf | clipbatch | persp | zbuf`,
# the pipe line run by this shell as render is). One run: every round runs every
# command once, in turn, so that a change in the machine's load falls on all of them;
# wall seconds (bash's microsecond clock) and CPU seconds (user + system of the whole
# process tree), medians of N rounds. The goals: auto within 5% of the best fixed depth
# on each core count, render's start-up within 15% of the stages by hand. POLYPIPE_LOAD
# is unset: auto plans for the load it finds. The load before and after, the model's
# constants, and what auto chose and predicted are printed with the tables. Not part of
# CI.
#
# Usage: scripts/bench-tree.sh depth-auto [--reps N]   (default 7)
set -euo pipefail
export LC_ALL=C
unset POLYPIPE_LOAD
reps=7
case ${1-} in
    --reps) reps=${2:?--reps needs N} ;;
    -h | --help) sed -n '/^mode_depth_auto/,/^# Usage/p' "${BASH_SOURCE[0]}" | sed '1d; s/^# \{0,1\}//'; exit 0 ;;
    '') ;;
    *) echo "bench-tree.sh depth-auto: unknown argument $1" >&2; exit 2 ;;
esac
[[ $reps =~ ^[1-9][0-9]*$ ]] || { echo "bench-tree.sh depth-auto: --reps needs a count, not '$reps'" >&2; exit 2; }
bench_build
B=$bindir
cd "$bench_root"
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-auto.XXXXXX")
trap 'rm -rf "$work"' EXIT
size=1920x1080
fill_scene "$B" 10000 "$size" > "$work/fill.txt"
two=examples/triangle-square.txt
last=$(($(nproc) - 1))
cores=(0 "0-$last")
depths=(0 1 2 3 auto)
load() { echo "load average $(cut -d' ' -f1-3 /proc/loadavg), runnable now $(cut -d' ' -f4 /proc/loadavg)"; }

# The commands, by name, each a function (so that the hand pipe line is timed as this
# shell runs it).
declare -A wall cpu
names=()
for c in "${cores[@]}"; do
    for d in "${depths[@]}"; do names+=("fill $c $d"); done
done
names+=("start render" "start hand")
run_one() { # NAME
    local c d
    case $1 in
        fill\ *)
            read -r _ c d <<<"$1"
            taskset -c "$c" "$B/render" --size "$size" --depth "$d" "$work/fill.txt" ;;
        "start render") "$B/render" --size 64x64 "$two" ;;
        "start hand") "$B/viewxf" --size 64x64 <"$two" | "$B/clipbatch" | "$B/persp" --size 64x64 | "$B/zbuf" ;;
    esac
}
# Every command once, its frames checked: every depth's the same bytes as depth 0's.
for n in "${names[@]}"; do run_one "$n" >"$work/out.${n// /_}"; done
for c in "${cores[@]}"; do
    for d in "${depths[@]}"; do
        cmp -s "$work/out.fill_${c}_$d" "$work/out.fill_0_0" ||
            { echo "bench-tree.sh depth-auto: depth $d on cores $c drew other bytes" >&2; exit 1; }
    done
done
cmp -s "$work/out.start_render" "$work/out.start_hand" ||
    { echo "bench-tree.sh depth-auto: render and the stages by hand drew other bytes" >&2; exit 1; }

before=$(load)
TIMEFORMAT='%3U %3S'
for ((r = 0; r < reps; r++)); do
    for ((i = 0; i < ${#names[@]}; i++)); do
        n=${names[(i + r) % ${#names[@]}]}
        t0=$EPOCHREALTIME
        { time run_one "$n" >/dev/null; } 2>"$work/time"
        t1=$EPOCHREALTIME
        wall[$n]+="$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.6f", b - a }') "
        cpu[$n]+="$(awk '{ printf "%.3f", $1 + $2 }' "$work/time") "
    done
done
after=$(load)
med() { tr ' ' '\n' <<<"$1" | grep . | median; }

echo
echo "Measured by \`scripts/bench-tree.sh depth-auto --reps $reps\` at commit $(git rev-parse --short HEAD)," \
    "$(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')), $(date -u '+%Y-%m-%d %H:%M') UTC;" \
    "before: $before; after: $after; POLYPIPE_LOAD unset; constants: $("$B/plan" status | head -1)."
echo
echo "| fill scene, cores | | depth 0 | 1 | 2 | 3 | auto | best | auto / best | auto chose |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for c in "${cores[@]}"; do
    best='' bestd=''
    declare -A m=() k=()
    for d in "${depths[@]}"; do
        m[$d]=$(med "${wall[fill $c $d]}")
        k[$d]=$(med "${cpu[fill $c $d]}")
        if [[ $d != auto ]] && { [[ -z $best ]] || awk -v a="${m[$d]}" -v b="$best" 'BEGIN { exit !(a < b) }'; }; then
            best=${m[$d]} bestd=$d
        fi
    done
    chose=$(taskset -c "$c" "$B/render" --size "$size" --stats "$work/fill.txt" 2>&1 >/dev/null |
        sed -n 's/^render: depth auto chose //p')
    echo "| \`taskset -c $c\` | wall s | ${m[0]} | ${m[1]} | ${m[2]} | ${m[3]} | ${m[auto]} | $bestd | **$(ratio "${m[auto]}" "$best")** | ${chose%% (*} |"
    echo "| | CPU s | ${k[0]} | ${k[1]} | ${k[2]} | ${k[3]} | ${k[auto]} | | | |"
    lines+=("cores $c: depth auto chose $chose")
done
echo
printf '%s\n' "${lines[@]}"
echo
r=$(med "${wall[start render]}") h=$(med "${wall[start hand]}")
rc=$(med "${cpu[start render]}") hc=$(med "${cpu[start hand]}")
echo "| two polygons, 64×64 | render | viewxf \| clipbatch \| persp \| zbuf | render / by hand |"
echo "|---|---|---|---|"
echo "| wall s | $r | $h | **$(ratio "$r" "$h")** |"
echo "| CPU s | $rc | $hc | $(ratio "$rc" "$hc") |"
)

# --- plan (the cost model's checks) ---------------------------------------------------
mode_plan() (
# The cost model's checks on this machine (docs/model.md, "The model against
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
# Usage: scripts/bench-tree.sh plan [--reps N]
set -euo pipefail
export LC_ALL=C
reps=5
case ${1-} in
    --reps) reps=${2:?--reps needs N} ;;
    -h | --help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    '') ;;
    *) echo "bench-tree.sh plan: unknown argument $1" >&2; exit 2 ;;
esac
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
bench_build
B=$bindir
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
size=1920x1080
scene=$work/fill.txt
fill_scene "$B" 10000 "$size" > "$scene"
scripts/render.sh --depth 0 --size $size "$scene" > /dev/null # binaries current

echo
echo "Measured by \`scripts/bench-tree.sh plan\` at commit $(git rev-parse --short HEAD), $(nproc) cores" \
    "($(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')), $(date -u '+%Y-%m-%d %H:%M') UTC," \
    "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $("$B/plan" status | head -1)."

# 1. auto against fixed depths, interleaved.
declare -A plan_times
depths=(auto 0 1 2 3)
for ((r = 0; r < reps; r++)); do
    for ((i = 0; i < ${#depths[@]}; i++)); do
        d=${depths[(i + r) % ${#depths[@]}]}
        plan_times[$d]+="$(seconds scripts/render.sh --size $size --depth "$d" "$scene") "
    done
done
declare -A med
best='' bestd=''
for d in "${depths[@]}"; do
    med[$d]=$(tr ' ' '\n' <<<"${plan_times[$d]}" | grep . | median)
    if [[ $d != auto ]] && { [[ -z $best ]] || awk -v a="${med[$d]}" -v b="$best" 'BEGIN { exit !(a < b) }'; }; then
        best=${med[$d]} bestd=$d
    fi
done
choice=$(scripts/render.sh --size $size --depth auto --stats "$scene" 2>&1 >/dev/null |
    sed -n 's/^render: depth auto chose //p')
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
)

# --- work ------------------------------------------------------------------------
mode_work() (
# The work the tree adds, counted rather than timed: render.sh --depth D on the
# fill-heavy scene (10,000 quads, depth complexity 10, 1920x1080) run under valgrind's
# cachegrind with its children traced, and the user-space instructions of every process
# summed by program (bash counts the script and its forks before they exec a stage).
# A count is the same from run to run on any load, where CPU seconds on a shared machine
# move by a fifth; what it leaves out is the kernel's part (starting and ending
# processes, faulting memory in, moving bytes through pipes) and the caches', which the
# CPU seconds of scripts/bench.sh's one-core table hold. The two together say how much of
# the tree's cost is its stages' work and how much is processes. Takes a few minutes.
#
#   scripts/bench-tree.sh work [MAX-DEPTH]        depths 0..MAX-DEPTH (default 2)
#
# Needs valgrind.
set -euo pipefail
max=${1:-2}
[[ $max =~ ^[0-6]$ ]] || { echo "bench-tree.sh work: MAX-DEPTH must be 0 to 6, not '$max'" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "bench-tree.sh work: needs valgrind (apt install valgrind)" >&2; exit 3; }
bench_build
cd "$bench_root"
work=$(mktemp -d "${TMPDIR:-/tmp}/bench-work.XXXXXX")
trap 'rm -rf "$work"' EXIT
fill_scene "$bindir" > "$work/fill.txt"
# Once outside valgrind: the binaries' freshness stamp written, the pictures to compare.
scripts/render.sh --size 1920x1080 --depth 0 "$work/fill.txt" > "$work/depth0.ppm"
declare -A count
programs=()
for ((d = 0; d <= max; d++)); do
    mkdir "$work/d$d"
    valgrind --trace-children=yes --tool=cachegrind --cache-sim=no \
        --cachegrind-out-file="$work/d$d/%p" \
        scripts/render.sh --size 1920x1080 --depth "$d" "$work/fill.txt" \
        > "$work/out$d.ppm" 2> "$work/log$d" ||
        { echo "bench-tree.sh work: depth $d failed under valgrind:" >&2; tail -5 "$work/log$d" >&2; exit 1; }
    cmp -s "$work/out$d.ppm" "$work/depth0.ppm" ||
        { echo "bench-tree.sh work: depth $d's frame differs from depth 0's" >&2; exit 1; }
    for f in "$work/d$d"/*; do
        program=$(sed -n 's/^cmd: *\([^ ]*\).*/\1/p' "$f")
        program=${program##*/}
        n=$(sed -n 's/^summary: *//p' "$f")
        [[ -n ${count[$program]+set} ]] || programs+=("$program")
        count[$program]=1
        count[$program.$d]=$(( ${count[$program.$d]:-0} + n ))
        count[processes.$program.$d]=$(( ${count[processes.$program.$d]:-0} + 1 ))
        count[total.$d]=$(( ${count[total.$d]:-0} + n ))
    done
done
millions() { awk -v n="$1" 'BEGIN { printf "%.1f", n / 1e6 }'; }
echo
echo "Measured by \`scripts/bench-tree.sh work $max\` at commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)," \
    "$(date -u +%Y-%m-%d): render.sh --depth D on the fill-heavy scene (10,000 quads, Dc≈10," \
    "1920×1080), millions of user-space instructions by program (cachegrind, children" \
    "traced; processes in brackets), every depth's frame identical to depth 0's."
echo
head="| program |" rule="|---|"
for ((d = 0; d <= max; d++)); do head+=" depth $d |"; rule+="---|"; done
echo "$head"
echo "$rule"
for program in "${programs[@]}"; do
    line="| $program |"
    for ((d = 0; d <= max; d++)); do
        if [[ -n ${count[$program.$d]:-} ]]; then
            line+=" $(millions "${count[$program.$d]}") (${count[processes.$program.$d]}) |"
        else
            line+=" – |"
        fi
    done
    echo "$line"
done
line="| **all** |" ratios="| **against depth 0** |"
for ((d = 0; d <= max; d++)); do
    line+=" **$(millions "${count[total.$d]}")** |"
    ratios+=" **$(ratio "${count[total.$d]}" "${count[total.0]}")** |"
done
echo "$line"
echo "$ratios"
)

# --- farm ---------------------------------------------------------------------------
mode_farm() (
# A movie rendered by frames (render.sh --by frames: farm on GNU parallel) over 1, 2 and 4
# hosts, each a stand-in ssh that runs the command here (the tests' POLYPIPE_SSH: no ssh
# or encryption), against render.sh here: wall seconds and the CPU seconds of every
# process of the run (perf stat -e task-clock where perf is installed, else bash's
# `time`), medians of N rounds, the runs of a round interleaved. Beside them, the cost
# model's prediction of the same runs (`plan movie --login 0`): its CPU seconds, and its
# wall seconds on hosts of their own with this machine's cores each. On one machine the
# stand-in hosts share its cores, so the measured wall time shows little; the CPU
# seconds, the work, are what compare.
#
# Usage: scripts/bench-tree.sh farm [--reps N] [--hosts N,…] [--frames N] [--chunk N]
set -euo pipefail
export LC_ALL=C
reps=5 hosts=1,2,4 frames=96 chunk=8 size=512x512
while (($#)); do
    case $1 in
        --reps) reps=${2:?--reps needs N}; shift 2 ;;
        --hosts) hosts=${2:?--hosts needs N,…}; shift 2 ;;
        --frames) frames=${2:?--frames needs N}; shift 2 ;;
        --chunk) chunk=${2:?--chunk needs N}; shift 2 ;;
        -h | --help) sed -n '/^mode_farm/,/^set -euo/{/^# /{s/^# \{0,1\}//;p}}' "${BASH_SOURCE[0]}"; exit 0 ;;
        *) echo "bench-tree.sh farm: unknown argument $1" >&2; exit 2 ;;
    esac
done
command -v parallel >/dev/null || { echo "bench-tree.sh farm: needs GNU parallel" >&2; exit 3; }
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cargo build --release --quiet --bins
B=$(release_bin "$root")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$B/scene" environment --polygons 1000 --depth-complexity 30 --size "$size" \
    --frames "$frames" > "$work/movie.pp"
cat > "$work/ssh" <<'SSH'
#!/bin/sh
while [ $# -gt 0 ]; do case $1 in -[oplSOiF]) shift 2 ;; -*) shift ;; *) break ;; esac; done
shift
[ "${1-}" = -- ] && shift
exec sh -c "$*"
SSH
chmod +x "$work/ssh"
IFS=, read -r -a counts <<<"$hosts"

# run NAME CMD…: one run, its wall and CPU seconds appended to $work/NAME.
run() {
    local name=$1 t0 t1 cpu
    shift
    t0=$EPOCHREALTIME
    if command -v perf >/dev/null; then
        perf stat -x, -e task-clock -o "$work/perf" -- "$@" >/dev/null 2>&1
        cpu=$(awk -F, '/task-clock/ { printf "%.3f", $1 / 1000 }' "$work/perf")
    else
        cpu=$(cpu_seconds "$@")
    fi
    t1=$EPOCHREALTIME
    awk -v a="$t0" -v b="$t1" -v c="$cpu" 'BEGIN { printf "%.3f %s\n", b - a, c }' >>"$work/$name"
}
for ((r = 0; r < reps; r++)); do
    run local scripts/render.sh --size "$size" --depth 0 "$work/movie.pp"
    for n in "${counts[@]}"; do
        list=$(seq -f 'h%g' 1 "$n" | paste -sd,)
        run "hosts$n" env POLYPIPE_SSH="$work/ssh" POLYPIPE_LOAD=0 scripts/render.sh \
            --by frames --hosts "$list" --chunk "$chunk" --size "$size" --depth 0 "$work/movie.pp"
    done
done
col() { awk -v c="$2" '{ print $c }' "$work/$1" | median; }
"$B/plan" movie --hosts "$hosts" --chunk "$chunk" --size "$size" --login 0 \
    --host-cores "$(nproc)" "$work/movie.pp" > "$work/plan"
predicted() { # HOSTS COLUMN: plan movie's row for HOSTS hosts
    awk -F'|' -v n="$1" -v c="$2" '$2 + 0 == n && $2 ~ /[0-9]/ { gsub(/ /, "", $c); print $c }' "$work/plan"
}
local_cpu=$(col local 2)
echo
echo "Measured by \`scripts/bench-tree.sh farm --reps $reps\` at commit" \
    "$(git rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) cores," \
    "load $(cut -d' ' -f1 /proc/loadavg), $(date -u +%Y-%m-%d): $frames frames of" \
    "\`scene environment --polygons 1000 --depth-complexity 30 --size $size\`," \
    "render.sh --size $size --depth 0, --by frames --chunk $chunk, medians of $reps."
echo
echo "| run | wall s | CPU s | CPU × local | predicted CPU s | predicted wall s, hosts of $(nproc) cores |"
echo "|---|---|---|---|---|---|"
echo "| render.sh here | $(col local 1) | $local_cpu | 1.00 | – | – |"
for n in "${counts[@]}"; do
    cpu=$(col "hosts$n" 2)
    echo "| --by frames, $n host$( ((n == 1)) || echo s) | $(col "hosts$n" 1) | $cpu |" \
        "$(ratio "$cpu" "$local_cpu") | $(predicted "$n" 7) | $(predicted "$n" 5) |"
done
echo
sed -n '/frames, /p' "$work/plan"
)

case ${1-} in
    pipeline) shift; mode_pipeline "$@" ;;
    farm) shift; mode_farm "$@" ;;
    plan) shift; mode_plan "$@" ;;
    merge) shift; mode_merge "$@" ;;
    depth-auto) shift; mode_depth_auto "$@" ;;
    work) shift; mode_work "$@" ;;
    -h | --help | "") sed -n '2,/^$/{s/^# \{0,1\}//;p}' "${BASH_SOURCE[0]}"; [[ -n ${1-} ]] ;;
    *) echo "bench-tree.sh: no mode '$1' (modes: pipeline merge depth-auto plan work farm)" >&2; exit 2 ;;
esac
