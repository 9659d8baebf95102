//! Filter widths from the differences of neighbouring values, as a GPU takes them (`ddx`,
//! `ddy`): [`DifferenceRows`] and [`DifferenceSpans`], a named approximate mode of the
//! antialiasing. The noise is evaluated without its gradients (the value path, about half the
//! cost of the path with gradients); each pixel's filter width comes from its neighbours.
//!
//! # Guarantees
//!
//! - The values are exact: those of [`crate::span::SpanEvaluator::eval_values`] of each row's
//!   span, bit for bit. Only the filter widths are approximate.
//! - Pixel `(x, y)`'s width is the stage's width ([`WidthStream::width_with`], the span's
//!   spread in quadrature) of the gradient `(f(x + 1, y) - f(x, y), f(x, y) - f(x, y - 1))`,
//!   the differences wrapping in 16.16 (exact while the true difference is below 2^15). A
//!   span's last pixel takes its left neighbour's horizontal difference (a span of one pixel:
//!   0). The colour is then the stage's colour at that width (tested against `ColorStage::shade`
//!   pixel by pixel); with `Antialias::Ramp` and the L2 norm, the ramp's level comes from the
//!   squared differences without a root ([`crate::filter::ramp::Ramp565::shade_differences_l2`]).
//! - Memory: the caller's [`DifferenceMemory`] of `W` pixels holds the values of two rows
//!   (`8 W` bytes); nothing else is kept. A row or span longer than `W` pixels, or a plane wider
//!   than `W`, is refused when the rows or spans are made.
//! - [`DifferenceRows`] evaluates each row once, and the row above the first once more.
//!   [`DifferenceSpans`] reuses the row above when it holds the span's pixels (spans shaded row
//!   by row, left to right, as a display is drawn); any other order is served by evaluating the
//!   row above the span once more (the same colours, at twice the cost).
//! - [`TextureEvaluator::shade_differences`] shades any span at a pixel position (a
//!   rasterizer's segments, `Renderer::with_differences`): the pixel above from the memory
//!   where it holds the row above (not on a tile's first row, [`TILE_ROWS`]), else the
//!   vertical difference of the span's nearest pixel that has one, else the span evaluated one
//!   row up; the values are the span's own, bit for bit.
//! - Deterministic integer arithmetic: the same colours on the host and on every device.
//!
//! ```
//! use texcore::filter::Antialias;
//! use texcore::format::TexPoint;
//! use texcore::ready::{Material, PresetName};
//! use texcore::span::{RowCache, Span};
//! use texcore::texture::DifferenceMemory;
//!
//! let marble = Material::preset(PresetName::Marble).texture::<256>(Antialias::Csat)?;
//! // A 128-pixel-wide plane, one row after the other.
//! let first = Span {
//!     s0: TexPoint::from_f64(0.0, 0.5, 0.0),
//!     ds: TexPoint::from_f64(1.0 / 64.0, 0.0, 0.0),
//!     dsdy: TexPoint::from_f64(0.0, 0.0, 1.0 / 64.0),
//!     len: 128,
//! };
//! let mut cache = RowCache::<128>::new();
//! let mut memory = DifferenceMemory::<128>::new(); // 8 x 128 + 16 bytes
//! let mut ev = marble.evaluator();
//! let mut rows = ev.difference_rows(&first, &mut cache, &mut memory).ok_or("too wide")?;
//! let mut line = [0u16; 128];
//! for _ in 0..4 {
//!     let mut px = line.iter_mut();
//!     rows.next_shade565(|c| {
//!         if let Some(p) = px.next() {
//!             *p = c.to_bits();
//!         }
//!     });
//!     // ... send `line` to the display
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::{log2, Texture, TextureEvaluator, TextureRows, TextureSpans};
use crate::color::{Rgb565, Rgba8888};
use crate::filter::{Antialias, ColorStage, GradientNorm, WidthStream};
use crate::format::{FilterWidth, TexValue};
use crate::span::{Faces, PlaneSetup, RowCache, Span};

/// The memory of the rows shaded with widths from differences: the values of two rows of up to
/// `W` pixels (the row above and the row being shaded), `8 W` bytes, and which pixels of which
/// rows they hold.
#[derive(Clone, Debug)]
pub struct DifferenceMemory<const W: usize> {
    rows: [[TexValue; W]; 2],
    held: [Held; 2],
}

/// The pixels `lo..hi` of row `row` held by one row of a [`DifferenceMemory`] (`row` `None`:
/// nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Held {
    row: Option<u16>,
    lo: u16,
    hi: u16,
}

impl Held {
    /// Nothing held.
    const NONE: Held = Held {
        row: None,
        lo: 0,
        hi: 0,
    };

    /// Whether pixels `x..x + len` of row `y` are held.
    fn covers(&self, y: u16, x: u16, len: u16) -> bool {
        self.row == Some(y) && self.lo <= x && u32::from(x) + u32::from(len) <= u32::from(self.hi)
    }

    /// Holds pixels `x..x + len` of row `y` as well: the pixels held grow to the union when
    /// they overlap or touch them (the values of a row are the same whichever span wrote them),
    /// and are replaced otherwise.
    fn hold(&mut self, y: u16, x: u16, len: u16) {
        let end = x.saturating_add(len);
        if self.row == Some(y) && x <= self.hi && end >= self.lo {
            self.lo = self.lo.min(x);
            self.hi = self.hi.max(end);
        } else {
            *self = Held {
                row: Some(y),
                lo: x,
                hi: end,
            };
        }
    }
}

impl<const W: usize> DifferenceMemory<W> {
    /// An empty memory.
    pub const fn new() -> Self {
        DifferenceMemory {
            rows: [[TexValue::ZERO; W]; 2],
            held: [Held::NONE; 2],
        }
    }

    /// Bytes held (`8 W` and the two rows' descriptions).
    pub const fn bytes() -> usize {
        core::mem::size_of::<Self>()
    }

