//! # zbuf: fragments → frames (the thesis's BUFFER and PAR.BUFF, chapters 4.2.3 and 6.3.3)
//!
//! The BUFFER process keeps a Z-buffer and an F-buffer (frame buffer) and, for each pixel
//! it receives, keeps the colour of the nearest polygon. PAR.BUFF does the same for many
//! scan converters at once and shows the frame once every one of them has sent its
//! NEXT.FRAME.
//!
//! Visibility (docs/DESIGN.md, "The Z specification"; thesis 2.3) is the tie rule of
//! [`proto::depth`]: folding the polygons at a pixel in stream order, a later one takes
//! the pixel only when nearer by more than 2⁻³⁰ of the holder's depth. Fragments of one
//! input come in stream order, but inputs are read concurrently, so each pixel keeps,
//! beside its depth, the index of the polygon that holds it, and a fragment of a polygon
//! earlier than the holder is judged from the other side ([`wins`]). Polygon k is the
//! same polygon on every branch of a splitter tree, and the tree's leaves cover disjoint
//! pixels, so every pixel's polygons arrive through one input, in stream order: the
//! result does not depend on the order the inputs' fragments arrive in, and the frame is
//! deterministic. (Inputs that overlap, which the tree never makes, get the fold's answer
//! for any two polygons at a pixel.)
//!
//! The concurrent reading of many inputs lives in [`par_buff`].

pub mod par_buff;

use proto::{ppm, Colour};
use stagecli::Error;
use std::io::{self, Write};
use std::path::PathBuf;

/// The Z-buffer, the polygon index per pixel and the F-buffer of one screen.
///
/// The depth and polygon buffers are needed only for depth-tested fragments (spans and
/// pixels, the thesis's PAR.BUFF). When every leaf of the splitter tree resolves its own
/// region and sends finished runs, zbuf only places them: the two buffers (12 of the
/// 15 bytes a pixel) are then not made at all, nor cleared frame by frame. They are made
/// at the first depth-tested fragment, and the runs painted before it in the frame are
/// marked in them then, so a frame that mixes the two comes out as if they had been
/// there from the start.
///
/// The depth and polygon buffers are laid out in square tiles of [`TILE`]×[`TILE`]
/// pixels, row-major inside each tile: a polygon's spans, row after row, then stay within
/// a few tiles of contiguous memory instead of striding a whole screen row (15 KB at
/// 1920 wide) from one row to the next, which at full HD missed the cache and the TLB on
/// every row and made the depth test three times slower. The F-buffer stays row-major,
/// the PPM's raster.
#[derive(Clone, Debug)]
pub struct FrameBuffer {
    width: u32,
    height: u32,
    background: Colour,
    /// Tiles across the screen.
    tiles_x: u32,
    /// Depth per pixel, tiled ([`FrameBuffer::tiled`]); `+∞` (MAX.DEPTH) where nothing
    /// is drawn. Empty until the first depth-tested fragment.
    depth: Vec<f64>,
    /// Index in the frame of the polygon that drew each pixel, tiled; `u32::MAX` for none.
    polygon: Vec<u32>,
    /// The F-buffer: RGB per pixel, row-major, row 0 at the top (a P6 PPM's raster), in
    /// memory laid out for huge pages.
    colour: scan::ZeroedBuffer<Colour>,
    /// Whether `depth` and `polygon` hold this frame's state. When not, they are empty or
    /// clear, and the runs painted so far this frame are listed in `painted`.
    depth_live: bool,
    /// Runs painted this frame while the depth buffer was not live: (row, x0, x1).
    painted: Vec<(u32, u32, u32)>,
    /// Whether `painted` lists each run as it came, for [`FrameBuffer::runs`] (the
    /// default). When not, a run that goes on where the last one listed ended, on its
    /// row, lengthens that entry instead ([`FrameBuffer::list_runs`]).
    runs_listed: bool,
}

/// Polygon index of pixels no polygon has drawn: after every real polygon.
const NO_POLYGON: u32 = u32::MAX;

/// The side of a tile of the depth and polygon buffers, in pixels.
pub const TILE: u32 = 64;
const SHIFT: u32 = TILE.trailing_zeros();

/// Where pixel (x, y) is in tiled buffers `tiles_x` tiles across: tiles row-major, each
/// a TILE×TILE block, row-major inside.
#[inline]
fn tiled(tiles_x: u32, x: u32, y: u32) -> usize {
    let tile = (y >> SHIFT) as usize * tiles_x as usize + (x >> SHIFT) as usize;
    (tile << (2 * SHIFT)) + (((y & (TILE - 1)) << SHIFT) + (x & (TILE - 1))) as usize
}

