//! Cameras, projection to [`ScreenVertex`], and clipping in camera space.
//!
//! # Spaces
//!
//! World space is right-handed with **y up** (`Q16.16`, coordinates within `±32767` units).
//! Camera space has the eye at the origin, `x` right, `y` up and `z` **forward** (the distance in
//! front of the eye along the view direction), as `i64` `Q16.16`. The screen has `x` right and `y`
//! down, pixel `(x, y)` covering `[x, x + 1) x [y, y + 1)`, and the image centre at
//! `(width / 2, height / 2)`.
//!
//! # Projection (all integer; the exact arithmetic is documented on [`View::project`])
//!
//! - Perspective with focal factor `f = cot(fovy / 2)` and focal length in pixels
//!   `K = f height / 2`: `x_s = width / 2 + K x / z`, `y_s = height / 2 - K y / z`, in
//!   `I28F4` (1/16 pixel), within 0.57/16 pixel of the exact value (one reciprocal of `z` per
//!   vertex).
//! - Orthographic with half view height `h`: `x_s = width / 2 + (height / 2) x / h`,
//!   `y_s = height / 2 - (height / 2) y / h`.
//! - Depth: perspective `z16 = 65535 (1/near - 1/z) / (1/near - 1/far)` (the NDC depth, affine in
//!   `1/z`, hence **linear in screen space**, as the rasterizer interpolates it); orthographic
//!   `z16 = 65535 (z - near) / (far - near)`. 0 is the near plane, 65535 the far plane.
//! - `1/w`: perspective `round(2^62 / z)` (`z` in `Q16.16`, below `2^31`, so at least 31
//!   significant bits), then scaled **per triangle** by a common power of two so that the largest
//!   of the three lies in `[2^30, 2^31)` (`U1F31` in `[0.5, 1)`): the ratios within a triangle,
//!   which are all the rasterizer uses, keep about 30 significant bits even for a vertex 10^5
//!   times farther than another. Orthographic: `0.5`.
//!
//! # Clipping
//!
//! Triangles are processed in camera space:
//! 1. **Rejected** if all three vertices are outside one plane of the view volume (near, far,
//!    or a screen edge widened by one pixel).
//! 2. **Clipped** (Sutherland-Hodgman, up to 9 vertices, then a fan) against the near plane, the
//!    far plane and the four planes of a **guard band** [`GUARD_PIXELS`] pixels outside the image
//!    centre, if any vertex is outside one of them. The rasterizer clips exactly to the screen,
//!    so only the near plane matters for what is seen; the others keep every projected
//!    coordinate far inside the rasterizer's guard band (`|raw| < 2^30`), however large the
//!    polygon (sea and sky planes to the horizon).
//!
//! A new vertex on an edge is interpolated from the edge's inside end towards its outside end,
//! `p = a + (b - a) d_a / (d_a - d_b)` (exact `i128` products, one rounding), for the position
//! and the texture coordinates alike (they are affine in position, so this is exact up to
//! rounding). The interpolation does not depend on which triangle the edge belongs to or on its
//! direction, so two triangles sharing an edge get identical clip vertices. A vertex made by the
//! near (far) plane gets `z = near` (`far`) exactly.

use super::math::{
    div_round, div_round_128, round_shift, round_shift_128, sat_i32, sat_i64, sin_cos, Angle, Vec3,
    ONE,
};
use crate::format::TexPoint;
use crate::raster::{ScreenCoord, ScreenVertex, GUARD_BAND};

/// Half-width of the clipping guard band, in pixels from the image centre (`2^24`). Projected
/// coordinates stay within `±(2^24 + 32768)` pixels, i.e. raw `I28F4` below `2^28 + 2^19`, far
/// inside the rasterizer's `2^30`.
pub const GUARD_PIXELS: i64 = 1 << 24;

// `View::outcodes` uses `GUARD_PIXELS * 2^16 = 2^40` as a shift.
const _: () = assert!(GUARD_PIXELS == 1 << 24);

/// Most vertices a clipped triangle can have (3 + one per clip plane).
pub const MAX_CLIP_VERTICES: usize = 9;

/// The projection of a [`Camera`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Projection {
    /// Perspective, with the focal factor `cot(fovy / 2)` in `Q16.16` (e.g. from
    /// [`focal_from_fov`]). Must be positive.
    Perspective {
        /// `cot(fovy / 2)`, `Q16.16`.
        focal: i32,
    },
    /// Orthographic, showing `2 half_height` world units vertically.
    Orthographic {
        /// Half the view height in world units, `Q16.16`. Must be positive.
        half_height: i32,
    },
}

/// `cot(fovy / 2)` in `Q16.16` for a vertical field of view `fovy` (by [`sin_cos`]); `fovy` is
/// clamped to `[2^-16, 1/2 - 2^-16]` turn.
pub const fn focal_from_fov(fovy: Angle) -> i32 {
    let lo = 1u32 << 16;
    let hi = (1u32 << 31) - (1 << 16);
    let a = if fovy.0 < lo {
        lo
    } else if fovy.0 > hi {
        hi
    } else {
        fovy.0
    };
    let (s, c) = sin_cos(Angle(a >> 1));
    sat_i32(div_round((c as i64) << 16, s as i64))
}

/// A camera: placement, projection, clipping depths and image size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Camera {
    /// Eye position (world, `Q16.16`).
    pub eye: Vec3,
    /// A point the camera looks at.
    pub target: Vec3,
    /// The world direction that appears upwards (need not be unit or orthogonal).
    pub up: Vec3,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Near clipping distance (`Q16.16`, positive; depth 0).
    pub near: i32,
    /// Far clipping distance (`Q16.16`, beyond `near`; depth 65535).
    pub far: i32,
    /// Image width in pixels.
    pub width: u16,
    /// Image height in pixels.
    pub height: u16,
}

impl Camera {
    /// A perspective camera.
    #[allow(clippy::too_many_arguments)]
    pub const fn perspective(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        focal: i32,
        near: i32,
        far: i32,
        width: u16,
        height: u16,
    ) -> Camera {
        Camera {
            eye,
            target,
            up,
            projection: Projection::Perspective { focal },
            near,
            far,
            width,
            height,
        }
    }

    /// An orthographic camera.
    #[allow(clippy::too_many_arguments)]
    pub const fn orthographic(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        half_height: i32,
        near: i32,
        far: i32,
        width: u16,
        height: u16,
    ) -> Camera {
        Camera {
            eye,
            target,
            up,
            projection: Projection::Orthographic { half_height },
            near,
            far,
            width,
            height,
        }
    }

