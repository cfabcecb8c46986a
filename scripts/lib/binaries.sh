# shellcheck shell=bash
# shellcheck disable=SC2154 # root, set by the script that sources this
# binaries.sh: the polypipe binaries built when missing or older than their sources,
# for the scripts that run them (render.sh, chart.sh), with one freshness check: a
# glance that starts no process on most runs, cargo only when a source is newer. Sourced,
# not run; needs `root` (the repository), `fail STATUS MESSAGE`, and the caller's name
# in `me` for its messages.

# The stages render.sh runs, and the other binaries the README's examples use: all built
# on the first run, so that every command in the README works after it.
binaries=(viewxf clipplane clipbatch splitter persp scanconv zbuf scanline warnock painter
    hiddenline supersample abuf scene zspec frames farm chart plan)

# release_dir TARGET: sets `bindir` to cargo's release folder in the target folder
# TARGET: TARGET/<host tuple>/release, where .cargo/config.toml's `target = "host-tuple"`
# has cargo build this machine's binaries (static ones, on Linux). The tuple is read from
# the folder cargo made, not asked of rustc (a process on every run): the first whose name
# starts with this machine's architecture (bash's HOSTTYPE: x86_64, aarch64), else the
# first of any; TARGET/release where cargo has made none yet (nothing built) or where the
# binaries were built without that setting.
release_dir() {
    local d
    for d in "$1/$HOSTTYPE"-*/release "$1"/*-*/release; do
        if [[ -d $d && ! -L $d ]]; then
            bindir=$d
            return 0
        fi
    done
    bindir=$1/release
}

