//! What the stages said and how they ended, told to the user: each stage's words with
//! its label and channels' names, the cause of a failed run, a host's failure, the
//! links' bytes (`--stats --hosts`) and the stages' costs (`--times`).

use super::plan::Stage;
use stagecli::stats::Record;
use std::io::Write;
use std::os::fd::RawFd;
use std::os::unix::process::ExitStatusExt;
use std::process::ExitStatus;

/// How the run ended: the launcher's exit status and what it writes on stderr.
#[derive(Debug, PartialEq, Eq)]
pub struct Outcome {
    pub status: u8,
    pub message: String,
}

/// A stage's exit as the shell numbers it: its status, or 128 + the signal that killed it.
pub fn shell_status(status: ExitStatus) -> i32 {
    status
        .code()
        .or_else(|| status.signal().map(|s| 128 + s))
        .unwrap_or(1)
}

/// `status 3`, or `killed by SIGKILL`, for a status as the shell numbers it.
pub fn describe(status: i32) -> String {
    if status > 128 {
        format!("killed by {}", stagecli::remote::signal_name(status - 128))
    } else {
        format!("status {status}")
    }
}

/// How the messages name node `node` of a tree of depth `depth`: `leaf N` or `subtree K`.
pub fn what_node(node: u64, depth: u32) -> String {
    let leaves = 1u64 << depth;
    if node >= leaves {
        format!("leaf {}", node - leaves)
    } else {
        format!("subtree {node}")
    }
}

/// What a stage wrote on stderr, for the user: each `/dev/fd/N` the stage was given for
/// a channel named by the channel (`zbuf: /dev/fd/9: …` becomes `zbuf: leaf-2: …`); a
/// line that starts with the bare program name given the stage's full label instead
/// (`scanconv: …` from leaf 2 becomes `scanconv (leaf 2): …`; lines a stage labelled
/// itself, as `splitter y=0 (node 2): …`, are left alone); a host's render's lines
/// (labelled by it) given the host. A `--stats` record ([`stagecli::stats`]) is given the
/// same: a value that is a `/dev/fd/N` its channel's name, a `label` (the stage's, where
/// the record has none) and, from a host, a `host`.
pub fn labelled(said: &str, stage: &Stage, fds: &[(RawFd, String)]) -> String {
    let program = stage.label.split(' ').next().unwrap_or("");
    let mut out = String::with_capacity(said.len());
    for line in said.lines() {
        if let Some(Ok(record)) = stagecli::stats::parse_line(line) {
            out.push_str(&format!("{}\n", labelled_record(record, stage, fds)));
            continue;
        }
        let line = name_channels(line, fds);
        if let Some((host, _)) = &stage.host {
            let line = stagecli::remote::without_render_prefix(&line);
            out.push_str(&format!("host {host}: {line}\n"));
        } else if let Some(rest) = line
            .strip_prefix(program)
            .and_then(|r| r.strip_prefix(": "))
        {
            out.push_str(&format!("{}: {rest}\n", stage.label));
        } else {
            out.push_str(&line);
            out.push('\n');
        }
    }
    out
}

/// A stage's `--stats` record as [`labelled`] gives it.
fn labelled_record(mut record: Record, stage: &Stage, fds: &[(RawFd, String)]) -> Record {
    let named: Vec<(String, String)> = record
        .fields()
        .iter()
        .filter(|(_, v)| v.starts_with("/dev/fd/"))
        .map(|(k, v)| (k.clone(), name_channels(v, fds)))
        .collect();
    for (k, v) in named {
        record.set(&k, v);
    }
    if record.get("label").is_none() {
        record.set("label", &stage.label);
    }
    if let Some((host, _)) = &stage.host {
        if record.get("host").is_none() {
            record.set("host", host);
        }
    }
    record
}

/// `line` with each `/dev/fd/N` in `fds` replaced by its channel's name.
fn name_channels(line: &str, fds: &[(RawFd, String)]) -> String {
    const DEV_FD: &str = "/dev/fd/";
    let mut out = String::new();
    let mut rest = line;
    while let Some(at) = rest.find(DEV_FD) {
        let after = &rest[at + DEV_FD.len()..];
        let digits = after.bytes().take_while(u8::is_ascii_digit).count();
        let name = after[..digits]
            .parse::<RawFd>()
            .ok()
            .and_then(|fd| fds.iter().find(|(f, _)| *f == fd));
        out.push_str(&rest[..at]);
        match name {
            Some((_, n)) => out.push_str(n),
            None => out.push_str(&rest[at..at + DEV_FD.len() + digits]),
        }
        rest = &after[digits..];
    }
    out.push_str(rest);
    out
}

