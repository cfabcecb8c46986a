#!/usr/bin/env bash
# chart.sh: speed against accuracy of every method, and the thesis's cost model
# (docs/DESIGN.md, "Measures"). A thin wrapper: it builds the binaries when cargo is there
# (cargo leaves them alone when they are current), then runs bins/chart, which runs
# scripts/render.sh as a user would for each scene, method and depth.
#
# Usage: scripts/chart.sh -o DIR [--quick] [--calibrate] [--standard] [--size WxH] [--reps N] SCENE[@WxH]…
#        scripts/chart.sh choose-depth [--size WxH] [--cores N] SCENE
# Writes DIR/results.csv, DIR/speed-accuracy.png and .svg, DIR/model.csv and DIR/model.png;
# --calibrate first measures the model's constants into bench/model.toml. `chart.sh --help`
# tells the rest.
set -u

script=$(readlink -f -- "${BASH_SOURCE[0]}") || { echo "chart.sh: cannot find where chart.sh lives" >&2; exit 3; }
root=${script%/*/*}
target=${CARGO_TARGET_DIR:-target}
[[ $target == /* ]] || target=$root/$target
bindir=$target/release

# The binaries chart and render.sh run, built together (render.sh would build the others
# on its first run, but chart runs zspec, scene and frames before that).
binaries=(chart viewxf clipplane clipbatch splitter persp scanconv zbuf scene zspec frames)
if command -v cargo >/dev/null; then
    packages=()
    for b in "${binaries[@]}"; do packages+=(-p "$b"); done
    (cd "$root" && cargo build --release --quiet "${packages[@]}") >&2 ||
        { echo "chart.sh: cargo build failed" >&2; exit 3; }
elif [[ ! -x $bindir/chart ]]; then
    echo "chart.sh: no $bindir/chart, and cargo is not on PATH to build it (Rust: https://rustup.rs)" >&2
    exit 3
fi

case ${1-} in
    choose-depth) exec "$bindir/chart" "$@" --root "$root" ;;
    *) exec "$bindir/chart" --root "$root" "$@" ;;
esac
