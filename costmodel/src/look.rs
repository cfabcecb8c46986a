//! A cheap look at a scene: the environment parameters of thesis chapter 5.2 that the cost
//! model needs — polygons and vertices before clipping (P_t), after it (P_r), the screen
//! (X_res × Y_res), the depth complexity Dc (projected area over screen area) and the
//! number of frames. The world-space scene is counted as it is read; the screen-space
//! figures come from the geometry the first stages of a render are built on (proto's
//! eye frame, Sutherland–Hodgman clipping and device mapping), called in this process.

use crate::error::{Context, Error, Result};
use proto::camera::Device;
use proto::geometry::{clip_against, PyramidPlane};
use proto::{Polygon, Reader, Token, Vertex};
use stagecli::Counted;
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

/// The environment parameters of one scene (totals over all its frames).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Environment {
    /// Frames in the scene.
    pub frames: u64,
    /// P_t: polygons in the world-space scene (all frames).
    pub polygons: u64,
    /// Their vertices (E·P_t).
    pub vertices: u64,
    /// P_r: polygons after clipping (all frames).
    pub relevant: u64,
    /// Their vertices.
    pub relevant_vertices: u64,
    /// Σ projected area of the clipped polygons, pixels (all frames): X·Y·Dc per frame.
    pub area: f64,
    /// X_res, Y_res.
    pub width: u32,
    pub height: u32,
    /// Whether the scene is in the text form.
    pub text: bool,
}

impl Environment {
    /// X_res × Y_res.
    pub fn screen(&self) -> f64 {
        self.width as f64 * self.height as f64
    }

    /// Dc: the average number of polygons covering a pixel (area over screen, per frame).
    pub fn depth_complexity(&self) -> f64 {
        if self.frames == 0 || self.screen() == 0.0 {
            0.0
        } else {
            self.area / (self.screen() * self.frames as f64)
        }
    }

    /// Σ H over the relevant polygons, the scan lines (spans) they cover, by the thesis's
    /// closed form (5.2): W = H = √(X·Y·Dc / P_r), so P_r·H = √(P_r·X·Y·Dc) a frame.
    pub fn spans(&self) -> f64 {
        if self.frames == 0 {
            return 0.0;
        }
        let f = self.frames as f64;
        f * ((self.relevant as f64 / f) * self.screen() * self.depth_complexity()).sqrt()
    }
}

/// Counts polygons and vertices of a world-space stream, and its frames.
pub fn count_world<R: Read>(input: R) -> Result<(u64, u64, u64)> {
    let mut reader = Reader::<Token, _>::new(input)?;
    let (mut frames, mut polygons, mut vertices) = (1u64, 0u64, 0u64);
    let mut record = Token::default();
    while reader.next_into(&mut record)? {
        match &record {
            Token::Polygon(p) => {
                polygons += 1;
                vertices += p.vertices.len() as u64;
            }
            Token::NextFrame => frames += 1,
            Token::Skip(_) | Token::End => {}
        }
    }
    Ok((frames, polygons, vertices))
}

/// The area of a screen-space polygon, pixels (the shoelace formula; either winding).
pub fn area(p: &Polygon) -> f64 {
    area_of(&p.vertices)
}

/// The area of the screen-space outline `vertices` (X, Y), pixels.
fn area_of(vertices: &[Vertex]) -> f64 {
    let n = vertices.len();
    let mut twice = 0.0;
    for i in 0..n {
        let a = vertices[i];
        let b = vertices[(i + 1) % n];
        twice += a.x * b.y - b.x * a.y;
    }
    (twice / 2.0).abs()
}

/// Counts a screen-space stream's polygons in view (those the clipper left vertices
/// of): (polygons, vertices, Σ area).
pub fn count_screen<R: Read>(input: R) -> Result<(u64, u64, f64)> {
    let mut reader = Reader::<Token, _>::new(input)?;
    let (mut polygons, mut vertices, mut sum) = (0u64, 0u64, 0.0);
    let mut record = Token::default();
    while reader.next_into(&mut record)? {
        if let Token::Polygon(p) = &record {
            if p.vertices.is_empty() {
                continue;
            }
            polygons += 1;
            vertices += p.vertices.len() as u64;
            sum += area(p);
        }
    }
    Ok((polygons, vertices, sum))
}

