//! Forward-differenced spans are bit-identical to direct evaluation: random spans and the named
//! hard cases (long spans, huge and negative coordinates, dense cells, steep quadrics, octaves far
//! past Nyquist).

use proptest::prelude::*;
use texcore::format::{Amplitude, MatrixEntry, QuadricCoeff, TexPoint};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, Octaves, Precision, TextureModel};
use texcore::noise::{BasisKind, Fade, NoiseBasis};
use texcore::quadric::Quadric;
use texcore::span::{EvalMode, EvalOptions, Sample, Span, SpanEvaluator, SpanStats};
use texcore::table::TableWrap;
use texcore::transform::Affine3;

fn eval<const T: usize>(
    m: &TextureModel<T>,
    mode: EvalMode,
    cull: bool,
    span: &Span,
) -> (Vec<Sample>, SpanStats) {
    let mut ev = SpanEvaluator::new(
        m,
        EvalOptions {
            mode,
            gradients: true,
            cull,
            ..Default::default()
        },
    );
    let mut out = Vec::with_capacity(usize::from(span.len));
    ev.eval(span, |s| out.push(s));
    (out, *ev.stats())
}

/// Asserts all three modes agree on `span`, with and without culling; returns the FD stats.
fn assert_exact<const T: usize>(m: &TextureModel<T>, span: &Span) -> SpanStats {
    let mut fd_stats = SpanStats::default();
    for cull in [true, false] {
        let (d, _) = eval(m, EvalMode::Direct, cull, span);
        let (f, st) = eval(m, EvalMode::Fd, cull, span);
        let (a, _) = eval(m, EvalMode::Auto, cull, span);
        assert_eq!(d.len(), usize::from(span.len));
        if let Some(i) = (0..d.len()).find(|&i| d[i] != f[i]) {
            panic!(
                "fd differs from direct at pixel {i} (cull {cull}): {:?} vs {:?}",
                f[i], d[i]
            );
        }
        if let Some(i) = (0..d.len()).find(|&i| d[i] != a[i]) {
            panic!(
                "auto differs from direct at pixel {i} (cull {cull}): {:?} vs {:?}",
                a[i], d[i]
            );
        }
        if cull {
            fd_stats = st;
        }
    }
    fd_stats
}

fn octaves<const T: usize>(
    q: Quadric,
    wrap: TableWrap,
    count: u8,
    freq: f64,
    basis: NoiseBasis,
) -> TextureModel<T> {
    TextureModel::new(q, wrap)
        .with_octaves(&Octaves {
            count,
            base: Affine3::scale(MatrixEntry::from_num(freq)),
            amplitude: Amplitude::ONE,
            rotate: true,
            basis,
            turbulence: false,
        })
        .unwrap()
}

fn marble() -> TextureModel<8> {
    octaves(
        Quadric::linear(
            QuadricCoeff::ZERO,
            QuadricCoeff::ZERO,
            QuadricCoeff::ONE,
            QuadricCoeff::ZERO,
        ),
        TableWrap::Mod,
        4,
        1.0,
        NoiseBasis::trilinear(HashKind::default()),
    )
}

fn p(s: f64, t: f64, r: f64) -> TexPoint {
    TexPoint::from_f64(s, t, r)
}

#[test]
fn zoom_in_4096_pixels_inside_one_cell() {
    let m: TextureModel<8> = octaves(
        Quadric::ZERO,
        TableWrap::Clamp,
        1,
        1.0,
        NoiseBasis::trilinear(HashKind::default()),
    );
    let span = Span {
        s0: p(3.0, 5.0, 7.0),
        ds: TexPoint::from_bits(16, 3, 1),
        dsdy: TexPoint::from_bits(0, 16, 0),
        len: 4095,
    };
    let st = assert_exact(&m, &span);
    assert_eq!(st.cell_setups, 1, "one cell for the whole span");
    assert_eq!(st.fd_pixels, 4095);
}

#[test]
fn zoom_out_crossing_4096_cells() {
    let m: TextureModel<8> = octaves(
        Quadric::ZERO,
        TableWrap::Clamp,
        1,
        1.0,
        NoiseBasis::trilinear(HashKind::default()),
    );
    // One cell per 2.2 pixels (below Nyquist), 4096+ cells.
    let span = Span {
        s0: p(-2000.25, 1.5, 0.5),
        ds: TexPoint::from_bits(29789, 0, 0),
        dsdy: TexPoint::ZERO,
        len: 9100,
    };
    let st = assert_exact(&m, &span);
    assert!(st.cell_setups >= 4096, "{}", st.cell_setups);
    // One cell per pixel and more (past Nyquist, evaluated with culling off).
    let span = Span {
        ds: TexPoint::from_bits(65536 + 4321, 0, 0),
        len: 4200,
        ..span
    };
    assert_exact(&m, &span);
}

