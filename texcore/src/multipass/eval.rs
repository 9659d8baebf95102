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
use crate::format::TexValue;
use crate::model::TextureModel;
use crate::noise::{saturate_i64 as sat_i64, split, BasisKind};
use crate::span::{EvalOptions, Sample, Setup, SpanStats};
use crate::table::TableWrap;

/// Pixels per band of a span evaluated by multipass noise: one sample chunk
/// ([`crate::span::SAMPLE_CHUNK`]), about 2 KB of band buffers on the stack.
pub const MULTIPASS_BAND: usize = crate::span::SAMPLE_CHUNK;

/// Evaluates the `len` pixels of a span of `model` by multipass noise with `config`, from the
/// span's set-up (the span evaluator's: lattice starts and steps, band-limiting, the quadric),
/// calling `emit` once per pixel in order, counting into `stats` as the span evaluator does (a
/// cell set-up per term and pixel: every pixel hashes its eight corners). `opts.mode` is not
/// consulted; `opts.gradients` is.
pub(crate) fn eval_span<const T: usize>(
    model: &TextureModel<T>,
    opts: EvalOptions,
    config: MultipassConfig,
    setup: &Setup<T>,
    len: u16,
    stats: &mut SpanStats,
    emit: &mut dyn FnMut(Sample),
) {
    let grads = crate::span::GRADIENTS && opts.gradients;
    let fv = model.noise_frac_bits();
    let vb = model.precision().value_bits();
    let wrap = model.wrap();
    let (quad, gqx, gqy) = (
        &setup.quadric().quad,
        setup.quadric().gqx,
        setup.quadric().gqy,
    );

    let mut band = Band::<MULTIPASS_BAND>::new();
    let mut nsum: [i64; MULTIPASS_BAND];
    let mut gxn: [i64; MULTIPASS_BAND];
    let mut gyn: [i64; MULTIPASS_BAND];
    let mut tgx = [0i64; MULTIPASS_BAND];
    let mut tgy = [0i64; MULTIPASS_BAND];
    let len = usize::from(len);
    let mut start = 0usize;
    while start < len {
        let n = (len - start).min(MULTIPASS_BAND);
        // The band's sums (the first `n <= MULTIPASS_BAND` entries are the band's pixels).
        nsum = [0; MULTIPASS_BAND];
        gxn = [0; MULTIPASS_BAND];
        gyn = [0; MULTIPASS_BAND];
        for (ts, term) in setup.terms.iter().zip(model.terms()) {
            if !ts.active {
                continue;
            }
            let want_g = grads && ts.gradient;
            let (du, dyl, a) = (ts.du, ts.dy, ts.amp);
            let (amp, neg) = if term.turbulence {
                (a.wrapping_abs(), a < 0)
            } else {
                (a, false)
            };
            let off = start as i32;
            let [u0, u1, u2] = ts.u0;
            let ub = [
                u0.wrapping_add(du[0].wrapping_mul(off)),
                u1.wrapping_add(du[1].wrapping_mul(off)),
                u2.wrapping_add(du[2].wrapping_mul(off)),
            ];
            stats.noise_evaluations += n as u64;
            stats.cell_setups += n as u64;
            if want_g {
                stats.gradient_evaluations += n as u64;
            }
            // Adds one pixel's contribution of the term to the band's sums.
            let add = |(s, gxs, gys): (&mut i64, &mut i64, &mut i64),
                       (v, gx, gy): (i64, i64, i64)| {
                let (mut v, mut gx, mut gy) = (v, gx, gy);
                if term.turbulence && ((v < 0) != neg) {
                    v = v.wrapping_neg();
                    gx = gx.wrapping_neg();
                    gy = gy.wrapping_neg();
                }
                *s = s.wrapping_add(v);
                if want_g {
                    *gxs = gxs.saturating_add(gx);
                    *gys = gys.saturating_add(gy);
                }
            };
            let sums = nsum
                .iter_mut()
                .zip(gxn.iter_mut())
                .zip(gyn.iter_mut())
                .take(n);
            let sums = sums.map(|((s, gx), gy)| (s, gx, gy));
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
                    band.derivative_into(term.basis.fade, du, &mut tgx);
                    band.derivative_into(term.basis.fade, dyl, &mut tgy);
                }
                let vals = band.values().iter().zip(tgx.iter()).zip(tgy.iter());
                for (sum, ((&v, &gx), &gy)) in sums.zip(vals) {
                    add(sum, (v, gx, gy));
                }
            } else {
                // Not a lattice value noise: per pixel, as the direct path.
                let b = &term.basis;
                let mut u = ub;
                for sum in sums {
                    let (cell, frac) = split(u);
                    let data = b.cell_bits(cell, amp, fv, vb);
                    let v = b.sample(&data, frac, amp, fv);
                    let (gx, gy) = if want_g {
                        (
                            b.derivative(&data, frac, du, amp, fv),
                            b.derivative(&data, frac, dyl, amp, fv),
                        )
                    } else {
                        (0, 0)
                    };
                    add(sum, (v, gx, gy));
                    u = [
                        u[0].wrapping_add(du[0]),
                        u[1].wrapping_add(du[1]),
                        u[2].wrapping_add(du[2]),
                    ];
                }
            }
        }
        let sums = nsum.iter().zip(gxn.iter()).zip(gyn.iter()).take(n);
        for (i, ((&ns, &gxs), &gys)) in sums.enumerate() {
            let p = (start + i) as i64;
            let q48 = quad.at(p);
            let f48 = match wrap {
                TableWrap::Mod => (q48 as i64).wrapping_add(ns >> fv),
                TableWrap::Clamp => sat_i64(q48).saturating_add(ns >> fv),
            };
            let f = TexValue::from_bits((f48 >> 32) as i32);
            let sample = if grads {
                stats.gradient_evaluations += 1;
                let pi = i128::from(p);
                let gq = |g: [i128; 2]| sat_i64(g[0].wrapping_add(g[1].wrapping_mul(pi)));
                Sample {
                    f,
                    gx: gq(gqx).saturating_add(gxs >> fv),
                    gy: gq(gqy).saturating_add(gys >> fv),
                }
            } else {
                Sample { f, gx: 0, gy: 0 }
            };
            emit(sample);
        }
        start += n;
    }
}