/// Opens a scene, an I/O error naming it as the stages do: `cannot open PATH: reason`.
pub fn open(scene: &Path) -> Result<std::fs::File> {
    std::fs::File::open(scene).with_context(|| format!("cannot open {}", scene.display()))
}

/// Whether the file starts like a text-form stream (else binary). Reading its first
/// bytes is also the check that it can be read at all: a folder opens, and fails only
/// here, as `PATH: Is a directory` (zspec's words for the same).
pub fn is_text(scene: &Path) -> Result<bool> {
    let mut first = [0u8; 8];
    let n = open(scene)?.read(&mut first).context(scene.display())?;
    Ok(n > 0 && first[..n] != proto::header::BINARY_MAGIC[..n])
}

/// How much of a stream `render --depth auto` keeps in memory to plan from (a scene on
/// stdin or in a pipe, [`look_sample`]): 512 KiB, about 2,000 quads of the text form. The
/// depth a scene needs depends on its polygons' sizes and the screen, not on each
/// polygon, so the first stretch of the scene is a fair sample of a scene whose polygons
/// are not ordered by size.
pub const SAMPLE_BYTES: u64 = 512 * 1024;

/// How much of a scene file `render --depth auto` and `plan depth` look at: 128 KiB,
/// about 500 quads of the text form, two of the reader's 64 KiB blocks. The look is
/// work the render waits for (on one core, all of it), and a quarter of the sample
/// costs a quarter: 0.6 ms against 2.2 on the bench's fill-heavy scene (10,000 quads,
/// Dc 10, 1920x1080), whose estimates it leaves within 4% (P_r 5,278 and Dc 10.4 against
/// the whole file's 5,076 and 10.0; 512 KiB: 5,157 and 10.1), and the depth chosen the
/// same.
pub const LOOK_BYTES: u64 = 128 * 1024;

/// Looks at a scene for a `width`×`height` screen: the world-space counts as read, and
/// the screen-space ones as `viewxf | clipplane ×6 | persp` computes them, through the
/// same proto geometry, in this process. `camera` are
/// viewxf's options as render.sh was given them (`--eye X,Y,Z` …).
///
/// With `sample` (bytes), reading stops at the first polygon past that many bytes of
/// the scene and the counts are scaled up to the whole file by its size: polygons,
/// vertices and area by the file's size over the sample's bytes a polygon, frames by the
/// polygons per frame seen (the polygons before the first NEXT.FRAME), when a NEXT.FRAME
/// was seen. Without, the
/// whole scene is read and the counts are exact.
pub fn look(
    scene: &Path,
    width: u32,
    height: u32,
    camera: &[String],
    sample: Option<u64>,
) -> Result<Environment> {
    look_with(scene, width, height, camera, sample, false, &mut |_, _| {})
}

/// [`look`], handing `each` every polygon it reads, as read (world space), with the
/// stream's attributes: a second scan of the scene (its colours, for `--max-error`) made
/// in the same pass, on the same records, rather than by parsing the file again.
pub fn look_each(
    scene: &Path,
    width: u32,
    height: u32,
    camera: &[String],
    sample: Option<u64>,
    each: &mut dyn FnMut(&proto::Attributes, &proto::Polygon),
) -> Result<Environment> {
    look_with(scene, width, height, camera, sample, false, each)
}

/// How many times its sample a stream on stdin is planned as, when it did not end within
/// the sample: 64 (32 MiB for a full sample). Its length is unknown; a stream longer than
/// the sample is planned as a long one, whose start-up costs are small against its work,
/// rather than as the sample alone, which would always favour the shallow trees' cheaper
/// start.
pub const STREAM_SCALE: f64 = 64.0;