#[test]
fn near_the_format_limits() {
    let m = marble();
    for s0 in [
        TexPoint::from_bits(i32::MAX - 1000, i32::MAX - 5, i32::MAX),
        TexPoint::from_bits(i32::MIN, i32::MIN + 7, i32::MIN + 123_456),
    ] {
        for ds in [
            TexPoint::from_bits(97, -13, 5),
            TexPoint::from_bits(-97, 13, 0),
        ] {
            let span = Span {
                s0,
                ds,
                dsdy: TexPoint::from_bits(1, 1, 1),
                len: 3000,
            };
            assert_exact(&m, &span);
        }
    }
}

#[test]
fn crossing_zero() {
    let span = Span {
        s0: p(-1.7, -0.3, -2.5),
        ds: p(0.0031, 0.0011, 0.0047),
        dsdy: p(0.0, 0.002, 0.0),
        len: 1200,
    };
    assert_exact(&marble(), &span);
}

#[test]
fn wholly_negative() {
    let span = Span {
        s0: p(-900.7, -300.3, -2.5),
        ds: p(0.0031, 0.0011, 0.0007),
        dsdy: p(0.0, 0.002, 0.0),
        len: 800,
    };
    assert_exact(&marble(), &span);
}

#[test]
fn running_backwards() {
    let span = Span {
        s0: p(1.7, 0.3, 2.5),
        ds: p(-0.0031, -0.0011, -0.0047),
        dsdy: p(0.0, -0.002, 0.0),
        len: 1200,
    };
    assert_exact(&marble(), &span);
}

#[test]
fn zero_step() {
    let span = Span {
        s0: p(1.7, 0.3, 2.5),
        ds: TexPoint::ZERO,
        dsdy: TexPoint::ZERO,
        len: 500,
    };
    let (d, _) = eval(&marble(), EvalMode::Fd, true, &span);
    assert!(d.iter().all(|s| *s == d[0]));
    assert_exact(&marble(), &span);
}

#[test]
fn starting_and_ending_on_cell_boundaries() {
    let m: TextureModel<8> = octaves(
        Quadric::ZERO,
        TableWrap::Clamp,
        1,
        1.0,
        NoiseBasis::trilinear(HashKind::default()),
    );
    // 1/64 cell per pixel from an integer point: pixel 64 is exactly on the next boundary.
    for (s0, ds) in [
        (
            TexPoint::from_bits(3 << 16, 0, 0),
            TexPoint::from_bits(1024, 0, 0),
        ),
        (
            TexPoint::from_bits(3 << 16, 0, 0),
            TexPoint::from_bits(-1024, 0, 0),
        ),
        (
            TexPoint::from_bits(3 << 16, 5 << 16, 0),
            TexPoint::from_bits(1024, 1024, 1024),
        ),
    ] {
        for len in [64u16, 65, 128, 129] {
            assert_exact(
                &m,
                &Span {
                    s0,
                    ds,
                    dsdy: TexPoint::ZERO,
                    len,
                },
            );
        }
    }
}

#[test]
fn lengths_zero_and_one() {
    for len in [0u16, 1] {
        let span = Span {
            s0: p(0.5, 0.5, 0.5),
            ds: p(0.01, 0.0, 0.0),
            dsdy: TexPoint::ZERO,
            len,
        };
        let st = assert_exact(&marble(), &span);
        assert_eq!(st.pixels, u64::from(len));
    }
}

#[test]
fn every_axis_and_oblique_directions() {
    let m = marble();
    let dirs = [
        p(0.004, 0.0, 0.0),
        p(0.0, 0.004, 0.0),
        p(0.0, 0.0, 0.004),
        p(-0.004, 0.0, 0.0),
        p(0.003, 0.002, 0.001),
        p(-0.0031, 0.0027, -0.0019),
    ];
    for ds in dirs {
        let span = Span {
            s0: p(0.37, 1.91, -0.55),
            ds,
            dsdy: p(0.001, 0.002, 0.003),
            len: 700,
        };
        assert_exact(&m, &span);
    }
}

