//! Small textured triangles: the fast path of [`Rasterizer::draw_textured`] in 32-bit words.
//!
//! A triangle whose raw vertex coordinates all lie in `(-2^14, 2^14)` (1024 pixels either side
//! of the origin, far past any band a device draws) is set up and walked here:
//!
//! - **Set-up** ([`Small::set_up`]): the area, culling, the vertex order, the edge functions
//!   and the edge walks' quotients fit `i32`; the depth plane is divided by the doubled area
//!   exactly as `setup::Plane::new` does it (the same rounding, from the same sums); the
//!   homogeneous planes take 32 x 32-bit products (weights below `2^30`, edge functions below
//!   `2^30`), taken to the texel words at the triangle's anchor (`textured::anchored_words`).
//! - **Walk** ([`draw_small`], out of line: a register file of its own): `i32` edge walkers,
//!   then per run (out of line too) the depth plane and the texel words at its first pixel,
//!   stepped, the depth test without a clamp (it never acts, [`SmallSetup::zplane`]) and the
//!   texel look-up of the general fast path.
//!
//! # Guarantees
//!
//! Exactly the pixels, depths and counters of the general fast path (and so of
//! [`Rasterizer::draw_depth`]'s coverage and depth): every value computed here is the same
//! integer the wide path computes, each bound stated where it is used. Tested against the
//! wide path on random small triangles, triangles at the small range's edges and slivers
//! (`small_path_equals_the_wide_path` in `textured.rs`).
//!
//! [`Rasterizer::draw_textured`]: super::Rasterizer::draw_textured
//! [`Rasterizer::draw_depth`]: super::Rasterizer::draw_depth

use super::edge::sorted_by_y;
use super::setup::{round_plane_shifted, Reject};
use super::textured::{anchor, texel_at, whole, words_at, words_of};
use super::{CullMode, DepthFunc, Perspective, Rect, ScreenVertex, TriangleOptions};
use crate::wide::leading_zeros_u32;
use core::num::NonZeroU32;

/// Raw coordinates of a *small* triangle lie in `(-SMALL, SMALL)` (1024 pixels either side of
/// the origin): its edge walk fits `i32` (see [`EdgeWalker32::new`]).
const SMALL: i32 = 1 << 14;

/// Pixels added to an edge walker's column before its division ([`EdgeWalker32`]): every
/// column it takes lies in `(-BIAS, BIAS)`.
const BIAS: i32 = 2048;

/// An edge walker in 32-bit words: exactly `edge::EdgeWalker`'s columns for a small triangle.
///
/// `edge::EdgeWalker` keeps the column `x = floor(N / m)` of the numerator `N` as a quotient and
/// a remainder, and steps both. Here the walker keeps `N + BIAS m` itself (one word, stepped by
/// `16 dx` a row) and divides it by `m` when a row asks for the column: one unsigned division
/// instead of the remainder's test and correction, and three words instead of five (the two
/// walkers and the runs' loop then fit the register file better).
///
/// Exactness: at every row [`draw_small`] reads (rows whose centres lie within the edge's
/// vertical extent), the column lies within a pixel of the edge's vertices' columns, which lie
/// in `(-2^10, 2^10)`: `N + BIAS m` is then in `[(BIAS - 2^10 - 2) m, (BIAS + 2^10 + 1) m)`,
/// positive and below `2^31` (`m = 16 dy < 2^19`), so the wrapping sums hold its exact value
/// and the unsigned quotient is `floor(N / m) + BIAS`.
#[derive(Clone, Copy)]
struct EdgeWalker32 {
    /// `N + BIAS m` (see above).
    n: u32,
    m: NonZeroU32,
    /// `16 dx`, the numerator's step a row (wrapping).
    step: u32,
}

