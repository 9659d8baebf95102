//! The span evaluator: the texture function along a scanline span, by direct evaluation or by
//! forward differencing (Kameya & Hart), with the filter-width gradients.
//!
//! A [`Span`] is `len` pixels with solid coordinates `s(i) = s0 + i ds`; the lattice point of noise
//! term `k` at pixel `i` is `U0_k + i DU_k` (`docs/model.md` section 3). Three evaluation modes give
//! **bit-identical** [`Sample`]s:
//!
//! - [`EvalMode::Direct`]: every pixel hashes its cell corners and interpolates (the reference
//!   path of the fixed-point model).
//! - [`EvalMode::Fd`]: trilinear value-noise terms are cubics in `i` inside a cell; they are set up
//!   once per cell and stepped with three wrapping i64 additions a pixel (the value) plus two each
//!   for the two gradient components. Wrapping arithmetic is exact here: every forward difference
//!   is an integer polynomial value, and the true result fits in i64, so the sum modulo 2^64 *is*
//!   the result. Cell exits are found once per cell (one division per axis), never per pixel.
//!   Other bases (smooth fades, gradient noise, mNoise) are degree 9 or more along a span; they keep
//!   their hashed cell cached and interpolate per pixel, which is exactly the direct computation.
//!   The quadric is a quadratic in `i`: two additions a pixel.
//! - [`EvalMode::Auto`]: per span and per term, forward differencing where cells span several
//!   pixels, direct where they are shorter (set-up would cost more than it saves).
//!
//! Two cheaper, approximate modes trade accuracy for time: [`EvalMode::Fd32`] (32-bit
//! accumulators) and [`EvalMode::Reanchored`] (piecewise cubic forward differencing of the
//! higher-degree bases); their error bounds are documented on the variants and priced in the
//! accuracy report.
//!
//! Octaves past the Nyquist limit (more than half a cell per pixel along either screen direction)
//! are culled when [`EvalOptions::cull`] is set: they contribute nothing to `f` and `2 |a_k|` (in
//! `f` units) to the span's extra filter width, [`SpanInfo::extra_width48`]. Nothing here panics,
//! for any span (any coordinates, any `ds`, any length up to 65535).

use crate::format::{TexPoint, TexValue};
use crate::model::{NoiseTerm, TextureModel};
use crate::noise::{split, CellData};
use crate::quadric::QuadraticSpan;
use crate::table::TableWrap;

/// A span of pixels: `s(i) = s0 + i ds`, with the second screen direction `dsdy` for the filter
/// width (zero if unknown).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    /// Solid coordinates of pixel 0.
    pub s0: TexPoint,
    /// Step per pixel along the span (`ds/dx`).
    pub ds: TexPoint,
    /// Step per pixel in the other screen direction (`ds/dy`).
    pub dsdy: TexPoint,
    /// Number of pixels.
    pub len: u16,
}

/// How a span is evaluated; every mode gives identical samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EvalMode {
    /// Per-pixel evaluation.
    Direct,
    /// Exact forward differencing.
    Fd,
    /// Forward differencing where cells are long, direct where they are short.
    #[default]
    Auto,
    /// Cheaper forward differencing of the cubic terms with 32-bit accumulators, re-anchored to
    /// the exact polynomial every [`FD32_ANCHOR`] pixels: **not** bit-identical; the error of `f` is
    /// at most `5489 * 2^-(16 + fv)` (one anchor interval's truncation drift, `1 + 32 + C(32,2) +
    /// C(32,3)` units) plus one unit of the final floor, per cubic term. Other terms as `Fd`.
    Fd32,
    /// Terms that are not cubics along a span (smooth and quintic fades, gradient noise, mNoise:
    /// degree 9 or more) forward-differenced as cubic Hermite segments through exact values and
    /// exact derivatives at both ends of each segment (piecewise re-anchoring): approximate between
    /// anchors, exact at them. A segment covers at most [`HERMITE_SEGMENT`] pixels and at most a
    /// quarter of a cell along the span (the Hermite error grows with the fourth power of the
    /// segment's length in cells), so it pays only where cells span many pixels. Cubic terms as
    /// `Fd`.
    Reanchored,
}

/// Options of the span evaluator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EvalOptions {
    /// Evaluation strategy.
    pub mode: EvalMode,
    /// Compute the filter-width gradients `gx`, `gy` (off: they are zero and cost nothing).
    pub gradients: bool,
    /// Drop octaves past the Nyquist limit.
    pub cull: bool,
}

