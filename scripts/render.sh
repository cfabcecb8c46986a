#!/usr/bin/env bash
# render.sh: compose the polypipe stages into the thesis's pipeline, the way occam's PAR
# wires channels (docs/DESIGN.md, "The splitter tree"; thesis chapter 6.3, CLIPPER/SPLITTER):
#
#   viewxf | clipbatch (the six planes; --clip chain: clipplane left | right | … | yon)
#     depth 0:  | zbuf --project (which projects, scan-converts and resolves the one leaf)
#     depth N:  | a binary tree of splitter nodes, N levels, each node computing its own
#               plane from its number (`splitter --node K`); persp | scanconv --resolve
#               (or --hse's method) on each of the 2^N leaves; one zbuf placing the
#               leaves' finished regions (--merge buffer: persp | scanconv on each leaf,
#               every fragment depth-tested in the one zbuf, the thesis's PAR.BUFF).
#
# Every stage is a process of its own, joined to the next by an anonymous pipe: the
# script works out the graph and becomes `plan launch`, which starts and watches the
# stages. When one fails (or is killed), it names it, stops the others and exits with that
# stage's class of failure (1 bad data, 2 usage, 3 I/O). Nothing is left on disk or
# running on any way out (success, failure, Ctrl-C, SIGTERM). The script only wires: the
# stages check their own options, compute their own planes and label their own --stats
# lines.

# It needs bash 5.1 and /proc. This check is plain sh, so that `sh
# render.sh` or an older bash stops here with a message rather than a syntax error.
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
Usage: render.sh [OPTIONS] [SCENE]

Renders a world-space scene (text or binary; `-` for stdin; default
examples/penetrating.txt) and writes one binary PPM (P6) per frame on stdout.

