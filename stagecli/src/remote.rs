//! How a command on another host ended, told in one line: the ssh sessions of `farm`
//! (`render --by frames`) and of render's host stages (`render --hosts`, `--by
//! leaves`) end the run with the same words for the same failures
//! (docs/DESIGN.md, "Stages on other hosts"). Also the one place where the command
//! that reaches a host (`POLYPIPE_SSH`) is read and a far command line is quoted.

/// A host's session that did not end well: the message after `host H: ` and the status
/// the run ends with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    pub message: String,
    pub status: u8,
}

/// The last non-blank line a session wrote on stderr, without render's own prefix.
pub fn last_line(stderr: &str) -> &str {
    let line = stderr
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    without_render_prefix(line)
}

/// A line a host's render wrote, without its prefix: `render: ` (or an older host's
/// `render.sh: `).
pub fn without_render_prefix(line: &str) -> &str {
    line.strip_prefix("render: ")
        .or_else(|| line.strip_prefix("render.sh: "))
        .unwrap_or(line)
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

/// The environment variable that names the command reaching a host (`ssh` by default).
pub const SSH_VARIABLE: &str = "POLYPIPE_SSH";

/// `WORD` for a POSIX shell, in single quotes.
pub fn quote(word: &str) -> String {
    format!("'{}'", word.replace('\'', r"'\''"))
}

/// The command a host's session runs: `exec WORD…`, each word quoted.
pub fn remote_command(words: &[String]) -> String {
    let mut line = String::from("exec");
    for w in words {
        line.push(' ');
        line.push_str(&quote(w));
    }
    line
}

/// The command that reaches a host, from the value of `POLYPIPE_SSH`: that value split
/// at whitespace, or, when it is unset, ssh with the options that make a host that is
/// gone known within seconds. A value that is set but blank names no command (run as it
/// is, the host's name would be taken for the command): an error that names the variable.
pub fn ssh_command(polypipe_ssh: Option<&str>) -> std::result::Result<Vec<String>, String> {
    match polypipe_ssh {
        Some(s) if s.trim().is_empty() => Err(format!(
            "{SSH_VARIABLE} is set but blank: set it to the command that reaches a host \
             (say 'ssh -p 2222'), or unset it for ssh"
        )),
        Some(s) => Ok(s.split_whitespace().map(str::to_string).collect()),
        None => Ok([
            "ssh",
            "-o",
            "BatchMode=yes",
            "-o",
            "ConnectTimeout=5",
            "-o",
            "ServerAliveInterval=2",
            "-o",
            "ServerAliveCountMax=3",
        ]
        .map(str::to_string)
        .to_vec()),
    }
}

/// [`ssh_command`] of this process's `POLYPIPE_SSH`; its error is a usage error (status 2).
pub fn ssh_command_from_env() -> crate::Result<Vec<String>> {
    let value = std::env::var_os(SSH_VARIABLE).map(|v| v.to_string_lossy().into_owned());
    ssh_command(value.as_deref()).map_err(crate::Error::usage)
}

/// Checks `--hosts H1,H2,…`: host names separated by commas, none empty, none starting
/// with `-` (ssh would take it for an option), none with white space.
pub fn parse_hosts(list: &str) -> std::result::Result<Vec<String>, String> {
    let hosts: Vec<String> = list.split(',').map(str::to_string).collect();
    let bad = |h: &String| h.is_empty() || h.starts_with('-') || h.chars().any(char::is_whitespace);
    if list.is_empty() || hosts.iter().any(bad) {
        return Err(format!(
            "--hosts must be host names separated by commas, not '{list}'"
        ));
    }
    Ok(hosts)
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

    #[test]
    fn the_ssh_command_comes_from_polypipe_ssh_and_a_blank_one_is_refused() {
        assert_eq!(
            ssh_command(Some("ssh -p 2222")).unwrap(),
            ["ssh", "-p", "2222"]
        );
        let default = ssh_command(None).unwrap();
        assert_eq!(default[0], "ssh");
        assert!(default.contains(&"BatchMode=yes".to_string()));
        for blank in ["", " ", "\t \n"] {
            assert_eq!(
                ssh_command(Some(blank)).unwrap_err(),
                "POLYPIPE_SSH is set but blank: set it to the command that reaches a host \
                 (say 'ssh -p 2222'), or unset it for ssh"
            );
        }
    }

    #[test]
    fn hosts_and_the_far_command_are_checked_and_quoted() {
        assert_eq!(parse_hosts("a,b,a").unwrap(), ["a", "b", "a"]);
        for bad in ["", "a,,b", "-oProxyCommand=x", "a b"] {
            assert_eq!(
                parse_hosts(bad).unwrap_err(),
                format!("--hosts must be host names separated by commas, not '{bad}'")
            );
        }
        assert_eq!(
            remote_command(&["render".into(), "--eye".into(), "it's".into()]),
            r"exec 'render' '--eye' 'it'\''s'"
        );
    }
}
