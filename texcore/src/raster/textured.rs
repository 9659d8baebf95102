//! Textured triangles: a triangle drawn straight into an RGB565 colour band from an RGB565
//! texture with nearest look-ups (the draw of a meshed texture atlas), without segments, the
//! perspective planes or the texture pipeline.
//!
//! # Guarantees
//!
//! - **Coverage and depth** are exactly those of [`Rasterizer::draw_depth`]: the same set-up
//!   (guard band, area, culling, top-left fill rule, depth plane, depth test and write).
//! - **Texture coordinates** are the vertices' `tex.x`, `tex.y` (raw `Q16.16` texels), taken to
//!   `f = 15 - log2(side)` fraction bits (clamped to the texture), and interpolated
//!   perspective-correctly at **every pixel** by the homogeneous ratio
//!   `u = N / D = (sum_i E_i q_i u_i) / (sum_i E_i q_i)` of the barycentric edge functions `E_i`
//!   (no division by the area: it cancels). `N` and `D` are planes with exact integer
//!   coefficients (scaled so that `D < 2^48`). Their *texel words* `N' = floor(N / 2^32)`,
//!   `D' = floor(D / 2^24)` (whose quotient is the coordinate in units of `2^(8 - f)` texel)
//!   are set up once a triangle at an anchor pixel, the top-left corner of its pixel box
//!   clamped to pixel `(0, 0)`, with the words of the planes' steps; each run of a row starts
//!   from them and steps them in 32 bits, and each pixel divides them on the 32-bit hardware
//!   divide. `q_i` is `1/w` normalised to 15 bits (the largest in `[2^14, 2^15)`; all equal for
//!   [`Perspective::Affine`]), so `D' >= 2^22 / r` with `r = max q_i / min q_i`. At a pixel
//!   `a` columns right of and `b` rows below the anchor each word is within `1 + a + b` units
//!   below its exact value, so the quotient is within about `side (1 + a + b) r 2^-22` texel of
//!   the real-arithmetic ratio of the quantised vertex data (`a + b <= px + py`; for the
//!   128-texel atlas `(1 + a + b) r 2^-15` texel: 1/64 texel at `a + b = 63`, `r = 8`). The
//!   texel read is `(floor(v), floor(u))`, clamped to the texture.
//! - **Fallback**: a triangle with a normalised `q_i` of 0 (ratio past `2^15`), a doubled area
//!   of `2^32` raw units or more, or edge functions past `i32` (far outside a small target) is
//!   drawn through [`Rasterizer::draw_depth`] (segments with `Every16`-style perspective, as
//!   the triangle's options say) with the same nearest look-up of each segment pixel.
//! - Integer arithmetic only, the same code on every target: host = device bit for bit. Never
//!   panics; a colour band shorter than the depth buffer's rectangle draws nothing.

use super::setup::CoverDepth;
use super::small::{depth_bias, draw_small, Small, SmallRun};
use super::{DepthBuffer, Perspective, Rasterizer, ScreenVertex, Segment, TriangleOptions};

/// An RGB565 texture of `SIDE x SIDE` texels (`SIDE` a power of two, 1 to 128), row-major:
/// the side in the type, so that the texel look-ups of [`Rasterizer::draw_textured`] know the
/// texture's length, its clamp and its row shift as constants. Built by [`Texture565::new`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Texture565<'a, const SIDE: usize> {
    /// Exactly `SIDE * SIDE` texels.
    texels: &'a [u16],
}

impl<'a, const SIDE: usize> Texture565<'a, SIDE> {
    /// `log2(SIDE)` (for a valid side).
    const LOG2: u32 = SIDE.trailing_zeros();

