//! A z-buffer for the region of the screen one leaf of the splitter tree sees (docs/DESIGN.md,
//! "Leaves resolve visibility": the merger assembles).
//!
//! The leaf does what the thesis's BUFFER does (chapter 4.2.3), but only for the pixels
//! its polygons cover, and at the end of each frame sends the finished pixels on as runs
//! of one colour along a row; the merger places them without a depth test.
//!
//! A leaf is not told its region: the splitter tree only guarantees that its polygons
//! lie in it. So the buffer is kept in square tiles of [`TILE`]×[`TILE`] pixels, each made
//! the first time a span touches it, and its memory grows with the part of the screen the
//! leaf's polygons cover, not with the screen (a 16-leaf tree over 1920×1080 gives each
//! leaf about 130,000 pixels; a whole-screen buffer would be 2 million). Tiles go back to
//! a pool at the end of each frame, cleared, and are reused by the next.
//!
//! Visibility is chapter 2.3's Z spec with the tie rule of docs/DESIGN.md, as in `zbuf`:
//! folding the polygons in stream order, a later one takes a pixel only when nearer by
//! more than 2⁻³⁰ of the holder's depth ([`proto::depth`]). A leaf reads one stream,
//! whose polygons come in stream order, so the holder is always the earlier polygon, and
//! the buffer keeps for each pixel not the holder's depth but the *bar* a newcomer must
//! get under ([`proto::depth::bar`]): the test is then one comparison a pixel.
//! The polygon index `zbuf` keeps per pixel to decide ties between its inputs is implied
//! by the order here, and a `skip N` (polygons of which the leaf gets nothing) needs no
//! record at all.

mod shaded;

use crate::depth::{depth_at, Depth};
use crate::pages::{advise_huge_page, reserve_unadvised, HUGE_PAGE};
use crate::walk::Span;
use crate::ztest::{self, ZTest};
use proto::Colour;
use std::ops::Range;

/// The row bars pay where at least one pixel in this many tested is turned away by them.
const PAYS: u64 = 16;
/// One frame in this many keeps the row bars whatever the last one found, to look again.
const PROBE: u64 = 16;

/// The side of a tile, in pixels.
pub const TILE: u32 = 64;
const SHIFT: u32 = TILE.trailing_zeros();

/// Where the row of screen row `y` in tile `tile` is kept among the tiles' rows (tile k's
/// row r at `k·TILE + r`).
#[inline]
fn row_at(tile: u32, y: u32) -> usize {
    tile as usize * TILE as usize + (y & (TILE - 1)) as usize
}
const AREA: usize = (TILE * TILE) as usize;
/// The slot of a tile position no span has touched this frame.
const UNTOUCHED: u32 = u32::MAX;
/// How many rows below a span the cells under it are prefetched.
const AHEAD: u32 = 2;

/// A pixel's colour as stored: R, G, B in the low three bytes and a non-zero top byte,
/// so that 0 means "no polygon covers this pixel yet".
#[inline]
fn pack(c: Colour) -> u32 {
    u32::from_le_bytes([c[0], c[1], c[2], 1])
}

#[inline]
fn unpack(p: u32) -> Colour {
    let [r, g, b, _] = p.to_le_bytes();
    [r, g, b]
}

/// The tiles' memory, one block a tile: its TILE×TILE depth bars, then its TILE×TILE
/// packed colours, each row-major within the tile. A pixel's bar means something only
/// where its colour is non-zero.
///
/// The slab reserves room for every tile of the screen up front (address space, not
/// memory: a page is mapped when a tile is first made in it), so that it never moves, and
/// asks the kernel for huge pages there (`madvise(MADV_HUGEPAGE)`): a full-HD buffer is
/// 25 MB, and faulting it in 4 KiB pages cost the fill-heavy scene's leaf a quarter of
/// its time in the kernel. Where the reservation cannot be had (a screen of billions of
/// pixels) the slab grows as tiles are made, in ordinary pages.
///
/// Tiles are made in the order spans first touch them, packed, so the memory a leaf
/// touches is its tiles' and the kernel zeroes whole huge pages of it, the last one
/// part-used. Bars and colours in one block leave one such last page a leaf, where two
/// slabs (bars, colours) left two: a leaf of the fill-heavy scene at depth 2 (135 tiles,
/// 6.5 MB) touched five huge pages, then four, the fourth a sixth used.
///
/// So each huge page after the first is asked for only as the first tile reaches it, and
/// only where the tiles expected ([`Slab::push_tile`]'s guess: the box of tile positions
/// touched so far) fill at least half of it; the rest of a last page comes in 4 KiB
/// pages, as tiles are made. A huge page costs about as much to zero as 0.8 MiB of 4 KiB
/// pages costs to fault in (this machine: 0.13 against 0.31-0.36 ms a MiB, touched a
/// page at a time), so a page half full or more is cheaper huge. A wrong guess costs
/// time, never a pixel.
///
/// The slab's tiles start on a 64-byte boundary (a cache line), and a block (48 KiB) is
/// whole cache lines: a tile row is then whole cache lines, and the z-test's four-pixel
/// blocks of bars (32 bytes) never straddle two.
struct Slab {
    /// The blocks, in units of a bar: a tile's colours take half a unit each.
    cells: Vec<Depth>,
    /// The cells before the first tile, there to align it.
    start: usize,
    /// Whether the vector's spare capacity is zeroed memory no one has written (its
    /// first allocation, asked of the allocator zeroed): a new tile is then there already.
    zeroed: bool,
    /// Whether the first tile starts on a huge page's boundary (a reservation of a huge
    /// page or more), its huge pages to be asked for one by one.
    huge: bool,
    /// Bytes from the first tile up to which the pages are decided (huge or not).
    decided: usize,
    /// Pages asked for huge so far, and pages decided and left to 4 KiB pages.
    pages: [usize; 2],
}

/// The alignment of a slab's first tile, in bytes.
const LINE: usize = 64;
/// A tile's block in units of a bar: AREA bars, then AREA colours of half a unit each.
const BLOCK: usize = AREA + AREA / 2;

/// A tile's colours, stored in units of a bar, as the packed colours they are.
#[inline(always)]
fn as_colours(units: &[Depth]) -> &[u32] {
    // SAFETY: the units' memory is `2 × units.len()` u32 cells, aligned for them (a u32's
    // alignment divides an f64's), and every bit pattern is a valid u32; the borrow of
    // `units` covers the new slice's lifetime.
    unsafe { std::slice::from_raw_parts(units.as_ptr() as *const u32, 2 * units.len()) }
}

/// [`as_colours`], to write.
#[inline(always)]
fn as_colours_mut(units: &mut [Depth]) -> &mut [u32] {
    // SAFETY: as in `as_colours`; every bit pattern is also a valid f64, so the units
    // stay valid whatever is written, and the mutable borrow is held throughout.
    unsafe { std::slice::from_raw_parts_mut(units.as_mut_ptr() as *mut u32, 2 * units.len()) }
}

impl Slab {
    fn new(tiles: usize) -> Self {
        // A slab of a huge page or more starts on a huge page's boundary
        // (`pages::reserve_unadvised`): unaligned, its first and last part-pages were
        // faulted in 4 KiB pages, 1,400 of the fill-heavy scene zbuf's 2,700 faults.
        let (cells, zeroed) = match reserve_unadvised::<Depth>(tiles.saturating_mul(BLOCK), LINE) {
            Some(v) => (v, true),
            None => (Vec::new(), false),
        };
        let start = cells.len();
        let first = cells.as_ptr().wrapping_add(start) as usize;
        let bytes = (cells.capacity() - start) * std::mem::size_of::<Depth>();
        Slab {
            huge: zeroed && bytes >= HUGE_PAGE && first.is_multiple_of(HUGE_PAGE),
            cells,
            start,
            zeroed,
            decided: 0,
            pages: [0, 0],
        }
    }

