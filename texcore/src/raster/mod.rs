//! Scanline rasterizer: triangles in, linear texture-coordinate segments out.
//!
//! The rasterizer turns screen-space triangles carrying solid texture coordinates into horizontal
//! [`Segment`]s along which the texture coordinates are **exactly linear**,
//! `s(i) = s0 + i * ds` (`docs/model.md`, section 3), and hands them to a caller-supplied
//! [`SegmentSink`]. It produces geometry only (no colours).
//!
//! # Formats and ranges
//!
//! | quantity | type | layout | range |
//! |---|---|---|---|
//! | vertex `x`, `y` | [`ScreenCoord`] | `I28F4` (1/16 pixel) | guard band: raw `|v| < 2^30`, i.e. `±2^26` pixels |
//! | vertex depth `z` | [`Depth`] | `u16` | 0 (near) ..= 65535 (far) |
//! | vertex `1/w` | [`InvW`] | `U1F31` | `[0, 2)`; only the ratios within a triangle matter |
//! | texture coordinates | [`TexPoint`] | 3 x `I16F16` | full range |
//! | pixel coordinates, clip rectangle | `u16` | integer | target up to 65535 x 65535 pixels |
//!
//! Pixel `(x, y)` has its centre at `(x + 0.5, y + 0.5)`. Triangles with a vertex outside the
//! guard band are rejected ([`Reject::OutsideGuardBand`]): clip them geometrically upstream. Any
//! `i32` bit pattern is accepted without panicking.
//!
//! Only ratios of `1/w` within one triangle matter: setup normalises the three values by a common
//! power of two (so the largest lies in `[2^29, 2^30)` as an integer), and the caller may scale them
//! per triangle as it likes. A vertex with `1/w = 0` (a point at infinity) is accepted; if all three
//! are 0 the triangle is interpolated affinely.
//!
//! # Coverage (fill rule)
//!
//! Coverage is exact: the edges are walked in integer arithmetic (`i128` at setup, `i64` quotient
//! and remainder per row), and a pixel is covered iff its centre is strictly inside the triangle, or
//! on a **top** or **left** edge (top-left rule, as in Direct3D/OpenGL). Shared edges of a mesh are
//! therefore drawn exactly once, with no gaps. Zero-area triangles (collinear or repeated vertices)
//! draw nothing; triangles that contain no pixel centre draw nothing. Both windings are drawn unless
//! [`CullMode`] says otherwise.
//!
//! Clipping to the rectangle set with [`Rasterizer::set_clip`] is exact too (the clip only selects
//! rows and columns), and every interpolated value is computed relative to the fixed screen origin,
//! never relative to the clip: rendering a frame in horizontal **bands** gives bit-identical
//! segments to rendering it whole.
//!
//! # Interpolation
//!
//! Interpolants are plane equations in `i64` evaluated relative to pixel `(0, 0)` with wrapping
//! arithmetic; the planes are computed exactly (rounded once) in `i128` at setup, so the value at
//! any pixel of a 65535-pixel target is within `2^16` units of the plane's last bit, far below one
//! `TexCoord` LSB. Error bounds and the Jacobian's precision are documented on [`Perspective`].
//!
//! # Perspective modes
//!
//! - [`Perspective::Affine`]: texture coordinates are screen-linear (`1/w` is ignored); one segment
//!   per covered run; **no divisions** at span time.
//! - [`Perspective::Exact`]: `s/w` and `1/w` are interpolated linearly and divided at every pixel
//!   (segments of length 1).
//! - [`Perspective::Every8`] / [`Perspective::Every16`]: exact divides at segment starts, which lie
//!   on screen columns that are multiples of 8 / 16 (and at run starts), and at the last pixel of
//!   each run; linear in between.
//!
//! # Depth
//!
//! An optional, caller-owned [`DepthBuffer`] (any `&mut [u16]` covering a rectangle, e.g. one
//! band) splits runs into visible sub-runs; `z` is interpolated screen-linearly.