impl EdgeWalker32 {
    /// The edge `a -> b` at row `py` (`a.y <= 16 py + 8 < b.y` when `a.y < b.y`), as
    /// `edge::EdgeWalker::new`: `N = (a.x - 8) dy + (cy - a.y) dx + m - 1` for `m = 16 dy`, or
    /// the column `floor(a.x / 16)` (`N = a.x`, `m = 16`, no step) for an edge with `dy <= 0`.
    /// The products and sums wrap; their true sum plus `BIAS m` is positive and below `2^31`
    /// (see the type), so the wrapping word is that value.
    #[inline(always)]
    fn new(a: [i32; 2], b: [i32; 2], py: i32) -> EdgeWalker32 {
        let (dx, dy) = (b[0].wrapping_sub(a[0]), b[1].wrapping_sub(a[1]));
        let (n, m, step) = if dy <= 0 {
            (a[0], 16, 0)
        } else {
            let m = dy.wrapping_mul(16);
            let cy = py.wrapping_mul(16).wrapping_add(8);
            let n = (a[0] - 8)
                .wrapping_mul(dy)
                .wrapping_add((cy - a[1]).wrapping_mul(dx))
                .wrapping_add(m - 1);
            (n, m, dx.wrapping_mul(16))
        };
        EdgeWalker32 {
            n: n.wrapping_add(BIAS.wrapping_mul(m)) as u32,
            // m >= 16 (no panic path: the minimum is never taken).
            m: NonZeroU32::new(m as u32).unwrap_or(NonZeroU32::MIN),
            step: step as u32,
        }
    }

    /// The column at the current row: `floor(N / m)`.
    #[inline(always)]
    fn x(&self) -> i32 {
        (self.n / self.m) as i32 - BIAS
    }

    /// On to the next row.
    #[inline(always)]
    fn advance(&mut self) {
        self.n = self.n.wrapping_add(self.step);
    }
}

/// The coverage of a small triangle in `i32` words (`edge::Coverage`).
pub(crate) struct SmallCoverage {
    top: [i32; 2],
    mid: [i32; 2],
    bot: [i32; 2],
    mid_right: bool,
    py_first: i32,
    py_mid: i32,
    py_end: i32,
}

/// What the pixels of a small triangle need besides its set-up: the depth test's bias and
/// write, and the texture.
pub(crate) struct SmallRun<'a> {
    pub(crate) bias: u32,
    pub(crate) write: bool,
    pub(crate) texels: &'a [u16],
}

/// The depth plane's value and the texel words of a small triangle at pixel `(px, py)` (both
/// at least 0: zero-extended, each depth product is one 32 x 64-bit multiplication; the words
/// from pixel `(0, 0)`, [`SmallSetup::words`]).
#[inline(always)]
fn start_at(set_up: &SmallSetup, px: u32, py: u32) -> (i64, [i32; 3]) {
    let [c, dx, dy] = set_up.zplane;
    let z = c
        .wrapping_add(dx.wrapping_mul(i64::from(px)))
        .wrapping_add(dy.wrapping_mul(i64::from(py)));
    (z, words_at(&set_up.words, [0, 0], px as i32, py as i32))
}

/// One run of a small triangle set up as `set_up`, from pixel `(px, py)` along `depth` and
/// `colour`: the depth plane and the texel words at its first pixel ([`start_at`]), then
/// stepped. With `LESS_WRITE` the depth test is `Less` and the depth written (the default
/// options: the test is one comparison with no bias, and the loop keeps one register more);
/// otherwise `run`'s bias and write apply. Returns the pixels that failed the depth test
/// (counted on the rarer branch: most pixels of a frame pass).
///
/// Out of line, computing its own start: its registers then hold the run's depth words, texel
/// words and steps (inlined into the row loop on the Cortex-M4F, with the start computed by the
/// loop, `atlas:marble` measured 2.6 instructions a frame pixel dearer).
#[inline(never)]
fn small_run<const LESS_WRITE: bool, const SIDE: usize>(
    depth: &mut [u16],
    colour: &mut [u16],
    set_up: &SmallSetup,
    (px, py): (u32, u32),
    run: &SmallRun<'_>,
) -> u32 {
    let (mut zp, [mut nu, mut nv, mut dd]) = start_at(set_up, px, py);
    let dz = set_up.zplane[1];
    let [du, dv, ddx] = set_up.words.map(|w| w[1]);
    let mut failed = 0u32;
    // A `Texture565`'s texels are whole: the look-ups' index is then below a constant length.
    let Some(texels) = whole::<SIDE>(run.texels) else {
        return failed;
    };
    let (bias, write) = if LESS_WRITE {
        (depth_bias(DepthFunc::Less), true)
    } else {
        (run.bias, run.write)
    };
    for (d, c) in depth.iter_mut().zip(colour.iter_mut()) {
        // The depth without the general path's clamp to the vertex depths: at a covered pixel
        // of a small triangle the clamp never acts (`SmallSetup::planes`), so this is the
        // clamped value itself.
        let z = (zp >> 32) as u32;
        #[cfg(debug_assertions)]
        assert!(set_up.zlim[0] <= z as i32 && z as i32 <= set_up.zlim[1]);
        if z < u32::from(*d) + bias {
            if write {
                *d = z as u16;
            }
            *c = texel_at::<SIDE>(texels, [nu, nv, dd]);
        } else {
            failed += 1;
        }
        zp = zp.wrapping_add(dz);
        nu = nu.wrapping_add(du);
        nv = nv.wrapping_add(dv);
        dd = dd.wrapping_add(ddx);
    }
    failed
}