    /// The derived per-frame data (basis, clip planes), or `None` if the camera is degenerate:
    /// `eye == target`, `up` parallel to the view direction, a non-positive focal factor or
    /// half height, `near <= 0`, `far <= near`, or an empty image.
    pub fn view(&self) -> Option<View> {
        let forward = self.target.sub(self.eye).normalized()?;
        let right = forward.cross(self.up).normalized()?;
        let up = right.cross(forward).normalized()?;
        if self.near <= 0 || self.far <= self.near || self.width == 0 || self.height == 0 {
            return None;
        }
        let (w, h) = (self.width as i64, self.height as i64);
        let (near, far) = (self.near as i64, self.far as i64);
        let proj = match self.projection {
            Projection::Perspective { focal } if focal > 0 => ViewProj::Perspective {
                k: focal as i64 * h / 2,
            },
            Projection::Orthographic { half_height } if half_height > 0 => ViewProj::Orthographic {
                hh: half_height as i64,
            },
            _ => return None,
        };
        let mut v = View {
            rows: [right, up, forward],
            eye: self.eye,
            proj,
            near,
            far,
            width: self.width,
            height: self.height,
            guard: [ClipPlane::ZERO; 6],
            screen: [ClipPlane::ZERO; 6],
            depth_scale: sat_i64(div_round_128(
                (65535 * (far as i128)) << 16,
                (far - near) as i128,
            )),
            margin: [w / 2 + 1, h / 2 + 1],
        };
        // Margins in pixels: the screen edges (plus one pixel) and the guard band.
        v.screen = v.planes(w / 2 + 1, h / 2 + 1);
        v.guard = v.planes(GUARD_PIXELS, GUARD_PIXELS);
        Some(v)
    }
}

/// A plane `d(p) = a . p + c >= 0` (inside) on camera-space `Q16.16` coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ClipPlane {
    a: [i64; 3],
    c: i128,
    /// 0: a side plane, 1: the near plane, 2: the far plane.
    kind: u8,
}

impl ClipPlane {
    const ZERO: ClipPlane = ClipPlane {
        a: [0; 3],
        c: 0,
        kind: 0,
    };

    #[inline]
    fn eval(&self, p: &[i64; 3]) -> i128 {
        // |a| < 2^47 (focal length in pixels, 2^40 guard margins, image height), |p| < 2^63:
        // the products are below 2^110 and nothing overflows; wrapping only avoids checks.
        let mut d = self.c;
        for (a, x) in self.a.iter().zip(p.iter()) {
            d = d.wrapping_add((*a as i128).wrapping_mul(*x as i128));
        }
        d
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ViewProj {
    /// Focal length in pixels, `Q16.16`.
    Perspective { k: i64 },
    /// Half view height, `Q16.16`.
    Orthographic { hh: i64 },
}

/// A camera-space vertex: position (`i64` `Q16.16`, `z` forward) and solid texture
/// coordinates (raw `I16F16`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct CamVertex {
    /// Camera-space position.
    pub p: [i64; 3],
    /// Texture coordinates.
    pub tex: [i32; 3],
}

/// A camera's per-frame data: orthonormal basis, projection constants and clip planes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct View {
    rows: [Vec3; 3],
    eye: Vec3,
    proj: ViewProj,
    near: i64,
    far: i64,
    width: u16,
    height: u16,
    guard: [ClipPlane; 6],
    screen: [ClipPlane; 6],
    /// Perspective depth factor `round(65535 f 2^16 / (f - n))`.
    depth_scale: i64,
    /// Screen margins in pixels (`width / 2 + 1`, `height / 2 + 1`: 1 to 32 768).
    margin: [i64; 2],
}

/// What happened to one triangle in [`View::clip_project`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ClipOutcome {
    /// Emitted unchanged (as one triangle).
    Inside,
    /// Cut by the near, far or guard planes into this many triangles (0 if nothing was left).
    Clipped(u8),
    /// Entirely outside the view volume.
    Rejected,
}

impl View {
    /// The camera basis `[right, up, forward]` (unit vectors, `Q16.16`).
    pub const fn basis(&self) -> [Vec3; 3] {
        self.rows
    }

    /// Image size.
    pub const fn size(&self) -> (u16, u16) {
        (self.width, self.height)
    }

    fn planes(&self, mx: i64, my: i64) -> [ClipPlane; 6] {
        let near = ClipPlane {
            a: [0, 0, 1],
            c: -(self.near as i128),
            kind: 1,
        };
        let far = ClipPlane {
            a: [0, 0, -1],
            c: self.far as i128,
            kind: 2,
        };
        let h = self.height as i64;
        match self.proj {
            // x K / (z 2^16) <= m  <=>  m 2^16 z - K x >= 0.
            ViewProj::Perspective { k } => {
                let (zx, zy) = (mx << 16, my << 16);
                let side = |a: [i64; 3]| ClipPlane { a, c: 0, kind: 0 };
                [
                    near,
                    far,
                    side([-k, 0, zx]),
                    side([k, 0, zx]),
                    side([0, -k, zy]),
                    side([0, k, zy]),
                ]
            }
            // x h / (2 hh) <= m  <=>  2 m hh - h x >= 0.
            ViewProj::Orthographic { hh } => {
                let side = |a: [i64; 3], m: i64| ClipPlane {
                    a,
                    c: 2 * m as i128 * hh as i128,
                    kind: 0,
                };
                [
                    near,
                    far,
                    side([-h, 0, 0], mx),
                    side([h, 0, 0], mx),
                    side([0, -h, 0], my),
                    side([0, h, 0], my),
                ]
            }
        }
    }

