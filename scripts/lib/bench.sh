# shellcheck shell=bash
# bench.sh (library): what the benchmark scripts share. Sourced, not run.
#
#   bench_options "$@"         the options every benchmark takes: --quick (sets `quick`
#                              to 1), --reps N (sets `reps`), -h/--help (prints the
#                              script's opening comment); the other words in `args`
#   bench_usage MESSAGE        says MESSAGE as a usage error and exits 2
#   bench_build                the binaries, built when missing or stale; sets `bindir`
#   bench_stamp                "Measured by `scripts/NAME ARGS` at commit …, N cores, date"
#   release_bin ROOT           the folder of ROOT's release binaries, after a cargo build
#                              (scripts/lib/binaries.sh)
#   methods_list KIND          the methods a benchmark runs, one `NAME<TAB>LEAF COMMAND` a
#                              line: KIND `hse` render's hidden-surface methods (--hse
#                              NAME), `aa` its anti-aliasing leaves (--aa NAME, `point`
#                              for none), `lines` the hidden-line drawing
#   method_leaf KIND NAME      the leaf command of method NAME of methods_list KIND
#   leaf_words ARRAY WORDS     sets ARRAY to the command WORDS, its binary in `bindir`
#                              (shellcheck sees ARRAY set when the script sets it to ())
#   seconds CMD…               wall seconds of one run (bash's microsecond clock), output
#                              to /dev/null
#   cpu_seconds CMD…           user + system seconds of one run (bash's `time`, ms)
#   peak_kib CMD…              peak resident memory of one run, KiB (GNU time's %M)
#   timed REPS CMD…            the median wall seconds of REPS runs: hyperfine where it is
#                              installed (one warm-up, its own statistics), else `seconds`
#   best_of REPS FN CMD…       the least of REPS runs of `FN CMD…` (seconds, cpu_seconds)
#   reading FILE CMD…          CMD with its stdin from FILE, opened afresh each run: for
#                              the functions above, which leave stdin as it is
#   median / best              the median / least of the numbers on stdin
#   quotient A B [PLACES]      A / B to PLACES places (default 2), `-` unless both > 0
#   ratio A B                  quotient A B 2
#   stat_count LINE WORDS      the number before WORDS in a stage's --stats LINE
#   differing A.ppm B.ppm      the pixels of B unlike A's, all frames (needs `bindir`)
#   to_screen WxH              world space on stdin to screen space on stdout: viewxf |
#                              clipbatch | persp at WxH (needs `bindir`)
#   fill_scene BIN [N [WxH]]   the fill-heavy scene as text on stdout, made by BIN/scene:
#                              environment, seed 2, depth complexity 10, N polygons
#                              (default 10,000) at WxH (default 1920x1080)
#
# A command that `seconds`, `cpu_seconds`, `peak_kib` or `timed` runs must succeed: when
# it fails, the function prints nothing on stdout, says on stderr which command failed
# with what status and the last line it wrote there, and returns that status, so that a
# failing command is never timed as a fast success (under `set -e` the script stops).
#
# Wall times come from the clock, not from /usr/bin/time's %e (10 ms steps, too coarse
# for runs of 30-100 ms). A script compares commands measured in one run, on one machine,
# and says so: ratios, not seconds, are what carry over.

bench_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bench_me=${0##*/}
bench_argv=''
# shellcheck source=binaries.sh
source "$bench_root/scripts/lib/binaries.sh" # release_bin, and bench_build's build_binaries

bench_usage() {
    echo "$bench_me: $1 (--help says more)" >&2
    exit 2
}

# shellcheck disable=SC2034 # quick, reps and args are the calling script's
bench_options() {
    bench_argv=$*
    args=()
    while (($#)); do
        case $1 in
            --quick) quick=1 ;;
            --reps)
                [[ ${2-} =~ ^[1-9][0-9]*$ ]] || bench_usage "--reps needs a whole number above 0"
                reps=$2
                shift
                ;;
            -h | --help)
                bench_help
                exit 0
                ;;
            -*) bench_usage "unknown option $1" ;;
            *) args+=("$1") ;;
        esac
        shift
    done
}