//! # Example: a frame in bands of 8 rows with a band-sized depth buffer
//!
//! ```
//! use texcore::raster::*;
//! use texcore::TexPoint;
//!
//! let v = |x: f32, y: f32, z: u16, w: f32, s: f64| ScreenVertex::new(
//!     ScreenCoord::from_num(x), ScreenCoord::from_num(y), z,
//!     InvW::from_num(1.0 / w), TexPoint::from_f64(s, 0.0, 0.0));
//! let tri = [v(0.0, 0.0, 100, 1.0, 0.0), v(64.0, 0.0, 100, 4.0, 8.0), v(0.0, 32.0, 100, 1.0, 0.0)];
//! let opts = TriangleOptions::new(Perspective::Every8);
//!
//! let mut rast = Rasterizer::new(Rect::from_size(64, 32));
//! let setup = rast.setup(&tri, &opts).unwrap();
//! let mut zbuf = [0u16; 64 * 8];
//! let mut pixels = 0;
//! for band in 0..4 {
//!     let rect = Rect::new(0, band * 8, 64, band * 8 + 8);
//!     let mut depth = DepthBuffer::new(&mut zbuf, rect).unwrap();
//!     depth.clear(u16::MAX);
//!     rast.set_clip(rect);
//!     rast.draw_setup_depth(&setup, &mut depth, &mut |seg: &Segment| {
//!         assert!(seg.len <= 8);
//!         pixels += seg.len as u32; // evaluate the texture along seg.s_at(0..seg.len) here
//!     });
//! }
//! assert_eq!(pixels as u64, rast.counters().pixels);
//! assert_eq!(rast.counters().setups, 1);
//! ```

mod depth;
mod edge;
mod perspective;
mod setup;
#[cfg(feature = "atlas")]
mod small;
#[cfg(test)]
mod tests;
#[cfg(feature = "atlas")]
mod textured;

pub use depth::{fill_u16, DepthBuffer, DepthFunc};
use setup::Prepared;
pub use setup::{Reject, TriangleSetup};
#[cfg(feature = "atlas")]
pub use textured::Texture565;

use crate::format::{TexCoord, TexPoint};
use fixed::types::{I28F4, U1F31};

/// A sub-pixel screen coordinate: 28 integer and 4 fraction bits (1/16 pixel).
pub type ScreenCoord = I28F4;
/// The perspective term `1/w` of a vertex, `U1F31`. Only its ratios within a triangle matter.
pub type InvW = U1F31;
/// A depth value: 0 is nearest, 65535 farthest.
pub type Depth = u16;

/// Number of fraction bits of [`ScreenCoord`].
pub const SUBPIXEL_BITS: u32 = 4;
/// Vertices must satisfy `|x.to_bits()| < GUARD_BAND` and `|y.to_bits()| < GUARD_BAND`
/// (`2^30` raw, `2^26` pixels); other triangles are rejected.
pub const GUARD_BAND: u32 = 1 << 30;

/// A vertex in screen space.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ScreenVertex {
    /// Horizontal position, sub-pixel (pixel `x` covers `[x, x + 1)`, centre `x + 0.5`).
    pub x: ScreenCoord,
    /// Vertical position, sub-pixel, growing downwards.
    pub y: ScreenCoord,
    /// Depth for the optional depth buffer (0 = near). Interpolated screen-linearly.
    pub z: Depth,
    /// Perspective term `1/w`; ignored by [`Perspective::Affine`].
    pub inv_w: InvW,
    /// Solid texture coordinates at the vertex.
    pub tex: TexPoint,
}

impl ScreenVertex {
    /// Builds a vertex.
    pub const fn new(x: ScreenCoord, y: ScreenCoord, z: Depth, inv_w: InvW, tex: TexPoint) -> Self {
        ScreenVertex {
            x,
            y,
            z,
            inv_w,
            tex,
        }
    }

