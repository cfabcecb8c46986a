# shellcheck shell=bash
# shellcheck disable=SC2034 # ssh_cmd: for the script that sources this
# hosts.sh: how render.sh reaches other hosts over ssh for --by leaves (docs/DESIGN.md,
# "Stages on other hosts"; --by frames is the farm binary's, which does the same in
# Rust). Sourced, not run.

# The command that reaches a host, in the array `ssh_cmd`. Plain ssh gets the options
# that make a dead host known within seconds; a POLYPIPE_SSH of the user's is taken as
# it is. One that is set but blank names no command, and is refused as stagecli::remote does.
if [[ -v POLYPIPE_SSH ]]; then
    [[ $POLYPIPE_SSH == *[![:space:]]* ]] ||
        die_usage "POLYPIPE_SSH is set but blank: set it to the command that reaches a host (say 'ssh -p 2222'), or unset it for ssh"
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
