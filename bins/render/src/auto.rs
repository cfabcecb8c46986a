//! `--depth auto`: the depth the cost model predicts fastest (thesis 5.2 and 6.4, with
//! this machine's calibration: docs/model.md), from a look at the scene's first 512 KiB,
//! all in this process.
//!
//! A scene file is looked at where it lies. A stream (stdin, or a pipe given as the
//! scene) is sampled first ([`crate::sample`]): its first 512 KiB kept in memory, or less
//! when it ends or pauses, and the launcher then feeds viewxf that sample and the rest
//! of the stream behind it ([`crate::launch::Feed`]), so that the stream is read once
//! and nothing goes to disk. A scene the look cannot read is left to the stages, at
//! depth 0, which report it as they do at any depth. With --hosts, the plan is for the
//! hosts (every host a subtree).

use crate::launch::Feed;
use crate::options::{Options, Scene};
use crate::sample::{self, Ended};
use std::fs::File;
use std::io::Read;
use std::os::fd::{AsFd, OwnedFd};
use std::path::Path;
use std::sync::Arc;

/// The depth chosen, and the line `--stats` prints about it.
pub struct Choice {
    pub depth: u32,
    /// `depth auto chose …`, for --stats.
    pub said: Option<String>,
}

/// A scene on a stream, sampled ([`sample_stream`]): the sample, whether it is the whole
/// stream, and the rest of the stream, until [`Sampled::feed`] takes it.
pub struct Sampled {
    pub sample: Arc<Vec<u8>>,
    pub whole: bool,
    pub rest: Option<OwnedFd>,
}

impl Sampled {
    /// The feed that gives viewxf the sample and then the rest of the stream; the
    /// sample stays here too, for the look.
    pub fn feed(&mut self) -> Feed {
        Feed {
            sample: Arc::clone(&self.sample),
            rest: self.rest.take(),
        }
    }
}

/// The largest scene file too small for the tree to pay on any number of cores, on a
/// `width`×`height` screen, so that the model need not be asked (`None` when the screen
/// is too large for any scene to be that small). A polygon takes at least 16 bytes of a
/// scene file (three vertices and NEXT.POLYGON take 31 in text) and fills at most the
/// screen, so a file of B bytes asks at most B/16·W·H depth tests of the leaves, which
/// test 300 million a CPU second (docs/performance.md, "The fill rate"): under
/// 9,600,000/(W·H) bytes that is under 2 ms, less than the tree's extra processes cost
/// to start.
pub fn tiny_bound(width: u32, height: u32) -> Option<u64> {
    let bound = 9_600_000 / (u64::from(width) * u64::from(height));
    (bound >= 64).then_some(bound)
}

/// What `--stats` says when `o`'s scene is a regular file too small for the tree to pay
/// ([`tiny_bound`]) and there are no hosts: depth 0, chosen before the load is read or
/// the model asked (`None` otherwise). A scene named that is a pipe (`<(…)`) is a stream,
/// read once, by the stages: it is not opened here.
pub fn tiny_scene(o: &Options) -> Option<String> {
    let (Scene::Path(p), true) = (&o.scene, o.hosts.is_empty()) else {
        return None;
    };
    if !p.is_file() {
        return None;
    }
    let bound = tiny_bound(o.width, o.height).filter(|b| tiny_file(p, *b))?;
    Some(format!(
        "depth auto chose 0 (a scene file of at most {bound} bytes on a {} screen: under 2 ms of depth tests; the model not asked)",
        o.size
    ))
}

/// Whether the file `path` is at most `bound` bytes and in the text form (a binary
/// stream, whose first byte is 0x89, is left to the model). Reads at most `bound + 1`
/// bytes.
pub fn tiny_file(path: &Path, bound: u64) -> bool {
    let Ok(f) = File::open(path) else {
        return false;
    };
    let mut data = Vec::new();
    if f.take(bound + 1).read_to_end(&mut data).is_err() {
        return false;
    }
    data.len() as u64 <= bound && data.first() != Some(&0x89)
}

/// The stream to sample for a scene, if it is one: stdin, or a scene named that is not
/// a regular file (a pipe, `<(…)`), opened here. A scene that cannot be opened is
/// status 3, as render says of any scene it cannot read.
pub fn stream_of(scene: &Scene) -> stagecli::Result<Option<OwnedFd>> {
    match scene {
        Scene::Stdin => std::io::stdin()
            .as_fd()
            .try_clone_to_owned()
            .map(Some)
            .map_err(|e| stagecli::Error::from(e).context("stdin")),
        Scene::Path(p) if !p.is_file() => File::open(p)
            .map(|f| Some(OwnedFd::from(f)))
            .map_err(|_| stagecli::Error::io(format!("cannot read scene {}", p.display()))),
        Scene::Path(_) => Ok(None),
    }
}

/// The machine to plan `o`'s render for: this one's cores (`taskset`'s, under it), and
/// the load of other programs on them, read before the render starts a stage (the
/// threads runnable now: the render's own are not yet among them); with --hosts, the
/// hosts.
pub fn target(o: &Options) -> costmodel::model::Target {
    let hosts = (!o.hosts.is_empty()).then_some(o.hosts.len() as u32);
    costmodel::cli::target(None, None, hosts, None, 1.0)
}

