#!/usr/bin/env bash
# chart.sh: speed against accuracy of every method, and the thesis's cost model
# (docs/DESIGN.md, "Measures"; docs/model.md). A thin wrapper: it builds the binaries when they are
# missing or stale, then runs bins/chart, which runs
# scripts/render.sh as a user would for each scene, method and depth.
#
# Usage: scripts/chart.sh -o DIR [--quick] [--standard] [--hard] [--size WxH] [--reps N] SCENE[@WxH]…
#        scripts/chart.sh --figures [--reps N]    # docs/images: the standard and hard scenes
#        scripts/chart.sh calibrate [--quick]     # fit the cost model to this machine now
#        scripts/chart.sh thesis                  # thesis 5.2's timings and 6.4's depth
#        scripts/chart.sh choose-depth [--size WxH] [--cores N] SCENE   # plan depth's alias
# Writes DIR/results.csv, DIR/max-error.csv (what render --max-error E would choose on
# each scene, ringed on the speed-accuracy panels), DIR/speed-accuracy.png and .svg,
# DIR/cost-environment.png and .svg (each method's cost against the scenes' environment
# statistics), DIR/model.csv and DIR/model.png;
# the first run on a machine calibrates the model (at most 20 s). `chart.sh --help` tells
# the rest.

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
bindir='' # set by build_binaries
build_binaries

case ${1-} in
    choose-depth | calibrate) exec "$bindir/chart" "$@" --root "$root" ;;
    thesis) exec "$bindir/chart" "$@" ;;
    *) exec "$bindir/chart" --root "$root" "$@" ;;
esac