    /// Tiles made so far.
    fn tiles(&self) -> usize {
        (self.cells.len() - self.start) / BLOCK
    }

    /// A new tile, every bar 0.0 and every colour 0 (empty), with `expected` tiles
    /// thought to be made in all (this one among them): where it reaches a huge page not
    /// yet decided, the page is asked for huge if those tiles fill half of it or more.
    fn push_tile(&mut self, expected: usize) {
        let len = self.cells.len() + BLOCK;
        if self.zeroed && len <= self.cells.capacity() {
            let size = std::mem::size_of::<Depth>();
            let to = (len - self.start) * size;
            let room = (self.cells.capacity() - self.start) * size;
            while self.huge && self.decided < to {
                let page = self.decided;
                let filled = expected.max(self.tiles() + 1) * BLOCK * size;
                // The first page huge whatever the guess, which knows nothing yet.
                if (page == 0 || filled >= page + HUGE_PAGE / 2) && page + HUGE_PAGE <= room {
                    let first = self.cells.as_ptr().wrapping_add(self.start) as *const u8;
                    advise_huge_page(first.wrapping_add(page));
                    self.pages[0] += 1;
                } else {
                    self.pages[1] += 1;
                }
                self.decided = page + HUGE_PAGE;
            }
            // SAFETY: the cells up to `len` are within the capacity, in memory the
            // allocator zeroed and nothing has written since (`zeroed`), and all-zero
            // bytes are a valid f64, 0.0 (`ZeroIsDefault`).
            unsafe { self.cells.set_len(len) };
            // The block's pages faulted in by a write, each once: the z-test's first look
            // at a new tile is a read, which mapped the zero page, and its first write
            // then faulted again to copy it.
            for cell in self.cells[len - BLOCK..].iter_mut().step_by(4096 / size) {
                // SAFETY: a write of the value the cell holds (0.0), volatile so that it
                // is not left out.
                unsafe { std::ptr::write_volatile(cell, 0.0) };
            }
        } else {
            // Beyond the first allocation the vector may move, into memory not zeroed.
            self.zeroed = false;
            self.cells.resize(len, 0.0);
        }
    }

    /// The index of tile k's first cell.
    #[inline]
    fn base(&self, k: u32) -> usize {
        self.start + k as usize * BLOCK
    }

    /// Tile k's bars.
    #[inline]
    fn bars(&self, k: u32) -> &[Depth] {
        &self.cells[self.base(k)..][..AREA]
    }

    /// Tile k's packed colours.
    #[inline]
    fn colours(&self, k: u32) -> &[u32] {
        as_colours(&self.cells[self.base(k) + AREA..][..AREA / 2])
    }

    /// Tile k's packed colours, to write.
    #[inline]
    fn colours_mut(&mut self, k: u32) -> &mut [u32] {
        let at = self.base(k) + AREA;
        as_colours_mut(&mut self.cells[at..][..AREA / 2])
    }

    /// Tile k's bars and colours, to write.
    #[inline]
    fn tile_mut(&mut self, k: u32) -> (&mut [Depth], &mut [u32]) {
        let at = self.base(k);
        let (bars, colours) = self.cells[at..][..BLOCK].split_at_mut(AREA);
        (bars, as_colours_mut(colours))
    }
}

/// Where the runs of a tile row start: bit i is set where cell i differs from cell i − 1,
/// and bit 0 always.
///
/// On x86-64, four cells a compare in 128-bit registers (SSE2, which every x86-64 has):
/// cells 4k..4k+4 against cells 4k−1..4k+3, the lanes' results taken as four bits. The
/// loop below, which the compiler vectorised with 64-bit lanes of shifted booleans, was
/// most of a movie's leaves' time in `finish_frame`.
#[cfg(target_arch = "x86_64")]
#[inline]
fn run_starts(line: &[u32; TILE as usize]) -> u64 {
    use std::arch::x86_64::*;
    let p = line.as_ptr();
    // SAFETY: SSE2 is part of x86-64. Every load is of four cells within the 64: cells
    // 0..4, then 4k..4k+4 and 4k−1..4k+3 for k in 1..16; unaligned loads.
    unsafe {
        let first = _mm_loadu_si128(p as *const __m128i);
        // Lanes 1-3 against cells 0-2 (lane 0 against a zero, its bit set anyway).
        let same = _mm_cmpeq_epi32(first, _mm_slli_si128::<4>(first));
        let mut starts = (!_mm_movemask_ps(_mm_castsi128_ps(same)) as u64 & 0xf) | 1;
        let mut k = 4;
        while k < TILE as usize {
            let cur = _mm_loadu_si128(p.add(k) as *const __m128i);
            let prev = _mm_loadu_si128(p.add(k - 1) as *const __m128i);
            let same = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(cur, prev)));
            starts |= (!same as u64 & 0xf) << k;
            k += 4;
        }
        starts
    }
}

/// [`run_starts`] a cell at a time: the definition, and the code off x86-64.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline]
fn run_starts_scalar(line: &[u32; TILE as usize]) -> u64 {
    let mut starts = 1u64;
    for i in 1..TILE as usize {
        starts |= u64::from(line[i] != line[i - 1]) << i;
    }
    starts
}

#[cfg(not(target_arch = "x86_64"))]
use run_starts_scalar as run_starts;

/// Paints the covered cells of one tile row, `line` (packed colours, 0 where no polygon
/// covers the pixel), into `out`, the same pixels of an RGB raster, and the rest in
/// `back`, or leaves them as they are without one.
///
/// Four pixels at a time where all four are covered (nearly every block of a filled
/// screen): their twelve RGB bytes gathered into two words and stored as an eight- and
/// a four-byte write, where a pixel at a time was three byte stores and a branch each.
/// A block with an empty pixel, and the row's last pixels, go a pixel at a time.
#[inline]
fn paint_row(out: &mut [Colour], line: &[u32], back: Option<Colour>) {
    debug_assert_eq!(out.len(), line.len());
    let mut outs = out.chunks_exact_mut(4);
    let mut cells = line.chunks_exact(4);
    for (o, c) in (&mut outs).zip(&mut cells) {
        let &[p0, p1, p2, p3] = c else {
            unreachable!("chunks of four")
        };
        if p0 != 0 && p1 != 0 && p2 != 0 && p3 != 0 {
            // Pixel i's bytes are the low three of p_i's little-endian bytes (`pack`).
            let lo = u64::from(p0 & 0x00ff_ffff)
                | u64::from(p1 & 0x00ff_ffff) << 24
                | u64::from(p2 & 0xffff) << 48;
            let hi = (p2 >> 16) & 0xff | p3 << 8;
            let bytes = o.as_flattened_mut();
            bytes[..8].copy_from_slice(&lo.to_le_bytes());
            bytes[8..12].copy_from_slice(&hi.to_le_bytes());
        } else {
            for (out, &p) in o.iter_mut().zip(c) {
                paint_one(out, p, back);
            }
        }
    }
    for (out, &p) in outs.into_remainder().iter_mut().zip(cells.remainder()) {
        paint_one(out, p, back);
    }
}

