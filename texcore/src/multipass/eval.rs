//! A span evaluated by multipass noise ([`crate::span::EvalMode::Multipass`]): the span is cut
//! into bands of [`MULTIPASS_BAND`] pixels, and each value-noise term runs its passes over a whole
//! band before the next term starts; the band's samples are then assembled as the direct
//! evaluation assembles them (the exact quadric, the wrapping noise sum, the saturating gradient
//! sums, turbulence, culling).
//!
//! Guarantee: with [`MultipassConfig::EXACT`] the samples are bit-identical to
//! [`crate::span::EvalMode::Direct`] for every model (tested). Terms that are not value noise
//! (gradient noise, mNoise) are evaluated per pixel exactly as the direct path does.

use super::band::{Band, PassTerm};
use super::MultipassConfig;
use crate::bandlimit::{build_spread_width48, term_band};
use crate::format::TexValue;
use crate::model::{quantize_coord, TextureModel};
use crate::noise::{split, BasisKind};
use crate::span::{EvalOptions, Sample, Span, SpanInfo, SpanStats};
use crate::table::TableWrap;

/// Pixels per band of a span evaluated by multipass noise: one sample chunk
/// ([`crate::span::SAMPLE_CHUNK`]), about 2 KB of band buffers on the stack.
pub const MULTIPASS_BAND: usize = crate::span::SAMPLE_CHUNK;

