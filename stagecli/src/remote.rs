//! How a command on another host ended, told in one line: the ssh sessions of `farm`
//! (`render.sh --by frames`) and of `plan launch`'s host stages (`render.sh --hosts`,
//! `--by leaves`) end the run with the same words for the same failures
//! (docs/DESIGN.md, "Stages on other hosts").

/// A host's session that did not end well: the message after `host H: ` and the status
/// the run ends with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    pub message: String,
    pub status: u8,
}

/// The last non-blank line a session wrote on stderr, without render.sh's own prefix.
pub fn last_line(stderr: &str) -> &str {
    let line = stderr
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    line.strip_prefix("render.sh: ").unwrap_or(line)
}

/// What a session that ended with `status` (the ssh's: the far command's, 255 for ssh's
/// own failure, `None` when killed by a signal `signal`) and `stderr` means; `what` names
/// the command that ran there (`the command`, `render.sh`). `None` for a success.
///
/// - 255 is ssh's own: the host could not be reached, refused us, or dropped (3);
/// - 126 and 127 are the far shell's: the command could not be run there (3);
/// - another status with a message is the far command's own failure, passed on (1 to 3;
///   a higher status as 1);
/// - a status with no message at all is a host that ran something else (a forced
///   command): 3.
pub fn classify(
    status: Option<i32>,
    signal: Option<i32>,
    stderr: &str,
    what: &str,
) -> Option<Failure> {
    let said = last_line(stderr);
    let (message, status) = match (status, signal) {
        (Some(0), _) => return None,
        (Some(255), _) => {
            let said = if said.is_empty() {
                "failed (status 255)"
            } else {
                said
            };
            let message = if said.starts_with("ssh:") {
                said.to_string()
            } else {
                format!("ssh: {said}")
            };
            (message, 3)
        }
        (Some(st @ (126 | 127)), _) => {
            let why = if said.is_empty() {
                format!("status {st}")
            } else {
                said.to_string()
            };
            (format!("cannot run {what} there: {why}"), 3)
        }
        (Some(st), _) if !said.is_empty() => (said.to_string(), if st <= 3 { st as u8 } else { 1 }),
        (Some(st), _) => (
            format!(
                "the command exited with status {st} and no message (does the host allow \
                 only another command?)"
            ),
            3,
        ),
        (None, sig) => {
            let name = sig.map_or_else(|| "a signal".to_string(), signal_name);
            let tail = if said.is_empty() {
                String::new()
            } else {
                format!(": {said}")
            };
            (format!("ssh was killed by {name}{tail}"), 3)
        }
    };
    Some(Failure { message, status })
}

/// A signal's name as `kill -l` gives it, with `SIG`: `SIGKILL`; `signal 40` for one
/// without a name here.
pub fn signal_name(sig: i32) -> String {
    let name = match sig {
        libc::SIGHUP => "SIGHUP",
        libc::SIGINT => "SIGINT",
        libc::SIGQUIT => "SIGQUIT",
        libc::SIGILL => "SIGILL",
        libc::SIGTRAP => "SIGTRAP",
        libc::SIGABRT => "SIGABRT",
        libc::SIGBUS => "SIGBUS",
        libc::SIGFPE => "SIGFPE",
        libc::SIGKILL => "SIGKILL",
        libc::SIGUSR1 => "SIGUSR1",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGUSR2 => "SIGUSR2",
        libc::SIGPIPE => "SIGPIPE",
        libc::SIGALRM => "SIGALRM",
        libc::SIGTERM => "SIGTERM",
        libc::SIGXCPU => "SIGXCPU",
        libc::SIGXFSZ => "SIGXFSZ",
        _ => return format!("signal {sig}"),
    };
    name.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_far_commands_name_is_the_callers() {
        let missing = classify(Some(127), None, "", "render.sh").unwrap();
        assert_eq!(
            (missing.message.as_str(), missing.status),
            ("cannot run render.sh there: status 127", 3)
        );
        let far = classify(Some(7), None, "render.sh: zbuf: full disk\n\n", "x").unwrap();
        assert_eq!((far.message.as_str(), far.status), ("zbuf: full disk", 1));
        assert_eq!(signal_name(libc::SIGSEGV), "SIGSEGV");
        assert_eq!(signal_name(40), "signal 40");
    }
}