    /// Builds a vertex from raw bit patterns: `x`, `y` in 1/16 pixel, `inv_w` in `2^-31`.
    pub const fn from_bits(x: i32, y: i32, z: Depth, inv_w: u32, tex: TexPoint) -> Self {
        ScreenVertex {
            x: ScreenCoord::from_bits(x),
            y: ScreenCoord::from_bits(y),
            z,
            inv_w: InvW::from_bits(inv_w),
            tex,
        }
    }
}

/// A half-open pixel rectangle `[x0, x1) x [y0, y1)`: the render target, a scissor or a band.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rect {
    /// First column.
    pub x0: u16,
    /// First row.
    pub y0: u16,
    /// One past the last column.
    pub x1: u16,
    /// One past the last row.
    pub y1: u16,
}

impl Rect {
    /// Builds `[x0, x1) x [y0, y1)` (empty if `x1 <= x0` or `y1 <= y0`).
    pub const fn new(x0: u16, y0: u16, x1: u16, y1: u16) -> Self {
        Rect { x0, y0, x1, y1 }
    }

    /// A `width` x `height` rectangle at the origin.
    pub const fn from_size(width: u16, height: u16) -> Self {
        Rect::new(0, 0, width, height)
    }

    /// Width in pixels (0 if empty).
    pub const fn width(&self) -> u16 {
        self.x1.saturating_sub(self.x0)
    }

    /// Height in pixels (0 if empty).
    pub const fn height(&self) -> u16 {
        self.y1.saturating_sub(self.y0)
    }

    /// Whether the rectangle contains no pixel.
    pub const fn is_empty(&self) -> bool {
        self.x1 <= self.x0 || self.y1 <= self.y0
    }

    /// The intersection of two rectangles.
    pub fn intersect(&self, other: &Rect) -> Rect {
        Rect::new(
            self.x0.max(other.x0),
            self.y0.max(other.y0),
            self.x1.min(other.x1),
            self.y1.min(other.y1),
        )
    }

    /// Whether pixel `(x, y)` is inside.
    pub const fn contains(&self, x: u16, y: u16) -> bool {
        x >= self.x0 && x < self.x1 && y >= self.y0 && y < self.y1
    }
}

/// A horizontal segment of covered pixels `x0 .. x0 + len` on row `y`, along which the solid
/// texture coordinates are exactly `s(i) = s0 + i * ds`, computed in `i64` as in
/// `docs/model.md` 3 ([`Segment::s_at`]). Every `s(i)` lies within the range of the triangle's
/// vertex coordinates up to the error bounds of [`Perspective`].
///
/// `ds` is also the x column of the screen-space Jacobian and `dsdy` its y column, in texture
/// units per pixel (see [`Perspective`] for how each is obtained and their precision). Components
/// that do not fit `I16F16` are saturated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Segment {
    /// Row.
    pub y: u16,
    /// First column.
    pub x0: u16,
    /// Number of pixels (at least 1).
    pub len: u16,
    /// Texture coordinates at pixel `x0`.
    pub s0: TexPoint,
    /// Step per pixel along the segment: `ds/dx`.
    pub ds: TexPoint,
    /// `ds/dy` at the segment (filter width only).
    pub dsdy: TexPoint,
}

impl Segment {
    /// The texture coordinates of pixel `i` of the segment, `s0 + i * ds`, as raw 16.16 values in
    /// `i64` (the span evaluator's exact form, `docs/model.md` 3).
    pub fn s_at(&self, i: u16) -> [i64; 3] {
        let s0 = self.s0.to_bits();
        let ds = self.ds.to_bits();
        let i = i as i64;
        [
            s0[0] as i64 + i * ds[0] as i64,
            s0[1] as i64 + i * ds[1] as i64,
            s0[2] as i64 + i * ds[2] as i64,
        ]
    }
}

/// Receives the segments of rasterized triangles.
pub trait SegmentSink {
    /// Called once per segment, in row order within a triangle, left to right within a row.
    fn segment(&mut self, seg: &Segment);
}

impl<F: FnMut(&Segment)> SegmentSink for F {
    fn segment(&mut self, seg: &Segment) {
        self(seg)
    }
}

