//! Hosts that a test makes for itself: OpenSSH servers on loopback addresses, for the
//! tests of `render.sh --hosts`.
//!
//! Each host is an `sshd` of its own on 127.0.0.2, 127.0.0.3, … (Linux routes all of
//! 127/8 to the loopback interface, so no set-up is needed), on a free port, with its own
//! host key, authorized key, log and temporary folder, all in one temporary directory. A
//! small script there, [`Hosts::ssh`], is the `POLYPIPE_SSH` that reaches them by the
//! names `node1`, `node2`, …: `exec ssh -F CONFIG "$@"`, the config mapping each name to
//! its address and port, with the test's key, no host-key questions and no prompts.
//!
//! The servers log at VERBOSE, so a test can see which hosts were used
//! ([`Hosts::sessions`]). Dropping a [`Hosts`] kills every server and its sessions.
//!
//! Where sshd is not installed, [`Hosts::start`] prints why the test is skipped and
//! returns `None`: the test returns early, it does not fail; except under `CI=true`
//! (`.ci/run`, and most CI services), where it fails the test, so that a CI that lost
//! its sshd does not pass the hosts tests without running them. (`.ci/run` installs
//! openssh-server and openssh-client first where it can.)

use std::collections::HashMap;
use std::fs;
use std::io::Write;
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Where Debian and most distributions install the server. sshd must be started by an
/// absolute path (it re-executes itself for every connection).
pub const SSHD: &str = "/usr/sbin/sshd";

/// What one made host does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Host {
    /// An sshd that runs whatever it is asked to.
    Serving,
    /// An sshd whose authorized key carries `command="…"`: every login runs that command
    /// instead of the one asked for (a host that refuses the command).
    ForcedCommand(String),
    /// An sshd that knows no key of ours (a host that refuses the login).
    DeniesKey,
    /// A name that maps to a free port on its address where nothing listens (a host that
    /// cannot be reached: connection refused).
    Unreachable,
}

struct Node {
    name: String,
    address: String,
    port: u16,
    sshd: Option<Child>,
    log: PathBuf,
    tmp: PathBuf,
}

/// A set of loopback hosts; see the module's documentation.
pub struct Hosts {
    dir: tempfile::TempDir,
    nodes: Vec<Node>,
    ssh: PathBuf,
}

/// Why hosts cannot be made here with the server `sshd`, or `None` when they can.
pub fn unavailable(sshd: &Path) -> Option<String> {
    if !sshd.is_file() {
        return Some(format!(
            "{} is not installed (apt-get install openssh-server openssh-client)",
            sshd.display()
        ));
    }
    for tool in ["ssh", "ssh-keygen"] {
        // Either answers -V or refuses it; only a missing program fails to start.
        let runs = Command::new(tool)
            .arg("-V")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok();
        if !runs {
            return Some(format!(
                "{tool} is not installed (apt-get install openssh-client)"
            ));
        }
    }
    // sshd running as root wants its privilege separation folder.
    let privsep = Path::new("/run/sshd");
    if is_root() && !privsep.is_dir() && fs::create_dir_all(privsep).is_err() {
        return Some("cannot create /run/sshd, which sshd needs".into());
    }
    None
}

/// Whether the hosts tests must run rather than be skipped: under `CI=true`.
pub fn must_run() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.trim_ascii() == b"0")
}

