#!/usr/bin/env bash
# bench-warnock.sh: Warnock's area subdivision and the hidden-line drawing against the
# z-buffer leaf (issue 21, items 1, 4, 5 and 6; docs/methods.md, "warnock" and "Hidden
# lines"). Self-contained: it makes its scenes itself, with awk, as screen-space streams.
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
# Usage: scripts/bench-warnock.sh [SIZE]   (default 500x500; REPS=N to change the runs)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
nice -n 10 cargo build --release --quiet -p warnock -p hiddenline -p scanconv -p zbuf -p zspec
B=${CARGO_TARGET_DIR:-$root/target}/release
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
        differ=$("$B/zspec" compare "$work/z.ppm" "$work/w.ppm" 2>/dev/null | awk '/differ/ { print $4 }' | head -n 1)
    fi
    polys=$(count "$ws" "polygons in")
    windows=$(awk -v s="$ws" 'BEGIN { split(s, p, "windows by depth: "); split(p[2], r, ";"); n = split(r[1], d, " "); t = 0; for (i = 1; i <= n; i++) t += d[i]; print t }')
    echo "| $name | $polys | $(count "$hs" "pieces drawn;") | $z | $w | $h | $zk | $wk | $hk | $windows | $(count "$ws" "single pixels") | $(count "$ws" "polygons looked at") | $differ |"
done
