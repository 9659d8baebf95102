//! Where a drawn shape lies in solid-texture space ([`PlaneMapping`]), and the exact `f32`
//! conversions of its set-up conveniences (never used in the pixel path).

use super::*;

/// Where a drawn shape lies in solid-texture space: display pixel `(x, y)` (relative to the
/// anchor) is shaded at `s = origin + (x + 1/2) step_x + (y + 1/2) step_y` (raw 16.16
/// components, wrapping like the span evaluator's coordinates).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlaneMapping {
    anchor: Point,
    plane: CheckPlane,
}

impl Default for PlaneMapping {
    /// 64 pixels per texture unit in the `(s, t)` plane at `r = 1/2`, anchored at the display's
    /// origin.
    fn default() -> Self {
        PlaneMapping::scaled(64)
    }
}

impl PlaneMapping {
    /// A mapping of a check plane ([`crate::presets::Preset::plane`]: the preset's look at 256
    /// pixels a side), anchored at the display's origin.
    pub const fn from_plane(plane: CheckPlane) -> PlaneMapping {
        PlaneMapping {
            anchor: Point::zero(),
            plane,
        }
    }

    /// The `(s, t)` plane at `r = 1/2`, `pixels_per_unit` pixels per texture unit (at least 1),
    /// anchored at the display's origin.
    pub const fn scaled(pixels_per_unit: u16) -> PlaneMapping {
        let p = if pixels_per_unit == 0 {
            1
        } else {
            pixels_per_unit as i32
        };
        let step = 65536 / p;
        PlaneMapping::from_plane(CheckPlane {
            origin: [0, 0, 32768],
            step_x: [step, 0, 0],
            step_y: [0, step, 0],
        })
    }

    /// The plane.
    pub const fn plane(&self) -> CheckPlane {
        self.plane
    }

    /// The display point the plane's origin is attached to.
    pub const fn anchor(&self) -> Point {
        self.anchor
    }

    /// The same mapping attached to display point `anchor` (for example a shape's top-left
    /// corner, so that the texture moves with the shape).
    pub const fn at(mut self, anchor: Point) -> PlaneMapping {
        self.anchor = anchor;
        self
    }

    /// The same mapping with solid coordinates `origin` (raw 16.16) at the anchor.
    pub const fn with_origin(mut self, origin: [i32; 3]) -> PlaneMapping {
        self.plane.origin = origin;
        self
    }

    /// The same mapping with the steps per pixel multiplied by `k` (raw 16.16: `65536` keeps
    /// them; `131072` shows twice as much texture), saturating.
    pub const fn with_zoom(mut self, k: i32) -> PlaneMapping {
        let mut i = 0;
        while i < 3 {
            self.plane.step_x[i] = mul_q16(self.plane.step_x[i], k);
            self.plane.step_y[i] = mul_q16(self.plane.step_y[i], k);
            i += 1;
        }
        self
    }

    /// The same mapping rotated by `angle` within its plane, about the anchor: `step_x` turns
    /// towards `step_y` (a quarter turn makes `step_x` the old `step_y`).
    pub const fn rotated(mut self, angle: Angle) -> PlaneMapping {
        let (s, c) = sin_cos(angle);
        let (sx, sy) = (self.plane.step_x, self.plane.step_y);
        let mut i = 0;
        while i < 3 {
            self.plane.step_x[i] = mul_q30(sx[i], c).wrapping_add(mul_q30(sy[i], s));
            self.plane.step_y[i] = mul_q30(sy[i], c).wrapping_sub(mul_q30(sx[i], s));
            i += 1;
        }
        self
    }

    /// The same mapping moved by `phase` texture units (raw 16.16) along the plane's normal:
    /// consecutive phases slice the solid texture at consecutive depths (an animation). A
    /// degenerate plane (parallel steps) does not move.
    pub const fn with_phase(mut self, phase: i32) -> PlaneMapping {
        let (a, b) = (self.plane.step_x, self.plane.step_y);
        let n = [
            a[1] as i64 * b[2] as i64 - a[2] as i64 * b[1] as i64,
            a[2] as i64 * b[0] as i64 - a[0] as i64 * b[2] as i64,
            a[0] as i64 * b[1] as i64 - a[1] as i64 * b[0] as i64,
        ];
        let len2 = (n[0] as i128 * n[0] as i128
            + n[1] as i128 * n[1] as i128
            + n[2] as i128 * n[2] as i128) as u128;
        let len = isqrt_u128(len2) as i128;
        if len == 0 {
            return self;
        }
        let mut i = 0;
        while i < 3 {
            // n_i / |n| * phase, rounded toward zero; |n_i| <= |n|, so it fits i32.
            let d = (n[i] as i128 * phase as i128) / len;
            self.plane.origin[i] = self.plane.origin[i].wrapping_add(d as i32);
            i += 1;
        }
        self
    }