/// The farthest of a covered tile row's TILE bars, in four 256-bit registers of running
/// maxima folded at the end. The compiler kept the fold of
/// [`RegionBuffer::refresh_row_bar`] one maximum after another, a chain of 64 dependent
/// instructions that was a third of the z-test's time on the fill-heavy scene. The bars
/// of a covered row are numbers, so taking the maxima in another order changes nothing
/// but, between 0 and −0, which zero is kept; and a row bar is only compared (`>=`),
/// where the two are one.
///
/// # Safety
///
/// The processor must have AVX2; `bars` must hold TILE cells.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn farthest_avx2(bars: &[Depth]) -> Depth {
    use std::arch::x86_64::*;
    assert!(bars.len() == TILE as usize);
    let p = bars.as_ptr();
    // SAFETY: the 64 cells p..p+64 are in `bars`; unaligned loads.
    unsafe {
        let mut m = [
            _mm256_loadu_pd(p),
            _mm256_loadu_pd(p.add(4)),
            _mm256_loadu_pd(p.add(8)),
            _mm256_loadu_pd(p.add(12)),
        ];
        let mut k = 16;
        while k < TILE as usize {
            for (j, mj) in m.iter_mut().enumerate() {
                *mj = _mm256_max_pd(_mm256_loadu_pd(p.add(k + 4 * j)), *mj);
            }
            k += 16;
        }
        let m = _mm256_max_pd(_mm256_max_pd(m[0], m[1]), _mm256_max_pd(m[2], m[3]));
        let h = _mm_max_pd(_mm256_castpd256_pd128(m), _mm256_extractf128_pd::<1>(m));
        _mm_cvtsd_f64(_mm_max_sd(h, _mm_unpackhi_pd(h, h)))
    }
}

/// One pixel of [`paint_row`]: packed colour `p`, or `back` (if any) where `p` is 0.
#[inline(always)]
fn paint_one(out: &mut Colour, p: u32, back: Option<Colour>) {
    if p != 0 {
        *out = unpack(p);
    } else if let Some(back) = back {
        *out = back;
    }
}

/// [`paint_row`] with 256-bit vectors: eight packed pixels loaded at once and tested for
/// an empty one with one compare. Where all eight are covered, or `back` is given and the
/// empty ones take it (blended in as a packed colour), their 24 RGB bytes are gathered by
/// a byte shuffle within each 128-bit half and a move of the halves' 12 bytes together,
/// and stored as 16 and 8 bytes: no branch a pixel. Over the frame before (a movie's
/// frames after the first), every block goes so. A row's last four are done the same in
/// 128 bits, and a block with an empty pixel and no `back` a pixel at a time. The same
/// raster to the byte.
///
/// # Safety
///
/// The processor must have AVX2; `out` and `line` must be of one length.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn paint_row_avx2(out: &mut [Colour], line: &[u32], back: Option<Colour>) {
    use std::arch::x86_64::*;
    debug_assert_eq!(out.len(), line.len());
    let len = line.len().min(out.len());
    // Bytes 0-2, 4-6, 8-10 and 12-14 of four packed pixels (each R, G, B, then the
    // top byte that marks it covered, `pack`): their RGB bytes in order, in each half.
    let gather = _mm256_setr_epi8(
        0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1, //
        0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
    );
    // The low half's three gathered words, then the high half's: 24 bytes in a row.
    let together = _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 3, 7);
    let zero = _mm256_setzero_si256();
    // The background as a covered cell, for the empty ones to take.
    let fill = back.map(|b| _mm256_set1_epi32(pack(b) as i32));
    let mut i = 0;
    while i + 8 <= len {
        // SAFETY: i + 8 <= len <= both lengths, so cells i..i+8 of `line` and pixels
        // i..i+8 of `out` (bytes 3i..3i+24, a Colour being 3 bytes) are in bounds;
        // unaligned loads and stores.
        unsafe {
            let mut v = _mm256_loadu_si256(line.as_ptr().add(i) as *const __m256i);
            let empty = _mm256_cmpeq_epi32(v, zero);
            let paint = if _mm256_testz_si256(empty, empty) != 0 {
                true
            } else if let Some(fill) = fill {
                v = _mm256_blendv_epi8(v, fill, empty);
                true
            } else {
                false
            };
            if paint {
                let o = out.as_mut_ptr().add(i) as *mut u8;
                let b = _mm256_permutevar8x32_epi32(_mm256_shuffle_epi8(v, gather), together);
                _mm_storeu_si128(o as *mut __m128i, _mm256_castsi256_si128(b));
                _mm_storel_epi64(o.add(16) as *mut __m128i, _mm256_extracti128_si256::<1>(b));
            } else {
                for k in i..i + 8 {
                    paint_one(out.get_unchecked_mut(k), *line.get_unchecked(k), back);
                }
            }
        }
        i += 8;
    }
    if i + 4 <= len {
        // SAFETY: as above, for cells and pixels i..i+4.
        unsafe {
            let mut v = _mm_loadu_si128(line.as_ptr().add(i) as *const __m128i);
            let empty = _mm_cmpeq_epi32(v, _mm_setzero_si128());
            let paint = if _mm_testz_si128(empty, empty) != 0 {
                true
            } else if let Some(fill) = fill {
                v = _mm_blendv_epi8(v, _mm256_castsi256_si128(fill), empty);
                true
            } else {
                false
            };
            if paint {
                let o = out.as_mut_ptr().add(i) as *mut u8;
                let b = _mm_shuffle_epi8(v, _mm256_castsi256_si128(gather));
                _mm_storel_epi64(o as *mut __m128i, b);
                (o.add(8) as *mut i32).write_unaligned(_mm_extract_epi32::<2>(b));
            } else {
                for k in i..i + 4 {
                    paint_one(out.get_unchecked_mut(k), *line.get_unchecked(k), back);
                }
            }
        }
        i += 4;
    }
    for (o, &p) in out[i..len].iter_mut().zip(&line[i..len]) {
        paint_one(o, p, back);
    }
}

/// Finished pixels `x0..x1` (end exclusive) of row `y`, all of one colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Run {
    pub y: u32,
    pub x0: u32,
    pub x1: u32,
    pub colour: Colour,
}

/// A finished run as the fragment stream carries it (`run Y X0 X1 R G B`).
impl From<Run> for proto::Fragment {
    fn from(r: Run) -> Self {
        proto::Fragment::Run {
            y: r.y,
            x0: r.x0,
            x1: r.x1,
            colour: r.colour,
        }
    }
}

/// Counts for `--stats`, over all frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionStats {
    /// Pixels depth-tested.
    pub pixels_tested: u64,
    /// Pixels that passed the test (written to the buffer).
    pub pixels_written: u64,
    /// Of the pixels tested, those turned away whole: the span's piece of a tile row lay
    /// behind the row's farthest bar ([`RegionBuffer::span`]), so no pixel was looked at.
    pub pixels_behind_row: u64,
    /// Runs sent on.
    pub runs: u64,
    /// Tiles allocated (the most any frame needed: the pool is reused frame to frame).
    pub tiles: u64,
}

/// The z-buffer of the part of a `width`×`height` screen that the spans fall in.
pub struct RegionBuffer {
    width: u32,
    height: u32,
    tiles_x: u32,
    tiles_y: u32,
    /// Per tile position, row-major, its tile in the slabs, or [`UNTOUCHED`].
    slot: Vec<u32>,
    /// Every tile ever made; the first `in_use` hold this frame's pixels, the rest are
    /// clear. Per pixel, the bar a later polygon's depth must be under to take it, and
    /// its packed colour.
    tiles: Slab,
    /// Per tile row ([`RegionBuffer::row_at`]), the farthest bar of its cells when every
    /// cell is covered, else NaN (and NaN throughout a frame that does not keep them): a
    /// span's piece that is nowhere nearer than it takes no cell, and is turned away
    /// without a test. (Not +∞ for a row with an empty cell: an empty cell takes a depth
    /// of +∞ too, and no depth compares as at or behind NaN.)
    row_bar: Vec<Depth>,
    /// The box of tile positions ever touched, `[x0, x1, y0, y1]` (inclusive; empty
    /// while `x0 > x1`): how many tiles the slab is expected to hold ([`Slab::push_tile`]).
    touched: [u32; 4],
    /// Whether this frame keeps [`RegionBuffer::row_bar`] (see [`RegionBuffer::clear`]).
    rows_kept: bool,
    /// Whether the last frame that kept the row bars turned away enough to pay for them.
    rows_paid: bool,
    /// This frame's pixels tested and turned away (the callers may take `stats`).
    frame_tested: u64,
    frame_behind: u64,
    /// Frames this buffer has finished.
    frames: u64,
    in_use: usize,
    /// Tiles `in_use..dirty` of the pool still hold an earlier frame's colours and row
    /// bars: cleared as each is taken again ([`RegionBuffer::first_touch`]), not when the
    /// frame ends, so that the last frame of a stream clears nothing.
    dirty: usize,
    /// The z-test's kernel, the fastest this processor has.
    kernel: ZTest,
    pub stats: RegionStats,
}

