//! Memory for the big buffers of a frame: zeroed by the kernel as it is first touched,
//! and laid out so that the kernel can back it with transparent huge pages.
//!
//! A full-HD region buffer is 25 MB and its F-buffer 6 MB. Faulted in 4 KiB pages, that
//! is some 7,500 page faults a frame buffer, each a trap into the kernel: on the
//! fill-heavy scene a quarter of the leaf's time. `madvise(MADV_HUGEPAGE)` asks for 2 MiB
//! pages, but the kernel can give one only for a whole 2 MiB of address space aligned to
//! 2 MiB, and the allocator's block starts anywhere: the part-pages at its two ends (up
//! to 4 MiB a buffer) still came in 4 KiB at a time, half of zbuf's faults on that scene.
//! So a buffer of a huge page or more is reserved with room to start its first cell on a
//! huge page's boundary, and, where rounding its end up to the next boundary costs at
//! most a 32nd of its size, to end on one; the pad is address space, never touched.

/// A transparent huge page of x86-64 (and most other 64-bit machines), in bytes.
pub const HUGE_PAGE: usize = 2 << 20;

/// Cell types whose all-zero bytes are their `Default` value (0.0, 0, black), so that
/// cells in zeroed memory need no writing.
///
/// # Safety
///
/// All-zero bytes must be a valid value of the type.
pub unsafe trait ZeroIsDefault: Copy + Default {}
// SAFETY: all-zero bytes are 0.0.
unsafe impl ZeroIsDefault for f64 {}
// SAFETY: all-zero bytes are 0.
unsafe impl ZeroIsDefault for u32 {}
// SAFETY: all-zero bytes are [0, 0, 0].
unsafe impl ZeroIsDefault for [u8; 3] {}

/// An empty vector with room for `n` cells in zeroed memory, or `None` where the
/// allocator cannot give it. For a large `n` the allocator maps fresh pages, which the
/// kernel zeroes only when they are first touched, and writes nothing itself.
fn zeroed_vec<T: ZeroIsDefault>(n: usize) -> Option<Vec<T>> {
    let layout = std::alloc::Layout::array::<T>(n).ok()?;
    if layout.size() == 0 {
        return None;
    }
    // SAFETY: the layout has a non-zero size.
    let p = unsafe { std::alloc::alloc_zeroed(layout) } as *mut T;
    if p.is_null() {
        return None;
    }
    // SAFETY: `p` was allocated by the global allocator with the layout of `n` cells of
    // T (so capacity `n`, T's alignment), and no cell is claimed initialised (length 0).
    Some(unsafe { Vec::from_raw_parts(p, 0, n) })
}

/// Room for `n` cells of zeroed memory whose first cell lies on a boundary of `align`
/// bytes (a huge page's instead, for `n` cells of a huge page or more): a vector whose
/// length is the number of pad cells before that first cell (all zero, never touched),
/// with capacity for the `n` after them, and huge pages asked for. `None` where the
/// allocator cannot give it. `align` must be a multiple of T's size.
pub(crate) fn reserve_aligned<T: ZeroIsDefault>(n: usize, align: usize) -> Option<Vec<T>> {
    let cells = reserve_unadvised(n, align)?;
    advise_huge_pages(&cells);
    Some(cells)
}

/// [`reserve_aligned`] without asking for huge pages: for a caller that asks page by
/// page ([`advise_huge_page`]) as it comes to use them.
pub(crate) fn reserve_unadvised<T: ZeroIsDefault>(n: usize, align: usize) -> Option<Vec<T>> {
    let size = std::mem::size_of::<T>().max(1);
    let bytes = n.checked_mul(size)?;
    let huge = bytes >= HUGE_PAGE;
    let align = if huge { HUGE_PAGE } else { align };
    // The end rounded up to a huge page where that adds little: the last part-page is
    // then a huge page too, with its unused tail zeroed by the kernel but never read.
    let tail = (HUGE_PAGE - bytes % HUGE_PAGE) % HUGE_PAGE;
    let extra = if huge && tail <= bytes / 32 {
        tail.div_ceil(size)
    } else {
        0
    };
    let mut cells = zeroed_vec::<T>(n.checked_add(align.div_ceil(size))?.checked_add(extra)?)?;
    let start = ((cells.as_ptr() as usize).wrapping_neg() % align).div_ceil(size);
    // SAFETY: `start` cells lie within the capacity (the pad reserved for them), in
    // memory the allocator zeroed, and all-zero bytes are a valid T.
    unsafe { cells.set_len(start) };
    Some(cells)
}