/// How the texture coordinates are interpolated across a triangle.
///
/// # Error bounds
///
/// In `TexCoord` LSBs (`2^-16`), against the interpolation of the vertex data computed in real
/// arithmetic (perspective-correct: `s = sum(l_i q_i s_i) / sum(l_i q_i)` with barycentrics
/// `l_i`; `Affine`: screen-linear), on targets up to 65535 pixels. The vertex data are taken as
/// quantised by setup: positions at 1/16 pixel, `1/w` to 30 significant bits relative to the
/// triangle's largest. Per component, let `b` be the bit length of `max_i |s_i - s_0|` (raw, at
/// most 32) and `ratio = max(1/w) / min(1/w)` over the triangle.
///
/// - `Exact`, and every segment start of `Every8`/`Every16`: the perspective quotient is rounded
///   to nearest, and `|s - s_true| <= E = 1/2 + ratio * (2^(2b - 62) + 2^(b - 45))`. For example
///   `E < 0.52` when the coordinate varies by less than 256 units across the triangle
///   (`b <= 24`) with `ratio <= 64`; `E` reaches `1/2 + ratio * 4` for a triangle spanning the
///   full `I16F16` range (`b = 32`), i.e. relative precision about `ratio * 2^-30` of the range.
/// - `Every8`/`Every16`: pixel `i` of a segment is within `E + i/2 + chord(i)`, where `chord(i)`
///   is the distance at pixel `i` between the true hyperbola and its chord through the segment's
///   exact end points (the next segment's start, or the run's last pixel), at most
///   `(n^2 / 4) * max(|d ln(1/w)/dx| * |ds/dx|)` over the segment (`n` = 8 or 16). The linear
///   continuation `s0 + steps * ds` reaches the exact end point within `steps / 2`.
/// - `Affine`: pixel `i` of a run is within `1/2 + i/2 + 2^(b - 46)` of the screen-linear plane
///   (`ds` is the plane gradient rounded to nearest, so the step error accumulates).
///
/// # Jacobian
///
/// `ds` doubles as the x column `ds/dx` of the screen-space Jacobian; `dsdy` is its y column.
/// - `Affine`: the plane gradients, constant per triangle, each within 1/2 LSB.
/// - Perspective modes: `dsdy` is the **analytic derivative of the perspective mapping at the
///   segment's first pixel centre**, `(d(s/w)/dy - s d(1/w)/dy) / (1/w)`, evaluated from the
///   interpolated planes and rounded to nearest: within `1/2 + E * |d ln(1/w)/dy| +
///   2^-24 * |ds/dy|` LSB. For segments of length 1, `ds` is the analytic `ds/dx` at the pixel
///   (same precision); for longer segments `ds` is the **exact secant**
///   `(s(end) - s(start)) / (end - start)` between the segment's exact end points, rounded to
///   nearest, which is the step that keeps the segment linear.
///
/// Components that do not fit `I16F16` are saturated. Where a step along x does not fit
/// `I16F16` (a coordinate changing by `2^15` units or more per pixel), the rasterizer falls
/// back to segments of length 1 with exact values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Perspective {
    /// Exact perspective divide at every pixel (segments of length 1).
    Exact,
    /// Exact divides every 8 pixels, linear in between (segments of up to 8 pixels).
    Every8,
    /// Exact divides every 16 pixels, linear in between (segments of up to 16 pixels).
    #[default]
    Every16,
    /// Screen-linear, no divides: one segment per covered run.
    Affine,
}

impl Perspective {
    /// The longest segment this mode emits (`None`: a whole run) for a triangle with perspective.
    ///
    /// A triangle whose three `1/w` are all zero carries no depth to divide by: every mode
    /// interpolates it affinely and emits whole runs, as [`Perspective::Affine`] does.
    pub const fn max_len(self) -> Option<u16> {
        match self {
            Perspective::Exact => Some(1),
            Perspective::Every8 => Some(8),
            Perspective::Every16 => Some(16),
            Perspective::Affine => None,
        }
    }
}

