#!/usr/bin/env bash
# bench-methods.sh: the hidden-surface methods measured, one mode a run:
#
#   scripts/bench-methods.sh methods [--quick] [--reps N]  every --hse at depth 0 and at
#                                                 its best depth, on bench.sh's scenes
#   scripts/bench-methods.sh painter [OPTIONS]    depth sort and hidden lines against the
#                                                 z-buffer leaf
#   scripts/bench-methods.sh scanline [OPTIONS]   Watkins's scan line as the crossings
#                                                 and the depth complexity grow
#   scripts/bench-methods.sh warnock [OPTIONS]    where area subdivision slows down
#   scripts/bench-methods.sh aa [N] [WxH] [REPS]  what anti-aliasing costs at a leaf
#
# Each mode's own notes are at its function below. They share scripts/lib/bench.sh.

# The modes are functions of their own (each a subshell), and some reuse a name for an
# array in one and a string in another, which shellcheck reads as one variable.
# shellcheck disable=SC2128,SC2154,SC2178
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

# --- methods (was scripts/bench-methods.sh) -------------------------------------
mode_methods() (
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
        best='' bd=
        for d in 0 1 2 3 4; do
            v=${t[$s.$m.$d]}
            if [[ -z $best ]] || awk -v a="$v" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$v bd=$d; fi
        done
        ratio=$(awk -v a="$best" -v b="$zbest" 'BEGIN { printf "%.2f", a / b }')
        echo "| ${label[$s]} | $m | ${t[$s.$m.0]} | $bd | $best | $ratio |"
    done
done
)

# --- painter (was scripts/bench-painter.sh) -------------------------------------
mode_painter() (
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
# Usage: scripts/bench-painter.sh
set -euo pipefail

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
)