/// Refuses, at the header, a screen whose frame buffer this machine cannot hold
/// (`stagecli::memory`: status 3, with what it would need).
pub fn check_memory(width: u32, height: u32) -> stagecli::Result<()> {
    stagecli::memory::check_screen(width, height, BYTES_PER_PIXEL, "depth, polygon and colour")
}

impl FrameBuffer {
    /// A cleared buffer (KH(MAX.DEPTH), KH(BACK.GROUND.COLOUR) in the thesis's CSP).
    /// The memory is asked for, not assumed: a screen too large for this machine is
    /// refused with what it would need (`a 65536x65536 frame needs 60 GiB …`) rather than
    /// aborting the process.
    pub fn new(width: u32, height: u32, background: Colour) -> Result<Self, String> {
        let n = width as usize * height as usize;
        let refuse = || {
            format!(
                "a {width}x{height} frame needs {} ({BYTES_PER_PIXEL} bytes a pixel: depth, \
                 polygon and colour), more memory than can be had",
                stagecli::error::bytes_text(n as u64 * BYTES_PER_PIXEL)
            )
        };
        // The depth and polygon buffers are made at the frame's first depth-tested
        // fragment (a merger that only places runs never needs them), but their memory is
        // asked for now, so that a screen too large is refused before any input is read.
        let tiles_x = width.div_ceil(TILE);
        let tiled_n = (tiles_x as usize * height.div_ceil(TILE) as usize) << (2 * SHIFT);
        let mut depth: Vec<f64> = Vec::new();
        let mut polygon: Vec<u32> = Vec::new();
        depth.try_reserve_exact(tiled_n).map_err(|_| refuse())?;
        polygon.try_reserve_exact(tiled_n).map_err(|_| refuse())?;
        scan::advise_huge_pages(&depth);
        scan::advise_huge_pages(&polygon);
        Ok(FrameBuffer {
            width,
            height,
            background,
            tiles_x,
            depth,
            polygon,
            colour: filled(n, background).ok_or_else(refuse)?,
            depth_live: false,
            painted: Vec::new(),
            runs_listed: true,
        })
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Where pixel (x, y) is in the tiled buffers.
    #[inline]
    fn tiled(&self, x: u32, y: u32) -> usize {
        tiled(self.tiles_x, x, y)
    }

    /// Re-initialises the buffers for the next frame.
    pub fn clear(&mut self) {
        if self.depth_live {
            self.depth.fill(f64::INFINITY);
            self.polygon.fill(NO_POLYGON);
            self.depth_live = false;
        }
        self.painted.clear();
        fill_colour(&mut self.colour, self.background);
    }

    /// Makes the depth and polygon buffers hold this frame's state, before a depth test.
    #[inline]
    fn depth_tested(&mut self) {
        if !self.depth_live {
            self.make_depth_live();
        }
    }

    #[cold]
    fn make_depth_live(&mut self) {
        let tiles = self.tiles_x as usize * self.height.div_ceil(TILE) as usize;
        let n = tiles << (2 * SHIFT);
        if self.depth.len() != n {
            // Within the capacity reserved by `new`: no allocation here.
            self.depth.resize(n, f64::INFINITY);
            self.polygon.resize(n, NO_POLYGON);
        }
        self.depth_live = true;
        for (y, x0, x1) in std::mem::take(&mut self.painted) {
            self.mark_painted(y, x0, x1);
        }
    }

    /// Marks pixels `x0..x1` of row `y` as finished in the depth buffer, tile by tile:
    /// no fragment can replace them.
    fn mark_painted(&mut self, y: u32, x0: u32, x1: u32) {
        let mut x = x0;
        while x < x1 {
            let end = x1.min(((x >> SHIFT) + 1) << SHIFT);
            let (at, n) = (self.tiled(x, y), (end - x) as usize);
            self.depth[at..at + n].fill(f64::NEG_INFINITY);
            self.polygon[at..at + n].fill(0);
            x = end;
        }
    }

    /// Pixels `columns` = `x0..x1` of row `y` from polygon `polygon`: pixel x has depth
    /// `z_row + x·dz` ([`proto::fragment::span_depth`]). The caller (the stream reader) has
    /// checked the span lies on the screen; an out-of-range span is clipped rather than
    /// trusted.
    #[inline]
    pub fn span(
        &mut self,
        y: u32,
        columns: std::ops::Range<u32>,
        z_row: f64,
        dz: f64,
        polygon: u32,
        colour: Colour,
    ) {
        if y >= self.height {
            return;
        }
        self.depth_tested();
        let x1 = columns.end.min(self.width);
        let x0 = columns.start.min(x1);
        let row = y as usize * self.width as usize;
        let mut x = x0;
        while x < x1 {
            let end = x1.min(((x >> SHIFT) + 1) << SHIFT);
            let (at, n) = (self.tiled(x, y), (end - x) as usize);
            let frame_at = row + x as usize;
            let depth = &mut self.depth[at..at + n];
            let index = &mut self.polygon[at..at + n];
            let frame = &mut self.colour[frame_at..frame_at + n];
            for (k, ((d, i), f)) in depth
                .iter_mut()
                .zip(index.iter_mut())
                .zip(frame.iter_mut())
                .enumerate()
            {
                let z = proto::fragment::span_depth(z_row, dz, x + k as u32);
                if wins(z, polygon, *d, *i) {
                    *d = z;
                    *i = polygon;
                    *f = colour;
                }
            }
            x = end;
        }
    }

    /// [`FrameBuffer::span`] for a Gouraud-shaded polygon (docs/DESIGN.md, "Shading"):
    /// where pixel x is written it takes `row.at(x)` ([`proto::shade::ShadeRow::at`]), its
    /// shading at its centre, rounded. Beside the flat span, not in it, so
    /// that the flat loop is unchanged.
    pub fn shaded_span(
        &mut self,
        y: u32,
        columns: std::ops::Range<u32>,
        (z_row, dz): (f64, f64),
        polygon: u32,
        row: proto::shade::ShadeRow<'_>,
    ) {
        if y >= self.height {
            return;
        }
        self.depth_tested();
        let x1 = columns.end.min(self.width);
        let x0 = columns.start.min(x1);
        let first = y as usize * self.width as usize;
        for x in x0..x1 {
            let at = self.tiled(x, y);
            let z = proto::fragment::span_depth(z_row, dz, x);
            if wins(z, polygon, self.depth[at], self.polygon[at]) {
                self.depth[at] = z;
                self.polygon[at] = polygon;
                self.colour[first + x as usize] = row.at(x);
            }
        }
    }

    /// Finished pixels `columns` of row `y`, visibility already resolved by a leaf of the
    /// splitter tree: placed without a depth test, and marked so that no depth-tested
    /// fragment can replace them (the leaves' regions are disjoint, so none arrives in a
    /// well-formed tree). An out-of-range run is clipped rather than trusted.
    #[inline]
    pub fn paint(&mut self, y: u32, columns: std::ops::Range<u32>, colour: Colour) {
        if y >= self.height {
            return;
        }
        let x1 = columns.end.min(self.width);
        let x0 = columns.start.min(x1);
        if x0 == x1 {
            return;
        }
        if self.depth_live {
            self.mark_painted(y, x0, x1);
        } else {
            match self.painted.last_mut() {
                // Kept only to mark the pixels should a depth test come: a leaf's runs go
                // left to right along a row, so its whole row is one entry.
                Some((row, _, end)) if !self.runs_listed && *row == y && *end == x0 => *end = x1,
                _ => self.painted.push((y, x0, x1)),
            }
        }
        let row = y as usize * self.width as usize;
        fill_colour(
            &mut self.colour[row + x0 as usize..row + x1 as usize],
            colour,
        );
    }

    /// A leaf's region resolved in this process (a tree's leaf 0, resolved by its merger;
    /// its last frame's) placed at the frame's end, as [`FrameBuffer::paint`] places the
    /// runs of the leaves that sent theirs: its finished pixels are final. They go
    /// straight into the F-buffer ([`scan::RegionBuffer::finish_into`]), or, where the
    /// frame is passed on as its runs (`list_runs`, [`FrameBuffer::runs`]), run by run.
    /// Clears the region for another frame. The fill-heavy scene's merger at depth 1
    /// (leaf 0's polygons and leaf 1's runs) took 24.0 ms of CPU making leaf 0's half of
    /// the screen into runs and painting them again, 22.2 placing it so (one core, the
    /// least of 21 runs).
    pub fn place(&mut self, region: &mut scan::RegionBuffer, list_runs: bool) {
        if list_runs {
            let Ok(()) = region.finish_frame(|r| {
                self.paint(r.y, r.x0..r.x1, r.colour);
                Ok::<(), std::convert::Infallible>(())
            });
        } else {
            region.finish_into(&mut self.colour);
        }
    }

    /// Whether [`FrameBuffer::runs`] is wanted (the default): the runs painted are then
    /// listed one by one. A merger that only shows its frames need not: it keeps where
    /// they lie, a row's abutting runs as one entry, which is all a depth test coming
    /// after them needs. On the fill-heavy scene at depth 2 the list of 62,000 runs was
    /// 180 page faults of the merger's 700.
    pub fn list_runs(&mut self, on: bool) {
        self.runs_listed = on;
    }

    /// The frame as the runs the leaves sent, each `(row, x0, x1, colour)`, in the order
    /// they came: what a subtree's merger on another host passes on to the merger above
    /// (docs/DESIGN.md, "Stages on other hosts"). `None` once a depth-tested fragment has
    /// come this frame, spans and pixels not being finished runs, or where the runs are
    /// not listed ([`FrameBuffer::list_runs`]).
    pub fn runs(&self) -> Option<impl Iterator<Item = (u32, u32, u32, Colour)> + '_> {
        (!self.depth_live && self.runs_listed).then(|| {
            self.painted.iter().map(|&(y, x0, x1)| {
                let at = y as usize * self.width as usize + x0 as usize;
                (y, x0, x1, self.colour[at])
            })
        })
    }

