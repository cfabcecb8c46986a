#!/usr/bin/env bash
# render.sh: the `render` binary (bins/render; `render --help`), built first when missing.
# It becomes render, telling it the repository (POLYPIPE_SOURCES), and render rebuilds
# the binaries with cargo when a source is newer than them (a look that costs well under
# a millisecond; `cargo build` with nothing to do takes 0.1 s). A host's POLYPIPE_BIN
# names its folder of binaries, run as they are.
[ -n "${BASH_VERSION-}" ] || { echo "render.sh: needs bash (this is not bash)" >&2; exit 3; }
set -u
if [[ -n ${POLYPIPE_BIN-} && -x $POLYPIPE_BIN/render ]]; then exec "$POLYPIPE_BIN/render" "$@"; fi
# The repository, through a symlink to this script: its folder resolved by cd, not a process.
script=${BASH_SOURCE[0]}
[[ ! -L $script ]] || script=$(readlink -f -- "$script") || exit 3
here=$PWD dir=.
[[ $script != */* ]] || dir=${script%/*}
CDPATH='' cd -P -- "$dir/.." || { echo "render.sh: cannot find where render.sh lives" >&2; exit 3; }
root=$PWD
cd -- "$here" || exit 3
# shellcheck source=lib/binaries.sh
source "$root/scripts/lib/binaries.sh"
find_binaries
if [[ ! -x $bindir/render ]]; then
    command -v cargo >/dev/null || {
        echo "render.sh: cannot build the polypipe binaries into $bindir: cargo is not on PATH (Rust: https://rustup.rs)" >&2
        exit 3
    }
    echo "render.sh: building the polypipe binaries (first run only)…" >&2
    build_binaries
fi
POLYPIPE_SOURCES=$root exec "$bindir/render" "$@"
