#!/usr/bin/env bash
# check.sh: tests the llvmpipe harness's claim to render the same picture as polypipe
# (same parser, camera, pyramid, depth rule), so that bench llvmpipe compares like with
# like. Not part of CI (CI has no Mesa): run it by hand after changing render.c.
#
# For each scene it renders with the exact reference (zspec), scripts/render.sh and the
# harness, prints the differing pixels per frame, and fails when any frame agrees on less
# than MIN_AGREEMENT percent (default 99.95: GL's sub-pixel snapping and edge ownership
# differ from the Z spec's on a few pixel centres that lie on or next to an edge), or
# when the frame counts differ (zspec compare refuses streams of different lengths). It also checks that bad input is refused.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
MIN_AGREEMENT=${MIN_AGREEMENT:-99.95}
cargo build --release --quiet -p scene -p zspec
# shellcheck source=../../scripts/lib/binaries.sh
source "$root/scripts/lib/binaries.sh"
B=$(release_bin "$root")
gl=$("$root/bench/llvmpipe/build.sh")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0

check() { # NAME SIZE SCENE
    local name=$1 size=$2 scene=$3
    "$B/zspec" --size "$size" "$scene" > "$work/ref.ppm"
    "$root/scripts/render.sh" --size "$size" "$scene" > "$work/pipe.ppm"
    "$gl" --size "$size" "$scene" > "$work/gl.ppm"
    local against
    for against in ref pipe; do
        local out status=0
        out=$("$B/zspec" compare --min-agreement "$MIN_AGREEMENT" "$work/$against.ppm" "$work/gl.ppm" 2>&1) || status=$?
        local label=zspec; [[ $against == pipe ]] && label=render.sh
        echo "$out" | awk -v n="$name ($size, llvmpipe vs $label)" \
            '{ px += $3; d += $5; f++; if ($5 > worst) worst = $5 }
             END { printf "%-62s %d frame(s), %d of %d pixels differ (worst frame %d)\n", n, f, d, px, worst }'
        if ((status != 0)); then
            echo "FAIL $name: a frame agrees with $label on less than $MIN_AGREEMENT%"
            echo "$out" | sed 's/^/  /'
            fail=1
        fi
    done
}

check penetrating 500x500 examples/penetrating.txt
check cube 640x480 examples/cube.txt
check overlapping-squares 500x500 examples/overlapping-squares.txt
"$B/scene" environment --polygons 1024 --seed 1 --text > "$work/env.txt"
check "environment 1,024" 500x500 "$work/env.txt"
"$B/scene" environment --polygons 10000 --depth-complexity 10 --size 1920x1080 --seed 2 --text > "$work/fill.txt"
check "environment 10,000, Dc 10" 1920x1080 "$work/fill.txt"
"$B/scene" environment --polygons 1024 --frames 10 --seed 4 --text > "$work/movie.txt"
check "environment movie, 10 frames" 500x500 "$work/movie.txt"
# A camera of its own: eye, at, up, s, d, hither and yon all away from their defaults.
# shellcheck disable=SC2054 # the commas are the options' own (X,Y,Z), not separators
cam=(--eye 12,9,18 --at 1,-1,0 --up 0.2,1,0 --s 8 --d 14 --hither 3 --yon 40)
"$B/zspec" "${cam[@]}" --size 640x360 "$work/env.txt" > "$work/ref.ppm"
"$gl" "${cam[@]}" --size 640x360 "$work/env.txt" > "$work/gl.ppm"
if out=$("$B/zspec" compare --min-agreement "$MIN_AGREEMENT" "$work/ref.ppm" "$work/gl.ppm" 2>&1); then
    printf "%-62s %s\n" "environment 1,024, own camera (640x360, llvmpipe vs zspec)" "$out"
else
    echo "FAIL own camera: $out"
    fail=1
fi

# Bad input is refused with status 1 and a message naming the line.
bad() { # EXPECTED-MESSAGE-PART TEXT
    local status=0 err
    err=$(printf '%s' "$2" | "$gl" --size 8x8 2>&1 >/dev/null) || status=$?
    if ((status != 1)) || [[ $err != *"$1"* ]]; then
        echo "FAIL bad input '$2': status $status, message '$err' (wanted '$1')"
        fail=1
    fi
}
bad "expected the header" "hello"
bad "unsupported stream version" "polypipe 2 world END"
bad "expected a world-space scene" "polypipe 1 eye END"
bad "ends without END" "polypipe 1 world colour 1 2 3 0 0 0"
bad "expected a finite number" $'polypipe 1 world\ncolour 1 2 3\n0 0 nan\nEND'
bad "line 4: expected a finite number (x y z of a vertex), found 'END'" $'polypipe 1 world\ncolour 1 2 3\n0 0\nEND'
bad "colour component" "polypipe 1 world colour 1 2 256 END"
bad "expected 'colour' after NEXT.POLYGON" "polypipe 1 world colour 1 2 3 NEXT.POLYGON END"
bad "after END" "polypipe 1 world END more"
((fail == 0)) && echo "llvmpipe harness: all checks passed"
exit "$fail"
