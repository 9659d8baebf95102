//! Optional depth buffer: caller-owned storage covering a rectangle (a whole target or one band).
//!
//! Depth is interpolated screen-linearly (as `z/w` after projection is): a plane with 32 extra
//! fraction bits anchored at pixel `(0, 0)`, rounded half up to an integer and clamped to the
//! range of the vertex depths. A run is split into maximal visible sub-runs, each emitted as its
//! own linear segments (with its own exact `s0`).

use super::setup::DepthPlane;
use super::{Counters, Depth, Rect};

/// Depth comparison: a pixel is visible if `new OP stored`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DepthFunc {
    /// Visible if strictly nearer (the first of equal depths wins).
    #[default]
    Less,
    /// Visible if nearer or equal (the last of equal depths wins).
    LessEqual,
    /// Always visible (depth is still written if enabled).
    Always,
}

impl DepthFunc {
    /// Whether a pixel at depth `new` passes against `stored`.
    pub const fn passes(self, new: Depth, stored: Depth) -> bool {
        match self {
            DepthFunc::Less => new < stored,
            DepthFunc::LessEqual => new <= stored,
            DepthFunc::Always => true,
        }
    }
}

/// Sets every element of `dst` to `v`, eight stores a turn: the per-element loop (or a
/// byte-wise `memset`) costs about three instructions an element on the devices, this about
/// one and a quarter. For depth buffers and bands of RGB565 pixels.
pub fn fill_u16(dst: &mut [u16], v: u16) {
    let mut chunks = dst.chunks_exact_mut(8);
    for c in &mut chunks {
        if let Ok(c) = <&mut [u16; 8]>::try_from(c) {
            *c = [v; 8];
        }
    }
    for d in chunks.into_remainder() {
        *d = v;
    }
}

/// A depth buffer over a rectangle of pixels, row-major, borrowed from the caller (any slice,
/// e.g. a `[u16; W * H]` array or one band's worth).
#[derive(Debug, PartialEq, Eq)]
pub struct DepthBuffer<'a> {
    data: &'a mut [Depth],
    rect: Rect,
}

impl<'a> DepthBuffer<'a> {
    /// A depth buffer for the pixels of `rect`, stored row-major in `data` (row stride
    /// `rect.width()`). Returns `None` if `data` is shorter than `width * height`.
    pub fn new(data: &'a mut [Depth], rect: Rect) -> Option<Self> {
        let need = rect.width() as usize * rect.height() as usize;
        if data.len() < need {
            return None;
        }
        Some(DepthBuffer { data, rect })
    }

    /// The rectangle covered.
    pub const fn rect(&self) -> Rect {
        self.rect
    }

    /// Moves the buffer to another rectangle of the same or smaller size (e.g. the next band),
    /// keeping the storage; returns `false` (and changes nothing) if the storage is too small.
    pub fn set_rect(&mut self, rect: Rect) -> bool {
        let need = rect.width() as usize * rect.height() as usize;
        if self.data.len() < need {
            return false;
        }
        self.rect = rect;
        true
    }

    /// Sets every depth to `value` (65535 = farthest).
    pub fn clear(&mut self, value: Depth) {
        let n = self.rect.width() as usize * self.rect.height() as usize;
        let n = n.min(self.data.len());
        if let Some(d) = self.data.get_mut(..n) {
            fill_u16(d, value);
        }
    }

    /// The stored depths, row-major over [`DepthBuffer::rect`] (textured-triangle path).
    #[cfg(feature = "atlas")]
    pub(crate) fn data_mut(&mut self) -> &mut [Depth] {
        self.data
    }

    fn index(&self, x: u16, y: u16) -> Option<usize> {
        if !self.rect.contains(x, y) {
            return None;
        }
        Some((y - self.rect.y0) as usize * self.rect.width() as usize + (x - self.rect.x0) as usize)
    }

    /// The stored depth at pixel `(x, y)`, if inside the rectangle.
    pub fn get(&self, x: u16, y: u16) -> Option<Depth> {
        self.index(x, y).and_then(|i| self.data.get(i).copied())
    }

    fn get_mut(&mut self, x: u16, y: u16) -> Option<&mut Depth> {
        self.index(x, y).and_then(move |i| self.data.get_mut(i))
    }
}

