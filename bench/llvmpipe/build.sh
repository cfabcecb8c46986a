#!/usr/bin/env bash
# build.sh: builds the Mesa llvmpipe harness (render.c, through OSMesa) with gcc -O2 and
# prints the path of the binary. Not part of cargo's build or CI: only bench llvmpipe
# and bench/llvmpipe/check.sh use it.
#
# Needs gcc and the OSMesa development files (Debian/Ubuntu: libosmesa6-dev). When they
# are missing and this runs as root with apt-get, it installs them; otherwise it says
# what to install and fails.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
src=$root/bench/llvmpipe/render.c
outdir=${CARGO_TARGET_DIR:-$root/target}/bench
out=$outdir/llvmpipe-render

command -v gcc >/dev/null || { echo "llvmpipe harness: gcc is needed (apt-get install gcc)" >&2; exit 1; }

have_osmesa() {
    printf '#include <GL/osmesa.h>\nint main(void) { return OSMesaGetCurrentContext() != 0; }\n' |
        gcc -x c - -o /dev/null -lOSMesa >/dev/null 2>&1
}
if ! have_osmesa; then
    if [[ $(id -u) == 0 ]] && command -v apt-get >/dev/null; then
        echo "llvmpipe harness: installing libosmesa6-dev" >&2
        { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libosmesa6-dev; } >&2
    fi
    have_osmesa || {
        echo "llvmpipe harness: OSMesa is missing; install it as root: apt-get install libosmesa6-dev" >&2
        echo "  (Fedora: dnf install mesa-libOSMesa-devel)" >&2
        exit 1
    }
fi

mkdir -p "$outdir"
if [[ ! -x $out || $src -nt $out || ${BASH_SOURCE[0]} -nt $out ]]; then
    gcc -O2 -Wall -Wextra -o "$out" "$src" -lOSMesa -lm >&2
fi
echo "$out"
