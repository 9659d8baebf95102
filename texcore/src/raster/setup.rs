//! Triangle setup: guard band, area and culling, coverage, and the exact plane equations of the
//! interpolants.
//!
//! Every interpolant is a plane `L(px, py) = c + dx px + dy py` over pixel positions, anchored at
//! the centre of pixel `(0, 0)` (never at the clip, so bands agree bit for bit), with `c`, `dx`,
//! `dy` the exact rational coefficients rounded once (half up) in `i128` and then wrapped to
//! `i64`. Evaluation wraps too: the true value at any pixel centre inside the triangle fits `i64`
//! (it is a convex combination of the vertex values, all below `2^62` in magnitude), so the
//! wrapping evaluation returns it exactly, up to the coefficient rounding of at most
//! `1/2 + (|px| + |py|)/2` units of the plane's last bit.
//!
//! Vertex values of the planes (`s_i` are raw 16.16 texture coordinates, `q_i` the normalised
//! `1/w`, `q_i <= 2^30`; `b` = `bitlen(max_i |s_i - s_0|)`, at most 32):
//!
//! | plane | vertex value | bound |
//! |---|---|---|
//! | affine `s` | `(s_i - s_0) << (62 - b)` | `< 2^62` |
//! | `1/w` | `q_i << 32` | `<= 2^62` |
//! | `s/w` | `((s_i - s_0) q_i) << (32 - b)` | `< 2^62` |
//! | depth | `z_i << 32` | `< 2^48` |
//!
//! so that the perspective quotient of component `s` is `(s/w plane) / (1/w plane >> b)`, both
//! carrying the same `32 - b` extra bits: the quotient has about 29 significant bits beyond the
//! range of `s` across the triangle.

use super::edge::{Coverage, HALF, SUB};
use super::{
    div_round_i128, sat_i32, Counters, CullMode, DepthFunc, Perspective, ScreenVertex,
    TriangleOptions, GUARD_BAND,
};
use crate::wide::mul_wide;
#[cfg(not(texcore_lean))]
use crate::wide::{Reciprocal32, Reciprocal64};

/// Why a triangle was not set up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Reject {
    /// Zero area (collinear or repeated vertices).
    Degenerate,
    /// Removed by back-face culling.
    Culled,
    /// A vertex lies outside the guard band ([`GUARD_BAND`](super::GUARD_BAND)).
    OutsideGuardBand,
}

/// A linear function of the pixel position (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Plane {
    /// Value at the centre of pixel `(0, 0)` (rounded, wrapped).
    pub(crate) c: i64,
    /// Change per pixel in x (rounded, wrapped).
    pub(crate) dx: i64,
    /// Change per pixel in y (rounded, wrapped).
    pub(crate) dy: i64,
    /// The rounded x gradient before wrapping.
    pub(crate) gx: i128,
    /// The rounded y gradient before wrapping.
    pub(crate) gy: i128,
}

/// `round(n / area2)` (half up, as [`div_round_i128`]) for the many plane numerators of one
/// triangle: the doubled area's reciprocal is prepared once (`area2` is below 2^63 in magnitude
/// inside the guard band), so each rounding division is a few multiplications instead of a long
/// division: a reciprocal in 32-bit words when `|area2| < 2^32` (every triangle below about 4000
/// pixels on a side: one 32 x 32-bit product a significant numerator word), in 64-bit words
/// otherwise. Gives exactly [`div_round_i128`]'s result.
///
/// The size-lean shape (`cfg(texcore_lean)`) prepares no reciprocal and divides each numerator
/// with [`div_round_i128`] itself (the reference the tests compare the reciprocal path with):
/// a slower set-up, but no second division routine.
#[derive(Clone, Copy, Debug)]
struct AreaDivisor {
    area2: i128,
    /// `|area2|` (when it fits 64 bits).
    #[cfg(not(texcore_lean))]
    mag: u64,
    /// The reciprocal of `|area2|`.
    #[cfg(not(texcore_lean))]
    recip: AreaRecip,
}

/// The reciprocal of a doubled area, by its width.
#[cfg(not(texcore_lean))]
#[derive(Clone, Copy, Debug)]
enum AreaRecip {
    /// `|area2| < 2^32`.
    Narrow(Reciprocal32),
    /// `2^32 <= |area2| < 2^64`.
    Wide(Reciprocal64),
    /// Zero or past 64 bits: [`div_round_i128`].
    None,
}

