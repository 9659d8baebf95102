//! Textured drawables for `embedded-graphics` (feature `embedded-graphics`).
//!
//! - [`TextureStyle`]: a primitive style that fills a shape with a [`Texture`]. Rectangles,
//!   circles, ellipses, triangles and rounded rectangles implement
//!   `StyledDrawable<TextureStyle>`, so `shape.into_styled(style).draw(&mut display)` works as
//!   with `PrimitiveStyle`.
//! - [`PlaneMapping`]: where the shape lies in solid-texture space: a plane with a scale, a
//!   rotation, an anchor point and an animation phase (a shift along the plane's normal, which
//!   slides the plane through the solid).
//! - [`TexturedScene`]: a scene (any [`TriangleSource`]: a [`crate::scene::Scene`], a mesh
//!   object) drawn through the [`Renderer`] as one `Drawable`; with feature `differences`,
//!   `TexturedScene::with_differences` draws it with the filter widths from differences (the
//!   renderer's approximate mode, its memory on the stack during `draw`), and
//!   `TextureStyle::with_differences` fills shapes so.
//!
//! ```
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::*};
//! use embedded_graphics::primitives::Rectangle;
//! use texcore::draw::{PlaneMapping, TextureStyle};
//! use texcore::filter::Antialias;
//! use texcore::ready::{Material, PresetName};
//!
//! let marble = Material::preset(PresetName::Marble).texture::<256>(Antialias::Csat)?;
//! let mut display = MockDisplay::<Rgb565>::new();
//! Rectangle::new(Point::new(4, 4), Size::new(40, 24))
//!     .into_styled(TextureStyle::new(&marble, PlaneMapping::scaled(32)))
//!     .draw(&mut display)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Guarantees:
//! - Any `DrawTarget` whose colour converts from `Rgb888` (`Rgb565`, `Bgr565`, `Rgb888`,
//!   `Gray8`, `BinaryColor`, ...); the texture's RGBA colours lose their alpha (opaque fill).
//!   For `Rgb565` the conversion gives the bits of [`Rgba8888::to_rgb565`] (tested), so a display
//!   shows exactly what the checksums measure.
//! - The shapes cover exactly the pixels `embedded-graphics` fills for them with a
//!   `PrimitiveStyle` fill (the pixels of `Primitive::points`). Each row run of a shape is one
//!   span of the span evaluator (cut into [`RUN_CHUNK`]-pixel spans, which give the same colours
//!   in every exact mode) and one `fill_contiguous` call; a rectangle is one `fill_contiguous`
//!   call for all its visible pixels. Only pixels inside the target's bounding box are shaded.
//!   The spans of one shape share its visible area's plane set-up
//!   ([`PlaneMapping::span_plane`], [`crate::span::PlaneSetup`]): the texture's terms are
//!   transformed once a shape, not once a span (the same colours; an area whose texture
//!   coordinates would wrap is set up span by span).
//! - Display errors are returned as `D::Error`; no panic, no allocation, no floating point in
//!   the pixel path (the `f32` set-up conveniences of [`PlaneMapping`] only convert to fixed
//!   point, through `micromath`'s bit-exact `fract`,
//!   identically on every target).

use core::marker::PhantomData;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Dimensions, Point, Size};
use embedded_graphics::pixelcolor::{PixelColor, Rgb888};
use embedded_graphics::primitives::{
    Circle, Ellipse, PointsIter, Rectangle, RoundedRectangle, StyledDrawable, Triangle,
};
use embedded_graphics::Drawable;
use micromath::F32Ext;

use crate::color::Rgba8888;
use crate::format::TexPoint;
use crate::presets::CheckPlane;
use crate::render::{RenderError, RenderStats, Renderer, TriangleSource};
use crate::scene::math::{isqrt_u128, sin_cos, Angle};
use crate::sink::PixelSink;
use crate::span::{PlaneSetup, Span, SpanPlane};
use crate::texture::{Texture, TextureEvaluator};

/// Pixels shaded per span call (a row run longer than this is shaded in pieces of this length;
/// the buffer of [`RUN_CHUNK`] RGBA colours lives on the stack).
pub const RUN_CHUNK: usize = 128;

/// The display colour of a texture colour: through `Rgb888`, alpha dropped.
#[inline]
pub fn display_color<C: From<Rgb888>>(c: Rgba8888) -> C {
    C::from(Rgb888::new(c.r, c.g, c.b))
}

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

/// A texture evaluator shading the spans of one display rectangle through its plane's set-up
/// ([`PlaneMapping::span_plane`], [`TextureEvaluator::shade_plane`]) when it has one, span by
/// span otherwise: the same colours either way. With `W > 0` (feature `differences`) and a
/// rectangle at most `W` pixels wide, its runs are shaded with the filter widths from
/// differences instead ([`AreaShader::shade_differences`]).
struct AreaShader<'t, 'm, const T: usize, const N: usize, const W: usize> {
    ev: TextureEvaluator<'t, T, N>,
    mapping: &'m PlaneMapping,
    /// The plane's set-up and the rectangle's top-left pixel.
    plane: Option<(PlaneSetup<'t, T>, Point)>,
    /// The difference memory and the rectangle's top-left pixel (the widths from differences).
    #[cfg(feature = "differences")]
    diff: Option<(crate::texture::DifferenceMemory<W>, Point)>,
}

impl<'t, 'm, const T: usize, const N: usize, const W: usize> AreaShader<'t, 'm, T, N, W> {
    fn new(texture: &'t Texture<T, N>, mapping: &'m PlaneMapping, area: &Rectangle) -> Self {
        let ev = texture.evaluator();
        // The widths from differences for a filtered texture on a rectangle that fits the
        // memory (its runs never take the plane's set-up; an unfiltered texture needs no
        // widths).
        #[cfg(feature = "differences")]
        if W > 0
            && area.size.width as usize <= W
            && texture.stage().antialias() != crate::filter::Antialias::None
        {
            return AreaShader {
                ev,
                mapping,
                plane: None,
                diff: Some((crate::texture::DifferenceMemory::new(), area.top_left)),
            };
        }
        let plane = mapping
            .span_plane(area)
            .and_then(|p| ev.plane_setup(&p))
            .map(|s| (s, area.top_left));
        AreaShader {
            ev,
            mapping,
            plane,
            #[cfg(feature = "differences")]
            diff: None,
        }
    }