/// What `--stats` says when the render has a core or less ([`one_core_at_most`]).
pub const ONE_CORE: &str = "depth auto chose 0 (a core or less for the render: a deeper tree \
     cannot run its stages side by side and only adds work; the model not asked)";

/// Whether `target` leaves the render's processes a core or less together (one core, as
/// under `taskset -c 0`, or a loaded machine's share) with no hosts: there the model
/// takes depth 0 for every scene, as a deeper tree only adds work
/// (`costmodel::model::Target::shares`; `a_core_or_less_is_depth_0_for_every_scene` holds
/// it), so render skips the look and the model (0.6 ms and more of a one-core render's
/// CPU, where nothing overlaps them).
pub fn one_core_at_most(target: &costmodel::model::Target) -> bool {
    target.hosts.is_none() && target.shares(0).1 <= 1.0
}

/// Samples `o`'s scene when it is a stream ([`stream_of`]): its first 512 KiB kept in
/// memory, or less when it ends or pauses ([`crate::sample`]). `None` for a scene file,
/// which the look reads where it lies.
pub fn sample_stream(o: &Options) -> stagecli::Result<Option<Sampled>> {
    let Some(fd) = stream_of(&o.scene)? else {
        return Ok(None);
    };
    let mut input = File::from(fd);
    let mut bytes = Vec::new();
    let (_, ended) = sample::sample(
        &mut input,
        &mut bytes,
        sample::SAMPLE_BYTES,
        sample::PATIENCE,
    )
    .map_err(|e| stagecli::Error::from(e).context("cannot read the scene's first bytes"))?;
    let whole = ended == Ended::Whole;
    Ok(Some(Sampled {
        sample: Arc::new(bytes),
        whole,
        rest: (!whole).then(|| OwnedFd::from(input)),
    }))
}

/// Chooses the depth for `o`'s scene (`o.depth` is `None`), from `sampled` when the scene
/// is a stream ([`sample_stream`]), else from the scene file. `root`: the repository
/// (bench/model.toml, the constants of a machine not yet calibrated); `bin`: the
/// binaries (whose calibration this is); `tell`: whether a person watches stderr, to be
/// told once that the machine is not calibrated. A scene the look cannot read is left to
/// the stages, at depth 0.
pub fn choose(
    o: &Options,
    sampled: Option<&Sampled>,
    target: &costmodel::model::Target,
    root: &Path,
    bin: &Path,
    tell: bool,
    me: &str,
) -> Choice {
    let mut choice = Choice {
        depth: 0,
        said: None,
    };
    // The camera as single words, so that a value with a leading minus stays a value.
    let camera: Vec<String> = o
        .camera
        .chunks(2)
        .map(|w| format!("{}={}", w[0], w.get(1).map_or("", String::as_str)))
        .collect();
    let Ok((k, note, state)) = costmodel::cli::constants(None, root, bin) else {
        return choice;
    };
    let env = match (&o.scene, sampled) {
        (_, Some(s)) => {
            costmodel::look::look_sample(&s.sample, o.width, o.height, &camera, s.whole)
        }
        (Scene::Path(p), None) => costmodel::look::look(
            p,
            o.width,
            o.height,
            &camera,
            Some(costmodel::look::LOOK_BYTES),
        ),
        (Scene::Stdin, None) => return choice,
    };
    // A scene the look cannot read: the stages say what is wrong with it, at depth 0.
    let Ok(env) = env else { return choice };
    let (depth, reason, _) = costmodel::model::choose_depth_on(&k, &env, target, 6);
    choice.depth = u32::from(depth);
    let reason = match note {
        Some(n) => format!("{reason}; {n}"),
        None => reason,
    };
    choice.said = Some(format!("depth auto chose {depth} ({reason})"));
    if tell && state.needs_fitting() {
        costmodel::cli::tell_once(&state, root, me);
    }
    choice
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn the_tiny_bound_is_two_ms_of_depth_tests() {
        assert_eq!(tiny_bound(64, 64), Some(2343));
        // 38 bytes at 500x500: smaller than any scene, so the model is asked.
        assert_eq!(tiny_bound(500, 500), None);
        assert_eq!(tiny_bound(387, 387), Some(64));
        assert_eq!(tiny_bound(1920, 1080), None);
    }

    #[test]
    fn a_tiny_file_is_small_and_text() {
        let mut f = tempfile::NamedTempFile::new().unwrap();
        f.write_all(&[b'p'; 100]).unwrap();
        assert!(tiny_file(f.path(), 100));
        assert!(!tiny_file(f.path(), 99));
        let mut b = tempfile::NamedTempFile::new().unwrap();
        b.write_all(&proto::header::BINARY_MAGIC).unwrap();
        assert!(!tiny_file(b.path(), 100));
        assert!(!tiny_file(Path::new("/nonexistent"), 100));
    }
}
