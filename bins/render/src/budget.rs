//! `--max-error E`: the cheapest sampling mode and depth predicted to keep the RMS error
//! against the 16×16 reference (`zspec --samples 16`) within E levels of 0–255
//! (`costmodel::accuracy`; docs/model.md, "Accuracy as a target").
//!
//! It chooses `--aa` and `--depth`, so it is refused beside an `--hse` other than zbuf
//! (the exact methods give the z-buffer's bytes, and only its leaf is in the time model),
//! an `--aa` other than none, a fixed `--depth`, `--merge buffer`, `--pixels`,
//! `--hidden-line` and `--hosts`. Where the look cannot judge the scene (a stream, which
//! the look would have to sample before the choice; a scene it cannot read), it takes the
//! safe choice, `ss16` (the reference's own sampling: 0 error on any scene), and says so.

use crate::options::{Cli, Options, Scene};
use costmodel::accuracy::{self, Accuracy};
use stagecli::Error;

/// `--max-error E` with the other options: a usage error for those it cannot combine with.
pub fn check(cli: &Cli) -> Result<(), Error> {
    let Some(e) = cli.max_error else {
        return Ok(());
    };
    let fixed_depth = cli.depth.and_then(crate::options::Depth::fixed);
    let clash = if cli.hse != "zbuf" {
        Some(format!("--hse {}", cli.hse))
    } else if cli.aa != "none" {
        Some(format!("--aa {}", cli.aa))
    } else if let Some(d) = fixed_depth {
        Some(format!("--depth {d}"))
    } else if cli.merge != crate::options::Merge::Tiles {
        Some("--merge buffer".into())
    } else if cli.pixels {
        Some("--pixels".into())
    } else if cli.hidden_line {
        Some("--hidden-line".into())
    } else if cli.hosts.is_some() || cli.subtree.is_some() {
        Some("--hosts".into())
    } else {
        None
    };
    match clash {
        Some(c) => Err(Error::usage(format!(
            "--max-error {e} chooses the z-buffer's --aa and --depth: not with {c}"
        ))),
        None => Ok(()),
    }
}

/// What `--max-error` chose.
#[derive(Clone, Debug, PartialEq)]
pub struct Chosen {
    pub aa: String,
    /// `None`: left to --depth auto (a stream).
    pub depth: Option<u32>,
    /// The line `--stats` prints.
    pub said: String,
}

/// The choice for `o`'s scene under `max_error` (`o` validated, --aa none, no fixed depth).
pub fn choose(
    o: &Options,
    max_error: f64,
    root: &std::path::Path,
    bin: &std::path::Path,
) -> Chosen {
    let safe = |why: &str| Chosen {
        aa: accuracy::SAFE.into(),
        depth: None,
        said: format!(
            "max-error {max_error} chose --aa {} (the reference's own sampling), the depth \
             auto's: {why}",
            accuracy::SAFE
        ),
    };
    let Scene::Path(path) = &o.scene else {
        return safe("a stream, which the look cannot judge before it is sampled");
    };
    if !path.is_file() {
        return safe("a stream, which the look cannot judge before it is sampled");
    }
    let camera: Vec<String> = o
        .camera
        .chunks(2)
        .map(|w| format!("{}={}", w[0], w.get(1).map_or("", String::as_str)))
        .collect();
    let Some(seen) = accuracy::Seen::of(path, o.width, o.height, &camera) else {
        return safe("a scene the look cannot read");
    };
    let Ok((k, note, _)) = costmodel::cli::constants(None, root, bin) else {
        return safe("no time model");
    };
    let target = crate::auto::target(o);
    let Some(best) = accuracy::choose(&Accuracy::load(), &k, &seen, &target, max_error) else {
        return safe("no mode predicted to meet it");
    };
    let (env, colours) = (&seen.env, &seen.colours);
    let note = note.map_or(String::new(), |n| format!("; {n}"));
    Chosen {
        aa: best.aa.clone(),
        depth: Some(u32::from(best.depth)),
        said: format!(
            "max-error {max_error} chose --aa {} --depth {} (predicted {:.3} s, RMS {:.2}, \
             {:.1}% of pixels wrong; {} edge pixels a pixel {:.3}, contrast² {:.3}; rule: the \
             fastest predicted to meet the budget{note})",
            best.aa,
            best.depth,
            best.seconds,
            best.rms,
            100.0 * best.wrong,
            if colours.flat {
                "flat,"
            } else {
                "shaded or transparent (no adaptiveK),"
            },
            accuracy::edge_fraction(env),
            colours.contrast2,
        ),
    }
}

/// `o` with the choice applied: its --aa, the leaf's stage for it, and its depth.
pub fn apply(mut o: Options, chosen: &Chosen, table: &[methods::Method]) -> Options {
    o.aa = chosen.aa.clone();
    if let Some(m) = methods::by_aa(table, &chosen.aa) {
        o.leaf = m.stage_words();
    }
    if chosen.depth.is_some() {
        o.depth = chosen.depth;
    }
    o
}