    /// [`PlaneMapping::rotated`] by `turns` of a full turn (set-up convenience): the fraction of
    /// a turn becomes a fixed-point [`Angle`] rounded to the nearest `2^-32` turn, the same bits
    /// on every target (see [`f32_to_nearest_i64`]). NaN does not rotate.
    pub fn rotated_turns(self, turns: f32) -> PlaneMapping {
        // In (-1, 1) exactly; times 2^32 is exact; a negative fraction wraps to its turn.
        let frac = f32_fract(turns);
        self.rotated(Angle(f32_to_nearest_i64(frac * 4_294_967_296.0) as u32))
    }

    /// [`PlaneMapping::with_zoom`] by `k` (set-up convenience): `k` in 16.16 rounded to
    /// nearest, saturating (see [`f32_to_nearest_i64`]).
    pub fn zoomed(self, k: f32) -> PlaneMapping {
        self.with_zoom(f32_to_q16(k))
    }

    /// [`PlaneMapping::with_phase`] by `phase` texture units (set-up convenience): in 16.16
    /// rounded to nearest, saturating (see [`f32_to_nearest_i64`]).
    pub fn phased(self, phase: f32) -> PlaneMapping {
        self.with_phase(f32_to_q16(phase))
    }

    /// The span of `len` pixels of display row `y` from display column `x`.
    pub fn span(&self, x: i32, y: i32, len: u16) -> Span {
        let p = &self.plane;
        let (x, y) = (
            i64::from(x) - i64::from(self.anchor.x),
            i64::from(y) - i64::from(self.anchor.y),
        );
        // Rounded down (not toward zero), so that a pixel's coordinates do not depend on where
        // its span starts: the span evaluator steps exactly by `step_x` from any start.
        let c = |i: usize| -> i32 {
            let v = i64::from(p.origin[i])
                + (i64::from(p.step_x[i]) * (2 * x + 1)).div_euclid(2)
                + (i64::from(p.step_y[i]) * (2 * y + 1)).div_euclid(2);
            v as i32
        };
        Span {
            s0: TexPoint::from_bits(c(0), c(1), c(2)),
            ds: TexPoint::from_bits(p.step_x[0], p.step_x[1], p.step_x[2]),
            dsdy: TexPoint::from_bits(p.step_y[0], p.step_y[1], p.step_y[2]),
            len,
        }
    }

    /// The spans of the display rectangle `area` as a [`SpanPlane`] (span `(x, y)` of it is
    /// [`PlaneMapping::span`]`(area.x + x, area.y + y, len)`): a span start is the plane's
    /// origin plus whole steps (`floor((2 x + 1) s / 2) = x s + floor(s / 2)`), so the plane's
    /// points are the mapping's, wrapped alike. `None` when `area` is wider or taller than
    /// `u16::MAX` or a start inside it would leave the coordinate range without wrapping.
    pub fn span_plane(&self, area: &Rectangle) -> Option<SpanPlane> {
        let w = u16::try_from(area.size.width).ok()?;
        let h = u16::try_from(area.size.height).ok()?;
        let s = self.span(area.top_left.x, area.top_left.y, 0);
        SpanPlane::new(s.s0, s.ds, s.dsdy, w, h).ok()
    }
}

/// `x` rounded to the nearest integer, ties away from zero, saturating to `i64`; NaN is 0.
///
/// The set-up conversions of the `f32` conveniences ([`PlaneMapping::rotated_turns`],
/// [`PlaneMapping::zoomed`], [`PlaneMapping::phased`]): the fraction comes from `micromath`'s
/// `fract` (exact, by bit manipulation: no FPU, no libm, identical on the host, the Cortex-M4F,
/// the FPU-less cores), the integer part from Rust's saturating `as` cast. Never used in the
/// pixel path.
pub fn f32_to_nearest_i64(x: f32) -> i64 {
    if x.is_nan() {
        return 0;
    }
    // Truncated toward zero (saturating); the fraction is `x` minus exactly that.
    let t = x as i64;
    let f = f32_fract(x);
    if f >= 0.5 {
        t.saturating_add(1)
    } else if f <= -0.5 {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// The fractional part of `x` with its sign (exact), 0 for NaN and the infinities:
/// `micromath`'s `fract` below `2^23`; every `f32` from `2^23` up is an integer (`micromath`
/// shifts by the exponent modulo 32 there and is not used).
fn f32_fract(x: f32) -> f32 {
    const WHOLE: f32 = 8_388_608.0; // 2^23
    if x.is_nan() || x >= WHOLE || x <= -WHOLE {
        0.0
    } else {
        F32Ext::fract(x)
    }
}

/// `x` as raw 16.16, rounded to nearest (ties away from zero), saturating to `i32`; NaN is 0.
pub(super) fn f32_to_q16(x: f32) -> i32 {
    // Times 2^16 is exact below the f32 overflow; beyond it, +-inf saturates.
    let v = f32_to_nearest_i64(x * 65536.0);
    v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
}

/// `a k / 2^16`, saturating.
const fn mul_q16(a: i32, k: i32) -> i32 {
    crate::scene::math::sat_i32((a as i64 * k as i64) >> 16)
}

/// `a c / 2^30` rounded (`|c| <= 2^30`, so it fits).
const fn mul_q30(a: i32, c: i32) -> i32 {
    ((a as i64 * c as i64 + (1 << 29)) >> 30) as i32
}