# release_bin ROOT: on stdout, the folder cargo builds the repository ROOT's release
# binaries into (release_dir of its target folder, a relative CARGO_TARGET_DIR taken from
# ROOT): for the scripts that run cargo build themselves, once it has built.
release_bin() {
    local target=${CARGO_TARGET_DIR:-target} bindir
    [[ $target == /* ]] || target=$1/$target
    release_dir "$target"
    echo "$bindir"
}

# link_bin TARGET: TARGET/bin made a link to `bindir` (TARGET/<host>/release), the one
# name for the binaries on every machine (the README's `target/bin/NAME`). Not
# TARGET/release: with a target named, cargo keeps the build scripts and procedural macros
# there, and a link in its place would have cargo wait for its own lock. Left alone where
# it is already that link, or is anything but a link.
link_bin() {
    local link=$1/bin
    [[ ! $link -ef $bindir ]] || return 0
    [[ -e $link && ! -L $link ]] || ln -sfn "${bindir#"$1"/}" "$link" 2>/dev/null || true
}

# build_binaries: sets `bindir`, and builds the binaries with cargo when one is missing
# or stale. Without cargo, binaries already built are run as they are (with a warning
# if stale).
build_binaries() {
    # cargo runs in the repository root and takes a relative CARGO_TARGET_DIR from there.
    local target=${CARGO_TARGET_DIR:-target} b
    [[ $target == /* ]] || target=$root/$target
    release_dir "$target"
    local stamp=$bindir/.render.sh-asked-cargo
    local -a missing=() stale=() packages=()
    if all_fresh "$stamp"; then
        link_bin "$target"
        return 0
    fi
    for b in "${binaries[@]}"; do
        packages+=(-p "$b")
        if [[ ! -x $bindir/$b ]]; then
            missing+=("$b")
        elif is_stale "$bindir/$b" "$stamp"; then
            stale+=("$b")
        fi
    done
    if ((${#missing[@]} + ${#stale[@]} == 0)); then
        # Every binary is current by its own sources: say so in the stamp, so that the
        # next run's quick look passes instead of reading every dep-info again (after a
        # `cargo build` by hand that left some binary untouched, every run did).
        touch "$stamp" 2>/dev/null
        link_bin "$target"
        return 0
    fi
    if ! command -v cargo >/dev/null; then
        ((${#missing[@]} == 0)) ||
            fail 3 "cannot build ${missing[*]} into $bindir: cargo is not on PATH (Rust: https://rustup.rs)"
        echo "$me: warning: ${stale[*]}: older than their sources, and no cargo on PATH to rebuild them; running them as they are" >&2
        return 0
    fi
    if ((${#missing[@]} == ${#binaries[@]})); then
        echo "$me: building the polypipe binaries (first run only)…" >&2
    elif ((${#missing[@]} > 0)); then
        echo "$me: building ${missing[*]}…" >&2
    elif [[ -t 2 ]]; then
        echo "$me: rebuilding the polypipe binaries (their sources changed)…" >&2
    fi
    (cd "$root" && cargo build --release --quiet "${packages[@]}") >&2 || fail 3 "cargo build failed"
    # The first build makes the folder: where it is, and the stamp there.
    release_dir "$target"
    touch "$bindir/.render.sh-asked-cargo" 2>/dev/null
    link_bin "$target"
}

# all_fresh STAMP: a quick look that finds nothing to do on most runs: every binary is
# there, and no file a binary could be built from is newer than the oldest binary and
# than STAMP. Those files are the workspace's manifests and lock and, in each of its
# crates (proto, scan, stagecli and bins/*: docs/DESIGN.md's layout), the manifest, a
# build script, and what is under src/ or fonts/ (chart's font) to three levels; not
# tests, benches, scripts, documents or examples. When it finds a file, is_stale decides
# binary by binary.
#
# Finding those files is globbing some forty folders (about 4 ms of every render), so
# the list is kept, with the folders it came from, in STAMP.sources: a run reads it (one
# `mapfile`, no process) and tests each name with `-nt`, the cost of a stat apiece. A
# file made, removed or renamed in a folder (an editor that saves by renaming included)
# makes the folder newer than the list, and the folders are globbed again.
all_fresh() {
    local b oldest='' file list=$1.sources
    for b in "${binaries[@]}"; do
        [[ -x $bindir/$b ]] || return 1
        [[ -n $oldest && ! $bindir/$b -ot $oldest ]] || oldest=$bindir/$b
    done
    # A source newer than both the oldest binary and STAMP: newer than the newer of them.
    local newest=$oldest
    [[ ! $1 -nt $oldest ]] || newest=$1
    local -a files=() folders=()
    # The list is trusted only whole: its last line says it was written to the end.
    if [[ -f $list ]] && mapfile -t files < "$list" && [[ ${files[-1]-} == end ]]; then
        unset 'files[-1]'
        for file in "${files[@]}"; do
            if [[ $file == */ ]]; then
                # A folder (listed with its slash): changed since the list was made?
                [[ ! $file -nt $list ]] || { files=(); break; }
            elif [[ $file -nt $newest ]]; then
                return 1
            fi
        done
        ((${#files[@]} == 0)) || return 0
    fi
    # (An empty list falls through too: a run on a tree with no sources globs.)
    files=("$root"/Cargo.toml "$root"/Cargo.lock)
    local had_nullglob=0
    ! shopt -q nullglob || had_nullglob=1
    shopt -s nullglob
    files+=("$root"/{proto,scan,stagecli,bins/*}/{Cargo.toml,build.rs,src/*,src/*/*,src/*/*/*,fonts/*})
    folders=("$root"/ "$root"/bins/ "$root"/{proto,scan,stagecli,bins/*}/{,src/,src/*/,src/*/*/,fonts/})
    ((had_nullglob)) || shopt -u nullglob
    for file in "${files[@]}"; do
        [[ $file -nt $newest ]] && return 1
    done
    # Where the list cannot be written (a read-only target), every run globs.
    { printf '%s\n' "${folders[@]}" "${files[@]}" end > "$list"; } 2>/dev/null
    return 0
}

# is_stale BINARY STAMP: whether a source of BINARY is newer than it and than STAMP (when
# a script last had cargo bring the binaries up to date: cargo leaves a binary alone when
# what changed does not affect it, as an unrelated change to Cargo.lock). The sources are
# the files cargo's dep-info (BINARY.d, "BINARY: SOURCE…") lists, the Cargo.toml of each
# crate among them, and the workspace's Cargo.toml and Cargo.lock; not tests, benches or
# documents, which no binary is built from.
is_stale() {
    local bin=$1 text file crate
    local -a files tomls=("$root/Cargo.toml" "$root/Cargo.lock")
    [[ -r $bin.d ]] || return 0
    IFS= read -r -d '' text <"$bin.d"
    text=${text#*: } text=${text//\\ /$'\1'} # a space in a name is `\ `
    read -r -a files <<<"${text//$'\n'/ }"
    for file in "${files[@]//$'\1'/ }"; do
        crate=${file#"$root"/} crate=${crate%%/src/*}
        [[ $file == "$root"/*/src/* ]] && tomls+=("$root/$crate/Cargo.toml")
    done
    for file in "${files[@]//$'\1'/ }" "${tomls[@]}"; do
        [[ $file -nt $bin && $file -nt $2 ]] && return 0
    done
    return 1
}