/// Asks for transparent huge pages over a vector's reserved capacity (whole 2 MiB pages
/// inside it), before it is written. A hint: ignored where the kernel has them off,
/// harmless where it has them always on.
pub fn advise_huge_pages<T>(cells: &Vec<T>) {
    let start = cells.as_ptr() as usize;
    let end = start + cells.capacity() * std::mem::size_of::<T>();
    let (from, to) = (
        start.next_multiple_of(HUGE_PAGE),
        end / HUGE_PAGE * HUGE_PAGE,
    );
    if to > from {
        // SAFETY: madvise only advises the kernel about the pages of a range this vector
        // owns (reserved and not yet written); it reads and writes no memory.
        unsafe {
            libc::madvise(from as *mut libc::c_void, to - from, libc::MADV_HUGEPAGE);
        }
    }
}

/// Asks for a transparent huge page over the 2 MiB at `page` (a huge page's boundary),
/// memory not yet written: a hint, as [`advise_huge_pages`].
pub(crate) fn advise_huge_page(page: *const u8) {
    debug_assert!((page as usize).is_multiple_of(HUGE_PAGE));
    // SAFETY: madvise only advises the kernel about the pages of the range; it reads and
    // writes no memory. A range not wholly mapped is refused (ENOMEM), changing nothing
    // that matters: the caller passes one inside a vector's capacity.
    unsafe {
        libc::madvise(page as *mut libc::c_void, HUGE_PAGE, libc::MADV_HUGEPAGE);
    }
}

/// `n` cells, all zero, in memory laid out for huge pages ([`reserve_aligned`]): a
/// frame's F-buffer. Derefs to the cells.
pub struct ZeroedBuffer<T> {
    cells: Vec<T>,
    start: usize,
}

impl<T: ZeroIsDefault> ZeroedBuffer<T> {
    /// `n` zero cells, or `None` where the memory cannot be had.
    pub fn new(n: usize) -> Option<Self> {
        if n == 0 {
            return Some(ZeroedBuffer {
                cells: Vec::new(),
                start: 0,
            });
        }
        let mut cells = reserve_aligned::<T>(n, std::mem::align_of::<T>())?;
        let start = cells.len();
        // SAFETY: the capacity holds `start + n` cells, all in memory the allocator
        // zeroed, and all-zero bytes are a valid T.
        unsafe { cells.set_len(start + n) };
        Some(ZeroedBuffer { cells, start })
    }
}

impl<T> std::ops::Deref for ZeroedBuffer<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.cells[self.start..]
    }
}

impl<T> std::ops::DerefMut for ZeroedBuffer<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.cells[self.start..]
    }
}

impl<T: ZeroIsDefault> Clone for ZeroedBuffer<T> {
    fn clone(&self) -> Self {
        // Only where allocation fails would `new` give nothing: as `Vec::clone`, abort.
        let mut copy = ZeroedBuffer::new(self.len()).expect("memory for a buffer's copy");
        copy.copy_from_slice(self);
        copy
    }
}

impl<T: std::fmt::Debug> std::fmt::Debug for ZeroedBuffer<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ZeroedBuffer")
            .field("len", &(self.cells.len() - self.start))
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_big_buffer_starts_on_a_huge_page_and_is_zero() {
        // 3-byte cells: the first one starts within two bytes after a boundary (a
        // boundary is not a multiple of 3 from wherever the allocator put the block).
        let n = 1920 * 1080;
        let b = ZeroedBuffer::<[u8; 3]>::new(n).expect("memory");
        assert_eq!(b.len(), n);
        assert!((b.as_ptr() as usize) % HUGE_PAGE < 3);
        assert!(b.iter().all(|&c| c == [0; 3]));
        let f = ZeroedBuffer::<f64>::new(HUGE_PAGE / 8 + 1).expect("memory");
        assert_eq!((f.as_ptr() as usize) % HUGE_PAGE, 0);
    }

    #[test]
    fn a_small_buffer_keeps_the_alignment_asked() {
        let v = reserve_aligned::<u32>(1000, 64).expect("memory");
        assert!(v.len() < 16);
        assert_eq!((v.as_ptr() as usize + 4 * v.len()) % 64, 0);
        assert!(v.capacity() >= v.len() + 1000);
        assert_eq!(ZeroedBuffer::<u32>::new(0).expect("empty").len(), 0);
    }

    #[test]
    fn a_clone_has_the_cells() {
        let mut b = ZeroedBuffer::<u32>::new(5).expect("memory");
        b[3] = 7;
        let c = b.clone();
        assert_eq!(&c[..], &[0, 0, 0, 7, 0]);
    }
}
