#!/usr/bin/env bash
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
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a > 0 && b > 0) printf "%.2f", a / b; else printf "-" }'; }

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
