//! Multipass noise at native precision with texcore's hash is bit-identical to direct evaluation
//! (random models, precisions and spans, with and without gradients and culling), and its
//! reduced precisions stay within their documented error of it.

use proptest::prelude::*;
use texcore::format::{Amplitude, MatrixEntry, TexPoint};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, Octaves, Precision, TextureModel};
use texcore::multipass::{MultipassConfig, PassHash, PassPrecision};
use texcore::noise::{BasisKind, Fade, NoiseBasis};
use texcore::quadric::Quadric;
use texcore::span::{EvalMode, EvalOptions, Sample, Span, SpanEvaluator, SpanStats};
use texcore::table::TableWrap;
use texcore::transform::Affine3;

fn eval<const T: usize>(
    m: &TextureModel<T>,
    mode: EvalMode,
    gradients: bool,
    cull: bool,
    span: &Span,
) -> (Vec<Sample>, SpanStats) {
    let mut ev = SpanEvaluator::new(
        m,
        EvalOptions {
            mode,
            gradients,
            cull,
            ..Default::default()
        },
    );
    let mut out = Vec::with_capacity(usize::from(span.len));
    let info = ev.eval(span, |s| out.push(s));
    assert_eq!(info.extra_width48, ev.extra_width48(span));
    (out, *ev.stats())
}

fn assert_exact<const T: usize>(m: &TextureModel<T>, span: &Span) {
    for gradients in [true, false] {
        for cull in [true, false] {
            let (d, ds) = eval(m, EvalMode::Direct, gradients, cull, span);
            let mp = EvalMode::Multipass(MultipassConfig::EXACT);
            let (p, ps) = eval(m, mp, gradients, cull, span);
            assert_eq!(d.len(), p.len());
            if let Some(i) = (0..d.len()).find(|&i| d[i] != p[i]) {
                panic!(
                    "multipass differs from direct at pixel {i} (gradients {gradients}, cull \
                     {cull}): {:?} vs {:?}",
                    p[i], d[i]
                );
            }
            assert_eq!(ps.pixels, ds.pixels);
            assert_eq!(ps.noise_evaluations, ds.noise_evaluations);
            assert_eq!(ps.culled_octaves, ds.culled_octaves);
        }
    }
}

fn arb_basis() -> impl Strategy<Value = NoiseBasis> {
    let kinds = proptest::sample::select(vec![
        BasisKind::Value,
        BasisKind::Value,
        #[cfg(feature = "gradient-noise")]
        BasisKind::Gradient,
        #[cfg(feature = "mnoise")]
        BasisKind::Modified,
    ]);
    let fades = proptest::sample::select(vec![
        Fade::Linear,
        #[cfg(feature = "smooth-fade")]
        Fade::Smooth,
        #[cfg(feature = "smooth-fade")]
        Fade::Quintic,
    ]);
    let hashes = proptest::sample::select(vec![
        #[cfg(feature = "perm-hash")]
        HashKind::Permutation,
        HashKind::Integer,
    ]);
    (kinds, fades, hashes).prop_map(|(kind, fade, hash)| NoiseBasis { kind, fade, hash })
}

prop_compose! {
    fn arb_term()(basis in arb_basis(), amp in -2.0f64..2.0, turb in any::<bool>(),
                  m in proptest::array::uniform9(-20.0f64..20.0),
                  t in proptest::array::uniform3(-100.0f64..100.0)) -> NoiseTerm {
        NoiseTerm {
            amplitude: Amplitude::from_num(amp),
            transform: Affine3::from_f64([[m[0], m[1], m[2]], [m[3], m[4], m[5]], [m[6], m[7], m[8]]], t),
            basis,
            turbulence: turb,
        }
    }
}

