#!/usr/bin/env bash
# hostile-pictures.sh: the painter's and the a-buffer's failure pictures of
# docs/methods.md, remade. Needs python3 (its zlib writes the PNGs); no
# ImageMagick. Not CI.
#   docs/images/painter-planes-{5,50}.png  scene planes 5, 50, 250x250: zbuf, painter,
#                                    painter --split, and the pixels --split gets wrong
#   docs/images/abuf-depth-extent.png  examples/screen/abuf-depth-extent.txt: the 8x8
#                                    supersampled reference, abuf, |difference| x4,
#                                    each pixel drawn 12x12
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
cargo build --release --quiet -p scene -p viewxf -p clipbatch -p persp -p scanconv -p zbuf -p painter -p abuf -p supersample
# shellcheck source=lib/binaries.sh
source "$root/scripts/lib/binaries.sh"
B=$(release_bin "$root")
out=$root/docs/images
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for n in 5 50; do
    "$B/scene" planes $n | "$B/viewxf" | "$B/clipbatch" | "$B/persp" --size 250x250 > "$work/planes$n.scr"
    "$B/scanconv" --resolve < "$work/planes$n.scr" | "$B/zbuf" > "$work/planes$n-zbuf.ppm"
    "$B/painter" < "$work/planes$n.scr" | "$B/zbuf" > "$work/planes$n-painter.ppm"
    "$B/painter" --split < "$work/planes$n.scr" 2> /dev/null | "$B/zbuf" > "$work/planes$n-split.ppm"
done
"$B/supersample" --samples 8 < examples/screen/abuf-depth-extent.txt | "$B/zbuf" > "$work/ext-ss8.ppm"
"$B/abuf" < examples/screen/abuf-depth-extent.txt | "$B/zbuf" > "$work/ext-abuf.ppm"

python3 - "$work" "$out" <<'PY'
import struct, sys, zlib

work, out = sys.argv[1], sys.argv[2]

def read_ppm(path):
    data = open(path, "rb").read()
    fields, i = [], 0
    while len(fields) < 4:
        while data[i:i + 1].isspace():
            i += 1
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        fields.append(data[i:j])
        i = j
    w, h = int(fields[1]), int(fields[2])
    px = data[i + 1:i + 1 + 3 * w * h]
    return w, h, [list(px[r * 3 * w:(r + 1) * 3 * w]) for r in range(h)]

def scale(img, k):
    w, h, rows = img
    return w * k, h * k, [sum(([r[3 * (x // k)], r[3 * (x // k) + 1], r[3 * (x // k) + 2]] for x in range(w * k)), []) for r in rows for _ in range(k)]

def diff(a, b, gain, mark=None):
    w, h, ra = a
    rows = []
    for y in range(h):
        row = []
        for x in range(3 * w):
            d = abs(ra[y][x] - b[2][y][x])
            row.append(min(255, d * gain))
        if mark:
            row = sum(([255, 255, 0] if any(row[3 * x:3 * x + 3]) else [0, 0, 0] for x in range(w)), [])
        rows.append(row)
    return w, h, rows

def montage(images, path, gap=6):
    h = max(i[1] for i in images)
    w = sum(i[0] for i in images) + gap * (len(images) + 1)
    rows = []
    for y in range(h + 2 * gap):
        row = [255] * (3 * gap)
        for img in images:
            iw, ih, ir = img
            yy = y - gap
            row += ir[yy] if 0 <= yy < ih else [255] * (3 * iw)
            row += [255] * (3 * gap)
        rows.append(bytes(row))
    raw = b"".join(b"\0" + r for r in rows)
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h + 2 * gap, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)

planes = []
for n in (5, 50):
    z = read_ppm(f"{work}/planes{n}-zbuf.ppm")
    p = read_ppm(f"{work}/planes{n}-painter.ppm")
    s = read_ppm(f"{work}/planes{n}-split.ppm")
    planes += [z, p, s, diff(z, s, 1, mark=True)]
montage(planes[:4], f"{out}/painter-planes-5.png")
montage(planes[4:], f"{out}/painter-planes-50.png")
ss = read_ppm(f"{work}/ext-ss8.ppm")
ab = read_ppm(f"{work}/ext-abuf.ppm")
montage([scale(ss, 12), scale(ab, 12), scale(diff(ss, ab, 4), 12)], f"{out}/abuf-depth-extent.png")
PY
echo "hostile-pictures.sh: wrote $out/painter-planes-5.png, painter-planes-50.png, abuf-depth-extent.png" >&2