    /// Forgets every row held: the next span shaded through the memory evaluates the pixels
    /// above it. [`TextureEvaluator::shade_differences`] takes the pixels above a span from the
    /// memory whenever it holds them, so call this wherever the surface changes (at each
    /// triangle, as the renderer does): the differences are then taken within one surface.
    pub fn forget(&mut self) {
        self.held = [Held::NONE; 2];
    }

    /// Records that memory row `k` now holds pixels `x..x + len` of row `y` as well
    /// ([`Held::hold`]).
    fn hold(&mut self, k: usize, y: u16, x: u16, len: u16) {
        if let Some(h) = self.held.get_mut(k) {
            h.hold(y, x, len);
        }
    }

    /// The memory borrowed without its width in the type, with the face blends of `faces`
    /// (none: [`Faces::none`]).
    pub(crate) fn rows_mut<'m>(&'m mut self, faces: Faces<'m>) -> MemoryRows<'m> {
        let [a, b] = &mut self.rows;
        MemoryRows {
            rows: [a, b],
            held: &mut self.held,
            faces,
        }
    }
}

/// A [`DifferenceMemory`] borrowed without its width in the type (what the renderer keeps),
/// with a face cache's parts for the values ([`crate::span::FaceCache`]; none: no cache).
#[derive(Debug)]
pub(crate) struct MemoryRows<'m> {
    rows: [&'m mut [TexValue]; 2],
    held: &'m mut [Held; 2],
    faces: Faces<'m>,
}

impl MemoryRows<'_> {
    /// Pixels a row holds.
    #[cfg_attr(not(feature = "differences"), allow(dead_code))]
    pub(crate) fn width(&self) -> usize {
        self.rows[0].len()
    }

    /// Forgets every row held ([`DifferenceMemory::forget`]).
    #[cfg_attr(not(feature = "differences"), allow(dead_code))]
    pub(crate) fn forget(&mut self) {
        *self.held = [Held::NONE; 2];
    }

    /// Records that memory row `k` holds pixels `x..x + len` of row `y` as well
    /// ([`Held::hold`]).
    fn hold(&mut self, k: usize, y: u16, x: u16, len: u16) {
        if let Some(h) = self.held.get_mut(k) {
            h.hold(y, x, len);
        }
    }
}

impl<const W: usize> Default for DifferenceMemory<W> {
    fn default() -> Self {
        Self::new()
    }
}

/// The values `f` of a span with their differences `(f, dx, dy)` (16 fraction bits): `dx` to
/// the right neighbour (the last pixel's, its left neighbour's; 0 for one pixel), `dy` from the
/// pixel above (`above`, the same pixels one row up). Stops at the shorter slice.
#[inline(always)]
fn differences<'a>(
    f: &'a [TexValue],
    above: &'a [TexValue],
) -> impl Iterator<Item = (TexValue, i32, i32)> + 'a {
    let mut dx = 0i32;
    let right = f.iter().skip(1).map(Some).chain(core::iter::once(None));
    f.iter().zip(right).zip(above).map(move |((&v, r), &a)| {
        if let Some(&r) = r {
            dx = r.to_bits().wrapping_sub(v.to_bits());
        }
        (v, dx, v.to_bits().wrapping_sub(a.to_bits()))
    })
}

/// A difference of 16 fraction bits as a gradient of 48.
#[inline(always)]
fn gradient48(d: i32) -> i64 {
    i64::from(d) << 32
}

/// A colour the values are shaded into: [`Rgba8888`] or [`Rgb565`].
pub(crate) trait SpanColor: Sized {
    /// The stage's colour of `v` at width `w`.
    fn at<const N: usize>(stage: &ColorStage<N>, v: TexValue, w: FilterWidth) -> Self;

    /// Shades the span through the stage's own one-read path where it has one for this colour
    /// (the ramp, to RGB565, with the L2 norm): whether it did.
    #[inline(always)]
    fn one_read<const N: usize, F: FnMut(Self)>(
        _stage: &ColorStage<N>,
        _norm: GradientNorm,
        _values: (&[TexValue], &[TexValue], i64),
        _emit: &mut F,
    ) -> bool {
        false
    }

    /// [`SpanColor::one_read`] written into `dst` (`dst[i] = put(colour of pixel i)`, `dst` as
    /// long as the values): whether it did.
    #[cfg_attr(not(feature = "differences"), allow(dead_code))]
    #[inline(always)]
    fn one_read_into<const N: usize, D, P: Fn(Self) -> D>(
        _stage: &ColorStage<N>,
        _norm: GradientNorm,
        _values: (&[TexValue], &[TexValue], i64),
        _dst: &mut [D],
        _put: P,
    ) -> bool {
        false
    }
}

impl SpanColor for Rgba8888 {
    #[inline(always)]
    fn at<const N: usize>(stage: &ColorStage<N>, v: TexValue, w: FilterWidth) -> Self {
        stage.shade(v, w)
    }

    /// The ramp's RGB565 colours widened as [`ColorStage::shade`] widens them.
    #[cfg(feature = "ramp")]
    #[inline(always)]
    fn one_read<const N: usize, F: FnMut(Self)>(
        stage: &ColorStage<N>,
        norm: GradientNorm,
        values: (&[TexValue], &[TexValue], i64),
        emit: &mut F,
    ) -> bool {
        Rgb565::one_read(stage, norm, values, &mut |c: Rgb565| emit(c.to_rgba8888()))
    }

    /// The ramp's RGB565 colours widened as [`ColorStage::shade`] widens them.
    #[cfg(feature = "ramp")]
    #[inline(always)]
    fn one_read_into<const N: usize, D, P: Fn(Self) -> D>(
        stage: &ColorStage<N>,
        norm: GradientNorm,
        values: (&[TexValue], &[TexValue], i64),
        dst: &mut [D],
        put: P,
    ) -> bool {
        Rgb565::one_read_into(stage, norm, values, dst, |c: Rgb565| put(c.to_rgba8888()))
    }
}