prop_compose! {
    fn arb_span()(s0 in proptest::array::uniform3(any::<i32>()),
                  scale in 0u32..20,
                  ds in proptest::array::uniform3(-65536i32..65536),
                  dy in proptest::array::uniform3(-65536i32..65536),
                  len in 0u16..200) -> Span {
        let sh = |v: i32| v >> scale;
        Span {
            s0: TexPoint::from_bits(s0[0] >> (scale / 2), s0[1] >> (scale / 2), s0[2] >> (scale / 2)),
            ds: TexPoint::from_bits(sh(ds[0]), sh(ds[1]), sh(ds[2])),
            dsdy: TexPoint::from_bits(sh(dy[0]), sh(dy[1]), sh(dy[2])),
            len,
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn native_multipass_is_direct(
        terms in proptest::collection::vec(arb_term(), 0..5),
        q in proptest::array::uniform10(-50.0f64..50.0),
        wrap in prop_oneof![Just(TableWrap::Mod), Just(TableWrap::Clamp)],
        span in arb_span(),
        coord_bits in 1u32..=16,
        value_bits in 1u32..=16,
        native in any::<bool>(),
    ) {
        let mut m: TextureModel<4> = TextureModel::new(Quadric::from_f64(q).unwrap(), wrap);
        for t in terms.into_iter().take(4) {
            m.push(t).unwrap();
        }
        if !native {
            m.set_precision(Precision::new(coord_bits, value_bits).unwrap());
        }
        assert_exact(&m, &span);
    }
}

/// Marble-like octaves (the seed scenes' shape) over a long span crossing many cells.
fn marble(fade: Fade) -> TextureModel<8> {
    let q = Quadric::from_f64([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0]).unwrap();
    TextureModel::new(q, TableWrap::Mod)
        .with_octaves(&Octaves {
            count: 4,
            base: Affine3::scale(MatrixEntry::from_num(2)),
            amplitude: Amplitude::ONE,
            rotate: true,
            basis: NoiseBasis {
                kind: BasisKind::Value,
                fade,
                hash: HashKind::Integer,
            },
            turbulence: false,
        })
        .unwrap()
}

fn p(s: f64, t: f64, r: f64) -> TexPoint {
    TexPoint::from_f64(s, t, r)
}

#[test]
fn marble_band_of_320_is_exact() {
    let span = Span {
        s0: p(0.3, 0.6, 0.2),
        ds: p(0.0061, -0.0013, 0.0023),
        dsdy: p(0.0, 0.006, 0.0),
        len: 320,
    };
    assert_exact(&marble(Fade::Linear), &span);
    #[cfg(feature = "smooth-fade")]
    assert_exact(&marble(Fade::Smooth), &span);
}

/// Largest `|f|` difference in `f` raw units (2^-16).
fn max_f_error(a: &[Sample], b: &[Sample]) -> i64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (i64::from(x.f.to_bits()) - i64::from(y.f.to_bits())).abs())
        .max()
        .unwrap_or(0)
}

#[test]
fn reduced_precisions_are_bounded_near_the_origin() {
    // Inside the first 16 cells of every octave (the 4.4 channel of the 8-bit setting wraps
    // there), sum |a| = 1.875: 16.8 within 0.11 a unit amplitude, 8-bit within 0.5.
    let span = Span {
        s0: p(0.3, 0.6, 0.2),
        ds: p(0.0011, 0.0003, 0.0007),
        dsdy: p(0.0, 0.001, 0.0),
        len: 320,
    };
    let m = marble(Fade::Linear);
    let (d, _) = eval(&m, EvalMode::Direct, false, true, &span);
    let err = |prec| {
        let mode = EvalMode::Multipass(MultipassConfig::with_precision(prec));
        max_f_error(&eval(&m, mode, false, true, &span).0, &d)
    };
    let (e8, e16) = (err(PassPrecision::Bits8), err(PassPrecision::Fixed16_8));
    assert!(
        e16 > 0 && f64::from(e16 as i32) < 0.11 * 1.875 * 65536.0,
        "16.8: {e16}"
    );
    assert!(
        e8 > e16 && f64::from(e8 as i32) < 0.5 * 1.875 * 65536.0,
        "8: {e8}"
    );
}

#[test]
fn other_hashes_make_other_noise() {
    let span = Span {
        s0: p(0.3, 0.6, 0.2),
        ds: p(0.0061, -0.0013, 0.0023),
        dsdy: p(0.0, 0.006, 0.0),
        len: 64,
    };
    let m = marble(Fade::Linear);
    let run = |hash| {
        let mode = EvalMode::Multipass(MultipassConfig {
            precision: PassPrecision::Native,
            hash,
        });
        eval(&m, mode, true, true, &span).0
    };
    let t = run(PassHash::Texcore);
    let s = run(PassHash::SummedRandom);
    let x = run(PassHash::Xor);
    assert_ne!(t, s);
    assert_ne!(t, x);
    assert_ne!(s, x);
}