    /// With the widths from differences: shades the run `x..x + len` of row `y` (inside the
    /// rectangle) as one span, its pixel above from the row shaded before it (relative to the
    /// rectangle's top-left pixel: [`TextureEvaluator::shade_differences`]), handing `piece`
    /// its colours in pieces of at most [`RUN_CHUNK`] pixels with each piece's first column.
    /// `false` (nothing shaded) without a difference memory or outside the rectangle.
    #[cfg(feature = "differences")]
    fn shade_differences(
        &mut self,
        (x, y, len): (i32, i32, u16),
        mut piece: impl FnMut(i32, &[Rgba8888]),
    ) -> bool {
        let Some((mem, at)) = self.diff.as_mut() else {
            return false;
        };
        let (Ok(dx), Ok(dy)) = (
            u16::try_from(i64::from(x) - i64::from(at.x)),
            u16::try_from(i64::from(y) - i64::from(at.y)),
        ) else {
            return false;
        };
        let span = self.mapping.span(x, y, len);
        let mut rows = mem.rows_mut(crate::span::Faces::none());
        self.ev
            .differences_pieces::<Rgba8888, _, RUN_CHUNK>(&mut rows, dx, dy, &span, |off, px| {
                piece(x.saturating_add(i32::from(off)), px)
            })
    }

    /// Shades the `len` pixels of display row `y` from column `x` (inside the rectangle, or
    /// shaded span by span).
    fn shade(&mut self, x: i32, y: i32, len: u16, emit: impl FnMut(Rgba8888)) {
        if let Some((setup, at)) = &self.plane {
            let (dx, dy) = (
                u16::try_from(i64::from(x) - i64::from(at.x)),
                u16::try_from(i64::from(y) - i64::from(at.y)),
            );
            if let (Ok(dx), Ok(dy)) = (dx, dy) {
                if setup.plane().contains(dx, dy, len) {
                    self.ev.shade_plane(setup, dx, dy, len, emit);
                    return;
                }
            }
        }
        self.ev.shade(&self.mapping.span(x, y, len), emit);
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
fn f32_to_q16(x: f32) -> i32 {
    // Times 2^16 is exact below the f32 overflow; beyond it, +-inf saturates.
    let v = f32_to_nearest_i64(x * 65536.0);
    v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
}

/// `a k / 2^16`, saturating.
const fn mul_q16(a: i32, k: i32) -> i32 {
    let v = (a as i64 * k as i64) >> 16;
    if v > i32::MAX as i64 {
        i32::MAX
    } else if v < i32::MIN as i64 {
        i32::MIN
    } else {
        v as i32
    }
}

/// `a c / 2^30` rounded (`|c| <= 2^30`, so it fits).
const fn mul_q30(a: i32, c: i32) -> i32 {
    ((a as i64 * c as i64 + (1 << 29)) >> 30) as i32
}

/// A primitive style that fills a shape with a texture placed by a [`PlaneMapping`]. `C` is the
/// display colour (inferred from the draw target).
///
/// With `W > 0` (feature `differences`, `TextureStyle::with_differences`) a filtered texture
/// takes its filter widths from the differences of neighbouring values (the named approximate
/// mode of [`crate::texture::DifferenceSpans`]: exact values without their gradients, about
/// half the noise's cost), a memory of two rows of `W` pixels (`8 W` bytes) on the stack during
/// `draw`. Each row run of the shape is then one span (the pixel above from the run shaded
/// before it on the row above, rows counted from the visible part's top, tiles of
/// [`crate::texture::TILE_ROWS`] rows as `TextureEvaluator::shade_differences` takes them),
/// written in pieces of [`RUN_CHUNK`] pixels. A shape whose visible part is wider than `W`
/// pixels, or a texture without antialiasing, is shaded as without it (widths from the
/// gradients; none).
#[derive(Debug)]
pub struct TextureStyle<'t, C, const T: usize, const N: usize, const W: usize = 0> {
    texture: &'t Texture<T, N>,
    mapping: PlaneMapping,
    color: PhantomData<fn() -> C>,
}

impl<C, const T: usize, const N: usize, const W: usize> Clone for TextureStyle<'_, C, T, N, W> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C, const T: usize, const N: usize, const W: usize> Copy for TextureStyle<'_, C, T, N, W> {}

impl<'t, C, const T: usize, const N: usize> TextureStyle<'t, C, T, N> {
    /// Fills with `texture` placed by `mapping`.
    pub const fn new(texture: &'t Texture<T, N>, mapping: PlaneMapping) -> Self {
        TextureStyle {
            texture,
            mapping,
            color: PhantomData,
        }
    }
}

#[cfg(feature = "differences")]
impl<'t, C, const T: usize, const N: usize, const W: usize> TextureStyle<'t, C, T, N, W> {
    /// The same style with the filter widths from the differences of neighbouring values (see
    /// the type's documentation), shapes up to `W2` pixels wide.
    pub const fn with_differences<const W2: usize>(self) -> TextureStyle<'t, C, T, N, W2> {
        TextureStyle {
            texture: self.texture,
            mapping: self.mapping,
            color: PhantomData,
        }
    }
}

impl<'t, C, const T: usize, const N: usize, const W: usize> TextureStyle<'t, C, T, N, W> {
    /// The texture.
    pub const fn texture(&self) -> &'t Texture<T, N> {
        self.texture
    }

    /// The mapping.
    pub const fn mapping(&self) -> PlaneMapping {
        self.mapping
    }

    /// The same style with another mapping.
    pub const fn with_mapping(mut self, mapping: PlaneMapping) -> Self {
        self.mapping = mapping;
        self
    }
}

/// Shades a row run `x .. x + len` of row `y` and writes it with `fill_contiguous`, in pieces
/// of at most [`RUN_CHUNK`] pixels.
fn fill_run<D, const T: usize, const N: usize, const W: usize>(
    ev: &mut AreaShader<'_, '_, T, N, W>,
    (x, y, len): (i32, i32, u32),
    target: &mut D,
) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    // The widths from differences: the run as one span (runs are at most `W <= u16::MAX`
    // pixels there), its pieces written as they come, the first display error kept.
    #[cfg(feature = "differences")]
    if let Ok(n) = u16::try_from(len) {
        let mut result = Ok(());
        let done = ev.shade_differences((x, y, n), |x0, px| {
            if result.is_ok() {
                let area = Rectangle::new(Point::new(x0, y), Size::new(px.len() as u32, 1));
                result = target.fill_contiguous(&area, px.iter().map(|&c| display_color(c)));
            }
        });
        if done {
            return result;
        }
    }
    let mut buf = [Rgba8888::BLACK; RUN_CHUNK];
    let mut done = 0u32;
    while done < len {
        let n = (len - done).min(RUN_CHUNK as u32);
        let x0 = x.saturating_add(done as i32);
        let mut i = 0;
        ev.shade(x0, y, n as u16, |c| {
            if let Some(b) = buf.get_mut(i) {
                *b = c;
            }
            i += 1;
        });
        let area = Rectangle::new(Point::new(x0, y), Size::new(n, 1));
        let colors = buf.iter().take(n as usize).map(|&c| display_color(c));
        target.fill_contiguous(&area, colors)?;
        done += n;
    }
    Ok(())
}