impl AreaDivisor {
    #[cfg(texcore_lean)]
    fn new(area2: i128) -> AreaDivisor {
        AreaDivisor { area2 }
    }

    /// `round(n / area2)`, ties up: [`div_round_i128`].
    #[cfg(texcore_lean)]
    #[inline]
    fn div_round(&self, n: i128) -> i128 {
        div_round_i128(n, self.area2)
    }

    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn new(area2: i128) -> AreaDivisor {
        let mag = u64::try_from(area2.unsigned_abs()).ok();
        let recip = match mag {
            Some(m) => match u32::try_from(m) {
                Ok(m32) => Reciprocal32::new(m32).map(AreaRecip::Narrow),
                Err(_) => Reciprocal64::new(m).map(AreaRecip::Wide),
            },
            None => None,
        };
        AreaDivisor {
            area2,
            mag: mag.unwrap_or(0),
            recip: recip.unwrap_or(AreaRecip::None),
        }
    }

    /// `round(n / area2)`, ties up, exactly as `div_round_i128(n, area2)`.
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn div_round(&self, n: i128) -> i128 {
        // |n| <= 2^126 (every plane numerator: below 2^125): with a = |area2| and
        // n' = n sign(area2), round_half_up(n' / a) = floor((n' + floor(a / 2)) / a) (for odd a,
        // the 1/2 that n' / a + 1/2 adds beyond floor(a / 2) / a never reaches the next multiple
        // of a), and m = n' + floor(a / 2) lies in (-2^127, 2^127). For m < 0,
        // floor(m / a) = -1 - floor((-m - 1) / a) = !floor(!m / a): the quotient of the magnitude
        // m ^ (m >> 127) < 2^127, xor-ed with the same mask.
        let top = ((n >> 96) as i32) >> 30;
        if let (AreaRecip::Narrow(r), true) = (self.recip, top == 0 || top == -1) {
            let n = if self.area2 < 0 { n.wrapping_neg() } else { n };
            let m = n.wrapping_add(i128::from(self.mag >> 1));
            let mask = m >> 127;
            return (r.div_u127((m ^ mask) as u128) as i128) ^ mask;
        }
        self.div_round_general(n)
    }

    /// [`AreaDivisor::div_round`] for every numerator (out of line: the narrow path is inlined
    /// into each plane).
    #[cfg(not(texcore_lean))]
    #[inline(never)]
    fn div_round_general(&self, n: i128) -> i128 {
        // As div_round_i128: a negative divisor negates both (saturating).
        let nn = if self.area2 < 0 {
            n.saturating_neg()
        } else {
            n
        };
        let (qm, rm) = match self.recip {
            AreaRecip::Narrow(r) => {
                let (q, r) = r.div_rem(nn.unsigned_abs());
                (q, u64::from(r))
            }
            AreaRecip::Wide(r) => r.div_rem(nn.unsigned_abs()),
            AreaRecip::None => return div_round_i128(n, self.area2),
        };
        let d = self.mag;
        // The Euclidean quotient and remainder by d > 0 from the magnitudes (rm < d); |q| <= 2^127
        // wraps like the shared division (only n = i128::MIN, d = 1).
        let (q, rem) = if nn >= 0 || rm == 0 {
            let q = qm as i128;
            (if nn >= 0 { q } else { q.wrapping_neg() }, rm)
        } else {
            ((qm as i128).wrapping_neg().wrapping_sub(1), d - rm)
        };
        if rem >= d - rem {
            q.saturating_add(1)
        } else {
            q
        }
    }
}

/// The plane of vertex values `z_i << 32` from its sums `s = [sum_i z_i E_i]` per coefficient
/// (`|s| < 2^62`) and the doubled area: `round(s_k 2^32 / area2)` (half up) wrapped to `i64`,
/// exactly the `c`, `dx`, `dy` of [`Plane::new`] for those vertex values (the same divisor and
/// rounding; the numerators are the same integers).
#[cfg(feature = "atlas")]
pub(crate) fn round_plane_shifted(s: [i64; 3], area2: i32) -> [i64; 3] {
    let area = AreaDivisor::new(i128::from(area2));
    s.map(|v| area.div_round(i128::from(v) << 32) as i64)
}

