#!/usr/bin/env bash
# methods-pictures.sh: the pictures of docs/methods.md, remade: where the painter's depth
# sort fails (the thesis's penetrating polygons; three bars in a cyclic overlap), beside
# the z-buffer's frame and the wrong pixels. Needs ImageMagick (montage, compare). Not CI.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cargo build --release --quiet --bins
# shellcheck source=lib/binaries.sh
source "$root/scripts/lib/binaries.sh"
B=$(release_bin "$root")
out=$root/docs/images
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The penetrating scene at 250x250 (depth 0), z-buffer and painter, and where they differ.
scripts/render.sh --size 250x250 -o "$work/pen-zbuf.png"
scripts/render.sh --size 250x250 --hse painter -o "$work/pen-painter.png"
compare -metric AE "$work/pen-zbuf.png" "$work/pen-painter.png" \
    -highlight-color yellow -lowlight-color black -compose src "$work/pen-diff.png" 2>/dev/null || true
montage -label 'zbuf (exact)' "$work/pen-zbuf.png" -label 'painter' "$work/pen-painter.png" \
    -label 'pixels that differ' "$work/pen-diff.png" -tile 3x1 -geometry +6+6 \
    -pointsize 16 "$out/methods-penetrating.png"

# Three bars in a cyclic overlap (screen space): z-buffer, painter, painter --split.
for m in "scanconv --resolve" painter "painter --split"; do
    name=${m// /}
    $B/$m < examples/screen/cyclic-bars.txt | "$B/zbuf" -o "$work/cyc-$name.png"
done
montage -label 'zbuf (exact)' "$work/cyc-scanconv--resolve.png" -label 'painter' "$work/cyc-painter.png" \
    -label 'painter --split' "$work/cyc-painter--split.png" -tile 3x1 -geometry +6+6 \
    -pointsize 16 "$out/methods-cyclic.png"
echo "methods-pictures.sh: wrote $out/methods-penetrating.png and $out/methods-cyclic.png" >&2
