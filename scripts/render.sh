#!/usr/bin/env bash
# render.sh: compose the polypipe stages into the thesis's pipeline, the way occam's PAR
# wires channels (DESIGN.md, "The stages"; thesis chapter 6.3, CLIPPER/SPLITTER):
#
#   viewxf | clipplane left | right | top | bottom | hither | yon
#     depth 0:  | persp | scanconv | zbuf
#     depth N:  | a binary tree of splitter nodes, N levels alternating x and y planes,
#               each node bisecting its own rectangle of the screen on a pixel boundary;
#               persp | scanconv on each of the 2^N leaves; one zbuf reading all leaves.
#               The picture is byte for byte depth 0's (cut edges carry their original
#               edge, cut polygons their whole plane: proto/src/polygon.rs).
#
# Every stage is a process of its own, joined to the next by a named pipe in a private
# temporary directory. The script watches them all: when one fails (or is killed), it
# names it, stops the others and exits non-zero. The directory and every child are
# removed on every way out (success, failure, Ctrl-C, SIGTERM).

set -u

usage() {
    cat <<'EOF'
Usage: render.sh [OPTIONS] [SCENE]

Renders a world-space scene (text or binary; `-` for stdin; default
examples/penetrating.txt) and writes one binary PPM (P6) per frame on stdout.

Options:
  --size WxH        screen size in pixels (default 500x500)
  --depth N         splitter tree depth, 0 to 6 (default 0: no splitter)
  --eye X,Y,Z  --at X,Y,Z  --up X,Y,Z  --s S  --d D  --hither K1  --yon K2
                    camera and view volume, passed to viewxf
  --zmode MODE      persp's depth: projective (default) or eye-z
  --merge MODE      tiles (default): each leaf resolves its region, zbuf places the
                    finished pixels; buffer: the thesis's PAR.BUFF, every fragment
                    depth-tested in the one zbuf
  --stats           splitter nodes, scan converters and zbuf print counts on stderr
  -o PATTERN        zbuf writes one file per frame (e.g. frame%04d.png) instead
  -h, --help        this text

Examples:
  scripts/render.sh > penetrating.ppm
  scripts/render.sh --depth 3 --size 640x480 --eye 10,10,20 scene.txt > out.ppm
  scene environment --frames 10 | scripts/render.sh --depth 2 - -o frame%03d.png
EOF
}

die_usage() {
    echo "render.sh: $*" >&2
    echo "Try 'render.sh --help'." >&2
    exit 2
}

size=500x500
depth=0
merge=tiles
stats=()
zmode=()
outopt=()
camera=()
scene=
scene_given=0

