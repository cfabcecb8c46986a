#!/usr/bin/env bash
# bench-methods.sh: the hidden-surface methods measured, one mode a run:
#
#   scripts/bench-methods.sh methods [--quick] [--reps N]  every --hse at depth 0 and at
#                                                 its best depth, on bench.sh's scenes
#   scripts/bench-methods.sh painter [OPTIONS]    depth sort and hidden lines against the
#                                                 z-buffer leaf
#   scripts/bench-methods.sh scanline [OPTIONS]   Watkins's scan line as the crossings
#                                                 and the depth complexity grow, and
#                                                 what its line-to-line coherence buys
#   scripts/bench-methods.sh warnock [OPTIONS]    where area subdivision slows down
#   scripts/bench-methods.sh aa [N] [WxH] [REPS]  what anti-aliasing costs at a leaf
#   scripts/bench-methods.sh bounds [REPS]        every method on the hostile scenes
#                                                 against 256 MB and 30 s, and painter
#                                                 --split on crossing planes
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
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release --quiet --bins
B=$(release_bin "$root")

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
# Usage: scripts/bench-methods.sh painter            the environments above
#        scripts/bench-methods.sh painter --hostile  the hostile scenes (`scene stack`,
#            `slivers`, `pinhead`, `strips`, `planes`) at 500x500: painter, painter --split
#            and abuf against the z-buffer leaf, each run under `timeout 120`; wall s (best
#            of REPS, default 3), peak RSS, the ratios to the z-buffer, and for the
#            painter the pixels unlike the z-buffer's and whether it said it gave up.
set -euo pipefail

if [[ ${1:-} == --hostile ]]; then
    root=$(cd "$(dirname "$0")/.." && pwd)
    cd "$root"
    cargo build --release --quiet -p scene -p viewxf -p clipbatch -p persp -p scanconv -p zbuf -p zspec -p painter -p abuf
    B=$(release_bin "$root")
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
B=$(release_bin "$root")
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
#   6. what the coherence from line to line buys: `scanline` (the segment list kept in
#      X order by the minor sort, the line above's front and crossings tried first)
#      against `scanline --sort-afresh` (sorted afresh, no prediction) on scenes with
#      much coherence (Archuleta's spheres, 20,000 stacked quads) and little (10,000
#      slivers; 1,000 strips whose order along the line reverses from top to bottom;
#      400 planes all crossing, where the front changes ~118 times a line), 500x500: instructions by `valgrind --tool=callgrind` (steady on a loaded machine;
#      skipped without valgrind), CPU seconds, and the counters per scan line
#
# Sections 1-3 are FRAMES frames (default 10) of one scene each, so that times are
# measurable. Each cell is the smallest CPU time (user + system) of REPS runs (default 3; the
# machine is shared); `ratio` is scanline over z-buffer; the counters are from
# `scanline --stats`: segments, sample spans, depth comparisons and crossings (splits of a
# sample span where another segment comes in front), per scan line.
#
# Usage: scripts/bench-methods.sh scanline [SECTION...]   (sections 1-6; default all)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet -p scanline -p scanconv -p scene -p viewxf -p clipplane \
    -p clipbatch -p persp -p frames
