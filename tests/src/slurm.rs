//! A one-node Slurm that a test makes for itself, for the tests of `render.sh --by frames
//! --slurm-array`: munged, slurmctld and slurmd as this machine (its own host name and
//! cores), each in the foreground under the test, everything they keep (the munge key,
//! its socket, slurm.conf, the state, the spool, the logs) in one temporary directory.
//! No cgroups (`ProctrackType=proctrack/linuxproc`, `TaskPlugin=task/none`), no
//! accounting; Slurm's client commands find the cluster through `SLURM_CONF`
//! ([`Cluster::command`]). Dropping a [`Cluster`] stops every daemon it started, the test
//! failed or not.
//!
//! Where Slurm or munge is not installed, or the test does not run as root (the
//! daemons' user), [`Cluster::start`] skips the test ([`crate::skip`]: under `CI=true` it
//! fails instead; `.ci/run` installs slurm-wlm and munge) and returns `None`.

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const DAEMONS: [&str; 3] = [
    "/usr/sbin/munged",
    "/usr/sbin/slurmctld",
    "/usr/sbin/slurmd",
];

/// A running one-node cluster; see the module's documentation.
pub struct Cluster {
    dir: tempfile::TempDir,
    daemons: Vec<(String, Child)>,
}

/// Why a cluster cannot be made here, or `None` when it can.
fn unavailable() -> Option<String> {
    for d in DAEMONS {
        if !Path::new(d).is_file() {
            return Some(format!(
                "{d} is not installed (apt-get install slurm-wlm munge)"
            ));
        }
    }
    for tool in ["sbatch", "squeue", "sinfo"] {
        if Command::new(tool)
            .arg("--version")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_err()
        {
            return Some(format!(
                "{tool} is not installed (apt-get install slurm-wlm)"
            ));
        }
    }
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.trim_ascii() == b"0");
    if !root {
        return Some("the Slurm daemons run as root, and this is not root".to_string());
    }
    None
}

fn free_port() -> u16 {
    TcpListener::bind(("127.0.0.1", 0))
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port()
}

impl Cluster {
    /// Starts munged, slurmctld and slurmd and waits until the node is idle; `None`
    /// (skipped, said on stderr) where it cannot, except under `CI=true`.
    pub fn start() -> Option<Cluster> {
        if let Some(why) = unavailable() {
            crate::skip(&why);
            return None;
        }
        let dir = tempfile::Builder::new()
            .prefix("polypipe-slurm.")
            .tempdir()
            .expect("a temporary directory");
        let mut cluster = Cluster {
            dir,
            daemons: Vec::new(),
        };
        let d = cluster.dir.path().to_path_buf();
        for sub in ["state", "spool"] {
            std::fs::create_dir_all(d.join(sub)).unwrap();
        }
        // munge's key: any 1024 random bytes, readable by root alone.
        let mut key = vec![0u8; 1024];
        use std::io::Read;
        std::fs::File::open("/dev/urandom")
            .and_then(|mut f| f.read_exact(&mut key))
            .expect("random bytes for munge's key");
        std::fs::write(d.join("munge.key"), &key).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(d.join("munge.key"), std::fs::Permissions::from_mode(0o600))
            .unwrap();
        let socket = d.join("munge.sock");
        let munged = Command::new(DAEMONS[0])
            .arg("--foreground")
            .arg("--force")
            .arg(format!("--key-file={}", d.join("munge.key").display()))
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--pid-file={}", d.join("munged.pid").display()))
            .arg(format!("--log-file={}", d.join("munged.log").display()))
            .arg(format!("--seed-file={}", d.join("munged.seed").display()))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start munged");
        cluster.daemons.push(("munged".into(), munged));
        cluster.wait_for("munged's socket", || socket.exists());

        let host = Command::new("hostname")
            .arg("-s")
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .expect("run hostname");
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let p = |name: &str| d.join(name).display().to_string();
        let conf = format!(
            "ClusterName=polypipe\nSlurmctldHost={host}\nSlurmctldAddr=127.0.0.1\n\
             SlurmUser=root\nSlurmdUser=root\nSlurmctldPort={}\nSlurmdPort={}\n\
             AuthType=auth/munge\nAuthInfo=socket={}\nStateSaveLocation={}\n\
             SlurmdSpoolDir={}\nSlurmctldPidFile={}\nSlurmdPidFile={}\n\
             SlurmctldLogFile={}\nSlurmdLogFile={}\nProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\nJobAcctGatherType=jobacct_gather/none\n\
             SwitchType=switch/none\nMpiDefault=none\nReturnToService=2\n\
             SchedulerType=sched/builtin\nSchedulerParameters=batch_sched_delay=0,sched_interval=1\nSelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\nMinJobAge=600\n\
             NodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN\n\
             PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            free_port(),
            free_port(),
            socket.display(),
            p("state"),
            p("spool"),
            p("slurmctld.pid"),
            p("slurmd.pid"),
            p("slurmctld.log"),
            p("slurmd.log"),
        );
        std::fs::write(d.join("slurm.conf"), conf).unwrap();
        for (name, args) in [("slurmctld", &["-D", "-i"][..]), ("slurmd", &["-D"][..])] {
            let child = Command::new(format!("/usr/sbin/{name}"))
                .args(args)
                .arg("-f")
                .arg(d.join("slurm.conf"))
                .env("SLURM_CONF", d.join("slurm.conf"))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap_or_else(|e| panic!("start {name}: {e}"));
            cluster.daemons.push((name.into(), child));
        }
        cluster.wait_for("the node idle", || {
            cluster
                .command("sinfo")
                .args(["-h", "-o", "%t"])
                .output()
                .is_ok_and(|o| o.stdout.trim_ascii() == b"idle")
        });
        Some(cluster)
    }