impl SpanColor for Rgb565 {
    #[inline(always)]
    fn at<const N: usize>(stage: &ColorStage<N>, v: TexValue, w: FilterWidth) -> Self {
        stage.shade565(v, w)
    }

    #[cfg(feature = "ramp")]
    #[inline(always)]
    fn one_read<const N: usize, F: FnMut(Self)>(
        stage: &ColorStage<N>,
        norm: GradientNorm,
        (f, above, extra48): (&[TexValue], &[TexValue], i64),
        emit: &mut F,
    ) -> bool {
        let ramp = one_read_ramp(stage, norm);
        if let Some(r) = ramp {
            r.shade_differences_l2(f, above, extra48, emit);
        }
        ramp.is_some()
    }

    #[cfg(feature = "ramp")]
    #[inline(always)]
    fn one_read_into<const N: usize, D, P: Fn(Self) -> D>(
        stage: &ColorStage<N>,
        norm: GradientNorm,
        (f, above, extra48): (&[TexValue], &[TexValue], i64),
        dst: &mut [D],
        put: P,
    ) -> bool {
        let ramp = one_read_ramp(stage, norm);
        if let Some(r) = ramp {
            r.shade_differences_l2_into(f, above, extra48, dst, put);
        }
        ramp.is_some()
    }
}

/// The stage's ramp when it has a one-read path for widths from differences: a ramp, the L2
/// norm and `N <= 2^15`.
#[cfg(feature = "ramp")]
#[inline(always)]
fn one_read_ramp<const N: usize>(
    stage: &ColorStage<N>,
    norm: GradientNorm,
) -> Option<&crate::filter::Ramp565<N>> {
    match (stage.ramp(), norm, log2(N) <= 15) {
        (Some((_, r)), GradientNorm::L2, true) => Some(r),
        _ => None,
    }
}

/// The colours of values `f` under `above` (and the span's spread) with widths from their
/// differences (see the module documentation).
#[inline(always)]
fn shade_values<const N: usize, C: SpanColor, F: FnMut(C)>(
    stage: &ColorStage<N>,
    norm: GradientNorm,
    (f, above, extra48): (&[TexValue], &[TexValue], i64),
    mut emit: F,
) {
    if C::one_read(stage, norm, (f, above, extra48), &mut emit) {
        return;
    }
    let filtered = stage.antialias() != Antialias::None;
    let mut widths = WidthStream::new(norm, log2(N));
    for (v, dx, dy) in differences(f, above) {
        let w = if filtered {
            widths.width_with(gradient48(dx), gradient48(dy), extra48)
        } else {
            FilterWidth::ZERO
        };
        emit(C::at(stage, v, w));
    }
}

/// The rows of a plane shaded with widths from differences: made by
/// [`TextureEvaluator::difference_rows`] (see the module documentation).
#[derive(Debug)]
pub struct DifferenceRows<'e, 't, 'c, const T: usize, const N: usize, const W: usize> {
    tex: &'t Texture<T, N>,
    rows: TextureRows<'e, 't, 'c, T, N>,
    mem: &'c mut DifferenceMemory<W>,
    /// The memory's row holding the row above the next one (`None` before the first row).
    above: Option<usize>,
}

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// The rows of a plane from `first` (each next row's span is the last one's with `s0`
    /// advanced by `dsdy`), shaded with filter widths from the differences of neighbouring
    /// values ([`DifferenceRows`]), the values through `cache` (the span evaluator's row
    /// schedule, as [`TextureEvaluator::rows`]) and kept in `mem`. `None` when the rows are
    /// longer than `W` pixels.
    pub fn difference_rows<'e, 'c, const R: usize, const V: usize, const W: usize>(
        &'e mut self,
        first: &Span,
        cache: &'c mut RowCache<R, V>,
        mem: &'c mut DifferenceMemory<W>,
    ) -> Option<DifferenceRows<'e, 't, 'c, T, N, W>> {
        if usize::from(first.len) > W {
            return None;
        }
        mem.forget();
        let tex = self.tex;
        Some(DifferenceRows {
            tex,
            rows: self.rows(&first.prev_row(), cache),
            mem,
            above: None,
        })
    }
}

impl<const T: usize, const N: usize, const W: usize> DifferenceRows<'_, '_, '_, T, N, W> {
    /// The span of the next row.
    pub fn span(&self) -> Span {
        match self.above {
            Some(_) => *self.rows.span(),
            None => self.rows.span().next_row(),
        }
    }

    /// Evaluates the next row's values (and, first, the row above it) into the memory: the
    /// row's values, the row above's and the row's spread.
    fn next_values(&mut self) -> (&[TexValue], &[TexValue], i64) {
        let n = usize::from(self.rows.span().len).min(W);
        let above = match self.above {
            Some(a) => a,
            None => {
                if let Some(row) = self.mem.rows.get_mut(1) {
                    self.rows.next_values(row.get_mut(..n).unwrap_or(&mut []));
                }
                1
            }
        };
        let [r0, r1] = &mut self.mem.rows;
        let (up, cur) = if above == 0 { (r0, r1) } else { (r1, r0) };
        let extra = self.rows.next_values(cur.get_mut(..n).unwrap_or(&mut []));
        self.above = Some(1 - above);
        (
            cur.get(..n).unwrap_or(&[]),
            up.get(..n).unwrap_or(&[]),
            extra,
        )
    }

    /// Shades the next row, calling `emit` with each pixel's colour in order (see the module
    /// documentation), and moves to the row after it.
    pub fn next_shade<F: FnMut(Rgba8888)>(&mut self, emit: F) {
        self.next(emit);
    }

    /// [`DifferenceRows::next_shade`] straight to RGB565: its colours reduced to RGB565, bit for
    /// bit; with `Antialias::Ramp` (feature `ramp`) and the L2 norm, one ramp read a pixel.
    pub fn next_shade565<F: FnMut(Rgb565)>(&mut self, emit: F) {
        self.next(emit);
    }

    /// The next row's colours of type `C`.
    #[inline(always)]
    fn next<C: SpanColor, F: FnMut(C)>(&mut self, emit: F) {
        let tex = self.tex;
        let n = u64::from(self.rows.span().len);
        self.rows.count(tex.stage.antialias() != Antialias::None, n);
        shade_values(&tex.stage, tex.norm, self.next_values(), emit);
    }
}