# --- scanline (was scripts/bench-scanline.sh) -----------------------------------
mode_scanline() (
# bench-scanline.sh: how Watkins's scan-line method (`scanline`) grows against the
# z-buffer leaf (`scanconv --resolve`) on the same screen-space streams, leaf alone, file
# to file (Newman and Sproull 1973, 14.4.3: "its dependence on complexity of the
# scene is difficult to analyze ... the computation grows roughly as the *visible*
# complexity increases").
#
#   1. crossings K: K narrow columns across a 1024x1024 screen, each holding two
#      full-height quads whose planes cross in its middle: depth complexity 2 everywhere,
#      K crossings of the visible polygon per scan line
#   2. stacked D: D full-screen quads on parallel planes in random order: depth
#      complexity D, no crossing (one sample span a line holds D segments)
#   3. tilted D: D full-screen quads, each tilted at random about a vertical axis: depth
#      complexity D, and the front of the pile changes along every line
#   4. environment Dc: the thesis's test environment (scene environment, 10,000 quads
#      at 500x500, half of them outside the pyramid, 10 frames) through viewxf, the
#      clippers and persp
#   5. Archuleta's figures 2 and 3 (Archuleta 1972): the building (scene building, 1000
#      frames) at 256 and at 1024 scan lines, against his 7.2 s and 23.7 s on a
#      DECsystem-10 (3.3 times for 4 times the lines)
#
# Sections 1-3 are FRAMES frames (default 10) of one scene each, so that times are
# measurable. Each cell is the smallest CPU time (user + system) of REPS runs (default 3; the
# machine is shared); `ratio` is scanline over z-buffer; the counters are from
# `scanline --stats`: segments, sample spans, depth comparisons and crossings (splits of a
# sample span where another segment comes in front), per scan line.
#
# Usage: scripts/bench-scanline.sh [SECTION...]   (sections 1-5; default all)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet -p scanline -p scanconv -p scene -p viewxf -p clipplane \
    -p persp -p frames
B=$root/target/release
REPS=${REPS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sections=("$@")
((${#sections[@]})) || sections=(1 2 3 4 5)
want() { [[ " ${sections[*]} " == *" $1 "* ]]; }

# cpu CMD: the smallest user + system seconds of REPS runs.
cpu() {
    local i
    for ((i = 0; i < REPS; i++)); do
        /usr/bin/time -f '%U %S' -o "$work/time" bash -c "$1" >/dev/null 2>&1
        tail -n 1 "$work/time" | awk '{ printf "%.2f\n", $1 + $2 }'
    done | sort -n | head -n 1
}

# ratio A B: A/B, or "-" when either is below the timer's 0.01 s.

# row NAME PARAM FILE: one table row for a binary screen-space stream.
row() {
    local s z stats
    s=$(cpu "$B/scanline < $2 > /dev/null")
    z=$(cpu "$B/scanconv --resolve < $2 > /dev/null")
    # Counters: "scanline: P polygons in, F frames, R runs out, L scan lines, S segments,
    # N sample spans, E segments examined, C depth comparisons, X crossings, ..."
    stats=$("$B/scanline" --stats < "$2" 2>&1 >/dev/null |
        awk -F'[:,] *' '{
            split($2, p, " "); split($3, fr, " "); split($5, l, " "); split($6, g, " "); split($7, n, " ");
            split($9, c, " "); split($10, x, " ");
            L = (l[1] > 0 ? l[1] : 1);
            printf "%d | %.1f | %.1f | %.1f | %.1f", p[1] / fr[1], g[1] / L, n[1] / L, c[1] / L, x[1] / L
        }')
    echo "| $1 | $stats | $s | $z | $(ratio "$s" "$z") |"
}

header() {
    echo "## $1"
    echo
    echo "| $2 | polygons a frame | segments/line | sample spans/line | depth comparisons/line | crossings/line | scanline s | z-buffer s | ratio |"
    echo "|---|---|---|---|---|---|---|---|---|"
}

# Screen-space text streams, made with awk, then binary (frames passes them through).
W=1024
H=1024
FRAMES=${FRAMES:-10}
to_binary() { "$B/frames" > "$1"; }

if want 1; then
    header "1. Crossings per scan line (depth complexity 2, ${W}x$H, $FRAMES frames; CPU s, best of $REPS)" K
    for k in 1 4 16 64 256 512; do
        awk -v W=$W -v H=$H -v F=$FRAMES -v K=$k 'BEGIN {
            print "polypipe 1 screen " W " " H
            n = K
            for (f = 0; f < F; f++) {
                if (f) print "NEXT.FRAME"
                first = 1
                for (i = 0; i < n; i++) {
                    x0 = i * W / n; x1 = (i + 1) * W / n
                    for (j = 0; j < 2; j++) {
                        if (!first) print "NEXT.POLYGON"; first = 0
                        za = (j ? 0.8 : 0.2); zb = 1 - za
                        print "colour " (i * 7 % 256) " " (j * 200) " 90"
                        print x0, 0, za; print x1, 0, zb; print x1, H, zb; print x0, H, za
                    }
                }
            }
            print "END"
        }' | to_binary "$work/cross$k"
        row "$k" "$work/cross$k"
    done
    echo
fi

if want 2; then
    header "2. Stacked parallel planes (depth complexity D, no crossing, ${W}x$H, $FRAMES frames; CPU s, best of $REPS)" D
    for d in 1 4 16 64 256; do
        awk -v W=$W -v H=$H -v F=$FRAMES -v D=$d 'BEGIN {
            srand(D * 7 + 1)
            print "polypipe 1 screen " W " " H
            for (f = 0; f < F; f++) {
                if (f) print "NEXT.FRAME"
                for (i = 0; i < D; i++) {
                    if (i) print "NEXT.POLYGON"
                    z = 0.05 + 0.9 * rand()
                    print "colour " int(rand() * 256) " " int(rand() * 256) " 7"
                    print 0, 0, z; print W, 0, z + 0.01; print W, H, z + 0.01; print 0, H, z
                }
            }
            print "END"
        }' | to_binary "$work/stack$d"
        row "$d" "$work/stack$d"
    done
    echo
fi

if want 3; then
    header "3. Tilted full-screen planes (depth complexity D, the front changing along each line, ${W}x$H, $FRAMES frames; CPU s, best of $REPS)" D
    for d in 1 4 16 64 256; do
        awk -v W=$W -v H=$H -v F=$FRAMES -v D=$d 'BEGIN {
            srand(D * 13 + 5)
            print "polypipe 1 screen " W " " H
            for (f = 0; f < F; f++) {
                if (f) print "NEXT.FRAME"
                for (i = 0; i < D; i++) {
                    if (i) print "NEXT.POLYGON"
                    za = 0.05 + 0.9 * rand(); zb = 0.05 + 0.9 * rand()
                    print "colour " int(rand() * 256) " " int(rand() * 256) " 7"
                    print 0, 0, za; print W, 0, zb; print W, H, zb; print 0, H, za
                }
            }
            print "END"
        }' | to_binary "$work/tilt$d"
        row "$d" "$work/tilt$d"
    done
    echo
fi

if want 4; then
    header "4. The test environment, 10,000 quads at 500x500, a 10-frame movie (CPU s, best of $REPS)" Dc
    clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"
    for dc in 1 4 16; do
        "$B/scene" environment --polygons 10000 --depth-complexity $dc --seed 5 --size 500x500 \
            --frames 10 |
            "$B/viewxf" --size 500x500 | bash -c "$clip" | "$B/persp" --size 500x500 > "$work/env$dc"
        row "$dc" "$work/env$dc"
    done
    echo
fi

if want 5; then
    header "5. Archuleta's building at 256 and 1024 scan lines, 1000 frames (CPU s, best of $REPS)" lines
    clip="$B/clipplane left | $B/clipplane right | $B/clipplane top | $B/clipplane bottom | $B/clipplane hither | $B/clipplane yon"
    for n in 256 1024; do
        "$B/scene" building --frames 1000 | "$B/viewxf" --size ${n}x$n | bash -c "$clip" |
            "$B/persp" --size ${n}x$n > "$work/building$n"
        row "$n" "$work/building$n"
    done
    echo
fi
)

# --- warnock (was scripts/bench-warnock.sh) -------------------------------------
mode_warnock() (
# bench-warnock.sh: where Warnock's area subdivision slows down, against the z-buffer
# leaf.
#
# Each scene is made once as a screen-space stream (scene | viewxf | clipbatch | persp),
# then timed through one leaf, file to /dev/null: `warnock` and `scanconv --resolve`
# (the z-buffer leaf render.sh runs today). CPU seconds (user + system) are the best of
# REPS runs (default 3; the machine is shared, the fastest run the least disturbed), peak
# resident memory from one more run, and warnock's own counters from --stats: windows
# visited, the deepest level, the windows decided pixel by pixel, and the rows of
# coverage and depth it read. The scenes:
#
#   small-N     environment, N small quadrilaterals, depth complexity 1 (many small
#               polygons: every polygon's edges are subdivided down to pixels)
#   fill        environment, 10,000 quadrilaterals, depth complexity 10 (big overlapping
#               polygons: long lists of surrounders)
#   mesh        scene mesh: a screen of quadrilaterals sharing edges
#   slivers-N   N triangles a fraction of a pixel wide, fanned over a background
#   penetrate   two planes crossing along a line over the whole screen (deep subdivision
#               along the line), and scene penetrating / triangle-square / spheres
#
# Usage: scripts/bench-warnock.sh [SIZE]   (default 500x500)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet -p warnock -p scanconv -p scene -p viewxf -p clipbatch -p persp
B=$root/target/release
REPS=${REPS:-3}
size=${1:-500x500}
W=${size%x*} H=${size#*x}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

screen() { # screen NAME SCENE-ARGS...: a screen-space stream of a scene
    local name=$1
    shift
    "$B/scene" "$@" | "$B/viewxf" --size "$size" | "$B/clipbatch" | "$B/persp" --size "$size" > "$work/$name.pp"
}

slivers() { # slivers N: N slivers 0.3 px wide fanned from the top-left corner
    awk -v n="$1" -v w="$W" -v h="$H" 'BEGIN {
        printf "polypipe 1 screen %d %d\ncolour 10 10 10\n0 0 0.9\n%d 0 0.9\n%d %d 0.9\n0 %d 0.9\n", w, h, w, w, h, h
        r = (w < h ? w : h) - 2
        for (k = 0; k < n; k++) {
            a = k * 3.14159265358979 / 2 / n
            x = 1 + r * cos(a); y = 1 + r * sin(a)
            printf "NEXT.POLYGON\ncolour %d 200 0\n1 1 %.6f\n%.6f %.6f 0.5\n%.6f %.6f 0.5\n",
                k % 256, 0.1 + 0.3 * k / n, x, y, x + 0.3 * sin(a), y - 0.3 * cos(a)
        }
        print "END"
    }' > "$work/slivers-$1.pp"
}

penetrate() { # two planes over the whole screen crossing at X = W·0.55
    awk -v w="$W" -v h="$H" 'BEGIN {
        c = w * 0.55
        printf "polypipe 1 screen %d %d\n", w, h
        printf "colour 200 0 0\n0 0 0.2\n%d 0 %.9f\n%d %d %.9f\n0 %d 0.2\n", w, 0.2 + 0.4 * w / c * 0.5, w, h, 0.2 + 0.4 * w / c * 0.5, h
        # blue: 0.55 at X = 0, equal to red at X = c
        zc = 0.2 + 0.2 * c / c
        zr = 0.55 + (zc - 0.55) * w / c
        printf "NEXT.POLYGON\ncolour 0 0 200\n0 0 0.55\n%d 0 %.9f\n%d %d %.9f\n0 %d 0.55\nEND\n", w, zr, w, h, zr, h
    }' > "$work/penetrate.pp"
}

echo "preparing scenes at $size ..." >&2
for n in 1000 10000 100000; do
    screen "small-$n" environment --polygons "$n" --clipped 0 --depth-complexity 1 --seed 3 --size "$size"
done
screen fill environment --polygons 10000 --clipped 0 --depth-complexity 10 --seed 2 --size "$size"
screen mesh mesh
screen penetrating penetrating
screen triangle-square triangle-square
screen spheres spheres
for n in 100 1000 10000; do slivers "$n"; done
penetrate

# cpu CMD: the smallest CPU seconds (user + system) of REPS runs.
cpu() {
    local i
    for ((i = 0; i < REPS; i++)); do
        /usr/bin/time -f '%U %S' -o "$work/time" bash -c "$1" > /dev/null 2>&1
        awk '{ printf "%.2f\n", $1 + $2 }' "$work/time"
    done | sort -n | head -n 1
}
rss() { # rss CMD: peak resident KiB of one run
    /usr/bin/time -f '%M' -o "$work/time" bash -c "$1" > /dev/null 2>&1
    tail -n 1 "$work/time"
}

echo "## warnock against the z-buffer leaf at $size (CPU s best of $REPS; peak KiB)"
echo
echo "| scene | polygons | zbuf s | warnock s | warnock/zbuf | zbuf KiB | warnock KiB | windows | levels | pixel windows | subdivided | coverage rows | depth rows |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for name in small-1000 small-10000 small-100000 fill mesh slivers-100 slivers-1000 slivers-10000 penetrate penetrating triangle-square spheres; do
    f=$work/$name.pp
    z=$(cpu "$B/scanconv --resolve < $f")
    w=$(cpu "$B/warnock < $f")
    zk=$(rss "$B/scanconv --resolve < $f")
    wk=$(rss "$B/warnock < $f")
    stats=$("$B/warnock" --stats < "$f" 2>&1 > /dev/null)
    row=$(awk -v s="$stats" 'BEGIN {
        split(s, part, "windows by depth: "); split(part[2], rest, ";")
        n = split(rest[1], d, " "); total = 0
        for (i = 1; i <= n; i++) total += d[i]
        polys = s; sub(/^warnock: /, "", polys); sub(/ polygons in.*/, "", polys)
        match(s, /[0-9]+ single pixels/); px = substr(s, RSTART, RLENGTH); sub(/ .*/, "", px)
        match(s, /[0-9]+ subdivided/); sd = substr(s, RSTART, RLENGTH); sub(/ .*/, "", sd)
        match(s, /[0-9]+ coverage rows/); cr = substr(s, RSTART, RLENGTH); sub(/ .*/, "", cr)
        match(s, /[0-9]+ depth rows/); dr = substr(s, RSTART, RLENGTH); sub(/ .*/, "", dr)
        printf "%s|%d|%d|%s|%s|%s|%s", polys, total, n, px, sd, cr, dr
    }')
    IFS='|' read -r polys total levels px sd cr dr <<< "$row"
    echo "| $name | $polys | $z | $w | $(ratio "$w" "$z") | $zk | $wk | $total | $levels | $px | $sd | $cr | $dr |"
done
)