/// Looks at the sample of a stream ([`crate::sample`]) kept in `sample`: when `whole`,
/// the stream is the sample and the look is exact; otherwise the sample was cut where it
/// was (in the middle of a record, perhaps: what is cut off is not counted), and the
/// counts are scaled to a stream [`STREAM_SCALE`] times as long, its frames the
/// sample's polygons a frame (when a NEXT.FRAME was seen; else one frame).
pub fn look_stream(
    sample: &Path,
    width: u32,
    height: u32,
    camera: &[String],
    whole: bool,
) -> Result<Environment> {
    if whole {
        return look(sample, width, height, camera, None);
    }
    let e = look_with(sample, width, height, camera, None, true, &mut |_, _| {})?;
    Ok(scale_stream(e))
}

/// [`look_stream`] of a sample kept in memory (`render --depth auto`'s, of a scene on
/// stdin or in a pipe): the same counts, from the bytes rather than a file.
pub fn look_sample(
    sample: &[u8],
    width: u32,
    height: u32,
    camera: &[String],
    whole: bool,
) -> Result<Environment> {
    let text = !sample.is_empty()
        && sample[..sample.len().min(8)] != proto::header::BINARY_MAGIC[..sample.len().min(8)];
    let e = look_reader(
        sample,
        sample.len() as u64,
        text,
        "the scene's sample",
        (width, height),
        camera,
        None,
        !whole,
        &mut |_, _| {},
    )?;
    Ok(if whole { e } else { scale_stream(e) })
}

/// The counts of a sample cut from a stream, scaled to a stream [`STREAM_SCALE`] times as
/// long, its frames the sample's polygons a frame (when a NEXT.FRAME was seen).
fn scale_stream(mut e: Environment) -> Environment {
    let frames_seen = e.frames;
    let up = |n: u64| (n as f64 * STREAM_SCALE).round() as u64;
    e.polygons = up(e.polygons);
    e.vertices = up(e.vertices);
    e.relevant = up(e.relevant);
    e.relevant_vertices = up(e.relevant_vertices);
    e.area *= STREAM_SCALE;
    if frames_seen > 1 {
        e.frames = up(frames_seen);
    }
    e
}

fn look_with(
    scene: &Path,
    width: u32,
    height: u32,
    camera: &[String],
    sample: Option<u64>,
    cut: bool,
    each: &mut dyn FnMut(&proto::Attributes, &proto::Polygon),
) -> Result<Environment> {
    let text = is_text(scene)?;
    let file = open(scene)?;
    let total = file.metadata().map(|m| m.len()).unwrap_or(0);
    let name = scene.display().to_string();
    let mut e = look_reader(
        file,
        total,
        text,
        &name,
        (width, height),
        camera,
        sample,
        cut,
        each,
    )?;
    // A sample that ended inside the first frame saw no NEXT.FRAME, and its counts, scaled
    // to the whole file, read as one frame: a movie of 100 frames of 1,024 quads at
    // 500x500 (265 KB of text a frame, the sample 128 KiB) looked like one frame of
    // 100,000 polygons at Dc 100, which a deeper tree pays for, where each of its frames
    // is Dc 1 and the tree's per-frame costs (a leaf's finished region, the merger's
    // runs) are not repaid. Where the first frame's end is found a little further on,
    // the frames are the file's size over the first frame's.
    if let Some(s) = sample {
        if text && e.frames == 1 && total > s {
            if let Some(first) = first_frame_end(scene, s + FRAME_SEARCH)? {
                e.frames = ((total as f64 / first as f64).round() as u64).max(1);
            }
        }
    }
    Ok(e)
}

/// How far past the sample [`look`] searches a text scene for the end of its first
/// frame: 1 MiB, a frame of some 4,000 quads. A frame larger than that is work enough
/// that the tree's per-frame costs hardly count, and the scene is judged as one frame.
/// The search is a byte search, not a parse: on a one-frame scene, which it reads to
/// the limit in vain, it cost `plan depth` about 0.3 ms (the 26 MB scene (b) of
/// bench llvmpipe, 1.8–2.0 ms of CPU before, 2.2–2.4 after); on a movie it stops at
/// the first frame's end.
pub const FRAME_SEARCH: u64 = 1 << 20;