/// Draws a small triangle's covered pixels inside `clip` (within `rect`, the rectangle of
/// `depth` and `colour`): exactly the rows and runs of `edge::for_each_run`, and the pixels of
/// the general fast path. Out of line, with `i32` edge walkers: a register file of its own.
/// Returns the pixels shown and the pixels that failed the depth test.
#[inline(never)]
pub(crate) fn draw_small<const SIDE: usize>(
    set_up: &SmallSetup,
    clip: Rect,
    rect: Rect,
    depth: &mut [u16],
    colour: &mut [u16],
    run: &SmallRun<'_>,
) -> [u32; 2] {
    let cov = &set_up.cov;
    let mut counts = [0u32; 2];
    let y0 = cov.py_first.max(i32::from(clip.y0));
    let y1 = cov.py_end.min(i32::from(clip.y1));
    if y0 >= y1 || clip.x0 >= clip.x1 {
        return counts;
    }
    let stride = usize::from(rect.width());
    let (cx0, cx1) = (i32::from(clip.x0), i32::from(clip.x1));
    let long = EdgeWalker32::new(cov.top, cov.bot, y0);
    let short = if y0 < cov.py_mid {
        EdgeWalker32::new(cov.top, cov.mid, y0)
    } else {
        EdgeWalker32::new(cov.mid, cov.bot, y0)
    };
    // The walkers as the left and right edges, the short one replaced at the middle row.
    let (mut left, mut right) = if cov.mid_right {
        (long, short)
    } else {
        (short, long)
    };
    for py in y0..y1 {
        if py == cov.py_mid && py != y0 {
            let lower = EdgeWalker32::new(cov.mid, cov.bot, py);
            if cov.mid_right {
                right = lower;
            } else {
                left = lower;
            }
        }
        let (l, r) = (left.x(), right.x());
        let xa = l.max(cx0);
        let xb = r.min(cx1);
        left.advance();
        right.advance();
        if xa >= xb {
            continue;
        }
        // clip.x0 <= xa < xb <= clip.x1 and clip.y0 <= py < clip.y1, inside `rect`.
        let off = (py - i32::from(rect.y0)) as usize * stride + (xa - i32::from(rect.x0)) as usize;
        let n = (xb - xa) as usize;
        let (Some(drow), Some(crow)) = (depth.get_mut(off..off + n), colour.get_mut(off..off + n))
        else {
            continue;
        };
        // 0 <= xa, py (inside the clip).
        let start = (xa as u32, py as u32);
        let failed = if run.write && run.bias == depth_bias(DepthFunc::Less) {
            small_run::<true, SIDE>(drow, crow, set_up, start, run)
        } else {
            small_run::<false, SIDE>(drow, crow, set_up, start, run)
        };
        counts[0] += n as u32 - failed;
        counts[1] += failed;
    }
    counts
}

/// The first pixel row (or column) whose centre is at or after raw `v`
/// (`edge::first_centre_at_or_after` in `i32`; `|v| < 2^14`).
#[inline(always)]
fn first_centre(v: i32) -> i32 {
    (v - 8 + 15).div_euclid(16)
}