while (($# > 0)); do
    case $1 in
        -h | --help) usage; exit 0 ;;
        --size) (($# >= 2)) || die_usage "--size needs WxH"; size=$2; shift 2 ;;
        --size=*) size=${1#*=}; shift ;;
        --depth) (($# >= 2)) || die_usage "--depth needs N"; depth=$2; shift 2 ;;
        --depth=*) depth=${1#*=}; shift ;;
        --eye | --at | --up | --s | --d | --hither | --yon)
            (($# >= 2)) || die_usage "$1 needs a value"
            camera+=("$1" "$2"); shift 2 ;;
        --eye=* | --at=* | --up=* | --s=* | --d=* | --hither=* | --yon=*)
            camera+=("$1"); shift ;;
        --merge) (($# >= 2)) || die_usage "--merge needs tiles or buffer"; merge=$2; shift 2 ;;
        --merge=*) merge=${1#*=}; shift ;;
        --zmode) (($# >= 2)) || die_usage "--zmode needs a mode"; zmode=(--depth "$2"); shift 2 ;;
        --stats) stats=(--stats); shift ;;
        -o) (($# >= 2)) || die_usage "-o needs a PATTERN"; outopt=(-o "$2"); shift 2 ;;
        -) ((scene_given == 0)) || die_usage "more than one SCENE"
            scene=-; scene_given=1; shift ;;
        -*) die_usage "unknown option $1" ;;
        *) ((scene_given == 0)) || die_usage "more than one SCENE"
            scene=$1; scene_given=1; shift ;;
    esac
done

[[ $depth =~ ^[0-6]$ ]] || die_usage "--depth must be an integer from 0 to 6, not '$depth'"
[[ $merge == tiles || $merge == buffer ]] || die_usage "--merge must be tiles or buffer, not '$merge'"
[[ $size =~ ^[0-9]+[xX][0-9]+$ ]] || die_usage "--size must be WxH, e.g. 500x500, not '$size'"

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd) || exit 3
if ((scene_given == 0)); then
    scene=$root/examples/penetrating.txt
fi
if [[ $scene != - && ! -r $scene ]]; then
    echo "render.sh: cannot read scene $scene" >&2
    exit 3
fi

# --- The binaries: build them if they are missing or older than their sources. -------
# Only the stages used here (and proto) are checked and built, so that a crate the
# pipeline does not run cannot hold it up.
bindir=${CARGO_TARGET_DIR:-$root/target}/release
stages=(viewxf clipplane splitter persp scanconv zbuf)
sources=("$root/proto" "$root/scan" "$root/Cargo.toml" "$root/Cargo.lock")
packages=()
for b in "${stages[@]}"; do
    sources+=("$root/bins/$b")
    packages+=(-p "$b")
done
stale=0
for b in "${stages[@]}"; do
    if [[ ! -x $bindir/$b ]] ||
        [[ -n $(find "${sources[@]}" \( -name '*.rs' -o -name Cargo.toml -o -name Cargo.lock \) \
            -newer "$bindir/$b" -print -quit 2>/dev/null) ]]; then
        stale=1
        break
    fi
done
if ((stale)); then
    (cd "$root" && cargo build --release --quiet "${packages[@]}") >&2 || {
        echo "render.sh: cargo build failed" >&2
        exit 3
    }
fi

# --- The tree's planes, worked out before any stage starts. ---------------------------
source "$root/scripts/tree-planes.sh" || exit 3
tree_planes "${size%%[xX]*}" "${size##*[xX]}" "$depth"

# --- Processes and their clean-up. -----------------------------------------------------
tmp=$(mktemp -d "${TMPDIR:-/tmp}/render.XXXXXX") || exit 3
pids=()              # every stage, upstream first
declare -A stage_of  # pid → stage name, for the messages
exec 3<&0            # the scene on stdin, for viewxf (a background job's stdin is /dev/null)

# Stops every stage still running (TERM, then KILL after a second), reaps them all.
stop_all() {
    local pid alive i
    for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null; done
    for ((i = 0; i < 20; i++)); do
        alive=0
        for pid in "${pids[@]}"; do
            if kill -0 "$pid" 2>/dev/null; then alive=1; break; fi
        done
        ((alive)) || break
        sleep 0.05
    done
    for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null; done
    wait 2>/dev/null
}

cleanup() {
    local status=$?
    trap - EXIT INT TERM
    stop_all
    rm -rf "$tmp"
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# start NAME CMD... <IN >OUT: runs one stage in the background and records it.
# (Redirections are given by the caller through the variables `in` and `out`.)
# Each stage's stderr goes to a file of its own, shown when the run ends: on success all
# of them in pipeline order (--stats), on failure only the causing stage's, since the
# stages downstream of it then fail too ("stream ends without END"), which is noise.
start() {
    local name=$1
    shift
    "$@" <"$in" >"$out" 2>"$tmp/stderr.${#pids[@]}" 3<&- &
    pids+=($!)
    stage_of[$!]=$name
}

# start_last NAME CMD...: the final stage, writing to the script's stdout.
start_last() {
    local name=$1
    shift
    "$@" <"$in" 2>"$tmp/stderr.${#pids[@]}" 3<&- &
    pids+=($!)
    stage_of[$!]=$name
}

fifo() {
    mkfifo "$tmp/$1" || exit 3
    printf '%s' "$tmp/$1"
}

# --- The clipper chain: viewxf and the six planes of the pyramid (chapter 3). ---------
if [[ $scene == - ]]; then in=/dev/fd/3; else in=$scene; fi
out=$(fifo view)
start viewxf "$bindir/viewxf" --size "$size" "${camera[@]}"
for plane in left right top bottom hither yon; do
    in=$out
    out=$(fifo "clip-$plane")
    start "clipplane $plane" "$bindir/clipplane" "$plane"
done
clipped=$out

# --- The splitter tree (chapter 6.3): nodes numbered as a heap, each bisecting its part
# of the screen on a pixel boundary (scripts/tree-planes.sh). ---------------------------
leaves=$((1 << depth))
declare -A input_of
input_of[1]=$clipped
for ((node = 1; node < leaves; node++)); do
    a=$((2 * node)) b=$((2 * node + 1))
    input_of[$a]=$(fifo "node-$a")
    input_of[$b]=$(fifo "node-$b")
    in=${input_of[$node]}
    out=/dev/null
    start "splitter ${plane_of[$node]} (node $node)" "$bindir/splitter" "${stats[@]}" \
        "${plane_of[$node]}" "${input_of[$a]}" "${input_of[$b]}"
done

# --- The leaves: persp | scanconv each, all into one zbuf (chapter 6.3.3). With --merge
# tiles each scanconv resolves its own region (--resolve) and zbuf only places the runs.
resolve=()
[[ $merge == tiles ]] && resolve=(--resolve)
fragments=()
for ((leaf = leaves; leaf < 2 * leaves; leaf++)); do
    if ((depth == 0)); then suffix=""; else suffix=" (leaf $((leaf - leaves)))"; fi
    in=${input_of[$leaf]}
    out=$(fifo "screen-$leaf")
    start "persp$suffix" "$bindir/persp" --size "$size" "${zmode[@]}"
    in=$out
    out=$(fifo "leaf-$((leaf - leaves))")
    start "scanconv$suffix" "$bindir/scanconv" "${resolve[@]}" "${stats[@]}"
    fragments+=("$out")
done
in=/dev/null
start_last zbuf "$bindir/zbuf" "${stats[@]}" "${outopt[@]}" "${fragments[@]}"
exec 3<&-

# --- Watch: the first stage to fail stops the rest. ------------------------------------
describe() { # describe STATUS
    if (($1 > 128)); then
        local sig
        sig=$(kill -l "$(($1 - 128))" 2>/dev/null) || sig=$(($1 - 128))
        printf 'killed by SIG%s' "$sig"
    else
        printf 'status %s' "$1"
    fi
}

# labelled_stderr INDEX: what stage INDEX wrote on stderr, each line that starts with the
# program's name given the stage's full name instead ("scanconv: …" from leaf 2 becomes
# "scanconv (leaf 2): …", "splitter y=0: …" becomes "splitter y=0 (node 2): …"), and the
# private directory left out of the fifo names zbuf reports ("zbuf: leaf-2: …").
labelled_stderr() {
    local label=${stage_of[${pids[$1]}]} line
    local program=${label%% *}
    while IFS= read -r line || [[ -n $line ]]; do
        line=${line//"$tmp/"/}
        if [[ $line == "$program"[:\ ]* && $line == *": "* ]]; then
            line="$label: ${line#*: }"
        fi
        printf '%s\n' "$line"
    done <"$tmp/stderr.$1"
}

finished() { # finished PID: whether it has exited (reaped or a zombie)
    ! kill -0 "$1" 2>/dev/null ||
        [[ $(awk '{ print $3 }' "/proc/$1/stat" 2>/dev/null) == Z ]]
}

# `wait -n` reports each stage as it ends. bash does not promise that it reports every
# one: a stage that ends while the script is busy elsewhere (a command substitution
# above, on a loaded machine) can be reaped then, and its status kept only for `wait PID`.
# So when `wait -n` has no child left, the statuses it did not report are collected with
# `wait PID`, and success means every stage was seen to exit 0.
declare -A status_of=() # pid → exit status, as learnt
failed=
while :; do
    done_pid=
    wait -n -p done_pid
    status=$?
    if [[ -z ${done_pid-} ]]; then # no child left to wait for
        for pid in "${pids[@]}"; do
            [[ -n ${status_of[$pid]-} ]] && continue
            wait "$pid" 2>/dev/null
            status_of[$pid]=$?
            # 127: bash has no status for it at all; the stages downstream tell.
            ((status_of[$pid] == 0 || status_of[$pid] == 127)) || failed=1
        done
        break
    fi
    status_of[$done_pid]=$status
    if ((status != 0)); then
        failed=1
        break
    fi
done

if [[ -n $failed ]]; then
    # A stage failed. Those downstream of it fail in turn when their input ends short,
    # so among the stages that have finished by now, name one killed by a signal, or
    # else the most upstream, as the cause.
    sleep 0.1
    for pid in "${pids[@]}"; do
        [[ -n ${status_of[$pid]-} ]] && continue
        if finished "$pid"; then
            wait "$pid" 2>/dev/null
            status_of[$pid]=$?
        fi
    done
    cause=
    for pid in "${pids[@]}"; do
        st=${status_of[$pid]-0}
        # 127: bash knew no such child, so no status to blame it on.
        ((st != 0 && st != 127)) || continue
        if ((st > 128)); then cause=$pid; break; fi
        [[ -n $cause ]] || cause=$pid
    done
    for i in "${!pids[@]}"; do
        [[ ${pids[$i]} == "$cause" ]] && labelled_stderr "$i" >&2
    done
    if [[ -n $cause ]]; then
        echo "render.sh: ${stage_of[$cause]} failed ($(describe "${status_of[$cause]}"))" >&2
    else
        # Only status 127 was seen (a stage that could not be run at all).
        echo "render.sh: a stage could not be run (status 127)" >&2
    fi
    exit 1
fi
for i in "${!pids[@]}"; do labelled_stderr "$i" >&2; done
exit 0
