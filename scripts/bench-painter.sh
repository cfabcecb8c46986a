#!/usr/bin/env bash
# bench-painter.sh: depth sort (painter, with and without --split) and hidden lines
# (hiddenline) against the z-buffer leaf (scanconv --resolve), leaf alone, file to file:
# the screen-space stream of a scene (viewxf | clipbatch | persp, made once) in, the
# leaf's output to /dev/null. Per scene and method: the best wall time of REPS runs
# (default 5; the machine is shared), peak resident memory, and for the pixel methods
# the pixels that differ from the z-buffer's frame (zbuf over the leaf's runs, zspec
# compare) and the painter's cycles (--stats).
#
# Scenes: the thesis's environment (scene environment, chapter 5.2) of 1,000, 10,000 and
# 100,000 polygons, depth complexity 3, 500x500; the thesis's penetrating scene.
#
# Usage: scripts/bench-painter.sh            the environments above
#        scripts/bench-painter.sh --hostile  the hostile scenes (`scene stack`,
#            `slivers`, `pinhead`, `strips`, `planes`) at 500x500: painter, painter --split
#            and abuf against the z-buffer leaf, each run under `timeout 120`; wall s (best
#            of REPS, default 3), peak RSS, the ratios to the z-buffer, and for the
#            painter the pixels unlike the z-buffer's and whether it said it gave up.
set -euo pipefail

if [[ ${1:-} == --hostile ]]; then
    root=$(cd "$(dirname "$0")/.." && pwd)
    cd "$root"
    cargo build --release --quiet -p scene -p viewxf -p clipbatch -p persp -p scanconv -p zbuf -p zspec -p painter -p abuf
    B=$root/target/release
    REPS=${REPS:-3}
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
    scenes=("stack 20000" "slivers 10000" "pinhead 100000" "strips 3000" "stack 2000" "planes 2000" "planes 5" "planes 50" "planes 400")
    for s in "${scenes[@]}"; do
        "$B/scene" $s | "$B/viewxf" | "$B/clipbatch" | "$B/persp" --size 500x500 > "$work/${s// /-}.scr"
    done
    # run CMD...: best wall s of REPS runs (killed at 120 s: "timeout") and the peak RSS
    # in MB of the last.
    run() {
        local t=999999 rss=0 i
        for ((i = 0; i < REPS; i++)); do
            local start=$EPOCHREALTIME
            if ! timeout 120 /usr/bin/time -o "$work/time" -f '%M' "$@" < "$in" > /dev/null 2> /dev/null; then
                echo "timeout 0"
                return
            fi
            local end=$EPOCHREALTIME
            local e
            e=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')
            t=$(awk -v a="$t" -v b="$e" 'BEGIN { print (b < a) ? b : a }')
            rss=$(awk '{ printf "%.1f", $1 / 1024 }' < "$work/time")
        done
        echo "$t $rss"
    }
    echo "| scene, 500x500 | method | wall s | peak RSS MB | time / zbuf | RSS / zbuf | pixels unlike zbuf | said it gave up |"
    echo "|---|---|---|---|---|---|---|---|"
    for s in "${scenes[@]}"; do
        in=$work/${s// /-}.scr
        "$B/scanconv" --resolve < "$in" | "$B/zbuf" > "$work/z.ppm"
        read -r zt zr <<< "$(run "$B/scanconv" --resolve)"
        echo "| $s | zbuf (scanconv --resolve) | $zt | $zr | 1 | 1 | — | — |"
        for method in "painter" "painter --split" "abuf"; do
            read -r t rss <<< "$(run "$B"/$method)"
            diff=— said=—
            if [[ $method == painter* && $t != timeout ]]; then
                "$B"/$method < "$in" 2> "$work/err" | "$B/zbuf" > "$work/m.ppm"
                diff=$("$B/zspec" compare "$work/z.ppm" "$work/m.ppm" 2> /dev/null | sed -n 's/.* pixels, \([0-9]*\) differ.*/\1/p' || true)
                said=no
                grep -q "could not order" "$work/err" && said=yes
            fi
            rt=$(awk -v a="$t" -v b="$zt" 'BEGIN { if (a == "timeout") print "—"; else printf "%.2f", a / b }')
            rr=$(awk -v a="$rss" -v b="$zr" 'BEGIN { printf "%.2f", a / b }')
            echo "| $s | $method | $t | $rss | $rt | $rr | $diff | $said |"
        done
    done
    exit 0
fi

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet -p scene -p viewxf -p clipbatch -p persp -p scanconv -p zbuf -p zspec -p painter -p hiddenline
B=$root/target/release
REPS=${REPS:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

screen() { "$B/viewxf" | "$B/clipbatch" | "$B/persp" --size 500x500; }
for n in 1000 10000 100000; do
    "$B/scene" environment --polygons "$n" --depth-complexity 3 --seed 4 | screen > "$work/env$n.scr"
done
screen < examples/penetrating.txt > "$work/penetrating.scr"

# best CMD...: the smallest wall time of REPS runs (seconds, bash's clock around
# /usr/bin/time) and the peak RSS (KiB) of the last, input from $in.
best() {
    local t=999999 rss=0 i s
    for ((i = 0; i < REPS; i++)); do
        local start=$EPOCHREALTIME
        /usr/bin/time -o "$work/time" -f '%M' "$@" < "$in" > /dev/null 2> /dev/null
        local end=$EPOCHREALTIME
        e=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", b - a }')
        read -r m < "$work/time"
        t=$(awk -v a="$t" -v b="$e" 'BEGIN { print (b < a) ? b : a }')
        rss=$m
    done
    echo "$t $rss"
}

printf '%-12s %-20s %8s %12s %10s %7s %9s\n' scene method wall_s max_rss_kib differing cycles given_up
for scene in penetrating env1000 env10000 env100000; do
    in=$work/$scene.scr
    "$B/scanconv" --resolve < "$in" | "$B/zbuf" > "$work/z.ppm"
    for method in "scanconv --resolve" "painter" "painter --split" "hiddenline"; do
        read -r t rss <<< "$(best "$B"/$method)"
        diff=- cycles=- given_up=-
        case $method in
            painter*)
                "$B"/$method --stats < "$in" 2> "$work/stats" | "$B/zbuf" > "$work/m.ppm"
                diff=$("$B/zspec" compare "$work/z.ppm" "$work/m.ppm" 2> /dev/null | sed -n 's/.* pixels, \([0-9]*\) differ.*/\1/p' || true)
                cycles=$(sed -n 's/.* swaps, \([0-9]*\) cycles, .*/\1/p' "$work/stats")
                given_up=$(sed -n 's/.* \([0-9]*\) cycles painted out of order.*/\1/p' "$work/stats")
                ;;
            scanconv*) diff=0 ;;
        esac
        printf '%-12s %-20s %8s %12s %10s %7s %9s\n' "$scene" "$method" "$t" "$rss" "$diff" "$cycles" "$given_up"
    done
done