/// The set-up of a small triangle: what [`draw_small`] needs.
pub(crate) struct SmallSetup {
    pub(crate) cov: SmallCoverage,
    /// The depth plane `[c, dx, dy]` (the depth's rounding folded into `c`).
    ///
    /// Its high word at a covered pixel lies between the least and the greatest vertex depth,
    /// so the general path's clamp to them never acts here and the walk leaves it out: each
    /// coefficient is within 1/2 of its exact value (`round_plane_shifted`) and a covered
    /// pixel lies within `2^10` pixels of the origin in either axis, so the plane is within
    /// `2^11` of the exact `2^32 sum_i z_i E_i / area2`. That is a convex combination of the
    /// `z_i 2^32` (the pixel's centre lies in the closed triangle: every `E_i / area2 >= 0`),
    /// and with the folded `2^31` the value lies in `[zlo 2^32 + 2^31 - 2^11, zhi 2^32 + 2^31 +
    /// 2^11]`, inside `[zlo 2^32, (zhi + 1) 2^32)`. The plane's words wrap, but its value at a
    /// covered pixel (below `2^49`) fits `i64`, so the wrapping sum is that value. Checked by a
    /// debug assertion in the walk and by `small_depth_needs_no_clamp` (against the clamping
    /// wide path).
    pub(crate) zplane: [i64; 3],
    /// The texel words `N_u'`, `N_v'`, `D'` (`textured::texel_words`), each `[at pixel (0, 0),
    /// dx, dy]`: the wide path's words at the anchor (`textured::anchored_words`) taken back
    /// to the origin modulo `2^32`, so that every pixel's words are the wide path's
    /// ([`words_at`] wraps) and a run needs no anchor.
    pub(crate) words: [[i32; 3]; 3],
    /// The least and greatest vertex depth (for the debug assertion of the walk only).
    #[cfg(debug_assertions)]
    pub(crate) zlim: [i32; 2],
}

/// What [`Small::set_up`] decides.
pub(crate) enum Small {
    /// A vertex lies outside `(-2^14, 2^14)`: the general set-up applies.
    Wide,
    /// Rejected (degenerate or culled), as the general set-up rejects it.
    Rejected(Reject),
    /// Set up, but a normalised `1/w` is 0: the general rasterizer draws it.
    General,
    /// Set up for [`draw_small`].
    Ready(SmallSetup),
}

/// The number of significant bits of `v` (`wide::leading_zeros_u32`: a table on rv32imc).
#[inline(always)]
fn bitlen(v: u32) -> u32 {
    32 - leading_zeros_u32(v)
}