/// Back-face culling. Winding is as seen on the screen (y growing downwards): a triangle is
/// clockwise when `(x1 - x0)(y2 - y0) - (x2 - x0)(y1 - y0) > 0`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CullMode {
    /// Draw both windings.
    #[default]
    None,
    /// Discard clockwise triangles.
    Clockwise,
    /// Discard counter-clockwise triangles.
    CounterClockwise,
}

/// Per-triangle (per-object) drawing options. The default is [`TriangleOptions::new`] with the
/// default perspective mode: no culling, depth test `Less` with writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TriangleOptions {
    /// Texture coordinate interpolation.
    pub perspective: Perspective,
    /// Back-face culling.
    pub cull: CullMode,
    /// Depth comparison (only with a depth buffer).
    pub depth_func: DepthFunc,
    /// Whether passing pixels write their depth (only with a depth buffer).
    pub depth_write: bool,
}

impl Default for TriangleOptions {
    fn default() -> Self {
        TriangleOptions::new(Perspective::default())
    }
}

impl TriangleOptions {
    /// Options with the given interpolation, no culling, depth test `Less` with writes.
    pub const fn new(perspective: Perspective) -> Self {
        TriangleOptions {
            perspective,
            cull: CullMode::None,
            depth_func: DepthFunc::Less,
            depth_write: true,
        }
    }
}

/// Activity counters. All counts wrap (they never panic).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Counters {
    /// Triangles submitted to [`Rasterizer::setup`] / [`Rasterizer::draw`].
    pub triangles: u32,
    /// Triangles set up (not rejected).
    pub setups: u32,
    /// Triangles rejected as zero-area.
    pub degenerate: u32,
    /// Triangles rejected by back-face culling.
    pub culled: u32,
    /// Triangles rejected for a vertex outside the guard band.
    pub outside_guard_band: u32,
    /// Triangles skipped by [`Rasterizer::draw`] because their bounding box misses the clip.
    pub offscreen: u32,
    /// Pixels emitted in segments.
    pub pixels: u64,
    /// Segments emitted.
    pub segments: u64,
    /// Points at which the perspective quotient `(s/w) / (1/w)` was evaluated.
    pub persp_points: u64,
    /// Integer divisions performed while interpolating (quotients, Jacobian quotients and secant
    /// slopes of length other than a power of two). Setup and edge-walker initialisation are not
    /// counted. Always 0 for [`Perspective::Affine`].
    pub divides: u64,
    /// Pixels discarded by the depth test.
    pub depth_failed: u64,
    /// Triangles whose texture interpolation (the texture planes, most of a set-up's work) was
    /// set up: every one [`Rasterizer::setup`] sets up, but for [`Rasterizer::draw`] and
    /// [`Rasterizer::draw_depth`] only those with a visible pixel in the clip.
    pub texture_setups: u32,
}

/// The rasterizer: a clip rectangle and activity counters.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Rasterizer {
    clip: Rect,
    counters: Counters,
}

impl Rasterizer {
    /// A rasterizer drawing into `clip` (the target, a scissor or a band).
    pub const fn new(clip: Rect) -> Self {
        Rasterizer {
            clip,
            counters: Counters {
                triangles: 0,
                setups: 0,
                degenerate: 0,
                culled: 0,
                outside_guard_band: 0,
                offscreen: 0,
                pixels: 0,
                segments: 0,
                persp_points: 0,
                divides: 0,
                depth_failed: 0,
                texture_setups: 0,
            },
        }
    }

    /// The clip rectangle.
    pub const fn clip(&self) -> Rect {
        self.clip
    }

    /// Sets the clip rectangle (e.g. the next band).
    pub fn set_clip(&mut self, clip: Rect) {
        self.clip = clip;
    }

    /// The activity counters.
    pub const fn counters(&self) -> Counters {
        self.counters
    }

    /// Resets the activity counters to zero.
    pub fn reset_counters(&mut self) {
        self.counters = Counters::default();
    }