B=$(release_bin "$root")
REPS=${REPS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sections=("$@")
((${#sections[@]})) || sections=(1 2 3 4 5 6)
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
        awk -F'[:;,] *' '{
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

if want 6; then
    echo "## 6. What the coherence from line to line buys, 500x500 (instructions: callgrind; CPU s, best of $REPS)"
    echo
    echo "| scene | segments/line | merged in/line | re-sorted/line | swaps/line | fronts predicted held / failed | crossings predicted held / failed | midpoint subdivisions/line | instructions, coherent | instructions, --sort-afresh | ratio | CPU s, coherent | CPU s, --sort-afresh |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    instructions() { # instructions FILE ARGS...: callgrind's instruction count, or "-"
        local f=$1
        shift
        if command -v valgrind > /dev/null; then
            valgrind --tool=callgrind --callgrind-out-file=/dev/null "$B/scanline" "$@" < "$f" 2>&1 > /dev/null |
                sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
        else
            echo -
        fi
    }
    screen() { "$B/viewxf" | "$B/clipbatch" | "$B/persp" --size 500x500; }
    "$B/scene" spheres | screen > "$work/spheres"
    "$B/scene" stack 20000 | screen > "$work/stack20000"
    "$B/scene" slivers 10000 | screen > "$work/slivers10000"
    "$B/scene" planes 400 | screen > "$work/planes400"
    # 1,000 strips a pixel wide whose order along the line reverses from the top of the
    # screen to the bottom: every pair changes places once.
    awk 'BEGIN {
        print "polypipe 1 screen 500 500"
        for (i = 0; i < 1000; i++) {
            if (i) print "NEXT.POLYGON"
            t = 0.5 * i + 0.1; b = 499.1 - 0.5 * i; z = 0.1 + 0.0008 * i
            print "colour " (i % 256) " 100 200"
            print t, 0, z; print t + 1, 0, z; print b + 1, 500, z; print b, 500, z
        }
        print "END"
    }' | to_binary "$work/reversing1000"
    for name in spheres stack20000 slivers10000 reversing1000 planes400; do
        f=$work/$name
        stats=$("$B/scanline" --stats < "$f" 2>&1 > /dev/null |
            awk -F'[:;,] *' '{
                split($5, l, " "); split($6, g, " "); split($12, m, " "); split($13, r, " ");
                split($14, w, " "); split($16, fh, " "); split($17, ff, " "); split($18, ch, " ");
                split($19, cf, " "); split($20, md, " ");
                L = (l[1] > 0 ? l[1] : 1);
                printf "%.1f | %.2f | %.2f | %.2f | %d / %d | %d / %d | %.2f", g[1] / L, m[1] / L, r[1] / L, w[1] / L, fh[1], ff[1], ch[1], cf[1], md[1] / L
            }')
        ic=$(instructions "$f")
        ia=$(instructions "$f" --sort-afresh)
        ir=$(awk -v a="$ic" -v b="$ia" 'BEGIN { if (b > 0) printf "%.3f", a / b; else print "-" }')
        cc=$(cpu "$B/scanline < $f > /dev/null")
        ca=$(cpu "$B/scanline --sort-afresh < $f > /dev/null")
        echo "| $name | $stats | $ic | $ia | $ir | $cc | $ca |"
    done
    echo
fi
)

# --- warnock (was scripts/bench-warnock.sh) -------------------------------------
mode_warnock() (
# bench-warnock.sh: Warnock's area subdivision and the hidden-line drawing against the
# z-buffer leaf. Self-contained: it makes its scenes itself, with awk, as screen-space streams.
#
# Each scene is timed through one leaf, file to /dev/null: `scanconv --resolve` (the
# z-buffer leaf render.sh runs), `warnock`, and `hiddenline` (SVG). CPU seconds (user +
# system) are the best of REPS runs (default 3; the machine is shared, the fastest run is
# the least disturbed; hiddenline runs once where it takes over 5 s), peak resident memory
# from one more run. Warnock's frame is compared with the z-buffer's (`zspec compare`:
# the pixels that differ), and its own counters come from --stats: windows visited, the
# windows decided pixel by pixel, the polygons the Looker looked at. "Visible edges" is
# the number of visible edge pieces hiddenline draws: the visible complexity.
#
# Scenes (W x H, default 500x500):
#
#   stack-N      N full-screen squares at distinct depths, shuffled (depth complexity N)
#   slivers-N    N triangles from one side of the screen to the other, 0.4 px wide at
#                their base, random heights and tilted depths (crossing everywhere)
#   pinhead-N    N triangles 0.24-0.6 px in radius around one pixel's centre, at distinct
#                depths, shuffled (N fragments in one pixel)
#   tiles-K      K x K squares tiling the screen in front, over 2,000 random rectangles
#                behind them: the visible edges grow with K, the hidden polygons do not
#   hidden-N     8 x 8 tiles in front of N random rectangles: the visible edges stay,
#                the hidden polygons grow
#   penetrate    two planes over the whole screen crossing along a line
#
# Usage: scripts/bench-methods.sh warnock [SIZE]   (default 500x500; REPS=N to change the runs)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
nice -n 10 cargo build --release --quiet -p warnock -p hiddenline -p scanconv -p zbuf -p zspec
B=$(release_bin "$root")
REPS=${REPS:-3}
size=${1:-500x500}
W=${size%x*} H=${size#*x}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The order k·p mod n, p prime to n near 0.618·n: neither back to front nor front to back.
SHUFFLE='function gcd(a, b) { return b == 0 ? a : gcd(b, a % b) }
function step(n,   p) { p = int(n * 0.618); if (p < 1) p = 1; while (gcd(p, n) != 1) p++; return p }
function colour(k) { printf "colour %d %d %d\n", 128 + k % 128, int(k / 128) % 256, k % 251 }'

stack() {
    awk -v n="$1" -v w="$W" -v h="$H" "$SHUFFLE"'
    BEGIN { printf "polypipe 1 screen %d %d\n", w, h; p = step(n)
        for (i = 0; i < n; i++) { k = (i * p) % n; if (i) print "NEXT.POLYGON"; colour(k)
            z = 0.2 + 0.6 * k / n
            printf "0 0 %.9f\n%d 0 %.9f\n%d %d %.9f\n0 %d %.9f\n", z, w, z, w, h, z, h, z }
        print "END" }' > "$work/stack-$1.pp"
}

slivers() {
    awk -v n="$1" -v w="$W" -v h="$H" "$SHUFFLE"'
    BEGIN { srand(2); printf "polypipe 1 screen %d %d\n", w, h
        for (k = 0; k < n; k++) { if (k) print "NEXT.POLYGON"; colour(k)
            y0 = rand() * h; y1 = rand() * h; z0 = 0.1 + 0.8 * rand(); z1 = 0.1 + 0.8 * rand()
            if (rand() < 0.5) { a = 0; b = w } else { a = w; b = 0 }
            printf "%.6f %.6f %.9f\n%.6f %.6f %.9f\n%.6f %.6f %.9f\n", a, y0, z0, b, y1 - 0.2, z1, b, y1 + 0.2, z1 }
        print "END" }' > "$work/slivers-$1.pp"
}

pinhead() {
    awk -v n="$1" -v w="$W" -v h="$H" "$SHUFFLE"'
    BEGIN { srand(3); printf "polypipe 1 screen %d %d\n", w, h; p = step(n)
        cx = int(w / 2) + 0.5; cy = int(h / 2) - 0.5; tau = 6.283185307179586
        for (i = 0; i < n; i++) { k = (i * p) % n; if (i) print "NEXT.POLYGON"; colour(k)
            z = 0.2 + 0.6 * k / n; s = rand() * tau
            for (j = 0; j < 3; j++) { a = s + tau * j / 3 + (rand() - 0.5) * 0.6; r = 0.24 + 0.36 * rand()
                printf "%.6f %.6f %.9f\n", cx + r * cos(a), cy + r * sin(a), z } }
        print "END" }' > "$work/pinhead-$1.pp"
}

tiles() { # tiles NAME K N: K x K tiles in front of N random rectangles
    awk -v kk="$2" -v n="$3" -v w="$W" -v h="$H" "$SHUFFLE"'
    BEGIN { srand(5); printf "polypipe 1 screen %d %d\n", w, h; first = 1
        for (i = 0; i < n; i++) { if (!first) print "NEXT.POLYGON"; first = 0; colour(i)
            x = rand() * w; y = rand() * h; s = 50 + 200 * rand(); z = 0.5 + 0.4 * rand()
            printf "%.6f %.6f %.9f\n%.6f %.6f %.9f\n%.6f %.6f %.9f\n%.6f %.6f %.9f\n", x, y, z, x + s, y, z, x + s, y + s, z, x, y + s, z }
        for (j = 0; j < kk; j++) for (i = 0; i < kk; i++) { if (!first) print "NEXT.POLYGON"; first = 0
            colour(n + j * kk + i); x0 = w * i / kk; x1 = w * (i + 1) / kk; y0 = h * j / kk; y1 = h * (j + 1) / kk
            printf "%.6f %.6f 0.2\n%.6f %.6f 0.2\n%.6f %.6f 0.2\n%.6f %.6f 0.2\n", x0, y0, x1, y0, x1, y1, x0, y1 }
        print "END" }' > "$work/$1.pp"
}

penetrate() {
    awk -v w="$W" -v h="$H" 'BEGIN { printf "polypipe 1 screen %d %d\n", w, h
        printf "colour 200 0 0\n0 0 0.2\n%d 0 0.6\n%d %d 0.6\n0 %d 0.2\n", w, w, h, h
        printf "NEXT.POLYGON\ncolour 0 0 200\n0 0 0.55\n%d 0 0.31\n%d %d 0.31\n0 %d 0.55\nEND\n", w, w, h, h }' > "$work/penetrate.pp"
}

echo "bench-warnock.sh: making the scenes at $size ..." >&2
stack 1000
stack 20000
slivers 1000
slivers 10000
pinhead 10000
pinhead 100000
for k in 2 8 32 128; do tiles "tiles-$k" "$k" 2000; done
for n in 1000 10000 100000; do tiles "hidden-$n" 8 "$n"; done
penetrate

# cpu CMD [REPS]: the smallest CPU seconds (user + system) of REPS runs.
cpu() {
    local i reps=${2:-$REPS}
    for ((i = 0; i < reps; i++)); do
        /usr/bin/time -f '%U %S' -o "$work/time" bash -c "$1" > /dev/null 2>&1
        awk '{ printf "%.2f\n", $1 + $2 }' "$work/time"
    done | sort -n | head -n 1
}
rss() { # rss CMD: peak resident KiB of one run
    /usr/bin/time -f '%M' -o "$work/time" bash -c "$1" > /dev/null 2>&1
    tail -n 1 "$work/time"
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", (b > 0 ? a / b : 0) }'; }
count() { # count STATS WORDS: the number before WORDS in a --stats line
    awk -v s="$1" -v what="$2" 'BEGIN { if (match(s, "[0-9]+ " what)) { v = substr(s, RSTART, RLENGTH); sub(/ .*/, "", v); print v } else print "?" }'
}

echo "## warnock and hiddenline against the z-buffer leaf, $size (CPU s, best of $REPS; peak KiB)"
echo
echo "| scene | polygons | visible edges | zbuf s | warnock s | hiddenline s | zbuf KiB | warnock KiB | hiddenline KiB | windows | pixel windows | looked at | pixels ≠ zbuf |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for name in stack-1000 stack-20000 slivers-1000 slivers-10000 pinhead-10000 pinhead-100000 \
    tiles-2 tiles-8 tiles-32 tiles-128 hidden-1000 hidden-10000 hidden-100000 penetrate; do
    f=$work/$name.pp
    z=$(cpu "$B/scanconv --resolve < $f")
    w=$(cpu "$B/warnock < $f")
    h=$(cpu "$B/hiddenline < $f" 1)
    if awk -v h="$h" 'BEGIN { exit !(h < 5) }'; then h=$(cpu "$B/hiddenline < $f"); fi
    zk=$(rss "$B/scanconv --resolve < $f")
    wk=$(rss "$B/warnock < $f")
    hk=$(rss "$B/hiddenline < $f")
    ws=$("$B/warnock" --stats < "$f" 2>&1 > "$work/w.runs")
    hs=$("$B/hiddenline" --stats < "$f" 2>&1 > /dev/null)
    "$B/scanconv" --resolve < "$f" > "$work/z.runs"
    if cmp -s "$work/w.runs" "$work/z.runs"; then
        differ=0
    else
        "$B/zbuf" < "$work/w.runs" > "$work/w.ppm"
        "$B/zbuf" < "$work/z.runs" > "$work/z.ppm"
        differ=$("$B/zspec" compare --tolerance 1 "$work/z.ppm" "$work/w.ppm" 2>/dev/null | awk '/differ/ { print $4 }' | head -n 1)
    fi
    polys=$(count "$ws" "polygons in")
    windows=$(awk -v s="$ws" 'BEGIN { split(s, p, "windows by depth: "); split(p[2], r, ";"); n = split(r[1], d, " "); t = 0; for (i = 1; i <= n; i++) t += d[i]; print t }')
    echo "| $name | $polys | $(count "$hs" "pieces drawn;") | $z | $w | $h | $zk | $wk | $hk | $windows | $(count "$ws" "single pixels") | $(count "$ws" "polygons looked at") | $differ |"
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
TMP=$(mktemp -d "${TMPDIR:-/tmp}/bench-aa.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml" \
  -p scene -p viewxf -p clipbatch -p persp -p scanconv -p supersample -p abuf
B=$(release_bin "$ROOT")

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

# --- bounds ---------------------------------------------------------------------
mode_bounds() (
# The bounds every method must keep on the scenes a user makes in a minute to break it:
# on `scene stack 20000`, `scene slivers 10000` and `scene pinhead 100000` at 500x500,
# each of scanline, warnock, painter, painter --split, hiddenline and abuf under 256 MB
# of peak resident memory and 30 s; and painter --split on `scene planes N` (N = 5, 50,
# 400) within 0.5% of the z-buffer's pixels, or saying on stderr that it could not.
#
# Each method runs as a leaf alone, the screen-space stream (scene | viewxf | clipbatch |
# persp, made once) in and its output to /dev/null, under `timeout 120`, through
# /usr/bin/time: wall seconds, CPU seconds (user + system) and peak RSS of the run with
# the least CPU of REPS (default 1). The z-buffer leaf (`scanconv --resolve`) is the
# yardstick. On a loaded machine wall time can be several times the CPU time; the
# bound is checked on both, and a row says which it misses.
#
# Usage: scripts/bench-methods.sh bounds [REPS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
nice -n 10 cargo build --release --quiet -p scene -p viewxf -p clipbatch -p persp -p scanconv \
    -p zbuf -p zspec -p scanline -p warnock -p painter -p abuf -p hiddenline
B=$(release_bin "$root")
REPS=${1:-1}
[[ $REPS =~ ^[1-9][0-9]*$ ]] || { echo "bench-methods.sh bounds: REPS must be a positive integer" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
screen() { "$B/scene" "$@" | "$B/viewxf" | "$B/clipbatch" | "$B/persp" --size 500x500; }

# measure CMD...: "wall cpu rss_mb" of the run with the least CPU of REPS, from $in; or
# "timeout" past 120 s.
measure() {
    local best='' i
    for ((i = 0; i < REPS; i++)); do
        if ! timeout 120 /usr/bin/time -o "$work/time" -f '%e %U %S %M' "$@" < "$in" > /dev/null 2> /dev/null; then
            echo timeout
            return
        fi
        local line
        line=$(tail -n 1 "$work/time" | awk '{ printf "%.2f %.2f %.1f", $1, $2 + $3, $4 / 1024 }')
        if [[ -z $best ]] || awk -v a="$line" -v b="$best" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !(x[2] < y[2]) }'; then
            best=$line
        fi
    done
    echo "$best"
}

echo "| scene, 500x500 | method | wall s | CPU s | peak RSS MB | CPU / zbuf | within 256 MB and 30 s |"
echo "|---|---|---|---|---|---|---|"
for s in "stack 20000" "slivers 10000" "pinhead 100000"; do
    in=$work/${s// /-}.scr
    # shellcheck disable=SC2086
    screen $s > "$in"
    zcpu=
    for method in "scanconv --resolve" scanline warnock painter "painter --split" hiddenline abuf; do
        echo "bench-methods.sh bounds: $s, $method" >&2
        # shellcheck disable=SC2086
        read -r wall cpu rss <<< "$(measure "$B"/$method)"
        if [[ $wall == timeout ]]; then
            echo "| $s | $method | over 120 | — | — | — | no: over 120 s wall |"
            continue
        fi
        [[ -n $zcpu ]] || zcpu=$cpu
        ratio=$(awk -v a="$cpu" -v b="$zcpu" 'BEGIN { if (b > 0) printf "%.1f", a / b; else print "—" }')
        ok=$(awk -v w="$wall" -v c="$cpu" -v m="$rss" 'BEGIN {
            if (m >= 256) print "no: memory"; else if (c >= 30) print "no: CPU time";
            else if (w >= 30) print "CPU yes, wall no"; else print "yes" }')
        label=$method
        [[ $method == "scanconv --resolve" ]] && label="zbuf (scanconv --resolve)"
        echo "| $s | $label | $wall | $cpu | $rss | $ratio | $ok |"
    done
done

echo
echo "| scene planes N, 500x500 | pixels unlike the z-buffer | share | painter --split said it could not order | within 0.5% or said |"
echo "|---|---|---|---|---|"
for n in 5 50 400; do
    in=$work/planes-$n.scr
    screen planes "$n" > "$in"
    "$B/scanconv" --resolve < "$in" | "$B/zbuf" > "$work/z.ppm"
    "$B/painter" --split < "$in" 2> "$work/err" | "$B/zbuf" > "$work/p.ppm"
    differ=$("$B/zspec" compare "$work/z.ppm" "$work/p.ppm" 2> /dev/null | sed -n 's/.* pixels, \([0-9]*\) differ.*/\1/p' || true)
    [[ -n $differ ]] || differ=0
    said=no
    grep -q "could not order" "$work/err" && said=yes
    share=$(awk -v d="$differ" 'BEGIN { printf "%.2f%%", 100 * d / 250000 }')
    ok=$(awk -v d="$differ" -v s="$said" 'BEGIN { print (d < 1250 || s == "yes") ? "yes" : "no" }')
    echo "| $n | $differ | $share | $said | $ok |"
done
)

case ${1-} in
    methods) shift; mode_methods "$@" ;;
    painter) shift; mode_painter "$@" ;;
    scanline) shift; mode_scanline "$@" ;;
    warnock) shift; mode_warnock "$@" ;;
    aa) shift; mode_aa "$@" ;;
    bounds) shift; mode_bounds "$@" ;;
    -h | --help | "") sed -n '2,/^$/{s/^# \{0,1\}//;p}' "${BASH_SOURCE[0]}"; [[ -n ${1-} ]] ;;
    *) echo "bench-methods.sh: no mode '$1' (modes: methods painter scanline warnock aa bounds)" >&2; exit 2 ;;
esac
