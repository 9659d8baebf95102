//! Shading one segment of a triangle: the per-slot evaluators of a frame ([`Slots`]), the
//! segment's colours (or, for [`Output::FilterWidth`], its filter widths as grey) in chunks of at
//! most [`CHUNK`] pixels, lit and handed on. With a difference memory
//! ([`Renderer::with_differences`]) a filtered texture takes its widths from the differences of
//! neighbouring values. Nothing here allocates or panics.

use super::band::ChunkColor;
use super::*;

/// The least vertical extent, in rows (of its vertices' bounding box), of a triangle that takes
/// its filter widths from differences when the renderer has a difference memory
/// ([`Renderer::with_differences`]): a shorter one takes them from the gradients (two tiles of
/// `texture::TILE_ROWS`; on the built-in marble scene's mesh 905.0 -> 843.8 instructions a frame
/// pixel on the Cortex-M4F with the ramp, and 49.4 -> 51.8 dB; the same from 16 to 64 rows, 861.9
/// from 8).
#[cfg(feature = "differences")]
pub const DIFFERENCE_MIN_ROWS: u16 = 16;

/// Per-slot evaluators, created once per frame.
pub(super) struct Slots<'t, const T: usize, const N: usize> {
    pub(super) evals: heapless::Vec<TextureEvaluator<'t, T, N>, MAX_TEXTURES>,
    pub(super) widths: heapless::Vec<Option<WidthEval<'t, T, N>>, MAX_TEXTURES>,
    /// The frame's difference memory ([`Renderer::with_differences`]).
    #[cfg(feature = "differences")]
    pub(super) mem: Option<MemoryRows<'t>>,
    /// The triangle being drawn takes its widths from the gradients although the renderer has
    /// a difference memory (it spans fewer than [`DIFFERENCE_MIN_ROWS`] rows).
    #[cfg(feature = "differences")]
    pub(super) short: bool,
}

impl<const T: usize, const N: usize> Slots<'_, T, N> {
    /// A new triangle: the differences start again (they are taken within one triangle).
    #[inline(always)]
    pub(super) fn new_triangle(&mut self, tri: &[ScreenVertex; 3]) {
        #[cfg(feature = "differences")]
        if let Some(m) = self.mem.as_mut() {
            m.forget();
            let [_, _, y0, y1] = crate::raster::bounding_box(tri);
            self.short = i64::from(y1) - i64::from(y0) < 16 * i64::from(DIFFERENCE_MIN_ROWS);
        }
        #[cfg(not(feature = "differences"))]
        let _ = tri;
    }
}

/// Evaluates filter widths for [`Output::FilterWidth`].
pub(super) struct WidthEval<'t, const T: usize, const N: usize> {
    pub(super) tex: &'t Texture<T, N>,
    pub(super) eval: Option<SpanEvaluator<'t, T>>,
}

pub(super) fn slots_stats<const T: usize, const N: usize>(slots: &Slots<'_, T, N>) -> ShadeStats {
    let mut s = ShadeStats::default();
    for e in &slots.evals {
        s.add(&e.stats());
    }
    for w in slots.widths.iter().flatten() {
        if let Some(e) = &w.eval {
            s.span.add(e.stats());
        }
    }
    s
}

/// `log2 N` of a power of two.
pub(super) const fn log2(n: usize) -> u32 {
    usize::BITS - 1 - n.leading_zeros()
}

/// Shades an unlit segment with widths from differences straight into `row` (one element a
/// pixel of the segment, `put` making each from its colour: an opaque object's pixels in the
/// band's own storage, no chunk and no copy); whether it could (the texture is filtered, the
/// renderer has a difference memory and the triangle takes its widths from it). The colours
/// are [`shade_segment`]'s. (The gradients' path keeps its chunks: written straight into the row
/// it compiled its whole evaluation a second time, 9 KB of the fast shape and 0.2 KB past the
/// `full` size budget, for 9 to 14 instructions a pixel.)
#[cfg(feature = "differences")]
#[inline(always)]
pub(super) fn shade_segment_into<C: ChunkColor, const T: usize, const N: usize, R>(
    slots: &mut Slots<'_, T, N>,
    slot: usize,
    output: Output,
    seg: &Segment,
    row: &mut [R],
    put: impl Fn(C) -> R,
) -> bool {
    let (Output::Color, false, Some(m), Some(e)) = (
        output,
        slots.short,
        slots.mem.as_mut(),
        slots.evals.get_mut(slot),
    ) else {
        return false;
    };
    if e.stage().antialias() == crate::filter::Antialias::None {
        return false;
    }
    let span = Span {
        s0: seg.s0,
        ds: seg.ds,
        dsdy: seg.dsdy,
        len: seg.len,
    };
    e.differences_into::<C, R, _>(m, seg.x0, seg.y, &span, row, put)
}

