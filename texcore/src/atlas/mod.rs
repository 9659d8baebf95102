//! Meshed texture atlases (Carr & Hart 2002): the device side of baking a solid texture into a
//! 2-D atlas laid over a mesh, and of sampling it.
//!
//! The layout (which triangle goes where, computed on the host, `host_sim::atlas`) reaches the
//! device as a slice of [`AtlasTriangle`]s. Every atlas triangle is an isosceles right triangle
//! with integer legs `L` inside a rectangular **block** of texels that it shares with at most
//! one other triangle (its **pair**, across the hypotenuse). In texel units (texel `(i, j)`
//! covers `[i, i+1) x [j, j+1)`, centre `(i + 1/2, j + 1/2)`), for a block at `(X, Y)` of
//! `W x H` texels and gutter `g` (0 or 1), with `o = g / 2` and `R = L + 2g`:
//!
//! - the **upper** triangle has its right angle at `(X + o, Y + o)` and legs along `+u`, `+v`;
//!   it owns the texels with `di + dj <= W + H - 2 - R` (`di = i - X`, `dj = j - Y`);
//! - the **lower** triangle has its right angle at `(X + W - o, Y + H - o)` and legs along
//!   `-u`, `-v`; it owns the texels with `ei + ej <= R - 1` (`ei = X + W - 1 - i`,
//!   `ej = Y + H - 1 - j`).
//!
//! With `W >= R + 1` and `H >= R` the two regions are disjoint and cover the block (the pair's
//! shared diagonal is over-scanned on both sides: the paper's hypotenuse over-scan, one extra
//! column per pair, plus `2g` columns and rows of gutter). Each triangle owns every texel a
//! look-up at a point strictly inside it reads with a non-zero weight: with `g = 0` the nearest
//! texel (the corners on texel boundaries: a point with `u + v < L` from the right angle lies
//! in a texel with `di + dj <= L - 1`); with `g = 1` the nearest texel and the four texels of
//! the bilinear footprint (texel centres less than one texel away in each axis: with the corners
//! on texel *centres*, `di + dj <= L + 1`). Look-ups exactly on an edge are not covered: the
//! atlas coordinates handed to a renderer are [`AtlasTriangle::inset_corners`], [`INSET`] inside
//! every edge, more than a renderer's rounding. Owned texels outside the triangle hold the
//! triangle's solid coordinates **extrapolated**, so a sample near an edge blends only this
//! triangle's texture, never a neighbour's nor the background: no seams.
//!
//! [`bake`] evaluates the texture into the owned texels of every triangle, row by row: along an
//! atlas row the solid coordinates are affine, so each row of a triangle is one
//! [`Span`] (forward-differenced where the texture allows) whose `ds` and
//! `dsdy` are the texel's footprint in solid space (the filter width). [`sample`] holds nearest,
//! bilinear and MIP look-ups of a baked atlas. Nothing allocates; nothing panics.

pub mod sample;

use crate::color::Rgba8888;
use crate::format::TexPoint;
use crate::span::Span;
use crate::texture::TextureEvaluator;

/// How far inside its atlas triangle's edges a renderer's atlas coordinates are
/// ([`AtlasTriangle::inset_corners`]), raw `Q16.16` texels: 1/64 texel.
pub const INSET: i32 = 1 << 10;

/// Which half of a block an atlas triangle is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Half {
    /// Right angle at the block's top-left, legs along `+u` and `+v`.
    Upper,
    /// Right angle at the block's bottom-right, legs along `-u` and `-v`.
    Lower,
}

/// Why an atlas triangle cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AtlasError {
    /// Leg length 0.
    ZeroLeg,
    /// The block is smaller than `(L + 2g + 1) x (L + 2g)`.
    BlockTooSmall,
    /// The block does not fit `u16` texel coordinates.
    OutOfRange,
    /// A gutter other than 0 (nearest look-ups) or 1 (bilinear).
    Gutter,
}

impl core::fmt::Display for AtlasError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            AtlasError::ZeroLeg => write!(f, "atlas triangle with a zero leg"),
            AtlasError::BlockTooSmall => write!(f, "atlas block too small for its triangle"),
            AtlasError::OutOfRange => write!(f, "atlas block beyond 65535 texels"),
            AtlasError::Gutter => write!(f, "atlas gutter other than 0 or 1"),
        }
    }
}