/// The visible part `[x0, x1)` of a run on row `y`: `None` outside `clip`.
fn clip_run(clip: &Rectangle, y: i32, x0: i32, x1: i32) -> Option<(i32, i32, u32)> {
    let br = clip.bottom_right()?;
    if y < clip.top_left.y || y > br.y {
        return None;
    }
    let a = x0.max(clip.top_left.x);
    let b = x1.min(br.x.saturating_add(1));
    (a < b).then(|| (a, y, (b - a) as u32))
}

/// Fills the pixels of `points` (any order; runs of consecutive pixels of a row are shaded as
/// one span) with the style's texture.
fn fill_points<D, I, const T: usize, const N: usize, const W: usize>(
    points: I,
    bounds: Rectangle,
    style: &TextureStyle<'_, D::Color, T, N, W>,
    target: &mut D,
) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
    I: Iterator<Item = Point>,
{
    let clip = target.bounding_box();
    let mut ev =
        AreaShader::<T, N, W>::new(style.texture, &style.mapping, &bounds.intersection(&clip));
    // The open run: row, first column, one past the last column.
    let mut run: Option<(i32, i32, i32)> = None;
    for p in points {
        match run {
            Some((y, x0, x1)) if y == p.y && x1 == p.x && x1 < i32::MAX => {
                run = Some((y, x0, x1 + 1));
            }
            _ => {
                if let Some((y, x0, x1)) = run {
                    if let Some(r) = clip_run(&clip, y, x0, x1) {
                        fill_run(&mut ev, r, target)?;
                    }
                }
                run = Some((p.y, p.x, p.x.saturating_add(1)));
            }
        }
    }
    if let Some((y, x0, x1)) = run {
        if let Some(r) = clip_run(&clip, y, x0, x1) {
            fill_run(&mut ev, r, target)?;
        }
    }
    Ok(())
}

/// The colours of a rectangle's rows, shaded [`RUN_CHUNK`] pixels at a time (the iterator of
/// the rectangle's single `fill_contiguous` call).
struct RectColors<'e, 't, 'm, C, const T: usize, const N: usize> {
    ev: &'e mut AreaShader<'t, 'm, T, N, 0>,
    area: Rectangle,
    /// Next pixel to shade (relative to the area).
    x: u32,
    y: u32,
    buf: [Rgba8888; RUN_CHUNK],
    len: usize,
    pos: usize,
    color: PhantomData<fn() -> C>,
}

impl<C: From<Rgb888>, const T: usize, const N: usize> Iterator for RectColors<'_, '_, '_, C, T, N> {
    type Item = C;

    fn next(&mut self) -> Option<C> {
        if self.pos == self.len {
            if self.y >= self.area.size.height {
                return None;
            }
            let w = self.area.size.width;
            let n = (w - self.x).min(RUN_CHUNK as u32);
            let px = self.area.top_left.x.saturating_add(self.x as i32);
            let py = self.area.top_left.y.saturating_add(self.y as i32);
            let buf = &mut self.buf;
            let mut i = 0;
            self.ev.shade(px, py, n as u16, |c| {
                if let Some(b) = buf.get_mut(i) {
                    *b = c;
                }
                i += 1;
            });
            self.len = n as usize;
            self.pos = 0;
            self.x += n;
            if self.x >= w {
                self.x = 0;
                self.y += 1;
            }
        }
        let c = self.buf.get(self.pos).copied().unwrap_or(Rgba8888::BLACK);
        self.pos += 1;
        Some(display_color(c))
    }
}

impl<'t, C, const T: usize, const N: usize, const W: usize>
    StyledDrawable<TextureStyle<'t, C, T, N, W>> for Rectangle
where
    C: PixelColor + From<Rgb888>,
{
    type Color = C;
    type Output = ();

    /// One `fill_contiguous` call for the visible part of the rectangle (with the widths from
    /// differences, one a row run piece).
    fn draw_styled<D>(
        &self,
        style: &TextureStyle<'t, C, T, N, W>,
        target: &mut D,
    ) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let area = self.intersection(&target.bounding_box());
        if area.size.width == 0 || area.size.height == 0 {
            return Ok(());
        }
        // With the widths from differences, each visible row is one run (as a shape's runs).
        #[cfg(feature = "differences")]
        if W > 0 {
            let mut ev = AreaShader::<T, N, W>::new(style.texture, &style.mapping, &area);
            let (x, w) = (area.top_left.x, area.size.width);
            for dy in 0..area.size.height {
                let y = area.top_left.y.saturating_add(dy as i32);
                fill_run(&mut ev, (x, y, w), target)?;
            }
            return Ok(());
        }
        let mut ev = AreaShader::<T, N, 0>::new(style.texture, &style.mapping, &area);
        let colors = RectColors {
            ev: &mut ev,
            area,
            x: 0,
            y: 0,
            buf: [Rgba8888::BLACK; RUN_CHUNK],
            len: 0,
            pos: 0,
            color: PhantomData::<fn() -> C>,
        };
        target.fill_contiguous(&area, colors)
    }
}

/// `StyledDrawable<TextureStyle>` for shapes filled through their points.
macro_rules! textured_by_points {
    ($($shape:ty),*) => {$(
        impl<'t, C, const T: usize, const N: usize, const W: usize>
            StyledDrawable<TextureStyle<'t, C, T, N, W>> for $shape
        where
            C: PixelColor + From<Rgb888>,
        {
            type Color = C;
            type Output = ();

            fn draw_styled<D>(
                &self,
                style: &TextureStyle<'t, C, T, N, W>,
                target: &mut D,
            ) -> Result<(), D::Error>
            where
                D: DrawTarget<Color = C>,
            {
                fill_points(self.points(), self.bounding_box(), style, target)
            }
        }
    )*};
}