/// The stage to blame for a failed run, among those whose exit is known (the shell's
/// numbering; 0 for one still running): one killed by a signal, or else the most
/// upstream (the first in the graph's order) that failed.
pub fn cause(statuses: &[Option<i32>]) -> Option<usize> {
    let mut first = None;
    for (i, st) in statuses.iter().enumerate() {
        match st.unwrap_or(0) {
            0 => continue,
            s if s > 128 => return Some(i),
            _ => {
                first.get_or_insert(i);
            }
        }
    }
    first
}

/// The node a merger's message says sent back nothing (`zbuf: from-5: empty input`).
fn empty_from(said: &str) -> Option<u64> {
    from_node(said)
        .filter(|(_, what)| what.starts_with("empty input"))
        .map(|(node, _)| node)
}

/// The node a merger's message is about, and what it says of its stream
/// (`zbuf: from-5: line 1, column 2: not UTF-8 text` gives 5 and `line 1, …`).
fn from_node(said: &str) -> Option<(u64, &str)> {
    said.lines().find_map(|line| {
        let (_, rest) = line.split_once(": from-")?;
        let (node, what) = rest.split_once(": ")?;
        Some((node.parse().ok()?, what))
    })
}

/// A stage on a host that sent nothing for `--host-timeout`: what it said, then its
/// host and node named, status 3.
pub fn silent_host(
    stage: &Stage,
    said: &str,
    depth: u32,
    timeout: std::time::Duration,
    me: &str,
) -> Outcome {
    let s = timeout.as_secs_f64();
    let Some((host, node)) = &stage.host else {
        return Outcome {
            status: 3,
            message: format!(
                "{said}{me}: {} sent nothing for {s} s (--host-timeout)\n",
                stage.label
            ),
        };
    };
    Outcome {
        status: 3,
        message: format!(
            "{said}{me}: host {host} ({}): sent nothing for {s} s (--host-timeout): counted as failed\n",
            what_node(*node, depth)
        ),
    }
}

/// With `--stats` and `--hosts`: each host stage's node, host, and the bytes its link
/// carried each way (thesis 6.5 estimates them for the transputer links), from the local
/// stages' records: the splitters' `out1_bytes` and `out2_bytes` and the merger's
/// `bytes_in` from `from-K`. A subtree at the root carries the clipper's whole output,
/// which nothing counts. A line for people and a record (`node`, `host`, `bytes_there`
/// where counted, `bytes_back`) a host.
pub fn links(stages: &[Stage], said: &[String], depth: u32, me: &str) -> String {
    let records: Vec<Record> = said
        .iter()
        .flat_map(|t| t.lines())
        .filter_map(stagecli::stats::parse_line)
        .filter_map(Result::ok)
        .filter(|r| r.get("host").is_none())
        .collect();
    let mut out = String::new();
    for s in stages {
        let Some((host, node)) = &s.host else {
            continue;
        };
        let mut record = Record::new(me).with("node", node).with("host", host);
        let mut there = "not counted (the clipper's output)".to_string();
        let mut back = "?".to_string();
        if *node > 1 {
            let out_key = if node & 1 == 0 {
                "out1_bytes"
            } else {
                "out2_bytes"
            };
            if let Some(n) = records
                .iter()
                .filter(|r| r.stage() == "splitter" && r.count("node") == Some(node >> 1))
                .find_map(|r| r.count(out_key))
            {
                there = format!("{n} bytes there");
                record.set("bytes_there", n);
            }
        }
        let from = format!("from-{node}");
        if let Some(n) = records
            .iter()
            .filter(|r| r.stage() == "zbuf" && r.get("input") == Some(from.as_str()))
            .find_map(|r| r.count("bytes_in"))
        {
            back = format!("{n} bytes back");
            record.set("bytes_back", n);
        }
        out.push_str(&format!(
            "{me}: {} on host {host}: {there}, {back}\n{record}\n",
            what_node(*node, depth)
        ));
    }
    out
}

/// What one stage cost, from `wait4`: its CPU (user and system) and its own peak
/// resident memory, and when it ended, counted from the launcher's start.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cost {
    pub user_s: f64,
    pub system_s: f64,
    pub peak_kib: u64,
    pub ended_s: f64,
}

