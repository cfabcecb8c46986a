#!/usr/bin/env bash
# chart.sh: speed against accuracy of every method, and the thesis's cost model
# (docs/DESIGN.md, "Measures"). A thin wrapper: it builds the binaries when they are
# missing or stale, then runs bins/chart, which runs
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

# The binaries chart and render.sh run, built only when missing or older than their
# sources (render.sh's check, scripts/lib/binaries.sh): cargo is not run at all on
# most runs.
me=chart.sh
fail() {
    echo "chart.sh: $2" >&2
    exit "$1"
}
# shellcheck source=lib/binaries.sh
source "$root/scripts/lib/binaries.sh"
build_binaries
# shellcheck disable=SC2154 # bindir, set by build_binaries

case ${1-} in
    choose-depth) exec "$bindir/chart" "$@" --root "$root" ;;
    *) exec "$bindir/chart" --root "$root" "$@" ;;
esac