impl Small {
    /// Sets up `v` with `opts` for a texture with `frac` fraction bits (`Texture565::frac`).
    #[inline(never)]
    pub(crate) fn set_up(v: &[ScreenVertex; 3], opts: &TriangleOptions, frac: u32) -> Small {
        let p = v.map(|p| [p.x.to_bits(), p.y.to_bits()]);
        if !p.iter().flatten().all(|c| c.unsigned_abs() < SMALL as u32) {
            return Small::Wide;
        }
        let [p0, p1, p2] = p;
        // Coordinate differences below 2^15: products below 2^30, their difference below 2^31.
        let area2 = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
        if area2 == 0 {
            return Small::Rejected(Reject::Degenerate);
        }
        let culled = match opts.cull {
            CullMode::None => false,
            CullMode::Clockwise => area2 > 0,
            CullMode::CounterClockwise => area2 < 0,
        };
        if culled {
            return Small::Rejected(Reject::Culled);
        }
        // Edge functions E_i = [E_i(0, 0), dE_i/dx, dE_i/dy] (`setup::PlaneBasis`): |x - 8| below
        // 2^14 + 8, so each product is below 2^28.01 and the constant below 2^29.01; the steps
        // below 2^19.
        let mut e = [[0i32; 3]; 3];
        for (ei, [xj, yj], [xk, yk]) in [(0, p1, p2), (1, p2, p0), (2, p0, p1)] {
            if let Some(row) = e.get_mut(ei) {
                *row = [
                    (xj - 8) * (yk - 8) - (xk - 8) * (yj - 8),
                    (yj - yk) * 16,
                    (xk - xj) * 16,
                ];
            }
        }
        // Depth: the plane of z_i << 32 is round((sum_i z_i E_i) 2^32 / area2) per coefficient
        // (sums below 2^47.6, exact in i64), as `setup::Plane::new` rounds it.
        let z = v.map(|p| i32::from(p.z));
        // The edge functions by coefficient: `cols[c][i]` is `E_i`'s coefficient `c`.
        let [e0, e1, e2] = e;
        let cols = [
            [e0[0], e1[0], e2[0]],
            [e0[1], e1[1], e2[1]],
            [e0[2], e1[2], e2[2]],
        ];
        // Three 32 x 32 -> 64-bit products (operands below 2^31: a widening multiplication
        // each), summed exactly in i64.
        let dot = |a: [i32; 3], c: [i32; 3]| {
            let p = |k: usize| i64::from(a[k]) * i64::from(c[k]);
            p(0) + p(1) + p(2)
        };
        let [c0, c1, c2] = cols;
        // The steps `sum_i a_i dE_i/dx`, `sum_i a_i dE_i/dy`: on rv32imc from two differences
        // of `a` ([`difference_steps`]: two products each instead of three), elsewhere as the
        // sums themselves (the Cortex-M's multiply-accumulate makes the three products as
        // cheap). The same integers either way.
        let steps = |a: [i32; 3]| {
            if cfg!(target_arch = "riscv32") {
                difference_steps(a, &p)
            } else {
                (dot(a, c1), dot(a, c2))
            }
        };
        let (zsx, zsy) = steps(z);
        let zsums = [dot(z, c0), zsx, zsy];
        // The homogeneous planes (`textured::Homogeneous::new`): weights q_i u_i, q_i v_i, q_i
        // below 2^30, edge functions below 2^29.01: each sum of three products below 2^60.6,
        // exact in i64, then scaled by 2^k and negated for a negative area modulo 2^64.
        let inv_w = v.map(|p| p.inv_w.to_bits());
        let qmax = inv_w.iter().copied().max().unwrap_or(0);
        let q = if opts.perspective == Perspective::Affine || qmax == 0 {
            [1u32 << 14; 3]
        } else {
            let bl = bitlen(qmax);
            inv_w.map(|w| {
                if bl > 15 {
                    w >> (bl - 15)
                } else {
                    w << (15 - bl)
                }
            })
        };
        if q.contains(&0) {
            return Small::General;
        }
        let k = 33 - bitlen(area2.unsigned_abs());
        let top = (1i32 << 15) - 1;
        let coord = |t: i32| (t >> (16 - frac)).max(0).min(top);
        let [t0, t1, t2] = v.map(|p| p.tex.to_bits());
        let [q0, q1, q2] = q.map(|qi| qi as i32);
        // The weights of vertex i per plane j (N_u, N_v, D).
        let w = [
            [q0 * coord(t0[0]), q1 * coord(t1[0]), q2 * coord(t2[0])],
            [q0 * coord(t0[1]), q1 * coord(t1[1]), q2 * coord(t2[1])],
            [q0, q1, q2],
        ];
        // 2^k with the area's sign (k <= 33): one wrapping product scales and negates (a
        // shift by `k` and a negation measured 2.4 instructions a frame pixel dearer on the
        // Cortex-M4F, 0.45 cheaper on rv32imc).
        let scale = if area2 < 0 { -(1i64 << k) } else { 1i64 << k };
        // The texel words at the anchor from the edge functions there (`E_i(A)`: below
        // 2^29.01 + 2 2^19 2^10 < 2^31 for an anchor within 2^10 pixels of the origin, so each
        // sum of three products is below 2^62.2), exactly the wide path's `c + dx ax + dy ay` of
        // the same planes modulo 2^64 (`anchored_words`).
        let anchor = anchor(p0[0].min(p1[0]).min(p2[0]), p0[1].min(p1[1]).min(p2[1]));
        let [ax, ay] = anchor;
        // Constant indices (a closure's index is a bounds check in the size-lean shape).
        let e_at = |c: i32, dx: i32, dy: i32| c + dx * ax + dy * ay;
        let ea = [
            e_at(c0[0], c1[0], c2[0]),
            e_at(c0[1], c1[1], c2[1]),
            e_at(c0[2], c1[2], c2[2]),
        ];
        let scaled = |v: i64| v.wrapping_mul(scale);
        let (at, dx, dy) = {
            let [wu, wv, wd] = w;
            let (ux, uy) = steps(wu);
            let (vx, vy) = steps(wv);
            let (dxd, dyd) = steps(wd);
            (
                [dot(wu, ea), dot(wv, ea), dot(wd, ea)].map(scaled),
                [ux, vx, dxd].map(scaled),
                [uy, vy, dyd].map(scaled),
            )
        };
        // Taken back from the anchor to pixel (0, 0), wrapping: the same words at every pixel.
        let words = words_of(at, dx, dy).map(|[w, wx, wy]| {
            [
                w.wrapping_sub(wx.wrapping_mul(ax))
                    .wrapping_sub(wy.wrapping_mul(ay)),
                wx,
                wy,
            ]
        });
        // The depth plane's divisions and the coverage last, in this order (measured on the
        // Cortex-M4F: fewer values live across the divisions and the planes' products).
        let [zc, zdx, zdy] = depth_plane(zsums, area2);
        // The vertices sorted by y as `edge::Coverage::new` sorts them (the anchor took the
        // least y, `cov.top`'s, itself).
        let [a, b, c] = sorted_by_y(p);
        let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let cov = SmallCoverage {
            top: a,
            mid: b,
            bot: c,
            mid_right: cross > 0,
            py_first: first_centre(a[1]),
            py_mid: first_centre(b[1]),
            py_end: first_centre(c[1]),
        };
        Small::Ready(SmallSetup {
            cov,
            zplane: [zc.wrapping_add(1 << 31), zdx, zdy],
            words,
            #[cfg(debug_assertions)]
            zlim: [
                z.iter().copied().min().unwrap_or(0),
                z.iter().copied().max().unwrap_or(0),
            ],
        })
    }
}