Options:
  --size WxH        screen size in pixels, W and H from 1 to 65536 (default 500x500)
  --depth N         splitter tree depth, 0 to 6 (0: no splitter), or auto (the
                    default): the depth the cost model (`plan depth`, docs/model.md)
                    predicts fastest for this scene, screen and machine (and --hosts),
                    from a look at its first 512 KiB; `chart calibrate` fits the
                    model to this machine
  --eye X,Y,Z  --at X,Y,Z  --up X,Y,Z  --s S  --d D  --hither K1  --yon K2
                    camera and view volume, passed to viewxf
  --zmode MODE      persp's depth: reciprocal (default: -K1/z_e), projective (the
                    classic z-buffer's, which loses precision near yon) or eye-z
                    (the occam code's)
  --merge MODE      tiles (default): each leaf resolves its own region and zbuf only
                    places the finished pixels; buffer: the thesis's PAR.BUFF, every
                    fragment depth-tested in the one zbuf
  --hse METHOD      the leaves' hidden-surface method: zbuf (default), scanline
                    (Watkins), warnock (area subdivision) or painter (depth sort,
                    wrong where polygons interpenetrate or overlap cyclically);
                    every one at every --depth, with --merge tiles
  --split           with --hse painter: cut polygons by each other's planes where no
                    depth order exists (Newell, Newell and Sancha's splitting step)
  --aa MODE         anti-aliasing at the leaves: none (default: one sample at each
                    pixel centre), ss2, ss4, ss8, ss16 (K×K samples a pixel, box
                    filter) or abuf (Carpenter's a-buffer, 8×8 coverage masks)
  --pixels          with --merge buffer: one fragment per pixel (the thesis's
                    quadruplets) instead of spans
  --hidden-line     draw the visible parts of the polygons' edges as SVG, to the
                    file -o names (FILE.svg; frame%03d.svg for a movie), at depth 0
                    (not with --hse, --aa, --merge buffer or --pixels)
  --hidden-line-method M
                    with --hidden-line: continuous (default: exact pieces) or
                    archuleta (Archuleta's counters on scan lines, raster resolution)
  --clip MODE       batch (default): clipbatch, the six planes in one process over a
                    batch of polygons (Theoharis & Page's DAP clipper); chain: the
                    thesis's six clipplane processes
  --stats           splitter nodes, scan converters and zbuf print counts on stderr
  --times           after the run, each stage's CPU (user, system), its peak
                    memory and when it ended, and their sums, on stderr
  -o PATTERN        zbuf writes one file per frame (e.g. frame%04d.png) instead
  --hosts H1,H2,…   run the tree on other hosts over ssh ($POLYPIPE_SSH HOST …,
                    default ssh), round-robin: each host a leaf, or a whole subtree
                    (its splitters and leaves) when the tree has more leaves than
                    there are hosts; the streams go there, the finished pixels
                    come back, and the frames are a local run's
  --by MODE         with --hosts: leaves (default), or frames: cut a movie into
                    chunks of a few frames, each rendered whole by render.sh on
                    a host GNU parallel chooses, a failed chunk retried on
                    another, the frames written back in order (the `farm`
                    binary; stdout, or -o's files)
  --chunk N         with --by frames: frames a chunk, one ssh session each
                    (default 8)
  --sshloginfile F  with --by frames: the hosts from GNU parallel's file (N/host)
  --retries N       with --by frames: tries of a chunk, each on another host while
                    there is one (default 3)
  --joblog FILE     with --by frames: parallel's job log (default: farm.joblog
                    beside -o's files)
  --resume          with --by frames and -o: render only the chunks the job log
                    does not call finished
  --slurm-array DIR with --by frames and -o: write DIR/render.sbatch, a Slurm job
                    array of the chunks, instead of rendering
  --first-frame N   with -o: the number the pattern gives the first frame (default 0)
  --remote-bin DIR  with --hosts: the binaries' folder on the hosts (default: this one's)
  --subtree K       what --hosts runs on a host: node K's part of the tree (its
                    splitters, leaves and a zbuf --runs), from the stream into node K
                    on stdin to its finished runs on stdout
  -h, --help        this text
  --version         the version

The frames are byte-identical for every --depth with reciprocal or projective depth, but not
with --zmode eye-z: eye-space z is not linear across the screen, and each piece
of a split polygon interpolates it between its own vertices.

The first run builds the binaries (cargo, release, into $CARGO_TARGET_DIR, taken
from the repository root when relative, or target/); later runs rebuild them when
their sources change. Needs bash 5.1 or later and /proc.

Exit status: 0 success, 1 bad input data, 2 bad arguments, 3 I/O or environment;
a failing stage's own status passes through (a stage killed by a signal: 1).

Examples:
  scripts/render.sh > penetrating.ppm
  scripts/render.sh --depth 3 --size 640x480 --eye 10,10,20 scene.txt > out.ppm
  scene environment --frames 10 | scripts/render.sh --depth 2 - -o frame%03d.png
EOF
}

# fail STATUS MESSAGE: one line on stderr, and out.
fail() {
    local status=$1
    shift
    echo "render.sh: $*" >&2
    exit "$status"
}

die_usage() { fail 2 "$@"; }

# --- The repository and its version. ---------------------------------------------------

# Sets `root` to the repository this script belongs to, through any symlink to it.
locate_repository() {
    local script=${BASH_SOURCE[0]} here=$PWD dir
    # Where the script is not a symlink, its folder resolved by cd, without a process.
    if [[ ! -L $script ]]; then
        dir=.
        [[ $script != */* ]] || dir=${script%/*}
        if CDPATH='' cd -P -- "$dir/.." 2>/dev/null; then
            root=$PWD
            cd -- "$here" || fail 3 "cannot go back to $here"
            return
        fi
    fi
    script=$(readlink -f -- "$script") || fail 3 "cannot find where render.sh lives"
    root=${script%/*/*}
}

polypipe_version() { # the workspace's version, from its Cargo.toml
    sed -n '/^version *= *"/{s/^[^"]*"//;s/".*//;p;q}' "$root/Cargo.toml"
}

# --- Options. ---------------------------------------------------------------------------

size=500x500
depth=auto # --depth (auto: plan depth decides, or 0 when there is no plan)
depth_asked=0
zmode=reciprocal
hse=zbuf    # --hse: the leaves' hidden-surface method
split=()    # --split: painter's splitting step
aa=none     # --aa: the leaves' anti-aliasing
pixels=()   # --pixels: scanconv's one record per pixel (with --merge buffer)
hidden_line=0 # --hidden-line: hiddenline's SVG instead of frames
hl_method=()  # --hidden-line-method: hiddenline's --method
merge=tiles # --merge: leaves resolve their regions (tiles), or one z-buffer (buffer)
clip="batch" # --clip: clipbatch (batch), or the six clipplane processes (chain)
scene=
scene_given=0
hosts=()  # the hosts, an array made by check_hosts from --hosts
hosts_list= # --hosts H1,H2,…
by=       # --by leaves|frames
remote_bin= # --remote-bin DIR
chunk=()    # --chunk N, for farm (--by frames)
farm_opts=() # --sshloginfile, --retries, --joblog, --resume, --slurm-array: farm's own
first_frame=() # --first-frame N: the number -o gives the first frame (zbuf's, or farm's)
forward=()  # the options a host's render.sh gets with --by frames
subtree=    # --subtree K: this is a host rendering node K's subtree for --hosts
camera=() # viewxf's options, as given
stats=()  # --stats, for the stages that count
times=()  # --times, for the launcher
feed=     # --depth auto's sample of a stream, fed to viewxf before the rest
output=() # zbuf's -o PATTERN

# The options that take a value (each also as --option=value), and those that do not.
valued=" --size --depth --zmode --hse --aa --merge --clip --hidden-line-method -o --eye --at --up --s --d --hither --yon --hosts --by --remote-bin --subtree --chunk --sshloginfile --retries --joblog --slurm-array --first-frame "
flags=" -h --help --version --stats --times --pixels --hidden-line --split --resume "

parse_options() {
    local opt value
    while (($# > 0)); do
        opt=$1 value=
        shift
        if [[ $opt == --*=* && $valued == *" ${opt%%=*} "* ]]; then
            value=${opt#*=} opt=${opt%%=*}
        elif [[ $opt == --*=* && $flags == *" ${opt%%=*} "* ]]; then
            die_usage "${opt%%=*} takes no value"
        elif [[ $valued == *" $opt "* ]]; then
            (($# > 0)) || die_usage "$opt needs a value"
            value=$1
            shift
        fi
        # With --by frames, the hosts' render.sh gets every option about the picture.
        case $opt in
            --hosts | --by | --remote-bin | --chunk | -o | -h | --help | --version | --times | [!-]* | -) ;;
            --sshloginfile | --retries | --joblog | --resume | --slurm-array | --first-frame) ;;
            *) forward+=("$opt"); [[ $valued != *" $opt "* ]] || forward+=("$value") ;;
        esac
        case $opt in
            -h | --help) usage; exit 0 ;;
            --version) echo "render.sh $(polypipe_version)"; exit 0 ;;
            --size) size=$value ;;
            --depth) depth=$value depth_asked=1 ;;
            --zmode) zmode=$value ;;
            --merge) merge=$value ;;
            --hse) hse=$value ;;
            --aa) aa=$value ;;
            --pixels) pixels=(--pixels) ;;
            --split) split=(--split) ;;
            --hidden-line) hidden_line=1 ;;
            --hidden-line-method) hl_method=(--method "$value") ;;
            --clip) clip=$value ;;
            -o) output=(-o "$value") ;;
            --eye | --at | --up | --s | --d | --hither | --yon) camera+=("$opt" "$value") ;;
            --stats) stats=(--stats) ;;
            --times) times=(--times) ;;
            --hosts) hosts_list=$value ;;
            --by) by=$value ;;
            --remote-bin) remote_bin=$value ;;
            --chunk) chunk=(--chunk "$value") ;;
            --sshloginfile | --retries | --joblog | --slurm-array) farm_opts+=("$opt" "$value") ;;
            --resume) farm_opts+=(--resume) ;;
            --first-frame) first_frame=(--first-frame "$value") ;;
            --subtree) subtree=$value ;;
            -?*) die_usage "unknown option ${opt%%=*}" ;;
            *)
                ((scene_given == 0)) || die_usage "more than one SCENE: '$scene' and '$opt'"
                scene=$opt scene_given=1
                ;;
        esac
    done
}