/// The spans of one plane shaded with widths from differences, from its rows' cell schedule:
/// made by [`TextureEvaluator::difference_spans`] (see the module documentation).
#[derive(Debug)]
pub struct DifferenceSpans<'e, 't, 'c, const T: usize, const N: usize, const W: usize> {
    tex: &'t Texture<T, N>,
    spans: TextureSpans<'e, 't, 'c, T, N>,
    mem: &'c mut DifferenceMemory<W>,
}

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// The spans of `plane` (made by [`TextureEvaluator::plane_setup`]) shaded with filter
    /// widths from the differences of neighbouring values ([`DifferenceSpans`]), the values
    /// from the plane's rows' cell schedule in `cache` (as [`TextureEvaluator::plane_spans`])
    /// and kept in `mem`. `None` when the plane is wider than `W` pixels.
    pub fn difference_spans<'e, 'c, const R: usize, const V: usize, const W: usize>(
        &'e mut self,
        plane: &'c PlaneSetup<'t, T>,
        cache: &'c mut RowCache<R, V>,
        mem: &'c mut DifferenceMemory<W>,
    ) -> Option<DifferenceSpans<'e, 't, 'c, T, N, W>> {
        if usize::from(plane.plane().width()) > W {
            return None;
        }
        mem.forget();
        let tex = self.tex;
        Some(DifferenceSpans {
            tex,
            spans: self.plane_spans(plane, cache),
            mem,
        })
    }
}

impl<const T: usize, const N: usize, const W: usize> DifferenceSpans<'_, '_, '_, T, N, W> {
    /// Evaluates the values of the span of `len` pixels at `(x, y)` (and of the pixels above it
    /// when the memory does not hold them) into the memory: the span's values, those above and
    /// the span's spread. `None` when the span is not inside the plane's rectangle.
    fn values(&mut self, x: u16, y: u16, len: u16) -> Option<(&[TexValue], &[TexValue], i64)> {
        // Inside the rectangle: `x + len <= width <= W`.
        let span = self.spans.span_plane().span(x, y, len)?;
        let (lo, hi) = (usize::from(x), usize::from(x) + usize::from(len));
        let held = self.mem.held;
        let covered = |k: usize| y.checked_sub(1).is_some_and(|u| held[k].covers(u, x, len));
        // The memory row holding the pixels above (or the one to take them): not the one
        // holding the span's row so far.
        let up = if covered(0) {
            0
        } else if covered(1) || held[0].row == Some(y) {
            1
        } else {
            0
        };
        if !covered(up) {
            let row = self.mem.rows.get_mut(up)?.get_mut(lo..hi)?;
            match y.checked_sub(1) {
                Some(u) => {
                    self.spans.values(x, u, row);
                    self.mem.hold(up, u, x, len);
                }
                // Above the plane's first row: its span one row up, not kept.
                None => {
                    self.spans.span_values(&span.prev_row(), row);
                    self.mem.held[up] = Held::NONE;
                }
            }
        }
        let cur = 1 - up;
        let extra = self
            .spans
            .values(x, y, self.mem.rows.get_mut(cur)?.get_mut(lo..hi)?);
        self.mem.hold(cur, y, x, len);
        let [r0, r1] = &self.mem.rows;
        let (u, c) = if up == 0 { (r0, r1) } else { (r1, r0) };
        Some((c.get(lo..hi)?, u.get(lo..hi)?, extra))
    }

    /// Shades the span of `len` pixels at `(x, y)` of the plane, calling `emit` with each
    /// pixel's colour in order (see the module documentation). Nothing is shaded when the span
    /// is not inside the plane's rectangle.
    pub fn shade<F: FnMut(Rgba8888)>(&mut self, x: u16, y: u16, len: u16, emit: F) {
        self.span(x, y, len, emit);
    }

    /// [`DifferenceSpans::shade`] straight to RGB565: its colours reduced to RGB565, bit for
    /// bit; with `Antialias::Ramp` (feature `ramp`) and the L2 norm, one ramp read a pixel.
    pub fn shade565<F: FnMut(Rgb565)>(&mut self, x: u16, y: u16, len: u16, emit: F) {
        self.span(x, y, len, emit);
    }

    /// The span's colours of type `C`.
    #[inline(always)]
    fn span<C: SpanColor, F: FnMut(C)>(&mut self, x: u16, y: u16, len: u16, emit: F) {
        let tex = self.tex;
        if let Some(values) = self.values(x, y, len) {
            shade_values(&tex.stage, tex.norm, values, emit);
            self.spans
                .count(tex.stage.antialias() != Antialias::None, len);
        }
    }
}