#[test]
fn steep_quadric_mod_and_clamp() {
    // Thousands of wood rings across the span: q = 4000 (s^2 + t^2).
    for wrap in [TableWrap::Mod, TableWrap::Clamp] {
        let q =
            Quadric::from_f64([4000.0, 0.0, 0.0, 0.0, 4000.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        let m: TextureModel<8> = TextureModel::new(q, wrap)
            .with(NoiseTerm::new(
                Amplitude::ONE,
                Affine3::scale3(
                    MatrixEntry::from_num(4),
                    MatrixEntry::from_num(4),
                    MatrixEntry::ONE,
                ),
                NoiseBasis::trilinear(HashKind::default()),
            ))
            .unwrap();
        let span = Span {
            s0: p(-1.0, 0.25, 0.0),
            ds: p(0.001, 0.0, 0.0),
            dsdy: p(0.0, 0.001, 0.0),
            len: 2000,
        };
        assert_exact(&m, &span);
        let (d, _) = eval(&m, EvalMode::Fd, true, &span);
        if wrap == TableWrap::Clamp {
            // q reaches 4000: saturates nowhere near the i64 limit, clamps only in the table.
            assert!(d.iter().any(|s| s.f.to_num::<f64>() > 1000.0));
        }
    }
}

#[test]
fn eight_octaves_far_past_nyquist() {
    let m: TextureModel<8> = octaves(
        Quadric::ZERO,
        TableWrap::Clamp,
        8,
        2.0,
        NoiseBasis::trilinear(HashKind::default()),
    );
    let span = Span {
        s0: p(0.1, 0.2, 0.3),
        ds: p(0.01, 0.003, 0.0),
        dsdy: p(0.0, 0.01, 0.0),
        len: 640,
    };
    let st = assert_exact(&m, &span);
    // Octave i steps 2^(i+1) * 0.01 cells: octaves 6 and 7 (1.28 and 2.56 cells a pixel) are
    // past one cell a pixel and band-limited: octave 6 faded (amplitude 1/64 to 1/82), octave 7
    // culled (1/128 faded to 1/328, below 1/256).
    assert_eq!(st.faded_octaves, 1);
    assert_eq!(st.culled_octaves, 1);
}

/// The permutation hash where it is compiled in, else the integer hash.
fn table_hash() -> HashKind {
    #[cfg(feature = "perm-hash")]
    return HashKind::Permutation;
    #[cfg(not(feature = "perm-hash"))]
    return HashKind::Integer;
}

/// Every basis the enabled features compile in.
fn arb_basis() -> impl Strategy<Value = NoiseBasis> {
    let kinds = proptest::sample::select(vec![
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
    let hashes = proptest::sample::select(vec![table_hash(), HashKind::Integer]);
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
                  len in 0u16..700) -> Span {
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
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn random_models_and_spans_are_exact(
        terms in proptest::collection::vec(arb_term(), 0..5),
        q in proptest::array::uniform10(-50.0f64..50.0),
        wrap in prop_oneof![Just(TableWrap::Mod), Just(TableWrap::Clamp)],
        span in arb_span(),
    ) {
        let mut m: TextureModel<4> = TextureModel::new(Quadric::from_f64(q).unwrap(), wrap);
        for t in terms.into_iter().take(4) {
            m.push(t).unwrap();
        }
        assert_exact(&m, &span);
    }

    /// Every coordinate and value precision keeps forward differencing bit-identical to direct
    /// evaluation (random precisions, models and spans).
    #[test]
    fn random_precisions_are_exact(
        terms in proptest::collection::vec(arb_term(), 1..4),
        q in proptest::array::uniform10(-50.0f64..50.0),
        wrap in prop_oneof![Just(TableWrap::Mod), Just(TableWrap::Clamp)],
        span in arb_span(),
        coord_bits in 1u32..=16,
        value_bits in 1u32..=16,
    ) {
        let mut m: TextureModel<4> = TextureModel::new(Quadric::from_f64(q).unwrap(), wrap);
        for t in terms.into_iter().take(4) {
            m.push(t).unwrap();
        }
        m.set_precision(Precision::new(coord_bits, value_bits).unwrap());
        assert_exact(&m, &span);
    }
}

/// The precision study's settings (coordinate fraction bits and lattice value bits in
/// {4, 8, 12, 16}, every pair): forward differencing, auto and (for trilinear octaves) fd32 equal
/// direct evaluation on marble-like octaves, zoomed in, at the check-plane scale and far out.
#[test]
fn precision_settings_keep_fd_exact() {
    for bits_c in [4u32, 8, 12, 16] {
        for bits_v in [4u32, 8, 12, 16] {
            let prec = Precision::new(bits_c, bits_v).unwrap();
            for basis in [
                NoiseBasis::trilinear(table_hash()),
                NoiseBasis::trilinear(HashKind::Integer),
                #[cfg(feature = "smooth-fade")]
                NoiseBasis {
                    kind: BasisKind::Value,
                    fade: Fade::Smooth,
                    hash: table_hash(),
                },
                #[cfg(feature = "gradient-noise")]
                NoiseBasis {
                    kind: BasisKind::Gradient,
                    fade: Fade::Linear,
                    hash: table_hash(),
                },
            ] {
                let m: TextureModel<8> = octaves(
                    Quadric::from_f64([0., 0., 0., 0., 0., 0., 0., 0., 0.5, 0.]).unwrap(),
                    TableWrap::Mod,
                    4,
                    1.0,
                    basis,
                )
                .with_precision(prec);
                for (s0, ds, len) in [
                    (p(3.0, 5.0, 7.0), TexPoint::from_bits(16, 0, 0), 4095u16),
                    (p(0.0, 0.5, 0.0), TexPoint::from_bits(512, 0, 0), 16),
                    (
                        p(-1.5, -0.25, -2.0),
                        TexPoint::from_bits(128, 64, 256),
                        1000,
                    ),
                    (p(0.1, 0.2, 0.3), p(0.31, 0.02, -0.1), 300),
                ] {
                    let span = Span {
                        s0,
                        ds,
                        dsdy: p(0.0, 0.0, 0.0078125),
                        len,
                    };
                    assert_exact(&m, &span);
                    if basis.is_cubic() {
                        let (d, _) = eval(&m, EvalMode::Direct, true, &span);
                        let (f, _) = eval(&m, EvalMode::Fd32, true, &span);
                        assert_eq!(d, f, "fd32 {bits_c}/{bits_v} {basis:?}");
                    }
                }
            }
        }
    }
}

/// 16/16 is the native format: a model with `Precision::NATIVE` set explicitly is the default
/// model and gives the same samples; fewer bits change them.
#[test]
fn native_precision_is_the_default() {
    let m = marble();
    assert_eq!(m.precision(), Precision::NATIVE);
    assert_eq!(m.precision(), Precision::default());
    let explicit = m.clone().with_precision(Precision::new(16, 16).unwrap());
    assert_eq!(explicit, m);
    let span = Span {
        s0: p(0.1, 0.2, 0.3),
        ds: p(0.0031, -0.0007, 0.0019),
        dsdy: p(0.0005, 0.003, -0.0001),
        len: 600,
    };
    let (a, _) = eval(&m, EvalMode::Auto, true, &span);
    let (b, _) = eval(&explicit, EvalMode::Auto, true, &span);
    assert_eq!(a, b);
    for prec in [
        Precision::new(12, 16).unwrap(),
        Precision::new(16, 12).unwrap(),
    ] {
        let (c, _) = eval(&m.clone().with_precision(prec), EvalMode::Auto, true, &span);
        assert_ne!(a, c, "{prec:?}");
    }
    assert!(Precision::new(24, 16).is_err());
    assert!(Precision::new(16, 0).is_err());
    let mut q = m.clone();
    assert!(q.set_coord_bits(17).is_err());
    assert_eq!(q.precision(), Precision::NATIVE);
    q.set_coord_bits(8).unwrap();
    q.set_value_bits(4).unwrap();
    assert_eq!(q.precision(), Precision::new(8, 4).unwrap());
}

/// Largest |a - b| over two sample runs, in raw `f` units (2^-16) and raw gx units (2^-48).
fn max_errors(a: &[Sample], b: &[Sample]) -> (i64, i64) {
    let mut ef = 0i64;
    let mut eg = 0i64;
    for (x, y) in a.iter().zip(b) {
        ef = ef.max((i64::from(x.f.to_bits()) - i64::from(y.f.to_bits())).abs());
        eg = eg.max(
            (i128::from(x.gx) - i128::from(y.gx))
                .unsigned_abs()
                .min(i64::MAX as u128) as i64,
        );
    }
    (ef, eg)
}

/// Holds with and without the feature `fd32` (without it `Fd32` is exact `Fd`).
#[test]
fn fd32_drift_within_documented_bound() {
    let m = marble();
    let fv = m.noise_frac_bits();
    // Documented: per cubic term at most 5489 * 2^-(16+fv) of f plus one unit of the floor.
    let bound = (4 * (5489 >> fv) + 4 + 1 + 4) as i64;
    let mut worst = 0;
    for (k, ds) in [
        p(0.0003, 0.0001, 0.0),
        p(0.002, -0.001, 0.0007),
        p(-0.01, 0.003, 0.002),
    ]
    .into_iter()
    .enumerate()
    {
        let span = Span {
            s0: p(0.3 + k as f64, -1.2, 0.7),
            ds,
            dsdy: p(0.0, 0.001, 0.0),
            len: 2000,
        };
        let (d, _) = eval(&m, EvalMode::Direct, true, &span);
        let (f, st) = eval(&m, EvalMode::Fd32, true, &span);
        assert!(st.fd_pixels > 0);
        let (ef, _) = max_errors(&d, &f);
        worst = worst.max(ef);
        assert!(ef <= bound, "fd32 error {ef} raw units > bound {bound}");
    }
    // It is an approximation, but not a bad one: within 4 raw units of 2^-16 here.
    assert!(worst <= 4, "worst {worst}");
}

#[cfg(all(feature = "reanchor", feature = "smooth-fade"))]
#[test]
fn reanchored_smooth_noise_is_close_to_direct() {
    for kind in [
        BasisKind::Value,
        #[cfg(feature = "gradient-noise")]
        BasisKind::Gradient,
        #[cfg(feature = "mnoise")]
        BasisKind::Modified,
    ] {
        let basis = NoiseBasis {
            kind,
            fade: Fade::Smooth,
            hash: table_hash(),
        };
        let m: TextureModel<8> = octaves(Quadric::ZERO, TableWrap::Clamp, 4, 2.0, basis);
        let span = Span {
            s0: p(0.31, 0.17, -0.4),
            ds: p(0.003, 0.001, 0.0005),
            dsdy: p(0.0, 0.003, 0.0),
            len: 1500,
        };
        let (d, _) = eval(&m, EvalMode::Direct, true, &span);
        let (r, st) = eval(&m, EvalMode::Reanchored, true, &span);
        assert!(st.fd_pixels == 1500, "{kind:?}");
        let (ef, eg) = max_errors(&d, &r);
        // Bound asserted for quarter-cell Hermite segments: 2^-10 of f (measured: 2^-11).
        assert!(ef <= 64, "{kind:?}: max f error {ef} raw units");
        let gscale = d.iter().map(|s| s.gx.unsigned_abs()).max().unwrap() as i64;
        assert!(eg <= gscale / 8, "{kind:?}: gx error {eg} of {gscale}");
    }
}

/// Unrotated octaves along each lattice axis, forwards and backwards (the single-axis cell
/// set-up with its shared faces, `span::axis`, and the per-pixel face blends, `span::direct`),
/// with and without gradients, turbulent or not, with and without a quadric: every mode agrees
/// with direct evaluation.
#[test]
fn single_axis_spans_are_exact() {
    let no_grads = |m: &TextureModel<8>, mode: EvalMode, span: &Span| -> Vec<Sample> {
        let mut ev = SpanEvaluator::new(
            m,
            EvalOptions {
                mode,
                gradients: false,
                cull: true,
                ..Default::default()
            },
        );
        let mut out = Vec::new();
        ev.eval(span, |s| out.push(s));
        out
    };
    for hash in [HashKind::Integer, table_hash()] {
        for (turbulence, q) in [
            (false, Quadric::ZERO),
            (
                true,
                Quadric::from_f64([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.1]).unwrap(),
            ),
        ] {
            let m: TextureModel<8> = TextureModel::new(q, TableWrap::Mod)
                .with_octaves(&Octaves {
                    count: 4,
                    base: Affine3::scale(MatrixEntry::from_num(3.0)),
                    amplitude: Amplitude::ONE,
                    rotate: false,
                    basis: NoiseBasis::trilinear(hash),
                    turbulence,
                })
                .unwrap();
            for k in 0..3 {
                for step in [300, 2048, -2048, 9000, -40000] {
                    let mut ds = [0; 3];
                    ds[k] = step;
                    let span = Span {
                        s0: TexPoint::from_bits(-123_457, 98_765, 24_248),
                        ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
                        dsdy: TexPoint::from_bits(700, -1500, 300),
                        len: 600,
                    };
                    assert_exact(&m, &span);
                    let d = no_grads(&m, EvalMode::Direct, &span);
                    for mode in [EvalMode::Fd, EvalMode::Auto] {
                        assert_eq!(
                            no_grads(&m, mode, &span),
                            d,
                            "{mode:?} axis {k} step {step}"
                        );
                    }
                }
            }
        }
    }
}
