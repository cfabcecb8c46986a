#!/usr/bin/env bash
# bench.sh: polypipe against Mesa's llvmpipe, against its own fused run, and against
# itself at splitter depths 0-4: one markdown table of ratios, every figure
# from this one run, so the ratios compare runs made on the same machine under the same
# load. Not part of CI.
#
# Every figure is the whole process's wall time (start to exit, reading the text scene
# and writing the PPM frames to /dev/null), the median of REPS runs (default 5). The
# commands are run interleaved, one round of all of them per repetition, so that a change
# in the machine's load during the run falls on every command alike. Each command is run
# once more first, not timed, to warm the page cache and to keep its pictures for the
# table's last column. Beside each A/B (the ratio of the medians) is the median of the
# rounds' own A/B ("by rounds"): A and B of one round ran moments apart, so a change in
# load between rounds falls on both, and on a noisy machine it is the steadier figure.
#
# The scenes are the four classes below, made by `scene environment` as text (the
# user's input and llvmpipe's is text):
#   (a) 1,024 quads at 500x500            (b) 100,000 quads, depth complexity 2, 500x500
#   (c) 10,000 quads, depth complexity 10, 1920x1080 (the fill-heavy scene)
#   (d) a 100-frame movie of 1,024 quads at 500x500
#   (e) two polygons at 64x64 (examples/triangle-square.txt: start-up, nothing else)
#   (f) a large mesh at 500x500: a real model, not one of this project's generators'
#       (`scene obj --shade` of MESH, default WusonOBJ.obj of Debian's
#       assimp-testmodels: 3,732 faces, mostly triangles of a few pixels). Get it with
#       `apt-get install assimp-testmodels` (it lands in /usr/share/assimp/models/OBJ/);
#       when the file is missing the row is skipped, with a message saying so.
#
# The rows: render.sh with its default options against the llvmpipe harness
# (bench/llvmpipe/render.c through OSMesa, the same scene, camera and pyramid) and
# against the fused run (target/bin/fused, if built: one process chaining the same
# stage libraries; run as `fused --size WxH SCENE`), then render.sh --depth 0..4 on the
# fill-heavy scene with each merge mode (--merge tiles and --merge buffer, if render.sh
# has them), each against depth 0 in the same mode. A/B below 1 means A is faster.
# A second table gives render.sh against llvmpipe by CPU seconds (user + system of the
# whole process tree) from the same runs, and a third the work the tree adds: the CPU
# seconds of render.sh --depth 0..4 on the fill-heavy scene, all on one core
# (`taskset -c 0`), each against depth 0's.
#
# --scaling instead runs render.sh --depth 0..6 on the fill-heavy scene on every core
# count from 1 to nproc (`taskset -c 0-(N-1)`), interleaved likewise, and prints the
# wall seconds and the speed-up of each against depth 0 on one core.
#
# Environment: RENDER (default scripts/render.sh) and FUSED (default target/bin/fused,
# or the release folder's examples/fused) name other commands to measure in their place;
# POLYPIPE_BIN a folder of built binaries to measure as they are, with no cargo build;
# MESH the OBJ file of row (f) (default /usr/share/assimp/models/OBJ/WusonOBJ.obj).
#
# Usage: scripts/bench.sh [--quick] [--reps N] [--scaling] [--fill N WxH]
#   --quick    3 repetitions and smaller scenes (b: 20,000 quads; c: 2,000 quads at
#              960x540; d: 20 frames), to try the script out
#   --reps N   repetitions per command (median of N; default 5, or 3 with --quick)
#   --scaling  only the table of depths 0-6 against core counts 1..nproc
#   --fill N WxH  the fill-heavy scene (c) with N quads at WxH instead (a heavier one
#              shows what the tree does when the work outweighs starting the processes)
#
# Needs: cargo (unless POLYPIPE_BIN), taskset (util-linux), gcc and OSMesa
# (bench/llvmpipe/build.sh installs libosmesa6-dev when run as root; otherwise llvmpipe's
# rows are n/a and it says what to install; --scaling needs neither), python3 or awk for
# the medians.
set -euo pipefail
export LC_ALL=C

