//! Drawing one triangle: straight to the sink ([`StreamDraw`], scenes with neither depth nor
//! blending) or into a band with its depth test and blending ([`BandDraw`]), each segment shaded
//! by [`shade_segment`]. A walk without light compiles the same code whether the lit walk exists
//! or not.

use super::band::Band;
use super::segment::shade_segment;
#[cfg(feature = "differences")]
use super::segment::shade_segment_into;
use super::*;

/// What the streamed renderer draws a triangle with ([`Renderer::render_streamed`]).
pub(super) struct StreamDraw<'a, 't, S, P, const T: usize, const N: usize> {
    pub(super) scene: &'a S,
    pub(super) slots: Slots<'t, T, N>,
    pub(super) output: Output,
    pub(super) raster: Rasterizer,
    pub(super) sink: &'a mut P,
    /// Pixels lit.
    pub(super) lit: u64,
}

impl<S: TriangleSource, P: PixelSink, const T: usize, const N: usize>
    StreamDraw<'_, '_, S, P, T, N>
{
    /// Draws triangle `tri` of object `obj` straight to the sink, lit by `light`.
    #[inline(always)]
    pub(super) fn triangle<W: WalkLight>(&mut self, obj: usize, tri: &[ScreenVertex; 3], light: W) {
        let Some(o) = self.scene.object(obj) else {
            return;
        };
        let (slots, output, sink, lit) =
            (&mut self.slots, self.output, &mut *self.sink, &mut self.lit);
        slots.new_triangle(tri);
        let mut plane = W::Plane::default();
        let mut seg_sink = |seg: &Segment| {
            let light = light.segment(&mut plane, tri);
            shade_segment::<Rgba8888, T, N, _, _>(
                slots,
                o.texture,
                output,
                seg,
                light,
                |x, chunk| {
                    if W::LIT {
                        *lit += chunk.len() as u64;
                    }
                    sink.write_span(x, seg.y, chunk)
                },
            );
        };
        self.raster.draw(tri, &o.raster, &mut seg_sink);
    }
}

/// What the banded renderer draws a triangle with ([`Renderer::render_banded_rows_binned`]), into
/// a band `B` ([`Band`]: RGBA8888 or RGB565).
pub(super) struct BandDraw<'a, 't, S, B, const T: usize, const N: usize> {
    pub(super) scene: &'a S,
    pub(super) slots: Slots<'t, T, N>,
    pub(super) output: Output,
    pub(super) raster: Rasterizer,
    pub(super) buf: B,
    pub(super) depth: Option<DepthBuffer<'a>>,
    /// The bins this band's walk fills (the first band's, unless they were filled already).
    pub(super) binning: Option<&'a [core::cell::Cell<GroupRows>]>,
    /// The image's rows (what the bins record).
    pub(super) image: core::ops::Range<u16>,
    /// Pixels composited with [`Blend::Over`].
    pub(super) blended: u64,
    /// Pixels lit.
    pub(super) lit: u64,
}

impl<S: TriangleSource, B: Band, const T: usize, const N: usize> BandDraw<'_, '_, S, B, T, N> {
    /// One band's walk over the scene without light: the groups `keep` takes, each triangle
    /// drawn by [`BandDraw::triangle`]. Out of line, as is [`BandDraw::walk_lit`], so that each
    /// walk is compiled on its own: the unlit walk is the same code whether the lit one exists
    /// (feature `lighting`) or not.
    #[inline(never)]
    pub(super) fn walk_unlit<K: FnMut(usize) -> bool>(&mut self, keep: K) {
        let scene = self.scene;
        scene.for_each_triangle_grouped(keep, |g, obj, tri| self.triangle(g, obj, tri, Unlit));
    }

    /// One band's walk over the scene with its lights (see [`BandDraw::walk_unlit`]).
    #[cfg(feature = "lighting")]
    #[inline(never)]
    pub(super) fn walk_lit<K: FnMut(usize) -> bool>(&mut self, keep: K) {
        let scene = self.scene;
        scene.for_each_lit_triangle_grouped(keep, |g, obj, tri, l| self.triangle(g, obj, tri, l));
    }

    /// Draws triangle `tri` (group `g`, object `obj`) into the band, lit by `light`, recording
    /// its rows in the bins when this walk fills them.
    #[inline(always)]
    pub(super) fn triangle<W: WalkLight>(
        &mut self,
        g: usize,
        obj: usize,
        tri: &[ScreenVertex; 3],
        light: W,
    ) {
        if let Some(b) = self.binning.and_then(|bins| bins.get(g)) {
            if let Some((r0, r1)) = triangle_rows(tri, &self.image, self.buf.width()) {
                let mut r = b.get();
                r.include(r0, r1);
                b.set(r);
            }
        }
        let Some(o) = self.scene.object(obj) else {
            return;
        };
        let (slots, output, buf) = (&mut self.slots, self.output, &mut self.buf);
        slots.new_triangle(tri);
        let (blended, lit) = (&mut self.blended, &mut self.lit);
        let mut plane = W::Plane::default();
        // An unlit walk shades in the band's pixel (an RGB565 band: straight to RGB565); a lit
        // one in RGBA8888, lit, then written (reduced by an RGB565 band), so that both bands
        // hold the same colours. The choice is the walk's type: one shading path is compiled
        // into each walk.
        let mut seg_sink = |seg: &Segment| {
            let light = light.segment(&mut plane, tri);
            if W::LIT {
                shade_segment::<Rgba8888, T, N, _, _>(
                    slots,
                    o.texture,
                    output,
                    seg,
                    light,
                    |x, chunk| {
                        *lit += chunk.len() as u64;
                        if o.blend == Blend::Over {
                            *blended += chunk.len() as u64;
                            buf.blend_rgba(x, seg.y, chunk);
                        } else {
                            buf.write_rgba(x, seg.y, chunk);
                        }
                    },
                );
            } else {
                // An opaque segment with widths from differences straight into the band's
                // row.
                #[cfg(feature = "differences")]
                if o.blend != Blend::Over {
                    if let Some(row) = buf.raw_row(seg.x0, seg.y, seg.len) {
                        let into = shade_segment_into::<B::Px, T, N, _>;
                        if into(slots, o.texture, output, seg, row, B::to_raw) {
                            return;
                        }
                    }
                }
                shade_segment::<B::Px, T, N, _, _>(
                    slots,
                    o.texture,
                    output,
                    seg,
                    light,
                    |x, chunk| {
                        if o.blend == Blend::Over {
                            *blended += chunk.len() as u64;
                            buf.blend(x, seg.y, chunk);
                        } else {
                            buf.write(x, seg.y, chunk);
                        }
                    },
                );
            }
        };
        match (o.depth, self.depth.as_mut()) {
            (true, Some(d)) => self.raster.draw_depth(tri, &o.raster, d, &mut seg_sink),
            _ => self.raster.draw(tri, &o.raster, &mut seg_sink),
        }
    }
}

/// Writes the rows `rows` of `buf` to `sink`. Out of line, so that the sink's per-pixel loop is
/// compiled apart from the band loop's state.
#[inline(never)]
pub(super) fn flush_rows<P: PixelSink>(
    buf: &RgbaBuffer<'_>,
    rows: core::ops::Range<u16>,
    sink: &mut P,
) {
    for y in rows {
        if let Some(row) = buf.row(y) {
            sink.write_span(0, y, row);
        }
    }
}