/// The barycentric edge functions of a triangle, shared by all its planes: `E_i` at the centre
/// of pixel `(0, 0)` and its steps per pixel in x and y (`sum_i E_i = area2`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlaneBasis {
    /// `[E_i(HALF, HALF), dE_i/dx SUB, dE_i/dy SUB]` for `i = 0, 1, 2`: below `2^62`, `2^35` and
    /// `2^35` in magnitude inside the guard band.
    e: [[i64; 3]; 3],
    /// Every entry of `e` fits `i32` (every triangle below about 2000 pixels from the origin), so
    /// the plane numerators take 64 x 32-bit products (never in the size-lean shape).
    narrow: bool,
}

impl PlaneBasis {
    /// The edge functions of the raw vertex positions `p` (guard band).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(crate) fn new(p: &[[i64; 2]; 3]) -> PlaneBasis {
        let [p0, p1, p2] = *p;
        let mut e = [[0i64; 3]; 3];
        for (ei, [xj, yj], [xk, yk]) in [(0, p1, p2), (1, p2, p0), (2, p0, p1)] {
            // Coordinates less HALF are below 2^30 + 8 in magnitude, so |E_i| < 2^62;
            // dE_i/dx = yj - yk, dE_i/dy = xk - xj per raw unit (SUB raw units per pixel).
            if let Some(row) = e.get_mut(ei) {
                *row = [
                    (xj - HALF) * (yk - HALF) - (xk - HALF) * (yj - HALF),
                    (yj - yk) * SUB,
                    (xk - xj) * SUB,
                ];
            }
        }
        let narrow = !cfg!(texcore_lean) && e.iter().flatten().all(|v| i32::try_from(*v).is_ok());
        PlaneBasis { e, narrow }
    }
}

/// `sum_i l_i e_i` exactly, for `|l_i| <= 2^62` and `e_i` that fit `i32`: each `l_i` split into
/// `(l_i >> 32) 2^32 + (l_i mod 2^32)`, the high products (below `2^61` in magnitude, their sum
/// below `2^63`) summed in `i64`, the low ones (below `2^63`) in `i128`.
#[inline(always)]
fn dot_narrow(l: [i64; 3], e: [i64; 3]) -> i128 {
    let mut hi: i64 = 0;
    let mut lo: i128 = 0;
    for (li, ei) in l.into_iter().zip(e) {
        let b = i64::from(ei as i32);
        hi += i64::from((li >> 32) as i32) * b;
        lo += i128::from(i64::from(li as u32) * b);
    }
    (i128::from(hi) << 32) + lo
}

impl Plane {
    /// The zero plane.
    const ZERO: Plane = Plane {
        c: 0,
        dx: 0,
        dy: 0,
        gx: 0,
        gy: 0,
    };

    /// The plane through the vertex values `l` (each `|l_i| <= 2^62`) at the vertex positions
    /// of `basis`, `area` dividing by the doubled signed area `!= 0`.
    fn new(l: [i64; 3], basis: &PlaneBasis, area: &AreaDivisor) -> Plane {
        let mut num = [0i128; 3];
        for (k, n) in num.iter_mut().enumerate() {
            let e = basis.e.map(|row| row.get(k).copied().unwrap_or(0));
            *n = if !cfg!(texcore_lean) && basis.narrow {
                dot_narrow(l, e)
            } else {
                // |l_i E_i| < 2^124, |l_i dE_i| < 2^97: the sum of three fits i128.
                mul_wide(l[0], e[0]) + mul_wide(l[1], e[1]) + mul_wide(l[2], e[2])
            };
        }
        let [num_c, num_x, num_y] = num;
        let gx = area.div_round(num_x);
        let gy = area.div_round(num_y);
        Plane {
            c: area.div_round(num_c) as i64,
            dx: gx as i64,
            dy: gy as i64,
            gx,
            gy,
        }
    }

    /// The plane's value at pixel `(px, py)` (wrapping).
    #[inline]
    pub(crate) fn at(&self, px: i64, py: i64) -> i64 {
        self.c
            .wrapping_add(self.dx.wrapping_mul(px))
            .wrapping_add(self.dy.wrapping_mul(py))
    }
}

