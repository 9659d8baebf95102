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

mod mapping;
mod scene;
mod style;

pub use mapping::{f32_to_nearest_i64, PlaneMapping};
pub use scene::{TexturedScene, DRAW_FACES};
pub use style::TextureStyle;

#[cfg(test)]
mod tests;