    /// The texture of `texels` (`SIDE * SIDE` of them, row-major); `None` unless `SIDE` is a
    /// power of two from 1 to 128 and `texels.len() == SIDE * SIDE`.
    pub fn new(texels: &'a [u16]) -> Option<Texture565<'a, SIDE>> {
        if !SIDE.is_power_of_two() || SIDE > 128 || texels.len() != SIDE * SIDE {
            return None;
        }
        Some(Texture565 { texels })
    }

    /// Side in texels.
    pub const fn side(&self) -> u16 {
        SIDE as u16
    }

    /// Fraction bits of the interpolated coordinates (`15 - log2(SIDE)`, 8 to 15).
    const fn frac(&self) -> u32 {
        15u32.saturating_sub(Self::LOG2)
    }

    /// The texel at raw `Q16.16` coordinates `(u, v)`, nearest, clamped.
    #[inline]
    fn nearest_q16(&self, u: i32, v: i32) -> u16 {
        let max = SIDE as i32 - 1;
        let tu = (u >> 16).max(0).min(max) as usize;
        let tv = (v >> 16).max(0).min(max) as usize;
        self.texels
            .get((tv << Self::LOG2) | tu)
            .copied()
            .unwrap_or(0)
    }
}

/// Number of significant bits of `v`.
const fn bitlen(v: u64) -> u32 {
    64 - v.leading_zeros()
}

/// The per-triangle state of the homogeneous interpolation: planes `[c, dx, dy]` (at the centre
/// of pixel `(0, 0)`, per pixel) of `N_u`, `N_v` and `D`, all scaled by `2^k` so that `D < 2^48`
/// and `N < 2^63` at every covered pixel.
struct Homogeneous {
    planes: [[i64; 3]; 3],
}

impl Homogeneous {
    /// The planes of a prepared triangle (its edge functions, vertex `1/w`, texture coordinates
    /// and doubled area) for texture `tx`; `None` when the fast path does not apply.
    fn new<const SIDE: usize>(
        pre: &CoverDepth,
        v: &[ScreenVertex; 3],
        affine: bool,
        tx: &Texture565<'_, SIDE>,
    ) -> Option<Homogeneous> {
        let ((e, narrow), area2) = (pre.edges(), pre.area2());
        let inv_w = v.map(|p| p.inv_w.to_bits());
        let tex = v.map(|p| p.tex.to_bits().map(i64::from));
        let mag = u32::try_from(area2.unsigned_abs()).ok()?;
        if !narrow || mag == 0 {
            return None;
        }
        let qmax = inv_w.iter().copied().max().unwrap_or(0);
        let q = if affine || qmax == 0 {
            [1u32 << 14; 3]
        } else {
            let b = bitlen(u64::from(qmax));
            inv_w.map(|w| if b > 15 { w >> (b - 15) } else { w << (15 - b) })
        };
        if q.contains(&0) {
            return None;
        }
        // D <= |area2| q_max < 2^(bitlen + 15): scaled by 2^k, k = 33 - bitlen >= 1, below 2^48.
        let k = 33 - bitlen(u64::from(mag));
        let f = tx.frac();
        let top = (1i64 << 15) - 1;
        let coord = |t: i64| (t >> (16 - f)).max(0).min(top);
        let neg = area2 < 0;
        let mut w = [[0i64; 3]; 3];
        for ((wi, qi), t) in w.iter_mut().zip(q).zip(tex) {
            let qi = i64::from(qi);
            // q u < 2^30; scaled < 2^63 - 2^33.
            let ws = [qi * coord(t[0]), qi * coord(t[1]), qi].map(|x| x << k);
            *wi = if neg { ws.map(i64::wrapping_neg) } else { ws };
        }
        let mut planes = [[0i64; 3]; 3];
        for (j, plane) in planes.iter_mut().enumerate() {
            for (c, out) in plane.iter_mut().enumerate() {
                // Ring arithmetic modulo 2^64: exact wherever the true value fits (every covered
                // pixel, where E_i >= 0 sum to |area2|).
                *out = e.iter().zip(&w).fold(0i64, |acc, (ei, wi)| {
                    let (a, b) = (
                        ei.get(c).copied().unwrap_or(0),
                        wi.get(j).copied().unwrap_or(0),
                    );
                    acc.wrapping_add(a.wrapping_mul(b))
                });
            }
        }
        Some(Homogeneous { planes })
    }
}

/// The 32-bit *texel words* of the homogeneous planes' values `hom = [N_u, N_v, D]` (scaled as
/// [`Homogeneous`] scales them: `D < 2^48`, `N < 2^63` at a covered pixel): `[N_u >> 32,
/// N_v >> 32, D >> 24]` (floors; below `2^31` and `2^24`), whose quotient `N' / D'` is the
/// coordinate in units of `2^(8 - f)` texel. Each word is a function of its value modulo
/// `2^64` (bits 32.. or 24.. of it, wrapped to 32 bits), so the words of wrapping sums are the
/// wrapping sums of the words up to their floors' carries ([`anchored_words`]).
#[inline(always)]
pub(crate) fn texel_words(hom: [i64; 3]) -> [i32; 3] {
    let [nu, nv, dd] = hom;
    [(nu >> 32) as i32, (nv >> 32) as i32, (dd >> 24) as i32]
}

/// The texel words of a triangle's homogeneous planes `[N_u, N_v, D]` (each `[c, dx, dy]` at
/// pixel `(0, 0)`, scaled as [`Homogeneous`]), as `[at the anchor, dx, dy]` each, and the
/// anchor ([`anchor`]): the top-left corner of the triangle's pixel box clamped to the pixels
/// of any target. A covered
/// pixel `(px, py)` then lies `a = px - ax >= 0` and `b = py - ay >= 0` pixels from it, and its
/// words `w + a wx + b wy` (wrapping `i32`) are each within `1 + a + b` units below the floors
/// of its exact values (the floors of the anchor's values and of the steps each lose less than
/// a unit; the sum's true value fits `i32`, so the wrapping sum is it): with `D' >= 2^22 / r`
/// (`q_i` normalised, `r = max q_i / min q_i`), the quotient is within about
/// `side (1 + a + b) r 2^-22` texel of the exact ratio (`a + b <= px + py`). The small and the
/// wide path take the same integers here, so their pixels are the same.
#[inline(always)]
pub(crate) fn anchored_words(
    planes: [[i64; 3]; 3],
    min_x: i32,
    min_y: i32,
) -> ([[i32; 3]; 3], [i32; 2]) {
    let [ax, ay] = anchor(min_x, min_y);
    let at = |p: [i64; 3]| {
        p[0].wrapping_add(p[1].wrapping_mul(i64::from(ax)))
            .wrapping_add(p[2].wrapping_mul(i64::from(ay)))
    };
    let words = words_of(planes.map(at), planes.map(|p| p[1]), planes.map(|p| p[2]));
    (words, [ax, ay])
}

/// The anchor pixel of [`anchored_words`] for a triangle whose least raw vertex coordinates
/// are `min_x`, `min_y`: the first pixel column and row whose centres are at or past them
/// (`edge::first_centre_at_or_after`), clamped to 0.
#[inline(always)]
pub(crate) fn anchor(min_x: i32, min_y: i32) -> [i32; 2] {
    [min_x, min_y].map(|m| (m.wrapping_add(7) >> 4).max(0))
}

/// The texel words at pixel `(px, py)` from the anchored words `words` ([`anchored_words`]):
/// `w + a wx + b wy` for the pixel `a` columns and `b` rows from `anchor` (wrapping). The one
/// place both paths take them, so their pixels are the same.
#[inline(always)]
pub(crate) fn words_at(words: &[[i32; 3]; 3], anchor: [i32; 2], px: i32, py: i32) -> [i32; 3] {
    let (a, b) = (px.wrapping_sub(anchor[0]), py.wrapping_sub(anchor[1]));
    words.map(|[w, wx, wy]| {
        w.wrapping_add(wx.wrapping_mul(a))
            .wrapping_add(wy.wrapping_mul(b))
    })
}

/// The texel words `[at the anchor, dx, dy]` of each plane from the planes' values at the
/// anchor and their steps ([`anchored_words`]).
#[inline(always)]
pub(crate) fn words_of(at: [i64; 3], dx: [i64; 3], dy: [i64; 3]) -> [[i32; 3]; 3] {
    let (w, wx, wy) = (texel_words(at), texel_words(dx), texel_words(dy));
    [
        [w[0], wx[0], wy[0]],
        [w[1], wx[1], wy[1]],
        [w[2], wx[2], wy[2]],
    ]
}

/// The texel at the texel words `[N_u', N_v', D']` ([`texel_words`], stepped along a run) in
/// `texels`, a texture of `SIDE x SIDE` texels: the quotients `N' / D'` (a numerator below 0
/// taken as 0; a divisor of 0 reads texel `(0, 0)`), each clamped to `SIDE - 1`. `texels` is
/// taken to its `SIDE * SIDE` texels by the caller, once a run: the index is then below its
/// length by construction (no bounds check per pixel; texel 0 if `texels` is shorter).
#[inline(always)]
pub(crate) fn texel_at<const SIDE: usize>(texels: &[u16], words: [i32; 3]) -> u16 {
    let [nu, nv, dd] = words;
    let den = dd as u32;
    let max = SIDE as u32 - 1;
    let log2 = Texture565::<SIDE>::LOG2;
    // The quotient is in units of 2^(8 - f) texel: f - 8 = 7 - log2(SIDE) bits to drop.
    let fs = 7u32.saturating_sub(log2);
    let q = |n: i32| (n.max(0) as u32).checked_div(den).unwrap_or(0) >> fs;
    let (u, t) = (q(nu), q(nv));
    // Both inside the texture (the common case: one test of the two, `SIDE` a power of two),
    // or each clamped to its last texel: the same index either way.
    let i = if (u | t) >> log2 == 0 {
        (t << log2) | u
    } else {
        (t.min(max) << log2) | u.min(max)
    };
    texels.get(i as usize).copied().unwrap_or(0)
}

/// `texels` taken to exactly `SIDE * SIDE` texels (the whole texture of a [`Texture565`]):
/// what [`texel_at`] reads, its length then a constant. `None` if `texels` is shorter (never
/// for a `Texture565`'s texels).
#[inline(always)]
pub(crate) fn whole<const SIDE: usize>(texels: &[u16]) -> Option<&[u16]> {
    texels.get(..SIDE * SIDE)
}

impl Rasterizer {
    /// Draws a textured triangle into `colour` (RGB565, row-major over `depth`'s rectangle, as
    /// `depth`'s storage) with the depth test and write of `opts`, reading `tex` nearest at the
    /// vertices' `tex.x`, `tex.y` (raw `Q16.16` texels) interpolated perspective-correctly: see
    /// the module documentation ([`Texture565`]) for the guarantees. Clipped to the clip
    /// rectangle and the depth buffer's rectangle.
    pub fn draw_textured<const SIDE: usize>(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
        depth: &mut DepthBuffer<'_>,
        tex: &Texture565<'_, SIDE>,
        colour: &mut [u16],
    ) {
        self.draw_textured_with(v, opts, depth, tex, colour, true);
    }