/// Screen-linear texture coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct AffineInterp {
    /// `(s - s_0) << shift` per component.
    pub(crate) planes: [Plane; 3],
    /// Extra fraction bits of each plane (`>= 30`).
    pub(crate) shift: [u32; 3],
    /// Gradient in x per pixel, raw 16.16 (saturated).
    pub(crate) ds: [i32; 3],
    /// Gradient in y per pixel, raw 16.16 (saturated).
    pub(crate) dsdy: [i32; 3],
    /// Some x gradient does not fit `I16F16`: emit pixels one by one.
    pub(crate) steep: bool,
}

/// Perspective-correct texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PerspInterp {
    /// `q << 32` (normalised `1/w`, `q <= 2^30`).
    pub(crate) q: Plane,
    /// `((s - s_0) q) << (32 - qshift)` per component.
    pub(crate) p: [Plane; 3],
    /// The 1/w plane is shifted right by this much for component `c` (`bitlen` of its range).
    pub(crate) qshift: [u32; 3],
}

impl PerspInterp {
    /// All planes zero (a placeholder until the planes are computed).
    const ZERO: PerspInterp = PerspInterp {
        q: Plane::ZERO,
        p: [Plane::ZERO; 3],
        qshift: [0; 3],
    };
}

/// How a triangle's texture coordinates are interpolated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interp {
    /// Screen-linear.
    Affine(AffineInterp),
    /// Perspective-correct (with the mode's segment length).
    Persp(PerspInterp),
}

/// A triangle ready to be drawn: exact coverage data and plane equations. Independent of the
/// clip rectangle, so one setup can be drawn into any number of bands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleSetup {
    pub(crate) cov: Coverage,
    pub(crate) opts: TriangleOptions,
    pub(crate) interp: Interp,
    /// Depth plane: `z << 32`.
    pub(crate) z: Plane,
    /// Depth range of the vertices (interpolated depth is clamped to it).
    pub(crate) zlo: i64,
    pub(crate) zhi: i64,
    /// Texture coordinates of vertex 0 (raw), the offset of the planes.
    pub(crate) base: [i64; 3],
    /// Range of the vertex texture coordinates (raw); interpolated values are clamped to it.
    pub(crate) lo: [i64; 3],
    pub(crate) hi: [i64; 3],
    area2: i128,
}

/// Number of significant bits of `v`.
fn bitlen(v: u64) -> u32 {
    64 - v.leading_zeros()
}

/// A triangle whose coverage and depth plane are set up, its texture interpolation not yet
/// ([`Prepared::complete`] adds it). The rasteriser prepares a triangle, depth-tests its covered
/// pixels and completes the set-up only when a pixel is visible: a triangle hidden in a band,
/// or covering no pixel centre of it, costs no texture planes (12 of the 15 rounding divisions
/// of a perspective triangle). The completed set-up is the one [`TriangleSetup::new`] returns.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Prepared {
    /// The set-up; its `interp` is written by `fill_interp` (valid once `done`).
    setup: TriangleSetup,
    done: bool,
    area: AreaDivisor,
    basis: PlaneBasis,
    tex: [[i64; 3]; 3],
    range: [u64; 3],
    inv_w: [u32; 3],
}

/// The first parts of every triangle set-up, expanded into each constructor (a function would
/// move its results into the set-up; the expansion builds them in place, in the constructor's
/// own order). `cover_and_depth!(reject v, opts)`: guard band, doubled area and culling
/// (returning the rejection from the enclosing constructor), as `(p, area2)`;
/// `cover_and_depth!(planes v, p, area2)`: the area's divisor, the edge functions and the depth
/// plane, as `(area, basis, z, zlo, zhi)`.
macro_rules! cover_and_depth {
    (reject $v:expr, $opts:expr) => {{
        let (v, opts): (&[ScreenVertex; 3], &TriangleOptions) = ($v, $opts);
        let inside = |c: i32| c.unsigned_abs() < GUARD_BAND;
        if !v
            .iter()
            .all(|p| inside(p.x.to_bits()) && inside(p.y.to_bits()))
        {
            return Err(Reject::OutsideGuardBand);
        }
        let p: [[i64; 2]; 3] = v.map(|p| [p.x.to_bits() as i64, p.y.to_bits() as i64]);
        // |coordinate differences| < 2^31: products < 2^62, area2 < 2^63 in magnitude (exact
        // in i64).
        let area2 = i128::from(
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]),
        );
        if area2 == 0 {
            return Err(Reject::Degenerate);
        }
        let culled = match opts.cull {
            CullMode::None => false,
            CullMode::Clockwise => area2 > 0,
            CullMode::CounterClockwise => area2 < 0,
        };
        if culled {
            return Err(Reject::Culled);
        }
        (p, area2)
    }};
    (planes $v:expr, $p:expr, $area2:expr) => {{
        let (v, p, area2): (&[ScreenVertex; 3], &[[i64; 2]; 3], i128) = ($v, $p, $area2);
        let area = AreaDivisor::new(area2);
        let zs = v.map(|p| p.z as i64);
        let basis = PlaneBasis::new(p);
        let z = Plane::new(zs.map(|z| z << 32), &basis, &area);
        let zlo = zs.iter().copied().min().unwrap_or(0);
        let zhi = zs.iter().copied().max().unwrap_or(0);
        (area, basis, z, zlo, zhi)
    }};
}

