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

/// The job slots an sshlogin file gives: `N/host` N, a bare host 1 (farm runs parallel
/// with `-j1`), blank lines and `#` comments none. A file with none is refused before
/// parallel starts; parallel reads the file itself.
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
        assert_eq!(
            slots_in_sshloginfile("# farm\n4/alpha\nbeta\n\n2/ssh -p 2222 gamma\n"),
            7
        );
    }
}