/// Rows of the tiles of [`TextureEvaluator::shade_differences`]: the pixels above a row `y`
/// with `y % TILE_ROWS == 0` are always evaluated one row up on its span, never taken from the
/// memory, so that the colours do not depend on where a renderer's bands start (any multiple
/// of `TILE_ROWS` rows).
pub const TILE_ROWS: u16 = 8;

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// Shades `span`, the pixels `x..x + span.len` of row `y` of any surface, with filter widths
    /// from the differences of neighbouring values (see the module documentation), calling
    /// `emit` with each pixel's colour in order; for a renderer's segments, drawn row by row.
    ///
    /// The pixels above come from `mem` where it holds them (row `y - 1`, shaded through it
    /// since it was last [forgotten](DifferenceMemory::forget)), unless `y` is the first row of
    /// a tile of [`TILE_ROWS`] rows; the others are evaluated on `span` one row up
    /// (`s0 - dsdy`) and kept. The span's values are kept for the row below. So a triangle's
    /// rows shaded top to bottom evaluate each pixel once, and the row above its first row and
    /// above each tile's first row once more; and the colours are the same whether the rows are
    /// drawn at once or in bands of any multiple of [`TILE_ROWS`] rows. Returns `false` (and
    /// shades nothing) when the span reaches past pixel `W`.
    pub fn shade_differences<const W: usize, F: FnMut(Rgba8888)>(
        &mut self,
        mem: &mut DifferenceMemory<W>,
        x: u16,
        y: u16,
        span: &Span,
        emit: F,
    ) -> bool {
        self.differences_each(&mut mem.rows_mut(Faces::none()), x, y, span, emit)
    }

    /// [`TextureEvaluator::shade_differences`] straight to RGB565: its colours reduced to
    /// RGB565, bit for bit; with `Antialias::Ramp` (feature `ramp`) and the L2 norm, one ramp
    /// read a pixel.
    pub fn shade565_differences<const W: usize, F: FnMut(Rgb565)>(
        &mut self,
        mem: &mut DifferenceMemory<W>,
        x: u16,
        y: u16,
        span: &Span,
        emit: F,
    ) -> bool {
        self.differences_each(&mut mem.rows_mut(Faces::none()), x, y, span, emit)
    }

    /// [`TextureEvaluator::shade_differences`] through a borrowed memory, colours of type `C`
    /// handed to `emit` one by one (from [`TextureEvaluator::differences_pieces`]).
    fn differences_each<C, F>(
        &mut self,
        mem: &mut MemoryRows<'_>,
        x: u16,
        y: u16,
        span: &Span,
        mut emit: F,
    ) -> bool
    where
        C: SpanColor + Copy + Default,
        F: FnMut(C),
    {
        self.differences_pieces::<C, _, 64>(mem, x, y, span, |_, px| {
            px.iter().for_each(|&c| emit(c));
        })
    }

    /// [`TextureEvaluator::shade_differences`] through a borrowed memory, a piece of at most
    /// `K` pixels at a time: each piece's colours written into a buffer of `K` and handed to
    /// `out` with the piece's first pixel (relative to `x`), so that no call is made per pixel
    /// (the renderer's chunks).
    #[inline]
    pub(crate) fn differences_pieces<C, O, const K: usize>(
        &mut self,
        mem: &mut MemoryRows<'_>,
        x: u16,
        y: u16,
        span: &Span,
        mut out: O,
    ) -> bool
    where
        C: SpanColor + Copy + Default,
        O: FnMut(u16, &mut [C]),
    {
        let Some((f, above, extra)) = self.segment_values(mem, x, y, span) else {
            return false;
        };
        let tex = self.tex;
        let n = f.len();
        let mut buf = [C::default(); K];
        let mut a = 0;
        while a < n {
            let b = (a + K).min(n);
            // One pixel past the piece, so that its last pixel takes its right neighbour's
            // difference; that pixel's colour falls past the buffer.
            let e = (b + 1).min(n);
            let mut k = 0;
            let piece = (
                f.get(a..e).unwrap_or(&[]),
                above.get(a..e).unwrap_or(&[]),
                extra,
            );
            shade_values(&tex.stage, tex.norm, piece, |c| {
                if let Some(p) = buf.get_mut(k) {
                    *p = c;
                }
                k += 1;
            });
            if let Some(p) = buf.get_mut(..b - a) {
                out(a as u16, p);
            }
            a = b;
        }
        self.count_lookups(
            tex.stage.antialias() != Antialias::None,
            u64::from(span.len),
        );
        true
    }

    /// [`TextureEvaluator::differences_pieces`] written straight into `dst` (one element a pixel
    /// of the span, `put` making each from its colour) instead of pieces: the same colours
    /// (the pieces are the whole span's colours cut into runs). `false` (nothing written) when
    /// the span reaches past the memory's width or past `dst`. (The renderer's, feature
    /// `differences`.)
    #[cfg(feature = "differences")]
    #[inline]
    pub(crate) fn differences_into<C, D, P>(
        &mut self,
        mem: &mut MemoryRows<'_>,
        x: u16,
        y: u16,
        span: &Span,
        dst: &mut [D],
        put: P,
    ) -> bool
    where
        C: SpanColor,
        P: Fn(C) -> D,
    {
        let Some(dst) = dst.get_mut(..usize::from(span.len)) else {
            return false;
        };
        let Some(values) = self.segment_values(mem, x, y, span) else {
            return false;
        };
        let tex = self.tex;
        if !C::one_read_into(&tex.stage, tex.norm, values, dst, &put) {
            let mut out = dst.iter_mut();
            shade_values(&tex.stage, tex.norm, values, |c: C| {
                if let Some(d) = out.next() {
                    *d = put(c);
                }
            });
        }
        self.count_lookups(
            tex.stage.antialias() != Antialias::None,
            u64::from(span.len),
        );
        true
    }

    /// The values of `span` at pixels `x..` of row `y` and of the pixels above it (from `mem`
    /// where it holds them, else evaluated one row up), both kept in `mem`, and the span's
    /// spread; `None` when the span reaches past the memory's width.
    fn segment_values<'m>(
        &mut self,
        mem: &'m mut MemoryRows<'_>,
        x: u16,
        y: u16,
        span: &Span,
    ) -> Option<(&'m [TexValue], &'m [TexValue], i64)> {
        let len = span.len;
        let (lo, hi) = (usize::from(x), usize::from(x) + usize::from(len));
        if hi > mem.width() {
            return None;
        }
        let end = x + len;
        let held = *mem.held;
        let above = y.checked_sub(1);
        // The memory row holding pixels of the row above that meet or touch the span's (none
        // for a tile's first row, whose pixels above are always extrapolated).
        let reuse = y % TILE_ROWS != 0;
        let meets = |h: &Held| reuse && h.row == above && h.lo <= end && h.hi >= x;
        let found = held.iter().position(meets);
        // The span's pixels `c0..c1` whose pixels above the memory holds (empty: none).
        let covered = found
            .and_then(|k| held.get(k))
            .map(|h| (h.lo.max(x), h.hi.min(end)))
            .filter(|(c0, c1)| c0 < c1);
        // The memory row for the pixels above: the one holding the row above, or one not
        // holding the span's row.
        let up = found
            .or_else(|| held.iter().position(|h| reuse && h.row == above))
            .unwrap_or(usize::from(held[0].row == Some(y)));
        let [r0, r1] = &mut mem.rows;
        let (up_row, cur_row) = if up == 0 { (r0, r1) } else { (r1, r0) };
        let faces = &mut mem.faces;
        if covered.is_none() {
            // None held: the span one row up, evaluated.
            let out = up_row.get_mut(lo..hi)?;
            self.values_into(&span.prev_row(), out, faces);
        }
        let extra = self.values_into(span, cur_row.get_mut(lo..hi)?, faces);
        if let Some((c0, c1)) = covered {
            // The pixels left and right of those held take the vertical difference of the
            // nearest held one (no evaluation: a triangle's edges move along its rows).
            let (f, u) = (cur_row.get(lo..hi)?, up_row.get_mut(lo..hi)?);
            let (a, b) = (usize::from(c0 - x), usize::from(c1 - x));
            let dy = |i: usize| {
                let (fi, ui) = (
                    f.get(i).map_or(0, |v| v.to_bits()),
                    u.get(i).map_or(0, |v| v.to_bits()),
                );
                fi.wrapping_sub(ui)
            };
            let (left, right) = (dy(a), dy(b - 1));
            // Only the pixels outside the held ones `a..b` (a loop over the whole span tested
            // every pixel: about 6 instructions a pixel of `scene:fire~ramp-diff`).
            let shift = |u: &mut [TexValue], f: &[TexValue], d: i32| {
                for (p, v) in u.iter_mut().zip(f) {
                    *p = TexValue::from_bits(v.to_bits().wrapping_sub(d));
                }
            };
            if let (Some(u), Some(f)) = (u.get_mut(..a), f.get(..a)) {
                shift(u, f, left);
            }
            if let (Some(u), Some(f)) = (u.get_mut(b..), f.get(b..)) {
                shift(u, f, right);
            }
        }
        // What the memory holds: the row above as it was when it holds it (its own values,
        // not the ones made here), else the pixels evaluated one row up (none above a tile's
        // first row or the image's); the span's row grows by the span.
        let (u, c) = (up, 1 - up);
        let holds_above = held.get(u).is_some_and(|h| reuse && h.row == above);
        if !holds_above {
            match above.filter(|_| reuse) {
                Some(a) => mem.hold(u, a, x, len),
                None => {
                    if let Some(h) = mem.held.get_mut(u) {
                        *h = Held::NONE;
                    }
                }
            }
        }
        mem.hold(c, y, x, len);
        let [r0, r1] = &mem.rows;
        let (up_row, cur_row) = if up == 0 { (r0, r1) } else { (r1, r0) };
        Some((cur_row.get(lo..hi)?, up_row.get(lo..hi)?, extra))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::TexPoint;
    use crate::span::{EvalMode, SpanEvaluator, SpanPlane};
    use crate::texture::Shader;

    fn textures() -> Vec<Texture<8, 256>> {
        crate::texture::tests::zebra_textures(EvalMode::Auto)
    }

    /// The planes of the tests: `(origin, ds, dsdy)`. The marble's own scale; a plane zoomed
    /// out 40 times with culling (a spread, and differences past 2^15); negative and huge
    /// coordinates; a rotated one.
    fn planes() -> [(TexPoint, TexPoint, TexPoint); 4] {
        [
            (
                TexPoint::from_f64(0.0, 0.5, 0.0),
                TexPoint::from_f64(1.0 / 128.0, 0.0, 0.0),
                TexPoint::from_f64(0.0, 0.0, 1.0 / 128.0),
            ),
            (
                TexPoint::from_f64(-3.0, 0.25, 1.0),
                TexPoint::from_f64(0.3, 0.0, 0.0),
                TexPoint::from_f64(0.0, 0.0, 0.31),
            ),
            (
                TexPoint::from_f64(-30000.0, 20000.5, -1.0),
                TexPoint::from_f64(0.02, 0.0, 0.0),
                TexPoint::from_f64(0.0, -0.03, 0.0),
            ),
            (
                TexPoint::from_f64(0.3, -0.2, 0.9),
                TexPoint::from_f64(0.004, 0.001, -0.002),
                TexPoint::from_f64(0.0, 0.004, 0.001),
            ),
        ]
    }

    /// The values of `span` and its spread, evaluated directly (any shader).
    fn values<const N: usize>(tex: &Texture<8, N>, span: &Span) -> (Vec<TexValue>, i64) {
        let mut out = Vec::new();
        let opts = EvalOptions {
            mode: EvalMode::Direct,
            ..tex.options()
        };
        let extra = match tex.shader() {
            Shader::Model(m) => {
                out.resize(usize::from(span.len), TexValue::ZERO);
                SpanEvaluator::new(m, opts)
                    .eval_values(span, &mut out)
                    .extra_width48
            }
            #[cfg(feature = "perturb")]
            Shader::Perturbed(p) => {
                let mut e = crate::material::MaterialEvaluator::new(p, opts);
                e.eval(span, |s| out.push(s.f)).extra_width48
            }
        };
        (out, extra)
    }

    use crate::span::EvalOptions;

    /// The reference colours of `span`: the differences to the right neighbour (the last
    /// pixel's, its left neighbour's) and to the pixel above, as gradients of the stage's width.
    fn reference<const N: usize>(tex: &Texture<8, N>, span: &Span) -> Vec<Rgba8888> {
        let (f, extra) = values(tex, span);
        let (up, _) = values(tex, &span.prev_row());
        let stage = tex.stage();
        let mut widths = WidthStream::new(tex.norm(), log2(N));
        let n = f.len();
        (0..n)
            .map(|i| {
                let dx = if n < 2 {
                    0
                } else if i + 1 < n {
                    f[i + 1].to_bits().wrapping_sub(f[i].to_bits())
                } else {
                    f[i].to_bits().wrapping_sub(f[i - 1].to_bits())
                };
                let dy = f[i].to_bits().wrapping_sub(up[i].to_bits());
                let g = |d: i32| i64::from(d) << 32;
                stage.shade(f[i], widths.width_with(g(dx), g(dy), extra))
            })
            .collect()
    }

    fn first_span((o, ds, dsdy): (TexPoint, TexPoint, TexPoint), len: u16) -> Span {
        Span {
            s0: o,
            ds,
            dsdy,
            len,
        }
    }

    #[test]
    fn rows_are_the_differences_of_direct_values() {
        for tex in textures() {
            for (k, p) in planes().into_iter().enumerate() {
                let tex = &tex.clone().with_culling(k == 1);
                for len in [1u16, 2, 37, 64] {
                    let first = first_span(p, len);
                    let mut cache = RowCache::<64>::new();
                    let mut mem = DifferenceMemory::<64>::new();
                    let mut ev = tex.evaluator();
                    let mut rows = ev.difference_rows(&first, &mut cache, &mut mem).unwrap();
                    let mut span = first;
                    for _ in 0..4 {
                        assert_eq!(rows.span(), span);
                        let want = reference(tex, &span);
                        let mut got = Vec::new();
                        rows.next_shade(|c| got.push(c));
                        assert_eq!(got, want, "{:?} plane {k} len {len}", tex.stage());
                        span = span.next_row();
                    }
                    // RGB565: the same colours reduced.
                    let mut ev = tex.evaluator();
                    let mut rows = ev.difference_rows(&first, &mut cache, &mut mem).unwrap();
                    let mut span = first;
                    for _ in 0..4 {
                        let want: Vec<_> = reference(tex, &span)
                            .iter()
                            .map(|c| c.to_rgb565())
                            .collect();
                        let mut got = Vec::new();
                        rows.next_shade565(|c| got.push(c));
                        assert_eq!(got, want, "{:?} plane {k} len {len}", tex.stage());
                        span = span.next_row();
                    }
                }
            }
        }
    }

    /// `shade_differences` over a plane's rows, each cut into two touching spans, across tile
    /// boundaries: each span is the reference (the memory's rows above are the plane's own, and
    /// a tile's first row extrapolated on its span is the same row), in RGBA and RGB565; a span
    /// past the memory is refused. Models only: a perturbed material's values depend (in the
    /// last bits of its perturbed coordinates) on where its span starts, so the pixels above
    /// kept from a span cut elsewhere differ from the reference's.
    #[test]
    fn spans_at_positions_are_the_reference() {
        let models: Vec<_> = textures()
            .into_iter()
            .filter(|t| matches!(t.shader(), Shader::Model(_)))
            .collect();
        assert!(models.len() >= 4, "{}", models.len());
        for tex in models {
            for (k, p) in planes().into_iter().enumerate() {
                let tex = &tex.clone().with_culling(k == 1);
                let first = first_span(p, 48);
                let mut mem = DifferenceMemory::<48>::new();
                let mut ev = tex.evaluator();
                let mut row = first;
                for y in 0..20u16 {
                    let cut = (y * 7) % 48;
                    for (x, len) in [(0, cut), (cut, 48 - cut)] {
                        let mut span = row;
                        span.s0 = TexPoint::from_bits(
                            row.s0.to_bits()[0].wrapping_add(row.ds.to_bits()[0] * i32::from(x)),
                            row.s0.to_bits()[1].wrapping_add(row.ds.to_bits()[1] * i32::from(x)),
                            row.s0.to_bits()[2].wrapping_add(row.ds.to_bits()[2] * i32::from(x)),
                        );
                        span.len = len;
                        let want = reference(tex, &span);
                        let mut got = Vec::new();
                        if y % 2 == 0 {
                            assert!(ev.shade_differences(&mut mem, x, y, &span, |c| got.push(c)));
                            assert_eq!(got, want, "plane {k} row {y} at {x}");
                        } else {
                            let f = |c: Rgb565| got.push(c.to_rgba8888());
                            assert!(ev.shade565_differences(&mut mem, x, y, &span, f));
                            let want: Vec<_> =
                                want.iter().map(|c| c.to_rgb565().to_rgba8888()).collect();
                            assert_eq!(got, want, "plane {k} row {y} at {x} (RGB565)");
                        }
                    }
                    row = row.next_row();
                }
                let span = Span { len: 8, ..first };
                assert!(!ev.shade_differences(&mut mem, 41, 0, &span, |_| ()));
            }
        }
    }

    /// The plane of `p` over `w` x `h` pixels.
    fn plane(p: (TexPoint, TexPoint, TexPoint), w: u16, h: u16) -> SpanPlane {
        SpanPlane::new(p.0, p.1, p.2, w, h).unwrap()
    }

    #[test]
    fn spans_in_any_order_are_the_rows() {
        for tex in textures() {
            for (k, p) in planes().into_iter().enumerate() {
                let tex = &tex.clone().with_culling(k == 1);
                let (w, h) = (48u16, 5u16);
                let sp = plane(p, w, h);
                // The rows, shaded whole.
                let mut want = Vec::new();
                let mut cache = RowCache::<64>::new();
                let mut mem = DifferenceMemory::<64>::new();
                let mut ev = tex.evaluator();
                let first = sp.span(0, 0, w).unwrap();
                let mut rows = ev.difference_rows(&first, &mut cache, &mut mem).unwrap();
                for _ in 0..h {
                    let mut row = Vec::new();
                    rows.next_shade565(|c| row.push(c));
                    // A span's last pixel takes its left neighbour's difference: the spans
                    // below end at 16, 32 and 48.
                    want.push(row);
                }
                let Some(setup) = ev.plane_setup(&sp) else {
                    continue;
                };
                // Spans of 16 row by row, then of uneven lengths, then column by column and in
                // a scrambled order.
                let orders: [Vec<(u16, u16, u16)>; 3] = [
                    (0..h)
                        .flat_map(|y| (0..w).step_by(16).map(move |x| (x, y, 16)))
                        .collect(),
                    (0..w)
                        .step_by(16)
                        .flat_map(|x| (0..h).map(move |y| (x, y, 16)))
                        .collect(),
                    [(32, 3), (0, 0), (16, 4), (0, 2), (32, 0), (16, 1), (0, 1)]
                        .into_iter()
                        .map(|(x, y)| (x, y, 16))
                        .collect(),
                ];
                for (i, order) in orders.iter().enumerate() {
                    let mut cache = RowCache::<64>::new();
                    let mut mem = DifferenceMemory::<64>::new();
                    let mut ev = tex.evaluator();
                    let mut spans = ev.difference_spans(&setup, &mut cache, &mut mem).unwrap();
                    for &(x, y, len) in order {
                        let mut got = Vec::new();
                        spans.shade565(x, y, len, |c| got.push(c));
                        let span = sp.span(x, y, len).unwrap();
                        let r: Vec<_> = reference(tex, &span)
                            .iter()
                            .map(|c| c.to_rgb565())
                            .collect();
                        assert_eq!(got, r, "{:?} plane {k} at {x}, {y}", tex.stage());
                        // Pixels but a span's last are the whole row's.
                        let row = &want[usize::from(y)];
                        let (x0, x1) = (usize::from(x), usize::from(x + len));
                        assert_eq!(got[..got.len() - 1], row[x0..x1 - 1]);
                        let mut full = Vec::new();
                        spans.shade(x, y, len, |c| full.push(c));
                        assert_eq!(full, reference(tex, &span));
                    }
                    drop(spans);
                    // Row by row, each span shaded twice: every row's values evaluated twice,
                    // the row above the first too, and never the row above the others (the
                    // memory holds it).
                    if i == 0 {
                        let (w, h) = (u64::from(w), u64::from(h));
                        assert_eq!(ev.stats().span.pixels, 2 * (w * h + w), "plane {k}");
                    }
                }
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// Any sequence of spans of a plane, in any order and of any lengths (inside the
        /// rectangle or not), shades each span as the reference does from direct values.
        #[test]
        fn any_sequence_of_spans_is_the_reference(
            plane_k in 0usize..4,
            filter in 0usize..8,
            spans in proptest::collection::vec((0u16..40, 0u16..6, 1u16..24), 1..24),
        ) {
            let all = textures();
            let tex = &all[filter * all.len() / 8];
            let p = planes()[plane_k];
            let sp = plane(p, 40, 6);
            let mut cache = RowCache::<64>::new();
            let mut mem = DifferenceMemory::<40>::new();
            let mut ev = tex.evaluator();
            let Some(setup) = ev.plane_setup(&sp) else {
                return Ok(());
            };
            let mut ds = ev.difference_spans(&setup, &mut cache, &mut mem).unwrap();
            for (x, y, len) in spans {
                let mut got = Vec::new();
                ds.shade(x, y, len, |c| got.push(c));
                let want = match sp.span(x, y, len) {
                    Some(span) => reference(tex, &span),
                    None => Vec::new(),
                };
                proptest::prop_assert_eq!(got, want, "{} {} {}", x, y, len);
            }
        }
    }

    #[test]
    fn too_long_rows_and_wide_planes_are_refused() {
        let tex = &textures()[0];
        let p = planes()[0];
        let mut cache = RowCache::<64>::new();
        let mut mem = DifferenceMemory::<32>::new();
        let mut ev = tex.evaluator();
        assert!(ev
            .difference_rows(&first_span(p, 33), &mut cache, &mut mem)
            .is_none());
        assert!(ev
            .difference_rows(&first_span(p, 32), &mut cache, &mut mem)
            .is_some());
        let setup = ev.plane_setup(&plane(p, 33, 4)).unwrap();
        assert!(ev.difference_spans(&setup, &mut cache, &mut mem).is_none());
        let setup = ev.plane_setup(&plane(p, 32, 4)).unwrap();
        let mut spans = ev.difference_spans(&setup, &mut cache, &mut mem).unwrap();
        // Outside the rectangle: nothing.
        let mut n = 0;
        spans.shade565(20, 0, 13, |_| n += 1);
        spans.shade(0, 4, 1, |_| n += 1);
        assert_eq!(n, 0);
        spans.shade(20, 3, 12, |_| n += 1);
        assert_eq!(n, 12);
        assert_eq!(DifferenceMemory::<32>::bytes(), 8 * 32 + 16);
    }

    #[test]
    fn counters_count_each_pixel_once_and_each_evaluation() {
        for tex in textures() {
            let first = first_span(planes()[0], 40);
            let mut cache = RowCache::<64>::new();
            let mut mem = DifferenceMemory::<64>::new();
            let mut ev = tex.evaluator();
            let mut rows = ev.difference_rows(&first, &mut cache, &mut mem).unwrap();
            for _ in 0..3 {
                rows.next_shade565(|_| {});
            }
            drop(rows);
            let s = ev.stats();
            let filtered = tex.stage().antialias() != Antialias::None;
            assert_eq!(s.filter_lookups, if filtered { 120 } else { 0 });
            assert_eq!(s.plain_lookups, if filtered { 0 } else { 120 });
            // Four rows evaluated: the one above the first, and three.
            assert_eq!(s.span.pixels, 160);
        }
    }
}
