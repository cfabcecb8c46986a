#!/usr/bin/env bash
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
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", (b > 0 ? a / b : 0) }'; }

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
