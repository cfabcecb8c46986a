# shellcheck shell=bash
# binaries.sh, sourced by the scripts that run the polypipe binaries: where cargo puts them.

# release_dir TARGET: sets `bindir` to TARGET/<host tuple>/release, where .cargo/config.toml's
# `target = "host-tuple"` has cargo build (this machine's architecture first); else TARGET/release.
release_dir() {
    local d
    for d in "$1/$HOSTTYPE"-*/release "$1"/*-*/release; do
        [[ -d $d && ! -L $d ]] && { bindir=$d; return 0; }
    done
    bindir=$1/release
}
# find_binaries: sets `target` ($CARGO_TARGET_DIR from `root`, or root/target) and `bindir`,
# and links TARGET/bin to bindir (the README's target/bin) unless it is already.
find_binaries() {
    target=${CARGO_TARGET_DIR:-target} && [[ $target == /* ]] || target=$root/$target
    release_dir "$target"
    [[ $target/bin -ef $bindir || (-e $target/bin && ! -L $target/bin) ]] ||
        ln -sfn "${bindir#"$target"/}" "$target/bin" 2>/dev/null || true
}
# release_bin ROOT: on stdout, the folder of the repository ROOT's release binaries.
release_bin() { local root=$1 target bindir; find_binaries; echo "$bindir"; }
# build_binaries: cargo builds them all when render is missing; else render's own look
# (bins/render/src/fresh.rs) has cargo build only when a source is newer than them.
build_binaries() {
    find_binaries
    if [[ -x $bindir/render ]]; then POLYPIPE_SOURCES=$root "$bindir/render" --build-only || exit 3; return; fi
    (cd "$root" && cargo build --release --quiet --bins) >&2 || { echo "${me:-${0##*/}}: cargo build failed" >&2; exit 3; }
    find_binaries
}