/// One triangle of an atlas layout: its block, half, leg and gutter, and the solid texture
/// coordinates of its three corners (right-angle corner, the corner along `u`, the corner
/// along `v`). Built by [`AtlasTriangle::new`], which checks the geometry once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AtlasTriangle {
    x: u16,
    y: u16,
    w: u16,
    h: u16,
    leg: u16,
    gutter: u8,
    half: Half,
    solid: [TexPoint; 3],
}

impl AtlasTriangle {
    /// A triangle of leg `leg` and gutter `gutter` (0: nearest look-ups, 1: bilinear) in the
    /// `w x h` block at `(x, y)`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        x: u16,
        y: u16,
        w: u16,
        h: u16,
        leg: u16,
        gutter: u8,
        half: Half,
        solid: [TexPoint; 3],
    ) -> Result<AtlasTriangle, AtlasError> {
        if leg == 0 {
            return Err(AtlasError::ZeroLeg);
        }
        if gutter > 1 {
            return Err(AtlasError::Gutter);
        }
        let need = leg as u32 + 2 * gutter as u32;
        if (w as u32) < need + 1 || (h as u32) < need {
            return Err(AtlasError::BlockTooSmall);
        }
        if x as u32 + w as u32 > u16::MAX as u32 || y as u32 + h as u32 > u16::MAX as u32 {
            return Err(AtlasError::OutOfRange);
        }
        Ok(AtlasTriangle {
            x,
            y,
            w,
            h,
            leg,
            gutter,
            half,
            solid,
        })
    }

    /// The block `(x, y, w, h)`.
    pub fn block(&self) -> (u16, u16, u16, u16) {
        (self.x, self.y, self.w, self.h)
    }

    /// The leg length in texels.
    pub fn leg(&self) -> u16 {
        self.leg
    }

    /// Which half of its block.
    pub fn half(&self) -> Half {
        self.half
    }

    /// The solid coordinates of the corners (right angle, along `u`, along `v`).
    pub fn solid(&self) -> [TexPoint; 3] {
        self.solid
    }

    /// The atlas positions of the corners, in texels times 16 (1/16 texel, exact):
    /// right angle, along `u`, along `v`.
    pub fn corners_x16(&self) -> [[i32; 2]; 3] {
        // The right angle is `g / 2` texels inside the block's corner: 8 g sixteenths.
        let (o, l) = (8 * self.gutter as i32, 16 * self.leg as i32);
        let (x, y, w, h) = (self.x as i32, self.y as i32, self.w as i32, self.h as i32);
        let (rx, ry, sx) = match self.half {
            Half::Upper => (16 * x + o, 16 * y + o, 1),
            Half::Lower => (16 * (x + w) - o, 16 * (y + h) - o, -1),
        };
        [[rx, ry], [rx + sx * l, ry], [rx, ry + sx * l]]
    }

    /// The atlas coordinates a renderer interpolates over the triangle (raw `Q16.16` texels;
    /// right angle, along `u`, along `v`): the corners moved [`INSET`] inside both legs and,
    /// along the legs, `INSET` inside the hypotenuse too (`u + v <= L - INSET` from the right
    /// angle). Every point of this smaller triangle, and every point a few `2^-16` texel off it,
    /// is strictly inside the triangle, where the owned texels hold every look-up's footprint.
    /// (`Q16.16` holds texel coordinates below 32 768: a block beyond them, which
    /// [`AtlasTriangle::new`] accepts up to 65 535, gets wrapped coordinates, never a panic.)
    pub fn inset_corners(&self) -> [[i32; 2]; 3] {
        let c = self.corners_x16().map(|p| p.map(|v| v << 12));
        let s = match self.half {
            Half::Upper => INSET,
            Half::Lower => -INSET,
        };
        [
            [c[0][0] + s, c[0][1] + s],
            [c[1][0] - 2 * s, c[1][1] + s],
            [c[2][0] + s, c[2][1] - 2 * s],
        ]
    }

    /// The texels the triangle owns on atlas row `j`: `Some((first column, count))`.
    pub fn row(&self, j: u16) -> Option<(u16, u16)> {
        if j < self.y || j >= self.y + self.h {
            return None;
        }
        let reach = self.leg as i32 + 2 * self.gutter as i32;
        let (w, h) = (self.w as i32, self.h as i32);
        match self.half {
            Half::Upper => {
                let dj = (j - self.y) as i32;
                let max_sum = w + h - 2 - reach;
                let n = (max_sum - dj + 1).clamp(0, w);
                (n > 0).then_some((self.x, n as u16))
            }
            Half::Lower => {
                let ej = (self.y + self.h - 1 - j) as i32;
                let n = (reach - ej).clamp(0, w);
                (n > 0).then_some((self.x + self.w - n as u16, n as u16))
            }
        }
    }

    /// The direction of the legs (`+1` for the upper half, `-1` for the lower) and the doubled
    /// leg `2 a` (the divisor of the affine map, in half texels).
    fn sign_and_divisor(&self) -> (i64, i64) {
        let sx: i64 = match self.half {
            Half::Upper => 1,
            Half::Lower => -1,
        };
        (sx, 2 * self.leg as i64)
    }

    /// The steps of the solid coordinates (raw `Q16.16`) per texel along `u` and `v`: the affine
    /// map's, the same for every texel of the triangle (computed once a triangle by [`bake`]).
    fn steps(&self) -> RowSteps {
        let [r, a, b] = self.solid.map(|p| p.to_bits().map(i64::from));
        let (sx, l2) = self.sign_and_divisor();
        let mut su = [0i64; 3];
        let mut sv = [0i64; 3];
        for k in 0..3 {
            su[k] = div_round(2 * sx * (a[k] - r[k]), l2);
            sv[k] = div_round(2 * sx * (b[k] - r[k]), l2);
        }
        RowSteps { su, sv }
    }

    /// The solid coordinates (raw `Q16.16`) at the centre of texel `(i, j)`: the affine map of the
    /// triangle, extrapolated outside it.
    fn at(&self, i: u16, j: u16) -> [i64; 3] {
        let [r, a, b] = self.solid.map(|p| p.to_bits().map(i64::from));
        let (sx, l2) = self.sign_and_divisor();
        let [[rx, ry], _, _] = self.corners_x16();
        // Offsets of the texel centre from the right angle, in half texels, along the legs.
        let du = sx * (2 * i as i64 + 1 - (rx as i64 >> 3));
        let dv = sx * (2 * j as i64 + 1 - (ry as i64 >> 3));
        let mut s = [0i64; 3];
        for k in 0..3 {
            let (eu, ev) = (a[k] - r[k], b[k] - r[k]);
            s[k] = r[k] + div_round(eu * du + ev * dv, l2);
        }
        s
    }

    /// The span of solid coordinates over the owned texels of row `j`, with its first column
    /// (`None` when the triangle owns nothing there).
    pub fn row_span(&self, j: u16) -> Option<(u16, Span)> {
        self.row_span_with(j, &self.steps())
    }

    /// [`AtlasTriangle::row_span`] with the triangle's steps computed once.
    fn row_span_with(&self, j: u16, steps: &RowSteps) -> Option<(u16, Span)> {
        let (x0, len) = self.row(j)?;
        let s = self.at(x0, j);
        let sat = |v: i64| v.clamp(i32::MIN as i64, i32::MAX as i64) as i32;
        let p = |v: [i64; 3]| TexPoint::from_bits(sat(v[0]), sat(v[1]), sat(v[2]));
        Some((
            x0,
            Span {
                s0: p(s),
                ds: p(steps.su),
                dsdy: p(steps.sv),
                len,
            },
        ))
    }
}