bench_build() {
    local root=$bench_root me=$bench_me
    fail() {
        echo "$me: $2" >&2
        exit "$1"
    }
    build_binaries
}

# The opening comment of the script that sourced this, from its second line to the first
# line that is not a comment.
bench_help() { sed -n '2,/^[^#]/{/^#/s/^# \{0,1\}//p}' "$0"; }

bench_stamp() {
    printf 'Measured by `scripts/%s%s` at commit %s, %s cores, %s' "$bench_me" \
        "${bench_argv:+ $bench_argv}" "$(git -C "$bench_root" rev-parse --short HEAD 2>/dev/null || echo unknown)" \
        "$(nproc)" "$(date -u '+%Y-%m-%d %H:%M UTC')"
}

# methods_list KIND: see above. The rows come from the table of methods (methods/src/lib.rs)
# as `render --list-methods` prints it (a header, then NAME, SELECTOR, OPTIONS, STAGE, …
# tab-separated), so that the benchmarks run what render runs: the rows whose selector is
# `hse:NAME`, `aa:NAME` (after `point`, no anti-aliasing, which is zbuf's leaf) or
# `hidden-line:continuous` (the hiddenline stage's own method), each with its stage.
methods_list() {
    local rows name selector stage want
    case $1 in
        hse) want=hse: ;;
        aa) want=aa: ;;
        lines) want=hidden-line:continuous ;;
        *)
            echo "$bench_me: methods_list: no kind '$1' (kinds: hse aa lines)" >&2
            return 2
            ;;
    esac
    rows=$("${bindir:?methods_list needs bindir}/render" --list-methods) || {
        echo "$bench_me: methods_list: \`$bindir/render --list-methods\` failed" >&2
        return 3
    }
    if [[ $1 == aa ]]; then
        printf 'point\t%s\n' "$(awk -F'\t' '$2 == "hse:zbuf" { print $4 }' <<<"$rows")"
    fi
    while IFS=$'\t' read -r name selector _ stage _; do
        if [[ $selector == "$want"* ]]; then
            printf '%s\t%s\n' "$name" "$stage"
        fi
    done < <(tail -n +2 <<<"$rows")
}

method_leaf() {
    local rows name leaf
    rows=$(methods_list "$1") || return
    while IFS=$'\t' read -r name leaf; do
        [[ $name == "$2" ]] && { echo "$leaf"; return 0; }
    done <<<"$rows"
    echo "$bench_me: methods_list $1 has no method '$2'" >&2
    return 2
}

leaf_words() {
    local -n words=$1
    read -r -a words <<<"$2"
    words[0]=${bindir:?leaf_words needs bindir}/${words[0]}
}

# bench_failed STATUS ERRFILE CMD…: the one message for a measured command that failed.
bench_failed() {
    local status=$1 err=$2 last=''
    shift 2
    [[ -s $err ]] && last=$(tail -n 1 "$err")
    echo "$bench_me: \`$*\` failed with status $status${last:+: $last}" >&2
}