impl Default for EvalOptions {
    fn default() -> Self {
        EvalOptions {
            mode: EvalMode::Auto,
            gradients: true,
            cull: true,
        }
    }
}

/// The texture function and its screen gradient at one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// `f`.
    pub f: TexValue,
    /// `df/dx` with 48 fraction bits (saturating); zero when gradients are off.
    pub gx: i64,
    /// `df/dy` with 48 fraction bits (saturating); zero when gradients are off.
    pub gy: i64,
}

/// Per-span facts the shading stage needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpanInfo {
    /// Extra filter width from culled or aliasing octaves, in `f` units with 48 fraction bits.
    pub extra_width48: i64,
}

/// Activity counters (pixels, set-ups, evaluations), for `--stats` and cost accounting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpanStats {
    /// Pixels evaluated.
    pub pixels: u64,
    /// Spans evaluated.
    pub spans: u64,
    /// Lattice cell set-ups (corner hashing), per term.
    pub cell_setups: u64,
    /// Noise term samples produced (per term per pixel).
    pub noise_evaluations: u64,
    /// Octaves culled past the Nyquist limit (per term per span).
    pub culled_octaves: u64,
    /// Gradient samples (per pixel, counting the quadric and each term).
    pub gradient_evaluations: u64,
    /// Pixels produced by forward differencing of at least one term.
    pub fd_pixels: u64,
}

impl SpanStats {
    /// Adds another set of counters.
    pub fn add(&mut self, o: &SpanStats) {
        self.pixels += o.pixels;
        self.spans += o.spans;
        self.cell_setups += o.cell_setups;
        self.noise_evaluations += o.noise_evaluations;
        self.culled_octaves += o.culled_octaves;
        self.gradient_evaluations += o.gradient_evaluations;
        self.fd_pixels += o.fd_pixels;
    }
}

/// Half a cell per pixel (raw 16.16): the Nyquist limit of a lattice noise.
pub const NYQUIST_STEP: i32 = 1 << 15;

/// A term's span set-up.
#[derive(Clone, Copy, Debug, Default)]
struct TermSetup {
    u0: [i32; 3],
    du: [i32; 3],
    dy: [i32; 3],
    /// Evaluate the value.
    active: bool,
    /// Evaluate the gradient (false when past Nyquist: its width goes to `extra_width48`).
    gradient: bool,
}

#[inline(always)]
fn exact(p: TexPoint) -> [i64; 3] {
    let b = p.to_bits();
    [i64::from(b[0]), i64::from(b[1]), i64::from(b[2])]
}

#[inline(always)]
fn sat_i64(x: i128) -> i64 {
    crate::noise::saturate_i64(x)
}

/// Combines the exact quadric (48 fraction bits) and the noise sum (`48 + fv`) into `f`
/// (`docs/model.md` section 6): wrapping for `mod`, saturating for `clamp`.
#[inline(always)]
fn combine(wrap: TableWrap, q48: i128, n: i64, fv: u32) -> TexValue {
    let f48 = match wrap {
        TableWrap::Mod => (q48 as i64).wrapping_add(n >> fv),
        TableWrap::Clamp => sat_i64(q48).saturating_add(n >> fv),
    };
    TexValue::from_bits((f48 >> 32) as i32)
}

/// Pixels from fraction `f` (0..65535) until the lattice coordinate leaves the cell, stepping `d`.
#[inline(always)]
fn pixels_in_cell_axis(f: u32, d: i32) -> u32 {
    if d > 0 {
        (0xFFFF - f) / d as u32 + 1
    } else if d < 0 {
        f / d.unsigned_abs() + 1
    } else {
        u32::MAX
    }
}

#[inline(always)]
fn pixels_in_cell(frac: [u32; 3], d: [i32; 3]) -> u32 {
    pixels_in_cell_axis(frac[0], d[0])
        .min(pixels_in_cell_axis(frac[1], d[1]))
        .min(pixels_in_cell_axis(frac[2], d[2]))
}

/// The per-span part of the model evaluation shared by every mode.
struct Setup<const T: usize> {
    terms: [TermSetup; T],
    quad: QuadraticSpan,
    quad_zero: bool,
    gqx: [i128; 2],
    gqy: [i128; 2],
    extra_width48: i64,
}

/// Forward-difference state of a cubic term inside one cell (exact, 64-bit).
#[derive(Clone, Copy, Debug, Default)]
struct Cubic {
    p: [i64; 4],
    gx: [i64; 3],
    gy: [i64; 3],
}