/// The depth plane `round_plane_shifted(sums, area2)` of a small triangle (`|sums_i| < 2^48`,
/// `area2 != 0`): for `|area2| < 2^16` (every triangle under 128 pixels) by long division in
/// 16-bit digits on the 32-bit hardware divide, four digits a coefficient; otherwise
/// [`round_plane_shifted`] itself.
///
/// The same integers: with `a = |area2|` and `v` the sum times the area's sign, the coefficient
/// is `floor((v 2^32 + floor(a / 2)) / a)` (round half up: `setup::AreaDivisor::div_round`),
/// and for a negative numerator `m`, `floor(m / a) = !floor(!m / a)`. `!m`'s high part is
/// `!v < 2^48` and its low word `!floor(a / 2)`. Each digit step divides `r 2^16 + digit` with
/// `r < a <= 2^16`, below `2^32`; the first divides the top 32 of the 48 high bits. The
/// quotient is assembled modulo `2^64`, as the wide path's `as i64` takes it.
#[inline(always)]
fn depth_plane(sums: [i64; 3], area2: i32) -> [i64; 3] {
    let a = area2.unsigned_abs();
    let Some(d) = NonZeroU32::new(a).filter(|_| a < 1 << 16) else {
        return round_plane_shifted(sums, area2);
    };
    let half = a >> 1;
    sums.map(|v| {
        let v = if area2 < 0 { v.wrapping_neg() } else { v };
        let mask = v >> 63;
        let hi = (v ^ mask) as u64;
        let lo = half ^ mask as u32;
        let step = |r: u32, digit: u32| {
            let cur = (r << 16) | digit;
            (cur / d, cur % d)
        };
        let top = (hi >> 16) as u32;
        let (q3, r) = (top / d, top % d);
        let (q2, r) = step(r, (hi & 0xFFFF) as u32);
        let (q1, r) = step(r, lo >> 16);
        let (q0, _) = step(r, lo & 0xFFFF);
        let q = (u64::from(q3) << 48)
            .wrapping_add(u64::from(q2) << 32)
            .wrapping_add(u64::from(q1) << 16)
            .wrapping_add(u64::from(q0));
        (q as i64) ^ mask
    })
}