fn user_name() -> String {
    let out = Command::new("id").arg("-un").output().expect("run id -un");
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Tests that make hosts take this first: the servers, the processes a test looks for
/// when it checks that nothing was left behind, and the time-sensitive fault tests do
/// not share the machine with another such test.
pub fn serial() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A free TCP port on `address` (bound and released; nothing else on this machine is
/// expected to grab it in the next moment).
fn free_port(address: &str) -> u16 {
    TcpListener::bind((address, 0))
        .and_then(|l| l.local_addr())
        .unwrap_or_else(|e| panic!("no free port on {address}: {e}"))
        .port()
}

fn keygen(path: &Path) {
    let status = Command::new("ssh-keygen")
        .args(["-q", "-t", "ed25519", "-N", "", "-C", "polypipe-test", "-f"])
        .arg(path)
        .stdin(Stdio::null())
        .status()
        .expect("run ssh-keygen");
    assert!(status.success(), "ssh-keygen -f {} failed", path.display());
}

impl Hosts {
    /// Starts one host of each kind given, named node1, node2, … in that order, on
    /// 127.0.0.2, 127.0.0.3, … . Returns `None`, having printed why, where sshd is not
    /// installed (under `CI=true`, panics instead); panics if an installed sshd does not
    /// start.
    pub fn start(kinds: &[Host]) -> Option<Hosts> {
        Self::start_checked(Path::new(SSHD), must_run(), kinds)
    }

    /// [`Hosts::start`] with the server at `sshd`, failing rather than skipping where
    /// it cannot run when `must` is true.
    pub fn start_checked(sshd: &Path, must: bool, kinds: &[Host]) -> Option<Hosts> {
        if must {
            if let Some(why) = unavailable(sshd) {
                panic!("no loopback ssh hosts under CI=true, where they must run: {why}");
            }
        }
        Self::start_using(sshd, kinds)
    }

    /// [`Hosts::start`] with the server at `sshd` (an absolute path).
    pub fn start_using(sshd: &Path, kinds: &[Host]) -> Option<Hosts> {
        if let Some(why) = unavailable(sshd) {
            crate::note_skip(&format!("no loopback ssh hosts: {why}"));
            return None;
        }
        let dir = tempfile::Builder::new()
            .prefix("polypipe-hosts.")
            .tempdir()
            .expect("a temporary directory");
        let d = dir.path().to_path_buf();
        let client_key = d.join("id_ed25519");
        keygen(&client_key);
        let public = fs::read_to_string(d.join("id_ed25519.pub")).expect("the public key");
        let user = user_name();

        let mut nodes = Vec::new();
        let mut config = String::new();
        for (i, kind) in kinds.iter().enumerate() {
            let n = i + 1;
            let name = format!("node{n}");
            let address = format!("127.0.0.{}", n + 1);
            let port = free_port(&address);
            let log = d.join(format!("sshd-{name}.log"));
            let tmp = d.join(format!("tmp-{name}"));
            fs::create_dir(&tmp).expect("a host's temporary folder");
            config += &format!("Host {name}\n  HostName {address}\n  Port {port}\n");
            let mut node = Node {
                name,
                address,
                port,
                sshd: None,
                log,
                tmp,
            };
            if *kind != Host::Unreachable {
                let authorized = match kind {
                    Host::ForcedCommand(cmd) => {
                        format!("command=\"{}\" {public}", cmd.replace('"', "\\\""))
                    }
                    Host::DeniesKey => String::new(),
                    _ => public.clone(),
                };
                node.sshd = Some(start_sshd(sshd, &d, &node, &authorized));
            }
            nodes.push(node);
        }
        config += &format!(
            "Host *\n  User {user}\n  IdentityFile {key}\n  IdentitiesOnly yes\n  \
             StrictHostKeyChecking no\n  UserKnownHostsFile {known}\n  BatchMode yes\n  \
             ConnectTimeout 5\n  ServerAliveInterval 1\n  ServerAliveCountMax 3\n  \
             LogLevel ERROR\n",
            key = client_key.display(),
            known = d.join("known_hosts").display(),
        );
        let config_path = d.join("ssh_config");
        fs::write(&config_path, config).expect("write ssh_config");
        let ssh = d.join("ssh");
        write_script(
            &ssh,
            &format!(
                "#!/bin/sh\nexec ssh -F '{}' \"$@\"\n",
                config_path.display()
            ),
        );
        let hosts = Hosts { dir, nodes, ssh };
        for node in &hosts.nodes {
            if node.sshd.is_some() {
                wait_until_listening(node);
            }
        }
        Some(hosts)
    }

    /// The `POLYPIPE_SSH` script that reaches the hosts by name.
    pub fn ssh(&self) -> &Path {
        &self.ssh
    }

    /// The temporary directory that holds everything of these hosts.
    pub fn dir(&self) -> &Path {
        self.dir.path()
    }

    /// Host `i`'s name (from 0: `node1` is host 0).
    pub fn name(&self, i: usize) -> &str {
        &self.nodes[i].name
    }

    /// Every host's name, comma-separated, for `--hosts`.
    pub fn names(&self) -> String {
        self.nodes
            .iter()
            .map(|n| n.name.as_str())
            .collect::<Vec<_>>()
            .join(",")
    }

    /// Host `i`'s address and port, as ssh's messages give them.
    pub fn address(&self, i: usize) -> (&str, u16) {
        (&self.nodes[i].address, self.nodes[i].port)
    }

    /// What host `i`'s sshd has logged so far.
    pub fn log(&self, i: usize) -> String {
        fs::read_to_string(&self.nodes[i].log).unwrap_or_default()
    }

    /// The sessions host `i` has started: a command (the one asked for, or the key's forced
    /// one) run for a logged-in user.
    pub fn sessions(&self, i: usize) -> usize {
        self.log(i)
            .lines()
            .filter(|l| l.contains("Starting session: "))
            .count()
    }

    /// The `TMPDIR` that host `i` gives its sessions (sshd's SetEnv), to check that a
    /// remote run left nothing there.
    pub fn remote_tmp(&self, i: usize) -> &Path {
        &self.nodes[i].tmp
    }

    /// Host `i` goes away: its sshd and every process of its sessions are killed
    /// (SIGKILL), as when a machine loses power. Connections to it are reset.
    pub fn drop_host(&mut self, i: usize) {
        if let Some(mut sshd) = self.nodes[i].sshd.take() {
            kill_tree(sshd.id());
            let _ = sshd.wait();
        }
    }

    /// The processes of host `i`'s sessions still running (the descendants of its sshd).
    pub fn session_processes(&self, i: usize) -> Vec<String> {
        match &self.nodes[i].sshd {
            Some(sshd) => descendants(sshd.id()).into_iter().map(describe).collect(),
            None => Vec::new(),
        }
    }
}

impl Drop for Hosts {
    fn drop(&mut self) {
        for i in 0..self.nodes.len() {
            self.drop_host(i);
        }
    }
}

fn write_script(path: &Path, text: &str) {
    use std::os::unix::fs::PermissionsExt;
    let mut f = fs::File::create(path).expect("create a script");
    f.write_all(text.as_bytes()).expect("write a script");
    fs::set_permissions(path, fs::Permissions::from_mode(0o755)).expect("chmod a script");
}

/// Starts one host's sshd in the foreground (`-D`), logging to its file. The log goes by
/// `-e` to stderr, redirected: with `-E FILE`, OpenSSH 9.2 logs only the listener, not the
/// sessions (the re-executed child does not get the file).
///
/// Sessions get `SHLVL=1`: bash, run by sshd at shell level 1, reads the user's ~/.bashrc,
/// and root's on these machines starts pyenv, whose `rehash` waits up to a minute on a lock
/// that a session killed mid-test (a host dropped on purpose) leaves behind; every later
/// test then waited that minute. At level 2 bash reads no startup file.
fn start_sshd(sshd: &Path, dir: &Path, node: &Node, authorized: &str) -> Child {
    let host_key = dir.join(format!("host-key-{}", node.name));
    keygen(&host_key);
    let keys = dir.join(format!("authorized_keys-{}", node.name));
    fs::write(&keys, authorized).expect("write authorized_keys");
    let config = dir.join(format!("sshd_config-{}", node.name));
    let text = format!(
        "ListenAddress {address}:{port}\n\
         HostKey {host_key}\n\
         PidFile {pid}\n\
         AuthorizedKeysFile {keys}\n\
         StrictModes no\n\
         UsePAM no\n\
         PermitRootLogin prohibit-password\n\
         PasswordAuthentication no\n\
         KbdInteractiveAuthentication no\n\
         LogLevel VERBOSE\n\
         SetEnv TMPDIR={tmp} SHLVL=1\n",
        address = node.address,
        port = node.port,
        host_key = host_key.display(),
        pid = dir.join(format!("sshd-{}.pid", node.name)).display(),
        keys = keys.display(),
        tmp = node.tmp.display(),
    );
    fs::write(&config, text).expect("write sshd_config");
    let log = fs::File::create(&node.log).expect("create the sshd log");
    Command::new(sshd)
        .arg("-D")
        .arg("-e")
        .arg("-f")
        .arg(&config)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", sshd.display()))
}

fn wait_until_listening(node: &Node) {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let log = fs::read_to_string(&node.log).unwrap_or_default();
        if log.contains("Server listening on") {
            return;
        }
        assert!(
            Instant::now() < deadline,
            "sshd for {} did not start listening on {}:{}; its log:\n{log}",
            node.name,
            node.address,
            node.port
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

// --- Processes, from /proc. -------------------------------------------------------------

/// Every process's parent: pid → ppid.
fn parents() -> HashMap<u32, u32> {
    let mut map = HashMap::new();
    let Ok(entries) = fs::read_dir("/proc") else {
        return map;
    };
    for entry in entries.flatten() {
        let Some(pid) = entry
            .file_name()
            .to_str()
            .and_then(|s| s.parse::<u32>().ok())
        else {
            continue;
        };
        let Ok(stat) = fs::read_to_string(entry.path().join("stat")) else {
            continue;
        };
        // "pid (comm) state ppid …": comm may hold spaces and parentheses.
        if let Some(ppid) = stat
            .rsplit_once(") ")
            .and_then(|(_, rest)| rest.split_whitespace().nth(1))
            .and_then(|s| s.parse().ok())
        {
            map.insert(pid, ppid);
        }
    }
    map
}

/// The processes below `root` (not `root` itself), parents before children.
pub fn descendants(root: u32) -> Vec<u32> {
    let parents = parents();
    let mut found = vec![root];
    let mut i = 0;
    while i < found.len() {
        let p = found[i];
        let mut children: Vec<u32> = parents
            .iter()
            .filter(|&(_, &pp)| pp == p)
            .map(|(&c, _)| c)
            .collect();
        children.sort_unstable();
        found.extend(children);
        i += 1;
    }
    found.remove(0);
    found
}

/// Kills `root` and everything below it, at once (SIGKILL), so that nothing can react.
fn kill_tree(root: u32) {
    let mut all = vec![root];
    all.extend(descendants(root));
    let _ = Command::new("kill")
        .arg("-KILL")
        .args(all.iter().map(u32::to_string))
        .stderr(Stdio::null())
        .status();
}

/// `PID: command line` of a process, for messages.
pub fn describe(pid: u32) -> String {
    let cmdline = fs::read(format!("/proc/{pid}/cmdline")).unwrap_or_default();
    let words: Vec<String> = cmdline
        .split(|&b| b == 0)
        .filter(|w| !w.is_empty())
        .map(|w| String::from_utf8_lossy(w).into_owned())
        .collect();
    format!("{pid}: {}", words.join(" "))
}

/// The processes now running but this one, zombies left out (they are gone but for
/// their status), that `keep` keeps, described for messages and sorted.
fn living_processes(keep: impl Fn(u32) -> bool) -> Vec<String> {
    let me = std::process::id();
    let mut found: Vec<String> = parents()
        .keys()
        .copied()
        .filter(|&pid| pid != me)
        .filter(|pid| {
            let state = fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
            !state
                .rsplit_once(") ")
                .is_some_and(|(_, rest)| rest.starts_with('Z'))
        })
        .filter(|&pid| keep(pid))
        .map(describe)
        .collect();
    found.sort();
    found
}

/// The processes now running that were started with `var=value` in their environment:
/// a run's own processes, told from those of another test that runs the same programs
/// at the same time, when the run was given a `var` of its own (a TMPDIR in the test's
/// folder).
pub fn processes_with_env(var: &str, value: &Path) -> Vec<String> {
    let mut wanted = format!("{var}=").into_bytes();
    wanted.extend_from_slice(value.as_os_str().as_encoded_bytes());
    living_processes(|pid| {
        let environ = fs::read(format!("/proc/{pid}/environ")).unwrap_or_default();
        environ.split(|&b| b == 0).any(|v| v == wanted.as_slice())
    })
}

/// The processes now running whose program is one of `programs`, or whose command line
/// contains one of `markers` (a test's own folders, a script's path): what a run left
/// behind, once it has ended.
pub fn processes_matching(programs: &[PathBuf], markers: &[String]) -> Vec<String> {
    living_processes(|pid| {
        let exe = fs::read_link(format!("/proc/{pid}/exe")).ok();
        let line = describe(pid);
        exe.as_ref().is_some_and(|e| programs.contains(e))
            || markers.iter().any(|m| line.contains(m.as_str()))
    })
}