    /// [`Rasterizer::draw_textured`], through the small path ([`Small::set_up`]) when `small`
    /// allows it and the triangle is small (the tests draw both ways and compare).
    fn draw_textured_with<const SIDE: usize>(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
        depth: &mut DepthBuffer<'_>,
        tex: &Texture565<'_, SIDE>,
        colour: &mut [u16],
        small: bool,
    ) {
        let rect = depth.rect();
        let stride = usize::from(rect.width());
        if colour.len() < stride * usize::from(rect.height()) {
            return;
        }
        let clip = self.clip.intersect(&rect);
        if self.misses(v, clip) {
            return;
        }
        let set_up = if small {
            Small::set_up(v, opts, tex.frac())
        } else {
            Small::Wide
        };
        match &set_up {
            Small::Wide => {}
            Small::Rejected(r) => return self.count_setup(Some(r)),
            Small::General => {
                self.count_setup(None);
                return self.draw_textured_general(v, opts, depth, tex, colour, stride);
            }
            Small::Ready(s) => {
                self.count_setup(None);
                let run = SmallRun {
                    bias: depth_bias(opts.depth_func),
                    write: opts.depth_write,
                    texels: tex.texels,
                };
                let [shown, failed] =
                    draw_small::<SIDE>(s, clip, rect, depth.data_mut(), colour, &run);
                let c = &mut self.counters;
                c.pixels = c.pixels.wrapping_add(u64::from(shown));
                c.depth_failed = c.depth_failed.wrapping_add(u64::from(failed));
                return;
            }
        }
        let r = CoverDepth::new(v, opts);
        self.count_setup(r.as_ref().err());
        let Ok(pre) = &r else {
            return;
        };
        let affine = opts.perspective == Perspective::Affine;
        let Some(h) = Homogeneous::new(pre, v, affine, tex) else {
            return self.draw_textured_general(v, opts, depth, tex, colour, stride);
        };
        let plane = pre.depth_plane();
        // The depth test as one unsigned comparison `z < stored + bias`: `Less` is bias 0,
        // `LessEqual` bias 1, `Always` past every depth (z and stored are below 2^16).
        let bias = depth_bias(plane.func);
        let write = plane.write;
        // The rounded depth at a covered pixel centre is within one unit of `[zlo, zhi]` (the
        // exact value is a convex combination of the vertex depths, the plane's rounding is far
        // below half a unit), so its `i32` truncation is the value itself and the clamp in
        // `i32` is the clamp in `i64` (`max` then `min`, as the depth stage does: `clamp` would
        // carry a panic branch for `zlo > zhi`, which the set-up never gives).
        let (zlo, zhi) = (plane.zlo as i32, plane.zhi as i32);
        let dz = plane.z.dx;
        let Some(texels) = whole::<SIDE>(tex.texels) else {
            return;
        };
        let data = depth.data_mut();
        let counters = &mut self.counters;
        let raw = v.map(|p| [p.x.to_bits(), p.y.to_bits()]);
        let min_x = raw.iter().map(|p| p[0]).min().unwrap_or(0);
        let min_y = raw.iter().map(|p| p[1]).min().unwrap_or(0);
        let (words, anchor) = anchored_words(h.planes, min_x, min_y);
        let [du, dv, ddx] = words.map(|w| w[1]);
        super::edge::walk_runs(&pre.coverage(), clip, |py, xa, xb| {
            let off = usize::from(py - rect.y0) * stride + usize::from(xa - rect.x0);
            let n = usize::from(xb - xa);
            let (Some(drow), Some(crow)) =
                (data.get_mut(off..off + n), colour.get_mut(off..off + n))
            else {
                return;
            };
            let (px, pyi) = (i64::from(xa), i64::from(py));
            let mut zp = plane.z.at(px, pyi);
            let [mut nu, mut nv, mut dd] = words_at(&words, anchor, i32::from(xa), i32::from(py));
            let mut shown = 0u32;
            for (d, c) in drow.iter_mut().zip(crow.iter_mut()) {
                let z = ((zp.wrapping_add(1 << 31) >> 32) as i32).max(zlo).min(zhi) as u16;
                if u32::from(z) < u32::from(*d) + bias {
                    if write {
                        *d = z;
                    }
                    *c = texel_at::<SIDE>(texels, [nu, nv, dd]);
                    shown += 1;
                }
                zp = zp.wrapping_add(dz);
                nu = nu.wrapping_add(du);
                nv = nv.wrapping_add(dv);
                dd = dd.wrapping_add(ddx);
            }
            counters.pixels = counters.pixels.wrapping_add(u64::from(shown));
            counters.depth_failed = counters
                .depth_failed
                .wrapping_add((n as u64).wrapping_sub(u64::from(shown)));
        });
    }