impl Cost {
    pub(super) fn of(usage: &libc::rusage, ended_s: f64) -> Cost {
        let s = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Cost {
            user_s: s(usage.ru_utime),
            system_s: s(usage.ru_stime),
            peak_kib: u64::try_from(usage.ru_maxrss).unwrap_or(0),
            ended_s,
        }
    }
}

/// `--times`: a line a stage, `render: LABEL: 6.6 ms CPU (6.1 user, 0.5 system), 3.1
/// MB peak, ended at 31.0 ms`, and a last line of their sums: the CPU of all of them, and
/// the sum of their peaks, a bound on what the stages, running side by side, held at any
/// one moment. Each line is followed by its record ([`stagecli::stats`]): a stage's
/// `label`, `user_ms`, `system_ms`, `peak_kib`, `ended_ms`; the sums' `stages`, `cpu_ms`,
/// `peaks_kib`, `last_ended_ms` (times to the microsecond).
pub fn times(stages: &[Stage], costs: &[Cost], me: &str) -> String {
    let ms = |s: f64| s * 1e3;
    let mb = |kib: u64| kib as f64 / 1024.0;
    let mut out = String::new();
    for (s, c) in stages.iter().zip(costs) {
        out.push_str(&format!(
            "{me}: {}: {:.1} ms CPU ({:.1} user, {:.1} system), {:.1} MB peak, ended at {:.1} ms\n",
            s.label,
            ms(c.user_s + c.system_s),
            ms(c.user_s),
            ms(c.system_s),
            mb(c.peak_kib),
            ms(c.ended_s)
        ));
        let record = Record::new(me)
            .with("label", &s.label)
            .with("user_ms", format!("{:.3}", ms(c.user_s)))
            .with("system_ms", format!("{:.3}", ms(c.system_s)))
            .with("peak_kib", c.peak_kib)
            .with("ended_ms", format!("{:.3}", ms(c.ended_s)));
        out.push_str(&format!("{record}\n"));
    }
    let cpu: f64 = costs.iter().map(|c| c.user_s + c.system_s).sum();
    let peak: u64 = costs.iter().map(|c| c.peak_kib).sum();
    let last = costs.iter().map(|c| c.ended_s).fold(0.0, f64::max);
    out.push_str(&format!(
        "{me}: {} stages: {:.1} ms CPU, {:.1} MB of peaks, the last ended at {:.1} ms\n",
        costs.len(),
        ms(cpu),
        mb(peak),
        ms(last)
    ));
    let record = Record::new(me)
        .with("stages", costs.len())
        .with("cpu_ms", format!("{:.3}", ms(cpu)))
        .with("peaks_kib", peak)
        .with("last_ended_ms", format!("{:.3}", ms(last)));
    out.push_str(&format!("{record}\n"));
    out
}

/// Writes the outcome's message on stderr, in one write.
pub fn tell(outcome: &Outcome) {
    if !outcome.message.is_empty() {
        let _ = std::io::stderr().write_all(outcome.message.as_bytes());
    }
}

/// What the supervisor knows of a run that has ended, and what the user asked to be told.
pub struct Ended<'a> {
    pub stages: &'a [Stage],
    /// What each stage said, [`labelled`].
    pub said: Vec<String>,
    /// What each stage said, as it said it.
    pub raw: &'a [Vec<u8>],
    /// How each stage exited, where it has.
    pub exits: &'a [Option<ExitStatus>],
    pub costs: &'a [Cost],
    /// The tree's depth, for naming the hosts' nodes.
    pub depth: u32,
    /// The hosts' links' bytes on success (`--stats --hosts`).
    pub links: bool,
    /// What each stage cost on success (`--times`).
    pub times: bool,
}

