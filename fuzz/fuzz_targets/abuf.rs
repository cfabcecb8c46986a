//! The a-buffer's fragment lists (sampling thesis 6.3.4 to 6.3.6; scan/src/abuf/list.rs), and
//! the whole method on arbitrary screen polygons.
//!
//! Lists: fragments of arbitrary masks, depths, colours and order inserted one by one.
//! No panic; the list stays sorted by (zmin, order), holds nothing behind an earlier
//! fully covering fragment, and a simple pixelstruct holds one full fragment; the packed
//! colour lies within the fragments' and background's colours. When every fragment has
//! one depth (zmin = zmax; nothing intersects), the packed colour is exactly the
//! box-filtered per-sample answer: each sample shows the covering fragment of least
//! (depth, order), or the background.
//!
//! Lists past [`scan::abuf::list::MAX_LIST`] merge their farthest fragments: never longer.
//!
//! Frames: polygons through `ABuffer::resolve` on screens up to 24×24: no panic, each
//! pixel sent once (image_of checks), exactly the pixels with a covered sample, and the
//! same runs with the cull as without it.
#![no_main]
use scan::abuf::list::{Fragment, ListStats, Packer, PixelStruct};
use scan::abuf::ABuffer;
use libfuzzer_sys::fuzz_target;
use polypipe_fuzz::{polygon, Bytes};
use proto::Vertex;
use scan::frame::{image_of, HiddenSurface};

fn lists(b: &mut Bytes) {
    let flat = b.u8() & 1 == 0;
    let background = [b.u8(), b.u8(), b.u8()];
    let palette = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
    let mut frags = Vec::new();
    let mut i = 0u32;
    // Up to 96: past 64 (list::MAX_LIST) the farthest fragments merge.
    while !b.is_empty() && frags.len() < 96 {
        let mask = match b.u8() % 4 {
            0 => u64::MAX,
            1 => b.u64(),
            2 => (b.u8() as u64) << (8 * (b.u8() % 8)),
            _ => !(1u64 << (b.u8() % 64)),
        };
        // Depths as the f64 depth form has them: a few small values (ties),
        // extremes, and any finite number.
        let zmin = match b.u8() % 3 {
            0 => (b.u8() % 8) as f64 * 0.125,
            1 => -f64::MAX + (b.u8() as f64) * 1e292,
            _ => {
                let z = f64::from_bits(b.u64());
                if z.is_finite() {
                    z
                } else {
                    0.0
                }
            }
        };
        // As scan's depths are: never -0 (DepthPlane::row adds +0.0), which total_cmp
        // would order before 0 and so before an earlier fragment at the same depth.
        let zmin = zmin + 0.0;
        let zmax = if flat {
            zmin
        } else {
            let z = zmin + (b.u8() % 16) as f64 * 0.0625;
            if z.is_finite() {
                z
            } else {
                zmin
            }
        };
        let colour = if b.u8() & 1 == 0 {
            palette[(b.u8() % 4) as usize]
        } else {
            [b.u8(), b.u8(), b.u8()]
        };
        // Increasing, as polygons come in stream order, with gaps.
        let order = (i << 8) | b.u8() as u32;
        i += 1;
        if mask != 0 {
            frags.push(Fragment {
                colour,
                mask,
                zmin,
                zmax,
                order,
                opacity: proto::OPAQUE,
            });
        }
    }
    let (mut pool, mut stats) = (Vec::new(), ListStats::default());
    let mut p = PixelStruct::Empty;
    for f in &frags {
        p.insert(*f, &mut pool, &mut stats);
        let list = p.fragments();
        for pair in list.windows(2) {
            assert!(
                pair[0]
                    .zmin
                    .total_cmp(&pair[1].zmin)
                    .then(pair[0].order.cmp(&pair[1].order))
                    .is_le(),
                "{list:?}"
            );
        }
        for (k, g) in list.iter().enumerate() {
            if g.mask == u64::MAX {
                for x in &list[k + 1..] {
                    assert!(
                        !(x.zmin > g.zmax || (x.zmin == g.zmax && x.order > g.order)),
                        "{x:?} behind {g:?} kept"
                    );
                }
            }
        }
        if let PixelStruct::Simple(s) = &p {
            assert_eq!(s.mask, u64::MAX);
        }
    }
    let got = p.pack(background, &mut Packer::default(), &mut stats);
    assert_eq!(got.is_some(), !frags.is_empty());
    let Some(got) = got else { return };
    for ch in 0..3 {
        let values = frags.iter().map(|f| f.colour[ch]).chain([background[ch]]);
        let (lo, hi) = (values.clone().min().unwrap(), values.max().unwrap());
        assert!(
            lo <= got[ch] && got[ch] <= hi,
            "{got:?} out of range, {frags:?}"
        );
    }
    assert!(stats.max_list <= scan::abuf::list::MAX_LIST as u64);
    if flat && stats.merged == 0 {
        let mut sum = [0u32; 3];
        for s in 0..64 {
            let front = frags
                .iter()
                .filter(|f| f.mask >> s & 1 == 1)
                .min_by(|f, g| f.zmin.total_cmp(&g.zmin).then(f.order.cmp(&g.order)));
            let c = front.map_or(background, |f| f.colour);
            for (t, v) in sum.iter_mut().zip(c) {
                *t += v as u32;
            }
        }
        let want = sum.map(|t| ((t + 32) / 64) as u8);
        assert_eq!(got, want, "{frags:?}");
    }
}

fn frame(b: &mut Bytes) {
    let width = 1 + (b.u8() % 24) as u32;
    let height = 1 + (b.u8() % 24) as u32;
    let mut polys = Vec::new();
    while !b.is_empty() && polys.len() < 8 {
        let mut p = polygon(b, |b| {
            let c = |b: &mut Bytes| {
                if b.u8() % 8 == 0 {
                    b.f64()
                } else {
                    b.grid() + 8.0
                }
            };
            Vertex::new(c(b), c(b), b.coord(), 1.0)
        });
        if b.u8() % 4 == 0 {
            p.plane = Some(Vertex::new(b.coord(), b.coord(), b.coord(), b.coord()));
        }
        if scan::check_on_screen(&p, width, height).is_ok() {
            polys.push(p);
        }
    }
    let mut runs = Vec::new();
    let background = [b.u8(), b.u8(), b.u8()];
    ABuffer::new(background).resolve(&polys, width, height, &mut runs);
    let image = image_of(&runs, width, height);
    // The cull leaves out only what would be thrown away: the same runs without it.
    let mut uncut = Vec::new();
    ABuffer::without_cull(background).resolve(&polys, width, height, &mut uncut);
    assert_eq!(runs, uncut);
    // The pixels sent are those with a covered sample: the z-buffer of the 8-times-finer
    // screen says which.
    let fine: Vec<_> = polys.iter().map(|p| scan::fine::scaled(p, 8)).collect();
    let samples = scan::frame::zbuffer_image(&fine, width * 8, height * 8);
    for y in 0..height {
        for x in 0..width {
            let covered = (0..64)
                .any(|s| samples[((y * 8 + s / 8) * width * 8 + x * 8 + s % 8) as usize].is_some());
            assert_eq!(
                image[(y * width + x) as usize].is_some(),
                covered,
                "({x}, {y})"
            );
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    if b.u8() & 1 == 0 {
        lists(&mut b);
    } else {
        frame(&mut b);
    }
});