    /// One pixel (the thesis's quadruplet).
    #[inline]
    pub fn pixel(&mut self, x: u32, y: u32, z: f64, polygon: u32, colour: Colour) {
        if x >= self.width || y >= self.height {
            return;
        }
        self.depth_tested();
        let k = self.tiled(x, y);
        if wins(z, polygon, self.depth[k], self.polygon[k]) {
            self.depth[k] = z;
            self.polygon[k] = polygon;
            self.colour[y as usize * self.width as usize + x as usize] = colour;
        }
    }

    /// The F-buffer's pixels, row-major, for a leaf that resolved the whole screen to
    /// paint into ([`scan::RegionBuffer::finish_into`]). Not for a frame where runs are
    /// passed on or depth-tested fragments come: what is painted here is not recorded.
    pub fn raster_mut(&mut self) -> &mut [Colour] {
        &mut self.colour
    }

    /// The F-buffer as RGB bytes, row 0 first.
    pub fn rgb(&self) -> &[u8] {
        self.colour.as_flattened()
    }

    /// The colour of pixel (x, y).
    pub fn colour_at(&self, x: u32, y: u32) -> Colour {
        self.colour[y as usize * self.width as usize + x as usize]
    }

    /// Writes the frame as a PPM: binary (P6) or plain (P3), maxval 255.
    pub fn write_ppm<W: Write>(&self, out: &mut W, form: ppm::Form) -> io::Result<()> {
        ppm::write(out, self.width, self.height, self.rgb(), form)
    }
}

