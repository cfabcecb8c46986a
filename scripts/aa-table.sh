#!/usr/bin/env bash
# aa-table.sh: the error table of docs/antialiasing.md: each anti-aliasing leaf of
# render.sh (--aa) against the exact 16×16 reference (`zspec --samples 16`), on the
# scenes of tests/tests/surfaces/antialiasing.rs, through a splitter tree of depth D built as
# render.sh builds it (splitter --node K), every leaf `persp | METHOD`, merged by zbuf.
# Columns: `zspec compare --metrics --edges`'s overall edge-pixel RMSE and whole-frame
# RMSE (0-255 units), and the share of pixels differing from the 16×16 reference.
#
# Usage: scripts/aa-table.sh [WxH] [DEPTH] [PICTURES_DIR]
#   (defaults 64x48 0; with a folder, also writes there each scene's frames as PNGs,
#   side by side: point, ss4, abuf, reference, magnified 4×)
set -euo pipefail
# shellcheck source=lib/bench.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/bench.sh"

for arg in "$@"; do
  case $arg in
    -h | --help) bench_help; exit 0 ;;
    -*) bench_usage "unknown option $arg" ;;
  esac
done
SIZE=${1:-64x48}
DEPTH=${2:-0}
PICS=${3:-}
ROOT=$bench_root
TMP=$(mktemp -d "${TMPDIR:-/tmp}/aa-table.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

bench_build
export PATH=$bindir:$PATH

scene environment --polygons 200 --seed 7 >"$TMP/environment.pp"
scene sphere --stacks 8 --slices 12 >"$TMP/sphere.pp"
cp "$ROOT/examples/penetrating.txt" "$TMP/penetrating.pp"
scene needles >"$TMP/needles.pp"

# render SCENE METHOD...: the frame through a tree of depth DEPTH.
render() {
  local scene=$1 n l leaves=()
  shift
  viewxf --size "$SIZE" <"$scene" | clipbatch >"$TMP/node-1"
  for ((n = 1; n < 1 << DEPTH; n++)); do
    splitter --node $n --depth "$DEPTH" --size "$SIZE" "$TMP/node-$((2 * n))" \
      "$TMP/node-$((2 * n + 1))" <"$TMP/node-$n"
  done
  for ((l = 0; l < 1 << DEPTH; l++)); do
    persp --size "$SIZE" <"$TMP/node-$(((1 << DEPTH) + l))" | "$@" >"$TMP/leaf-$l"
    leaves+=("$TMP/leaf-$l")
  done
  zbuf "${leaves[@]}"
}

mapfile -t methods < <(methods_list aa)
echo "against zspec --samples 16, $SIZE, tree depth $DEPTH"
printf '%-12s %-6s %9s %9s %10s\n' scene method edge_rmse rmse differing
for scene in environment sphere penetrating needles; do
  zspec --size "$SIZE" --samples 16 --edge-mask "$TMP/edges.ppm" <"$TMP/$scene.pp" >"$TMP/ref.ppm"
  for method in "${methods[@]}"; do
    IFS=$'\t' read -r m leaf <<<"$method"
    read -ra cmd <<<"$leaf"
    render "$TMP/$scene.pp" "${cmd[@]}" >"$TMP/$m.ppm"
    zspec compare --metrics --edges "$TMP/edges.ppm" "$TMP/ref.ppm" "$TMP/$m.ppm" \
      | awk -v s="$scene" -v m="$m" '/^overall/ { for (i = 1; i < NF; i++) v[$i] = $(i + 1);
          printf "%-12s %-6s %9.2f %9.2f %10.4f\n", s, m, v["edge_rmse"], v["rmse"],
            v["differing_fraction"] }'
  done
  if [[ -n $PICS ]]; then
    mkdir -p "$PICS"
    # Side by side, magnified 4×, 4 pixels of white between: as a stream of `run`
    # records, which zbuf -o writes as a PNG.
    python3 - "$TMP"/{point,ss4,abuf,ref}.ppm <<'PY' | zbuf -o "$PICS/aa-$scene.png"
import sys
def ppm(path):
    data = open(path, 'rb').read()
    fields, i = [], 0
    while len(fields) < 4:
        while data[i:i+1].isspace(): i += 1
        j = i
        while not data[j:j+1].isspace(): j += 1
        fields.append(data[i:j]); i = j
    w, h = int(fields[1]), int(fields[2])
    px = data[i+1:i+1+3*w*h]
    return w, h, px
frames = [ppm(p) for p in sys.argv[1:]]
w, h = frames[0][0], frames[0][1]
z, gap = 4, 4
W = len(frames) * (w * z + gap) - gap
print(f"polypipe 2 fragments {W} {h * z}")
for y in range(h * z):
    print(f"run {y} 0 {W} 255 255 255")
for k, (_, _, px) in enumerate(frames):
    x0 = k * (w * z + gap)
    for y in range(h * z):
        for x in range(w):
            o = 3 * ((y // z) * w + x)
            r, g, b = px[o], px[o+1], px[o+2]
            print(f"run {y} {x0 + x * z} {x0 + x * z + z} {r} {g} {b}")
print("END")
PY
  fi
done