impl RegionBuffer {
    /// An empty buffer: no tile is made until a span touches it.
    pub fn new(width: u32, height: u32) -> Self {
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        RegionBuffer {
            width,
            height,
            tiles_x,
            tiles_y,
            slot: vec![UNTOUCHED; tiles_x as usize * tiles_y as usize],
            tiles: Slab::new(tiles_x as usize * tiles_y as usize),
            row_bar: Vec::new(),
            touched: [u32::MAX, 0, u32::MAX, 0],
            rows_kept: true,
            rows_paid: true,
            frame_tested: 0,
            frame_behind: 0,
            frames: 0,
            in_use: 0,
            dirty: 0,
            kernel: ZTest::detect(),
            stats: RegionStats::default(),
        }
    }

    /// The z-test kernel in use ([`ZTest::detect`]'s choice unless set).
    pub fn kernel(&self) -> ZTest {
        self.kernel
    }

    /// Runs the z-test with `kernel` from now on (the tests and benchmarks compare the
    /// kernels; the result is the same with each).
    ///
    /// # Panics
    ///
    /// When this processor cannot run it ([`ZTest::available`]).
    pub fn set_kernel(&mut self, kernel: ZTest) {
        assert!(kernel.available(), "this processor cannot run {kernel:?}");
        self.kernel = kernel;
    }

    /// The screen's width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The tile at tile position (tx, ty), made (or taken from the pool) on first touch.
    #[inline(always)]
    fn tile(&mut self, tx: u32, ty: u32) -> u32 {
        let at = (ty * self.tiles_x + tx) as usize;
        let s = self.slot[at];
        if s != UNTOUCHED {
            return s;
        }
        self.first_touch(at)
    }

    /// The tile for tile position `at`, touched for the first time this frame.
    #[cold]
    #[inline(never)]
    fn first_touch(&mut self, at: usize) -> u32 {
        let (tx, ty) = (at as u32 % self.tiles_x, at as u32 / self.tiles_x);
        let [x0, x1, y0, y1] = &mut self.touched;
        (*x0, *x1, *y0, *y1) = ((*x0).min(tx), (*x1).max(tx), (*y0).min(ty), (*y1).max(ty));
        if self.in_use == self.tiles.tiles() {
            // The tiles expected: those in the box of the tile positions touched so far.
            let [x0, x1, y0, y1] = self.touched;
            let expected = (x1 - x0 + 1) as usize * (y1 - y0 + 1) as usize;
            self.tiles.push_tile(expected);
            self.row_bar.extend([Depth::NAN; TILE as usize]);
            self.stats.tiles += 1;
        }
        let s = self.in_use as u32;
        if self.in_use < self.dirty {
            // A tile of an earlier frame, taken again: empty it (see `clear`).
            self.tiles.colours_mut(s).fill(0);
            let rows = row_at(s, 0);
            self.row_bar[rows..rows + TILE as usize].fill(Depth::NAN);
        }
        self.in_use += 1;
        self.slot[at] = s;
        s
    }

    /// One polygon's span ([`crate::SpanWalker`]) in its colour.
    #[inline]
    pub fn draw(&mut self, span: &Span, colour: Colour) {
        self.span(span.y, span.columns(), span.z_row, span.dz, colour);
    }

    /// Pixels `columns` of row `y` in `colour`: pixel x has depth `z_row + x·dz`
    /// ([`crate::depth_at`]), as `zbuf` computes a fragment span's. A pixel is written when it is
    /// empty or the tie rule gives it to this polygon. Spans must come polygon by polygon
    /// in stream order (see the module notes). A span off the screen is clipped.
    pub fn span(&mut self, y: u32, columns: Range<u32>, z_row: Depth, dz: Depth, colour: Colour) {
        match self.kernel {
            ZTest::Scalar => self.span_in(y, columns, z_row, dz, colour, ztest::scalar),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `kernel` is Avx2 only where the processor has AVX2 and POPCNT
            // (`ZTest::detect`, `set_kernel`).
            ZTest::Avx2 => unsafe { self.span_avx2(y, columns, z_row, dz, colour) },
            #[cfg(not(target_arch = "x86_64"))]
            ZTest::Avx2 => unreachable!("AVX2 is never detected off x86-64"),
        }
    }

    /// [`RegionBuffer::span`] compiled for AVX2, so that the kernel is inlined into the
    /// loop over the span's tiles.
    ///
    /// # Safety
    ///
    /// The processor must have AVX2 and POPCNT.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,popcnt")]
    unsafe fn span_avx2(
        &mut self,
        y: u32,
        columns: Range<u32>,
        z_row: Depth,
        dz: Depth,
        colour: Colour,
    ) {
        self.span_in(y, columns, z_row, dz, colour, |b, c, lo, hi, l, z, d, p| {
            // SAFETY: the caller promises AVX2 and POPCNT; `span_in` passes one tile
            // row's cells (TILE of each, a multiple of 4) and lo <= hi <= TILE.
            unsafe { ztest::avx2(b, c, lo, hi, l, z, d, p) }
        })
    }