/// Whether polygon `polygon` at depth `z` takes a pixel held by polygon `held_polygon` at
/// `held`: the tie rule ([`proto::depth::takes`]) when it comes later in the stream than
/// the holder, the rule seen from the other side ([`proto::depth::takes_back`]) when
/// earlier. An empty pixel is held by [`NO_POLYGON`], after every polygon, at `+∞`; a
/// finished pixel (a leaf's run) by polygon 0 at `−∞`, which nothing takes. Two
/// fragments of one polygon at one pixel (which a polygon's own spans never make) keep
/// the nearer, whichever came first.
#[inline]
pub fn wins(z: f64, polygon: u32, held: f64, held_polygon: u32) -> bool {
    if polygon != held_polygon {
        proto::depth::in_front(z, polygon > held_polygon, held)
    } else {
        z < held
    }
}

/// A frame buffer's memory per pixel: depth (f64), polygon index (u32), colour (RGB).
pub const BYTES_PER_PIXEL: u64 = 8 + 4 + 3;

/// `n` copies of `value`, or `None` when the memory cannot be had; in huge pages where
/// the kernel gives them. The memory is zeroed fresh pages, which the kernel zeroes as
/// they are first touched, so that a black background costs no writing here (a full-HD
/// frame is 6 MB).
fn filled(n: usize, value: Colour) -> Option<scan::ZeroedBuffer<Colour>> {
    let mut v = scan::ZeroedBuffer::new(n)?;
    if value != [0; 3] {
        fill_colour(&mut v, value);
    }
    Some(v)
}

