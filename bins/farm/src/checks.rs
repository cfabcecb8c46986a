//! The checks of what came back: the frames of a try, and how a try ended.

pub use stagecli::remote::{last_line, parse_hosts, remote_command, Failure};
use stagecli::{Error, FrameNames, Result};
use std::io::BufRead;
use std::path::PathBuf;

/// Reads one PPM frame (a header `P6 W H 255` and W·H RGB pixels, as zbuf writes it)
/// into the bytes zbuf would have written; `None` at the end; a message when it is not
/// one.
pub fn next_frame<R: BufRead>(input: &mut R) -> std::result::Result<Option<Frame>, String> {
    match proto::ppm::read(input) {
        Ok(None) => Ok(None),
        Ok(Some(image)) => {
            let mut rgb = Vec::with_capacity(image.pixels.len() * 3);
            for p in &image.pixels {
                rgb.extend_from_slice(p);
            }
            Ok(Some(Frame {
                width: image.width,
                height: image.height,
                rgb,
            }))
        }
        Err(e) => Err(e.to_string()),
    }
}

/// A frame as it came back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Frame {
    /// The frame as zbuf writes it on stdout: binary PPM.
    pub fn ppm(&self) -> Vec<u8> {
        let mut bytes = format!("P6\n{} {}\n255\n", self.width, self.height).into_bytes();
        bytes.extend_from_slice(&self.rgb);
        bytes
    }
}

/// Where the frames go.
#[derive(Clone, Debug)]
pub enum Output {
    /// Binary PPMs one after another on stdout, in the movie's order.
    Stdout,
    /// One file a frame, as zbuf's `-o PATTERN --first-frame N` writes them: the movie's
    /// frame k to `names.name(first + k)`, PNG or PPM by the extension.
    Files {
        pattern: String,
        names: FrameNames,
        png: bool,
        first: u64,
    },
}

impl Output {
    /// `-o PATTERN` (zbuf's: `%d`/`%0Nd` the frame's number, `.png` or `.ppm`) with
    /// `--first-frame N`.
    pub fn files(pattern: &str, first: u64) -> std::result::Result<Output, String> {
        let (names, ext) = FrameNames::parse_ending(pattern, &["png", "ppm"])?;
        if !names.numbered() {
            return Err(format!(
                "-o {pattern}: a movie needs a pattern with %d for the frame number (as \
                 frame%05d.png)"
            ));
        }
        Ok(Output::Files {
            pattern: pattern.to_string(),
            names,
            png: ext == "png",
            first,
        })
    }

    /// The file of the movie's frame `k` (`None` for stdout).
    pub fn path(&self, k: u64) -> Option<PathBuf> {
        match self {
            Output::Stdout => None,
            Output::Files { names, first, .. } => Some(names.name(first + k).into()),
        }
    }

    /// The number in the file name of the movie's frame `k` (`--first-frame` + k).
    pub fn number(&self, k: u64) -> u64 {
        match self {
            Output::Stdout => k,
            Output::Files { first, .. } => first + k,
        }
    }

    /// Writes the movie's frame `k` to its file, the bytes zbuf's `-o` would write.
    pub fn save(&self, k: u64, frame: &Frame) -> Result<()> {
        let (Some(path), Output::Files { png, .. }) = (self.path(k), self) else {
            return Ok(());
        };
        let fail = |e: String| Error::io(format!("cannot write {}: {e}", path.display()));
        let bytes = if *png {
            let mut bytes = std::io::Cursor::new(Vec::new());
            image::write_buffer_with_format(
                &mut bytes,
                &frame.rgb,
                frame.width,
                frame.height,
                image::ExtendedColorType::Rgb8,
                image::ImageFormat::Png,
            )
            .map_err(|e| fail(e.to_string()))?;
            bytes.into_inner()
        } else {
            frame.ppm()
        };
        Ok(stagecli::whole::write_whole(&path, &bytes)?)
    }
}

/// Whether the file of a frame is one whole frame: a PNG that decodes, or a PPM of one
/// frame and nothing after it; its width and height, or why not.
pub fn verify_frame(path: &std::path::Path, png: bool) -> std::result::Result<(u32, u32), String> {
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => "missing".to_string(),
        _ => stagecli::error::io_message(&e),
    })?;
    if !meta.is_file() {
        return Err("not a file".to_string());
    }
    if png {
        let image = image::ImageReader::open(path)
            .map_err(|e| stagecli::error::io_message(&e))?
            .with_guessed_format()
            .map_err(|e| stagecli::error::io_message(&e))?;
        if image.format() != Some(image::ImageFormat::Png) {
            return Err("not a PNG".to_string());
        }
        let decoded = image.decode().map_err(|e| format!("cut or damaged: {e}"))?;
        return Ok((decoded.width(), decoded.height()));
    }
    let file = std::fs::File::open(path).map_err(|e| stagecli::error::io_message(&e))?;
    let mut input = std::io::BufReader::new(file);
    match next_frame(&mut input) {
        Ok(Some(f)) => match next_frame(&mut input) {
            Ok(None) => Ok((f.width, f.height)),
            _ => Err("more than one frame".to_string()),
        },
        Ok(None) => Err("empty".to_string()),
        Err(why) => Err(format!("cut or damaged: {why}")),
    }
}

/// The frames of a chunk, for messages: `frames 8 to 11`, `frame 3`.
pub fn frames_text(first: u64, frames: u64) -> String {
    if frames == 1 {
        format!("frame {first}")
    } else {
        format!("frames {first} to {}", first + frames - 1)
    }
}

/// A chunk's place in the movie.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ChunkInfo {
    pub first: u64,
    pub frames: u64,
}

