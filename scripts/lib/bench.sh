# shellcheck shell=bash
# bench.sh (library): what the benchmark scripts share. Sourced, not run.
#
#   bench_build                the binaries, built when missing or stale; sets `bindir`
#   release_bin ROOT           the folder of ROOT's release binaries, after a cargo build
#                              (scripts/lib/binaries.sh)
#   seconds CMD…               wall seconds of one run (bash's microsecond clock), output
#                              to /dev/null
#   cpu_seconds CMD…           user + system seconds of one run (bash's `time`, ms)
#   peak_kib CMD…              peak resident memory of one run, KiB (GNU time's %M)
#   median / best              the median / least of the numbers on stdin
#   timed REPS CMD…            the median wall seconds of REPS runs: hyperfine where it is
#                              installed (one warm-up, its own statistics), else `seconds`
#   ratio A B                  A / B to two places, `-` where either is not positive
#   fill_scene BIN [N [WxH]]   the fill-heavy scene as text on stdout, made by BIN/scene:
#                              environment, seed 2, depth complexity 10, N polygons
#                              (default 10,000) at WxH (default 1920x1080)
#
# Wall times come from the clock, not from /usr/bin/time's %e (10 ms steps, too coarse
# for runs of 30-100 ms). A script compares commands measured in one run, on one machine,
# and says so: ratios, not seconds, are what carry over.

bench_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# shellcheck source=binaries.sh
source "$bench_root/scripts/lib/binaries.sh" # release_bin, and bench_build's build_binaries

bench_build() {
    local root=$bench_root me=${0##*/}
    fail() {
        echo "$me: $2" >&2
        exit "$1"
    }
    build_binaries
}

seconds() {
    local t0=$EPOCHREALTIME
    "$@" >/dev/null 2>&1
    awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.6f\n", b - a }'
}

cpu_seconds() {
    local TIMEFORMAT='%3U %3S' line
    line=$({ time "$@" >/dev/null 2>&1; } 2>&1)
    awk '{ printf "%.3f\n", $1 + $2 }' <<<"$line"
}

peak_kib() {
    local f
    f=$(mktemp "${TMPDIR:-/tmp}/bench-rss.XXXXXX")
    /usr/bin/time -f %M -o "$f" "$@" >/dev/null 2>&1
    tail -n 1 "$f"
    rm -f "$f"
}

median() { sort -g | awk '{ t[NR] = $1 } END { if (NR) printf "%.3f", NR % 2 ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2 }'; }

best() { sort -g | head -n 1; }

timed() {
    local reps=$1 i
    shift
    if command -v hyperfine >/dev/null; then
        local json
        json=$(mktemp "${TMPDIR:-/tmp}/bench-hyperfine.XXXXXX")
        local line=""
        for i in "$@"; do line+=" $(printf '%q' "$i")"; done
        hyperfine -N --style none --warmup 1 --runs "$reps" --export-json "$json" \
            "${line# }" >/dev/null 2>&1
        awk -F: '/"median"/ { gsub(/[ ,]/, "", $2); printf "%.3f", $2; exit }' "$json"
        rm -f "$json"
        return
    fi
    for ((i = 0; i < reps; i++)); do seconds "$@"; done | median
}

ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a > 0 && b > 0) printf "%.2f", a / b; else printf "-" }'; }

fill_scene() {
    "$1/scene" environment --text --seed 2 --polygons "${2:-10000}" --depth-complexity 10 \
        --size "${3:-1920x1080}"
}