usage() { sed -n '/^# Usage:/,/^# Needs:/p' "$0" | sed '$d; s/^# \{0,1\}//'; }

quick=0
scaling=0
reps=
fill_opt=()
while (($#)); do
    case $1 in
        --quick) quick=1; shift ;;
        --scaling) scaling=1; shift ;;
        --reps) (($# >= 2)) || { echo "bench.sh: --reps needs N" >&2; exit 2; }; reps=$2; shift 2 ;;
        --reps=*) reps=${1#*=}; shift ;;
        --fill)
            (($# >= 3)) || { echo "bench.sh: --fill needs N and WxH" >&2; exit 2; }
            [[ $2 =~ ^[1-9][0-9]*$ && $3 =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] ||
                { echo "bench.sh: --fill needs a count and WxH, not '$2 $3'" >&2; exit 2; }
            fill_opt=("$2" "$3")
            shift 3
            ;;
        -h | --help) usage; exit 0 ;;
        *) echo "bench.sh: unknown argument $1" >&2; usage >&2; exit 2 ;;
    esac
done
[[ -z $reps ]] && reps=$((quick ? 3 : 5))
[[ $reps =~ ^[1-9][0-9]*$ ]] || { echo "bench.sh: --reps must be a positive integer, not '$reps'" >&2; exit 2; }

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=lib/bench.sh
source "$root/scripts/lib/bench.sh"
cd "$root"
render=${RENDER:-$root/scripts/render.sh}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# POLYPIPE_BIN names a folder of built binaries to measure as they are, never built (as
# render.sh takes it): a machine with no cargo, such as a many-core one lent for --scaling.
if [[ -n ${POLYPIPE_BIN-} ]]; then
    B=$POLYPIPE_BIN
    for b in scene plan; do
        [[ -x $B/$b ]] || { echo "bench.sh: no $b in $B (POLYPIPE_BIN)" >&2; exit 3; }
    done
    export POLYPIPE_BIN
    echo "bench.sh: measuring the binaries in $B as they are (POLYPIPE_BIN)" >&2
else
    echo "bench.sh: building polypipe" >&2
    cargo build --release --quiet --bins
    B=$(release_bin "$root")
fi
gl=
if ((scaling)); then :; elif gl=$("$root/bench/llvmpipe/build.sh"); then :; else
    gl=
    echo "bench.sh: no llvmpipe harness; its rows will read n/a" >&2
fi
fused=
for f in ${FUSED:-} "$B/fused" "$B/examples/fused"; do
    if [[ -x $f ]]; then fused=$f; break; fi
done
merge=0
if "$render" --help 2>/dev/null | grep -q -- --merge; then merge=1; fi

# --- The scenes. ----------------------------------------------------------------------
if ((quick)); then
    geo_n=20000 fill_n=2000 fill_size=960x540 movie_frames=20
else
    geo_n=100000 fill_n=10000 fill_size=1920x1080 movie_frames=100
fi
((${#fill_opt[@]})) && fill_n=${fill_opt[0]} fill_size=${fill_opt[1]}
commas() { sed ':a; s/\B[0-9]\{3\}\>/,&/; ta' <<< "$1"; }
scenes=(env geo fill movie two)
declare -A size label
size[env]=500x500 label[env]="(a) $(commas 1024) quads, 500×500"
size[geo]=500x500 label[geo]="(b) $(commas "$geo_n") quads, Dc≈2, 500×500"
size[fill]=$fill_size label[fill]="(c) $(commas "$fill_n") quads, Dc≈10, ${fill_size/x/×}"
size[movie]=500x500 label[movie]="(d) $(commas 1024) quads × $movie_frames frames, 500×500"
size[two]=64x64 label[two]="(e) two polygons, 64×64"
echo "bench.sh: generating the scenes" >&2
"$B/scene" environment --text --seed 1 --polygons 1024 --size 500x500 > "$work/env.txt"
"$B/scene" environment --text --seed 3 --polygons "$geo_n" --depth-complexity 2 --size 500x500 > "$work/geo.txt"
fill_scene "$B" "$fill_n" "$fill_size" > "$work/fill.txt"
"$B/scene" environment --text --seed 4 --polygons 1024 --frames "$movie_frames" --size 500x500 > "$work/movie.txt"
cp "$root/examples/triangle-square.txt" "$work/two.txt"
# (f), from a model file this project did not make: skipped, with a message, without it.
mesh=${MESH:-/usr/share/assimp/models/OBJ/WusonOBJ.obj}
if [[ -r $mesh ]] && "$B/scene" obj --shade --text "$mesh" > "$work/mesh.txt"; then
    faces=$(grep -c '^[[:space:]]*f[[:space:]]' "$mesh" || true)
    scenes+=(mesh)
    size[mesh]=500x500 label[mesh]="(f) ${mesh##*/}, $(commas "$faces") faces, 500×500"
else
    echo "bench.sh: no large mesh at $mesh (apt-get install assimp-testmodels, or MESH=FILE.obj): row (f) skipped" >&2
fi

# --- The commands, by name. -----------------------------------------------------------
jobs=()
declare -A cmd ok
job() { # NAME COMMAND...: a command to time, its words quoted once here
    local name=$1 q
    shift
    printf -v q '%q ' "$@"
    jobs+=("$name")
    cmd[$name]=$q
}
cores=$(nproc)
if ((scaling)); then
    scenes=()
    for ((c = 1; c <= cores; c++)); do
        for d in 0 1 2 3 4 5 6; do
            job "scale.$c.$d" taskset -c "0-$((c - 1))" "$render" --size "$fill_size" --depth "$d" "$work/fill.txt"
        done
    done
    modes=()
else
    for s in "${scenes[@]}"; do
        job "pipe.$s" "$render" --size "${size[$s]}" "$work/$s.txt"
        [[ -n $gl ]] && job "gl.$s" "$gl" --size "${size[$s]}" "$work/$s.txt"
        [[ -n $fused ]] && job "fused.$s" "$fused" --size "${size[$s]}" "$work/$s.txt"
    done
    # Without --merge (a render.sh older than the leaves that resolve), the depths are measured as they are.
    modes=(tiles buffer)
    ((merge)) || modes=(default tiles buffer)
    for m in "${modes[@]}"; do
        merge_opt=(--merge "$m")
        case $m in
            default) merge_opt=() ;;
            *) ((merge)) || continue ;;
        esac
        for d in 0 1 2 3 4; do
            job "depth.$m.$d" "$render" --size "$fill_size" --depth "$d" "${merge_opt[@]}" "$work/fill.txt"
        done
    done
    # The work on one core: CPU seconds, not wall.
    for d in 0 1 2 3 4; do
        job "one.$d" taskset -c 0 "$render" --size "$fill_size" --depth "$d" "$work/fill.txt"
    done
fi

# --- Warm-up: every command once, its pictures kept; a failure is reported, and the
# command's rows read n/a (render.sh failing stops the run: nothing to compare).
echo "bench.sh: warming up (${#jobs[@]} commands)" >&2
for j in "${jobs[@]}"; do
    if eval "${cmd[$j]}" > "$work/out.$j" 2> "$work/err.$j"; then
        ok[$j]=1
    else
        echo "bench.sh: $j failed: ${cmd[$j]}" >&2
        sed 's/^/  /' "$work/err.$j" >&2
        [[ $j == pipe.* ]] && exit 1
    fi
done

# --- The timed rounds. ----------------------------------------------------------------
# Each run's wall seconds (bash's microsecond clock) and CPU seconds (user + system of the
# whole process tree: bash's `time` counts the children it waited for, to the
# millisecond; written to a file, so that no subshell is timed).
declare -A times cpus
TIMEFORMAT='%3U %3S'
for ((r = 1; r <= reps; r++)); do
    echo "bench.sh: round $r of $reps" >&2
    for j in "${jobs[@]}"; do
        [[ -n ${ok[$j]:-} ]] || continue
        t0=$EPOCHREALTIME
        { time eval "${cmd[$j]}" > /dev/null 2> "$work/err.$j"; } 2> "$work/time.$j" ||
            { echo "bench.sh: $j failed in round $r" >&2; cat "$work/err.$j" >&2; exit 1; }
        t1=$EPOCHREALTIME
        times[$j]+="$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.6f", b - a }') "
        cpus[$j]+="$(awk '{ printf "%.3f", $1 + $2 }' "$work/time.$j") "
    done
done

figures() { # LIST: a job's figures (one a round, space-separated), one a line
    tr ' ' '\n' <<< "$1" | grep .
}

job_median() { # JOB: the median of its wall times, or nothing
    [[ -n ${times[$1]:-} ]] || return 0
    figures "${times[$1]}" | median
}

cpu_median() { # JOB: the median of its CPU times, or nothing
    [[ -n ${cpus[$1]:-} ]] || return 0
    figures "${cpus[$1]}" | median
}

# by_rounds A-LIST B-LIST: the median of the rounds' A/B (two jobs' figures, in round
# order), to two places; `-` where there are none, or a round has no positive pair.
by_rounds() {
    local ratios
    ratios=$(paste -d ' ' <(figures "$1") <(figures "$2") |
        awk '!($1 > 0 && $2 > 0) { exit 1 } { print $1 / $2 }') && [[ -n $ratios ]] ||
        { echo -; return; }
    median <<< "$ratios" | awk '{ printf "%.2f", $1 }'
}

# differ A B: how two runs' pictures compare ("identical", or differing pixels of all).
differ() {
    local a=$work/out.$1 b=$work/out.$2
    [[ -n ${ok[$1]:-} && -n ${ok[$2]:-} ]] || { echo n/a; return; }
    if cmp -s "$a" "$b"; then echo identical; return; fi
    "$B/zspec" compare --min-agreement 0 "$a" "$b" 2>&1 |
        awk '/differ/ { px += $3; d += $5; n++ } END { if (n) printf "%d of %d px differ\n", d, px; else print "frames differ" }' |
        sed ':a; s/\B[0-9]\{3\}\>/,&/; ta'
}

# row WHAT SCENE-LABEL JOB-A JOB-B CHECK
row() {
    local ta tb ratio=n/a rounds=n/a
    ta=$(job_median "$3") tb=$(job_median "$4")
    [[ -n $ta ]] || ta=n/a
    [[ -n $tb ]] || tb=n/a
    if [[ $ta != n/a && $tb != n/a ]]; then
        ratio=$(ratio "$ta" "$tb")
        rounds=$(by_rounds "${times[$3]}" "${times[$4]}")
    fi
    echo "| $1 | $2 | $ta | $tb | **$ratio** | $rounds | $5 |"
}

# --- The table. ------------------------------------------------------------------------
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null || true)
mesa=n/a
[[ -n $gl ]] && mesa=$("$gl" --renderer 2>/dev/null || echo n/a)
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
# Binaries from elsewhere need not be this commit's: the table says whose they are.
[[ -z ${POLYPIPE_BIN-} ]] || commit+=" (the scripts; the binaries: POLYPIPE_BIN=$POLYPIPE_BIN)"
if ((scaling)); then
    echo
    echo "Measured by \`scripts/bench.sh$( ((quick)) && echo ' --quick') --scaling\` at commit $commit on" \
        "${cpu:-an unknown CPU}, $cores cores, $(date -u +%Y-%m-%d): render.sh --depth D on" \
        "${label[fill]} under \`taskset -c 0-(N-1)\`, whole-process wall seconds, median of" \
        "$reps, from one run; speed-up against depth 0 on one core."
    echo
    head="| cores |" rule="|---|"
    for d in 0 1 2 3 4 5 6; do head+=" depth $d s (speed-up) |" rule+="---|"; done
    echo "$head"
    echo "$rule"
    base=$(job_median scale.1.0)
    for ((c = 1; c <= cores; c++)); do
        line="| $c |"
        for d in 0 1 2 3 4 5 6; do
            t=$(job_median "scale.$c.$d")
            if [[ -n $t ]]; then line+=" $t ($(ratio "$base" "$t")) |"; else line+=" n/a |"; fi
        done
        echo "$line"
    done
    exit 0
fi

echo
echo "Measured by \`scripts/bench.sh$( ((quick)) && echo ' --quick')\` at commit $commit on ${cpu:-an unknown CPU}," \
    "$(nproc) cores, $(date -u +%Y-%m-%d): whole-process wall seconds, median of $reps," \
    "from one run. A/B below 1 means A is faster. llvmpipe: $mesa, through OSMesa," \
    "reading the same text scene (bench/llvmpipe/render.c)."
echo
echo "| A against B | scene | A s | B s | A/B | by rounds | pictures |"
echo "|---|---|---|---|---|---|---|"
for s in "${scenes[@]}"; do
    row "render.sh against llvmpipe" "${label[$s]}" "pipe.$s" "gl.$s" "$(differ "pipe.$s" "gl.$s")"
done
for s in "${scenes[@]}"; do
    row "render.sh against fused run" "${label[$s]}" "pipe.$s" "fused.$s" "$(differ "pipe.$s" "fused.$s")"
done
for m in "${modes[@]}"; do
    for d in 0 1 2 3 4; do
        what="depth $d against depth 0, \`--merge $m\`"
        if [[ $m == default ]]; then
            what="depth $d against depth 0 (render.sh without \`--merge\`)"
            check="$(differ "depth.$m.$d" "depth.$m.0") to depth 0"
        elif ((merge)); then
            check="$(differ "depth.$m.$d" "depth.tiles.0") to tiles depth 0"
        else
            check="n/a: render.sh has no --merge"
        fi
        row "$what" "${label[fill]}" "depth.$m.$d" "depth.$m.0" "$check"
    done
done

echo
echo "The same runs by CPU: user + system seconds of the whole process tree (llvmpipe's" \
    "threads counted), median of $reps."
echo
echo "| A against B | scene | A CPU s | B CPU s | A/B | by rounds |"
echo "|---|---|---|---|---|---|"
for s in "${scenes[@]}"; do
    a=$(cpu_median "pipe.$s") b=$(cpu_median "gl.$s")
    echo "| render.sh against llvmpipe | ${label[$s]} | ${a:-n/a} | ${b:-n/a} | **$(ratio "${a:-0}" "${b:-0}")** | $(by_rounds "${cpus[pipe.$s]:-}" "${cpus[gl.$s]:-}") |"
done

echo
echo "The work the tree adds: render.sh --depth D on ${label[fill]}, all on one core" \
    "(\`taskset -c 0\`), CPU seconds (user + system of the whole process tree), median of $reps."
echo
echo "| depth | CPU s | against depth 0 | by rounds |"
echo "|---|---|---|---|"
base=$(cpu_median one.0)
for d in 0 1 2 3 4; do
    t=$(cpu_median "one.$d")
    echo "| $d | ${t:-n/a} | **$(ratio "${t:-0}" "${base:-0}")** | $(by_rounds "${cpus[one.$d]:-}" "${cpus[one.0]:-}") |"
done