/// Forward-difference state with 32-bit accumulators (the exact state's top 32 bits at the anchor).
#[derive(Clone, Copy, Debug, Default)]
struct Cubic32 {
    p: [i32; 4],
    gx: [i32; 3],
    gy: [i32; 3],
}

/// A re-anchored cubic Hermite segment: value (cubic), x-gradient (its derivative, quadratic) and
/// y-gradient (linear between the anchors).
#[derive(Clone, Copy, Debug, Default)]
struct Hermite {
    p: [i64; 4],
    gx: [i64; 3],
    gy: [i64; 2],
}

/// How one term is evaluated along the current span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Strategy {
    Off,
    /// Per-pixel hashing and interpolation.
    Direct,
    /// Cached cell, per-pixel interpolation (exact).
    Cached,
    /// Exact 64-bit forward differencing of the cubic.
    Fd,
    /// 32-bit forward differencing, re-anchored every [`FD32_ANCHOR`] pixels.
    Fd32,
    /// Cubic Hermite segments of at most [`HERMITE_SEGMENT`] pixels (approximate).
    Hermite,
}

/// Re-anchoring interval of [`EvalMode::Fd32`], in pixels.
pub const FD32_ANCHOR: u32 = 32;
/// Longest Hermite segment of [`EvalMode::Reanchored`], in pixels.
pub const HERMITE_SEGMENT: u32 = 16;

#[derive(Clone, Copy, Debug)]
struct TermRun {
    strategy: Strategy,
    data: CellData,
    cell: [u16; 3],
    cached: bool,
    remaining: u32,
    u: [i32; 3],
    fd: Cubic,
    fd32: Cubic32,
    herm: Hermite,
}

impl Default for TermRun {
    fn default() -> Self {
        TermRun {
            strategy: Strategy::Off,
            data: CellData::Value([0; 8]),
            cell: [0; 3],
            cached: false,
            remaining: 0,
            u: [0; 3],
            fd: Cubic::default(),
            fd32: Cubic32::default(),
            herm: Hermite::default(),
        }
    }
}

/// Evaluates spans of one model.
#[derive(Debug)]
pub struct SpanEvaluator<'m, const T: usize> {
    model: &'m TextureModel<T>,
    opts: EvalOptions,
    stats: SpanStats,
}

impl<'m, const T: usize> SpanEvaluator<'m, T> {
    /// An evaluator for `model` with `opts`.
    pub fn new(model: &'m TextureModel<T>, opts: EvalOptions) -> Self {
        SpanEvaluator {
            model,
            opts,
            stats: SpanStats::default(),
        }
    }

    /// The counters so far.
    pub fn stats(&self) -> &SpanStats {
        &self.stats
    }

    /// The options.
    pub fn options(&self) -> EvalOptions {
        self.opts
    }

    fn setup(&mut self, span: &Span) -> Setup<T> {
        let m = self.model;
        let s0 = exact(span.s0);
        let ds = exact(span.ds);
        let dy = exact(span.dsdy);
        let quad = m.quadric().along(s0, ds);
        let grads = self.opts.gradients;
        let mut terms = [TermSetup::default(); T];
        let mut extra: i64 = 0;
        for (ts, term) in terms.iter_mut().zip(m.terms()) {
            let (du, dyl, beyond) = lattice_steps(term, span);
            if beyond {
                extra = extra.saturating_add(culled_width48(term));
                if self.opts.cull {
                    self.stats.culled_octaves += 1;
                    continue;
                }
            }
            *ts = TermSetup {
                u0: term.transform.apply_point(span.s0),
                du,
                dy: dyl,
                active: true,
                gradient: grads && !beyond,
            };
        }
        let (gqx, gqy) = if grads {
            (
                m.quadric().derivative_along(s0, ds, ds),
                m.quadric().derivative_along(s0, ds, dy),
            )
        } else {
            ([0, 0], [0, 0])
        };
        Setup {
            terms,
            quad_zero: quad.is_zero(),
            quad,
            gqx,
            gqy,
            extra_width48: extra,
        }
    }

    /// The extra filter width of `span` from octaves past the Nyquist limit (what
    /// [`SpanInfo::extra_width48`] of [`SpanEvaluator::eval`] will be), without evaluating it.
    pub fn extra_width48(&self, span: &Span) -> i64 {
        let mut extra: i64 = 0;
        for term in self.model.terms() {
            if lattice_steps(term, span).2 {
                extra = extra.saturating_add(culled_width48(term));
            }
        }
        extra
    }

