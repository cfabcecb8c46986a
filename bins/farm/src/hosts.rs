//! The hosts: parallel's sshlogins and their job slots.

use std::path::PathBuf;

/// Where the chunks go: parallel's sshlogins.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Logins {
    /// `--hosts H1,H2,…`: each host with its job slots, a host named twice having two
    /// (`2/H`), in the order first named.
    List(Vec<(usize, String)>),
    /// `--sshloginfile FILE`, parallel's own format (`N/host` a line), read by parallel.
    File(PathBuf),
}

/// `--hosts H1,H2,…` as sshlogins: `a,b,a` is `2/a` and `1/b`.
pub fn logins_from_hosts(list: &str) -> std::result::Result<Vec<(usize, String)>, String> {
    let mut logins: Vec<(usize, String)> = Vec::new();
    for host in stagecli::remote::parse_hosts(list)? {
        match logins.iter_mut().find(|(_, h)| *h == host) {
            Some((n, _)) => *n += 1,
            None => logins.push((1, host)),
        }
    }
    Ok(logins)
}

/// The job slots an sshlogin file gives, as farm counts them to bound its spool: `N/host`
/// N, a bare host 1, blank lines and `#` comments none. A file with none is refused
/// before parallel starts. (parallel gives a bare host as many slots as it has CPU
/// threads, asking it with `parallel --number-of-threads`, or one where it cannot ask;
/// farm's spool holds two chunks for it, so that `N/host` is how to keep more there.)
pub fn slots_in_sshloginfile(text: &str) -> usize {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| {
            l.split_once('/')
                .and_then(|(n, _)| n.trim().parse::<usize>().ok())
                .unwrap_or(1)
        })
        .sum()
}

/// The lines of the sshlogin file farm hands parallel (`--sshloginfile`, which parallel
/// reads again when it changes, so a host dropped from it gets no more chunks): `N/host`
/// for each host of `--hosts`, or the lines of the user's file that name a host.
pub fn login_lines(logins: &Logins, text: Option<&str>) -> Vec<String> {
    match (logins, text) {
        (Logins::List(l), _) => l.iter().map(|(n, h)| format!("{n}/{h}")).collect(),
        (Logins::File(_), Some(text)) => text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .map(str::to_string)
            .collect(),
        (Logins::File(_), None) => Vec::new(),
    }
}

/// The host of an sshlogin line, as parallel names it to a job (`$PARALLEL_SSHLOGIN`):
/// the line without its `N/`.
pub fn host_of_line(line: &str) -> &str {
    match line.split_once('/') {
        Some((n, host)) if n.trim().parse::<usize>().is_ok() => host.trim(),
        _ => line.trim(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hosts_named_twice_have_two_job_slots() {
        assert_eq!(
            logins_from_hosts("a,b,a").unwrap(),
            [(2, "a".to_string()), (1, "b".to_string())]
        );
        assert!(logins_from_hosts("a,,b").is_err());
        assert_eq!(host_of_line("2/node1"), "node1");
        assert_eq!(host_of_line("node2"), "node2");
        assert_eq!(
            login_lines(&Logins::File("f".into()), Some("# x\n2/a\n\n b \n")),
            ["2/a", "b"]
        );
        assert_eq!(
            slots_in_sshloginfile("# farm\n4/alpha\nbeta\n\n2/ssh -p 2222 gamma\n"),
            7
        );
    }
}
