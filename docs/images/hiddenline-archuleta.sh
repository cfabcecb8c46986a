#!/bin/bash
# hiddenline-archuleta.sh: draws docs/images/hiddenline-archuleta.png, Archuleta's three
# problems on his two spheres at 64x48: the window X 22-46, Y 10-38 of the frame, drawn
# by `hiddenline` (continuous, wide and grey) and `hiddenline --method archuleta` (thin
# and red) over the boundaries between scan lines (faint blue), 30 times enlarged.
#
# Usage: docs/images/hiddenline-archuleta.sh      (needs rsvg-convert: librsvg2-bin)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
cargo build --release --quiet -p scene -p viewxf -p clipbatch -p persp -p hiddenline
source scripts/lib/binaries.sh
B=$(release_bin "$root")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$B/scene" spheres | "$B/viewxf" --size 64x48 | "$B/clipbatch" | "$B/persp" --size 64x48 > "$work/frame"
"$B/hiddenline" < "$work/frame" > "$work/continuous.svg"
"$B/hiddenline" --method archuleta < "$work/frame" > "$work/archuleta.svg"
x=22 y=10 w=24 h=28 s=30
{
    echo "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"$((w * s))\" height=\"$((h * s))\" viewBox=\"$x $y $w $h\">"
    echo "<rect x=\"$x\" y=\"$y\" width=\"$w\" height=\"$h\" fill=\"white\"/>"
    echo '<g stroke="rgb(200,215,240)" stroke-width="0.04">'
    for ((r = y; r <= y + h; r++)); do echo "<line x1=\"$x\" y1=\"$r\" x2=\"$((x + w))\" y2=\"$r\"/>"; done
    echo '</g><g fill="none" stroke-width="0.3" stroke-linecap="round" stroke="rgb(160,160,160)">'
    grep '<line' "$work/continuous.svg" | sed 's/ stroke="[^"]*"//'
    echo '</g><g fill="none" stroke-width="0.08" stroke-linecap="round" stroke="rgb(220,0,0)">'
    grep '<line' "$work/archuleta.svg" | sed 's/ stroke="[^"]*"//'
    echo '</g></svg>'
} > "$work/both.svg"
rsvg-convert "$work/both.svg" -o docs/images/hiddenline-archuleta.png
echo "wrote docs/images/hiddenline-archuleta.png" >&2