    /// Waits up to 30 s for `ready`, else fails with the daemons' logs.
    fn wait_for(&self, what: &str, ready: impl Fn() -> bool) {
        let start = Instant::now();
        while !ready() {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "no {what} after 30 s:\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// The daemons' logs, for a failure's message.
    pub fn logs(&self) -> String {
        ["munged.log", "slurmctld.log", "slurmd.log"]
            .iter()
            .map(|f| {
                let text = std::fs::read_to_string(self.dir.path().join(f)).unwrap_or_default();
                let tail: Vec<&str> = text.lines().rev().take(15).collect();
                let tail: Vec<&str> = tail.into_iter().rev().collect();
                format!("--- {f}\n{}", tail.join("\n"))
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// slurm.conf, for `SLURM_CONF`.
    pub fn conf(&self) -> PathBuf {
        self.dir.path().join("slurm.conf")
    }

    /// A client command (`sbatch`, `squeue`, `bash -c …`) that reaches this cluster.
    pub fn command(&self, program: &str) -> Command {
        let mut cmd = Command::new(program);
        cmd.env("SLURM_CONF", self.conf());
        cmd
    }

    /// Waits until no job is queued or running, at most `limit`.
    pub fn wait_idle(&self, limit: Duration) {
        let start = Instant::now();
        loop {
            let out = self
                .command("squeue")
                .arg("-h")
                .output()
                .expect("run squeue");
            if out.status.success() && out.stdout.trim_ascii().is_empty() {
                return;
            }
            assert!(
                start.elapsed() < limit,
                "jobs still queued after {limit:?}:\n{}\n{}",
                String::from_utf8_lossy(&out.stdout),
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

impl Drop for Cluster {
    /// Cancels the cluster's jobs, then SIGTERM to each daemon, the last started first;
    /// SIGKILL to one still there after ten seconds.
    fn drop(&mut self) {
        // A test that failed midway may leave jobs: cancelled first, so that no task of
        // this cluster's outlives it.
        let _ = self
            .command("scancel")
            .args(["--user", "root"])
            .stderr(Stdio::null())
            .status();
        for (_, child) in self.daemons.iter_mut().rev() {
            let _ = Command::new("kill")
                .arg("-TERM")
                .arg(child.id().to_string())
                .status();
            let start = Instant::now();
            loop {
                if !matches!(child.try_wait(), Ok(None)) {
                    break;
                }
                if start.elapsed() > Duration::from_secs(10) {
                    let _ = child.kill();
                    let _ = child.wait();
                    break;
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        }
    }
}