    /// Evaluates `span`, calling `emit` once per pixel in order. Returns the span's facts.
    pub fn eval<F: FnMut(Sample)>(&mut self, span: &Span, emit: F) -> SpanInfo {
        let setup = self.setup(span);
        self.stats.spans += 1;
        self.stats.pixels += u64::from(span.len);
        let info = SpanInfo {
            extra_width48: setup.extra_width48,
        };
        let mode = self.opts.mode;
        self.run(
            span.len,
            &setup,
            |ts: &TermSetup, cubic: bool| match mode {
                EvalMode::Direct => Strategy::Direct,
                EvalMode::Fd => {
                    if cubic {
                        Strategy::Fd
                    } else {
                        Strategy::Cached
                    }
                }
                EvalMode::Auto => {
                    // Forward differencing pays when a cell spans at least 4 pixels on every axis.
                    if ts.du.iter().any(|d| d.unsigned_abs() > 1 << 14) {
                        Strategy::Direct
                    } else if cubic {
                        Strategy::Fd
                    } else {
                        Strategy::Cached
                    }
                }
                EvalMode::Fd32 => {
                    if cubic {
                        Strategy::Fd32
                    } else {
                        Strategy::Cached
                    }
                }
                EvalMode::Reanchored => {
                    if cubic {
                        Strategy::Fd
                    } else {
                        Strategy::Hermite
                    }
                }
            },
            emit,
        );
        info
    }