/// `(sum_i a_i dE_i/dx, sum_i a_i dE_i/dy)` for the edge functions of the raw vertices `p`
/// (`dE_i/dx = (y_j - y_k) 16`, `dE_i/dy = (x_k - x_j) 16` for `(i, j, k)` the rotations of
/// `(0, 1, 2)`) from two differences of `a`: the sums expand to `(a_1 - a_0)(y_2 - y_0) -
/// (a_2 - a_0)(y_1 - y_0)` and `(a_2 - a_0)(x_1 - x_0) - (a_1 - a_0)(x_2 - x_0)`, times 16.
/// Exact for `|a_i| < 2^30` (the differences fit `i32`) and coordinates in `(-2^14, 2^14)`:
/// every product is below `2^45`.
#[inline(always)]
fn difference_steps(a: [i32; 3], p: &[[i32; 2]; 3]) -> (i64, i64) {
    let [p0, p1, p2] = *p;
    let [dx1, dy1] = [p1[0] - p0[0], p1[1] - p0[1]].map(i64::from);
    let [dx2, dy2] = [p2[0] - p0[0], p2[1] - p0[1]].map(i64::from);
    let (a1, a2) = (i64::from(a[1] - a[0]), i64::from(a[2] - a[0]));
    ((a1 * dy2 - a2 * dy1) * 16, (a2 * dx1 - a1 * dx2) * 16)
}