/// The bytes of a text scene's first frame up to and including its first `NEXT.FRAME`
/// (the keyword, wherever it stands), if one is among the first `limit` bytes.
fn first_frame_end(scene: &Path, limit: u64) -> Result<Option<u64>> {
    const WORD: &[u8] = b"NEXT.FRAME";
    let mut file = open(scene)?.take(limit);
    let finder = memchr::memmem::Finder::new(WORD);
    // A block and the keyword's length less one before it, kept from the block before,
    // so that a keyword across two blocks is found.
    let keep = WORD.len() - 1;
    let mut buf = vec![0u8; keep + (64 << 10)];
    let (mut have, mut offset) = (0usize, 0u64); // bytes in buf; the file offset of buf[0]
    loop {
        let n = match file.read(&mut buf[have..]) {
            Ok(0) => return Ok(None),
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e).with_context(|| format!("reading {}", scene.display())),
        };
        have += n;
        if let Some(at) = finder.find(&buf[..have]) {
            return Ok(Some(offset + (at + WORD.len()) as u64));
        }
        let tail = have.min(keep);
        buf.copy_within(have - tail..have, 0);
        offset += (have - tail) as u64;
        have = tail;
    }
}

/// The look itself, of `input` (`total` bytes, `text` or binary; `name` for messages),
/// handing `each` every polygon as read.
#[allow(clippy::too_many_arguments)]
fn look_reader<R: Read>(
    input: R,
    total: u64,
    text: bool,
    name: &str,
    (width, height): (u32, u32),
    camera: &[String],
    sample: Option<u64>,
    cut: bool,
    each: &mut dyn FnMut(&proto::Attributes, &proto::Polygon),
) -> Result<Environment> {
    #[derive(clap::Parser)]
    struct Camera {
        #[command(flatten)]
        view: stagecli::ViewArgs,
    }
    let size = format!("{width}x{height}");
    let args = ["viewxf", "--size", &size]
        .into_iter()
        .map(String::from)
        .chain(camera.iter().cloned());
    let cam = <Camera as clap::Parser>::try_parse_from(args)
        .map_err(|e| Error::Usage(format!("camera options {camera:?}: {e}")))?;
    // A camera or view volume that cannot be looked through (`--hither 0`) is a usage
    // error of viewxf's words, so chart exits 2 for it as viewxf does.
    let (frame, view) = cam.view.resolve()?;
    // The pyramid's six planes and the device mapping, as clipplane and persp take them
    // from the stream's view volume.
    let planes = PyramidPlane::ALL.map(|p| p.plane(&view));
    let device = Device {
        width,
        height,
        view,
    };
    let (mut eye, mut clipped) = (Vec::new(), Vec::new());

    let bytes = Arc::new(AtomicU64::new(0));
    // With a sample, nothing past it is read: a polygon that runs on past the sample (up
    // to a record's 64 MiB) ends the look where the sample does, as a cut one.
    let mut reader = Reader::<Token, _>::new(std::io::BufReader::with_capacity(
        1 << 16,
        Counted {
            inner: input.take(sample.unwrap_or(u64::MAX)),
            bytes: Arc::clone(&bytes),
        },
    ))
    .with_context(|| format!("reading {name}"))?;
    let mut e = Environment {
        frames: 1,
        width,
        height,
        text,
        ..Default::default()
    };
    let mut per_frame = None; // polygons before the first NEXT.FRAME
    let (mut read_so_far, mut anchor) = (0u64, (0u64, 0u64)); // bytes; (polygons, their bytes)
    let mut whole = true;
    let mut record = Token::default();
    loop {
        match reader.next_into(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            // A sample cut from a stream ends where it was cut: in a record, perhaps.
            Err(_) if cut && e.polygons > 0 => break,
            Err(_) if sample.is_some_and(|s| bytes.load(Relaxed) >= s) && e.polygons > 0 => {
                whole = false;
                break;
            }
            Err(err) => return Err(Error::from(err).context(format!("reading {name}"))),
        }
        match &mut record {
            Token::Polygon(p) => {
                each(&reader.header().attributes, p);
                e.polygons += 1;
                e.vertices += p.vertices.len() as u64;
                // The reader refills its buffer a block at a time: at a refill, the
                // polygons before this one took the bytes read until then.
                if bytes.load(Relaxed) != read_so_far {
                    if read_so_far > 0 {
                        anchor = (e.polygons - 1, read_so_far);
                    }
                    read_so_far = bytes.load(Relaxed);
                }
                // viewxf, the six clipplane stages, then persp's device mapping.
                eye.clear();
                eye.extend(p.vertices.iter().map(|v| frame.to_eye(v.truncate())));
                for plane in &planes {
                    clip_against(&eye, plane, &mut clipped);
                    std::mem::swap(&mut eye, &mut clipped);
                }
                if !eye.is_empty() {
                    e.relevant += 1;
                    e.relevant_vertices += eye.len() as u64;
                    for v in &mut eye {
                        let (x, y) = device.project(*v);
                        *v = Vertex::new(x, y, 0.0, 1.0);
                    }
                    e.area += area_of(&eye);
                }
                if sample.is_some_and(|s| bytes.load(Relaxed) > s) {
                    whole = false;
                    break;
                }
            }
            Token::NextFrame => {
                per_frame.get_or_insert(e.polygons);
                e.frames += 1;
            }
            Token::Skip(_) | Token::End => {}
        }
    }
    if !whole && total > 0 && anchor.0 > 0 && e.polygons > 0 {
        // Polygons in the whole file at the sample's bytes a polygon, over those seen.
        let scale = total as f64 * anchor.0 as f64 / anchor.1 as f64 / e.polygons as f64;
        let up = |n: u64| (n as f64 * scale).round() as u64;
        e.polygons = up(e.polygons);
        e.vertices = up(e.vertices);
        e.relevant = up(e.relevant);
        e.relevant_vertices = up(e.relevant_vertices);
        e.area *= scale;
        if let Some(n) = per_frame.filter(|n| *n > 0) {
            e.frames = (e.polygons as f64 / n as f64).round().max(1.0) as u64;
        }
    }
    Ok(e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proto::DVec4;

    #[test]
    fn area_of_a_square_either_winding() {
        let v = |x, y| DVec4::new(x, y, 0.5, 1.0);
        let mut p = Polygon::new(
            Default::default(),
            vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 10.0), v(0.0, 10.0)],
        );
        assert_eq!(area(&p), 100.0);
        p.vertices.reverse();
        assert_eq!(area(&p), 100.0);
    }

    #[test]
    fn closed_form_spans() {
        // 512 polygons over 500×500 at Dc 1: H = √(250000/512) ≈ 22 (thesis 5.2).
        let e = Environment {
            frames: 1,
            relevant: 512,
            area: 250_000.0,
            width: 500,
            height: 500,
            ..Default::default()
        };
        assert!((e.depth_complexity() - 1.0).abs() < 1e-12);
        let h = e.spans() / 512.0;
        assert!((h - 22.097).abs() < 0.01, "{h}");
    }

    /// A text scene of `frames` frames of `n` small squares, a third of them out of view.
    fn squares(frames: usize, n: usize) -> tempfile::NamedTempFile {
        use std::io::Write;
        let mut f = tempfile::NamedTempFile::new().unwrap();
        writeln!(f, "polypipe 1 world").unwrap();
        for frame in 0..frames {
            if frame > 0 {
                writeln!(f, "NEXT.FRAME").unwrap();
            }
            for i in 0..n {
                let (x, y) = (
                    (i % 60) as f64 * 0.5 - 15.0,
                    (i / 60 % 40) as f64 * 0.5 - 10.0,
                );
                if i > 0 {
                    writeln!(f, "NEXT.POLYGON").unwrap();
                }
                writeln!(f, "colour 1 2 3").unwrap();
                for (dx, dy) in [(0.0, 0.0), (0.4, 0.0), (0.4, 0.4), (0.0, 0.4)] {
                    writeln!(f, "{:.15} {:.15} 0.123456789012345", x + dx, y + dy).unwrap();
                }
            }
        }
        writeln!(f, "END").unwrap();
        f
    }

    #[test]
    fn a_sample_judges_the_whole() {
        // 8 frames of 1,000 squares (about 2 MB): the sample reads about a quarter.
        let f = squares(8, 1000);
        let whole = look(f.path(), 500, 500, &[], None).unwrap();
        assert_eq!(
            (whole.frames, whole.polygons, whole.vertices),
            (8, 8_000, 32_000)
        );
        assert!(whole.relevant > 0 && whole.relevant < whole.polygons);
        let part = look(f.path(), 500, 500, &[], Some(SAMPLE_BYTES)).unwrap();
        let near = |a: f64, b: f64| (a / b - 1.0).abs() < 0.02;
        assert!(near(part.polygons as f64, 8_000.0), "{part:?}");
        assert!(
            near(part.relevant as f64, whole.relevant as f64),
            "{part:?}"
        );
        assert!(near(part.area, whole.area), "{part:?} {whole:?}");
        assert_eq!(part.frames, 8);
        // A scene smaller than the sample is read whole.
        let small = squares(2, 100);
        assert_eq!(
            look(small.path(), 500, 500, &[], Some(SAMPLE_BYTES)).unwrap(),
            look(small.path(), 500, 500, &[], None).unwrap()
        );
    }

    #[test]
    fn a_movie_whose_first_frame_outruns_the_sample_is_still_a_movie() {
        // 4 frames of 1,000 squares, about 250 KB each: the look's 128 KiB ends inside
        // the first frame, whose end is found past it.
        let f = squares(4, 1000);
        let len = f.as_file().metadata().unwrap().len();
        assert!(
            len / 4 > LOOK_BYTES && len < LOOK_BYTES + FRAME_SEARCH,
            "{len}"
        );
        let whole = look(f.path(), 500, 500, &[], None).unwrap();
        let part = look(f.path(), 500, 500, &[], Some(LOOK_BYTES)).unwrap();
        assert_eq!((whole.frames, part.frames), (4, 4));
        let near = |a: f64, b: f64| (a / b - 1.0).abs() < 0.02;
        assert!(
            near(part.depth_complexity(), whole.depth_complexity()),
            "{part:?} {whole:?}"
        );
        // One frame larger than the search is judged one frame, as it is.
        let still = squares(1, 6000);
        assert!(still.as_file().metadata().unwrap().len() > LOOK_BYTES + FRAME_SEARCH);
        assert_eq!(
            look(still.path(), 500, 500, &[], Some(LOOK_BYTES))
                .unwrap()
                .frames,
            1
        );
    }

    #[test]
    fn the_frame_search_finds_a_keyword_across_two_blocks() {
        use std::io::Write;
        // The keyword straddles the end of the search's first read.
        let mut f = tempfile::NamedTempFile::new().unwrap();
        let pad = (64 << 10) + 9 - 4; // the first read: 9 bytes kept + 64 KiB
        f.write_all(&vec![b' '; pad]).unwrap();
        f.write_all(b"NEXT.FRAME\nEND\n").unwrap();
        assert_eq!(
            first_frame_end(f.path(), 1 << 20).unwrap(),
            Some(pad as u64 + 10)
        );
        assert_eq!(first_frame_end(f.path(), pad as u64 + 9).unwrap(), None);
    }

    #[test]
    fn the_camera_moves_what_is_in_view() {
        let f = squares(1, 1600);
        let front = look(f.path(), 500, 500, &[], None).unwrap();
        let away = look(
            f.path(),
            500,
            500,
            &[
                "--eye".into(),
                "0,0,-20".into(),
                "--at".into(),
                "0,0,-40".into(),
            ],
            None,
        )
        .unwrap();
        assert!(front.relevant > 0);
        assert_eq!(away.relevant, 0);
        assert!(look(
            f.path(),
            500,
            500,
            &["--eye".into(), "nonsense".into()],
            None
        )
        .is_err());
    }

    #[test]
    fn counts_a_text_scene() {
        let scene = "polypipe 1 world\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\nNEXT.FRAME\ncolour 1 2 3\n0 0 0\n1 0 0\n0 1 0\n1 1 0\nEND\n";
        let (frames, polygons, vertices) = count_world(scene.as_bytes()).unwrap();
        assert_eq!((frames, polygons, vertices), (2, 2, 7));
    }
}
