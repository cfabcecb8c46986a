#!/usr/bin/env bash
# tree.sh: the splitter tree as the design card and the thesis draw it (Theoharis 1985,
# 6.3.3, "The New Pipeline"), one process a stage, joined by named pipes the way occam's
# PAR joins channels:
#
#   viewxf → clipplane left → right → top → bottom → hither → yon        (chapter 3)
#     → splitter node 1 → nodes 2, 3 → …   N levels; node K feeds 2K and 2K+1 (6.1, 6.2)
#     → at each leaf, nodes 2^N … 2^(N+1) − 1: persp → scanconv            (chapter 4)
#     → zbuf, reading every leaf at once: one z-buffer for every fragment (PAR.BUFF, 4.2.3)
#
# The topology written out to be read: render.sh runs this graph with fewer processes (a
# batch clipper, two levels to a splitter), to the same bytes (`--merge buffer --depth N`).
set -uo pipefail
usage="usage: tree.sh [--depth N] [--size WxH] [SCENE]
Renders SCENE (a polypipe stream; \`-\` or none: stdin) through a depth-N splitter tree
(N from 0 to 6, default 2) at WxH pixels (default 500x500): PPM frames on stdout. The
binaries are \$POLYPIPE_BIN's, or target/bin's (scripts/render.sh builds them there)."
die() { echo "tree.sh: $2" >&2; exit "$1"; } # STATUS MESSAGE

depth=2 size=500x500 scene=-
while (($#)); do
    case $1 in
        --depth) (($# > 1)) || die 2 "--depth needs a value"; depth=$2; shift ;;
        --size) (($# > 1)) || die 2 "--size needs a value"; size=$2; shift ;;
        -h | --help) echo "$usage"; exit 0 ;;
        -?*) die 2 "unknown option '$1' (tree.sh --help lists them)" ;;
        *) scene=$1 ;;
    esac
    shift
done
((BASH_VERSINFO[0] * 100 + BASH_VERSINFO[1] >= 501)) || die 3 "needs bash 5.1 or later"
[[ $depth =~ ^[0-6]$ ]] || die 2 "--depth must be an integer from 0 to 6, not '$depth'"
bin=${POLYPIPE_BIN:-$(dirname "$0")/../target/bin}
for b in viewxf clipplane splitter persp scanconv zbuf; do
    [[ -x $bin/$b ]] || die 3 "no $b in $bin (scripts/render.sh builds it; or set POLYPIPE_BIN)"
done
exec 3<&0 # the script's stdin, for a scene `-` (a stage started with & would get /dev/null)
[[ $scene == - ]] && scene=/dev/fd/3
[[ -r $scene ]] || die 3 "cannot read the scene $scene"

# The channels, a named pipe a stream, and each stage's messages, in a folder of our own,
# removed (and any stage still running stopped) however the script ends.
pipes=$(mktemp -d "${TMPDIR:-/tmp}/tree.XXXXXX") || die 3 "cannot make a temporary folder"
names=() # the stages, in the order they were started
declare -A running=() # process id → the stage's number in `names`
trap '{ ((${#running[@]} == 0)) || kill "${!running[@]}"; rm -rf "$pipes"; } 2>/dev/null' EXIT
trap 'exit 130' INT; trap 'exit 143' TERM

# run NAME IN OUT COMMAND...: start a stage in the background, from IN to OUT (`-`: the
# script's stdout), its messages kept until we know which stage failed first.
run() {
    local name=$1 in=$2 out=$3 err=$pipes/stderr-${#names[@]}
    shift 3
    if [[ $out == - ]]; then "$@" <"$in" 2>"$err" & else "$@" <"$in" >"$out" 2>"$err" & fi
    running[$!]=${#names[@]} names+=("$name")
}

# The clipper chain: the viewing transformation and the six planes of the pyramid. What
# the last writes is the input of the tree's root, node 1 (at depth 0, the one leaf).
mkfifo "$pipes"/{view,left,right,top,bottom,hither,yon} && ln -s yon "$pipes/node-1"
run viewxf "$scene" "$pipes/view" "$bin/viewxf" --size "$size"
from=view
for plane in left right top bottom hither yon; do
    run "clipplane $plane" "$pipes/$from" "$pipes/$plane" "$bin/clipplane" "$plane"
    from=$plane
done

# The splitter nodes, numbered as a heap: node K computes its plane from K (the levels
# alternate x and y, each cut on a pixel boundary), splitting node-K into node-2K, -2K+1.
leaves=$((1 << depth))
for ((k = 2; k < 2 * leaves; k++)); do mkfifo "$pipes/node-$k"; done
for ((k = 1; k < leaves; k++)); do
    run "splitter (node $k)" "$pipes/node-$k" /dev/null "$bin/splitter" --node "$k" \
        --depth "$depth" --size "$size" "$pipes/node-$((2 * k))" "$pipes/node-$((2 * k + 1))"
done

# The leaves, left to right: each projects its region's polygons and scan converts them;
# zbuf depth-tests every leaf's fragments in one buffer and writes the frames.
fragments=()
for ((leaf = 0; leaf < leaves; leaf++)); do
    mkfifo "$pipes/screen-$leaf" "$pipes/frag-$leaf"
    run "persp (leaf $leaf)" "$pipes/node-$((leaves + leaf))" "$pipes/screen-$leaf" \
        "$bin/persp" --size "$size"
    run "scanconv (leaf $leaf)" "$pipes/screen-$leaf" "$pipes/frag-$leaf" "$bin/scanconv"
    fragments+=("$pipes/frag-$leaf")
done
run zbuf /dev/null - "$bin/zbuf" "${fragments[@]}"

# Wait for each stage: the first to fail is named, its status is ours, the rest stopped.
while ((${#running[@]})); do
    pid='' && wait -n -p pid "${!running[@]}"; status=$?
    # A stage bash has reaped already goes unnamed by wait -n: `wait PID` gives its status.
    [[ -n $pid ]] || { for pid in "${!running[@]}"; do break; done; wait "$pid"; status=$?; }
    n=${running[$pid]} && unset "running[$pid]"
    if ((status != 0)); then
        cat "$pipes/stderr-$n" >&2
        die "$status" "${names[n]} failed (status $status)"
    fi
done
for n in "${!names[@]}"; do cat "$pipes/stderr-$n" >&2; done