    /// [`Rasterizer::draw_textured`] through the general rasterizer (its segments, nearest
    /// look-ups along each).
    fn draw_textured_general<const SIDE: usize>(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
        depth: &mut DepthBuffer<'_>,
        tex: &Texture565<'_, SIDE>,
        colour: &mut [u16],
        stride: usize,
    ) {
        let rect = depth.rect();
        self.draw_depth(v, opts, depth, &mut |seg: &Segment| {
            let s0 = seg.s0.to_bits();
            let ds = seg.ds.to_bits();
            let (mut u, mut t) = (s0[0], s0[1]);
            let start = usize::from(seg.y.wrapping_sub(rect.y0)) * stride
                + usize::from(seg.x0.wrapping_sub(rect.x0));
            let Some(out) = colour.get_mut(start..start + usize::from(seg.len)) else {
                return;
            };
            for px in out {
                *px = tex.nearest_q16(u, t);
                u = u.wrapping_add(ds[0]);
                t = t.wrapping_add(ds[1]);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use super::*;
    use crate::format::TexPoint;

    /// A texture whose texel at `(tu, tv)` is `tv * side + tu`.
    fn index_texture(side: u16) -> std::vec::Vec<u16> {
        (0..u32::from(side) * u32::from(side))
            .map(|i| i as u16)
            .collect()
    }

    fn vtx(x: f64, y: f64, z: u16, w: f64, u: f64, v: f64) -> ScreenVertex {
        ScreenVertex::new(
            ScreenCoord::from_num(x),
            ScreenCoord::from_num(y),
            z,
            InvW::from_num(1.0 / w),
            TexPoint::from_f64(u, v, 0.0),
        )
    }

    #[test]
    fn texture_constructor_checks_side_and_length() {
        let t = index_texture(16);
        assert!(Texture565::<16>::new(&t).is_some());
        assert_eq!(Texture565::<16>::new(&t).map(|t| t.side()), Some(16));
        assert!(Texture565::<8>::new(&t).is_none());
        assert!(Texture565::<16>::new(&t[..255]).is_none());
        assert!(Texture565::<1>::new(&t[..1]).is_some());
        assert!(Texture565::<0>::new(&[]).is_none());
        let t = index_texture(12);
        assert!(Texture565::<12>::new(&t).is_none());
        let t = vec![0u16; 256 * 256];
        assert!(Texture565::<256>::new(&t).is_none());
    }

    /// The pixels a triangle covers (depth written) through `draw_depth` and `draw_textured`
    /// are the same, and every textured pixel reads the texel of the real-arithmetic
    /// perspective-correct coordinates within the stated bound: the 128-texel atlas's side
    /// (`f = 8`) and a 16-texel texture (`f = 11`: the texel words' extra shift).
    #[test]
    fn coverage_equals_draw_depth_and_texels_follow_perspective() {
        coverage_and_texels::<128>();
        coverage_and_texels::<16>();
    }

    fn coverage_and_texels<const SIDE: usize>() {
        let (w, h) = (64u16, 48u16);
        let side = SIDE as u16;
        let texels = index_texture(side);
        let tex = Texture565::<SIDE>::new(&texels).unwrap();
        let top = f64::from(side - 1);
        // The triangles' texel coordinates are given for 128 texels.
        let vtx = |x: f64, y: f64, z: u16, w: f64, u: f64, v: f64| {
            let k = f64::from(side) / 128.0;
            vtx(x, y, z, w, u * k, v * k)
        };
        let tris = [
            [
                vtx(3.3, 2.1, 100, 1.0, 1.5, 2.5),
                vtx(60.7, 9.9, 900, 3.0, 120.0, 10.25),
                vtx(12.2, 45.5, 500, 1.7, 20.0, 126.0),
            ],
            [
                vtx(50.0, 40.0, 10, 2.0, 100.0, 100.0),
                vtx(5.0, 30.0, 10, 1.0, 3.0, 70.0),
                vtx(40.0, 1.0, 10, 4.0, 60.0, 4.0),
            ],
            // Affine-like (equal w), thin.
            [
                vtx(0.5, 0.5, 0, 1.0, 0.5, 0.5),
                vtx(63.5, 3.0, 0, 1.0, 127.5, 6.0),
                vtx(1.0, 2.0, 0, 1.0, 1.0, 3.5),
            ],
        ];
        for (k, tri) in tris.iter().enumerate() {
            for persp in [Perspective::Every16, Perspective::Affine] {
                let opts = TriangleOptions::new(persp);
                let mut zref = vec![u16::MAX; usize::from(w) * usize::from(h)];
                let mut zfast = zref.clone();
                let mut colour = vec![u16::MAX; zref.len()];
                let rect = Rect::from_size(w, h);
                let mut r = Rasterizer::new(rect);
                let mut db = DepthBuffer::new(&mut zref, rect).unwrap();
                r.draw_depth(tri, &opts, &mut db, &mut |_: &Segment| {});
                let mut db = DepthBuffer::new(&mut zfast, rect).unwrap();
                r.draw_textured(tri, &opts, &mut db, &tex, &mut colour);
                assert_eq!(zref, zfast, "triangle {k}: coverage and depth");
                let mut drawn = 0;
                for (i, c) in colour.iter().enumerate() {
                    if zfast[i] == u16::MAX {
                        assert_eq!(*c, u16::MAX);
                        continue;
                    }
                    drawn += 1;
                    let (px, py) = (
                        (i % usize::from(w)) as f64 + 0.5,
                        (i / usize::from(w)) as f64 + 0.5,
                    );
                    // Barycentric weights of the pixel centre, perspective-weighted.
                    let p = tri.map(|v| (v.x.to_num::<f64>(), v.y.to_num::<f64>()));
                    let e = |a: (f64, f64), b: (f64, f64)| {
                        (b.0 - a.0) * (py - a.1) - (b.1 - a.1) * (px - a.0)
                    };
                    let l = [e(p[1], p[2]), e(p[2], p[0]), e(p[0], p[1])];
                    let q = tri.map(|v| {
                        if persp == Perspective::Affine {
                            1.0
                        } else {
                            v.inv_w.to_num::<f64>()
                        }
                    });
                    let den: f64 = (0..3).map(|j| l[j] * q[j]).sum();
                    let coord = |c: usize| {
                        (0..3)
                            .map(|j| l[j] * q[j] * f64::from(tri[j].tex.to_bits()[c]) / 65536.0)
                            .sum::<f64>()
                            / den
                    };
                    let (u, v) = (coord(0), coord(1));
                    let (tu, tv) = (f64::from(*c % side), f64::from(*c / side));
                    // Within side (1 + i) r 2^-22 texel of the quantised data's ratio (r <= 4,
                    // runs below 64 pixels: below 1/128 texel), whose vertex coordinates are
                    // within 2^-f texel and whose q_i within 2^-14 of the real ones: 6/256
                    // texel allowed.
                    let tol = 6.0 / 256.0;
                    assert!(
                        tu >= (u - tol).floor().max(0.0) && tu <= (u + tol).floor().min(top),
                        "side {side} triangle {k} pixel {i}: u {u} texel {tu}"
                    );
                    assert!(
                        tv >= (v - tol).floor().max(0.0) && tv <= (v + tol).floor().min(top),
                        "side {side} triangle {k} pixel {i}: v {v} texel {tv}"
                    );
                }
                assert!(drawn > 20, "triangle {k}: {drawn} pixels");
            }
        }
    }

    /// A triangle past the fast path's range (doubled area of 2^32 raw units or more) is drawn
    /// through the general rasterizer: the same coverage as `draw_depth`.
    #[test]
    fn large_triangles_take_the_general_path() {
        let (w, h) = (32u16, 16u16);
        let texels = index_texture(128);
        let tex = Texture565::<128>::new(&texels).unwrap();
        let tri = [
            vtx(-9000.0, -9000.0, 5, 1.0, 0.0, 0.0),
            vtx(9000.0, -9000.0, 5, 1.0, 127.0, 0.0),
            vtx(0.0, 9000.0, 5, 1.0, 64.0, 127.0),
        ];
        let opts = TriangleOptions::new(Perspective::Every16);
        let rect = Rect::from_size(w, h);
        let mut r = Rasterizer::new(rect);
        let mut zref = vec![u16::MAX; 512];
        let mut zfast = zref.clone();
        let mut colour = vec![u16::MAX; 512];
        r.draw_depth(
            &tri,
            &opts,
            &mut DepthBuffer::new(&mut zref, rect).unwrap(),
            &mut |_: &Segment| {},
        );
        r.draw_textured(
            &tri,
            &opts,
            &mut DepthBuffer::new(&mut zfast, rect).unwrap(),
            &tex,
            &mut colour,
        );
        assert_eq!(zref, zfast);
        assert!(colour.iter().all(|c| *c != u16::MAX));
        // A colour band shorter than the depth rectangle draws nothing.
        let mut short = vec![u16::MAX; 511];
        let mut z = vec![u16::MAX; 512];
        r.draw_textured(
            &tri,
            &opts,
            &mut DepthBuffer::new(&mut z, rect).unwrap(),
            &tex,
            &mut short,
        );
        assert!(z.iter().all(|d| *d == u16::MAX));
    }

    /// Draws `tri` through the small path and through the wide fast path (`rects`: the
    /// rasterizer's target, its clip and the depth buffer's rectangle, whose depths start as
    /// `z`) and checks that both give the same depths, colours and counters (`n` names the
    /// triangle); returns the pixels shown.
    fn both_ways(
        tri: &[ScreenVertex; 3],
        opts: &TriangleOptions,
        tex: &Texture565<'_, 128>,
        rects: (Rect, Rect, Rect),
        z: Vec<u16>,
        n: u32,
    ) -> u64 {
        let (target, clip, rect) = rects;
        let draw = |small: bool| {
            let mut z = z.clone();
            let mut colour = vec![u16::MAX; z.len()];
            let mut r = Rasterizer::new(target);
            r.set_clip(clip);
            let mut db = DepthBuffer::new(&mut z, rect).unwrap();
            r.draw_textured_with(tri, opts, &mut db, tex, &mut colour, small);
            (z, colour, r.counters())
        };
        let (zs, cs, ks) = draw(true);
        let (zw, cw, kw) = draw(false);
        assert_eq!(zs, zw, "triangle {n}: depth");
        assert_eq!(cs, cw, "triangle {n}: colour");
        assert_eq!(ks, kw, "triangle {n}: counters");
        ks.pixels
    }

    /// A xorshift generator from `seed`: each call `rnd(m)` its next state modulo `m`.
    fn below(seed: u64) -> impl FnMut(u64) -> u64 {
        let mut rng = crate::test_rng::XorShift64::new(seed);
        move |m| rng.below(m)
    }

    /// The texel look-up against its definition (each quotient clamped to the last texel on
    /// its own): words inside the texture, past it in one or both coordinates, negative
    /// numerators and a zero divisor, for sides 128 and 16.
    #[test]
    fn texel_at_clamps_each_coordinate() {
        fn check<const SIDE: usize>(seed: u64) {
            let texels: std::vec::Vec<u16> = (0..SIDE * SIDE).map(|i| i as u16 ^ 0x5A5A).collect();
            let log2 = Texture565::<SIDE>::LOG2;
            let fs = 7u32.saturating_sub(log2);
            let want = |[nu, nv, dd]: [i32; 3]| {
                let q = |n: i32| {
                    let q = (n.max(0) as u32).checked_div(dd as u32).unwrap_or(0) >> fs;
                    q.min(SIDE as u32 - 1)
                };
                texels[((q(nv) << log2) | q(nu)) as usize]
            };
            let mut rnd = below(seed);
            let (mut inside, mut clamped) = (0u32, 0u32);
            for n in 0..40_000u32 {
                let dd = match n % 8 {
                    0 => 0,
                    1 => 1,
                    _ => 1 + rnd(1 << 24) as i32,
                };
                // Quotients from 0 to about 4 sides (in units of 2^(8 - f) texel), now and
                // then a negative numerator or one far past the texture.
                let num =
                    |r: &mut dyn FnMut(u64) -> u64| match r(10) {
                        0 => -(r(1 << 30) as i32),
                        1 => r(1 << 31) as i32,
                        _ => (r((4 * 128) << fs) as i64 * i64::from(dd.max(1)))
                            .min(i64::from(i32::MAX)) as i32,
                    };
                let words = [num(&mut rnd), num(&mut rnd), dd];
                let got = texel_at::<SIDE>(&texels, words);
                assert_eq!(got, want(words), "{words:?}");
                let q = |n: i32| (n.max(0) as u32).checked_div(dd as u32).unwrap_or(0) >> fs;
                if q(words[0]).max(q(words[1])) < SIDE as u32 {
                    inside += 1;
                } else {
                    clamped += 1;
                }
            }
            assert!(inside > 5_000 && clamped > 5_000, "{inside} {clamped}");
        }
        check::<128>(0x1234_5678_9ABC_DEF1);
        check::<16>(0x0F1E_2D3C_4B5A_6978);
    }

    /// Small triangles (the `i32` set-up and walk) draw exactly the pixels, depths and counters
    /// of the wide fast path: random triangles across a band, every depth function, both
    /// perspective modes, culling, partly clipped, vertices at the small range's edges and just
    /// past them, slivers.
    #[test]
    fn small_path_equals_the_wide_path() {
        let (w, h) = (96u16, 40u16);
        let texels = index_texture(128);
        let tex = Texture565::<128>::new(&texels).unwrap();
        let mut st = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = |lo: i64, hi: i64| {
            lo + ((crate::test_rng::lcg64(&mut st) >> 33) as i64).rem_euclid(hi - lo)
        };
        let mut drawn = 0u64;
        for n in 0..600 {
            // Raw 28.4 coordinates around the band, some far off it (still small), some tiny.
            let span = if n % 5 == 0 { 16_000 } else { 1_800 };
            // Every 7th triangle has its vertices at the small range's edges (2^14 - 1 raw
            // units either way) or just past them (the wide path), or a sliver one unit wide.
            let edge = |v: i64| match n % 21 {
                0 => v.signum() * 16_383,
                7 => v.signum() * 16_384,
                14 => v.clamp(-2, 2),
                _ => v,
            };
            let tri: [ScreenVertex; 3] = core::array::from_fn(|_| {
                ScreenVertex::from_bits(
                    edge(rnd(-span, span)) as i32,
                    rnd(-span / 2, span) as i32,
                    rnd(0, 65_536) as u16,
                    rnd(1, 1 << 31) as u32,
                    TexPoint::from_bits(
                        rnd(-(1 << 20), 1 << 24) as i32,
                        rnd(-(1 << 20), 1 << 24) as i32,
                        0,
                    ),
                )
            });
            let mut opts = TriangleOptions::new(if n % 3 == 0 {
                Perspective::Affine
            } else {
                Perspective::Every16
            });
            opts.depth_func = [DepthFunc::Less, DepthFunc::LessEqual, DepthFunc::Always][n % 3];
            opts.depth_write = n % 4 != 1;
            opts.cull = [
                CullMode::None,
                CullMode::Clockwise,
                CullMode::CounterClockwise,
            ][n % 3];
            let z: Vec<u16> = (0..usize::from(w) * usize::from(h))
                .map(|i| (i as u16).wrapping_mul(977))
                .collect();
            let clip = Rect::new(3, 0, w - 5, 64);
            let rect = Rect::new(0, 8, w, 8 + h);
            drawn += both_ways(
                &tri,
                &opts,
                &tex,
                (Rect::from_size(w, 64), clip, rect),
                z,
                n as u32,
            );
        }
        assert!(drawn > 20_000, "{drawn} pixels drawn");
    }

    /// The small path writes its depths without the wide path's clamp to the vertex depths
    /// (`SmallSetup::zplane`: it never acts at a covered pixel). Steep depth planes at their
    /// extremes: vertex depths 0 and 65535, slivers and needles one raw unit wide, vertices at
    /// the small range's edges, every pixel written (`Always`), against the clamping wide path.
    #[test]
    fn small_depth_needs_no_clamp() {
        let (w, h) = (64u16, 32u16);
        let texels = index_texture(128);
        let tex = Texture565::<128>::new(&texels).unwrap();
        let mut rnd = below(0x2545_f491_4f6c_dd1d);
        let depths = [0u16, 1, 32_768, 65_534, 65_535];
        let mut drawn = 0u64;
        for n in 0..3000u32 {
            // Raw 28.4 coordinates over the band and a little past it; one vertex of every
            // fourth triangle far out (up to the small range's edge), every third triangle a
            // sliver: its second vertex one raw unit from the first.
            let c = |r: &mut dyn FnMut(u64) -> u64, span: u64| r(2 * span) as i32 - span as i32;
            let mut p = [[0i32; 2]; 3];
            for (k, v) in p.iter_mut().enumerate() {
                let span = if k == 2 && n % 4 == 0 { 16_383 } else { 600 };
                *v = [c(&mut rnd, span) + 512, c(&mut rnd, span) + 256];
            }
            if n % 3 == 0 {
                p[1] = [p[0][0] + 1, p[0][1] + (rnd(3) as i32 - 1)];
            }
            let tri: [ScreenVertex; 3] = core::array::from_fn(|k| {
                ScreenVertex::from_bits(
                    p[k][0].clamp(-16_383, 16_383),
                    p[k][1].clamp(-16_383, 16_383),
                    depths[rnd(5) as usize],
                    rnd(1 << 31) as u32 + 1,
                    TexPoint::from_bits(rnd(1 << 23) as i32, rnd(1 << 23) as i32, 0),
                )
            });
            let mut opts = TriangleOptions::new(if n % 2 == 0 {
                Perspective::Affine
            } else {
                Perspective::Every16
            });
            opts.depth_func = DepthFunc::Always;
            let rect = Rect::from_size(w, h);
            let z = vec![0x5555u16; usize::from(w) * usize::from(h)];
            drawn += both_ways(&tri, &opts, &tex, (rect, rect, rect), z, n);
        }
        assert!(drawn > 50_000, "{drawn} pixels drawn");
    }

    /// Every texel the fast paths read lies within the stated bound of the quantised vertex
    /// data's exact ratio (`anchored_words`): the words are within `1 + a + b` units below
    /// their exact values at a pixel `a` columns and `b` rows from the anchor, so the quotient
    /// lies in `[(N - d) / D, N / (D - d)]` (exact `N`, `D` in word units, `d = 1 + a + b`).
    /// Random triangles in and far around a 96 x 64 target (anchors up to 1000 pixels away,
    /// long rows), `1/w` ratios up to 16, both texture sides' fraction bits.
    #[test]
    fn texels_stay_within_the_stated_bound() {
        texels_within_bound::<128>(0x51A7_E5ED);
        texels_within_bound::<16>(0xB0_0B1E5);
    }

    fn texels_within_bound<const SIDE: usize>(seed: u64) {
        let (w, h) = (96u16, 64u16);
        let texels = index_texture(SIDE as u16);
        let tex = Texture565::<SIDE>::new(&texels).unwrap();
        let f = tex.frac();
        let fs = f - 8;
        let mut rnd = below(seed);
        let mut checked = 0u64;
        for n in 0..400u32 {
            // Raw 28.4 vertices: around the target, or (every third triangle) one vertex up to
            // 1000 pixels away, so the anchor and the rows are far apart.
            let far = n % 3 == 0;
            let tri: [ScreenVertex; 3] = core::array::from_fn(|k| {
                let span = if far && k == 0 { 16_000 } else { 1_700 };
                let c = |r: u64| r as i32 - span as i32 / 2;
                let (x, y) = (c(rnd(span)) + 768, c(rnd(span)) + 512);
                ScreenVertex::from_bits(
                    x.clamp(-16_383, 16_383),
                    y.clamp(-16_383, 16_383),
                    rnd(65_536) as u16,
                    // 1/w over a ratio of up to 16.
                    (1u32 << 30) >> rnd(5),
                    TexPoint::from_bits(
                        rnd(SIDE as u64 * 65_536) as i32,
                        rnd(SIDE as u64 * 65_536) as i32,
                        0,
                    ),
                )
            });
            let mut opts = TriangleOptions::new(Perspective::Every16);
            opts.depth_func = DepthFunc::Always;
            let rect = Rect::from_size(w, h);
            let mut z = vec![0u16; usize::from(w) * usize::from(h)];
            let mut colour = vec![u16::MAX; z.len()];
            let mut r = Rasterizer::new(rect);
            let mut db = DepthBuffer::new(&mut z, rect).unwrap();
            r.draw_textured(&tri, &opts, &mut db, &tex, &mut colour);
            // The quantised data as the set-up takes it: q_i normalised to 15 bits, the
            // coordinates to f fraction bits, the edge functions at pixel centres.
            let p = tri.map(|v| [i64::from(v.x.to_bits()), i64::from(v.y.to_bits())]);
            let qmax = tri.iter().map(|v| v.inv_w.to_bits()).max().unwrap();
            let bl = 32 - qmax.leading_zeros();
            let q = tri.map(|v| {
                let x = v.inv_w.to_bits();
                i128::from(if bl > 15 {
                    x >> (bl - 15)
                } else {
                    x << (15 - bl)
                })
            });
            let top = (1i32 << 15) - 1;
            let coord = |t: i32| i128::from((t >> (16 - f)).clamp(0, top));
            let area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
            if area2 == 0 {
                continue;
            }
            let k = 33 - (64 - area2.unsigned_abs().leading_zeros()) as i32;
            let min_x = p.iter().map(|c| c[0]).min().unwrap() as i32;
            let min_y = p.iter().map(|c| c[1]).min().unwrap() as i32;
            let anchor = [((min_x + 7) >> 4).max(0), ((min_y + 7) >> 4).max(0)];
            for (i, c) in colour.iter().enumerate() {
                if *c == u16::MAX {
                    continue;
                }
                let (px, py) = ((i % usize::from(w)) as i64, (i / usize::from(w)) as i64);
                let e = |j: usize, l: usize| {
                    let (a, b) = (p[j], p[l]);
                    (a[0] - 8 - 16 * px) * (b[1] - 8 - 16 * py)
                        - (b[0] - 8 - 16 * px) * (a[1] - 8 - 16 * py)
                };
                let ee = [e(1, 2), e(2, 0), e(0, 1)].map(|v| i128::from(v * area2.signum()));
                let d: i128 = (0..3).map(|j| ee[j] * q[j]).sum();
                let num = |c: usize| -> i128 {
                    (0..3)
                        .map(|j| ee[j] * q[j] * coord(tri[j].tex.to_bits()[c]))
                        .sum()
                };
                // Exact values in word units: N 2^k / 2^32 and D 2^k / 2^24.
                let scale = 2f64.powi(k);
                let dw = d as f64 * scale / 2f64.powi(24);
                let delta = 1.0 + (px - i64::from(anchor[0]) + py - i64::from(anchor[1])) as f64;
                let max = SIDE as f64 - 1.0;
                let texel = |c: usize| {
                    let nw = num(c) as f64 * scale / 2f64.powi(32);
                    let lo = ((nw - delta) / dw / 2f64.powi(fs as i32)).floor();
                    let hi = (nw / (dw - delta) / 2f64.powi(fs as i32)).floor();
                    (lo.clamp(0.0, max), hi.clamp(0.0, max))
                };
                let (tu, tv) = (f64::from(*c % SIDE as u16), f64::from(*c / SIDE as u16));
                let ((ul, uh), (vl, vh)) = (texel(0), texel(1));
                assert!(
                    ul <= tu && tu <= uh && vl <= tv && tv <= vh,
                    "side {SIDE} triangle {n} pixel ({px}, {py}): texel ({tu}, {tv}) outside \
                     [{ul}, {uh}] x [{vl}, {vh}]"
                );
                checked += 1;
            }
        }
        assert!(checked > 30_000, "{checked} pixels checked");
    }
}