/// Evaluates `span` of `model` by multipass noise with `config`, calling `emit` once per pixel in
/// order, counting into `stats` as the span evaluator does (a cell set-up per term and pixel: every
/// pixel hashes its eight corners). `opts.mode` is not consulted; `opts.gradients` and
/// `opts.cull` are.
pub fn eval_span<const T: usize>(
    model: &TextureModel<T>,
    opts: EvalOptions,
    config: MultipassConfig,
    span: &Span,
    stats: &mut SpanStats,
    emit: &mut dyn FnMut(Sample),
) -> SpanInfo {
    let grads = crate::span::GRADIENTS && opts.gradients;
    let fv = model.noise_frac_bits();
    let vb = model.precision().value_bits();
    let cb = model.precision().coord_bits();
    let wrap = model.wrap();
    stats.spans += 1;
    stats.pixels += u64::from(span.len);

    let bits = |p: crate::format::TexPoint| p.to_bits().map(i64::from);
    let (s0, ds, dy) = (bits(span.s0), bits(span.ds), bits(span.dsdy));
    let quad = model.quadric().along(s0, ds);
    let gqx = model.quadric().derivative_along(s0, ds, ds);
    let gqy = model.quadric().derivative_along(s0, ds, dy);

    // Per-term set-up: lattice origin, steps and band-limiting, as the direct path
    // (`crate::bandlimit`): the span's faded amplitude, culling and spread.
    let mut variance: u64 = 0;
    let mut setups = [([0i32; 3], [0i32; 3], [0i32; 3], false, false, 0i32); T];
    for (st, term) in setups.iter_mut().zip(model.terms()) {
        let du = term.transform.apply_vector(span.ds);
        let dyl = term.transform.apply_vector(span.dsdy);
        let b = term_band(term, du, dyl, opts.cull);
        variance = variance.saturating_add(b.variance);
        if !b.active {
            stats.culled_octaves += 1;
            continue;
        }
        if b.amplitude != term.amplitude.to_bits() {
            stats.faded_octaves += 1;
        }
        let mut u0 = term.transform.apply_point(span.s0);
        let mut du = du;
        if cb < 16 {
            u0 = u0.map(|c| quantize_coord(c, cb));
            du = du.map(|c| quantize_coord(c, cb));
        }
        *st = (u0, du, dyl, true, grads && b.gradient, b.amplitude);
    }
    let info = SpanInfo {
        extra_width48: build_spread_width48(variance),
    };

    let mut band = Band::<MULTIPASS_BAND>::new();
    let mut nsum = [0i64; MULTIPASS_BAND];
    let mut gxn = [0i64; MULTIPASS_BAND];
    let mut gyn = [0i64; MULTIPASS_BAND];
    let mut tgx = [0i64; MULTIPASS_BAND];
    let mut tgy = [0i64; MULTIPASS_BAND];
    let len = usize::from(span.len);
    let mut start = 0usize;
    while start < len {
        let n = (len - start).min(MULTIPASS_BAND);
        nsum[..n].fill(0);
        gxn[..n].fill(0);
        gyn[..n].fill(0);
        for (&(u0, du, dyl, active, want_g, a), term) in setups.iter().zip(model.terms()) {
            if !active {
                continue;
            }
            let (amp, neg) = if term.turbulence {
                (a.wrapping_abs(), a < 0)
            } else {
                (a, false)
            };
            let off = start as i32;
            let ub = [0, 1, 2].map(|k| u0[k].wrapping_add(du[k].wrapping_mul(off)));
            stats.noise_evaluations += n as u64;
            stats.cell_setups += n as u64;
            if want_g {
                stats.gradient_evaluations += n as u64;
            }
            if matches!(term.basis.kind, BasisKind::Value) {
                let pt = PassTerm {
                    hash: term.basis.hash,
                    fade: term.basis.fade,
                    amp_raw: amp,
                    fv,
                    value_bits: vb,
                    config,
                    gradients: want_g,
                };
                band.run(&pt, ub, du, n);
                if want_g {
                    band.derivative_into(term.basis.fade, du, &mut tgx[..n]);
                    band.derivative_into(term.basis.fade, dyl, &mut tgy[..n]);
                }
                let vals = band.values();
                for i in 0..n {
                    let (mut v, mut gx, mut gy) = (vals[i], tgx[i], tgy[i]);
                    if term.turbulence && ((v < 0) != neg) {
                        v = v.wrapping_neg();
                        gx = gx.wrapping_neg();
                        gy = gy.wrapping_neg();
                    }
                    nsum[i] = nsum[i].wrapping_add(v);
                    if want_g {
                        gxn[i] = gxn[i].saturating_add(gx);
                        gyn[i] = gyn[i].saturating_add(gy);
                    }
                }
            } else {
                // Not a lattice value noise: per pixel, as the direct path.
                let b = &term.basis;
                for i in 0..n {
                    let u = [0, 1, 2].map(|k| ub[k].wrapping_add(du[k].wrapping_mul(i as i32)));
                    let (cell, frac) = split(u);
                    let data = b.cell_bits(cell, amp, fv, vb);
                    let mut v = b.sample(&data, frac, amp, fv);
                    let (mut gx, mut gy) = if want_g {
                        (
                            b.derivative(&data, frac, du, amp, fv),
                            b.derivative(&data, frac, dyl, amp, fv),
                        )
                    } else {
                        (0, 0)
                    };
                    if term.turbulence && ((v < 0) != neg) {
                        v = v.wrapping_neg();
                        gx = gx.wrapping_neg();
                        gy = gy.wrapping_neg();
                    }
                    nsum[i] = nsum[i].wrapping_add(v);
                    if want_g {
                        gxn[i] = gxn[i].saturating_add(gx);
                        gyn[i] = gyn[i].saturating_add(gy);
                    }
                }
            }
        }
        for i in 0..n {
            let p = (start + i) as i64;
            let q48 = quad.at(p);
            let f48 = match wrap {
                TableWrap::Mod => (q48 as i64).wrapping_add(nsum[i] >> fv),
                TableWrap::Clamp => sat_i64(q48).saturating_add(nsum[i] >> fv),
            };
            let f = TexValue::from_bits((f48 >> 32) as i32);
            let sample = if grads {
                stats.gradient_evaluations += 1;
                let pi = i128::from(p);
                let gq = |g: [i128; 2]| sat_i64(g[0].wrapping_add(g[1].wrapping_mul(pi)));
                Sample {
                    f,
                    gx: gq(gqx).saturating_add(gxn[i] >> fv),
                    gy: gq(gqy).saturating_add(gyn[i] >> fv),
                }
            } else {
                Sample { f, gx: 0, gy: 0 }
            };
            emit(sample);
        }
        start += n;
    }
    info
}

fn sat_i64(x: i128) -> i64 {
    x.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64
}