/// Sets every pixel of `pixels` to `colour`: as `fill`, but 16 pixels (48 bytes) a
/// copy of one pattern where `fill` of a 3-byte element stores it pixel by pixel, and
/// one `memset` for a grey. (Assigning `[colour; 16]` to each block compiled to 48
/// one-byte stores; a copy of a pattern made once is three 16-byte ones. The merger
/// paints every run of the leaves so: on the fill-heavy scene, 83,000 runs a frame.)
#[inline]
pub fn fill_colour(pixels: &mut [Colour], colour: Colour) {
    if colour[0] == colour[1] && colour[1] == colour[2] {
        pixels.as_flattened_mut().fill(colour[0]);
        return;
    }
    // The colour repeated over 48 bytes (16 pixels, a whole number of 16-byte vector
    // stores), made of six 8-byte words: a word starting at byte 8k starts at the colour's
    // byte 8k mod 3, so the words go phase 0, 2, 1, 0, 2, 1. (Made byte by byte, `i % 3`
    // each, it cost more than painting a run of the merger's average 25 pixels.)
    let word = |a: u8, b: u8, c: u8| {
        let x = u64::from(a) | u64::from(b) << 8 | u64::from(c) << 16;
        x | x << 24 | x << 48
    };
    let [r, g, b] = colour;
    let (p0, p1, p2) = (word(r, g, b), word(g, b, r), word(b, r, g));
    let mut pattern = [0u8; 48];
    for (bytes, w) in pattern.chunks_exact_mut(8).zip([p0, p2, p1, p0, p2, p1]) {
        bytes.copy_from_slice(&w.to_le_bytes());
    }
    let bytes = pixels.as_flattened_mut();
    let n = bytes.len();
    // Whole blocks, then the tail as pieces of fixed size, each a few stores rather than
    // a call to memcpy for the odd length (that call was a third of painting the
    // merger's average run). A piece may overlap the one before it: it starts on a
    // pixel boundary (n and every piece's size are multiples of 3), so the bytes it
    // writes twice get the same values.
    if n >= 48 {
        let (blocks, _) = bytes.as_chunks_mut::<48>();
        for block in blocks {
            *block = pattern;
        }
        copy_piece::<48>(bytes, n - 48, &pattern);
    } else if n >= 24 {
        copy_piece::<24>(bytes, 0, &pattern);
        copy_piece::<24>(bytes, n - 24, &pattern);
    } else if n >= 12 {
        copy_piece::<12>(bytes, 0, &pattern);
        copy_piece::<12>(bytes, n - 12, &pattern);
    } else if n >= 6 {
        copy_piece::<6>(bytes, 0, &pattern);
        copy_piece::<6>(bytes, n - 6, &pattern);
    } else if n == 3 {
        copy_piece::<3>(bytes, 0, &pattern);
    }
}

/// The first `N` bytes of a colour's repeating pattern into `bytes[at..at + N]`, `at` a
/// multiple of 3 (a pixel's first byte).
#[inline(always)]
fn copy_piece<const N: usize>(bytes: &mut [u8], at: usize, pattern: &[u8; 48]) {
    let piece: &[u8; N] = pattern[..N].try_into().expect("N ≤ 48");
    bytes[at..at + N].copy_from_slice(piece);
}

pub use stagecli::parse_colour;

/// `-o PATTERN`: one picture file per frame ([`stagecli::FrameNames`]: `%d`, `%0Nd` the
/// frame number), in the format its extension names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FramePattern {
    names: stagecli::FrameNames,
    /// The image format, chosen by the extension.
    pub format: ImageFormat,
}

/// The image formats `-o` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Ppm,
}

impl FramePattern {
    pub fn parse(pattern: &str) -> Result<Self, String> {
        let (names, ext) = stagecli::FrameNames::parse_ending(pattern, &["png", "ppm"])?;
        let format = match ext {
            "png" => ImageFormat::Png,
            _ => ImageFormat::Ppm,
        };
        Ok(FramePattern { names, format })
    }

    /// Whether the pattern numbers its files (and so can take more than one frame).
    pub fn numbered(&self) -> bool {
        self.names.numbered()
    }

    /// The file name of frame `frame`.
    pub fn path(&self, frame: u64) -> PathBuf {
        self.names.name(frame).into()
    }