/// The depth test of `opts` as one unsigned comparison `z < stored + bias`: `Less` is bias 0,
/// `LessEqual` bias 1, `Always` past every depth (z and stored are below 2^16).
pub(crate) const fn depth_bias(func: DepthFunc) -> u32 {
    match func {
        DepthFunc::Less => 0,
        DepthFunc::LessEqual => 1,
        DepthFunc::Always => 1 << 16,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The walker's column at every row of an edge is `floor(N / m)` of `edge::EdgeWalker`'s
    /// numerator (in `i64`): random edges, and edges whose ends are at the small range's
    /// corners (the longest, steepest and flattest), stepped from their first row to their
    /// last; and `floor(a.x / 16)` for a horizontal edge.
    #[test]
    fn edge_walker_columns_are_the_quotients() {
        let mut rng = crate::test_rng::XorShift64::new(0x0DDB_1A5E_5BAD_5EED);
        let lim = SMALL - 1;
        let ends = [-lim, lim, 0, -1, 1, 8, -8];
        let mut rows = 0u64;
        for n in 0..4000u32 {
            let (a, b) = if n < 7u32.pow(4) {
                let c = |i: u32| ends[(n / 7u32.pow(i) % 7) as usize];
                ([c(0), c(1)], [c(2), c(3)])
            } else {
                let mut c = || rng.below(2 * lim as u64 + 1) as i32 - lim;
                ([c(), c()], [c(), c()])
            };
            let (a, b) = if a[1] <= b[1] { (a, b) } else { (b, a) };
            let (dx, dy) = (i64::from(b[0] - a[0]), i64::from(b[1] - a[1]));
            if dy == 0 {
                let w = EdgeWalker32::new(a, b, 0);
                assert_eq!(w.x(), a[0].div_euclid(16), "{a:?} {b:?}");
                continue;
            }
            let (first, end) = (first_centre(a[1]), first_centre(b[1]));
            let mut w = EdgeWalker32::new(a, b, first);
            for py in first..end {
                let cy = i64::from(py) * 16 + 8;
                let m = 16 * dy;
                let num = i64::from(a[0] - 8) * dy + (cy - i64::from(a[1])) * dx + m - 1;
                assert_eq!(i64::from(w.x()), num.div_euclid(m), "{a:?} {b:?} row {py}");
                w.advance();
                rows += 1;
            }
        }
        assert!(rows > 1_000_000, "{rows} rows");
    }

    /// `x` with `c x = 1` modulo `m` (`c` and `m` coprime; 0 for `m = 1`).
    fn inverse_mod(c: i64, m: i64) -> i64 {
        let (mut r0, mut r1, mut x0, mut x1) = (m, c.rem_euclid(m), 0i64, 1i64);
        while r1 != 0 {
            let q = r0 / r1;
            (r0, r1) = (r1, r0 - q * r1);
            (x0, x1) = (x1, x0 - q * x1);
        }
        x0.rem_euclid(m)
    }

    /// The small depth plane is `round_plane_shifted`'s: random sums below `2^48` and areas
    /// of either sign, both sides of `2^16` (the digit division and the fall-back), the ends
    /// of both ranges, and numerators on and beside a rounding step (`v 2^32 + floor(a / 2)`
    /// a multiple of `a`, give or take one), where a wrong half or a wrong sign's floor shows.
    #[test]
    fn depth_plane_is_round_plane_shifted() {
        let mut rng = crate::test_rng::XorShift64::new(0x5EED_DEC0_DE0F_A11D);
        let vlim = (1i64 << 48) - 1;
        let vends = [0, 1, -1, vlim, -vlim, 1 << 32, -(1 << 32), (1 << 32) - 1];
        let aends = [
            1i32,
            -1,
            2,
            -2,
            3,
            0xFFFF,
            -0xFFFF,
            0x1_0000,
            -0x1_0000,
            0x7FFF_FFFF,
        ];
        let mut ties = 0u32;
        for n in 0..400_000u32 {
            let a = match n % 4 {
                0 => aends[(n / 4) as usize % aends.len()],
                1 => 1 + rng.below(0xFFFF) as i32,
                2 => -(1 + rng.below(0xFFFF) as i32),
                _ => rng.below(1 << 32) as u32 as i32,
            };
            if a == 0 {
                continue;
            }
            let mut v = [0i64; 3];
            for (k, x) in v.iter_mut().enumerate() {
                *x = match (n / 3 + k as u32) % 4 {
                    0 => vends[rng.below(vends.len() as u64) as usize],
                    1 => rng.below(2 * vlim as u64 + 1) as i64 - vlim,
                    2 => rng.below(1 << 20) as i64 - (1 << 19),
                    _ => {
                        // On a rounding step: `v 2^32 + floor(a / 2)` within one of a multiple
                        // of an odd `a` (through the inverse of `2^32` modulo `a`).
                        let m = i64::from(a.unsigned_abs() | 1).min(0xFFFF);
                        let inv = inverse_mod((1i64 << 32) % m, m);
                        let t = (m - m / 2 + rng.below(3) as i64 - 1).rem_euclid(m);
                        let k = rng.below(1 << 20) as i64 - (1 << 19);
                        ties += 1;
                        let v = (t * inv).rem_euclid(m) + k * m;
                        if a < 0 {
                            -v
                        } else {
                            v
                        }
                    }
                };
            }
            assert_eq!(depth_plane(v, a), round_plane_shifted(v, a), "{v:?} / {a}");
        }
        assert!(ties > 50_000, "{ties}");
    }

    /// The three-term sums `sum_i a_i dE_i/dx`, `sum_i a_i dE_i/dy` of the edge functions.
    fn edge_sums(a: [i32; 3], p: &[[i32; 2]; 3]) -> (i64, i64) {
        let [p0, p1, p2] = *p;
        let mut s = (0i64, 0i64);
        for (ai, [xj, yj], [xk, yk]) in [(a[0], p1, p2), (a[1], p2, p0), (a[2], p0, p1)] {
            s.0 += i64::from(ai) * i64::from((yj - yk) * 16);
            s.1 += i64::from(ai) * i64::from((xk - xj) * 16);
        }
        s
    }

    /// The difference form is the sums, at random and at the ranges' ends (weights to
    /// `2^30 - 1`, coordinates to `+-(2^14 - 1)`); a wrong sign or a wrong pair fails.
    #[test]
    fn difference_steps_are_the_edge_sums() {
        let mut rng = crate::test_rng::XorShift64::new(0x9E37_79B9_7F4A_7C15);
        let mut rnd = |m: u64| rng.below(m);
        let lim = SMALL - 1;
        let ends = [-lim, lim, 0, 1, -1];
        for n in 0..200_000u32 {
            let (a, p) = if n < 3125 {
                // Every coordinate at an end, weights at their extremes.
                let c = |i: u32| ends[(n / 5u32.pow(i) % 5) as usize];
                let p = [[c(0), c(1)], [c(2), c(3)], [c(4), c(0)]];
                let a = [(1 << 30) - 1, 0, (n as i32 & 1) * ((1 << 30) - 1)];
                (a, p)
            } else {
                let c = |r: &mut dyn FnMut(u64) -> u64| r(2 * lim as u64 + 1) as i32 - lim;
                let p = [
                    [c(&mut rnd), c(&mut rnd)],
                    [c(&mut rnd), c(&mut rnd)],
                    [c(&mut rnd), c(&mut rnd)],
                ];
                let a = [0; 3].map(|_| rnd(1 << 30) as i32);
                (a, p)
            };
            assert_eq!(difference_steps(a, &p), edge_sums(a, &p), "{a:?} {p:?}");
        }
    }
}