/// Depth-tests the covered pixels `[xa, xb)` of row `y` (inside the buffer's rectangle) and calls
/// `visible(y, x0, x1, counters)` for each visible sub-run `[x0, x1)`.
pub(crate) fn depth_run<V: FnMut(u16, u16, u16, &mut Counters)>(
    setup: &DepthPlane,
    depth: &mut DepthBuffer<'_>,
    y: u16,
    xa: u16,
    xb: u16,
    ctr: &mut Counters,
    mut visible_run: V,
) {
    let func = setup.func;
    let write = setup.write;
    let mut zp = setup.z.at(xa as i64, y as i64);
    let mut start: Option<u16> = None;
    for x in xa..xb {
        let z = (zp.wrapping_add(1 << 31) >> 32)
            .max(setup.zlo)
            .min(setup.zhi) as Depth;
        zp = zp.wrapping_add(setup.z.dx);
        let visible = match depth.get_mut(x, y) {
            Some(d) => {
                let pass = func.passes(z, *d);
                if pass && write {
                    *d = z;
                }
                pass
            }
            None => false,
        };
        match (visible, start) {
            (true, None) => start = Some(x),
            (false, Some(s)) => {
                visible_run(y, s, x, ctr);
                start = None;
            }
            _ => {}
        }
        if !visible {
            ctr.depth_failed = ctr.depth_failed.wrapping_add(1);
        }
    }
    if let Some(s) = start {
        visible_run(y, s, xb, ctr);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::super::*;
    use crate::format::TexPoint;
    use std::vec::Vec;

    /// Every element of every length (whole turns of eight, remainders, empty), and nothing
    /// past the slice.
    #[test]
    fn fill_u16_sets_every_element() {
        for n in 0..40usize {
            let mut buf = [0x5A5Au16; 48];
            fill_u16(&mut buf[..n], 0xBEEF);
            assert!(buf[..n].iter().all(|&v| v == 0xBEEF), "n = {n}");
            assert!(buf[n..].iter().all(|&v| v == 0x5A5A), "n = {n}");
        }
    }

    fn quad(x0: i32, y0: i32, x1: i32, y1: i32, z: [u16; 4]) -> [[ScreenVertex; 3]; 2] {
        let v = |x: i32, y: i32, z: u16| {
            ScreenVertex::from_bits(
                16 * x,
                16 * y,
                z,
                1 << 30,
                TexPoint::from_bits(x, y, z as i32),
            )
        };
        let (a, b, c, d) = (
            v(x0, y0, z[0]),
            v(x1, y0, z[1]),
            v(x1, y1, z[2]),
            v(x0, y1, z[3]),
        );
        [[a, b, c], [a, c, d]]
    }

    /// Draws quads in order with a depth buffer; returns, per pixel, the index of the quad
    /// whose segment last covered it (segments of hidden pixels must not be emitted).
    fn draw(quads: &[[[ScreenVertex; 3]; 2]], opts: TriangleOptions, clip: Rect) -> Vec<u8> {
        let mut store = [0u16; 32 * 32];
        let mut db = DepthBuffer::new(&mut store, clip).unwrap();
        db.clear(u16::MAX);
        let mut r = Rasterizer::new(Rect::from_size(32, 32));
        let mut owner = std::vec![0u8; 32 * 32];
        for (k, q) in quads.iter().enumerate() {
            for t in q {
                r.draw_depth(t, &opts, &mut db, &mut |s: &Segment| {
                    for i in 0..s.len {
                        owner[s.y as usize * 32 + (s.x0 + i) as usize] = k as u8 + 1;
                    }
                });
            }
        }
        owner
    }

    #[test]
    fn nearer_wins_in_either_order() {
        let far = quad(2, 2, 20, 20, [1000; 4]);
        let near = quad(10, 10, 28, 28, [500; 4]);
        for opts in [
            TriangleOptions::new(Perspective::Affine),
            TriangleOptions::new(Perspective::Every8),
        ] {
            let a = draw(&[far, near], opts, Rect::from_size(32, 32));
            let b = draw(&[near, far], opts, Rect::from_size(32, 32));
            for y in 0..32 {
                for x in 0..32 {
                    let in_far = (2..20).contains(&x) && (2..20).contains(&y);
                    let in_near = (10..28).contains(&x) && (10..28).contains(&y);
                    let expect = if in_near {
                        2
                    } else if in_far {
                        1
                    } else {
                        0
                    };
                    assert_eq!(a[y * 32 + x], expect, "{x} {y}");
                    // Drawn the other way round, indices swap.
                    let expect_b = [0, 2, 1][expect as usize];
                    assert_eq!(b[y * 32 + x], expect_b, "{x} {y}");
                }
            }
        }
    }

    #[test]
    fn interpenetrating_planes_split_runs() {
        // Quad A's depth grows left to right, quad B's shrinks: they cross at the middle
        // column, so each row of the second quad is split into a hidden and a visible part.
        let a = quad(0, 0, 32, 8, [0, 32 * 1000, 32 * 1000, 0]);
        let b = quad(0, 0, 32, 8, [32 * 1000, 0, 0, 32 * 1000]);
        let owner = draw(
            &[a, b],
            TriangleOptions::new(Perspective::Exact),
            Rect::from_size(32, 32),
        );
        for y in 0..8 {
            for x in 0..32 {
                // z_A = 1000 (x + 0.5), z_B = 1000 (31.5 - x): B is nearer for x >= 16.
                let expect = if x >= 16 { 2 } else { 1 };
                assert_eq!(owner[y * 32 + x], expect, "{x} {y}");
            }
        }
        // A visible sub-run's first segment starts with its own exact s0: pixel 16 of B.
        let mut store = [u16::MAX; 32 * 8];
        let mut db = DepthBuffer::new(&mut store, Rect::from_size(32, 8)).unwrap();
        let mut r = Rasterizer::new(Rect::from_size(32, 8));
        let o = TriangleOptions::new(Perspective::Affine);
        for t in &a {
            r.draw_depth(t, &o, &mut db, &mut |_: &Segment| {});
        }
        let mut segs = Vec::new();
        for t in &b {
            r.draw_depth(t, &o, &mut db, &mut |s: &Segment| segs.push(*s));
        }
        assert_eq!(r.counters().depth_failed, 8 * 16);
        for s in &segs {
            assert!(s.x0 >= 16, "{s:?}");
            // s = x raw units (from the vertex data): s0 = round(x0 + 0.5) in raw units.
            let twice = 2 * s.s0.s.to_bits() as i64;
            assert!((twice - (2 * s.x0 as i64 + 1)).abs() <= 1, "{s:?}");
        }
    }

    #[test]
    fn depth_is_screen_linear_rounded_to_nearest() {
        // z at each covered pixel centre is the screen-linear interpolation rounded to nearest
        // (within 1/2 plus the plane's negligible error).
        let v = [
            ScreenVertex::from_bits(13, 7, 100, 1 << 30, TexPoint::ZERO),
            ScreenVertex::from_bits(500, 90, 65535, 1 << 30, TexPoint::ZERO),
            ScreenVertex::from_bits(77, 511, 4321, 1 << 30, TexPoint::ZERO),
        ];
        let mut store = [u16::MAX; 32 * 32];
        let mut db = DepthBuffer::new(&mut store, Rect::from_size(32, 32)).unwrap();
        let mut o = TriangleOptions::new(Perspective::Affine);
        o.depth_func = DepthFunc::Always;
        let mut r = Rasterizer::new(Rect::from_size(32, 32));
        let mut covered = std::vec![false; 32 * 32];
        r.draw_depth(&v, &o, &mut db, &mut |s: &Segment| {
            for i in 0..s.len {
                covered[s.y as usize * 32 + (s.x0 + i) as usize] = true;
            }
        });
        let p = v.map(|p| {
            [
                p.x.to_bits() as f64 / 16.0,
                p.y.to_bits() as f64 / 16.0,
                p.z as f64,
            ]
        });
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        let mut n = 0;
        for y in 0..32u16 {
            for x in 0..32u16 {
                if !covered[y as usize * 32 + x as usize] {
                    continue;
                }
                let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                let mut z = 0.0;
                for i in 0..3 {
                    let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                    let e = (p[j][0] - cx) * (p[k][1] - cy) - (p[k][0] - cx) * (p[j][1] - cy);
                    z += e / area * p[i][2];
                }
                let got = db.get(x, y).unwrap() as f64;
                assert!((got - z).abs() <= 0.5 + 1e-6, "{x} {y} {got} {z}");
                n += 1;
            }
        }
        assert!(n > 100);
    }

    #[test]
    fn buffer_bounds_and_bands() {
        let mut small = [0u16; 10];
        assert!(DepthBuffer::new(&mut small, Rect::from_size(4, 4)).is_none());
        let mut store = [0u16; 16];
        let mut db = DepthBuffer::new(&mut store, Rect::new(0, 4, 4, 8)).unwrap();
        db.clear(7);
        assert_eq!(db.get(0, 4), Some(7));
        assert_eq!(db.get(0, 3), None);
        assert!(!db.set_rect(Rect::new(0, 0, 5, 4)));
        assert!(db.set_rect(Rect::new(0, 8, 4, 12)));
        assert_eq!(db.get(3, 11), Some(7));
    }

    #[test]
    fn banded_depth_equals_full_frame() {
        let quads = [
            quad(1, 1, 25, 30, [100, 900, 5000, 3000]),
            quad(5, 3, 31, 20, [4000, 200, 700, 100]),
            quad(0, 12, 30, 31, [50, 6000, 50, 6000]),
        ];
        let opts = TriangleOptions::new(Perspective::Every8);
        let full = draw(&quads, opts, Rect::from_size(32, 32));
        // Bands of 5 rows with a band-sized depth buffer.
        let mut owner = std::vec![0u8; 32 * 32];
        let mut store = [0u16; 32 * 5];
        let mut r = Rasterizer::new(Rect::from_size(32, 32));
        for band in 0..7u16 {
            let rect = Rect::new(0, band * 5, 32, (band * 5 + 5).min(32));
            let mut db = DepthBuffer::new(&mut store, rect).unwrap();
            db.clear(u16::MAX);
            r.set_clip(rect);
            for (k, q) in quads.iter().enumerate() {
                for t in q {
                    r.draw_depth(t, &opts, &mut db, &mut |s: &Segment| {
                        assert!(rect.contains(s.x0, s.y));
                        for i in 0..s.len {
                            owner[s.y as usize * 32 + (s.x0 + i) as usize] = k as u8 + 1;
                        }
                    });
                }
            }
        }
        assert_eq!(owner, full);
    }

    /// `draw_depth` sets a triangle's texture planes up only at its first visible run, and
    /// emits exactly the segments of a complete set-up drawn with `draw_setup_depth`.
    #[test]
    fn hidden_triangles_set_no_texture_planes_up() {
        let near = quad(2, 2, 30, 30, [100; 4]);
        let far = quad(4, 4, 20, 20, [9000; 4]);
        // A bounding box over the centres of pixels (0, 0) and (1, 0), but a triangle (raw
        // 1/16 pixel: x 9..23, y 0..12) between them: it covers no pixel centre.
        let sliver = [
            ScreenVertex::from_bits(9, 0, 50, 1 << 30, TexPoint::ZERO),
            ScreenVertex::from_bits(23, 0, 50, 1 << 30, TexPoint::ZERO),
            ScreenVertex::from_bits(16, 12, 50, 1 << 30, TexPoint::ZERO),
        ];
        for opts in [
            TriangleOptions::new(Perspective::Affine),
            TriangleOptions::new(Perspective::Every16),
        ] {
            let clip = Rect::from_size(32, 32);
            let run = |lazy: bool| {
                let mut store = [0u16; 32 * 32];
                let mut db = DepthBuffer::new(&mut store, clip).unwrap();
                db.clear(u16::MAX);
                let mut r = Rasterizer::new(clip);
                let mut segs = Vec::new();
                for t in near.iter().chain(&far).chain([&sliver]) {
                    let mut sink = |s: &Segment| segs.push(*s);
                    if lazy {
                        r.draw_depth(t, &opts, &mut db, &mut sink);
                    } else if let Ok(setup) = r.setup(t, &opts) {
                        r.draw_setup_depth(&setup, &mut db, &mut sink);
                    }
                }
                (segs, r.counters())
            };
            let (lazy, lc) = run(true);
            let (eager, ec) = run(false);
            assert_eq!(lazy, eager);
            assert_eq!((lc.setups, ec.setups), (5, 5));
            // The far quad is hidden and the sliver covers no centre: only the near quad's two
            // triangles get texture planes.
            assert_eq!(lc.texture_setups, 2);
            assert_eq!(ec.texture_setups, 5);
            assert!(lc.depth_failed > 0);
            assert_eq!(
                lc.pixels,
                eager.iter().map(|s| u64::from(s.len)).sum::<u64>()
            );
        }
    }
}