# Checks what the script itself uses; the camera and -o are for their stages to check
# (a stage's usage error comes out of render.sh as status 2).
validate_options() {
    [[ $depth =~ ^[0-6]$ || $depth == auto ]] ||
        die_usage "--depth must be an integer from 0 to 6 or auto, not '$depth'"
    # The bounds of every stage's --size (proto::camera::parse_size).
    if ! [[ $size =~ ^0*([1-9][0-9]{0,4})[xX]0*([1-9][0-9]{0,4})$ ]] ||
        ((BASH_REMATCH[1] > 65536 || BASH_REMATCH[2] > 65536)); then
        die_usage "--size must be WxH with W and H from 1 to 65536, not '$size'"
    fi
    [[ $zmode == @(reciprocal|projective|eye-z) ]] ||
        die_usage "--zmode must be reciprocal, projective or eye-z, not '$zmode'"
    [[ $merge == @(tiles|buffer) ]] || die_usage "--merge must be tiles or buffer, not '$merge'"
    [[ $clip == @(batch|chain) ]] || die_usage "--clip must be batch or chain, not '$clip'"
    [[ $hse == @(zbuf|scanline|warnock|painter) ]] ||
        die_usage "--hse must be zbuf, scanline, warnock or painter, not '$hse'"
    ((${#split[@]} == 0)) || [[ $hse == painter ]] ||
        die_usage "--split is the painter's splitting step: it needs --hse painter"
    [[ $aa == @(none|ss2|ss4|ss8|ss16|abuf) ]] ||
        die_usage "--aa must be none, ss2, ss4, ss8, ss16 or abuf, not '$aa'"
    # The methods and anti-aliasing modes are the leaves' own: PAR.BUFF sends every
    # fragment to the one zbuf, and anti-aliasing resolves with a z-buffer.
    [[ $merge == tiles || ($hse == zbuf && $aa == none) ]] ||
        die_usage "--merge buffer is the z-buffer's, point-sampled: not with --hse $hse --aa $aa"
    [[ $hse == zbuf || $aa == none ]] ||
        die_usage "--aa $aa is a z-buffer's anti-aliasing: not with --hse $hse"
    ((${#pixels[@]} == 0)) || [[ $merge == buffer ]] ||
        die_usage "--pixels sends fragments to the one z-buffer: it needs --merge buffer"
    ((hidden_line || ${#hl_method[@]} == 0)) || die_usage "--hidden-line-method needs --hidden-line"
    if ((hidden_line)); then
        [[ $depth == [0a]* ]] ||
            die_usage "--hidden-line draws at depth 0 (the tree's cuts are not edges), not --depth $depth"
        ((${#output[@]})) || die_usage "--hidden-line needs -o FILE.svg"
        # Its drawing has no hidden-surface method, samples or merger of its own to
        # change: options for those would be taken and do nothing.
        [[ $hse == zbuf && $aa == none && $merge == tiles && ${#pixels[@]} == 0 ]] ||
            die_usage "--hidden-line draws the visible edges: not with --hse, --aa, --merge buffer or --pixels"
    fi
    if [[ -n $subtree ]]; then
        # A host's part of the tree is cut by the tree's depth, which --hosts gives it.
        [[ $depth != auto ]] || die_usage "--subtree needs --depth N, the depth of the tree it is part of"
        [[ $subtree =~ ^[1-9][0-9]*$ ]] && ((subtree < 2 << depth)) ||
            die_usage "--subtree must be a node of the tree, 1 to $(((2 << depth) - 1)), not '$subtree'"
        [[ $merge == tiles && ${#hosts[@]} == 0 && $hidden_line == 0 ]] ||
            die_usage "--subtree is a host's part of --hosts: not with --merge buffer, --hosts or --hidden-line"
    fi
    if ((${#hosts[@]})); then
        [[ $merge == tiles ]] ||
            die_usage "--hosts runs leaves that resolve their regions: not with --merge buffer"
        ((hidden_line == 0)) || die_usage "--hidden-line is drawn here: not with --hosts"
    fi
    ((scene_given)) || scene=$root/examples/penetrating.txt
    [[ $scene == - || -r $scene ]] || fail 3 "cannot read scene $scene"
    # As the stages say of a folder given as their input (viewxf would say it too, but
    # --depth auto first samples a scene it cannot read twice).
    [[ ! -d $scene ]] || fail 3 "$scene: Is a directory"
}

# --- The binaries: built when missing or older than their sources. ---------------------

stages=(viewxf clipplane clipbatch splitter persp scanconv zbuf) # the ones a render runs

# Sets `bindir`: a host's folder of binaries (POLYPIPE_BIN), or this repository's
# `binaries`, built when missing or stale (scripts/lib/binaries.sh).
ensure_binaries() {
    # POLYPIPE_BIN names a folder of built binaries, run as they are and never built: a
    # host's, given by `render.sh --hosts … --remote-bin DIR` (farm runs
    # `POLYPIPE_BIN=DIR render.sh …` there), which may have no sources and no cargo.
    if [[ -n ${POLYPIPE_BIN-} ]]; then
        bindir=$POLYPIPE_BIN
        local method
        leaf_method
        for b in "${stages[@]}" "${method[0]}" plan; do
            [[ -x $bindir/$b ]] || fail 3 "no $b in $bindir (POLYPIPE_BIN)"
        done
        return 0
    fi
    build_binaries
}


# --- The stages, described for the launcher. -------------------------------------------

# render.sh works out the process graph and then becomes `plan launch` (exec), which
# makes each channel an anonymous pipe, starts the stages, watches them, and ends the
# run as this script says in its usage: the stages' own words in order on success, the
# failing one's and one line naming it on failure, 130 or 143 when stopped
# (bins/plan/src/launch.rs). Nothing goes to disk, so nothing is left behind however
# the run ends. Before, the script did it itself, with a private folder of named pipes
# kept by a process of its own and `wait -n`: about half of a small render's start-up
# (docs/performance.md, "Start-up").
spec=() # the stages: `LABEL IN OUT HOST NODE PIPES N` and the N words of each command

# start NAME IN OUT CMD...: one stage of the graph, reading IN and writing OUT: `-` (the
# script's stdin or stdout), `pipe:NAME` (a channel to another stage) or a file. The last
# `npipes` words of CMD (0 unless set for the call) are channels too, `pipe:NAME`, which
# the stage gets as /dev/fd/N (a splitter's two outputs, the merger's inputs). A stage
# on another host gives `host_here` and `node_here` for the messages about it.
start() {
    local name=$1 in=$2 out=$3 n=${npipes:-0}
    shift 3
    [[ $in == - || $in == pipe:* ]] || in=file:$in
    [[ $out == - || $out == pipe:* ]] || out=file:$out
    local -a cmd=("$@")
    local i
    for ((i = $# - n; i < $#; i++)); do cmd[i]=${cmd[i]#pipe:}; done
    spec+=("$name" "$in" "$out" "${host_here-}" "${node_here-}" "$n" "$#" "${cmd[@]}")
}

# --- The process graph. -----------------------------------------------------------------

# The clipper chain: viewxf and the six planes of the pyramid (chapter 3). The scene on
# stdin (`-`) is read after --depth auto's sample of it through `plan relay`. Sets
# `clipped`: at depth 0 with the merger the leaf, the merger's input, `leaf-0`.
start_clipper_chain() {
    local in=$scene plane out=clipped
    if [[ $depth == 0 ]] && merger_is_leaf; then out='leaf-0'; fi
    if [[ -n $feed ]]; then
        start "plan relay" - pipe:feed "$bindir/plan" relay "$feed"
        in=pipe:feed
    fi
    start viewxf "$in" pipe:view "$bindir/viewxf" --size "$size" "${camera[@]}"
    in=pipe:view
    if [[ $clip == batch ]]; then
        start clipbatch "$in" "pipe:$out" "$bindir/clipbatch"
        clipped=pipe:$out
        return
    fi
    for plane in left right top bottom hither; do
        start "clipplane $plane" "$in" "pipe:clip-$plane" "$bindir/clipplane" "$plane"
        in=pipe:clip-$plane
    done
    start "clipplane yon" "$in" "pipe:$out" "$bindir/clipplane" yon
    clipped=pipe:$out
}

# The splitter tree (chapter 6.3): node K, numbered as a heap (root 1), reads input_of[K]
# and writes input_of[2K] and input_of[2K+1]; nodes 2^depth .. 2^(depth+1) − 1 are the
# leaves' inputs. Each node works out its own plane and --stats label from K.
#
# The nodes run two levels to a process (`splitter --node K --levels 2`, node K and its
# two children, writing its four grandchildren's streams), the levels paired from the
# bottom, so that an odd count leaves the top level's nodes alone: the same streams out,
# with a process and a stream's encoding and decoding fewer a pair (docs/performance.md,
# "The tree's depth"). Depth 2 is one splitter; depth 3 the root and two pairs.
#
# start_tree ROOT BELOW [leaves]: the splitters of ROOT's subtree numbered below BELOW
# (2^depth for the whole tree; less when subtrees go to other hosts), reading
# input_of[ROOT]. Sets `frontier` to the nodes their outputs feed: the leaves' inputs, or
# the subtrees'. With `leaves` (leaves started here follow), the last level projects its
# outputs to the screen (`splitter --project`), as a persp at each leaf would: a process a
# leaf fewer (docs/performance.md, "The tree's depth"); `projected` says so.
start_tree() {
    local root=$1 below=$2 first n node levels=0 group span k out label
    local -a to_screen=() outputs=()
    projected=0
    for ((first = root; first < below; first *= 2)); do levels=$((levels + 1)); done
    for ((first = root, n = 1; first < below; first *= group, n *= group)); do
        # This group of levels: one level if an odd number are left, else two.
        span=$((levels % 2 ? 1 : 2)) levels=$((levels - span)) group=$((1 << span))
        if [[ ${3-} == leaves ]] && ((first * group >= below)); then
            to_screen=(--project --zmode "$zmode")
            projected=1
        fi
        for ((node = first; node < first + n; node++)); do
            outputs=()
            local into=/dev/null named=$group
            for ((k = node * group; k < (node + 1) * group; k++)); do
                input_of[k]=pipe:node-$k
                out=${input_of[k]}
                if ((projected && k == 1 << depth)) && merger_is_leaf; then
                    # Leaf 0's polygons go to the merger, which resolves them itself:
                    # that output is the splitter's stdout.
                    input_of[k]=pipe:leaf-0 out=- into=pipe:leaf-0 named=$((group - 1))
                fi
                outputs+=("$out")
            done
            label="node $node"
            ((span == 1)) || label+=", $span levels"
            npipes=$named start "splitter ($label)" \
                "${input_of[node]}" "$into" "$bindir/splitter" "${stats[@]}" --node "$node" \
                --depth "$depth" --levels "$span" --size "$size" "${to_screen[@]}" "${outputs[@]}"
        done
    done
    frontier=()
    for ((node = first; node < first + n; node++)); do frontier+=("$node"); done
}

# The hidden-surface stage at each leaf, as --merge, --hse and --aa choose it (sets
# `method`: the binary's name, then its options): by default scanconv resolves its region
# with a z-buffer; --merge buffer sends fragments on for the one zbuf to test (the
# thesis's PAR.BUFF).
leaf_method() {
    if [[ $merge == buffer ]]; then
        method=(scanconv "${pixels[@]}")
    elif [[ $aa == ss* ]]; then
        method=(supersample --samples "${aa#ss}")
    elif [[ $aa == abuf ]]; then
        method=(abuf)
    elif [[ $hse == zbuf ]]; then
        method=(scanconv --resolve)
    elif [[ $hse == painter ]]; then
        method=(painter "${split[@]}")
    else
        method=("$hse")
    fi
}

# merger_is_leaf: whether the merger resolves leaf 0 itself: zbuf reads screen-space
# polygons and resolves them as `scanconv --resolve` does (the same code, scan's), into
# its frame with no runs encoded, piped and decoded, and a process fewer. At depth 0 that
# leaf is the whole screen: zbuf reads the clipper's stream and projects it too (`zbuf
# --project`, persp's code), so that depth 0 is viewxf | clipbatch | zbuf. In a tree, the
# last level's first splitter writes leaf 0's polygons, projected, straight to zbuf. Only
# for the leaves' point-sampled z-buffer with --merge tiles, the leaves here
# (docs/performance.md, "Start-up" and "The tree's depth").
merger_is_leaf() {
    [[ $hse == zbuf && $aa == none && $merge == tiles && -z $subtree ]] && ((${#hosts[@]} == 0))
}

# start_leaf LEAF INPUT OUT: leaf LEAF (0 .. 2^depth − 1) of the tree, persp | METHOD, from
# INPUT to OUT; only METHOD where the splitter above projected (`projected`).
start_leaf() {
    local leaf=$1 in=$2 out=$3 label=
    ((depth == 0)) || label=" (leaf $leaf)"
    if ((!projected)); then
        start "persp$label" "$in" "pipe:screen-$leaf" \
            "$bindir/persp" --size "$size" --zmode "$zmode"
        in=pipe:screen-$leaf
    fi
    start "${method[0]}$label" "$in" "$out" \
        "$bindir/${method[0]}" "${method[@]:1}" "${stats[@]}"
}

# The level of the tree whose subtrees go to the hosts (`--hosts`): the first with at least
# one subtree a host, or the leaves'.
host_level() {
    local level=0
    while ((level < depth && (1 << level) < ${#hosts[@]})); do level=$((level + 1)); done
    echo "$level"
}

# what_node NODE: how the messages name a subtree: `leaf N` for a leaf, else `subtree K`.
what_node() {
    if (($1 >= 1 << depth)); then echo "leaf $(($1 - (1 << depth)))"; else echo "subtree $1"; fi
}

# start_subtrees: each node of `frontier` and all below it on a host, round-robin, through
# ssh (docs/DESIGN.md, "Stages on other hosts"): the binary stream into the node goes down
# the ssh channel to `render.sh --subtree K` there, which runs the node's splitters and
# leaves and merges their runs (zbuf --runs); the runs come back up it into a pipe the
# merger here reads. render.sh is run from the same path there as here, its binaries from
# --remote-bin (default: this one's). When ssh goes (the host drops, or the run is
# stopped), the far side's input ends short and its output has no reader: it stops.
start_subtrees() {
    local node i=0 host word remote
    local dir=${remote_bin:-$bindir}
    for node in "${frontier[@]}"; do
        host=${hosts[i++ % ${#hosts[@]}]}
        remote="exec env POLYPIPE_BIN=$(quote "$dir") $(quote "$root/scripts/render.sh")"
        for word in --subtree "$node" --depth "$depth" --size "$size" --zmode "$zmode" \
            --hse "$hse" "${split[@]}" --aa "$aa" "${stats[@]}"; do
            remote+=" $(quote "$word")"
        done
        fragments+=("pipe:from-$node")
        host_here=$host node_here=$node start "$(what_node "$node") (host $host)" \
            "${input_of[node]}" "pipe:from-$node" "${ssh_cmd[@]}" "$host" "$remote"
    done
}

# start_leaves [OUT]: a leaf for each node of `frontier` (all leaves' inputs), each into a
# pipe the merger reads; or, given OUT, the one leaf into OUT.
start_leaves() {
    local node leaf method
    leaf_method
    for node in "${frontier[@]}"; do
        leaf=$((node - (1 << depth)))
        if [[ -n ${1-} ]]; then
            start_leaf "$leaf" "${input_of[node]}" "$1"
        elif [[ ${input_of[node]} == pipe:leaf-0 ]]; then
            fragments+=(pipe:leaf-0) # the merger's own (merger_is_leaf)
            # At depth 0 the clipper's eye-space stream: the merger projects it too.
            ((depth > 0)) || to_screen=(--project --zmode "$zmode" --size "$size")
        else
            fragments+=("pipe:leaf-$leaf")
            start_leaf "$leaf" "${input_of[node]}" "pipe:leaf-$leaf"
        fi
    done
}

# The tree and its leaves, here or on the hosts, and the merger: from `clipped` (or, for
# --subtree K, from stdin into node K) to stdout.
start_graph() {
    local top=${subtree:-1}
    input_of=([top]=$clipped)
    fragments=() to_screen=()
    if ((${#hosts[@]})); then
        start_tree 1 $((1 << $(host_level)))
        start_subtrees
    else
        start_tree "$top" $((1 << depth)) leaves
        if ((${#frontier[@]} == 1)) && [[ -n $subtree ]]; then
            start_leaves - # one leaf: its runs are the subtree's
            return
        fi
        start_leaves
    fi
    start_merger
}

# --hidden-line: persp | hiddenline, writing the SVG (Archuleta's output) where -o says.
start_hidden_line() {
    start persp "$clipped" pipe:screen "$bindir/persp" --size "$size" --zmode "$zmode"
    start hiddenline pipe:screen - "$bindir/hiddenline" "${hl_method[@]}" "${stats[@]}" "${output[@]}"
}

# The merger (chapter 6.3.3): one zbuf reading every leaf, writing the frames.
start_merger() {
    local relay=()
    [[ -z $subtree ]] || relay=(--runs) # a subtree's runs go on to the merger above
    npipes=${#fragments[@]} start zbuf /dev/null - "$bindir/zbuf" "${relay[@]}" "${stats[@]}" \
        "${to_screen[@]}" "${output[@]}" "${first_frame[@]}" "${fragments[@]}"
}

# --depth auto: the depth the cost model predicts fastest (thesis 5.2 and 6.4, with this
# machine's calibration: docs/model.md), from `plan depth`'s look at the scene's first
# 512 KiB. A stream (stdin, or a pipe given as the scene) is sampled first: `plan sample`
# keeps its first 512 KiB in a file of TMPDIR, or less when the stream ends, or pauses (a
# live source is not held up), and `plan relay` then feeds viewxf that sample and the
# rest of the stream behind it, so that no more than the sample is kept; the launcher
# removes the file when the run ends (the script itself, if it ends before). A scene the look cannot read is left to the stages, at
# depth 0, which report it as they do at any depth. With --hosts, the plan is for the
# hosts (every host a subtree). On a terminal, an uncalibrated machine is said once.
# tiny_scene: whether the scene file is too small for the tree to pay on any number of
# cores, so that the model need not be asked (starting `plan` and its look cost a small
# render about a third of its time). A polygon takes at least 16 bytes of a scene file
# (three vertices and NEXT.POLYGON take 31 in text) and fills at most the screen, so a
# file of B bytes asks at most B/16·W·H depth tests of the leaves, which test 300 million
# a CPU second (docs/performance.md, "The fill rate"): under 9,600,000/(W·H) bytes that
# is under 2 ms, less than the tree's extra processes cost to start. The bytes are
# counted by bash's `read`, without a process, up to that bound. A scene not in the text
# form (a binary stream: its first byte is 0x89) is left to the model.
# Sets tiny_bound, the bound in bytes.
tiny_scene() {
    local data
    [[ $size =~ ^0*([1-9][0-9]*)[xX]0*([1-9][0-9]*)$ ]] || return 1
    tiny_bound=$((9600000 / (BASH_REMATCH[1] * BASH_REMATCH[2])))
    ((tiny_bound >= 64)) || return 1
    LC_ALL=C IFS= read -r -d '' -N "$((tiny_bound + 1))" data < "$scene" 2>/dev/null
    ((${#data} <= tiny_bound)) && [[ ${data:0:1} != $'\x89' ]]
}

choose_depth() {
    local line look=$scene ended
    local -a extra=()
    if [[ ! -x $bindir/plan ]]; then
        # Asked for, the model is missed; by default (a host's binaries, say), depth 0.
        ((!depth_asked)) || fail 3 "no plan in $bindir, for --depth auto"
        depth=0
        return
    fi
    if [[ $scene == - ]]; then
        # The name chosen, and its removal set, before the file is made (`plan sample`
        # refuses a name that exists, a link included).
        sample=${TMPDIR:-/tmp}/render.$$.$SRANDOM.sample
        trap '[[ -z ${sample-} ]] || rm -f -- "$sample"' EXIT
        trap 'exit 130' INT
        trap 'exit 143' TERM
        ended=$("$bindir/plan" sample -o "$sample") ||
            fail 3 "cannot keep the sample of the scene in ${TMPDIR:-/tmp}"
        look=$sample
        extra=(--stream "$ended")
        if [[ $ended == whole ]]; then scene=$sample; else feed=$sample; fi
    fi
    ((${#hosts[@]} == 0)) || extra+=(--hosts "${#hosts[@]}")
    [[ ! -t 2 ]] || extra+=(--tell-once)
    # The answer is the first line; a once-said note follows it (stderr), shown only
    # when the model answered: a scene it cannot read is the stages' to report.
    if ! line=$("$bindir/plan" depth --root "$root" --size "$size" "${extra[@]}" \
        "${camera[@]}" "$look" 2>&1); then
        depth=0
        return
    fi
    [[ $line != *$'\n'* ]] || printf '%s\n' "${line#*$'\n'}" >&2
    line=${line%%$'\n'*}
    depth=${line%% *}
    [[ $depth =~ ^[0-6]$ ]] || fail 3 "plan depth answered '$line'"
    ((${#stats[@]} == 0)) || echo "render.sh: depth auto chose $line" >&2
}

# --by frames: the `farm` binary cuts the movie into chunks and hands them to GNU
# parallel, which runs each on a host, `render.sh OPTIONS -` there (this script, at the
# same path, with the binaries of --remote-bin), retrying a failed chunk on another; farm
# writes the frames back in order (stdout, or -o's files). With --slurm-array DIR, farm
# writes DIR/render.sbatch instead. The options are checked here first, as a local
# render would check them.
frames_on_hosts() {
    [[ -z $subtree ]] || die_usage "--subtree is a host's part of --by leaves: not with --by frames"
    ((${#times[@]} == 0)) || die_usage "--times is the stages' here: not with --by frames"
    local -a where=()
    [[ -z $hosts_list ]] || where=(--hosts "$hosts_list")
    hosts=()
    validate_options
    ensure_binaries
    exec "$bindir/farm" "${where[@]}" "${farm_opts[@]}" "${chunk[@]}" "${stats[@]}" \
        "${output[@]}" "${first_frame[@]}" "$scene" -- \
        env POLYPIPE_BIN="${remote_bin:-$bindir}" "$root/scripts/render.sh" "${forward[@]}" -
}

main() {
    locate_repository
    me=render.sh
    # shellcheck source=lib/binaries.sh
    source "$root/scripts/lib/binaries.sh"
    parse_options "$@"
    if [[ -n $hosts_list || -n $by ]]; then # rendering on other hosts
        [[ -n $hosts_list || ($by == frames && ${#farm_opts[@]} -gt 0) ]] ||
            die_usage "--by $by needs --hosts H1,H2,…"
        [[ ${by:-leaves} == @(leaves|frames) ]] ||
            die_usage "--by must be leaves or frames, not '$by'"
        # shellcheck source=hosts.sh
        source "$root/scripts/hosts.sh"
        [[ -z $hosts_list ]] || check_hosts "$hosts_list"
        [[ $by != frames ]] || frames_on_hosts
    fi
    ((${#chunk[@]} == 0)) || die_usage "--chunk is for --by frames"
    ((${#farm_opts[@]} == 0)) || die_usage "${farm_opts[0]} is for --by frames"
    ((${#first_frame[@]} == 0 || ${#output[@]} > 0)) || die_usage "--first-frame numbers -o's files: it needs -o"
    validate_options
    [[ -r /proc/self/stat ]] || fail 3 "needs /proc (Linux), to run its stages"
    ensure_binaries
    if [[ $depth == auto ]] && ((hidden_line)); then depth=0; fi
    # A scene that can be read only once (a pipe, `<(…)`), looked at by --depth auto, is
    # sampled as stdin is.
    if [[ $depth == auto && $scene != - && ! -f $scene && -z $subtree ]]; then
        exec <"$scene" || fail 3 "cannot read scene $scene"
        scene=-
    fi
    if [[ $depth == auto && -f $scene && -z $subtree ]] && ((${#hosts[@]} == 0)) && tiny_scene; then
        depth=0
        ((${#stats[@]} == 0)) ||
            echo "render.sh: depth auto chose 0 (a scene file of at most $tiny_bound bytes on a $size screen: under 2 ms of depth tests; the model not asked)" >&2
    fi
    [[ $depth != auto ]] || choose_depth
    graph
    local -a launch=(--depth "$depth" "${times[@]}")
    ((${#stats[@]} == 0 || ${#hosts[@]} == 0)) || launch+=(--links)
    [[ -z ${sample-} ]] || launch+=(--remove "$sample")
    exec "$bindir/plan" launch "${launch[@]}" -- "${spec[@]}"
}

# The stages, from the scene (or, for --subtree K, the stream into node K on stdin) to
# the frames on stdout: the clipper chain, which sets `clipped`, then all after it.
graph() {
    if [[ -n $subtree ]]; then
        clipped=- # the stream into node K
    else
        start_clipper_chain
    fi
    if ((hidden_line)); then
        start_hidden_line
    else
        start_graph
    fi
}

# Sourced (scripts/chart.sh does, for ensure_binaries: one freshness check for both), it
# only defines; run, it renders.
[[ ${BASH_SOURCE[0]} != "$0" ]] || main "$@"