    /// World to camera space: `(right . d, up . d, forward . d)` with `d = p - eye`, each rounded
    /// half up from `Q32.32`.
    pub fn to_camera(&self, p: Vec3) -> [i64; 3] {
        let d = [
            p.x as i64 - self.eye.x as i64,
            p.y as i64 - self.eye.y as i64,
            p.z as i64 - self.eye.z as i64,
        ];
        // Unit rows (|r| <= 2^16) times |d| <= 2^32: every sum fits i64. When every difference
        // fits i32 (any point within about 32 000 units of the eye), the same products are
        // 32 x 32 -> 64-bit ones. (The differences taken as checked `i32` subtractions: tested
        // on the `i64` differences, the compiler sees both branches compute the same sums and
        // keeps only the 64-bit one.)
        if let (Some(dx), Some(dy), Some(dz)) = (
            p.x.checked_sub(self.eye.x),
            p.y.checked_sub(self.eye.y),
            p.z.checked_sub(self.eye.z),
        ) {
            let d = [dx, dy, dz];
            return self.rows.map(|r| {
                let acc = i64::from(r.x) * i64::from(d[0])
                    + i64::from(r.y) * i64::from(d[1])
                    + i64::from(r.z) * i64::from(d[2]);
                round_shift(acc, 16)
            });
        }
        self.rows.map(|r| {
            let acc = r.x as i64 * d[0] + r.y as i64 * d[1] + r.z as i64 * d[2];
            round_shift(acc, 16)
        })
    }

    /// Projects a camera-space vertex (`z` is clamped to `[near, far]`); `inv_w` is returned
    /// unnormalised as `round(2^62 / z)` (see the module documentation), to be scaled per
    /// triangle by [`normalise_inv_w`].
    ///
    /// Perspective: one division per vertex, the reciprocal `r = round(2^62 / z)` (`z` in
    /// `[near, far]`, so `2^31 <= r <= 2^62`), then products only:
    /// `x_s = width/2 + round(x K r / 2^74)` (1/16 pixel; within `0.57` LSB of `x K / (z 2^12)`
    /// for any vertex inside the guard band), the depth
    /// `round(round((z - n) r / 2^31) D / 2^47)` with `D = round(65535 f 2^16 / (f - n))`, and
    /// `1/w = r`. (An exact division replaces the product for `|x K| >= 2^62`.)
    pub fn project(&self, v: &CamVertex) -> (ScreenVertex, u64) {
        match self.project_perspective_small(v) {
            Some(p) => p,
            None => self.project_wide(v),
        }
    }

    /// [`View::project`] in `i128` words, for any vertex.
    fn project_wide(&self, v: &CamVertex) -> (ScreenVertex, u64) {
        let [x, y, z] = v.p;
        // max then min, not clamp: no panic path even if near > far. 1 <= z < 2^31.
        let z = z.max(self.near).min(self.far);
        let n = self.near;
        let (w8, h8) = (self.width as i128 * 8, self.height as i128 * 8);
        let (sx, sy, depth, q) = match self.proj {
            ViewProj::Perspective { k } => {
                let r = inv_z(z);
                let off = |a: i128| -> i128 {
                    if a.unsigned_abs() < 1 << 62 {
                        round_shift_128(a * r as i128, 74)
                    } else {
                        div_round_128(a, (z as i128) << 12)
                    }
                };
                let sx = w8 + off(mul_wide(x, k));
                let sy = h8 - off(mul_wide(y, k));
                // (z - n) / z in Q31, then times 65535 f / (f - n).
                let t = round_shift_128((z - n) as i128 * r as i128, 31);
                let depth = round_shift_128(t * self.depth_scale as i128, 47);
                (sx, sy, depth, r)
            }
            ViewProj::Orthographic { hh } => {
                let s = self.height as i128 * 8;
                let sx = w8 + div_round_128(x as i128 * s, hh as i128);
                let sy = h8 - div_round_128(y as i128 * s, hh as i128);
                let depth = div_round((z - n) * 65535, self.far - n) as i128;
                (sx, sy, depth, 1u64 << 62)
            }
        };
        let lim = GUARD_BAND as i128 - 1;
        let sv = ScreenVertex {
            x: ScreenCoord::from_bits(sx.clamp(-lim, lim) as i32),
            y: ScreenCoord::from_bits(sy.clamp(-lim, lim) as i32),
            z: depth.clamp(0, 65535) as u16,
            inv_w: crate::raster::InvW::ZERO,
            tex: TexPoint::from_bits(v.tex[0], v.tex[1], v.tex[2]),
        };
        (sv, q)
    }

    /// [`View::project`] of a perspective view when `x`, `y` and the focal constant `K` fit
    /// `i32` (every vertex of a frame in practice): the same values from `i64` operands, each
    /// product a signed 64 x 64 -> 128-bit one rounded half up by one addition and shift
    /// ([`mul_round_shift`]); `None` otherwise.
    ///
    /// Bounds: `|x K| <= 2^62`, and `project`'s product branch takes `|x K| < 2^62` (the
    /// check leaves the rest to it); `r <= 2^62`, so `|x K r| < 2^124` and its
    /// rounded shift by 74 is below `2^50`; `(z - n) r < 2^93`, `t <= 2^31` and the depth
    /// factor below `2^63`, so `t D < 2^94`. Every sum is the one `project` forms.
    #[inline]
    fn project_perspective_small(&self, v: &CamVertex) -> Option<(ScreenVertex, u64)> {
        let ViewProj::Perspective { k } = self.proj else {
            return None;
        };
        let [x, y, z] = v.p;
        let fits = |a: i64| a == a as i32 as i64;
        if !(fits(x) && fits(y) && fits(k)) {
            return None;
        }
        let (kx, ky) = (x * k, y * k);
        if kx.unsigned_abs() >= 1 << 62 || ky.unsigned_abs() >= 1 << 62 {
            return None;
        }
        let z = z.max(self.near).min(self.far);
        let r = inv_z(z);
        // r <= 2^62: it fits i64.
        let ri = r as i64;
        let (w8, h8) = (i64::from(self.width) * 8, i64::from(self.height) * 8);
        let sx = w8 + mul_round_shift(kx, ri, 74);
        let sy = h8 - mul_round_shift(ky, ri, 74);
        // 0 <= z - n < 2^31 and 0 <= t <= 2^31 + 1 (r <= 2^62 / z + 1/2), the depth factor
        // positive: unsigned 32 x 64-bit products, the same values as the signed ones.
        let t = mul_u32_round_shift((z - self.near) as u32, r, 31) as i64;
        let depth = match u64::try_from(self.depth_scale) {
            Ok(d) => mul_u32_round_shift(t as u32, d, 47) as i64,
            Err(_) => mul_round_shift(t, self.depth_scale, 47),
        };
        let lim = i64::from(GUARD_BAND) - 1;
        let sv = ScreenVertex {
            x: ScreenCoord::from_bits(sx.max(-lim).min(lim) as i32),
            y: ScreenCoord::from_bits(sy.max(-lim).min(lim) as i32),
            z: depth.clamp(0, 65535) as u16,
            inv_w: crate::raster::InvW::ZERO,
            tex: TexPoint::from_bits(v.tex[0], v.tex[1], v.tex[2]),
        };
        Some((sv, r))
    }