# The clock and `time` print their decimal point by the locale; the sums are done in
# whole micro- or milliseconds, in bash.
seconds() {
    local err t0 t1 status=0
    err=$(mktemp "${TMPDIR:-/tmp}/bench-err.XXXXXX")
    t0=$EPOCHREALTIME
    "$@" >/dev/null 2>"$err" || status=$?
    t1=$EPOCHREALTIME
    ((status == 0)) || bench_failed "$status" "$err" "$@"
    rm -f "$err"
    ((status == 0)) || return "$status"
    local us=$((10#${t1/[.,]/} - 10#${t0/[.,]/}))
    printf '%d.%06d\n' $((us / 1000000)) $((us % 1000000))
}

cpu_seconds() {
    local TIMEFORMAT='%3U %3S' err times status=0 u s
    err=$(mktemp "${TMPDIR:-/tmp}/bench-err.XXXXXX")
    times=$(mktemp "${TMPDIR:-/tmp}/bench-time.XXXXXX")
    { time "$@" >/dev/null 2>"$err"; } 2>"$times" || status=$?
    ((status == 0)) || bench_failed "$status" "$err" "$@"
    read -r u s <"$times"
    rm -f "$err" "$times"
    ((status == 0)) || return "$status"
    local ms=$((10#${u/[.,]/} + 10#${s/[.,]/}))
    printf '%d.%03d\n' $((ms / 1000)) $((ms % 1000))
}

peak_kib() {
    if [[ ! -x /usr/bin/time ]]; then
        echo "$bench_me: peak_kib needs GNU time as /usr/bin/time (Debian's package time)" >&2
        return 3
    fi
    local err f status=0
    err=$(mktemp "${TMPDIR:-/tmp}/bench-err.XXXXXX")
    f=$(mktemp "${TMPDIR:-/tmp}/bench-rss.XXXXXX")
    /usr/bin/time -f %M -o "$f" "$@" >/dev/null 2>"$err" || status=$?
    if ((status == 0)); then tail -n 1 "$f"; else bench_failed "$status" "$err" "$@"; fi
    rm -f "$err" "$f"
    return "$status"
}

median() { sort -g | awk '{ t[NR] = $1 } END { if (NR) printf "%.3f", NR % 2 ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2 }'; }

best() { sort -g | head -n 1; }

timed() {
    local reps=$1 i t times=''
    shift
    if command -v hyperfine >/dev/null; then
        local json err line='' status=0
        json=$(mktemp "${TMPDIR:-/tmp}/bench-hyperfine.XXXXXX")
        err=$(mktemp "${TMPDIR:-/tmp}/bench-err.XXXXXX")
        for i in "$@"; do line+=" $(printf '%q' "$i")"; done
        hyperfine -N --style none --warmup 1 --runs "$reps" --export-json "$json" \
            "${line# }" >/dev/null 2>"$err" || status=$?
        if ((status == 0)); then
            awk -F: '/"median"/ { gsub(/[ ,]/, "", $2); printf "%.3f", $2; exit }' "$json"
        else
            bench_failed "$status" "$err" "$@"
        fi
        rm -f "$json" "$err"
        return "$status"
    fi
    for ((i = 0; i < reps; i++)); do
        t=$(seconds "$@") || return
        times+=$t$'\n'
    done
    printf '%s' "$times" | median
}

best_of() {
    local reps=$1 i t all=''
    shift
    for ((i = 0; i < reps; i++)); do
        t=$("$@") || return
        all+=$t$'\n'
    done
    printf '%s' "$all" | best
}

reading() { "${@:2}" <"$1"; }

quotient() { awk -v a="$1" -v b="$2" -v p="${3:-2}" 'BEGIN { if (a > 0 && b > 0) printf "%.*f", p, a / b; else printf "-" }'; }

ratio() { quotient "$1" "$2" 2; }

stat_count() {
    local re="([0-9]+) $2"
    if [[ $1 =~ $re ]]; then
        echo "${BASH_REMATCH[1]}"
    else
        echo "$bench_me: no count of '$2' in: $1" >&2
        return 1
    fi
}

# zspec compare --metrics --csv: a row per frame and one `overall`,
# `frame,pixels,differing,…`; zspec says itself what is wrong with a frame it cannot read.
differing() {
    local csv re=$'(^|\n)overall,[0-9]+,([0-9]+),'
    csv=$("${bindir:?differing needs bindir}/zspec" compare --metrics --csv "$1" "$2") || return
    if [[ $csv =~ $re ]]; then
        echo "${BASH_REMATCH[2]}"
    else
        echo "$bench_me: zspec compare $1 $2 gave no overall row" >&2
        return 1
    fi
}

to_screen() {
    "${bindir:?to_screen needs bindir}/viewxf" --size "$1" | "$bindir/clipbatch" |
        "$bindir/persp" --size "$1"
}

fill_scene() {
    "$1/scene" environment --text --seed 2 --polygons "${2:-10000}" --depth-complexity 10 \
        --size "${3:-1920x1080}"
}