// Not `Sector`: its `points()` differ from its `PrimitiveStyle` fill by a few edge pixels in
// embedded-graphics 0.8, so a textured sector would not cover the filled one exactly.
textured_by_points!(Circle, Ellipse, Triangle, RoundedRectangle);

/// A pixel sink over a draw target that keeps the first display error (and writes nothing
/// after it).
struct TargetSink<'d, D: DrawTarget> {
    target: &'d mut D,
    error: Option<D::Error>,
}

impl<D> PixelSink for TargetSink<'_, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    fn write_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        if self.error.is_some() {
            return;
        }
        let n = colors.len().min(usize::from(u16::MAX)) as u32;
        let area = Rectangle::new(Point::new(i32::from(x), i32::from(y)), Size::new(n, 1));
        let pixels = colors.iter().map(|&c| display_color(c));
        if let Err(e) = self.target.fill_contiguous(&area, pixels) {
            self.error = Some(e);
        }
    }

    fn fill_span(&mut self, x: u16, y: u16, len: u16, color: Rgba8888) {
        if self.error.is_some() {
            return;
        }
        let area = Rectangle::new(
            Point::new(i32::from(x), i32::from(y)),
            Size::new(u32::from(len), 1),
        );
        if let Err(e) = self.target.fill_solid(&area, display_color(color)) {
            self.error = Some(e);
        }
    }
}

/// A scene (any [`TriangleSource`]: a [`crate::scene::Scene`] of textured mesh objects) with its
/// textures, drawn through the [`Renderer`] as one `Drawable`.
///
/// Scenes without depth or blending stream their segments straight to the display; the others
/// render in bands through a band and a depth buffer of `BAND` pixels each on the stack
/// (`BAND * 6` bytes; `BAND / width` rows per band, at least one row). `draw` returns
/// `Err(D::Error)` for a display error and `Ok` with the renderer's result (its counters, or
/// why the scene could not be rendered: [`RenderError`]).
///
/// With `W > 0` (feature `differences`, `TexturedScene::with_differences`) the filter widths
/// come from the differences of neighbouring values (`Renderer::with_differences`, a named
/// approximate mode), the memory of rows of `W` pixels and a face cache of [`DRAW_FACES`]
/// entries on the stack during `draw` (`8 W + 32 DRAW_FACES` bytes and the cache's lanes); a
/// scene wider than `W` pixels is refused ([`RenderError::MemoryTooNarrow`]). Its bands are
/// then whole tiles of `texture::TILE_ROWS` rows, so the image is the streamed one (and
/// `texsim render --widths differences`'s) whenever `BAND` holds that many rows.
#[derive(Debug)]
pub struct TexturedScene<
    'a,
    S,
    C,
    const T: usize,
    const N: usize,
    const BAND: usize = 2048,
    const W: usize = 0,