/// Reads what a try of `chunk` sent back: its frames, or why they are not the chunk's
/// (nothing, too few, too many, or what is not a frame) in the words of a host's failure.
pub fn check_frames<R: BufRead>(
    input: &mut R,
    chunk: ChunkInfo,
) -> std::result::Result<Vec<Frame>, String> {
    let what = frames_text(chunk.first, chunk.frames);
    let mut frames = Vec::new();
    loop {
        match next_frame(input) {
            Ok(Some(f)) => frames.push(f),
            Ok(None) => break,
            Err(why) => {
                return Err(format!(
                    "sent back {} of its {what}, then garbage (not a frame: {why})",
                    frames.len()
                ))
            }
        }
    }
    let got = frames.len() as u64;
    match got {
        0 if chunk.frames > 0 => Err(format!("sent back nothing for its {what}")),
        n if n < chunk.frames => Err(format!("sent back {n} of its {what}")),
        n if n > chunk.frames => Err(format!("sent back {n} frames for its {what}")),
        _ => Ok(frames),
    }
}

/// What a try that ended with the shell status `status` (ssh's: the far command's, 255
/// for ssh's own failure, 128 + N when killed by signal N) and `stderr` means
/// ([`stagecli::remote::classify`], the command there being render.sh's).
pub fn classify(status: i32, stderr: &str) -> Option<Failure> {
    if (129..=128 + 64).contains(&status) {
        stagecli::remote::classify(None, Some(status - 128), stderr, "the command")
    } else {
        stagecli::remote::classify(Some(status), None, stderr, "the command")
    }
}

/// One try of a chunk that failed: the host and what it said.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Try {
    pub host: String,
    pub failure: Failure,
}

/// The one line for a chunk that failed on every try: the host(s), the chunk, the tries
/// and the last try's own words; its status is the last try's.
pub fn every_try_failed(chunk: ChunkInfo, tries: &[Try]) -> Failure {
    let what = frames_text(chunk.first, chunk.frames);
    let Some(last) = tries.last() else {
        return Failure {
            message: format!("{what}: not rendered (no try of it ended)"),
            status: 3,
        };
    };
    let mut hosts: Vec<&str> = Vec::new();
    for t in tries {
        if !hosts.contains(&t.host.as_str()) {
            hosts.push(&t.host);
        }
    }
    let n = tries.len();
    let times = if n == 1 {
        "1 try".to_string()
    } else {
        format!("{n} tries")
    };
    let message = if hosts.len() == 1 {
        format!(
            "host {}: {what}, {times}: {}",
            hosts[0], last.failure.message
        )
    } else {
        format!(
            "hosts {}: {what}, {times}, the last on {}: {}",
            hosts.join(", "),
            last.host,
            last.failure.message
        )
    };
    Failure {
        message,
        status: last.failure.status,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_came_back_is_checked_frame_by_frame() {
        let frame = |r: u8| [b"P6\n1 1\n255\n".as_slice(), &[r, 0, 0]].concat();
        let chunk = ChunkInfo {
            first: 8,
            frames: 2,
        };
        let two = [frame(1), frame(2)].concat();
        let got = check_frames(&mut &two[..], chunk).unwrap();
        assert_eq!(got.iter().map(|f| f.rgb[0]).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(
            check_frames(&mut &b""[..], chunk).unwrap_err(),
            "sent back nothing for its frames 8 to 9"
        );
        assert_eq!(
            check_frames(&mut &frame(1)[..], chunk).unwrap_err(),
            "sent back 1 of its frames 8 to 9"
        );
        let three = [frame(1), frame(2), frame(3)].concat();
        assert_eq!(
            check_frames(&mut &three[..], chunk).unwrap_err(),
            "sent back 3 frames for its frames 8 to 9"
        );
        let cut = [frame(1), b"P6\n1 1\n255\n\x01".to_vec()].concat();
        assert!(check_frames(&mut &cut[..], chunk)
            .unwrap_err()
            .starts_with("sent back 1 of its frames 8 to 9, then garbage (not a frame: "));
    }

    #[test]
    fn a_chunk_that_failed_every_try_is_one_line() {
        let chunk = ChunkInfo {
            first: 16,
            frames: 8,
        };
        let t = |host: &str, message: &str, status| Try {
            host: host.to_string(),
            failure: Failure {
                message: message.to_string(),
                status,
            },
        };
        let one = every_try_failed(chunk, &[t("bad", "ssh: x", 3), t("bad", "ssh: y", 3)]);
        assert_eq!(
            (one.message.as_str(), one.status),
            ("host bad: frames 16 to 23, 2 tries: ssh: y", 3)
        );
        let two = every_try_failed(
            chunk,
            &[
                t("a", "ssh: x", 3),
                t("b", "viewxf: stdin: line 3: not a number", 1),
            ],
        );
        assert_eq!(
            (two.message.as_str(), two.status),
            (
                "hosts a, b: frames 16 to 23, 2 tries, the last on b: viewxf: stdin: line 3: \
                 not a number",
                1
            )
        );
    }

    #[test]
    fn how_a_try_ended_is_told_in_one_line() {
        assert_eq!(classify(0, "render.sh: zbuf: 3 frames\n"), None);
        let ssh = classify(255, "ssh: connect to host x port 22: Connection refused\n").unwrap();
        assert_eq!(
            (ssh.message.as_str(), ssh.status),
            ("ssh: connect to host x port 22: Connection refused", 3)
        );
        let far = classify(1, "render.sh: viewxf: stdin: line 3: not a number\n").unwrap();
        assert_eq!(
            (far.message.as_str(), far.status),
            ("viewxf: stdin: line 3: not a number", 1)
        );
        let killed = classify(128 + libc::SIGKILL, "").unwrap();
        assert_eq!(
            (killed.message.as_str(), killed.status),
            ("ssh was killed by SIGKILL", 3)
        );
    }
}