    /// Rejects, clips and projects one camera-space triangle, calling `f` with each resulting
    /// screen triangle (same winding as the input; a clipped polygon is fanned from its first
    /// vertex).
    pub fn clip_project<F: FnMut(&[ScreenVertex; 3])>(
        &self,
        tri: &[CamVertex; 3],
        f: &mut F,
    ) -> ClipOutcome {
        let oc = [
            self.outcodes(&tri[0].p),
            self.outcodes(&tri[1].p),
            self.outcodes(&tri[2].p),
        ];
        // 1. Trivial rejection against the view volume.
        if oc[0].0 & oc[1].0 & oc[2].0 != 0 {
            return ClipOutcome::Rejected;
        }
        // 2. Inside the near/far/guard volume: no clipping.
        if (oc[0].1 | oc[1].1 | oc[2].1) == 0 {
            emit(self, tri, f);
            return ClipOutcome::Inside;
        }
        let mut poly = ClipPolygon::from_triangle(tri);
        for pl in &self.guard {
            poly = poly.clip(pl, self.near, self.far);
            if poly.len < 3 {
                return ClipOutcome::Clipped(0);
            }
        }
        let mut n = 0u8;
        for i in 1..poly.len.saturating_sub(1) {
            if let (Some(&a), Some(&b), Some(&c)) =
                (poly.v.first(), poly.v.get(i), poly.v.get(i + 1))
            {
                emit(self, &[a, b, c], f);
                n += 1;
            }
        }
        ClipOutcome::Clipped(n)
    }

    /// Which planes a camera-space point is outside of: bit `i` of the first value for plane `i`
    /// of the view volume (near, far, right, left, top, bottom screen edge plus one pixel), of the
    /// second for the near/far/guard-band volume. Exactly `ClipPlane::eval(p) < 0` for each
    /// plane, computed with one or two 64-bit products per plane pair instead of `i128` dot
    /// products.
    pub fn outcodes(&self, p: &[i64; 3]) -> (u8, u8) {
        let [x, y, z] = *p;
        let mut s = 0u8;
        if z < self.near {
            s |= 1;
        }
        if z > self.far {
            s |= 2;
        }
        let mut g = s;
        // Bits for "a > m" and "-a > m" on x (4, 8) and y (16, 32): `side_bits`.
        let [mx, my] = self.margin;
        match self.proj {
            ViewProj::Perspective { k } => {
                // The same tests in i64 when every operand is small: x, y, k in i32 make
                // |k x|, |k y| <= 2^62; 0 <= z < 2^31 and the margins (at most 32 768) make
                // m 2^16 z < 2^63; and the guard's 2^40 z reaches |k x| once z >= 2^22, so
                // its bits are clear there (below, 2^40 z < 2^62). Exact: the comparisons of
                // the same values.
                let small = |a: i64| a == a as i32 as i64;
                if small(x) && small(y) && small(k) && (z as u64) >> 31 == 0 {
                    let (kx, ky) = (x * k, y * k);
                    s |= side_bits(kx, (z * mx) << 16, 4) | side_bits(ky, (z * my) << 16, 16);
                    if z < 1 << 22 {
                        let gz = z << 40;
                        g |= side_bits(kx, gz, 4) | side_bits(ky, gz, 16);
                    }
                    return (s, g);
                }
                // Plane d = -k x + (m 2^16) z: outside iff k x > m 2^16 z.
                let (kx, ky) = (mul_wide(x, k), mul_wide(y, k));
                let (sx, sy) = (mul_wide(z, mx) << 16, mul_wide(z, my) << 16);
                let gz = (z as i128) << 40; // GUARD_PIXELS 2^16 z
                s |= side_bits(kx, sx, 4) | side_bits(ky, sy, 16);
                g |= side_bits(kx, gz, 4) | side_bits(ky, gz, 16);
            }
            ViewProj::Orthographic { hh } => {
                // Plane d = -h x + 2 m hh: outside iff h x > 2 m hh.
                let h = self.height as i64;
                let (hx, hy) = (mul_wide(x, h), mul_wide(y, h));
                let hh2 = 2 * hh as i128;
                s |= side_bits(hx, hh2 * mx as i128, 4) | side_bits(hy, hh2 * my as i128, 16);
                let gc = hh2 * GUARD_PIXELS as i128;
                g |= side_bits(hx, gc, 4) | side_bits(hy, gc, 16);
            }
        }
        (s, g)
    }

    /// Clips a camera-space triangle against the near, far and guard planes only (no projection),
    /// returning the polygon (for tests and tools).
    pub fn clip_polygon(&self, tri: &[CamVertex; 3]) -> ClipPolygon {
        let mut poly = ClipPolygon::from_triangle(tri);
        for pl in &self.guard {
            poly = poly.clip(pl, self.near, self.far);
        }
        poly
    }
}

/// `bit` if `a > m`, `bit << 1` if `-a > m` (both, neither): the two planes of a pair. `-a`
/// does not overflow for the outcodes' products (below `2^62` in `i64`, `2^126` in `i128`).
#[inline(always)]
fn side_bits<T: Copy + PartialOrd + core::ops::Neg<Output = T>>(a: T, m: T, bit: u8) -> u8 {
    (if a > m { bit } else { 0 }) | (if -a > m { bit << 1 } else { 0 })
}

/// `round(2^62 / z)` of a depth clamped to `[near, far]` (`1 <= z < 2^31`: the 32-bit divisor
/// takes the hardware-divide path), the unnormalised `1/w` of [`View::project`].
#[inline]
fn inv_z(z: i64) -> u64 {
    let zu = u32::try_from(z.max(1)).unwrap_or(u32::MAX);
    crate::wide::div_rem_u64_by_u32((1u64 << 62) + u64::from(zu >> 1), zu).map_or(0, |(q, _)| q)
}

/// `round(a b / 2^k)` rounded half up (`1 <= k <= 126`), from a signed 64 x 64 -> 128-bit
/// product; the caller bounds the result to `i64`.
#[inline(always)]
fn mul_round_shift(a: i64, b: i64, k: u32) -> i64 {
    ((a as i128 * b as i128 + (1i128 << (k - 1))) >> k) as i64
}

