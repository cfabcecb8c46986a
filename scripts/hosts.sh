# shellcheck shell=bash
# shellcheck disable=SC2034 # ssh_cmd, message, exit_status: for the script that sources this
# hosts.sh: how render.sh reaches other hosts over ssh for --by leaves (docs/DESIGN.md,
# "Stages on other hosts"; --by frames is the farm binary's, which does the same in
# Rust). Sourced, not run.

# The command that reaches a host, in the array `ssh_cmd`. Plain ssh gets the options
# that make a dead host known within seconds; a POLYPIPE_SSH of the user's is taken as
# it is.
if [[ -n ${POLYPIPE_SSH-} ]]; then
    read -r -a ssh_cmd <<<"$POLYPIPE_SSH"
else
    ssh_cmd=(ssh -o BatchMode=yes -o ConnectTimeout=5 -o ServerAliveInterval=2
        -o ServerAliveCountMax=3)
fi

# quote WORD: WORD for a POSIX shell on the far side, in single quotes.
quote() { printf "'%s'" "${1//\'/\'\\\'\'}"; }

# check_hosts LIST: the hosts of --hosts H1,H2,…, into the array `hosts`.
check_hosts() {
    IFS=, read -r -a hosts <<<"$1"
    local h
    ((${#hosts[@]} > 0)) || die_usage "--hosts must name at least one host"
    for h in "${hosts[@]}"; do
        [[ -n $h && $h != -* && $h != *[[:space:]]* ]] ||
            die_usage "--hosts must be host names separated by commas, not '$1'"
    done
}

# last_line FILE: its last non-blank line, with render.sh's own prefix taken off.
last_line() {
    local line
    line=$(grep -v '^[[:space:]]*$' "$1" 2>/dev/null | tail -n 1)
    line=${line#render.sh: }
    printf '%s' "$line"
}

# what_failed ERRFILE STATUS WHAT: sets `message` and `exit_status` for a host whose ssh
# ended with STATUS, having written ERRFILE on stderr; WHAT is what ran there.
what_failed() {
    local st=$2 said
    said=$(last_line "$1")
    if ((st == 255)); then
        # ssh's own failure: the host could not be reached, refused us, or dropped.
        message=${said:-"failed (status 255)"}
        [[ $message == ssh:* ]] || message="ssh: $message"
        exit_status=3
    elif ((st == 126 || st == 127)); then
        message="cannot run $3 there: ${said:-status $st}"
        exit_status=3
    elif ((st > 128)); then
        message="ssh was killed by SIG$(kill -l $((st - 128)) 2>/dev/null || echo $((st - 128)))${said:+: $said}"
        exit_status=3
    elif [[ -n $said ]]; then
        message=$said
        exit_status=$((st <= 3 ? st : 1))
    else
        message="the command exited with status $st and no message (does the host allow only another command?)"
        exit_status=3
    fi
}