/// A triangle set up for the textured-triangle path: coverage, depth plane and the edge
/// functions (no texture planes: that path interpolates homogeneously from the edge functions).
#[cfg(feature = "atlas")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoverDepth {
    cov: Coverage,
    basis: PlaneBasis,
    depth: DepthPlane,
    area2: i128,
}

#[cfg(feature = "atlas")]
impl CoverDepth {
    /// Guard band, area, culling, coverage and depth plane of a triangle: exactly those of
    /// [`Prepared::new`] (the same rejections, coverage and depth plane).
    pub(crate) fn new(v: &[ScreenVertex; 3], opts: &TriangleOptions) -> Result<CoverDepth, Reject> {
        let (p, area2) = cover_and_depth!(reject v, opts);
        let (_, basis, z, zlo, zhi) = cover_and_depth!(planes v, &p, area2);
        Ok(CoverDepth {
            cov: Coverage::new(p),
            basis,
            depth: DepthPlane::new(z, zlo, zhi, opts),
            area2,
        })
    }

    /// The coverage of the triangle.
    pub(crate) fn coverage(&self) -> Coverage {
        self.cov
    }

    /// The depth plane and test of the triangle.
    pub(crate) fn depth_plane(&self) -> DepthPlane {
        self.depth
    }

    /// The edge functions: `[E_i(0, 0), dE_i/dx, dE_i/dy]` per vertex `i`, and whether every
    /// entry fits `i32`.
    pub(crate) fn edges(&self) -> (&[[i64; 3]; 3], bool) {
        (&self.basis.e, self.basis.narrow)
    }

    /// The doubled signed area.
    pub(crate) fn area2(&self) -> i128 {
        self.area2
    }
}

impl Prepared {
    /// Guard band, area, culling, coverage, depth plane and texture ranges of a triangle.
    pub(crate) fn new(v: &[ScreenVertex; 3], opts: &TriangleOptions) -> Result<Prepared, Reject> {
        let (p, area2) = cover_and_depth!(reject v, opts);
        let tex = v.map(|p| p.tex.to_bits().map(|c| c as i64));
        let base = tex[0];
        let mut lo = base;
        let mut hi = base;
        let mut range = [0u64; 3];
        for t in &tex {
            for c in 0..3 {
                lo[c] = lo[c].min(t[c]);
                hi[c] = hi[c].max(t[c]);
                range[c] = range[c].max((t[c] - base[c]).unsigned_abs());
            }
        }
        let (area, basis, z, zlo, zhi) = cover_and_depth!(planes v, &p, area2);
        Ok(Prepared {
            setup: TriangleSetup {
                cov: Coverage::new(p),
                opts: *opts,
                // Written by `fill_interp` (in place when perspective).
                interp: Interp::Persp(PerspInterp::ZERO),
                z,
                zlo,
                zhi,
                base,
                lo,
                hi,
                area2,
            },
            done: false,
            area,
            basis,
            tex,
            range,
            inv_w: v.map(|p| p.inv_w.to_bits()),
        })
    }

    /// The coverage of the triangle.
    pub(crate) fn coverage(&self) -> Coverage {
        self.setup.cov
    }

    /// The depth plane and test of the triangle.
    pub(crate) fn depth_plane(&self) -> DepthPlane {
        self.setup.depth_plane()
    }

    /// The complete set-up, computing the texture interpolation on the first call.
    /// Counts it in `ctr.texture_setups`.
    pub(crate) fn complete(&mut self, ctr: &mut Counters) -> &TriangleSetup {
        if self.fill_once() {
            ctr.texture_setups = ctr.texture_setups.wrapping_add(1);
        }
        &self.setup
    }