# --- aa (was scripts/bench-aa.sh) -----------------------------------------------
mode_aa() (
# What anti-aliasing costs at a leaf: time and peak memory of the leaf's method alone on
# one screen-space frame, point sampling (scanconv --resolve) against supersampling 4×4
# and 8×8 and the a-buffer (docs/antialiasing.md). The scene is `scene environment`
# (thesis ch. 5.2) of N quadrilaterals at WxH, run once through viewxf | clipbatch |
# persp into a file; each method then reads that file, so only the method is timed.
# Wall and CPU seconds are the median of REPS runs; peak RSS (/usr/bin/time -v's
# "Maximum resident set size") the largest of them.
#
#   scripts/bench-aa.sh [N] [WxH] [REPS]      (defaults 100000 1920x1080 3)
set -euo pipefail

N=${1:-100000}
SIZE=${2:-1920x1080}
REPS=${3:-3}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
B=$ROOT/target/release
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-aa.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipbatch -p persp -p scanconv -p supersample -p abuf

"$B/scene" environment --polygons "$N" --size "$SIZE" --seed 1 \
  | "$B/viewxf" --size "$SIZE" | "$B/clipbatch" | "$B/persp" --size "$SIZE" >"$TMP/screen.bin"
polygons=$("$B/scanconv" --resolve --stats <"$TMP/screen.bin" 2>&1 >/dev/null \
  | sed -n 's/^scanconv: \([0-9]*\) polygons in.*/\1/p')

# measure NAME CMD...: one row, median wall and CPU seconds of REPS runs, largest RSS.
measure() {
  local name=$1 walls=() cpus=() rss=0 r
  shift
  for _ in $(seq "$REPS"); do
    /usr/bin/time -v -o "$TMP/time" "$@" <"$TMP/screen.bin" >"$TMP/out" 2>/dev/null
    walls+=("$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, t, ":"); s = 0;
      for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.2f", s }' "$TMP/time")")
    cpus+=("$(awk -F': ' '/User time/ { u = $2 } /System time/ { s = $2 }
      END { printf "%.2f", u + s }' "$TMP/time")")
    r=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$TMP/time")
    ((r > rss)) && rss=$r
  done
  local mid=$(((REPS + 1) / 2))
  printf '%-14s %8s %8s %12s %10s\n' "$name" \
    "$(printf '%s\n' "${walls[@]}" | sort -g | sed -n "${mid}p")" \
    "$(printf '%s\n' "${cpus[@]}" | sort -g | sed -n "${mid}p")" \
    "$rss" "$(stat -c %s "$TMP/out")"
}

echo "scene environment --polygons $N --size $SIZE --seed 1: $polygons polygons into the leaf"
echo "one leaf (depth 0), median of $REPS runs"
printf '%-14s %8s %8s %12s %10s\n' method wall_s cpu_s max_rss_kib out_bytes
measure point "$B/scanconv" --resolve
measure ss4 "$B/supersample" --samples 4
measure ss8 "$B/supersample" --samples 8
measure abuf "$B/abuf"
)

case ${1-} in
    methods) shift; mode_methods "$@" ;;
    painter) shift; mode_painter "$@" ;;
    scanline) shift; mode_scanline "$@" ;;
    warnock) shift; mode_warnock "$@" ;;
    aa) shift; mode_aa "$@" ;;
    -h | --help | "") sed -n '2,/^$/{s/^# \{0,1\}//;p}' "${BASH_SOURCE[0]}"; [[ -n ${1-} ]] ;;
    *) echo "bench-methods.sh: no mode '$1' (modes: methods painter scanline warnock aa)" >&2; exit 2 ;;
esac