impl Ended<'_> {
    /// The run's failure as garbage from a host, when the merger could not read what a
    /// host sent (anything but an empty stream) and the cause `c` is the merger or that
    /// host killed by the merger's end (SIGPIPE).
    fn garbage(&self, c: usize, statuses: &[Option<i32>], me: &str) -> Option<Outcome> {
        const SIGPIPE_STATUS: i32 = 128 + libc::SIGPIPE;
        self.stages.iter().enumerate().find_map(|(m, merger)| {
            if merger.host.is_some() || statuses[m].unwrap_or(0) == 0 {
                return None;
            }
            let (node, what) = from_node(&self.said[m])?;
            if what.starts_with("empty input") {
                return None;
            }
            let h = self
                .stages
                .iter()
                .position(|s| matches!(&s.host, Some((_, k)) if *k == node))?;
            if c != m && !(c == h && statuses[h] == Some(SIGPIPE_STATUS)) {
                return None;
            }
            let (host, _) = self.stages[h].host.clone().unwrap_or_default();
            Some(Outcome {
                status: 3,
                message: format!(
                    "{me}: host {host} ({}): sent what is not a polypipe stream: {what}\n",
                    what_node(node, self.depth)
                ),
            })
        })
    }

    /// How the run ended, in words: on success what every stage said (and the links'
    /// bytes and the costs, when asked); on a failure with `cause` its words and its
    /// name, or the host that failed or sent back nothing.
    pub fn outcome(&self, cause: Option<usize>, me: &str) -> Outcome {
        let fail = |message: String| Outcome { status: 3, message };
        let Some(c) = cause else {
            let mut message = self.said.concat();
            if self.links {
                message.push_str(&links(self.stages, &self.said, self.depth, me));
            }
            if self.times {
                message.push_str(&times(self.stages, self.costs, me));
            }
            return Outcome { status: 0, message };
        };
        let statuses: Vec<Option<i32>> = self.exits.iter().map(|e| e.map(shell_status)).collect();
        let st = statuses[c].unwrap_or(0);
        let said = &self.said[c];
        let stage = &self.stages[c];
        // A host that sent what is not a stream: the merger says what it found, and the
        // host, still writing, is killed by SIGPIPE (status 141) or is no cause.
        if let Some(out) = self.garbage(c, &statuses, me) {
            return out;
        }
        if stage.host.is_none() {
            // The merger found a host's runs empty: that host answered with nothing (a
            // command that is not render, say), the host's fault, not the data's.
            if let Some(node) = empty_from(said) {
                if let Some(h) = self
                    .stages
                    .iter()
                    .position(|s| matches!(&s.host, Some((_, k)) if *k == node))
                {
                    let (host, _) = self.stages[h].host.clone().unwrap_or_default();
                    return fail(format!(
                        "{me}: host {host} ({}): sent back nothing ({} from its command)\n",
                        what_node(node, self.depth),
                        describe(statuses[h].unwrap_or(0))
                    ));
                }
            }
        }
        if let Some((host, node)) = &stage.host {
            // A subtree on a host: what ssh or the far side said last is the message.
            let lines: Vec<&str> = said.lines().collect();
            let mut message: String = lines[..lines.len().saturating_sub(1)]
                .iter()
                .map(|l| format!("{l}\n"))
                .collect();
            let raw = String::from_utf8_lossy(&self.raw[c]);
            let (code, signal) = self.exits[c].map_or((Some(st), None), |e| (e.code(), e.signal()));
            let f = stagecli::remote::classify(code, signal, &raw, "render.sh").unwrap_or(
                stagecli::remote::Failure {
                    message: "failed".into(),
                    status: 1,
                },
            );
            message.push_str(&format!(
                "{me}: host {host} ({}): {}\n",
                what_node(*node, self.depth),
                f.message
            ));
            return Outcome {
                status: f.status,
                message,
            };
        }
        // A stage that ended with a status of the house's (1 to 3) and said why has
        // said it in one line naming itself: that line is the message. One that said
        // nothing, died of a signal or ended otherwise (a panic's 101) is named here.
        let own = (1..=3).contains(&st) && !said.trim().is_empty();
        Outcome {
            status: if (1..=3).contains(&st) { st as u8 } else { 1 },
            message: if own {
                said.clone()
            } else {
                format!("{said}{me}: {} failed ({})\n", stage.label, describe(st))
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::plan::tests::linear;
    use super::*;

    #[test]
    fn what_the_stages_said_names_the_stage_and_its_channels() {
        let s = linear();
        let zbuf = labelled(
            "zbuf: /dev/fd/12: empty input\nzbuf: /dev/fd/1: x\n",
            &s[4],
            &[(12, "from-3".into())],
        );
        assert_eq!(zbuf, "zbuf: from-3: empty input\nzbuf: /dev/fd/1: x\n");
        let mut leaf = s[1].clone();
        leaf.label = "scanconv (leaf 2)".into();
        assert_eq!(
            labelled("scanconv: bad\nsplitter y=0 (node 2): 5\n", &leaf, &[]),
            "scanconv (leaf 2): bad\nsplitter y=0 (node 2): 5\n"
        );
        assert_eq!(
            labelled("render: zbuf failed\nrender.sh: old\n", &s[2], &[]),
            "host a: zbuf failed\nhost a: old\n"
        );
        // A record: its channels named, and the stage's label (and host) added.
        assert_eq!(
            labelled(
                "zbuf: /dev/fd/12: 1 spans\n@stats zbuf input=/dev/fd/12 spans=1\n",
                &s[4],
                &[(12, "from-3".into())],
            ),
            "zbuf: from-3: 1 spans\n@stats zbuf input=from-3 spans=1 label=zbuf\n"
        );
        assert_eq!(
            labelled("@stats scanconv tiles=2 label=x\n", &s[2], &[]),
            "@stats scanconv tiles=2 label=x host=a\n"
        );
        assert_eq!(
            name_channels("/dev/fd/123 /dev/fd/12 /dev/fd/", &[(12, "x".into())]),
            "/dev/fd/123 x /dev/fd/"
        );
    }

    #[test]
    fn the_cause_is_one_killed_or_else_the_most_upstream() {
        assert_eq!(cause(&[Some(0), None, Some(1), Some(1)]), Some(2));
        assert_eq!(cause(&[Some(0), Some(1), Some(137), None]), Some(2));
        assert_eq!(cause(&[Some(0), None]), None);
        assert_eq!(describe(137), "killed by SIGKILL");
        assert_eq!(describe(2), "status 2");
        assert_eq!(what_node(5, 2), "leaf 1");
        assert_eq!(what_node(3, 2), "subtree 3");
        assert_eq!(empty_from("zbuf: from-5: empty input: expected"), Some(5));
        assert_eq!(empty_from("zbuf: stdin: empty input"), None);
    }

    #[test]
    fn times_are_a_line_a_stage_and_their_sums() {
        let s = linear();
        let cost = |user_s, system_s, peak_kib, ended_s| Cost {
            user_s,
            system_s,
            peak_kib,
            ended_s,
        };
        let costs = [
            cost(0.0061, 0.0005, 3174, 0.031),
            cost(0.002, 0.0, 1024, 0.04),
        ];
        assert_eq!(
            stagecli::stats::human(&times(&s[..2], &costs, "render")),
            "render: viewxf: 6.6 ms CPU (6.1 user, 0.5 system), 3.1 MB peak, ended at 31.0 ms\n\
             render: splitter (node 1): 2.0 ms CPU (2.0 user, 0.0 system), 1.0 MB peak, ended at 40.0 ms\n\
             render: 2 stages: 8.6 ms CPU, 4.1 MB of peaks, the last ended at 40.0 ms\n"
        );
        let said = times(&s[..2], &costs, "render");
        let records = stagecli::stats::records(&said).unwrap();
        assert_eq!(
            records.iter().map(ToString::to_string).collect::<Vec<_>>(),
            [
                "@stats render label=viewxf user_ms=6.100 system_ms=0.500 peak_kib=3174 ended_ms=31.000",
                "@stats render label=splitter%20(node%201) user_ms=2.000 system_ms=0.000 peak_kib=1024 ended_ms=40.000",
                "@stats render stages=2 cpu_ms=8.600 peaks_kib=4198 last_ended_ms=40.000",
            ]
        );
    }

    #[test]
    fn links_count_the_bytes_each_host_carried() {
        let s = linear();
        let said = vec![
            String::new(),
            "splitter x=0 (node 1): 10 polygons; 700 and 300 bytes out\n\
             @stats splitter node=1 plane=x%3D0 polygons_in=10 out1_bytes=700 out2_bytes=300\n"
                .into(),
            // A host's own splitter of node 1 is not the local one.
            "@stats splitter node=1 out1_bytes=5 out2_bytes=6 host=a\n".into(),
            String::new(),
            "zbuf: from-2: 3 runs, 40 bytes in\n@stats zbuf input=from-2 runs=3 bytes_in=40\n\
             @stats zbuf input=from-3 runs=1 bytes_in=9\n"
                .into(),
        ];
        assert_eq!(
            links(&s, &said, 1, "render"),
            "render: leaf 0 on host a: 700 bytes there, 40 bytes back\n\
             @stats render node=2 host=a bytes_there=700 bytes_back=40\n\
             render: leaf 1 on host b: 300 bytes there, 9 bytes back\n\
             @stats render node=3 host=b bytes_there=300 bytes_back=9\n"
        );
        // The prose alone is not read.
        let prose = vec![said[1].lines().next().unwrap_or("").to_string()];
        assert_eq!(
            links(&s, &prose, 1, "render"),
            "render: leaf 0 on host a: not counted (the clipper's output), ?\n\
             @stats render node=2 host=a\n\
             render: leaf 1 on host b: not counted (the clipper's output), ?\n\
             @stats render node=3 host=b\n"
        );
    }
}