    /// Computes the texture interpolation unless it is done; whether it computed it.
    #[inline(always)]
    fn fill_once(&mut self) -> bool {
        if self.done {
            return false;
        }
        self.fill_interp();
        self.done = true;
        true
    }

    /// Computes the texture interpolation (affine or perspective planes) into the set-up, plane
    /// by plane in place (the planes are a few hundred bytes: no copies of the whole).
    fn fill_interp(&mut self) {
        let (p, tex, range, area) = (&self.basis, self.tex, self.range, &self.area);
        let base = self.setup.base;
        let qmax = self.inv_w.iter().copied().max().unwrap_or(0);
        if self.setup.opts.perspective == Perspective::Affine || qmax == 0 {
            self.setup.interp = Interp::Affine(AffineInterp::default());
            let Interp::Affine(a) = &mut self.setup.interp else {
                return;
            };
            for c in 0..3 {
                let sh = 62 - bitlen(range[c]);
                let l = tex.map(|t| (t[c] - base[c]) << sh);
                let pl = Plane::new(l, p, area);
                let half = 1i128 << (sh - 1);
                let gx = pl.gx.saturating_add(half) >> sh;
                let gy = pl.gy.saturating_add(half) >> sh;
                a.steep |= i32::try_from(gx).is_err();
                a.ds[c] = sat_i32(gx);
                a.dsdy[c] = sat_i32(gy);
                a.planes[c] = pl;
                a.shift[c] = sh;
            }
        } else {
            // Normalise 1/w so that the largest lies in [2^29, 2^30] (shifting left, or right by
            // at most 2 bits with rounding half up: 1/w is used to 30 significant bits).
            let b = bitlen(qmax as u64);
            let q = self.inv_w.map(|w| {
                let w = w as i64;
                if b <= 30 {
                    w << (30 - b)
                } else {
                    (w + (1 << (b - 31))) >> (b - 30)
                }
            });
            // The placeholder of `Prepared::new` is already perspective: the planes are written
            // in place (no zeroed temporary copied over the set-up).
            if !matches!(self.setup.interp, Interp::Persp(_)) {
                self.setup.interp = Interp::Persp(PerspInterp::ZERO);
            }
            let Interp::Persp(pi) = &mut self.setup.interp else {
                return;
            };
            pi.q = Plane::new(q.map(|q| q << 32), p, area);
            for c in 0..3 {
                let bl = bitlen(range[c]);
                let mut l = [0i64; 3];
                for ((li, t), qi) in l.iter_mut().zip(&tex).zip(&q) {
                    *li = ((t[c] - base[c]) * qi) << (32 - bl);
                }
                pi.p[c] = Plane::new(l, p, area);
                pi.qshift[c] = bl;
            }
        }
    }
}

/// What the depth test of a triangle's pixels needs: the depth plane, its clamp range and the
/// test.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DepthPlane {
    /// `z << 32`.
    pub(crate) z: Plane,
    pub(crate) zlo: i64,
    pub(crate) zhi: i64,
    pub(crate) func: DepthFunc,
    pub(crate) write: bool,
}

impl DepthPlane {
    /// The depth plane `z` with its clamp range and the test and write of `opts`.
    fn new(z: Plane, zlo: i64, zhi: i64, opts: &TriangleOptions) -> DepthPlane {
        DepthPlane {
            z,
            zlo,
            zhi,
            func: opts.depth_func,
            write: opts.depth_write,
        }
    }
}

impl TriangleSetup {
    /// The depth plane and test.
    pub(crate) fn depth_plane(&self) -> DepthPlane {
        DepthPlane::new(self.z, self.zlo, self.zhi, &self.opts)
    }

    /// Whether [`TriangleSetup::new`] (and so every draw call) rejects the triangle, and why,
    /// without setting it up: the guard band, zero area and back-face culling, the same tests in
    /// the same order. A caller that keeps triangles for later (a frame's list of triangles)
    /// leaves out the ones that would draw nothing.
    pub fn check(v: &[ScreenVertex; 3], opts: &TriangleOptions) -> Result<(), Reject> {
        let _ = cover_and_depth!(reject v, opts);
        Ok(())
    }