/// `round(a b / 2^k)` rounded half up (`1 <= k <= 64`) from an unsigned 32 x 64-bit product
/// (below `2^96`): no sign handling and half the partial products of [`mul_round_shift`].
#[inline(always)]
fn mul_u32_round_shift(a: u32, b: u64, k: u32) -> u64 {
    ((u128::from(a) * u128::from(b) + (1u128 << (k - 1))) >> k) as u64
}

/// `a b` exactly, with a 64-bit multiplication when both are below `2^31` in magnitude.
#[inline]
fn mul_wide(a: i64, b: i64) -> i128 {
    const L: i64 = 1 << 31;
    if a > -L && a < L && b > -L && b < L {
        (a * b) as i128
    } else {
        a as i128 * b as i128
    }
}

/// Projects three camera-space vertices, normalises their `1/w` together, and emits them.
fn emit<F: FnMut(&[ScreenVertex; 3])>(view: &View, tri: &[CamVertex; 3], f: &mut F) {
    f(&assemble([
        view.project(&tri[0]),
        view.project(&tri[1]),
        view.project(&tri[2]),
    ]));
}

/// A screen triangle from three projected vertices ([`View::project`]): their `1/w` normalised
/// together ([`normalise_inv_w`]).
pub fn assemble(p: [(ScreenVertex, u64); 3]) -> [ScreenVertex; 3] {
    let q = normalise_inv_w([p[0].1, p[1].1, p[2].1]);
    let mut out = [p[0].0, p[1].0, p[2].0];
    for (v, q) in out.iter_mut().zip(q) {
        v.inv_w = crate::raster::InvW::from_bits(q);
    }
    out
}

/// Scales three `1/w` values (62 fraction bits) by a common power of two so that the largest
/// lies in `[2^30, 2^31]` (rounding half up); values already below that are kept.
pub fn normalise_inv_w(q: [u64; 3]) -> [u32; 3] {
    let m = q[0].max(q[1]).max(q[2]);
    let bits = 64 - m.leading_zeros();
    if bits <= 31 {
        // No shift: every value is below 2^31.
        return q.map(|v| v as u32);
    }
    // The shift s = bits - 31 >= 1: (v >> s) + bit s - 1 of v is ceil(t / 2) for t = v >> (s -
    // 1), and t <= m >> (bits - 32) < 2^32 fits a word. t from the value's two words, with
    // the shift `s - 1` (0 to 32) the same for all three (the 64-bit shift by a variable
    // amount is a long sequence on 32-bit targets).
    let s1 = bits - 32;
    q.map(|v| {
        let (hi, lo) = ((v >> 32) as u32, v as u32);
        let t = if s1 >= 32 {
            hi
        } else {
            // `hi << (32 - s1)` as two shifts (no shift by 32 when s1 = 0, where hi = 0).
            (lo >> s1) | ((hi << 1) << (31 - s1))
        };
        (t >> 1) + (t & 1)
    })
}

/// A convex polygon being clipped (at most [`MAX_CLIP_VERTICES`] vertices).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClipPolygon {
    /// Vertices (the first `len` are valid).
    pub v: [CamVertex; MAX_CLIP_VERTICES],
    /// Number of vertices.
    pub len: usize,
}

impl ClipPolygon {
    fn from_triangle(t: &[CamVertex; 3]) -> ClipPolygon {
        let mut v = [CamVertex::default(); MAX_CLIP_VERTICES];
        v[0] = t[0];
        v[1] = t[1];
        v[2] = t[2];
        ClipPolygon { v, len: 3 }
    }

    /// The valid vertices.
    pub fn vertices(&self) -> &[CamVertex] {
        self.v.get(..self.len).unwrap_or(&[])
    }

    fn push(&mut self, p: CamVertex) {
        if let Some(slot) = self.v.get_mut(self.len) {
            *slot = p;
            self.len += 1;
        }
    }

    fn clip(&self, pl: &ClipPlane, near: i64, far: i64) -> ClipPolygon {
        let vs = self.vertices();
        let mut out = ClipPolygon {
            v: [CamVertex::default(); MAX_CLIP_VERTICES],
            len: 0,
        };
        if vs.iter().all(|v| pl.eval(&v.p) >= 0) {
            return *self;
        }
        for (i, a) in vs.iter().enumerate() {
            let b = vs.get(i + 1).or(vs.first()).unwrap_or(a);
            let (da, db) = (pl.eval(&a.p), pl.eval(&b.p));
            if da >= 0 {
                out.push(*a);
            }
            if (da >= 0) != (db >= 0) {
                let mut p = if da >= 0 {
                    intersect(a, b, da, db)
                } else {
                    intersect(b, a, db, da)
                };
                match pl.kind {
                    1 => p.p[2] = near,
                    2 => p.p[2] = far,
                    _ => {}
                }
                out.push(p);
            }
        }
        out
    }
}

/// The point where edge `a` (inside, `da >= 0`) to `b` (outside, `db < 0`) crosses the plane:
/// `a + (b - a) da / (da - db)`, per component rounded half up.
fn intersect(a: &CamVertex, b: &CamVertex, da: i128, db: i128) -> CamVertex {
    let mut num = da;
    let mut den = da.saturating_sub(db); // > 0
                                         // Keep num, den below 2^62 (same shift: the ratio is kept to 62 bits) so that
                                         // (b - a) * num fits i128.
    let bits = 128 - den.leading_zeros();
    if bits > 62 {
        let s = bits - 62;
        num >>= s;
        den >>= s;
        if den == 0 {
            den = 1;
        }
    }
    let lerp = |x: i64, y: i64| -> i64 {
        let d = y as i128 - x as i128;
        sat_i64(x as i128 + div_round_128(d.saturating_mul(num), den))
    };
    CamVertex {
        p: [
            lerp(a.p[0], b.p[0]),
            lerp(a.p[1], b.p[1]),
            lerp(a.p[2], b.p[2]),
        ],
        tex: [
            sat_i32(lerp(a.tex[0] as i64, b.tex[0] as i64)),
            sat_i32(lerp(a.tex[1] as i64, b.tex[1] as i64)),
            sat_i32(lerp(a.tex[2] as i64, b.tex[2] as i64)),
        ],
    }
}

