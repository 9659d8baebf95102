//! How a walk over the scene lights its triangles, as a type ([`WalkLight`]): the unlit walk
//! compiles no lighting code at all, the lit walk (feature `lighting`) computes a triangle's
//! light plane once, at its first segment, and multiplies each chunk of pixels by it.

use super::*;

/// How a walk over the scene lights its triangles, as a type, so that each walk's drawing is
/// compiled for its own case: the unlit walk's [`Unlit`] has no value and no code (no light
/// plane, no option to test, no lighting stage: the same code as a build without the `lighting`
/// feature); the lit walk's vertex-light function (feature `lighting`) computes a triangle's
/// light plane at its first segment (a triangle with none in the band costs nothing) and
/// multiplies each chunk of its pixels by it.
pub(super) trait WalkLight: Copy {
    /// Whether the walk lights its pixels (counted in [`RenderStats::lit_pixels`]).
    const LIT: bool;
    /// Where a triangle's light plane is kept between its segments.
    type Plane: Default;
    /// The light of one segment of the triangle.
    type Segment<'p>: SegmentLight
    where
        Self: 'p;
    /// The light of triangle `tri`'s segments, computed into `plane` at the first one.
    fn segment<'p>(self, plane: &'p mut Self::Plane, tri: &[ScreenVertex; 3]) -> Self::Segment<'p>;
}

/// The light of one segment's pixels (see [`WalkLight`]).
pub(super) trait SegmentLight: Copy {
    /// Whether [`SegmentLight::light_span`] changes the pixels (an unlit segment's does not).
    const LIGHTS: bool = true;

    /// The lighting stage: multiplies the pixels `x..` of row `y` by the light.
    fn light_span(self, x: u16, y: u16, px: &mut [Rgba8888]);
}

/// No light: the unlit walk (and every walk of a build without the `lighting` feature).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Unlit;

impl WalkLight for Unlit {
    const LIT: bool = false;
    type Plane = ();
    type Segment<'p> = Unlit;

    #[inline(always)]
    fn segment(self, _: &mut (), _: &[ScreenVertex; 3]) -> Unlit {
        Unlit
    }
}

impl SegmentLight for Unlit {
    const LIGHTS: bool = false;

    #[inline(always)]
    fn light_span(self, _: u16, _: u16, _: &mut [Rgba8888]) {}
}

/// The lights of a triangle's three vertices (`Q16.16` per channel).
#[cfg(feature = "lighting")]
pub(super) type VertexLights = [crate::light::LightRgb; 3];

/// The lit walk: the scene's function giving the triangle's vertex lights
/// ([`TriangleSource::for_each_lit_triangle_grouped`]).
#[cfg(feature = "lighting")]
impl WalkLight for &dyn Fn() -> VertexLights {
    const LIT: bool = true;
    type Plane = Option<crate::gouraud::TriangleLight>;
    type Segment<'p>
        = &'p crate::gouraud::TriangleLight
    where
        Self: 'p;

    #[inline(always)]
    fn segment<'p>(
        self,
        plane: &'p mut Self::Plane,
        tri: &[ScreenVertex; 3],
    ) -> &'p crate::gouraud::TriangleLight {
        plane.get_or_insert_with(|| crate::gouraud::TriangleLight::new(tri, &self()))
    }
}

#[cfg(feature = "lighting")]
impl SegmentLight for &crate::gouraud::TriangleLight {
    #[inline(always)]
    fn light_span(self, x: u16, y: u16, px: &mut [Rgba8888]) {
        self.modulate_span(x, y, px);
    }
}