    /// Sets up a triangle (vertices in either winding).
    pub fn new(v: &[ScreenVertex; 3], opts: &TriangleOptions) -> Result<TriangleSetup, Reject> {
        // Completed in place (no moves of the whole set-up out of the `Result`).
        let mut r = Prepared::new(v, opts);
        let pre = match &mut r {
            Ok(pre) => pre,
            Err(e) => return Err(*e),
        };
        // Completed without counters (a zeroed `Counters` a triangle only to be dropped).
        pre.fill_once();
        Ok(pre.setup)
    }

    /// Twice the signed area in raw units (1/256 pixel^2); positive for clockwise triangles
    /// (on screen, y down).
    pub const fn area2(&self) -> i128 {
        self.area2
    }

    /// The options the triangle was set up with.
    pub const fn options(&self) -> &TriangleOptions {
        &self.opts
    }

    /// The rows `[first, end)` whose pixel centres lie within the triangle's vertical extent
    /// (before clipping; may be negative or beyond the target).
    pub const fn rows(&self) -> (i64, i64) {
        (self.cov.py_first, self.cov.py_end)
    }

    /// Whether texture coordinates are interpolated with perspective division (false for
    /// [`Perspective::Affine`] and for triangles whose `1/w` are all zero).
    pub const fn is_perspective(&self) -> bool {
        matches!(self.interp, Interp::Persp(_))
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use super::*;
    use crate::format::TexPoint;

    fn vtx(x: i32, y: i32) -> ScreenVertex {
        ScreenVertex::from_bits(x, y, 0, 1 << 31, TexPoint::ZERO)
    }

    #[test]
    fn degenerate_triangles_are_rejected() {
        let o = TriangleOptions::new(Perspective::Exact);
        let cases = [
            [vtx(0, 0), vtx(0, 0), vtx(0, 0)],
            [vtx(5, 7), vtx(5, 7), vtx(100, 3)],
            [vtx(0, 0), vtx(16, 16), vtx(160, 160)],
            [vtx(-3, 9), vtx(1000, 9), vtx(77, 9)],
            [vtx(i32::MAX / 4, 0), vtx(0, 0), vtx(-(i32::MAX / 4), 0)],
        ];
        for c in &cases {
            assert_eq!(TriangleSetup::new(c, &o), Err(Reject::Degenerate), "{c:?}");
        }
    }

    #[test]
    fn guard_band_and_extreme_inputs() {
        let o = TriangleOptions::new(Perspective::Every8);
        let g = GUARD_BAND as i32;
        let ok = [vtx(-(g - 1), -(g - 1)), vtx(g - 1, -(g - 1)), vtx(0, g - 1)];
        assert!(TriangleSetup::new(&ok, &o).is_ok());
        for bad in [g, -g, i32::MAX, i32::MIN] {
            let t = [vtx(bad, 0), vtx(0, 16), vtx(16, 0)];
            assert_eq!(TriangleSetup::new(&t, &o), Err(Reject::OutsideGuardBand));
            let t = [vtx(0, 0), vtx(0, bad), vtx(16, 0)];
            assert_eq!(TriangleSetup::new(&t, &o), Err(Reject::OutsideGuardBand));
        }
    }

    #[test]
    fn culling_by_winding() {
        let cw = [vtx(0, 0), vtx(160, 0), vtx(0, 160)];
        let ccw = [cw[0], cw[2], cw[1]];
        let mut o = TriangleOptions::new(Perspective::Affine);
        assert!(TriangleSetup::new(&cw, &o).unwrap().area2() > 0);
        assert!(TriangleSetup::new(&ccw, &o).unwrap().area2() < 0);
        o.cull = CullMode::Clockwise;
        assert_eq!(TriangleSetup::new(&cw, &o), Err(Reject::Culled));
        assert!(TriangleSetup::new(&ccw, &o).is_ok());
        o.cull = CullMode::CounterClockwise;
        assert!(TriangleSetup::new(&cw, &o).is_ok());
        assert_eq!(TriangleSetup::new(&ccw, &o), Err(Reject::Culled));
    }

    #[test]
    fn plane_is_exact_at_vertices_on_pixel_centres() {
        // Vertices on pixel centres: the plane reproduces vertex values up to coefficient
        // rounding (at most 1/2 + (|px| + |py|)/2 units).
        let p = [[8, 8], [16 * 40 + 8, 8], [16 * 3 + 8, 16 * 29 + 8]];
        let area2 = (p[1][0] - p[0][0]) as i128 * (p[2][1] - p[0][1]) as i128
            - (p[2][0] - p[0][0]) as i128 * (p[1][1] - p[0][1]) as i128;
        let l = [123_456_789i64 << 30, -(987_654_321i64 << 31), 5i64 << 40];
        let pl = Plane::new(l, &PlaneBasis::new(&p), &AreaDivisor::new(area2));
        for (i, px) in [(0usize, (0, 0)), (1, (40, 0)), (2, (3, 29))] {
            let err = (pl.at(px.0, px.1) as i128 - l[i] as i128).abs();
            assert!(err <= 1 + (px.0 + px.1) as i128 / 2 + 1, "{i} {err}");
        }
        assert_eq!(pl.at(0, 0), l[0]);
    }

    #[test]
    fn inverse_w_normalisation() {
        let mut v = [vtx(0, 0), vtx(160, 0), vtx(0, 160)];
        let o = TriangleOptions::new(Perspective::Exact);
        v[0].inv_w = InvW::from_bits(0);
        v[1].inv_w = InvW::from_bits(0);
        v[2].inv_w = InvW::from_bits(0);
        // All zero: affine fallback.
        assert!(!TriangleSetup::new(&v, &o).unwrap().is_perspective());
        v[2].inv_w = InvW::from_bits(3);
        let s = TriangleSetup::new(&v, &o).unwrap();
        assert!(s.is_perspective());
        if let Interp::Persp(p) = s.interp {
            // q_2 = 3 << 28 (bitlen 2): the plane at vertex 2's position, (0, 10) px corner.
            assert!(p.q.gy > 0);
            assert_eq!(p.q.gx, 0);
        }
        v[2].inv_w = InvW::from_bits(u32::MAX);
        assert!(TriangleSetup::new(&v, &o).unwrap().is_perspective());
    }

    #[test]
    fn area_divisor_rounds_as_div_round_i128() {
        let ns = [
            0i128,
            1,
            -1,
            2,
            -2,
            3,
            -3,
            i128::MAX,
            i128::MIN,
            i128::MIN + 1,
            1 << 100,
            -(1 << 100) - 7,
            (1 << 125) + 12345,
        ];
        let ds = [
            1i128,
            -1,
            2,
            -2,
            3,
            -3,
            (1 << 62) + 1,
            -(1 << 62) - 3,
            i128::from(i64::MAX),
            -i128::from(i64::MAX),
            1 << 64,
            -(1 << 64),
            (1 << 70) + 5,
        ];
        for &d in &ds {
            let a = AreaDivisor::new(d);
            for &n in &ns {
                assert_eq!(a.div_round(n), div_round_i128(n, d), "{n} / {d}");
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn narrow_plane_numerators_match_wide(
            l in proptest::array::uniform3(-(1i64 << 62)..=(1i64 << 62)),
            xy in proptest::array::uniform6(-(1i64 << 15)..(1i64 << 15)),
            lshift in 0u32..62,
        ) {
            let p = [[xy[0], xy[1]], [xy[2], xy[3]], [xy[4], xy[5]]];
            let area2 = (p[1][0] - p[0][0]) as i128 * (p[2][1] - p[0][1]) as i128
                - (p[2][0] - p[0][0]) as i128 * (p[1][1] - p[0][1]) as i128;
            proptest::prop_assume!(area2 != 0);
            let basis = PlaneBasis::new(&p);
            proptest::prop_assert_eq!(basis.narrow, !cfg!(texcore_lean));
            let wide = PlaneBasis { narrow: false, ..basis };
            let area = AreaDivisor::new(area2);
            for l in [l, l.map(|v| v >> lshift), [i64::MIN >> 1, (1 << 62), -(1 << 62) + 1]] {
                proptest::prop_assert_eq!(
                    Plane::new(l, &basis, &area),
                    Plane::new(l, &wide, &area)
                );
            }
        }

        #[test]
        fn area_divisor_matches_div_round_i128(
            n in proptest::prelude::any::<i128>(),
            d in proptest::prelude::any::<i64>(),
            nshift in 0u32..127,
            dshift in 0u32..63,
        ) {
            for d in [i128::from(d), i128::from(d >> dshift)] {
                if d == 0 {
                    continue;
                }
                let a = AreaDivisor::new(d);
                for n in [n, n >> nshift] {
                    proptest::prop_assert_eq!(a.div_round(n), div_round_i128(n, d));
                }
            }
        }
    }
}