/// `1.0` in `Q16.16` (re-exported for camera parameters).
pub const CAMERA_ONE: i32 = ONE;

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::scene::math::{milli, units};
    use std::vec::Vec;

    fn persp(eye: Vec3, target: Vec3) -> Camera {
        Camera::perspective(
            eye,
            target,
            Vec3::Y,
            focal_from_fov(Angle::from_degrees(60)),
            milli(100),
            units(1000),
            320,
            240,
        )
    }

    fn cv(p: [f64; 3], tex: [i32; 3]) -> CamVertex {
        CamVertex {
            p: p.map(|c| (c * 65536.0).round() as i64),
            tex,
        }
    }

    #[test]
    fn focal_factor() {
        let f = focal_from_fov(Angle::from_degrees(60)) as f64 / 65536.0;
        assert!((f - 1.0 / 30f64.to_radians().tan()).abs() < 2e-5);
        assert_eq!(focal_from_fov(Angle::from_degrees(90)), ONE);
        assert!(focal_from_fov(Angle(0)) > 0);
        assert!(focal_from_fov(Angle(u32::MAX)) > 0);
    }

    #[test]
    fn degenerate_cameras() {
        let c = persp(Vec3::ZERO, Vec3::ZERO);
        assert!(c.view().is_none());
        let mut c = persp(Vec3::ZERO, Vec3::units(0, 5, 0));
        assert!(c.view().is_none(), "up parallel to the view direction");
        c.target = Vec3::units(0, 0, -5);
        assert!(c.view().is_some());
        c.near = 0;
        assert!(c.view().is_none());
    }

    /// `to_camera` is its `i64` definition (`round_shift(r . (p - eye), 16)` per row) for points
    /// near the eye (the 32-bit products) and far from it, past `i32` differences (the 64-bit
    /// ones), at random and at the ends of the coordinates' range.
    #[test]
    fn to_camera_is_the_wide_dot_products() {
        let mut rng = crate::test_rng::XorShift64::new(0xCA3E_2A00_0D07_5EED);
        let ends = [i32::MIN, i32::MAX, 0, -1, 1, 1 << 30, -(1 << 30)];
        let mut far = 0u32;
        for n in 0..4000u32 {
            let mut c = |k: u32| match (n + k) % 3 {
                0 => ends[rng.below(ends.len() as u64) as usize],
                1 => rng.below(1 << 32) as u32 as i32,
                _ => rng.below(1 << 24) as i32 - (1 << 23),
            };
            let eye = Vec3::new(c(0), c(1), c(2));
            let target = Vec3::new(c(3), c(4), c(5));
            let Some(view) = persp(eye, target).view() else {
                continue;
            };
            for _ in 0..8 {
                let p = Vec3::new(c(6), c(7), c(8));
                let d = [
                    i64::from(p.x) - i64::from(eye.x),
                    i64::from(p.y) - i64::from(eye.y),
                    i64::from(p.z) - i64::from(eye.z),
                ];
                far += u32::from(d.iter().any(|&v| i32::try_from(v).is_err()));
                let want = view.rows.map(|r| {
                    let acc = i64::from(r.x) * d[0] + i64::from(r.y) * d[1] + i64::from(r.z) * d[2];
                    round_shift(acc, 16)
                });
                assert_eq!(view.to_camera(p), want, "{p:?} from {eye:?}");
            }
        }
        assert!(far > 1000, "{far}");
    }

    /// World points project where an f64 pinhole model puts them.
    #[test]
    fn projection_of_known_points() {
        let cam = persp(Vec3::milli(300, 1200, 5000), Vec3::milli(-200, 400, 0));
        let view = cam.view().unwrap();
        // f64 reference.
        let e = [0.3, 1.2, 5.0];
        let t = [-0.2, 0.4, 0.0];
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let norm = |a: [f64; 3]| {
            let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            a.map(|c| c / l)
        };
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let fw = norm(sub(t, e));
        let rt = norm(cross(fw, [0., 1., 0.]));
        let up = cross(rt, fw);
        let k = 1.0 / 30f64.to_radians().tan() * 120.0;
        let (n, fa) = (0.1, 1000.0);
        let project = |p: [f64; 3]| {
            let d = sub(p, e);
            let (x, y, z) = (dot(d, rt), dot(d, up), dot(d, fw));
            (
                160.0 + k * x / z,
                120.0 - k * y / z,
                65535.0 * (1. / n - 1. / z) / (1. / n - 1. / fa),
            )
        };
        // The target is at the centre of the screen, exactly.
        let (sv, _) = view.project(&CamVertex {
            p: view.to_camera(cam.target),
            tex: [0; 3],
        });
        assert_eq!((sv.x.to_bits(), sv.y.to_bits()), (160 * 16, 120 * 16));
        let pts = [
            [1.0, 1.0, 0.0],
            [-2.5, -0.3, 1.7],
            [0.0, 3.0, -8.0],
            [4.0, 0.5, 2.0],
        ];
        for p in pts {
            let (sv, _) = view.project(&CamVertex {
                p: view.to_camera(Vec3::from_array(p.map(|c| (c * 65536.0) as i32))),
                tex: [0; 3],
            });
            let (x, y, z) = project(p);
            assert!(
                (sv.x.to_num::<f64>() - x).abs() < 0.07,
                "{p:?}: x {} vs {x}",
                sv.x
            );
            assert!(
                (sv.y.to_num::<f64>() - y).abs() < 0.07,
                "{p:?}: y {} vs {y}",
                sv.y
            );
            assert!((sv.z as f64 - z).abs() < 1.5, "{p:?}: z {} vs {z}", sv.z);
        }
    }

    /// Points on the view volume's edges land on the image corners.
    #[test]
    fn corners() {
        let cam = persp(Vec3::ZERO, Vec3::units(0, 0, -1));
        let view = cam.view().unwrap();
        let k = 1.0 / 30f64.to_radians().tan() * 120.0;
        // At depth 10: x = +-160 * 10 / k, y = +-120 * 10 / k.
        for (sx, sy) in [(-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
            let p = [sx * 1600.0 / k, sy * 1200.0 / k, -10.0];
            let (v, _) = view.project(&CamVertex {
                p: view.to_camera(Vec3::from_array(p.map(|c| (c * 65536.0).round() as i32))),
                tex: [0; 3],
            });
            let ex = (160.0 + 160.0 * sx, 120.0 - 120.0 * sy);
            assert!((v.x.to_num::<f64>() - ex.0).abs() < 0.07, "{:?}", v);
            assert!((v.y.to_num::<f64>() - ex.1).abs() < 0.07, "{:?}", v);
        }
        // Orthographic: x = 160 + 120 x / h.
        let o = Camera::orthographic(
            Vec3::units(0, 0, 5),
            Vec3::ZERO,
            Vec3::Y,
            units(2),
            units(1),
            units(10),
            320,
            240,
        );
        let view = o.view().unwrap();
        let (v, q) = view.project(&CamVertex {
            p: view.to_camera(Vec3::milli(-2000 * 160 / 120, 2000, 0)),
            tex: [0; 3],
        });
        assert!(v.x.to_bits().abs() <= 1 && v.y.to_bits() == 0, "{v:?}");
        assert_eq!(v.z, div_round(65535 * 4, 9) as u16);
        assert_eq!(q, 1 << 62);
    }

    #[test]
    fn near_clipping_one_vertex_behind() {
        let view = persp(Vec3::ZERO, Vec3::units(0, 0, -1)).view().unwrap();
        let n = 0.1;
        // Camera space: z forward. One vertex behind the eye: a quad (two triangles).
        let tri = [
            cv([0.0, 0.0, -1.0], [0, 0, 0]),
            cv([1.0, 0.0, 3.0], [65536, 0, 0]),
            cv([-1.0, 1.0, 3.0], [0, 65536, 0]),
        ];
        let poly = view.clip_polygon(&tri);
        assert_eq!(poly.len, 4);
        let on_plane: Vec<_> = poly
            .vertices()
            .iter()
            .filter(|v| v.p[2] == milli(100) as i64)
            .collect();
        assert_eq!(on_plane.len(), 2, "{poly:?}");
        for v in on_plane {
            // Texture coordinates are the affine function of position: s = (x + 1) / ... solve
            // the plane through the three vertices in f64 and compare.
            let p = v.p.map(|c| c as f64 / 65536.0);
            // Edge from (0,0,-1) to (1,0,3) at z = n: t = (n + 1) / 4.
            // Edge from (0,0,-1) to (-1,1,3): same t.
            let t = (n + 1.0) / 4.0;
            let (s_exp, t_exp) = if p[0] > 0.0 { (t, 0.0) } else { (0.0, t) };
            assert!((v.tex[0] as f64 / 65536.0 - s_exp).abs() < 2e-5, "{v:?}");
            assert!((v.tex[1] as f64 / 65536.0 - t_exp).abs() < 2e-5, "{v:?}");
            let x_exp = if p[0] > 0.0 { t } else { -t };
            assert!((p[0] - x_exp).abs() < 2e-5);
        }
        let mut tris = Vec::new();
        let out = view.clip_project(&tri, &mut |t: &[ScreenVertex; 3]| tris.push(*t));
        assert_eq!(out, ClipOutcome::Clipped(2));
        assert_eq!(tris.len(), 2);
        // Vertices on the near plane have depth 0 and the largest 1/w.
        for t in &tris {
            for v in t {
                assert!(v.inv_w.to_bits() <= 1 << 31);
            }
        }
    }

    #[test]
    fn near_clipping_two_vertices_behind() {
        let view = persp(Vec3::ZERO, Vec3::units(0, 0, -1)).view().unwrap();
        let tri = [
            cv([0.0, 0.0, 2.0], [0, 0, 65536]),
            cv([1.0, 0.0, -2.0], [65536, 0, 0]),
            cv([-1.0, 1.0, -2.0], [0, 65536, 0]),
        ];
        let poly = view.clip_polygon(&tri);
        assert_eq!(poly.len, 3);
        let t = (2.0 - 0.1) / 4.0;
        for v in &poly.vertices()[1..] {
            assert_eq!(v.p[2], milli(100) as i64);
            let tex = v.tex.map(|c| c as f64 / 65536.0);
            assert!((tex[2] - (1.0 - t)).abs() < 2e-5, "{v:?}");
            assert!((tex[0] + tex[1] - t).abs() < 3e-5);
        }
        let mut n = 0;
        assert_eq!(
            view.clip_project(&tri, &mut |_: &[ScreenVertex; 3]| n += 1),
            ClipOutcome::Clipped(1)
        );
        assert_eq!(n, 1);
        // Entirely behind: rejected.
        let behind = [
            cv([0.0, 0.0, -2.0], [0; 3]),
            cv([1.0, 0.0, -2.0], [0; 3]),
            cv([0.0, 1.0, -0.05], [0; 3]),
        ];
        assert_eq!(
            view.clip_project(&behind, &mut |_: &[ScreenVertex; 3]| panic!()),
            ClipOutcome::Rejected
        );
        // Off to the side: rejected without clipping.
        let side = [
            cv([50.0, 0.0, 2.0], [0; 3]),
            cv([60.0, 0.0, 2.0], [0; 3]),
            cv([50.0, 1.0, 3.0], [0; 3]),
        ];
        assert_eq!(
            view.clip_project(&side, &mut |_: &[ScreenVertex; 3]| panic!()),
            ClipOutcome::Rejected
        );
    }

    /// Shared edges clip to identical vertices whichever triangle they belong to.
    #[test]
    fn clip_vertices_shared() {
        let view = persp(Vec3::ZERO, Vec3::units(0, 0, -1)).view().unwrap();
        let a = cv([0.3, -0.7, -1.3], [1, 2, 3]);
        let b = cv([-0.9, 0.2, 5.1], [99999, -5, 7]);
        let t1 = [a, b, cv([2.0, 2.0, 4.0], [0; 3])];
        let t2 = [b, a, cv([-2.0, -2.0, 4.0], [0; 3])];
        let p1 = view.clip_polygon(&t1);
        let p2 = view.clip_polygon(&t2);
        let on = |p: &ClipPolygon| -> Vec<CamVertex> {
            p.vertices()
                .iter()
                .filter(|v| v.p[2] == milli(100) as i64)
                .copied()
                .collect()
        };
        let shared: Vec<_> = on(&p1)
            .into_iter()
            .filter(|v| on(&p2).contains(v))
            .collect();
        assert_eq!(shared.len(), 1, "{p1:?} {p2:?}");
    }

    /// Random `i64` values of mixed magnitudes, from tiny to `2^(63 - shifts)` and up (a
    /// linear congruential generator from `seed`).
    fn mixed_values(seed: u64, shifts: u64) -> impl FnMut() -> i64 {
        let mut st = seed;
        move || {
            let st = crate::test_rng::lcg64(&mut st);
            let v = (st >> 1) as i64;
            v >> (st % shifts)
        }
    }

    /// A perspective camera at the extremes: the largest focal factor, near 1, far `i32::MAX`,
    /// a 65535 x 65535 image (its focal constant does not fit `i32`).
    fn extreme_camera() -> Camera {
        Camera::perspective(
            Vec3::ZERO,
            Vec3::units(0, 0, -1),
            Vec3::Y,
            i32::MAX,
            1,
            i32::MAX,
            65535,
            65535,
        )
    }

    /// The `i64` projection equals the `i128` one wherever it applies: random points of every
    /// magnitude and points at its bounds (`x`, `y` at `±2^31`, `x K` at `±2^62`), for
    /// cameras whose focal constant fits `i32` and one whose does not.
    #[test]
    fn small_projection_is_the_wide_one() {
        let mut rnd = mixed_values(777, 63);
        let cams = [
            persp(Vec3::ZERO, Vec3::units(0, 0, -1)),
            extreme_camera(),
            Camera::perspective(Vec3::ZERO, Vec3::units(0, 0, -1), Vec3::Y, ONE, 1, 2, 2, 2),
        ];
        let edges = [
            0,
            1,
            -1,
            (1 << 31) - 1,
            -(1 << 31),
            1 << 31,
            -(1 << 31) - 1,
            i64::MAX,
            i64::MIN,
        ];
        let mut fast = 0;
        for cam in cams {
            let view = cam.view().unwrap();
            let ViewProj::Perspective { k } = view.proj else {
                panic!("perspective");
            };
            let mut xs: Vec<i64> = edges.to_vec();
            // x K at and next to ±2^62.
            if k != 0 && (1i64 << 62) % k == 0 {
                let q = (1i64 << 62) / k;
                xs.extend([q, -q, q - 1, 1 - q]);
            }
            let mut pts: Vec<[i64; 3]> = Vec::new();
            for &x in &xs {
                for &z in &[1, 2, 1 << 20, (1 << 31) - 1, -5, i64::MAX] {
                    pts.push([x, x.wrapping_neg(), z]);
                    pts.push([x, 7, z]);
                }
            }
            for _ in 0..20000 {
                pts.push([rnd(), rnd(), rnd()]);
            }
            for p in pts {
                let v = CamVertex { p, tex: [1, 2, 3] };
                if let Some(s) = view.project_perspective_small(&v) {
                    fast += 1;
                    assert_eq!(s, view.project_wide(&v), "{p:?}");
                }
            }
        }
        assert!(fast > 10000, "the i64 path ran {fast} times");
    }

    /// The fast outcodes are exactly the signs of the clip planes.
    #[test]
    fn outcodes_match_planes() {
        let mut rnd = mixed_values(12345, 62);
        let cams = [
            persp(Vec3::ZERO, Vec3::units(0, 0, -1)),
            Camera::orthographic(
                Vec3::units(0, 0, 5),
                Vec3::ZERO,
                Vec3::Y,
                units(2),
                units(1),
                units(10),
                320,
                240,
            ),
            extreme_camera(),
        ];
        // The i64 path's bounds: coordinates at and past i32, z at and past 2^22 and 2^31.
        let edges = [
            0,
            1,
            -1,
            i32::MAX as i64,
            i32::MIN as i64,
            1 << 31,
            -(1 << 31) - 1,
        ];
        let zs = [0, 1, (1 << 22) - 1, 1 << 22, (1 << 31) - 1, 1 << 31, -1];
        let mut pts = Vec::new();
        for &x in &edges {
            for &y in &edges {
                for &z in &zs {
                    pts.push([x, y, z]);
                }
            }
        }
        for cam in cams {
            let view = cam.view().unwrap();
            for i in 0..20000 + pts.len() {
                let p = pts.get(i).copied().unwrap_or_else(|| [rnd(), rnd(), rnd()]);
                let (s, g) = view.outcodes(&p);
                for i in 0..6 {
                    assert_eq!(view.screen[i].eval(&p) < 0, s & (1 << i) != 0, "{p:?} {i}");
                    assert_eq!(view.guard[i].eval(&p) < 0, g & (1 << i) != 0, "{p:?} {i}");
                }
            }
        }
    }

    #[test]
    fn inv_w_normalisation() {
        assert_eq!(
            normalise_inv_w([1 << 62, 1 << 61, 1 << 40]),
            [1 << 30, 1 << 29, 1 << 8]
        );
        assert_eq!(normalise_inv_w([3, 2, 1]), [3, 2, 1]);
        assert_eq!(normalise_inv_w([0, 0, 0]), [0, 0, 0]);
        let q = normalise_inv_w([(1 << 62) / 3, 12345678901, 1]);
        assert!(q[0] >= 1 << 30 && q[0] <= 1 << 31);
        // Rounding half up: the shifted value plus the last bit shifted out, for any values
        // (one shift of the rounded form against the two of the definition).
        let want = |q: [u64; 3]| {
            let m = q[0].max(q[1]).max(q[2]);
            let shift = (64 - m.leading_zeros()).saturating_sub(31);
            q.map(|v| {
                let r = if shift == 0 {
                    v
                } else {
                    (v >> shift) + ((v >> (shift - 1)) & 1)
                };
                r.min(u64::from(u32::MAX)) as u32
            })
        };
        let mut rng = crate::test_rng::XorShift64::new(0x9E37_79B9_7F4A_7C15);
        let mut next = || rng.spread();
        for _ in 0..100_000 {
            let q = [next(), next(), next()];
            assert_eq!(normalise_inv_w(q), want(q), "{q:?}");
        }
        // The largest value at every bit length, the others random below it.
        for bits in 0..=64u32 {
            for _ in 0..200 {
                let top = if bits == 0 {
                    0
                } else {
                    u64::MAX >> (64 - bits)
                };
                let m = top & !(next() & (top >> 1));
                let below = |r: u64| r % m.saturating_add(1);
                let mut q = [m, below(next()), below(next())];
                q.rotate_left((next() % 3) as usize);
                assert_eq!(normalise_inv_w(q), want(q), "{q:?}");
            }
        }
        for q in [[u64::MAX; 3], [u64::MAX, 1, 0], [(1 << 31) - 1, 1 << 31, 3]] {
            assert_eq!(normalise_inv_w(q), want(q), "{q:?}");
        }
    }
}
