//! The plan of processes: the stages of a graph, where each one's input and output go,
//! and the channels (pipes) that join them, checked before anything starts.

use std::ffi::OsString;
use std::path::PathBuf;

/// Where a stage's stdin or stdout goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum End {
    /// The launcher's own (`-`): the scene on stdin, the frames on stdout.
    Inherit,
    /// A file, opened here (`file:PATH`).
    Path(PathBuf),
    /// A channel to another stage (`pipe:NAME`).
    Pipe(String),
}

/// One process of the graph.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stage {
    /// Its name in messages: `persp (leaf 2)`, `splitter (node 3)`.
    pub label: String,
    pub input: End,
    pub output: End,
    /// For a stage that runs on another host: the host and the node of the tree there.
    pub host: Option<(String, u64)>,
    /// The program and its arguments; the last `pipes` arguments are channel names,
    /// given to the program as `/dev/fd/N`.
    pub argv: Vec<OsString>,
    pub pipes: usize,
}

/// A graph that cannot be run (two readers of a channel, say): a bug in its builder.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SpecError {
    #[error("stage {0}: the description ends early")]
    Short(usize),
    #[error("stage {0}: {1}")]
    Bad(usize, String),
    #[error("channel {0}: {1}")]
    Channel(String, String),
}

/// Where a channel's two ends go: (stage, argument index or `None` for stdin/stdout).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Channel {
    pub writer: (usize, Option<usize>),
    pub reader: (usize, Option<usize>),
}

/// Each channel's writer and reader. A channel on a stdout is written there, on a stdin
/// read there; one named on a command line is the other end of one of those.
pub fn channels(stages: &[Stage]) -> Result<Vec<(String, Channel)>, SpecError> {
    let (chans, open) = channels_open(stages)?;
    match open.into_iter().next() {
        Some((name, _)) => Err(SpecError::Channel(
            name,
            "needs one writer and one reader".into(),
        )),
        None => Ok(chans),
    }
}

/// The channels of a graph's first stages, and those of their stdouts that none of them
/// reads (their readers start later), by name and writer.
pub type OpenChannels = (Vec<(String, Channel)>, Vec<(String, usize)>);

/// [`channels`] of the first stages of a graph: also those written on a stage's stdout
/// that none of them reads (their readers start later), by name and writer.
pub fn channels_open(stages: &[Stage]) -> Result<OpenChannels, SpecError> {
    let mut writers: Vec<(String, (usize, Option<usize>))> = Vec::new();
    let mut readers: Vec<(String, (usize, Option<usize>))> = Vec::new();
    let mut named: Vec<(String, (usize, usize))> = Vec::new();
    for (i, s) in stages.iter().enumerate() {
        if let End::Pipe(n) = &s.output {
            writers.push((n.clone(), (i, None)));
        }
        if let End::Pipe(n) = &s.input {
            readers.push((n.clone(), (i, None)));
        }
        for k in s.argv.len() - s.pipes..s.argv.len() {
            named.push((s.argv[k].to_string_lossy().into_owned(), (i, k)));
        }
    }
    for (name, (i, k)) in named {
        let w = writers.iter().any(|(n, _)| *n == name);
        let r = readers.iter().any(|(n, _)| *n == name);
        match (w, r) {
            (true, false) => readers.push((name, (i, Some(k)))),
            (false, true) => writers.push((name, (i, Some(k)))),
            _ => {
                return Err(SpecError::Channel(
                    name,
                    "named on a command line needs its other end on a stdin or a stdout".into(),
                ))
            }
        }
    }
    let mut out = Vec::new();
    let mut open = Vec::new();
    for (name, writer) in &writers {
        let mut found = readers.iter().filter(|(n, _)| n == name);
        match (
            found.next(),
            found.next(),
            writers.iter().filter(|(n, _)| n == name).count(),
        ) {
            (Some((_, reader)), None, 1) => out.push((
                name.clone(),
                Channel {
                    writer: *writer,
                    reader: *reader,
                },
            )),
            (None, _, 1) if writer.1.is_none() => open.push((name.clone(), writer.0)),
            _ => {
                return Err(SpecError::Channel(
                    name.clone(),
                    "needs one writer and one reader".into(),
                ))
            }
        }
    }
    if let Some((name, _)) = readers
        .iter()
        .find(|(n, _)| !writers.iter().any(|(w, _)| w == n))
    {
        return Err(SpecError::Channel(name.clone(), "has no writer".into()));
    }
    Ok((out, open))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    pub(in crate::launch) fn words(s: &[&str]) -> Vec<OsString> {
        s.iter().map(OsString::from).collect()
    }

    /// A stage of `argv`, from `input` to `output`, on `host` at a node when given.
    fn stage(
        label: &str,
        input: End,
        output: End,
        host: Option<(&str, u64)>,
        argv: &[&str],
        pipes: usize,
    ) -> Stage {
        Stage {
            label: label.into(),
            input,
            output,
            host: host.map(|(h, n)| (h.into(), n)),
            argv: words(argv),
            pipes,
        }
    }

    /// viewxf, a splitter, two leaves on hosts a and b, and the merger.
    pub(in crate::launch) fn linear() -> Vec<Stage> {
        let pipe = |n: &str| End::Pipe(n.into());
        vec![
            stage(
                "viewxf",
                End::Path("scene.txt".into()),
                pipe("view"),
                None,
                &["viewxf", "--text"],
                0,
            ),
            stage(
                "splitter (node 1)",
                pipe("view"),
                End::Path("/dev/null".into()),
                None,
                &["splitter", "node-2", "node-3"],
                2,
            ),
            stage(
                "leaf 0 (host a)",
                pipe("node-2"),
                pipe("from-2"),
                Some(("a", 2)),
                &["ssh"],
                0,
            ),
            stage(
                "leaf 1 (host b)",
                pipe("node-3"),
                pipe("from-3"),
                Some(("b", 3)),
                &["ssh"],
                0,
            ),
            stage(
                "zbuf",
                End::Path("/dev/null".into()),
                End::Inherit,
                None,
                &["zbuf", "from-2", "from-3"],
                2,
            ),
        ]
    }

    #[test]
    fn channels_join_each_writer_to_its_reader() {
        let s = linear();
        let c = channels(&s).unwrap();
        let find = |n: &str| c.iter().find(|(name, _)| name == n).unwrap().1;
        assert_eq!(
            find("view"),
            Channel {
                writer: (0, None),
                reader: (1, None)
            }
        );
        assert_eq!(
            find("node-3"),
            Channel {
                writer: (1, Some(2)),
                reader: (3, None)
            }
        );
        assert_eq!(
            find("from-2"),
            Channel {
                writer: (2, None),
                reader: (4, Some(1))
            }
        );
        assert_eq!(c.len(), 5);
    }

    #[test]
    fn a_graph_whose_channels_do_not_pair_is_refused() {
        let sh =
            |label: &str, input: End, output: End| stage(label, input, output, None, &[label], 0);
        let p = || End::Pipe("p".into());
        let two_readers = [
            sh("a", End::Inherit, p()),
            sh("b", p(), End::Inherit),
            sh("c", p(), End::Inherit),
        ];
        assert!(matches!(channels(&two_readers), Err(SpecError::Channel(n, _)) if n == "p"));
        let no_writer = [sh("b", p(), End::Inherit)];
        assert!(matches!(channels(&no_writer), Err(SpecError::Channel(n, _)) if n == "p"));
    }
}
