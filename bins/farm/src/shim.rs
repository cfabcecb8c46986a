//! parallel's ssh: the script that takes a chunk to its host and waits for farm.

use stagecli::remote::quote;
use std::path::Path;

/// The script parallel runs as its ssh (`--ssh`): `SCRIPT [OPTIONS] HOST COMMAND…`. For a
/// job (`$PARALLEL_SEQ` set: the chunk's argument line, from 1) it runs `SSH… "$@"` with
/// the chunk's stream `SPOOL/K.in` on stdin, its stdout to `K.part` and stderr to
/// `K.err`, the script's pid in `K.pid` (farm stops a host silent for `--host-timeout`, saying so
/// in `K.timeout`); on success it renames `K.part` to `K.out` (with the host in `K.host`)
/// and waits for farm to take it: `K.ok` then says the frames were whole and written, and
/// the job succeeds; `K.bad` says why not, and the try fails. A failed try is kept
/// (`K.tries`: host and status a line; `K.err.N`: its stderr). Every try, failed or not,
/// is one line of the job log, in parallel's format, its number `K` plus the offset
/// `SPOOL/seq0` (the job log's last number when the run began), its command `K.cmd`; and
/// one line `HOST<TAB>STATUS<TAB>K` of `SPOOL/ended`, which farm reads to name a failing
/// host at once. A chunk parallel starts on a host farm has dropped (a line of
/// `SPOOL/dropped`) goes to one of `SPOOL/left` instead. An idle job (`K.idle`) ends at once with status 0. Each job appends a
/// byte to `starts` as it starts and to `ends` as it ends. Anything else parallel runs
/// through its ssh goes straight to `SSH…`.
pub fn shim_script(spool: &Path, ssh: &[String], joblog: &Path) -> String {
    let ssh: Vec<String> = ssh.iter().map(|w| quote(w)).collect();
    let ssh = ssh.join(" ");
    let spool = quote(&spool.display().to_string());
    let joblog = quote(&joblog.display().to_string());
    format!(
        r#"#!/bin/sh
# farm's ssh for GNU parallel: chunk $PARALLEL_SEQ of the spool to the host and back.
spool={spool}
# parallel's worker runs the command with the far side's $SHELL, which sshd sets from the
# user's login; a stand-in for ssh that runs it here (a test's, a container's) inherits
# ours, and without one the worker runs nothing and exits 0. sh, as sshd would say.
export SHELL="${{SHELL:-/bin/sh}}"
k=${{PARALLEL_SEQ-}}
case $k in '' | *[!0-9]*) exec {ssh} "$@" ;; esac
# Every job of farm's is counted as it starts and as it ends: farm tells from the two
# when nothing runs.
if [ -e "$spool/$k.idle" ]; then
    rm -f "$spool/$k.idle"
    printf s >>"$spool/starts"
    printf e >>"$spool/ends"
    exit 0
fi
[ -e "$spool/$k.in" ] || exec {ssh} "$@"
printf s >>"$spool/starts"
trap '{{ printf e >>"$spool/ends"; }} 2>/dev/null' EXIT
host=${{PARALLEL_SSHLOGIN:-?}}
# A host farm has dropped gets no chunk: parallel reads its file of hosts again at most
# once a second, and a chunk it starts there meanwhile goes to a host left instead.
if [ -s "$spool/dropped" ] && [ "$1" = "$host" ] && grep -qxF -- "$host" "$spool/dropped"; then
    left=$(wc -l <"$spool/left")
    host=$(sed -n "$((k % left + 1))p" "$spool/left")
    shift
    set -- "$host" "$@"
fi
start=$(date +%s.%N)
sent=$(wc -c <"$spool/$k.in")
# In the foreground (an asynchronous list would ignore SIGINT): farm stops a silent host
# by signalling this script's children, by its pid.
printf '%s\n' "$$" >"$spool/$k.pid"
{ssh} "$@" <"$spool/$k.in" >"$spool/$k.part" 2>"$spool/$k.err"
st=$?
rm -f "$spool/$k.pid"
received=$(wc -c <"$spool/$k.part" 2>/dev/null || echo 0)
if [ -e "$spool/$k.timeout" ]; then
    # farm stopped a host that sent nothing for --host-timeout: its words.
    cat "$spool/$k.timeout" >>"$spool/$k.err"
    rm -f "$spool/$k.timeout"
    st=3
elif [ "$st" -eq 0 ]; then
    printf '%s\n' "$host" >"$spool/$k.host"
    mv -f "$spool/$k.part" "$spool/$k.out"
    while [ -e "$spool/$k.out" ]; do sleep 0.01; done
    if [ -e "$spool/$k.ok" ]; then
        rm -f "$spool/$k.ok"
    else
        # farm's reason: the try's last line.
        cat "$spool/$k.bad" >>"$spool/$k.err" 2>/dev/null
        rm -f "$spool/$k.bad"
        st=3
    fi
fi
[ -d "$spool" ] || exit "$st"
if [ "$st" -ne 0 ]; then
    rm -f "$spool/$k.part"
    n=1
    [ ! -e "$spool/$k.tries" ] || n=$(($(wc -l <"$spool/$k.tries") + 1))
    mv -f "$spool/$k.err" "$spool/$k.err.$n"
    printf '%s\t%s\n' "$host" "$st" >>"$spool/$k.tries"
fi
end=$(date +%s.%N)
seq=$((k + $(cat "$spool/seq0")))
printf '%s\t%s\t%.3f\t%10.3f\t%s\t%s\t%s\t0\t%s\n' \
    "$seq" "$host" "$start" "$(awk -v a="$start" -v b="$end" 'BEGIN {{ print b - a }}')" \
    "$sent" "$received" "$st" "$(cat "$spool/$k.cmd")" >>{joblog}
printf '%s\t%s\t%s\n' "$host" "$st" "$k" >>"$spool/ended"
exit "$st"
"#
    )
}
