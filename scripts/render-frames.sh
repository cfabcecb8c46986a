#!/usr/bin/env bash
# render-frames.sh: `render.sh --hosts H1,H2,… --by frames`: a movie's frames split across
# hosts in contiguous chunks, each chunk rendered whole on its host by render.sh there,
# the frames written back in order (docs/DESIGN.md, "Stages on other hosts").
#
#   frames --count MOVIE                      N frames; K = min(hosts, N) chunks
#   frames --from a --to b MOVIE > in.k       chunk k: frames a .. b−1, a = k·N/K, b = (k+1)·N/K
#   $POLYPIPE_SSH Hk render.sh OPTIONS - < in.k > out.k          all K at once
#   out.0, out.1, …, out.K−1 on stdout, each as soon as it and those before it are in
#
# The output stream is byte for byte a local render.sh's: a movie's frames are independent
# (thesis Appendix 1; docs/DESIGN.md, "Grammar"), and render.sh's frames do not depend on
# where or in which pieces they were rendered.
#
# One ssh per chunk, all at once, watched like render.sh watches its stages: the first
# host to fail (cannot be reached, refuses the command, lacks the programs, drops
# mid-run, or sends back fewer frames than it was given) stops the others, and the run
# ends non-zero with one line naming the host and what failed. The frames finished
# before, in order, are written whole; the private directory (chunks in and out) is
# removed on every way out. A remote render.sh stops when its ssh goes: its input ends
# short and its output has no reader.

# It needs bash 5.1 (`wait -n -p`); this check is plain sh, as render.sh's.
case ${BASH_VERSION-} in
    5.[1-9]* | [6-9].* | [1-9][0-9]*.*) ;;
    *)
        echo "render.sh: needs bash 5.1 or later (this is ${BASH_VERSION:-not bash})" >&2
        exit 3
        ;;
esac

set -u

usage() {
    cat <<'EOF'
Usage: render-frames.sh --hosts H1,H2,… [--remote-bin DIR] [RENDER OPTIONS] [SCENE]
       (render.sh --hosts H1,H2,… --by frames … runs this)

Renders a movie (a world-space stream of many frames; `-` for stdin; default
examples/penetrating.txt) on other hosts: the frames are split into contiguous
chunks, one per host, each rendered there whole by render.sh, and written back
in order on stdout, one binary PPM (P6) per frame: the same bytes as a local
`render.sh RENDER OPTIONS SCENE`.

Options:
  --hosts H1,H2,…   the hosts, as ssh names them (a host may be named twice:
                    it then renders two chunks at once)
  --by frames       accepted, for render.sh's sake (frames is the only way here)
  --remote-bin DIR  the folder of the polypipe binaries on the hosts (default: the
                    one here, target/release). render.sh itself is run from the
                    same path on the hosts as here.
  --stats           also: per host, the frames it rendered, the bytes each way
                    and the time; the hosts' own --stats lines, labelled
  -h, --help        this text
  Every other option is render.sh's (--size, --depth, --eye, …), passed to the
  hosts' render.sh unchanged. -o is not available: the frames come back on stdout.

Environment:
  POLYPIPE_SSH      the command that runs a command on a host, as
                    `$POLYPIPE_SSH HOST COMMAND` (default: ssh with BatchMode,
                    ConnectTimeout 5, ServerAliveInterval 2, ServerAliveCountMax 3,
                    so that a host that is gone is noticed within seconds)

Exit status: 0 success; 1 bad input data; 2 bad arguments; 3 a host could not be
reached, could not run the command or dropped (the message names it); a failing
host's render.sh status (1 to 3) passes through.

Examples:
  scene spheres --frames 300 | scripts/render-frames.sh --hosts alpha,beta --size 640x480 - > movie.ppm
  POLYPIPE_SSH='ssh -p 2222' scripts/render-frames.sh --hosts gpu1 --remote-bin /opt/polypipe/bin movie.pp
EOF
}

fail() { # fail STATUS MESSAGE: one line on stderr, and out
    local status=$1
    shift
    echo "render.sh: $*" >&2
    exit "$status"
}

die_usage() {
    echo "render.sh: $*" >&2
    echo "Try 'render-frames.sh --help'." >&2
    exit 2
}

# --- Options: ours, and render.sh's to pass on. -------------------------------------------

# render.sh's options that take a value (so that the value is not taken for the SCENE).
valued=" --size --depth --zmode --eye --at --up --s --d --hither --yon --hse --aa --merge "

hosts_arg=
remote_bin=
size=500x500
stats=0
scene=
scene_given=0
passed=() # render.sh's options, for the hosts