/// The steps of a triangle's solid coordinates per texel along `u` and `v` (raw `Q16.16`).
struct RowSteps {
    su: [i64; 3],
    sv: [i64; 3],
}

/// `n / l2` rounded to nearest, ties away from zero (the same on every target), for `l2 > 0`:
/// on the 32-bit divide when `|n| + l2 / 2` fits `u32` (every texel of a device-sized atlas),
/// else in 64 bits. `|n| < 2^62` (solid coordinates differ by less than `2^33`, offsets are
/// below `2^18` half texels), so the sum cannot overflow.
fn div_round(n: i64, l2: i64) -> i64 {
    let m = n.unsigned_abs() + (l2 / 2) as u64;
    let d = l2 as u64;
    let q = if m <= u64::from(u32::MAX) && d <= u64::from(u32::MAX) {
        // `checked_div`: no panic path; `l2 > 0` by construction.
        u64::from((m as u32).checked_div(d as u32).unwrap_or(0))
    } else {
        m.checked_div(d).unwrap_or(0)
    };
    if n >= 0 {
        q as i64
    } else {
        -(q as i64)
    }
}

/// Bakes `texture` into the owned texels of every triangle of `layout`, calling
/// `put(x, y, colour)` once per owned texel (row by row, left to right within a triangle's row).
/// Returns the number of texels written.
pub fn bake<const T: usize, const N: usize, P: FnMut(u16, u16, Rgba8888)>(
    layout: &[AtlasTriangle],
    texture: &mut TextureEvaluator<'_, T, N>,
    mut put: P,
) -> u32 {
    let mut texels = 0u32;
    for t in layout {
        let (_, y, _, h) = t.block();
        let steps = t.steps();
        for j in y..y.saturating_add(h) {
            if let Some((x0, span)) = t.row_span_with(j, &steps) {
                let mut x = x0;
                texture.shade(&span, |c| {
                    put(x, j, c);
                    x = x.wrapping_add(1);
                });
                texels = texels.wrapping_add(span.len as u32);
            }
        }
    }
    texels
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::sample::AtlasImage;
    use super::*;
    use std::format;
    use std::string::String;
    use std::vec;
    use std::vec::Vec;

    #[test]
    fn div_round_is_the_rounded_quotient() {
        // Round to nearest, ties away from zero, on both the 32-bit and the 64-bit path.
        let want = |n: i64, d: i64| -> i64 {
            let (q, r) = (n / d, n % d);
            if 2 * r.abs() >= d {
                q + n.signum()
            } else {
                q
            }
        };
        let big = [
            1i64 << 31,
            (1 << 32) - 1,
            1 << 32,
            1 << 40,
            (1 << 61) + 12345,
        ];
        for d in [1i64, 2, 3, 14, 16, 255, 4096, (1 << 32) - 2, 1 << 33] {
            for n in (-3000i64..3000).chain(big).chain(big.map(|b| -b)) {
                assert_eq!(div_round(n, d), want(n, d), "{n} / {d}");
                if n.abs() < 1 << 40 {
                    let m = n * 7919;
                    assert_eq!(div_round(m, d), want(m, d), "{m} / {d}");
                }
            }
        }
    }

    fn tp(s: i32, t: i32, r: i32) -> TexPoint {
        TexPoint::from_bits(s, t, r)
    }

    fn pair(l: u16, g: u8) -> [AtlasTriangle; 2] {
        pair_in(l, g, 0, 0)
    }

    /// The pair of leg `l` and gutter `g` in a block `dw` columns and `dh` rows larger than
    /// the smallest.
    fn pair_in(l: u16, g: u8, dw: u16, dh: u16) -> [AtlasTriangle; 2] {
        let w = l + 2 * g as u16 + 1 + dw;
        let h = l + 2 * g as u16 + dh;
        let solid = [tp(0, 0, 0), tp(65536, 0, 0), tp(0, 65536, 0)];
        [
            AtlasTriangle::new(3, 5, w, h, l, g, Half::Upper, solid).unwrap(),
            AtlasTriangle::new(3, 5, w, h, l, g, Half::Lower, solid).unwrap(),
        ]
    }

    /// An ownership rule: the texels a triangle owns on a row (`AtlasTriangle::row`).
    type RowRule = dyn Fn(&AtlasTriangle, u16) -> Option<(u16, u16)>;
    /// The atlas coordinates a renderer interpolates (`AtlasTriangle::inset_corners`).
    type CornerRule = dyn Fn(&AtlasTriangle) -> [[i32; 2]; 3];

    /// Checks a block's pair under the ownership rule `row` with the renderer's atlas
    /// coordinates `corners`: the halves own disjoint texel sets that cover the block, and
    /// every look-up a renderer makes over a triangle reads with a non-zero weight only texels
    /// that triangle owns. The look-ups are texcore's own kernels (nearest, and with `g = 1`
    /// bilinear) on a mask of the triangle's texels (alpha 255 owned, 0 otherwise, with a
    /// margin of unowned texels around the block); the points are those the renderer samples:
    /// a 1/32-texel grid of barycentric points of the inset triangle (its edges included), and
    /// every 1/512 texel along its edges moved by up to 4 `2^-16` texel in each axis (the
    /// renderer's rounding).
    fn check(
        p: &[AtlasTriangle; 2],
        g: u8,
        row: &RowRule,
        corners: &CornerRule,
    ) -> Result<(), String> {
        let (x, y, w, h) = p[0].block();
        let (iw, ih) = (x + w + 4, y + h + 4);
        let at = |i: u16, j: u16| j as usize * iw as usize + i as usize;
        let mut owner = vec![None; iw as usize * ih as usize];
        for (k, t) in p.iter().enumerate() {
            for j in y..y + h {
                if let Some((x0, n)) = row(t, j) {
                    for i in x0..x0 + n {
                        if i < x || i >= x + w {
                            return Err(format!("texel ({i}, {j}) outside the block"));
                        }
                        if owner[at(i, j)].replace(k).is_some() {
                            return Err(format!("texel ({i}, {j}) owned twice"));
                        }
                    }
                }
            }
        }
        for j in y..y + h {
            for i in x..x + w {
                if owner[at(i, j)].is_none() {
                    return Err(format!("texel ({i}, {j}) owned by neither half"));
                }
            }
        }
        for (k, t) in p.iter().enumerate() {
            let mask: Vec<Rgba8888> = owner
                .iter()
                .map(|&o| {
                    if o == Some(k) {
                        Rgba8888::WHITE
                    } else {
                        Rgba8888::TRANSPARENT
                    }
                })
                .collect();
            let img = AtlasImage::new(&mask, iw, ih).unwrap();
            let probe = |u: i64, v: i64| -> Result<(), String> {
                let (u, v) = (u as i32, v as i32);
                let nearest = img.nearest(u, v).a == 255;
                if !nearest || (g == 1 && img.bilinear(u, v).a != 255) {
                    return Err(format!(
                        "{:?} half: a {} look-up at ({}, {}) reads a texel it does not own",
                        t.half(),
                        if nearest { "bilinear" } else { "nearest" },
                        u as f64 / 65536.0,
                        v as f64 / 65536.0
                    ));
                }
                Ok(())
            };
            let c = corners(t).map(|q| q.map(i64::from));
            let l = t.leg() as i64;
            let n = 32 * l;
            for s in 0..=n {
                for q in 0..=n - s {
                    let pt = |a: usize| {
                        c[0][a] + ((c[1][a] - c[0][a]) * s + (c[2][a] - c[0][a]) * q) / n
                    };
                    probe(pt(0), pt(1))?;
                }
            }
            let n = 512 * l;
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                for s in 0..=n {
                    let pt = |d: usize| c[a][d] + (c[b][d] - c[a][d]) * s / n;
                    for du in [-4, 0, 4] {
                        for dv in [-4, 0, 4] {
                            probe(pt(0) + du, pt(1) + dv)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The two halves of a block own disjoint sets of texels covering the block, and each owns
    /// every texel a nearest (g = 0, 1) or bilinear (g = 1) look-up reads at the points a
    /// renderer samples over it (`check`): legs 1 to 11 in the smallest blocks, legs 1 to 5 in
    /// larger ones.
    #[test]
    fn halves_partition_the_block_and_own_their_footprints() {
        for g in [0u8, 1] {
            for l in 1..12u16 {
                for (dw, dh) in [(0, 0), (1, 0), (0, 1), (2, 3)] {
                    if (dw, dh) != (0, 0) && l > 5 {
                        continue;
                    }
                    let r = check(
                        &pair_in(l, g, dw, dh),
                        g,
                        &AtlasTriangle::row,
                        &AtlasTriangle::inset_corners,
                    );
                    assert_eq!(r, Ok(()), "leg {l} gutter {g} block +{dw} +{dh}");
                }
            }
        }
    }

    /// The check above fails with a rule one texel tighter (the upper half gives the last
    /// texel of each of its rows to the lower half), with the right angle one texel inside
    /// the block's corner instead of half a texel for bilinear look-ups (`g = 1`), and with the
    /// exact corners instead of the inset ones.
    #[test]
    fn the_ownership_check_fails_broken_rules() {
        let tighter = |t: &AtlasTriangle, j: u16| {
            let (x0, n) = t.row(j)?;
            match t.half() {
                Half::Upper => (n > 1).then_some((x0, n - 1)),
                Half::Lower if x0 > t.block().0 => Some((x0 - 1, n + 1)),
                Half::Lower => Some((x0, n)),
            }
        };
        let whole_texel_gutter = |t: &AtlasTriangle| {
            let d = if t.half() == Half::Upper {
                1 << 15
            } else {
                -(1 << 15)
            };
            t.inset_corners().map(|c| c.map(|v| v + d))
        };
        let exact = |t: &AtlasTriangle| t.corners_x16().map(|c| c.map(|v| v << 12));
        for l in 1..12u16 {
            for g in [0u8, 1] {
                let p = pair(l, g);
                let inset = &AtlasTriangle::inset_corners;
                let r = check(&p, g, &tighter, inset);
                assert!(
                    r.is_err_and(|e| e.contains("look-up")),
                    "leg {l} gutter {g}"
                );
                assert!(
                    check(&p, g, &AtlasTriangle::row, &exact).is_err(),
                    "leg {l} gutter {g}"
                );
            }
            let p = pair(l, 1);
            let r = check(&p, 1, &AtlasTriangle::row, &whole_texel_gutter);
            assert!(r.is_err_and(|e| e.contains("bilinear")), "leg {l}");
        }
    }

    /// The baked solid coordinates are the triangle's affine map at the texel centres.
    #[test]
    fn spans_follow_the_affine_map() {
        let p = pair(8, 1);
        // Upper: right angle at (3.5, 5.5), leg 8; centre of texel (5, 6) is (5.5, 6.5):
        // s = (2 / 8, 1 / 8).
        let (x0, span) = p[0].row_span(6).unwrap();
        assert_eq!(x0, 3);
        let s = |i: u16| span.s0.to_bits()[0] + i as i32 * span.ds.to_bits()[0];
        assert_eq!(s(2), 65536 * 2 / 8);
        assert_eq!(span.s0.to_bits()[1], 65536 / 8);
        assert_eq!(span.ds.to_bits(), [8192, 0, 0]);
        assert_eq!(span.dsdy.to_bits(), [0, 8192, 0]);
        // Lower: steps reversed.
        let (_, span) = p[1].row_span(14).unwrap();
        assert_eq!(span.ds.to_bits(), [-8192, 0, 0]);
    }

    #[test]
    fn bad_geometry_is_refused() {
        let s = [tp(0, 0, 0); 3];
        assert_eq!(
            AtlasTriangle::new(0, 0, 10, 10, 0, 0, Half::Upper, s),
            Err(AtlasError::ZeroLeg)
        );
        assert_eq!(
            AtlasTriangle::new(0, 0, 8, 10, 8, 0, Half::Upper, s),
            Err(AtlasError::BlockTooSmall)
        );
        assert_eq!(
            AtlasTriangle::new(0, 0, 11, 9, 8, 1, Half::Upper, s),
            Err(AtlasError::BlockTooSmall)
        );
        assert!(AtlasTriangle::new(0, 0, 11, 10, 8, 1, Half::Upper, s).is_ok());
        assert_eq!(
            AtlasTriangle::new(65530, 0, 10, 10, 8, 0, Half::Upper, s),
            Err(AtlasError::OutOfRange)
        );
    }

    #[test]
    #[cfg(feature = "csat")]
    fn bake_writes_each_owned_texel_once() {
        use crate::hash::HashKind;
        let tex =
            crate::texture::workload::marble_csat(HashKind::Integer, crate::span::EvalMode::Auto)
                .unwrap();
        let p = pair(6, 1);
        let mut ev = tex.evaluator();
        let mut seen = Vec::new();
        let n = bake(&p, &mut ev, |x, y, _| seen.push((x, y)));
        let (_, _, w, h) = p[0].block();
        assert_eq!(n as usize, w as usize * h as usize);
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), n as usize);
    }
}