    /// The evaluation loop. `choose(term setup, is_cubic)` picks each term's strategy.
    fn run<D, F>(&mut self, len: u16, setup: &Setup<T>, choose: D, mut emit: F)
    where
        D: Fn(&TermSetup, bool) -> Strategy,
        F: FnMut(Sample),
    {
        let m = self.model;
        let fv = m.noise_frac_bits();
        let wrap = m.wrap();
        let grads = self.opts.gradients;
        let terms = m.terms();
        // A model holds at most T terms; `min` lets the compiler see it (no bounds checks).
        let n = terms.len().min(T);

        let mut runs = [TermRun::default(); T];
        for (k, r) in runs.iter_mut().enumerate().take(n) {
            let ts = &setup.terms[k];
            if ts.active {
                r.strategy = choose(ts, terms[k].basis.is_cubic());
                r.u = ts.u0;
                if r.strategy == Strategy::Direct {
                    r.remaining = u32::MAX;
                }
            }
        }

        // Quadric forward differences (exact, wrapping i128).
        let qc = setup.quad.c;
        let mut q = qc[0];
        let mut dq = qc[1].wrapping_add(qc[2]);
        let ddq = qc[2].wrapping_mul(2);
        let mut gqx = setup.gqx[0];
        let mut gqy = setup.gqy[0];

        let len = u32::from(len);
        let mut i = 0u32;
        while i < len {
            // (Re-)anchor every term whose segment ended; the segment is the shortest of them.
            let mut seg = len - i;
            for k in 0..n {
                let r = &mut runs[k];
                if r.strategy == Strategy::Off {
                    continue;
                }
                if r.remaining == 0 {
                    let ts = &setup.terms[k];
                    let term = &terms[k];
                    let (amp, _) = amp_and_sign(term);
                    let (cell, frac) = split(r.u);
                    if !r.cached || cell != r.cell {
                        r.data = term.basis.cell(cell, amp, fv);
                        r.cell = cell;
                        r.cached = true;
                        self.stats.cell_setups += 1;
                    }
                    let in_cell = pixels_in_cell(frac, ts.du);
                    let want_g = grads && ts.gradient;
                    r.remaining = match (r.strategy, &r.data) {
                        (Strategy::Fd, CellData::Value(v)) => {
                            r.fd = cubic_setup(v, frac, ts, want_g);
                            in_cell
                        }
                        (Strategy::Fd32, CellData::Value(v)) => {
                            r.fd32 = narrow(&cubic_setup(v, frac, ts, want_g));
                            in_cell.min(FD32_ANCHOR)
                        }
                        (Strategy::Hermite, data) => {
                            // At most a quarter of a cell along the span, at most 16 pixels.
                            let step = ts.du.iter().map(|d| d.unsigned_abs()).max().unwrap_or(0);
                            let quarter = (1u32 << 14) / step.max(1);
                            let l = in_cell
                                .min(HERMITE_SEGMENT)
                                .min(quarter.max(2))
                                .min(len - i);
                            r.herm = hermite_setup(term, data, r.u, ts, l, amp, fv, want_g);
                            l
                        }
                        _ => in_cell,
                    };
                }
                seg = seg.min(r.remaining);
            }

            for _ in 0..seg {
                let mut nsum: i64 = 0;
                let mut gxn: i64 = 0;
                let mut gyn: i64 = 0;
                let mut any_fd = false;
                for k in 0..n {
                    let r = &mut runs[k];
                    let ts = &setup.terms[k];
                    let term = &terms[k];
                    let (amp, neg) = amp_and_sign(term);
                    let want_g = grads && ts.gradient;
                    let (mut v, mut gx, mut gy) = match r.strategy {
                        Strategy::Off => continue,
                        Strategy::Fd => {
                            any_fd = true;
                            let c = &mut r.fd;
                            let out = (c.p[0], c.gx[0], c.gy[0]);
                            c.p[0] = c.p[0].wrapping_add(c.p[1]);
                            c.p[1] = c.p[1].wrapping_add(c.p[2]);
                            c.p[2] = c.p[2].wrapping_add(c.p[3]);
                            if want_g {
                                c.gx[0] = c.gx[0].wrapping_add(c.gx[1]);
                                c.gx[1] = c.gx[1].wrapping_add(c.gx[2]);
                                c.gy[0] = c.gy[0].wrapping_add(c.gy[1]);
                                c.gy[1] = c.gy[1].wrapping_add(c.gy[2]);
                            }
                            out
                        }
                        Strategy::Fd32 => {
                            any_fd = true;
                            let c = &mut r.fd32;
                            let out = (
                                i64::from(c.p[0]) << 32,
                                i64::from(c.gx[0]) << 32,
                                i64::from(c.gy[0]) << 32,
                            );
                            c.p[0] = c.p[0].wrapping_add(c.p[1]);
                            c.p[1] = c.p[1].wrapping_add(c.p[2]);
                            c.p[2] = c.p[2].wrapping_add(c.p[3]);
                            if want_g {
                                c.gx[0] = c.gx[0].wrapping_add(c.gx[1]);
                                c.gx[1] = c.gx[1].wrapping_add(c.gx[2]);
                                c.gy[0] = c.gy[0].wrapping_add(c.gy[1]);
                                c.gy[1] = c.gy[1].wrapping_add(c.gy[2]);
                            }
                            out
                        }
                        Strategy::Hermite => {
                            any_fd = true;
                            let c = &mut r.herm;
                            let out = (c.p[0], c.gx[0], c.gy[0]);
                            c.p[0] = c.p[0].wrapping_add(c.p[1]);
                            c.p[1] = c.p[1].wrapping_add(c.p[2]);
                            c.p[2] = c.p[2].wrapping_add(c.p[3]);
                            if want_g {
                                c.gx[0] = c.gx[0].wrapping_add(c.gx[1]);
                                c.gx[1] = c.gx[1].wrapping_add(c.gx[2]);
                                c.gy[0] = c.gy[0].wrapping_add(c.gy[1]);
                            }
                            out
                        }
                        Strategy::Cached => {
                            let (_, frac) = split(r.u);
                            eval_term(term, &r.data, frac, ts, amp, fv, want_g)
                        }
                        Strategy::Direct => {
                            let (cell, frac) = split(r.u);
                            let data = term.basis.cell(cell, amp, fv);
                            self.stats.cell_setups += 1;
                            eval_term(term, &data, frac, ts, amp, fv, want_g)
                        }
                    };
                    if term.turbulence {
                        if v < 0 {
                            v = v.wrapping_neg();
                            gx = gx.wrapping_neg();
                            gy = gy.wrapping_neg();
                        }
                        if neg {
                            v = v.wrapping_neg();
                            gx = gx.wrapping_neg();
                            gy = gy.wrapping_neg();
                        }
                    }
                    nsum = nsum.wrapping_add(v);
                    if want_g {
                        gxn = gxn.saturating_add(gx);
                        gyn = gyn.saturating_add(gy);
                        self.stats.gradient_evaluations += 1;
                    }
                    self.stats.noise_evaluations += 1;
                    r.u = [
                        r.u[0].wrapping_add(ts.du[0]),
                        r.u[1].wrapping_add(ts.du[1]),
                        r.u[2].wrapping_add(ts.du[2]),
                    ];
                    r.remaining = r.remaining.saturating_sub(1);
                    if r.strategy == Strategy::Direct {
                        r.remaining = u32::MAX;
                    }
                }
                if any_fd {
                    self.stats.fd_pixels += 1;
                }

                let f = combine(wrap, if setup.quad_zero { 0 } else { q }, nsum, fv);
                let sample = if grads {
                    self.stats.gradient_evaluations += 1;
                    Sample {
                        f,
                        gx: sat_i64(gqx).saturating_add(gxn >> fv),
                        gy: sat_i64(gqy).saturating_add(gyn >> fv),
                    }
                } else {
                    Sample { f, gx: 0, gy: 0 }
                };
                emit(sample);

                if !setup.quad_zero {
                    q = q.wrapping_add(dq);
                    dq = dq.wrapping_add(ddq);
                }
                if grads {
                    gqx = gqx.wrapping_add(setup.gqx[1]);
                    gqy = gqy.wrapping_add(setup.gqy[1]);
                }
            }
            i += seg;
        }
    }
}

