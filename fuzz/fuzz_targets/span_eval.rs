//! Span evaluator: random models (up to four noise terms of every basis, fade, hash and
//! turbulence, any transform and quadric bits, any precision, both table wraps) and random spans
//! (any start, step and second direction, up to 1023 pixels). The exact modes (`Fd`, `Auto`)
//! and `Fused` (approximate only in the rows of `SpanEvaluator::rows`) give the same samples as
//! `Direct`, bit for bit, with and without culling and gradients; the
//! approximate modes (`Fd32`, `Reanchored`) never panic and give one sample per pixel. Every
//! band-limiting setting (either fade rule, any floor and share) is drawn too.
#![no_main]

use libfuzzer_sys::fuzz_target;
use texcore::bandlimit::{BandLimit, FadeWeight};
use texcore::format::{Amplitude, MatrixEntry, QuadricCoeff, TexPoint};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, Octaves, Precision, TextureModel};
use texcore::noise::{BasisKind, Fade, NoiseBasis};
use texcore::quadric::Quadric;
use texcore::span::{EvalMode, EvalOptions, Sample, Span, SpanEvaluator};
use texcore::table::TableWrap;
use texcore::transform::Affine3;
use texcore_fuzz::Bytes;

fn basis(b: &mut Bytes) -> NoiseBasis {
    NoiseBasis {
        kind: b.pick(&[BasisKind::Value, BasisKind::Gradient, BasisKind::Modified]),
        fade: b.pick(&[Fade::Linear, Fade::Smooth, Fade::Quintic]),
        hash: b.pick(&[HashKind::Permutation, HashKind::Integer]),
    }
}

fn entry(b: &mut Bytes) -> MatrixEntry {
    MatrixEntry::from_bits(b.i32_scaled())
}

fn transform(b: &mut Bytes) -> Affine3 {
    let m = [
        [entry(b), entry(b), entry(b)],
        [entry(b), entry(b), entry(b)],
        [entry(b), entry(b), entry(b)],
    ];
    Affine3::new(m, [entry(b), entry(b), entry(b)])
}

fn point(b: &mut Bytes) -> TexPoint {
    TexPoint::from_bits(b.i32_scaled(), b.i32_scaled(), b.i32_scaled())
}

fn model(b: &mut Bytes) -> TextureModel<4> {
    let coeffs = core::array::from_fn(|_| QuadricCoeff::from_bits(b.i32_scaled()));
    let wrap = b.pick(&[TableWrap::Mod, TableWrap::Clamp]);
    let mut m = TextureModel::new(Quadric::from_coefficients(coeffs), wrap);
    for _ in 0..b.below(5) {
        // A rejected term (amplitude budget, capacity) leaves the model as it was.
        if b.below(4) == 0 {
            let o = Octaves {
                count: b.below(5),
                base: transform(b),
                amplitude: Amplitude::from_bits(b.i32_scaled()),
                rotate: b.bool(),
                basis: basis(b),
                turbulence: b.bool(),
            };
            let _ = m.push_octaves(&o);
        } else {
            let t = NoiseTerm {
                amplitude: Amplitude::from_bits(b.i32_scaled()),
                transform: transform(b),
                basis: basis(b),
                turbulence: b.bool(),
            };
            let _ = m.push(t);
        }
    }
    if b.bool() {
        if let Ok(p) = Precision::new(u32::from(b.below(18)), u32::from(b.below(18))) {
            m.set_precision(p);
        }
    }
    m
}

/// A band-limiting setting: either rule, a floor in [1/16, 1] and a share in [0, 1).
fn band_limit(b: &mut Bytes) -> BandLimit {
    let weight = b.pick(&[FadeWeight::Footprint, FadeWeight::Reach]);
    let floor = (1 << 12) + u32::from(b.u16()) % ((1 << 16) - (1 << 12) + 1);
    BandLimit::new(weight, floor, u32::from(b.u16())).unwrap_or_default()
}

fn eval(
    m: &TextureModel<4>,
    mode: EvalMode,
    gradients: bool,
    cull: bool,
    band_limit: BandLimit,
    span: &Span,
) -> Vec<Sample> {
    let mut ev = SpanEvaluator::new(
        m,
        EvalOptions {
            mode,
            gradients,
            cull,
            band_limit,
        },
    );
    let mut out = Vec::with_capacity(usize::from(span.len));
    ev.eval(span, |s| out.push(s));
    out
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes::new(data);
    let m = model(&mut b);
    let span = Span {
        s0: point(&mut b),
        ds: point(&mut b),
        dsdy: point(&mut b),
        len: b.u16() & 1023,
    };
    let band = band_limit(&mut b);
    let n = usize::from(span.len);
    for (gradients, cull) in [(true, true), (true, false), (false, true)] {
        let direct = eval(&m, EvalMode::Direct, gradients, cull, band, &span);
        assert_eq!(direct.len(), n);
        // `Fused` differs only in the rows of `SpanEvaluator::rows`: spans are `Fd`'s.
        for mode in [EvalMode::Fd, EvalMode::Auto, EvalMode::Fused] {
            let got = eval(&m, mode, gradients, cull, band, &span);
            if let Some(i) = (0..n).find(|&i| got[i] != direct[i]) {
                panic!(
                    "{mode:?} differs from Direct at pixel {i} (gradients {gradients}, cull \
                     {cull}, {band:?}): {:?} vs {:?}\nmodel {m:?}\nspan {span:?}",
                    got[i], direct[i]
                );
            }
        }
    }
    for mode in [EvalMode::Fd32, EvalMode::Reanchored] {
        assert_eq!(eval(&m, mode, true, true, band, &span).len(), n);
    }
});