    /// Sets a triangle up (independently of the clip, so one setup can be drawn into several
    /// bands), counting the outcome.
    pub fn setup(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
    ) -> Result<TriangleSetup, Reject> {
        let mut r = self.prepare(v, opts);
        match &mut r {
            Ok(pre) => Ok(*pre.complete(&mut self.counters)),
            Err(e) => Err(*e),
        }
    }

    /// The first part of [`Rasterizer::setup`] (coverage and depth plane), counting the outcome
    /// as `setup` does; [`Prepared::complete`] adds the texture interpolation.
    fn prepare(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
    ) -> Result<Prepared, Reject> {
        let r = Prepared::new(v, opts);
        self.count_setup(r.as_ref().err());
        r
    }

    /// Counts a triangle submitted for set-up and its outcome (`None`: set up).
    #[inline(always)]
    fn count_setup(&mut self, rejected: Option<&Reject>) {
        let c = &mut self.counters;
        c.triangles = c.triangles.wrapping_add(1);
        match rejected {
            None => c.setups = c.setups.wrapping_add(1),
            Some(Reject::Degenerate) => c.degenerate = c.degenerate.wrapping_add(1),
            Some(Reject::Culled) => c.culled = c.culled.wrapping_add(1),
            Some(Reject::OutsideGuardBand) => {
                c.outside_guard_band = c.outside_guard_band.wrapping_add(1)
            }
        }
    }

    /// Draws a set-up triangle into the clip rectangle.
    pub fn draw_setup<S: SegmentSink + ?Sized>(&mut self, setup: &TriangleSetup, sink: &mut S) {
        let counters = &mut self.counters;
        edge::walk_runs(&setup.cov, self.clip, |py, xa, xb| {
            perspective::emit_run(setup, py, xa, xb, counters, sink);
        });
    }

    /// Draws a set-up triangle into the intersection of the clip rectangle and the depth buffer's
    /// rectangle, with the depth test and write of the triangle's options.
    pub fn draw_setup_depth<S: SegmentSink + ?Sized>(
        &mut self,
        setup: &TriangleSetup,
        depth: &mut DepthBuffer<'_>,
        sink: &mut S,
    ) {
        let counters = &mut self.counters;
        let clip = self.clip.intersect(&depth.rect());
        let plane = setup.depth_plane();
        edge::walk_runs(&setup.cov, clip, |py, xa, xb| {
            depth::depth_run(&plane, depth, py, xa, xb, counters, |y, x0, x1, ctr| {
                perspective::emit_run(setup, y, x0, x1, ctr, sink)
            });
        });
    }

    /// Sets up and draws a triangle into the clip rectangle. Triangles whose bounding box misses
    /// the clip are skipped before setup.
    pub fn draw<S: SegmentSink + ?Sized>(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
        sink: &mut S,
    ) {
        if self.misses(v, self.clip) {
            return;
        }
        // The texture planes are set up at the first covered run (none if no pixel centre of
        // the clip is covered).
        let mut r = self.prepare(v, opts);
        let Ok(pre) = &mut r else {
            return;
        };
        let counters = &mut self.counters;
        edge::walk_runs(&pre.coverage(), self.clip, |py, xa, xb| {
            let setup = pre.complete(counters);
            perspective::emit_run(setup, py, xa, xb, counters, sink);
        });
    }

    /// Sets up and draws a triangle with a depth buffer (see [`Rasterizer::draw_setup_depth`]).
    pub fn draw_depth<S: SegmentSink + ?Sized>(
        &mut self,
        v: &[ScreenVertex; 3],
        opts: &TriangleOptions,
        depth: &mut DepthBuffer<'_>,
        sink: &mut S,
    ) {
        if self.misses(v, self.clip.intersect(&depth.rect())) {
            return;
        }
        // The texture planes are set up at the first visible run: a triangle hidden in the
        // clip, or covering none of its pixel centres, costs only its coverage and depth plane.
        let mut r = self.prepare(v, opts);
        let Ok(pre) = &mut r else {
            return;
        };
        let counters = &mut self.counters;
        let clip = self.clip.intersect(&depth.rect());
        let plane = pre.depth_plane();
        edge::walk_runs(&pre.coverage(), clip, |py, xa, xb| {
            depth::depth_run(&plane, depth, py, xa, xb, counters, |y, x0, x1, ctr| {
                let setup = pre.complete(ctr);
                perspective::emit_run(setup, y, x0, x1, ctr, sink)
            });
        });
    }