while (($# > 0)); do
    opt=$1 value=
    shift
    if [[ $opt == --*=* ]]; then
        value=${opt#*=} opt=${opt%%=*}
        set -- "$value" "$@"
    fi
    case $opt in
        -h | --help) usage; exit 0 ;;
        --hosts | --remote-bin | --by)
            (($# > 0)) || die_usage "$opt needs a value"
            value=$1
            shift
            case $opt in
                --hosts) hosts_arg=$value ;;
                --remote-bin) remote_bin=$value ;;
                --by) [[ $value == frames ]] || die_usage "--by must be frames here, not '$value'" ;;
            esac
            ;;
        -o) die_usage "-o is not available with --by frames: the frames come back on stdout" ;;
        --stats) stats=1; passed+=("$opt") ;;
        -)
            ((scene_given == 0)) || die_usage "more than one SCENE: '$scene' and '-'"
            scene=- scene_given=1
            ;;
        -?*)
            if [[ $valued == *" $opt "* ]]; then
                (($# > 0)) || die_usage "$opt needs a value"
                value=$1
                shift
                passed+=("$opt" "$value")
                [[ $opt != --size ]] || size=$value
            else
                passed+=("$opt")
            fi
            ;;
        *)
            ((scene_given == 0)) || die_usage "more than one SCENE: '$scene' and '$opt'"
            scene=$opt scene_given=1
            ;;
    esac
done

[[ -n $hosts_arg ]] || die_usage "--hosts H1,H2,… is needed"
if ! [[ $size =~ ^0*([1-9][0-9]{0,4})[xX]0*([1-9][0-9]{0,4})$ ]] ||
    ((BASH_REMATCH[1] > 65536 || BASH_REMATCH[2] > 65536)); then
    die_usage "--size must be WxH with W and H from 1 to 65536, not '$size'"
fi
width=${BASH_REMATCH[1]} height=${BASH_REMATCH[2]}
# zbuf's frames: `P6\nW H\n255\n` and W·H RGB pixels, every frame the same length.
header="P6"$'\n'"$width $height"$'\n'"255"$'\n'
frame_bytes=$((${#header} + width * height * 3))

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd) || exit 3
source "$root/scripts/hosts.sh"
check_hosts "$hosts_arg"
((scene_given)) || scene=$root/examples/penetrating.txt
[[ $scene == - || -r $scene ]] || fail 3 "cannot read scene $scene"

# --- The binaries: `frames` here, and the stages that the hosts run from the same path
# unless --remote-bin says otherwise. Built when missing or older than their sources. ------
target=${CARGO_TARGET_DIR:-target}
[[ $target == /* ]] || target=$root/$target
bindir=$target/release
needed=(frames)
[[ -n $remote_bin ]] || needed+=(viewxf clipplane splitter persp scanconv zbuf)
stale=0
for b in "${needed[@]}"; do
    if [[ ! -x $bindir/$b ]] ||
        [[ -n $(find "$root/proto" "$root/bins/$b" "$root/Cargo.toml" "$root/Cargo.lock" \
            \( -name '*.rs' -o -name Cargo.toml -o -name Cargo.lock \) \
            -newer "$bindir/$b" -print -quit 2>/dev/null) ]]; then
        stale=1
    fi
done
if ((stale)); then
    packages=()
    for b in "${needed[@]}"; do packages+=(-p "$b"); done
    (cd "$root" && cargo build --release --quiet "${packages[@]}") >&2 ||
        fail 3 "cargo build failed"
fi
remote_bin=${remote_bin:-$bindir}

remote_cmd="exec env POLYPIPE_BIN=$(quote "$remote_bin") $(quote "$root/scripts/render.sh")"
for word in "${passed[@]}"; do remote_cmd+=" $(quote "$word")"; done
remote_cmd+=" -"

# --- The private directory, the ssh processes, and the clean-up. -------------------------

tmp=$(mktemp -d "${TMPDIR:-/tmp}/render-frames.XXXXXX") || exit 3
pids=()             # one ssh per chunk
declare -A chunk_of # pid → chunk number

stop_all() { # TERM, then KILL after a second; reaps them all
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

if [[ $scene == - ]]; then
    # The movie is read twice (counted, then cut), so stdin is kept here first.
    cat >"$tmp/scene" || fail 3 "cannot keep the scene from stdin in $tmp"
    scene=$tmp/scene
fi

# frames ARGS…: the local cutter; its own one-line message and status on failure.
frames_here() {
    local status
    "$bindir/frames" "$@" && return 0
    status=$?
    exit "$status"
}

total=$(frames_here --count "$scene") || exit $?
chunks=${#hosts[@]}
((chunks <= total)) || chunks=$total

# --- The chunks: cut, sent, rendered, collected. ------------------------------------------

declare -a first last host_of started ended # per chunk
for ((k = 0; k < chunks; k++)); do
    first[k]=$((k * total / chunks))
    last[k]=$(((k + 1) * total / chunks)) # one past
    host_of[k]=${hosts[k]}
    frames_here --from "${first[k]}" --to "${last[k]}" "$scene" >"$tmp/in.$k" || exit $?
    started[k]=$EPOCHREALTIME
    "${ssh_cmd[@]}" "${host_of[k]}" "$remote_cmd" <"$tmp/in.$k" >"$tmp/out.$k" 2>"$tmp/err.$k" &
    pids+=($!)
    chunk_of[$!]=$k
done

# Writes the finished chunks in order, from `next` on, each as soon as those before it
# are written; a written chunk's file is removed at once.
next=0
declare -A done_ok=()
flush() {
    while ((next < chunks)) && [[ -n ${done_ok[$next]-} ]]; do
        cat "$tmp/out.$next" || {
            local status=$?
            # The reader went away (`| head`): a quiet end, as the stages have.
            ((status == 141)) && exit 0
            fail 3 "cannot write the frames of host ${host_of[next]} to stdout"
        }
        rm -f "$tmp/out.$next"
        next=$((next + 1))
    done
}

# chunk_ended CHUNK STATUS: records how a host's ssh ended. Success is status 0 and every
# frame sent back; otherwise sets `failed`, `message` and `exit_status`.
chunk_ended() {
    local k=$1 st=$2 got want
    ended[k]=$EPOCHREALTIME
    if ((st != 0)); then
        what_failed "$tmp/err.$k" "$st" render.sh
        failed=$k
        return 1
    fi
    got=$(stat -c %s "$tmp/out.$k")
    want=$(((last[k] - first[k]) * frame_bytes))
    if ((got != want)); then
        message="sent back $got bytes, not the $want of its $((last[k] - first[k])) frames (${first[k]} to $((last[k] - 1)))"
        exit_status=3
        failed=$k
        return 1
    fi
    done_ok[$k]=1
}

# Waits for the hosts; the first to fail stops the rest. As in render.sh, `wait -n` may
# not report a child that bash reaped while busy elsewhere, so when it has no child left,
# the others' statuses are collected with `wait PID`.
failed=
while [[ -z $failed ]]; do
    done_pid=
    wait -n -p done_pid
    status=$?
    if [[ -z ${done_pid-} ]]; then # no child left to wait for
        for pid in "${pids[@]}"; do
            k=${chunk_of[$pid]}
            [[ -n ${ended[k]-} ]] && continue
            wait "$pid" 2>/dev/null
            chunk_ended "$k" $? || break
        done
        break
    fi
    chunk_ended "${chunk_of[$done_pid]}" "$status" && flush
done

if [[ -n $failed ]]; then
    # Stop the other hosts, then write what is whole and in order: the finished chunks
    # before the first unfinished one, and that one's complete frames.
    stop_all
    flush
    if ((next < chunks)) && [[ -s $tmp/out.$next ]]; then
        whole=$(($(stat -c %s "$tmp/out.$next") / frame_bytes))
        if ((whole > last[next] - first[next])); then whole=$((last[next] - first[next])); fi
        head -c $((whole * frame_bytes)) "$tmp/out.$next"
    fi
    fail "$exit_status" "host ${host_of[failed]}: $message"
fi
flush

# --- Success: the hosts' own stderr (their --stats), labelled; ours with --stats. -------
for ((k = 0; k < chunks; k++)); do
    sed "s/^render\.sh: //; s/^/host ${host_of[k]//\//\\/}: /" "$tmp/err.$k" >&2
done
if ((stats)); then
    for ((k = 0; k < chunks; k++)); do
        sent=$(stat -c %s "$tmp/in.$k")
        secs=$(awk -v a="${started[k]}" -v b="${ended[k]}" 'BEGIN { printf "%.2f", b - a }')
        echo "render.sh: host ${host_of[k]}: frames ${first[k]} to $((last[k] - 1)) ($((last[k] - first[k]))), sent $sent bytes, received $(((last[k] - first[k]) * frame_bytes)) bytes, ${secs} s" >&2
    done
    for ((k = chunks; k < ${#hosts[@]}; k++)); do
        echo "render.sh: host ${hosts[k]}: no frames (the movie has $total)" >&2
    done
fi
exit 0