/// Amplitude used for the corner values and the sign applied afterwards (turbulence).
#[inline(always)]
fn amp_and_sign(term: &NoiseTerm) -> (i32, bool) {
    let a = term.amplitude.to_bits();
    if term.turbulence {
        (a.wrapping_abs(), a < 0)
    } else {
        (a, false)
    }
}

/// The top 32 bits (floor) of an exact forward-difference state.
fn narrow(c: &Cubic) -> Cubic32 {
    let h = |x: i64| (x >> 32) as i32;
    Cubic32 {
        p: [h(c.p[0]), h(c.p[1]), h(c.p[2]), h(c.p[3])],
        gx: [h(c.gx[0]), h(c.gx[1]), h(c.gx[2])],
        gy: [h(c.gy[0]), h(c.gy[1]), h(c.gy[2])],
    }
}

/// Division of an i128 by a positive divisor, rounded to nearest (ties away from zero), saturated.
fn div_round(x: i128, d: i128) -> i64 {
    let q = if x >= 0 {
        (x + d / 2) / d
    } else {
        (x - d / 2) / d
    };
    sat_i64(q)
}

/// Cubic Hermite segment over pixels `0..l` through the exact values and derivatives at pixels
/// `0` and `l - 1` (both inside the current cell).
#[allow(clippy::too_many_arguments)]
fn hermite_setup(
    term: &NoiseTerm,
    data: &CellData,
    u: [i32; 3],
    ts: &TermSetup,
    l: u32,
    amp: i32,
    fv: u32,
    grads: bool,
) -> Hermite {
    let (_, f0) = split(u);
    let b = &term.basis;
    let p0 = b.sample(data, f0, amp, fv);
    let g0 = b.derivative(data, f0, ts.du, amp, fv);
    let y0 = if grads {
        b.derivative(data, f0, ts.dy, amp, fv)
    } else {
        0
    };
    if l <= 1 {
        return Hermite {
            p: [p0, 0, 0, 0],
            gx: [g0, 0, 0],
            gy: [y0, 0],
        };
    }
    let mm = l - 1;
    let (_, fm) = split([
        u[0].wrapping_add(ts.du[0].wrapping_mul(mm as i32)),
        u[1].wrapping_add(ts.du[1].wrapping_mul(mm as i32)),
        u[2].wrapping_add(ts.du[2].wrapping_mul(mm as i32)),
    ]);
    let pm = b.sample(data, fm, amp, fv);
    let gm = b.derivative(data, fm, ts.du, amp, fv);
    let ym = if grads {
        b.derivative(data, fm, ts.dy, amp, fv)
    } else {
        0
    };
    let m = i128::from(mm);
    let (p0w, pmw, g0w, gmw) = (
        i128::from(p0),
        i128::from(pm),
        i128::from(g0),
        i128::from(gm),
    );
    let c2 = div_round(3 * (pmw - p0w) - (2 * g0w + gmw) * m, m * m);
    let c3 = div_round(2 * (p0w - pmw) + (g0w + gmw) * m, m * m * m);
    let c1 = g0;
    Hermite {
        p: [
            p0,
            c1.wrapping_add(c2).wrapping_add(c3),
            c2.wrapping_mul(2).wrapping_add(c3.wrapping_mul(6)),
            c3.wrapping_mul(6),
        ],
        gx: [
            g0,
            c2.wrapping_mul(2).wrapping_add(c3.wrapping_mul(3)),
            c3.wrapping_mul(6),
        ],
        gy: [y0, div_round(i128::from(ym) - i128::from(y0), m)],
    }
}