    /// Conservative bounding-box rejection (counts the triangle as submitted and offscreen).
    fn misses(&mut self, v: &[ScreenVertex; 3], clip: Rect) -> bool {
        let [x0, x1, y0, y1] = bounding_box(v);
        // In i32: 16 * 65535 + 8 fits.
        let edge = |c: u16| 16 * i32::from(c);
        // Pixel centres are at 16 p + 8: the box covers a centre of the clip only if
        // x1 >= 16 clip.x0 + 8 and x0 <= 16 (clip.x1 - 1) + 8 (same for y).
        let miss = clip.is_empty()
            || x1 < edge(clip.x0) + 8
            || x0 > edge(clip.x1) - 8
            || y1 < edge(clip.y0) + 8
            || y0 > edge(clip.y1) - 8;
        if miss {
            let c = &mut self.counters;
            c.triangles = c.triangles.wrapping_add(1);
            c.offscreen = c.offscreen.wrapping_add(1);
        }
        miss
    }
}

/// The raw 28.4 bounding box `[x0, x1, y0, y1]` (inclusive) of a triangle's vertices, in the
/// coordinates' own `i32` words.
#[inline]
pub(crate) fn bounding_box(v: &[ScreenVertex; 3]) -> [i32; 4] {
    let (mut x0, mut x1, mut y0, mut y1) = (i32::MAX, i32::MIN, i32::MAX, i32::MIN);
    for p in v {
        let (x, y) = (p.x.to_bits(), p.y.to_bits());
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    [x0, x1, y0, y1]
}

/// Builds a `TexPoint` from three raw `i64` values known to fit `i32`.
#[inline]
pub(crate) fn tex_point(v: [i64; 3]) -> TexPoint {
    TexPoint::new(
        TexCoord::from_bits(v[0] as i32),
        TexCoord::from_bits(v[1] as i32),
        TexCoord::from_bits(v[2] as i32),
    )
}

/// Saturates an `i128` to `i32`.
#[inline]
pub(crate) fn sat_i32(v: i128) -> i32 {
    v.clamp(i32::MIN as i128, i32::MAX as i128) as i32
}

/// `round(n / d)` (half up) for `d > 0`; never panics (returns `n` for `d <= 0`).
#[inline]
pub(crate) fn div_round_i64(n: i64, d: i64) -> i64 {
    if d <= 0 {
        return n;
    }
    // The magnitudes divide on the 32-bit hardware divide (`wide::div_rem_u64`: most divisors
    // here, the perspective quotients, are past 2^32, where the library division would take two
    // calls); the Euclidean quotient from them.
    let (q, r) = match crate::wide::div_rem_u64(n.unsigned_abs(), d as u64) {
        Some((qm, rm)) if n >= 0 => (qm as i64, rm as i64),
        // n < 0: -|n| = -(qm d + rm) = -(qm + 1) d + (d - rm) when rm > 0.
        Some((qm, 0)) => ((qm as i64).wrapping_neg(), 0),
        Some((qm, rm)) => ((qm as i64).wrapping_neg().wrapping_sub(1), d - rm as i64),
        None => (n, 0),
    };
    if r >= d - r {
        q.wrapping_add(1)
    } else {
        q
    }
}

/// `round(n / d)` (half up) for `d != 0`; never panics (returns 0 for `d == 0`).
#[inline]
pub(crate) fn div_round_i128(n: i128, d: i128) -> i128 {
    if d == 0 {
        return 0;
    }
    let (n, d) = if d < 0 {
        (n.saturating_neg(), d.saturating_neg())
    } else {
        (n, d)
    };
    let (q, r) = crate::wide::div_rem_euclid_i128(n, d);
    if r >= d - r {
        q.saturating_add(1)
    } else {
        q
    }
}