    /// The loop over the tiles a span crosses, each tile row's piece z-tested by
    /// `kernel` (bars, colours, first and end cell, the row's first column, z_row, dz,
    /// colour; it returns the pixels taken).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn span_in(
        &mut self,
        y: u32,
        columns: Range<u32>,
        z_row: Depth,
        dz: Depth,
        colour: Colour,
        kernel: impl Fn(&mut [Depth], &mut [u32], usize, usize, u32, Depth, Depth, u32) -> u64,
    ) {
        if y >= self.height {
            return;
        }
        let x1 = columns.end.min(self.width);
        let mut x = columns.start.min(x1);
        let colour = pack(colour);
        let (ty, offset) = (y >> SHIFT, ((y & (TILE - 1)) << SHIFT) as usize);
        let mut written = 0u64;
        while x < x1 {
            let tx = x >> SHIFT;
            let left = tx << SHIFT;
            let end = x1.min(left + TILE);
            let tile = self.tile(tx, ty);
            self.stats.pixels_tested += (end - x) as u64;
            // The piece's depth is monotonic along the row (a rounded product and sum of
            // monotonic terms), so its nearest is at one of its ends: where both are at
            // or behind every bar of a covered row, no cell passes the test.
            if self.rows_kept {
                self.frame_tested += (end - x) as u64;
                let row_bar = self.row_bar[row_at(tile, y)];
                if depth_at(z_row, dz, x) >= row_bar && depth_at(z_row, dz, end - 1) >= row_bar {
                    self.stats.pixels_behind_row += (end - x) as u64;
                    self.frame_behind += (end - x) as u64;
                    x = end;
                    continue;
                }
            }
            // The tile's row y: cell i is column left + i.
            let row = offset..offset + TILE as usize;
            let (bars, colours) = self.tiles.tile_mut(tile);
            let taken = kernel(
                &mut bars[row.clone()],
                &mut colours[row],
                (x - left) as usize,
                (end - left) as usize,
                left,
                z_row,
                dz,
                colour,
            );
            if taken > 0 {
                self.refresh_row_bar(tile, y);
            }
            written += taken;
            if (y & (TILE - 1)) + AHEAD < TILE {
                self.prefetch(
                    tile,
                    offset + (AHEAD << SHIFT) as usize,
                    x - left,
                    end - left,
                );
            }
            x = end;
        }
        self.stats.pixels_written += written;
    }

    /// Sets row `y`'s entry of [`RegionBuffer::row_bar`] in `tile` from its cells, after
    /// a span took some of them, in a frame that keeps the row bars: the farthest bar if
    /// every cell is covered, else NaN. Inlined, so that in [`RegionBuffer::span_avx2`]
    /// it is compiled for AVX2 too.
    #[inline(always)]
    fn refresh_row_bar(&mut self, tile: u32, y: u32) {
        if !self.rows_kept {
            return;
        }
        let r = (y & (TILE - 1)) as usize;
        let cells = r << SHIFT..(r + 1) << SHIFT;
        let colours = &self.tiles.colours(tile)[cells.clone()];
        let bars = &self.tiles.bars(tile)[cells];
        let covered = colours.iter().fold(true, |all, &c| all & (c != 0));
        self.row_bar[row_at(tile, y)] = if covered {
            match self.kernel {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `kernel` is Avx2 only where the processor has AVX2; a tile row
                // is TILE cells.
                ZTest::Avx2 => unsafe { farthest_avx2(bars) },
                _ => bars
                    .iter()
                    .fold(Depth::NEG_INFINITY, |m, &b| if b > m { b } else { m }),
            }
        } else {
            Depth::NAN
        };
    }

    /// Asks for the cells `lo..hi` of the tile row starting at cell `row` to be brought
    /// into the cache: where the polygon's next spans will most likely fall.
    #[inline(always)]
    fn prefetch(&self, tile: u32, row: usize, lo: u32, hi: u32) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            let (lo, hi) = (lo as usize, hi as usize);
            let base = self
                .tiles
                .cells
                .as_ptr()
                .wrapping_add(self.tiles.base(tile));
            let bars = base.wrapping_add(row) as *const i8;
            let colours = (base.wrapping_add(AREA) as *const u32).wrapping_add(row) as *const i8;
            let mut b = (lo * 8) & !63;
            while b < hi * 8 {
                // SAFETY: a prefetch is a hint; it does not fault, whatever the address.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(bars.wrapping_add(b)) };
                b += 64;
            }
            let mut c = (lo * 4) & !63;
            while c < hi * 4 {
                // SAFETY: as above.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(colours.wrapping_add(c)) };
                c += 64;
            }
        }
    }

    /// The colour of pixel (x, y) so far this frame, if a polygon covers it.
    pub fn colour_at(&self, x: u32, y: u32) -> Option<Colour> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let s = self.slot[((y >> SHIFT) * self.tiles_x + (x >> SHIFT)) as usize];
        if s == UNTOUCHED {
            return None;
        }
        let at = (((y & (TILE - 1)) << SHIFT) + (x & (TILE - 1))) as usize;
        let p = self.tiles.colours(s)[at];
        (p != 0).then(|| unpack(p))
    }

    /// Ends the frame: hands every covered pixel to `emit` as runs of one colour along a
    /// row (rows top to bottom, runs left to right, each as long as it can be), then
    /// clears the buffer for the next frame. Pixels no polygon covered are left out: the
    /// merger shows the background there.
    pub fn finish_frame<E>(&mut self, mut emit: impl FnMut(Run) -> Result<(), E>) -> Result<(), E> {
        let mut row_tiles: Vec<(u32, u32)> = Vec::with_capacity(self.tiles_x as usize);
        let mut result = Ok(());
        'tile_rows: for ty in 0..self.tiles_y {
            row_tiles.clear();
            let slots =
                &self.slot[(ty * self.tiles_x) as usize..((ty + 1) * self.tiles_x) as usize];
            row_tiles.extend(
                slots
                    .iter()
                    .enumerate()
                    .filter(|(_, s)| **s != UNTOUCHED)
                    .map(|(tx, s)| (tx as u32, *s)),
            );
            if row_tiles.is_empty() {
                continue;
            }
            let rows = TILE.min(self.height - ty * TILE);
            for r in 0..rows {
                let y = ty * TILE + r;
                // The run being built: it may go on into the next tile.
                let mut open: Option<Run> = None;
                for &(tx, s) in &row_tiles {
                    let base = (r << SHIFT) as usize;
                    let Some(line) =
                        self.tiles.colours(s)[base..].first_chunk::<{ TILE as usize }>()
                    else {
                        unreachable!("a tile holds TILE rows of TILE cells")
                    };
                    let left = tx * TILE;
                    // The row's runs by where they start: bit i set where cell i differs
                    // from cell i − 1 (and at cell 0). Made a whole tile row at a time, as
                    // vector compares, rather than cell by cell along each run.
                    let mut starts = run_starts(line);
                    while starts != 0 {
                        let start = starts.trailing_zeros() as usize;
                        starts &= starts - 1;
                        let end = if starts == 0 {
                            TILE as usize
                        } else {
                            starts.trailing_zeros() as usize
                        };
                        let p = line[start];
                        if p == 0 {
                            continue;
                        }
                        let (x0, x1, colour) = (left + start as u32, left + end as u32, unpack(p));
                        match &mut open {
                            Some(run) if run.x1 == x0 && run.colour == colour => run.x1 = x1,
                            _ => {
                                if let Some(run) = open.replace(Run { y, x0, x1, colour }) {
                                    self.stats.runs += 1;
                                    if let Err(e) = emit(run) {
                                        result = Err(e);
                                        break 'tile_rows;
                                    }
                                }
                            }
                        }
                    }
                }
                if let Some(run) = open {
                    self.stats.runs += 1;
                    if let Err(e) = emit(run) {
                        result = Err(e);
                        break 'tile_rows;
                    }
                }
            }
        }
        self.clear();
        result
    }

    /// Ends the frame as [`RegionBuffer::finish_frame`] does, but paints the covered
    /// pixels straight into `raster`, the screen's row-major RGB pixels (a frame buffer
    /// holding the background), instead of handing them on as runs: for the merger that
    /// is also the only leaf (`zbuf` reading persp's stream at depth 0), where runs would
    /// only be taken apart again.
    pub fn finish_into(&mut self, raster: &mut [Colour]) {
        self.paint(raster, None);
    }

    /// [`RegionBuffer::finish_into`] over a raster that holds anything (the frame
    /// before's pixels): every pixel is written, the covered ones in their colour and the
    /// rest in `background`. A movie's frames then need no pass of their own to put the
    /// background back first: on a screen the polygons cover, the painting writes every
    /// pixel anyway.
    pub fn finish_over(&mut self, raster: &mut [Colour], background: Colour) {
        self.paint(raster, Some(background));
    }

    /// Paints the frame into `raster` (pixels no polygon covers: left as they are, or
    /// `back`), then clears the buffer.
    fn paint(&mut self, raster: &mut [Colour], back: Option<Colour>) {
        let width = self.width as usize;
        assert_eq!(raster.len(), width * self.height as usize, "raster size");
        for ty in 0..self.tiles_y {
            let rows = TILE.min(self.height - ty * TILE);
            for tx in 0..self.tiles_x {
                let s = self.slot[(ty * self.tiles_x + tx) as usize];
                let left = (tx * TILE) as usize;
                let cols = (TILE as usize).min(width - left);
                if s == UNTOUCHED {
                    if let Some(back) = back {
                        for r in 0..rows {
                            let at = (ty * TILE + r) as usize * width + left;
                            raster[at..at + cols].fill(back);
                        }
                    }
                    continue;
                }
                let tile = self.tiles.colours(s);
                for r in 0..rows {
                    let line = &tile[(r << SHIFT) as usize..][..cols];
                    let at = (ty * TILE + r) as usize * width + left;
                    let out = &mut raster[at..at + cols];
                    match self.kernel {
                        #[cfg(target_arch = "x86_64")]
                        // SAFETY: `kernel` is Avx2 only where the processor has AVX2
                        // (`ZTest::detect`, `set_kernel`); the slices are of one length.
                        ZTest::Avx2 => unsafe { paint_row_avx2(out, line, back) },
                        _ => paint_row(out, line, back),
                    }
                }
            }
        }
        self.clear();
    }

    /// Forgets this frame's pixels: the tiles in use are cleared and go back to the pool.
    ///
    /// And decides whether the next frame keeps the row bars. Keeping them costs every
    /// piece a comparison and every take a pass over its row, which pays only where a
    /// good share of the pieces lie behind covered rows: half the pixels tested on the
    /// fill-heavy scene (Dc≈10), a quarter of a per cent on the 100-frame movie. After a
    /// frame that kept them and turned away fewer than one pixel in [`PAYS`] of those it
    /// tested, the frames stop keeping them, all but one in [`PROBE`], which looks again.
    /// The pictures are the same either way.
    ///
    /// The tiles themselves are emptied only as the next frame takes them again
    /// ([`RegionBuffer::first_touch`]): a tile's colours are read only through its slot,
    /// and a tile no slot names is read by nothing. So the last frame of a stream (the
    /// only one of a still) leaves its 8 MB of colours at 1920×1080 as they are, where
    /// clearing them was a pass over memory long out of the caches.
    pub fn clear(&mut self) {
        self.slot.fill(UNTOUCHED);
        self.dirty = self.dirty.max(self.in_use);
        self.in_use = 0;
        if self.rows_kept {
            self.rows_paid = self.frame_behind.saturating_mul(PAYS) >= self.frame_tested;
        }
        self.frames += 1;
        self.rows_kept = self.rows_paid || self.frames.is_multiple_of(PROBE);
        (self.frame_tested, self.frame_behind) = (0, 0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every run of a frame.
    fn runs(rb: &mut RegionBuffer) -> Vec<Run> {
        let mut out = vec![];
        rb.finish_frame(|r| {
            out.push(r);
            Ok::<_, ()>(())
        })
        .unwrap();
        out
    }

    fn run(y: u32, x0: u32, x1: u32, colour: Colour) -> Run {
        Run { y, x0, x1, colour }
    }

    const R: Colour = [255, 0, 0];
    const G: Colour = [0, 255, 0];
    const B: Colour = [0, 0, 255];

    #[test]
    fn a_tiles_bars_and_colours_share_one_block_and_no_cell() {
        let mut slab = Slab::new(4);
        slab.push_tile(2);
        slab.push_tile(2);
        assert_eq!(slab.tiles(), 2);
        // Whole cache lines: the first tile on a line, each block 48 KiB.
        assert_eq!(slab.bars(0).as_ptr() as usize % LINE, 0);
        assert_eq!(BLOCK * std::mem::size_of::<Depth>(), 48 << 10);
        let (bars, colours) = slab.tile_mut(0);
        assert_eq!((bars.len(), colours.len()), (AREA, AREA));
        bars.fill(-1.0);
        colours.fill(u32::MAX);
        assert!(slab.bars(0).iter().all(|&b| b == -1.0));
        assert!(slab.colours(0).iter().all(|&c| c == u32::MAX));
        // The next tile's cells are apart from them, and zero.
        assert!(slab.bars(1).iter().all(|&b| b.to_bits() == 0));
        assert!(slab.colours(1).iter().all(|&c| c == 0));
        slab.colours_mut(0).fill(7);
        assert!(slab.bars(0).iter().all(|&b| b == -1.0));
        assert_eq!(slab.colours(0)[AREA - 1], 7);
    }

    #[test]
    fn a_last_huge_page_is_asked_for_only_where_the_tiles_expected_fill_half() {
        // A full-HD screen's slab (510 tiles); a leaf of a depth-2 tree makes 135 tiles
        // (6.33 MiB: three huge pages and a sixth of a fourth), and knows it early.
        let mut slab = Slab::new(510);
        if !slab.huge {
            return; // no room reserved on this machine: nothing to decide
        }
        for _ in 0..135 {
            slab.push_tile(135);
        }
        assert_eq!(slab.pages, [3, 1]);
        assert!(slab.bars(134).iter().all(|&b| b.to_bits() == 0));
        // The whole screen: every page is full but the last (23.9 MiB), all huge.
        let mut slab = Slab::new(510);
        for _ in 0..510 {
            slab.push_tile(510);
        }
        assert_eq!(slab.pages, [12, 0]);
        // The first page is huge even where the guess says one tile; the next, reached
        // with the guess that it is barely begun, is not.
        let mut slab = Slab::new(510);
        for k in 0..50 {
            slab.push_tile(k + 1);
        }
        assert_eq!(slab.pages, [1, 1]);
    }

    #[test]
    fn nearer_wins_and_a_tie_keeps_the_earlier_polygon() {
        let mut rb = RegionBuffer::new(4, 1);
        rb.span(0, 0..4, 10.0, 0.0, R); // polygon 0 at depth 10
        rb.span(0, 0..2, 10.0, 0.0, G); // polygon 1 ties: polygon 0 stays
        rb.span(0, 1..4, 8.0, 1.0, B); // polygon 2 at 9, 10, 11: nearer only at column 1
        assert_eq!(
            (0..4).map(|x| rb.colour_at(x, 0)).collect::<Vec<_>>(),
            [Some(R), Some(B), Some(R), Some(R)]
        );
        assert_eq!(
            runs(&mut rb),
            [run(0, 0, 1, R), run(0, 1, 2, B), run(0, 2, 4, R)]
        );
        assert_eq!(
            rb.stats,
            RegionStats {
                pixels_tested: 9,
                pixels_written: 5,
                pixels_behind_row: 0,
                runs: 3,
                tiles: 1
            }
        );
        // The next frame starts empty, in the same tile.
        assert_eq!(rb.colour_at(0, 0), None);
        assert_eq!(runs(&mut rb), []);
        rb.span(0, 3..4, 0.0, 0.0, G);
        assert_eq!(runs(&mut rb), [run(0, 3, 4, G)]);
        assert_eq!(rb.stats.tiles, 1);
    }

    #[test]
    fn the_farthest_depth_still_covers_an_empty_pixel() {
        let mut rb = RegionBuffer::new(3, 1);
        rb.span(0, 0..3, f64::MAX, 0.0, R);
        assert_eq!(runs(&mut rb), [run(0, 0, 3, R)]);
        rb.span(0, 0..3, f64::MAX, 0.0, R);
        rb.span(0, 0..3, f64::MAX, 0.0, G); // a tie at the largest depth: the earlier stays
        rb.span(0, 1..3, -f64::MAX, 0.0, B);
        assert_eq!(runs(&mut rb), [run(0, 0, 1, R), run(0, 1, 3, B)]);
    }

    #[test]
    fn a_later_polygon_must_be_nearer_by_more_than_the_tie_width() {
        // Reciprocal depths near yon (−1e-6), the later polygons 0.5 and 2 tie widths
        // nearer: the first ties (the earlier stays), the second takes the pixel.
        use proto::depth::TIE;
        let mut rb = RegionBuffer::new(3, 1);
        let held = -1e-6;
        rb.span(0, 0..3, held, 0.0, R);
        rb.span(0, 0..1, held * (1.0 + 0.5 * TIE), 0.0, G);
        rb.span(0, 1..2, held * (1.0 + 2.0 * TIE), 0.0, B);
        // A NaN depth draws nothing, even on an empty pixel.
        rb.span(0, 2..3, f64::NAN, 0.0, B);
        assert_eq!(
            runs(&mut rb),
            [run(0, 0, 1, R), run(0, 1, 2, B), run(0, 2, 3, R)]
        );
        rb.span(0, 0..3, f64::NAN, 0.0, B);
        assert_eq!(runs(&mut rb), []);
    }

    #[test]
    fn runs_join_across_tile_edges_and_split_at_colour_changes() {
        let mut rb = RegionBuffer::new(300, 130);
        rb.span(129, 10..250, 5.0, 0.0, R); // one run over four tiles
        rb.span(129, 128..129, 1.0, 0.0, G); // a nearer pixel at a tile's first column
        rb.span(0, 60..70, 5.0, 0.0, B);
        rb.span(0, 62..64, 5.0, 0.0, R); // tie: stays blue
        rb.span(64, 299..400, 5.0, 0.0, G); // clipped to the screen
        rb.span(130, 0..10, 5.0, 0.0, G); // below the screen: nothing
        assert_eq!(
            runs(&mut rb),
            [
                run(0, 60, 70, B),
                run(64, 299, 300, G),
                run(129, 10, 128, R),
                run(129, 128, 129, G),
                run(129, 129, 250, R),
            ]
        );
        // Tiles: (0,0), (1,0); (4,1); (0,2), (1,2), (2,2), (3,2).
        assert_eq!(rb.stats.tiles, 7);
    }

    #[test]
    fn memory_follows_the_region_not_the_screen() {
        // A leaf of a 16-leaf tree over 1920x1080 (480x270 at the top left): 8x5 tiles
        // of the screen's 30x17.
        let mut rb = RegionBuffer::new(1920, 1080);
        for y in 0..270 {
            rb.span(y, 0..480, 1.0, 0.0, R);
        }
        assert_eq!(rb.stats.tiles, 8 * 5);
        assert_eq!(runs(&mut rb).len(), 270);
        for y in 0..270 {
            rb.span(y, 0..480, 1.0, 0.0, R);
        }
        runs(&mut rb);
        assert_eq!(rb.stats.tiles, 8 * 5);
    }

    #[test]
    fn finish_into_paints_what_the_runs_say() {
        // Spans over three tiles across and two down, on a screen whose last tiles are
        // partial: the raster gets exactly the runs' pixels, the rest keeps its colour.
        let (w, h) = (150u32, 70u32);
        let draw = |rb: &mut RegionBuffer| {
            rb.span(3, 10..140, 5.0, 0.0, R);
            rb.span(3, 60..70, 4.0, 0.0, G);
            rb.span(69, 120..150, 1.0, 0.0, B);
            rb.span(64, 0..1, 1.0, 0.0, G);
        };
        let mut rb = RegionBuffer::new(w, h);
        draw(&mut rb);
        let back = [9, 9, 9];
        let mut want = vec![back; (w * h) as usize];
        for r in runs(&mut rb) {
            for x in r.x0..r.x1 {
                want[(r.y * w + x) as usize] = r.colour;
            }
        }
        draw(&mut rb);
        let mut got = vec![back; (w * h) as usize];
        rb.finish_into(&mut got);
        assert_eq!(got, want);
        // Over the frame before's pixels, with the background put back where nothing is.
        draw(&mut rb);
        let mut over = vec![[1, 2, 3]; (w * h) as usize];
        rb.finish_over(&mut over, back);
        assert_eq!(over, want);
        // Cleared for the next frame.
        assert_eq!(rb.colour_at(10, 3), None);
    }

    #[test]
    fn a_tile_taken_again_holds_nothing_of_the_frame_before() {
        // Frame 1 covers two tiles whole; frame 2 touches one other tile with a short span:
        // it gets the pool's first tile, frame 1's, and only its own pixels come out.
        let mut rb = RegionBuffer::new(256, 128);
        for y in 0..64 {
            rb.span(y, 0..128, 1.0, 0.0, R);
        }
        assert_eq!(runs(&mut rb).len(), 64);
        rb.span(70, 200..203, 1.0, 0.0, G);
        assert_eq!(rb.colour_at(0, 0), None);
        assert_eq!(rb.colour_at(200, 70), Some(G));
        assert_eq!(runs(&mut rb), [run(70, 200, 203, G)]);
        // And painted into a raster, the same.
        rb.span(70, 200..203, 1.0, 0.0, G);
        let mut got = vec![[0, 0, 0]; 256 * 128];
        rb.finish_into(&mut got);
        let mut want = vec![[0, 0, 0]; 256 * 128];
        want[70 * 256 + 200..70 * 256 + 203].fill(G);
        assert_eq!(got, want);
        // Over another frame's pixels: the untouched tiles get the background too.
        rb.span(70, 200..203, 1.0, 0.0, G);
        let mut over = vec![[7, 7, 7]; 256 * 128];
        rb.finish_over(&mut over, [0, 0, 0]);
        assert_eq!(over, want);
        // A far span in frame 1's tile, behind its old pixels' bars, still takes them.
        rb.span(5, 0..4, 9.0, 0.0, B);
        assert_eq!(runs(&mut rb), [run(5, 0, 4, B)]);
    }

    proptest::proptest! {
        /// Where the runs of a row start, four cells a compare, is the definition's.
        #[test]
        fn run_starts_are_where_a_cell_differs_from_the_one_before(
            // Few colours, so that neighbours are often the same.
            cells in proptest::collection::vec(0u32..3, TILE as usize),
            big in 0u32..=u32::MAX,
        ) {
            use proptest::prelude::*;
            let mut line = [0u32; TILE as usize];
            for (l, c) in line.iter_mut().zip(&cells) {
                *l = if *c == 2 { big } else { *c };
            }
            prop_assert_eq!(run_starts(&line), run_starts_scalar(&line));
        }

        /// The vector maximum of a covered row's bars is the scalar fold's (as a number:
        /// 0 and −0 are one to the comparisons that read it).
        #[test]
        fn the_vector_row_bar_is_the_farthest_bar(
            bars in proptest::collection::vec(
                proptest::prop_oneof![
                    8 => -4.0f64..4.0,
                    1 => proptest::strategy::Just(0.0),
                    1 => proptest::strategy::Just(-0.0),
                    1 => proptest::strategy::Just(f64::INFINITY),
                    1 => proptest::strategy::Just(f64::NEG_INFINITY),
                ],
                TILE as usize,
            ),
        ) {
            use proptest::prelude::*;
            let want = bars.iter().fold(Depth::NEG_INFINITY, |m, &b| if b > m { b } else { m });
            #[cfg(target_arch = "x86_64")]
            if ZTest::Avx2.available() {
                // SAFETY: the processor has AVX2; TILE bars.
                let got = unsafe { farthest_avx2(&bars) };
                prop_assert!(got == want, "{} against {}", got, want);
            }
        }

        /// Painting four pixels at a time (each way) leaves the raster a pixel at a time
        /// would.
        #[test]
        fn paint_row_paints_each_covered_pixel(
            // None: no polygon covers the pixel; black ([0, 0, 0]) is a covered colour.
            cells in proptest::collection::vec(
                proptest::option::weighted(0.8, proptest::array::uniform3(0u8..=255)),
                0..70,
            ),
            back in proptest::array::uniform3(0u8..=255),
            before in proptest::array::uniform3(0u8..=255),
        ) {
            use proptest::prelude::*;
            let line: Vec<u32> = cells.iter().map(|c| c.map_or(0, pack)).collect();
            let want: Vec<Colour> = cells.iter().map(|c| c.unwrap_or(back)).collect();
            // Over a raster holding the background (finish_into), and over one holding
            // anything else, with the background to put back (finish_over).
            for (start, with) in [(back, None), (before, Some(back))] {
                let mut got = vec![start; line.len()];
                paint_row(&mut got, &line, with);
                prop_assert_eq!(&got, &want);
                #[cfg(target_arch = "x86_64")]
                if ZTest::Avx2.available() {
                    let mut got = vec![start; line.len()];
                    // SAFETY: the processor has AVX2; the slices are of one length.
                    unsafe { paint_row_avx2(&mut got, &line, with) };
                    prop_assert_eq!(&got, &want);
                }
            }
        }

        /// The vector z-test gives the scalar one's runs and counts, span for span, on
        /// spans crossing tiles and the screen's edges.
        #[test]
        fn every_kernel_draws_the_same_frame(
            spans in proptest::collection::vec(
                (0u32..140, 0u32..300, 0u32..80, -2.0f64..2.0, -0.1f64..0.1, 0usize..3),
                1..60,
            )
        ) {
            proptest::prop_assume!(ZTest::Avx2.available());
            let draw = |kernel: ZTest| {
                let mut rb = RegionBuffer::new(200, 130);
                rb.set_kernel(kernel);
                for &(y, x0, n, z, dz, c) in &spans {
                    rb.span(y, x0..x0 + n, z, dz, [R, G, B][c]);
                }
                let out = runs(&mut rb);
                (out, rb.stats)
            };
            proptest::prop_assert_eq!(draw(ZTest::Avx2), draw(ZTest::Scalar));
        }
    }

    #[test]
    fn a_piece_behind_a_covered_row_is_turned_away_whole() {
        let mut rb = RegionBuffer::new(100, 2);
        // Row 0 of the first tile covered at depth 1..1.63 (rising to the right); row 1
        // left with empty cells.
        rb.span(0, 0..64, 1.0, 0.01, R);
        rb.span(1, 0..63, 1.0, 0.0, R);
        let tested = rb.stats.pixels_tested;
        // Behind every bar: turned away without a test, nothing changes.
        rb.span(0, 10..40, 2.0, 0.0, G);
        assert_eq!(rb.stats.pixels_behind_row, 30);
        assert_eq!(rb.stats.pixels_tested, tested + 30);
        // A row with an empty cell is always tested (the empty cell takes any depth).
        rb.span(1, 0..64, 2.0, 0.0, G);
        assert_eq!(rb.stats.pixels_behind_row, 30);
        // Nearer than the farthest bar at one end only (the piece slopes): tested, and
        // taken where nearer.
        rb.span(0, 50..64, 1.499 - 50.0 * 0.02, 0.02, B);
        assert_eq!(rb.stats.pixels_behind_row, 30);
        assert_eq!(
            runs(&mut rb),
            [
                run(0, 0, 50, R),
                run(0, 50, 51, B),
                run(0, 51, 64, R),
                run(1, 0, 63, R),
                run(1, 63, 64, G)
            ]
        );
        // The next frame starts with no row covered.
        rb.span(0, 0..10, 5.0, 0.0, G);
        assert_eq!(rb.stats.pixels_behind_row, 30);
        assert_eq!(runs(&mut rb), [run(0, 0, 10, G)]);
    }

    #[test]
    fn frames_that_turn_little_away_stop_keeping_row_bars_but_look_again() {
        let mut rb = RegionBuffer::new(64, 1);
        // A covered row, then a piece behind it: turned away (the first frame keeps bars).
        let draw = |rb: &mut RegionBuffer| {
            rb.span(0, 0..64, 1.0, 0.0, R);
            rb.span(0, 0..64, 2.0, 0.0, G);
        };
        draw(&mut rb);
        assert_eq!(rb.stats.pixels_behind_row, 64);
        rb.clear();
        // Half of what it tested was turned away: the next frame keeps them too.
        draw(&mut rb);
        assert_eq!(rb.stats.pixels_behind_row, 128);
        // A frame that turns nothing away (each span nearer than the last)...
        rb.clear();
        for i in 0..20 {
            rb.span(0, 0..64, 1.0 - 0.01 * f64::from(i), 0.0, R);
        }
        assert_eq!(rb.stats.pixels_behind_row, 128);
        rb.clear();
        // ...stops the next ones keeping them (frames 3 to 15: the piece is tested, the
        // picture the same)...
        for frame in 3..16 {
            draw(&mut rb);
            assert_eq!(rb.stats.pixels_behind_row, 128, "frame {frame}");
            assert_eq!(runs(&mut rb), [run(0, 0, 64, R)]);
        }
        // ...until frame 16 looks again, and finds it pays.
        draw(&mut rb);
        assert_eq!(rb.stats.pixels_behind_row, 192);
        rb.clear();
        draw(&mut rb);
        assert_eq!(rb.stats.pixels_behind_row, 256);
    }

    proptest::proptest! {
        /// Turning pieces away by their tile row's farthest bar gives what testing every
        /// pixel gives: the runs of a plain per-pixel z-buffer (the tie rule's bar, an
        /// empty pixel taking any depth but NaN), over spans that cover whole rows and
        /// fall behind them, and spans whose depth runs out to ±∞.
        #[test]
        fn turning_pieces_away_changes_no_pixel(
            spans in proptest::collection::vec(
                (
                    0u32..3,
                    0u32..140,
                    1u32..140,
                    0.0f64..4.0,
                    // Slopes that overflow to ±∞ along the row, as well as gentle ones.
                    proptest::prop_oneof![
                        8 => -0.02f64..0.02,
                        1 => proptest::strategy::Just(3e306),
                        1 => proptest::strategy::Just(-3e306),
                    ],
                    0usize..3,
                ),
                1..80,
            )
        ) {
            let (w, h) = (140u32, 3u32);
            let mut rb = RegionBuffer::new(w, h);
            let mut bars = vec![0.0; (w * h) as usize];
            let mut cells = vec![None; (w * h) as usize];
            for &(y, x0, n, z, dz, c) in &spans {
                let colour = [R, G, B][c];
                rb.span(y, x0..x0 + n, z, dz, colour);
                for x in x0..(x0 + n).min(w) {
                    let i = (y * w + x) as usize;
                    let d = depth_at(z, dz, x);
                    if (cells[i].is_none() && !d.is_nan()) || d < bars[i] {
                        bars[i] = proto::depth::bar(d);
                        cells[i] = Some(colour);
                    }
                }
            }
            let mut want = vec![];
            for y in 0..h {
                let mut x = 0;
                while x < w {
                    let Some(c) = cells[(y * w + x) as usize] else { x += 1; continue };
                    let start = x;
                    while x < w && cells[(y * w + x) as usize] == Some(c) {
                        x += 1;
                    }
                    want.push(run(y, start, x, c));
                }
            }
            proptest::prop_assert_eq!(runs(&mut rb), want);
        }
    }

    #[test]
    fn an_error_from_emit_still_clears() {
        let mut rb = RegionBuffer::new(4, 2);
        rb.span(0, 0..1, 0.0, 0.0, R);
        rb.span(1, 0..1, 0.0, 0.0, G);
        let mut n = 0;
        assert_eq!(
            rb.finish_frame(|_| {
                n += 1;
                Err("full")
            }),
            Err("full")
        );
        assert_eq!(n, 1);
        assert_eq!(runs(&mut rb), []);
    }
}