/// A term's lattice steps along the span and across it, and whether either passes the Nyquist
/// limit in any component.
#[inline]
fn lattice_steps(term: &NoiseTerm, span: &Span) -> ([i32; 3], [i32; 3], bool) {
    let du = term.transform.apply_vector(span.ds);
    let dy = term.transform.apply_vector(span.dsdy);
    let beyond = du
        .iter()
        .chain(dy.iter())
        .any(|c| c.unsigned_abs() > NYQUIST_STEP as u32);
    (du, dy, beyond)
}

/// The filter width a culled (or aliasing) term adds: `2 |a|` in `f` units, 48 fraction bits.
#[inline]
fn culled_width48(term: &NoiseTerm) -> i64 {
    (i64::from(term.amplitude.to_bits().unsigned_abs()) * 2) << 32
}

/// Value and gradients of one term at a fraction of its cached cell.
#[inline(always)]
fn eval_term(
    term: &NoiseTerm,
    data: &CellData,
    frac: [u32; 3],
    ts: &TermSetup,
    amp: i32,
    fv: u32,
    want_g: bool,
) -> (i64, i64, i64) {
    let b = &term.basis;
    let v = b.sample(data, frac, amp, fv);
    if want_g {
        (
            v,
            b.derivative(data, frac, ts.du, amp, fv),
            b.derivative(data, frac, ts.dy, amp, fv),
        )
    } else {
        (v, 0, 0)
    }
}

/// Forward-difference start values of a trilinear term in a new cell: the exact polynomial
/// sampled at the first pixels (fractions continued past the cell, wrapping) and differenced.
fn cubic_setup(v: &[i32; 8], frac: [u32; 3], ts: &TermSetup, grads: bool) -> Cubic {
    use crate::noise::value::{directional, interpolate};
    let w = |j: i64| -> [i64; 3] {
        [
            i64::from(frac[0]) + j * i64::from(ts.du[0]),
            i64::from(frac[1]) + j * i64::from(ts.du[1]),
            i64::from(frac[2]) + j * i64::from(ts.du[2]),
        ]
    };
    let p0 = interpolate(v, w(0));
    let p1 = interpolate(v, w(1));
    let p2 = interpolate(v, w(2));
    let p3 = interpolate(v, w(3));
    let d1 = p1.wrapping_sub(p0);
    let d2 = p2.wrapping_sub(p1).wrapping_sub(d1);
    let d3 = p3
        .wrapping_sub(p2.wrapping_mul(3))
        .wrapping_add(p1.wrapping_mul(3))
        .wrapping_sub(p0);
    let mut c = Cubic {
        p: [p0, d1, d2, d3],
        ..Cubic::default()
    };
    if grads {
        let du = [
            i64::from(ts.du[0]),
            i64::from(ts.du[1]),
            i64::from(ts.du[2]),
        ];
        let dy = [
            i64::from(ts.dy[0]),
            i64::from(ts.dy[1]),
            i64::from(ts.dy[2]),
        ];
        let quad = |d: [i64; 3]| -> [i64; 3] {
            let g0 = directional(v, w(0), d);
            let g1 = directional(v, w(1), d);
            let g2 = directional(v, w(2), d);
            let e1 = g1.wrapping_sub(g0);
            [g0, e1, g2.wrapping_sub(g1).wrapping_sub(e1)]
        };
        c.gx = quad(du);
        c.gy = quad(dy);
    }
    c
}