    /// Writes frame `frame` to its file, whole or not at all (a temporary renamed when
    /// complete: [`stagecli::whole`]); a .ppm file in the given form.
    pub fn save(&self, frame: u64, fb: &FrameBuffer, form: ppm::Form) -> stagecli::Result<()> {
        let path = self.path(frame);
        let mut file = stagecli::whole::WholeFile::create(&path)?;
        match self.format {
            ImageFormat::Ppm => {
                let mut out = io::BufWriter::new(&mut file);
                fb.write_ppm(&mut out, form)?;
                out.flush()?;
            }
            ImageFormat::Png => {
                let mut out = io::BufWriter::new(&mut file);
                use image::ImageEncoder;
                image::codecs::png::PngEncoder::new(&mut out)
                    .write_image(
                        fb.rgb(),
                        fb.width(),
                        fb.height(),
                        image::ExtendedColorType::Rgb8,
                    )
                    .map_err(|e| match e {
                        image::ImageError::IoError(io) => Error::from(io),
                        // The encoder refusing our own buffer: nothing the user can mend.
                        other => Error::io(other.to_string()),
                    })?;
                out.flush()?;
            }
        }
        file.commit()?;
        Ok(())
    }
}

/// The `--progress` display: frames finished and frames per second on stderr, redrawn in
/// place at most a few times a second. Only when `wanted` and stderr is a terminal: a
/// redirected or piped stderr (a log file, CI) gets nothing at all. (indicatif's stderr
/// target also hides itself off a terminal and when TERM=dumb; the explicit check makes
/// the rule ours rather than a library default.)
pub fn frame_progress(wanted: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !wanted || !io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar =
        indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::stderr());
    // The frame count is not known in advance (the stream ends with END), so a counter
    // with a rate rather than a bar with a length.
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("zbuf: {pos} frames, {fps} ({elapsed})")
    {
        bar.set_style(style.with_key(
            "fps",
            |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_fmt(format_args!("{:.1} frames/s", state.per_sec()));
            },
        ));
    }
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fill_colour_sets_every_pixel_and_no_other() {
        for colour in [[1, 2, 3], [7, 7, 7], [0, 0, 0], [255, 0, 255]] {
            for n in 0..100 {
                let mut pixels = vec![[9u8, 9, 9]; n + 2];
                fill_colour(&mut pixels[1..n + 1], colour);
                let mut want = vec![[9u8, 9, 9]; n + 2];
                want[1..n + 1].fill(colour);
                assert_eq!(pixels, want, "{n} pixels of {colour:?}");
            }
        }
    }

    #[test]
    fn progress_not_asked_for_is_hidden() {
        let bar = frame_progress(false);
        assert!(bar.is_hidden());
        bar.inc(3);
        assert_eq!(bar.position(), 3);
    }

    #[test]
    fn nearer_wins_and_ties_go_to_the_earlier_polygon() {
        let mut fb = FrameBuffer::new(4, 1, [0, 0, 0]).unwrap();
        // Polygon 1 at depth 10 over columns 0..4.
        fb.span(0, 0..4, 10.0, 0.0, 1, [1, 1, 1]);
        // Polygon 0, later in arrival but earlier in the stream, ties at depth 10: wins.
        fb.span(0, 0..2, 10.0, 0.0, 0, [2, 2, 2]);
        // Polygon 2 over columns 1..4 at depths 9, 10, 11: nearer at column 1; a tie at
        // column 2, where the earlier polygon 1 stays; farther at column 3.
        fb.span(0, 1..4, 8.0, 1.0, 2, [3, 3, 3]);
        fb.pixel(3, 0, 10.0, 5, [4, 4, 4]); // tie with polygon 1, later: loses
                                            // Nearer, but within the tie width of the holder: loses too.
        fb.pixel(3, 0, 10.0 * (1.0 - 0.5 * proto::depth::TIE), 5, [4, 4, 4]);
        fb.pixel(3, 0, 9.0, 5, [5, 5, 5]); // nearer: wins
        assert_eq!(fb.rgb(), &[2, 2, 2, 3, 3, 3, 1, 1, 1, 5, 5, 5]);
        fb.clear();
        assert_eq!(fb.rgb(), &[0; 12]);
    }

    #[test]
    fn painted_runs_are_final_whenever_the_depth_buffer_is_made() {
        // Runs only: no depth buffer at all.
        let mut fb = FrameBuffer::new(4, 2, [0, 0, 0]).unwrap();
        fb.paint(0, 1..3, [1, 1, 1]);
        assert!(fb.depth.is_empty());
        // A span after the run: made now, with the run's pixels marked; the nearest
        // possible depth still does not replace them.
        fb.span(0, 0..4, -f64::MAX, 0.0, 0, [2, 2, 2]);
        assert_eq!(
            fb.rgb(),
            [[2; 3], [1; 3], [1; 3], [2; 3], [0; 3], [0; 3], [0; 3], [0; 3]].as_flattened()
        );
        // A run after spans replaces what they drew.
        fb.paint(0, 0..1, [3, 3, 3]);
        fb.pixel(0, 0, -f64::MAX, 0, [4, 4, 4]);
        assert_eq!(fb.colour_at(0, 0), [3, 3, 3]);
        // The next frame: clear, runs listed again, the depth buffer kept but clear.
        fb.clear();
        fb.paint(1, 0..2, [5, 5, 5]);
        fb.span(1, 0..4, 7.0, 0.0, 9, [6, 6, 6]);
        fb.span(0, 0..1, 7.0, 0.0, 9, [6, 6, 6]);
        assert_eq!(
            fb.rgb(),
            [[6; 3], [0; 3], [0; 3], [0; 3], [5; 3], [5; 3], [6; 3], [6; 3]].as_flattened()
        );
        // A frame of spans, then one of runs only: the spans' depths are gone.
        fb.clear();
        fb.paint(0, 3..4, [8, 8, 8]);
        fb.clear();
        fb.span(0, 0..4, f64::MAX, 0.0, 5, [9, 9, 9]);
        assert_eq!(fb.rgb()[..12], [9; 12]);
    }

    #[test]
    fn runs_not_listed_are_kept_by_row_and_still_final() {
        let mut fb = FrameBuffer::new(6, 2, [0, 0, 0]).unwrap();
        fb.list_runs(false);
        fb.paint(0, 0..2, [1, 1, 1]);
        fb.paint(0, 2..3, [2, 2, 2]); // goes on where the last ended: one entry
        fb.paint(1, 3..6, [3, 3, 3]); // another row
        fb.paint(0, 4..5, [4, 4, 4]); // a gap before it
        fb.paint(0, 5..5, [5, 5, 5]); // empty: nothing
        assert_eq!(fb.painted, [(0, 0, 3), (1, 3, 6), (0, 4, 5)]);
        assert!(fb.runs().is_none());
        // A depth test after them: the painted pixels stay, the rest take the spans.
        fb.span(0, 0..6, -f64::MAX, 0.0, 0, [9, 9, 9]);
        fb.span(1, 0..6, -f64::MAX, 0.0, 0, [9, 9, 9]);
        assert_eq!(
            fb.rgb(),
            [
                [1; 3], [1; 3], [2; 3], [9; 3], [4; 3], [9; 3], [9; 3], [9; 3], [9; 3], [3; 3],
                [3; 3], [3; 3]
            ]
            .as_flattened()
        );
        // Listed (the default), each run is its own entry, with its colour.
        let mut fb = FrameBuffer::new(6, 1, [0, 0, 0]).unwrap();
        fb.paint(0, 0..2, [1, 1, 1]);
        fb.paint(0, 2..3, [2, 2, 2]);
        let runs: Vec<_> = fb.runs().expect("listed").collect();
        assert_eq!(runs, [(0, 0, 2, [1, 1, 1]), (0, 2, 3, [2, 2, 2])]);
    }

    proptest::proptest! {
        /// Spans and pixels over several tiles, some painted runs among them, in stream
        /// order, against each pixel's fold by the tie rule worked out directly: the
        /// tiled depth buffer puts every pixel where it belongs.
        #[test]
        fn tiles_hold_each_pixel_where_it_belongs(
            spans in proptest::collection::vec((0u32..70, 0u32..150, 1u32..150, -3i64..3, -1i64..=1), 1..40),
            paint in proptest::option::of((0u32..70, 0u32..150, 1u32..40, 1u32..4)),
            listed in proptest::bool::ANY,
        ) {
            const W: u32 = 150;
            const H: u32 = 70;
            let mut fb = FrameBuffer::new(W, H, [0, 0, 0]).unwrap();
            fb.list_runs(listed);
            let mut best: Vec<Option<(f64, u32)>> = vec![None; (W * H) as usize];
            let mut painted = vec![false; (W * H) as usize];
            let colour = |p: u32| [p as u8, 1, 2];
            if let Some((y, x0, len, pieces)) = paint {
                // The run in `pieces` abutting runs, as a leaf sends a row of colours.
                let x1 = (x0 + len).min(W);
                let cut = |k: u32| x0 + (x1 - x0) * k / pieces;
                for k in 0..pieces {
                    fb.paint(y, cut(k)..cut(k + 1), [7, 7, 7]);
                }
                for x in x0..x1 {
                    painted[(y * W + x) as usize] = true;
                }
            }
            for (p, &(y, x0, len, z0, dz)) in spans.iter().enumerate() {
                let (p, x1) = (p as u32, (x0 + len).min(W));
                let (z_row, dz) = (z0 as f64, dz as f64);
                if p % 5 == 4 {
                    fb.pixel(x0, y, proto::fragment::span_depth(z_row, dz, x0), p, colour(p));
                } else {
                    fb.span(y, x0..x1, z_row, dz, p, colour(p));
                }
                let x1 = if p % 5 == 4 { x0 + 1 } else { x1 };
                for x in x0..x1 {
                    let z = proto::fragment::span_depth(z_row, dz, x);
                    let slot = &mut best[(y * W + x) as usize];
                    if slot.is_none_or(|b| proto::depth::takes(z, b.0)) {
                        *slot = Some((z, p));
                    }
                }
            }
            for y in 0..H {
                for x in 0..W {
                    let k = (y * W + x) as usize;
                    let want = if painted[k] {
                        [7, 7, 7]
                    } else {
                        best[k].map_or([0, 0, 0], |(_, p)| colour(p))
                    };
                    proptest::prop_assert_eq!(fb.colour_at(x, y), want, "({}, {})", x, y);
                }
            }
        }
    }

    #[test]
    fn the_farthest_depths_still_draw_on_an_empty_pixel() {
        let mut fb = FrameBuffer::new(3, 1, [0, 0, 0]).unwrap();
        fb.span(0, 0..3, f64::MAX, 0.0, 0, [7, 7, 7]);
        assert_eq!(fb.rgb(), &[7; 9]);
        fb.span(0, 0..3, -f64::MAX, 0.0, 1, [8, 8, 8]);
        assert_eq!(fb.rgb(), &[8; 9]);
    }

    #[test]
    fn an_earlier_polygon_arriving_later_takes_back_only_beyond_the_tie_width() {
        use proto::depth::TIE;
        let mut fb = FrameBuffer::new(3, 1, [0, 0, 0]).unwrap();
        fb.span(0, 0..3, -1.0, 0.0, 5, [1, 1, 1]);
        // Polygon 2 (earlier): a tie at column 0 is its; half a width farther at column
        // 1 still ties (the later polygon 5 did not take it); two widths farther it loses.
        fb.pixel(0, 0, -1.0, 2, [2, 2, 2]);
        fb.pixel(1, 0, -(1.0 - 0.5 * TIE), 2, [2, 2, 2]);
        fb.pixel(2, 0, -(1.0 - 2.0 * TIE), 2, [2, 2, 2]);
        assert_eq!(fb.rgb(), &[2, 2, 2, 2, 2, 2, 1, 1, 1]);
    }

    #[test]
    fn ppm_bytes() {
        let mut fb = FrameBuffer::new(2, 1, [9, 8, 7]).unwrap();
        fb.pixel(1, 0, 0.0, 0, [1, 2, 3]);
        let mut out = Vec::new();
        fb.write_ppm(&mut out, ppm::Form::Binary).unwrap();
        assert_eq!(out, b"P6\n2 1\n255\n\x09\x08\x07\x01\x02\x03");
        out.clear();
        fb.write_ppm(&mut out, ppm::Form::Plain).unwrap();
        assert_eq!(out, b"P3\n2 1\n255\n9 8 7 1 2 3\n");
    }

    #[test]
    fn a_frame_buffer_is_15_bytes_a_pixel() {
        let n = 65536 * 65536 * BYTES_PER_PIXEL;
        assert_eq!(stagecli::error::bytes_text(n), "60 GiB");
    }

    #[test]
    fn colours_parse() {
        assert_eq!(parse_colour("1,2,255"), Ok([1, 2, 255]));
        assert!(parse_colour("1,2").is_err());
        assert!(parse_colour("1,2,256").is_err());
    }

    #[test]
    fn patterns_as_image2_reads_them() {
        let p = FramePattern::parse("out%03d.png").unwrap();
        assert_eq!(p.path(7), PathBuf::from("out007.png"));
        assert_eq!(p.path(1234), PathBuf::from("out1234.png"));
        assert_eq!(p.format, ImageFormat::Png);
        let p = FramePattern::parse("a%%b%dc.PPM").unwrap();
        assert_eq!(p.path(12), PathBuf::from("a%b12c.PPM"));
        assert_eq!(p.format, ImageFormat::Ppm);
        let p = FramePattern::parse("still.png").unwrap();
        assert!(!p.numbered());
        assert_eq!(p.path(3), PathBuf::from("still.png"));
        assert!(FramePattern::parse("a%d%d.png").is_err());
        assert!(FramePattern::parse("a%s.png").is_err());
        assert!(FramePattern::parse("a%d.jpg").is_err());
    }
}