> {
    scene: &'a S,
    textures: &'a [Texture<T, N>],
    color: PhantomData<fn() -> C>,
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize> Clone
    for TexturedScene<'_, S, C, T, N, BAND, W>
{
    fn clone(&self) -> Self {
        *self
    }
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize> Copy
    for TexturedScene<'_, S, C, T, N, BAND, W>
{
}

/// Face-cache entries of a [`TexturedScene`] drawn with the widths from differences (32 bytes
/// each, on the stack during `draw`; the values are the same with any number).
pub const DRAW_FACES: usize = 64;

impl<'a, S, C, const T: usize, const N: usize, const BAND: usize>
    TexturedScene<'a, S, C, T, N, BAND>
{
    /// `scene` with `textures` (the object's texture slot `i` is `textures[i]`).
    pub const fn new(scene: &'a S, textures: &'a [Texture<T, N>]) -> Self {
        TexturedScene {
            scene,
            textures,
            color: PhantomData,
        }
    }
}

#[cfg(feature = "differences")]
impl<'a, S, C, const T: usize, const N: usize, const BAND: usize, const W: usize>
    TexturedScene<'a, S, C, T, N, BAND, W>
{
    /// The same scene drawn with the filter widths from the differences of neighbouring values
    /// (see the type's documentation), rows of up to `W2` pixels (at least the scene's width).
    pub const fn with_differences<const W2: usize>(
        self,
    ) -> TexturedScene<'a, S, C, T, N, BAND, W2> {
        TexturedScene {
            scene: self.scene,
            textures: self.textures,
            color: PhantomData,
        }
    }
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize> Drawable
    for TexturedScene<'_, S, C, T, N, BAND, W>
where
    S: TriangleSource,
    C: PixelColor + From<Rgb888>,
{
    type Color = C;
    type Output = Result<RenderStats, RenderError>;

    fn draw<D>(&self, target: &mut D) -> Result<Self::Output, D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        #[cfg(feature = "differences")]
        if W > 0 {
            let mut mem = crate::texture::DifferenceMemory::<W>::new();
            let mut faces = crate::span::FaceCache::<DRAW_FACES, T>::new();
            let renderer = Renderer::new(self.textures).with_differences(&mut mem, &mut faces);
            return self.draw_with(&renderer, target);
        }
        self.draw_with(&Renderer::new(self.textures), target)
    }
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize>
    TexturedScene<'_, S, C, T, N, BAND, W>
where
    S: TriangleSource,
    C: PixelColor + From<Rgb888>,
{
    /// Draws the scene through `renderer`.
    fn draw_with<D>(
        &self,
        renderer: &Renderer<'_, T, N>,
        target: &mut D,
    ) -> Result<Result<RenderStats, RenderError>, D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let mut sink = TargetSink {
            target,
            error: None,
        };
        let result = match renderer.needs_bands(self.scene) {
            Err(e) => Err(e),
            Ok(false) => renderer.render_streamed(self.scene, &mut sink),
            Ok(true) => {
                let mut band = [Rgba8888::BLACK; BAND];
                let mut depth = [0u16; BAND];
                let w = usize::from(self.scene.size().0.max(1));
                let mut rows = (BAND / w).min(usize::from(u16::MAX)) as u16;
                // Bands of whole tiles with the widths from differences: the streamed image.
                if W > 0 && rows >= crate::texture::TILE_ROWS {
                    rows -= rows % crate::texture::TILE_ROWS;
                }
                renderer.render_banded(self.scene, &mut band, &mut depth, rows, &mut sink)
            }
        };
        match sink.error {
            Some(e) => Err(e),
            None => Ok(result),
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use embedded_graphics::mock_display::MockDisplay;
    use embedded_graphics::pixelcolor::{BinaryColor, Gray8, Rgb565};
    use embedded_graphics::prelude::*;
    use embedded_graphics::primitives::PrimitiveStyle;

    use super::*;
    use crate::filter::{Antialias, ColorStage, GradientNorm};
    use crate::format::TexValue;
    use crate::model::TextureModel;
    use crate::quadric::Quadric;
    use crate::ready::{Material, PresetName};
    use crate::scene::math::Angle;
    use crate::span::EvalMode;
    use crate::table::{ColorTable, TableLookup, TableWrap};
    use crate::texture::Shader;

    /// `f = s` (the quadric `s`), two-entry clamp table: black for `s < 1/2`, white after.
    fn split_texture() -> Texture<8, 2> {
        use crate::format::QuadricCoeff;
        let z = QuadricCoeff::ZERO;
        let q = Quadric::linear(QuadricCoeff::ONE, z, z, z);
        let model = TextureModel::new(q, TableWrap::Clamp);
        let table = ColorTable::from_entries([Rgba8888::BLACK, Rgba8888::WHITE]).unwrap();
        let stage = ColorStage::new(
            table,
            TableWrap::Clamp,
            TableLookup::Nearest,
            Antialias::None,
        )
        .unwrap();
        Texture::new(
            Shader::Model(model),
            stage,
            GradientNorm::L2,
            EvalMode::Auto,
        )
    }

    #[test]
    fn rgb565_conversion_is_texcores() {
        for v in 0..=255u8 {
            let c = Rgba8888::new(v, v, v, 255);
            let eg: Rgb565 = display_color(c);
            let tc = c.to_rgb565();
            let eg_bits = embedded_graphics::pixelcolor::raw::RawU16::from(eg).into_inner();
            assert_eq!(eg_bits, tc.to_bits(), "channel value {v}");
            let c = Rgba8888::new(v, 255 - v, v / 3, 0);
            let eg: Rgb565 = display_color(c);
            let eg_bits = embedded_graphics::pixelcolor::raw::RawU16::from(eg).into_inner();
            assert_eq!(eg_bits, c.to_rgb565().to_bits());
        }
    }

    /// Pixel art: a circle and a rectangle split black/white at `s = 1/2` (8 pixels per unit:
    /// the edge between columns 3 and 4 of the anchor).
    #[test]
    fn mock_display_pixel_art() {
        let tex = split_texture();
        let style = TextureStyle::new(&tex, PlaneMapping::scaled(8));
        let mut display = MockDisplay::<BinaryColor>::new();
        Rectangle::new(Point::new(0, 0), Size::new(8, 3))
            .into_styled(style)
            .draw(&mut display)
            .unwrap();
        Circle::new(Point::new(1, 4), 6)
            .into_styled(style)
            .draw(&mut display)
            .unwrap();
        display.assert_pattern(&[
            "....####", //
            "....####", //
            "....####", //
            "        ", //
            "  ..##  ", //
            " ...### ", //
            " ...### ", //
            " ...### ", //
            " ...### ", //
            "  ..##  ", //
        ]);
        // Moving the anchor moves the texture with the shape.
        let mut display = MockDisplay::<BinaryColor>::new();
        Rectangle::new(Point::new(2, 0), Size::new(8, 1))
            .into_styled(TextureStyle::new(
                &tex,
                PlaneMapping::scaled(8).at(Point::new(2, 0)),
            ))
            .draw(&mut display)
            .unwrap();
        display.assert_pattern(&["  ....####"]);
    }

    /// The textured shapes cover exactly the pixels of a `PrimitiveStyle` fill.
    #[test]
    fn shapes_cover_the_filled_pixels() {
        let tex = split_texture();
        let style = TextureStyle::new(&tex, PlaneMapping::scaled(1));
        let check = |draw_tex: &dyn Fn(&mut MockDisplay<BinaryColor>),
                     draw_fill: &dyn Fn(&mut MockDisplay<BinaryColor>)| {
            let mut a = MockDisplay::<BinaryColor>::new();
            draw_tex(&mut a);
            let mut b = MockDisplay::<BinaryColor>::new();
            draw_fill(&mut b);
            // Scale 1 pixel per unit puts every pixel at s >= 1/2: all white (On).
            assert_eq!(a, b);
        };
        let fill = PrimitiveStyle::with_fill(BinaryColor::On);
        let tri = Triangle::new(Point::new(1, 1), Point::new(30, 8), Point::new(9, 40));
        check(&|d| tri.into_styled(style).draw(d).unwrap(), &|d| {
            tri.into_styled(fill).draw(d).unwrap()
        });
        let e = Ellipse::new(Point::new(3, 2), Size::new(40, 17));
        check(&|d| e.into_styled(style).draw(d).unwrap(), &|d| {
            e.into_styled(fill).draw(d).unwrap()
        });
        let r = RoundedRectangle::with_equal_corners(
            Rectangle::new(Point::new(2, 2), Size::new(30, 20)),
            Size::new(6, 6),
        );
        check(&|d| r.into_styled(style).draw(d).unwrap(), &|d| {
            r.into_styled(fill).draw(d).unwrap()
        });
        // Partly off the display (negative coordinates and past 64): clipped, no error.
        let c = Circle::new(Point::new(-10, 40), 40);
        let mut a = MockDisplay::<BinaryColor>::new();
        c.into_styled(style).draw(&mut a).unwrap();
        let mut b = MockDisplay::<BinaryColor>::new();
        b.set_allow_out_of_bounds_drawing(true);
        c.into_styled(fill).draw(&mut b).unwrap();
        assert_eq!(a, b);
    }

    /// The colours are the evaluator's for the same spans, in every colour type; a rectangle
    /// wider than a chunk equals its rows shaded as whole spans.
    #[test]
    fn colours_are_the_texture_spans() {
        let marble = Material::preset(PresetName::Marble)
            .texture::<256>(Antialias::None)
            .unwrap();
        let mapping = PlaneMapping::scaled(40)
            .rotated(Angle::from_degrees(30))
            .at(Point::new(3, 1));
        let (w, h) = (60u32, 50u32);
        let mut want = Vec::new();
        for y in 0..h as i32 {
            marble
                .evaluator()
                .shade(&mapping.span(0, y, w as u16), |c| want.push(c));
        }
        let mut d = MockDisplay::<Rgb565>::new();
        Rectangle::new(Point::zero(), Size::new(w, h))
            .into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut d)
            .unwrap();
        let mut g = MockDisplay::<Gray8>::new();
        Circle::new(Point::zero(), 50)
            .into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut g)
            .unwrap();
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                let c = want[(y as u32 * w + x as u32) as usize];
                assert_eq!(d.get_pixel(Point::new(x, y)), Some(display_color(c)));
                if let Some(gc) = g.get_pixel(Point::new(x, y)) {
                    assert_eq!(gc, display_color::<Gray8>(c));
                }
            }
        }
    }

    /// Shapes drawn through their area's plane set-up equal their rows shaded span by span,
    /// also where the mapping's coordinates wrap inside the area (no plane: the spans are set
    /// up one by one) or come within a pixel of wrapping (a plane whose origin has wrapped).
    #[cfg(feature = "csat")]
    #[test]
    fn plane_set_up_areas_equal_their_spans() {
        let marble = Material::preset(PresetName::Marble)
            .texture::<256>(Antialias::Csat)
            .unwrap();
        // 40 pixels a texture unit: about 1600 raw units a pixel.
        let base = PlaneMapping::scaled(40).rotated(Angle::from_degrees(10));
        let (w, h) = (40i32, 30i32);
        for (origin, anchor, plane) in [
            ([0, 0, 0], 2, true),
            ([i32::MAX - 70_000, -(1 << 20), 7], 2, true),
            // Every pixel of the area past the wrap: the plane's origin has wrapped.
            ([i32::MAX - 100_000, 0, 0], -100, true),
            ([i32::MAX - 30_000, 0, 0], 2, false),
            ([0, i32::MAX - 10_000, 0], 2, false),
        ] {
            let mapping = base.with_origin(origin).at(Point::new(anchor, 3));
            let area = Rectangle::new(Point::zero(), Size::new(w as u32, h as u32));
            assert_eq!(mapping.span_plane(&area).is_some(), plane, "{origin:?}");
            let mut want = Vec::new();
            for y in 0..h {
                marble
                    .evaluator()
                    .shade(&mapping.span(0, y, w as u16), |c| want.push(c));
            }
            let mut d = MockDisplay::<Rgb888>::new();
            area.into_styled(TextureStyle::new(&marble, mapping))
                .draw(&mut d)
                .unwrap();
            let mut e = MockDisplay::<Rgb888>::new();
            Circle::new(Point::new(1, 0), 29)
                .into_styled(TextureStyle::new(&marble, mapping))
                .draw(&mut e)
                .unwrap();
            for y in 0..h {
                for x in 0..w {
                    let c = display_color(want[(y * w + x) as usize]);
                    assert_eq!(d.get_pixel(Point::new(x, y)), Some(c), "{origin:?}");
                    if let Some(ec) = e.get_pixel(Point::new(x, y)) {
                        assert_eq!(ec, c, "{origin:?} {x} {y}");
                    }
                }
            }
        }
    }

    /// The widths from differences (`TextureStyle::with_differences`): a rectangle's and a
    /// circle's pixels are their row runs shaded by `TextureEvaluator::shade_differences`
    /// through one memory, in row order, rows counted from the visible part's top-left (a
    /// rectangle partly off the display too); the same pixels as the exact style, and colours
    /// near its; a shape wider than `W` and an unfiltered texture are drawn as without it.
    #[cfg(all(feature = "differences", feature = "csat"))]
    #[test]
    fn difference_styles_shade_their_runs() {
        use std::collections::BTreeMap;
        let marble = Material::preset(PresetName::Marble)
            .texture::<256>(Antialias::Csat)
            .unwrap();
        let mapping = PlaneMapping::scaled(24)
            .rotated(Angle::from_degrees(20))
            .at(Point::new(3, 1));
        let exact = TextureStyle::new(&marble, mapping);
        let diff = exact.with_differences::<64>();
        // The reference: each row run of `points` (row order) through one memory.
        let reference = |points: &[Point], top_left: Point| {
            let mut mem = crate::texture::DifferenceMemory::<64>::new();
            let mut ev = marble.evaluator();
            let mut out = BTreeMap::new();
            let mut i = 0;
            while i < points.len() {
                let (y, x0) = (points[i].y, points[i].x);
                let mut n = 1;
                while points.get(i + n) == Some(&Point::new(x0 + n as i32, y)) {
                    n += 1;
                }
                let span = mapping.span(x0, y, n as u16);
                let (dx, dy) = ((x0 - top_left.x) as u16, (y - top_left.y) as u16);
                let mut x = x0;
                assert!(ev.shade_differences(&mut mem, dx, dy, &span, |c| {
                    out.insert((x, y), display_color::<Rgb888>(c));
                    x += 1;
                }));
                i += n;
            }
            out
        };
        let drawn = |d: &MockDisplay<Rgb888>| {
            let mut m = BTreeMap::new();
            for y in 0..64 {
                for x in 0..64 {
                    if let Some(c) = d.get_pixel(Point::new(x, y)) {
                        m.insert((x, y), c);
                    }
                }
            }
            m
        };
        let rect = Rectangle::new(Point::new(-7, 5), Size::new(50, 40));
        let circle = Circle::new(Point::new(10, 12), 45);
        let visible = |pts: Vec<Point>| -> Vec<Point> {
            pts.into_iter()
                .filter(|p| (0..64).contains(&p.x) && (0..64).contains(&p.y))
                .collect()
        };
        let mut close = (0usize, 0usize);
        let mut shapes = 0;
        for (points, top_left) in [
            (visible(rect.points().collect()), Point::new(0, 5)),
            (
                visible(circle.points().collect()),
                circle.bounding_box().top_left,
            ),
        ] {
            let (mut d, mut e) = (MockDisplay::<Rgb888>::new(), MockDisplay::<Rgb888>::new());
            if shapes == 0 {
                rect.into_styled(diff).draw(&mut d).unwrap();
                rect.into_styled(exact).draw(&mut e).unwrap();
            } else {
                circle.into_styled(diff).draw(&mut d).unwrap();
                circle.into_styled(exact).draw(&mut e).unwrap();
            }
            shapes += 1;
            let (got, want, ex) = (drawn(&d), reference(&points, top_left), drawn(&e));
            assert_eq!(got, want, "shape {shapes}");
            assert!(
                got.keys().eq(ex.keys()),
                "shape {shapes}: the exact style's pixels"
            );
            for (k, c) in &got {
                let x = ex[k];
                let most = c
                    .r()
                    .abs_diff(x.r())
                    .max(c.g().abs_diff(x.g()))
                    .max(c.b().abs_diff(x.b()));
                close.0 += usize::from(most <= 8);
                close.1 += 1;
            }
        }
        // Near the exact widths' colours: 95% of the pixels within 8 steps in every channel.
        // (3282 of 3317 when this was written.)
        assert!(close.0 * 100 >= close.1 * 95, "{close:?}");
        // Wider than the memory, and unfiltered: as without the differences.
        let narrow = exact.with_differences::<32>();
        let (mut a, mut b) = (MockDisplay::<Rgb888>::new(), MockDisplay::<Rgb888>::new());
        rect.into_styled(narrow).draw(&mut a).unwrap();
        rect.into_styled(exact).draw(&mut b).unwrap();
        assert_eq!(drawn(&a), drawn(&b));
        let split = split_texture();
        let (mut a, mut b) = (MockDisplay::<Rgb888>::new(), MockDisplay::<Rgb888>::new());
        let plain = TextureStyle::new(&split, mapping);
        circle
            .into_styled(plain.with_differences::<64>())
            .draw(&mut a)
            .unwrap();
        circle.into_styled(plain).draw(&mut b).unwrap();
        assert_eq!(drawn(&a), drawn(&b));
    }

    /// A 300 x 3 frame (rows longer than [`RUN_CHUNK`]).
    #[cfg(feature = "csat")]
    struct Wide(Vec<Option<Rgb888>>);

    #[cfg(feature = "csat")]
    impl Dimensions for Wide {
        fn bounding_box(&self) -> Rectangle {
            Rectangle::new(Point::zero(), Size::new(300, 3))
        }
    }

    #[cfg(feature = "csat")]
    impl DrawTarget for Wide {
        type Color = Rgb888;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
            &mut self,
            px: I,
        ) -> Result<(), Self::Error> {
            for Pixel(p, c) in px {
                if (0..300).contains(&p.x) && (0..3).contains(&p.y) {
                    self.0[(p.y * 300 + p.x) as usize] = Some(c);
                }
            }
            Ok(())
        }
    }

    /// Rows longer than a chunk, shaded in pieces (the rectangle's iterator and a circle's
    /// runs), equal whole-row spans.
    #[cfg(feature = "csat")]
    #[test]
    fn chunked_rows_equal_whole_spans() {
        let marble = Material::preset(PresetName::Marble)
            .texture::<256>(Antialias::Csat)
            .unwrap();
        let mapping = PlaneMapping::scaled(50)
            .rotated(Angle::from_degrees(-20))
            .at(Point::new(150, -1));
        let mut want = Vec::new();
        for y in 0..3 {
            marble.evaluator().shade(&mapping.span(0, y, 300), |c| {
                want.push(Some(display_color(c)))
            });
        }
        let mut frame = Wide(std::vec![None; 900]);
        Rectangle::new(Point::new(-5, 0), Size::new(400, 3))
            .into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut frame)
            .unwrap();
        assert_eq!(frame.0, want);
        let mut frame = Wide(std::vec![None; 900]);
        Ellipse::new(Point::new(-20, -40), Size::new(340, 82))
            .into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut frame)
            .unwrap();
        assert_eq!(frame.0[300..600], want[300..600]);
    }

    #[test]
    fn f32_set_up_conversion_rounds_to_nearest() {
        // Against f64's round (ties away from zero), which is exact for every f32.
        let mut x = 0x9E37_79B9u32;
        let mut values = std::vec![0.5f32, -0.5, 1.5, -2.5, 0.49999997, 8388609.0, -8388609.0];
        values.extend([1.0e30, -1.0e30, f32::MAX, f32::MIN, f32::INFINITY, 3.0e9]);
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let v = f32::from_bits(x);
            if v.is_finite() {
                values.push(v);
            }
        }
        for v in values {
            let want = (v as f64).round();
            let want = want.clamp(i64::MIN as f64, i64::MAX as f64) as i64;
            assert_eq!(f32_to_nearest_i64(v), want, "{v:e}");
        }
        assert_eq!(f32_to_nearest_i64(f32::NAN), 0);
        assert_eq!(f32_to_q16(1.0e10), i32::MAX);
        assert_eq!(f32_to_q16(-1.0e10), i32::MIN);
        assert_eq!(f32_to_q16(1.0 / 131072.0), 1, "a tie rounds away from zero");
    }

    #[test]
    fn mapping_set_up() {
        let m = PlaneMapping::scaled(256);
        assert_eq!(m.plane().step_x, [256, 0, 0]);
        let q = m.rotated(Angle::QUARTER);
        assert_eq!(q.plane().step_x, [0, 256, 0]);
        assert_eq!(q.plane().step_y, [-256, 0, 0]);
        assert_eq!(m.rotated_turns(0.25), q);
        assert_eq!(m.rotated_turns(1.25), q);
        assert_eq!(m.zoomed(2.0).plane().step_x, [512, 0, 0]);
        // The (s, t) plane's normal is r: the phase moves r.
        assert_eq!(m.phased(0.5).plane().origin, [0, 0, 65536]);
        assert_eq!(m.rotated_turns(-0.75), q);
        assert_eq!(m.rotated_turns(f32::NAN), m);
        assert_eq!(m.rotated_turns(3.0e9), m, "whole turns only");
        // 0.3 in 16.16 is 19660.8: rounded to 19661, not truncated to 19660.
        let one = PlaneMapping::scaled(1);
        assert_eq!(one.zoomed(0.3).plane().step_x, [19661, 0, 0]);
        assert_eq!(m.zoomed(f32::INFINITY), m.with_zoom(i32::MAX));
        assert_eq!(m.phased(-0.25).plane().origin, [0, 0, 16384]);
        assert_eq!(m.phased(f32::NAN), m);
        assert_eq!(m.with_phase(-32768).plane().origin, [0, 0, 0]);
        let sp = m.at(Point::new(10, 0)).span(10, 0, 4);
        assert_eq!(sp.s0, TexPoint::from_bits(128, 128, 32768));
        let _ = TexValue::ZERO;
    }

    /// A display error stops drawing and comes back as `D::Error`.
    #[test]
    fn display_errors_propagate() {
        struct Failing;
        impl Dimensions for Failing {
            fn bounding_box(&self) -> Rectangle {
                Rectangle::new(Point::zero(), Size::new(16, 16))
            }
        }
        impl DrawTarget for Failing {
            type Color = Rgb565;
            type Error = &'static str;
            fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
                &mut self,
                _: I,
            ) -> Result<(), &'static str> {
                Err("bus error")
            }
        }
        let tex = split_texture();
        let style = TextureStyle::new(&tex, PlaneMapping::scaled(8));
        let r = Rectangle::new(Point::zero(), Size::new(4, 4)).into_styled(style);
        assert_eq!(r.draw(&mut Failing), Err("bus error"));
        let c = Circle::new(Point::zero(), 5).into_styled(style);
        assert_eq!(c.draw(&mut Failing), Err("bus error"));
        let scene = crate::scene::by_name("zoneplate").unwrap();
        let ts: TexturedScene<'_, _, Rgb565, 8, 2> =
            TexturedScene::new(&scene, core::slice::from_ref(&tex));
        assert_eq!(ts.draw(&mut Failing), Err("bus error"));
    }

    /// A scene drawn as a `Drawable` equals the renderer's buffer render.
    #[test]
    fn textured_scene_equals_buffer_render() {
        use crate::sink::RgbaBuffer;
        for name in ["zoneplate", "marble"] {
            let scene = crate::scene::by_name(name).unwrap();
            let scene = scene.at_frame(scene.still());
            let textures: Vec<Texture<8, 256>> = scene
                .slots
                .iter()
                .map(|s| {
                    Material::by_name(s.material, crate::hash::HashKind::default())
                        .unwrap()
                        .with_keys(
                            s.keys.unwrap_or(
                                Material::by_name(s.material, crate::hash::HashKind::default())
                                    .unwrap()
                                    .keys(),
                            ),
                        )
                        .texture(Antialias::None)
                        .unwrap()
                })
                .collect();
            let (w, h) = scene.size();
            let mut img = std::vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
            let mut buf = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
            let r = Renderer::new(&textures);
            let mut band = std::vec![Rgba8888::BLACK; usize::from(w) * 8];
            let mut depth = std::vec![0u16; usize::from(w) * 8];
            r.render_banded(&scene, &mut band, &mut depth, 8, &mut buf)
                .unwrap();
            let mut d = MockDisplay::<Rgb888>::new();
            d.set_allow_overdraw(true);
            d.set_allow_out_of_bounds_drawing(true);
            // MockDisplay is 64 x 64: compare its part of the frame.
            let ts: TexturedScene<'_, _, Rgb888, 8, 256> = TexturedScene::new(&scene, &textures);
            ts.draw(&mut d).unwrap().unwrap();
            for y in 0..64 {
                for x in 0..64 {
                    let c = img[y * usize::from(w) + x];
                    assert_eq!(
                        d.get_pixel(Point::new(x as i32, y as i32)),
                        Some(Rgb888::new(c.r, c.g, c.b)),
                        "{name} ({x}, {y})"
                    );
                }
            }
        }
    }

    /// With the widths from differences a scene drawn as a `Drawable` equals the renderer's
    /// streamed render with a memory of its own (bands of 12 rows' room drawn as bands of 8),
    /// differs from the gradients' frame, and a memory narrower than the scene is refused.
    #[cfg(all(feature = "differences", feature = "csat"))]
    #[test]
    fn textured_scene_with_differences_equals_the_renderer() {
        use crate::sink::RgbaBuffer;
        let scene = crate::scene::by_name("marble").unwrap();
        let scene = scene.at_frame(scene.still());
        let textures: Vec<Texture<8, 256>> = scene
            .slots
            .iter()
            .map(|s| {
                let m = Material::by_name(s.material, crate::hash::HashKind::default()).unwrap();
                let keys = s.keys.unwrap_or(m.keys());
                m.with_keys(keys).texture(Antialias::Csat).unwrap()
            })
            .collect();
        let (w, h) = scene.size();
        let mut img = std::vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
        let mut buf = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
        let mut mem = crate::texture::DifferenceMemory::<320>::new();
        let mut faces = crate::span::FaceCache::<16, 8>::new();
        let r = Renderer::new(&textures).with_differences(&mut mem, &mut faces);
        let mut band = std::vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
        let mut depth = std::vec![0u16; usize::from(w) * usize::from(h)];
        r.render_banded(&scene, &mut band, &mut depth, h, &mut buf)
            .unwrap();
        /// A whole frame as a display.
        struct Frame(u32, Vec<Rgb888>);
        impl OriginDimensions for Frame {
            fn size(&self) -> Size {
                Size::new(self.0, self.1.len() as u32 / self.0)
            }
        }
        impl DrawTarget for Frame {
            type Color = Rgb888;
            type Error = core::convert::Infallible;
            fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
                &mut self,
                pixels: I,
            ) -> Result<(), Self::Error> {
                for Pixel(p, c) in pixels {
                    let i = p.y as usize * self.0 as usize + p.x as usize;
                    if let Some(px) = self.1.get_mut(i) {
                        *px = c;
                    }
                }
                Ok(())
            }
        }
        let n = usize::from(w) * usize::from(h);
        let mut d = Frame(u32::from(w), std::vec![Rgb888::BLACK; n]);
        let ts: TexturedScene<'_, _, Rgb888, 8, 256, { 320 * 12 }> =
            TexturedScene::new(&scene, &textures);
        ts.with_differences::<320>().draw(&mut d).unwrap().unwrap();
        let mut plain = Frame(u32::from(w), std::vec![Rgb888::BLACK; n]);
        ts.draw(&mut plain).unwrap().unwrap();
        let want: Vec<Rgb888> = img.iter().map(|c| Rgb888::new(c.r, c.g, c.b)).collect();
        assert!(d.1 == want);
        let differ = d.1.iter().zip(&plain.1).filter(|(a, b)| a != b).count();
        assert!(differ > 1000, "{differ}");
        let mut d = MockDisplay::<Rgb888>::new();
        d.set_allow_out_of_bounds_drawing(true);
        let ts: TexturedScene<'_, _, Rgb888, 8, 256> = TexturedScene::new(&scene, &textures);
        assert_eq!(
            ts.with_differences::<64>()
                .draw(&mut d)
                .unwrap()
                .unwrap_err(),
            RenderError::MemoryTooNarrow {
                width: w,
                memory: 64
            }
        );
    }
}