#[cfg(feature = "defmt")]
impl defmt::Format for Sample {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Sample(f raw {=i32}, gx {=i64}, gy {=i64})",
            self.f.to_bits(),
            self.gx,
            self.gy
        );
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Span {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Span(s0 {}, ds {}, dsdy {}, len {=u16})",
            self.s0,
            self.ds,
            self.dsdy,
            self.len
        );
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry, QuadricCoeff};
    use crate::hash::HashKind;
    use crate::model::{NoiseTerm, Octaves};
    use crate::noise::{BasisKind, Fade, NoiseBasis};
    use crate::quadric::Quadric;
    use crate::transform::Affine3;

    fn marble() -> TextureModel<8> {
        TextureModel::new(
            Quadric::linear(
                QuadricCoeff::ZERO,
                QuadricCoeff::ZERO,
                QuadricCoeff::ONE,
                QuadricCoeff::ZERO,
            ),
            TableWrap::Mod,
        )
        .with_octaves(&Octaves {
            count: 4,
            base: Affine3::scale(MatrixEntry::from_num(4)),
            amplitude: Amplitude::ONE,
            rotate: true,
            basis: NoiseBasis::trilinear(HashKind::Integer),
            turbulence: false,
        })
        .unwrap()
    }

    fn run<const T: usize>(m: &TextureModel<T>, mode: EvalMode, span: &Span) -> Vec<Sample> {
        let mut ev = SpanEvaluator::new(
            m,
            EvalOptions {
                mode,
                gradients: true,
                cull: true,
            },
        );
        let mut out = Vec::new();
        ev.eval(span, |s| out.push(s));
        out
    }

    #[test]
    fn fd_equals_direct_on_marble() {
        let m = marble();
        let span = Span {
            s0: TexPoint::from_f64(0.1, 0.2, 0.3),
            ds: TexPoint::from_f64(0.0031, -0.0007, 0.0019),
            dsdy: TexPoint::from_f64(0.0005, 0.003, -0.0001),
            len: 600,
        };
        let d = run(&m, EvalMode::Direct, &span);
        let f = run(&m, EvalMode::Fd, &span);
        let a = run(&m, EvalMode::Auto, &span);
        assert_eq!(d.len(), 600);
        assert_eq!(d, f);
        assert_eq!(d, a);
    }

    #[test]
    fn all_bases_identical_across_modes() {
        let kinds = [
            BasisKind::Value,
            #[cfg(feature = "gradient-noise")]
            BasisKind::Gradient,
            #[cfg(feature = "mnoise")]
            BasisKind::Modified,
        ];
        for kind in kinds {
            for fade in [
                Fade::Linear,
                #[cfg(feature = "smooth-fade")]
                Fade::Smooth,
            ] {
                let mut m: TextureModel<4> = TextureModel::new(
                    Quadric::from_f64([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap(),
                    TableWrap::Clamp,
                );
                let mut t = NoiseTerm::new(
                    Amplitude::from_num(-0.75),
                    Affine3::scale(MatrixEntry::from_num(3)),
                    NoiseBasis {
                        kind,
                        fade,
                        hash: HashKind::Integer,
                    },
                );
                m.push(t).unwrap();
                t.turbulence = true;
                t.transform = Affine3::scale(MatrixEntry::from_num(7));
                m.push(t).unwrap();
                let span = Span {
                    s0: TexPoint::from_f64(-1.3, 0.7, 2.1),
                    ds: TexPoint::from_f64(0.01, 0.004, -0.002),
                    dsdy: TexPoint::from_f64(0.0, 0.01, 0.0),
                    len: 400,
                };
                let d = run(&m, EvalMode::Direct, &span);
                assert_eq!(d, run(&m, EvalMode::Fd, &span), "{kind:?} {fade:?}");
                assert_eq!(d, run(&m, EvalMode::Auto, &span), "{kind:?} {fade:?}");
            }
        }
    }

    #[test]
    fn culling_counts_and_widens() {
        let m = marble();
        // A far-away span: 2 cells per pixel at the base octave already.
        let span = Span {
            s0: TexPoint::from_f64(0.0, 0.0, 0.0),
            ds: TexPoint::from_f64(0.5, 0.0, 0.0),
            dsdy: TexPoint::ZERO,
            len: 10,
        };
        let mut ev = SpanEvaluator::new(&m, EvalOptions::default());
        let info = ev.eval(&span, |_| {});
        assert_eq!(ev.stats().culled_octaves, 4);
        assert_eq!(ev.stats().noise_evaluations, 0);
        // 2 * (1 + 1/2 + 1/4 + 1/8) = 3.75
        assert_eq!(info.extra_width48, (3 * 65536 + 49152) << 32);
    }

    #[test]
    fn gradients_off_costs_nothing() {
        let m = marble();
        let span = Span {
            s0: TexPoint::from_f64(0.1, 0.2, 0.3),
            ds: TexPoint::from_f64(0.003, 0.0, 0.0),
            dsdy: TexPoint::from_f64(0.0, 0.003, 0.0),
            len: 100,
        };
        let mut ev = SpanEvaluator::new(
            &m,
            EvalOptions {
                gradients: false,
                ..EvalOptions::default()
            },
        );
        ev.eval(&span, |s| assert_eq!((s.gx, s.gy), (0, 0)));
        assert_eq!(ev.stats().gradient_evaluations, 0);
        assert_eq!(ev.stats().noise_evaluations, 400);
    }
}
