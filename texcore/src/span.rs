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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

/// Forward-difference state of a cubic term inside one cell.
#[derive(Clone, Copy, Debug, Default)]
struct Cubic {
    p: [i64; 4],
    gx: [i64; 3],
    gy: [i64; 3],
}

#[derive(Clone, Copy, Debug)]
enum TermState {
    Off,
    /// Forward differencing inside the current cell.
    Fd(Cubic),
    /// Cached cell, per-pixel interpolation.
    Cached(CellData),
    /// Per-pixel hashing and interpolation.
    Direct,
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
            let t = &term.transform;
            let du = t.apply_vector(span.ds);
            let dyl = t.apply_vector(span.dsdy);
            let beyond = du
                .iter()
                .chain(dyl.iter())
                .any(|c| c.unsigned_abs() > NYQUIST_STEP as u32);
            let a2 = (i64::from(term.amplitude.to_bits().unsigned_abs()) * 2) << 32;
            if beyond {
                extra = extra.saturating_add(a2);
                if self.opts.cull {
                    self.stats.culled_octaves += 1;
                    continue;
                }
            }
            *ts = TermSetup {
                u0: t.apply_point(span.s0),
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

    /// Evaluates `span`, calling `emit` once per pixel in order. Returns the span's facts.
    pub fn eval<F: FnMut(Sample)>(&mut self, span: &Span, emit: F) -> SpanInfo {
        let setup = self.setup(span);
        self.stats.spans += 1;
        self.stats.pixels += u64::from(span.len);
        let info = SpanInfo {
            extra_width48: setup.extra_width48,
        };
        match self.opts.mode {
            EvalMode::Direct => self.run(span.len, &setup, |_, _| false, emit),
            EvalMode::Fd => self.run(span.len, &setup, |_, _| true, emit),
            EvalMode::Auto => self.run(
                span.len,
                &setup,
                // Forward differencing pays when a cell spans at least 4 pixels on every axis.
                |ts: &TermSetup, _| ts.du.iter().all(|d| d.unsigned_abs() <= 1 << 14),
                emit,
            ),
        }
        info
    }

    /// The evaluation loop. `use_fd(term, k)` decides per term whether to forward-difference.
    fn run<D, F>(&mut self, len: u16, setup: &Setup<T>, use_fd: D, mut emit: F)
    where
        D: Fn(&TermSetup, usize) -> bool,
        F: FnMut(Sample),
    {
        let m = self.model;
        let fv = m.noise_frac_bits();
        let wrap = m.wrap();
        let grads = self.opts.gradients;
        let terms = m.terms();
        let n = terms.len();

        let mut state = [TermState::Off; T];
        let mut remaining = [0u32; T];
        let mut upoint = [[0i32; 3]; T];
        for k in 0..n {
            let ts = &setup.terms[k];
            if !ts.active {
                continue;
            }
            upoint[k] = ts.u0;
            state[k] = if terms[k].basis.is_cubic() && use_fd(ts, k) {
                TermState::Fd(Cubic::default())
            } else if use_fd(ts, k) {
                TermState::Cached(CellData::Value([0; 8]))
            } else {
                TermState::Direct
            };
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
            // Set up every forward-differenced or cached term whose cell ended.
            let mut seg = len - i;
            for k in 0..n {
                match state[k] {
                    TermState::Fd(_) | TermState::Cached(_) => {
                        if remaining[k] == 0 {
                            let ts = &setup.terms[k];
                            let (cell, frac) = split(upoint[k]);
                            let (amp, _) = Self::amp_and_sign(&terms[k]);
                            let basis = &terms[k].basis;
                            let data = basis.cell(cell, amp, fv);
                            self.stats.cell_setups += 1;
                            remaining[k] = pixels_in_cell(frac, ts.du);
                            state[k] = match (state[k], data) {
                                (TermState::Fd(_), CellData::Value(v)) => {
                                    TermState::Fd(cubic_setup(&v, frac, ts, grads && ts.gradient))
                                }
                                _ => TermState::Cached(data),
                            };
                        }
                        seg = seg.min(remaining[k]);
                    }
                    _ => {}
                }
            }

            for _ in 0..seg {
                let mut nsum: i64 = 0;
                let mut gxn: i64 = 0;
                let mut gyn: i64 = 0;
                let mut any_fd = false;
                for k in 0..n {
                    let ts = &setup.terms[k];
                    let term = &terms[k];
                    let (amp, neg) = Self::amp_and_sign(term);
                    let want_g = grads && ts.gradient;
                    let (mut v, mut gx, mut gy) = match &mut state[k] {
                        TermState::Off => continue,
                        TermState::Fd(c) => {
                            any_fd = true;
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
                        TermState::Cached(data) => {
                            let (_, frac) = split(upoint[k]);
                            eval_term(term, data, frac, ts, amp, fv, want_g)
                        }
                        TermState::Direct => {
                            let (cell, frac) = split(upoint[k]);
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
                    upoint[k] = [
                        upoint[k][0].wrapping_add(ts.du[0]),
                        upoint[k][1].wrapping_add(ts.du[1]),
                        upoint[k][2].wrapping_add(ts.du[2]),
                    ];
                    if remaining[k] != 0 {
                        remaining[k] -= 1;
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