/// Shades one segment into chunks of at most [`CHUNK`] pixels of colour `C` (the band's pixel,
/// [`ChunkColor`]), calling `out(x, chunk)`.
pub(super) fn shade_segment<
    C: ChunkColor,
    const T: usize,
    const N: usize,
    L: SegmentLight,
    O: FnMut(u16, &[C]),
>(
    slots: &mut Slots<'_, T, N>,
    slot: usize,
    output: Output,
    seg: &Segment,
    light: L,
    mut out: O,
) {
    let span = Span {
        s0: seg.s0,
        ds: seg.ds,
        dsdy: seg.dsdy,
        len: seg.len,
    };
    // Widths from differences for a filtered texture (an unfiltered one needs no widths, and
    // no row above): the segment's colours a chunk at a time.
    #[cfg(feature = "differences")]
    if let (Output::Color, false, Some(m), Some(e)) = (
        output,
        slots.short,
        slots.mem.as_mut(),
        slots.evals.get_mut(slot),
    ) {
        if e.stage().antialias() != crate::filter::Antialias::None {
            let piece = |off: u16, px: &mut [C]| {
                let x = seg.x0.saturating_add(off);
                C::light(light, x, seg.y, px);
                out(x, px);
            };
            if e.differences_pieces::<C, _, CHUNK>(m, seg.x0, seg.y, &span, piece) {
                return;
            }
        }
    }
    let mut chunk = [C::BLANK; CHUNK];
    let mut n = 0usize;
    let mut x = seg.x0;
    let mut push = |c: C| {
        if let Some(p) = chunk.get_mut(n) {
            *p = c;
        }
        n += 1;
        if n == CHUNK {
            C::light(light, x, seg.y, &mut chunk);
            out(x, &chunk);
            x = x.saturating_add(CHUNK as u16);
            n = 0;
        }
    };
    match output {
        Output::Color => {
            if let Some(e) = slots.evals.get_mut(slot) {
                C::shade_span(e, &span, &mut push);
            }
        }
        Output::FilterWidth => {
            if let Some(Some(we)) = slots.widths.get_mut(slot) {
                width_span(we, &span, |c| push(C::from_rgba(c)));
            }
        }
    }
    if let Some(rest) = chunk.get_mut(..n).filter(|r| !r.is_empty()) {
        C::light(light, x, seg.y, rest);
        out(x, rest);
    }
}

/// The filter width of each pixel of `span` as grey: `(w - 1) * 255 / (N - 1)`, clamped.
pub(super) fn width_span<const T: usize, const N: usize, F: FnMut(Rgba8888)>(
    we: &mut WidthEval<'_, T, N>,
    span: &Span,
    mut emit: F,
) {
    let lg = log2(N);
    let norm = we.tex.norm();
    let grey = |w: FilterWidth| {
        let one = 1u64 << 16;
        let w = u64::from(w.to_bits()).max(one) - one;
        let den = ((N as u64).max(2) - 1) << 16;
        let v = (w * 255 + den / 2) / den;
        let v = v.min(255) as u8;
        Rgba8888::new(v, v, v, 255)
    };
    match we.eval.as_mut() {
        Some(e) => {
            let extra = e.extra_width48(span);
            e.eval(span, |s| {
                emit(grey(filter_width_spread(s.gx, s.gy, extra, norm, lg)))
            });
        }
        None => {
            for _ in 0..span.len {
                emit(Rgba8888::new(255, 0, 255, 255));
            }
        }
    }
}
