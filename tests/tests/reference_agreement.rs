//! texcore against the independent f64 reference: presets, noise gradients, quadric overflow
//! policies, and the hard cases of the span evaluator.

use host_sim::bridge;
use host_sim::reference::model::{RefModel, RefTerm};
use host_sim::reference::noise;
use host_sim::unit::{self, UnitConfig};
use texcore::format::{Amplitude, MatrixEntry, TexPoint};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, Octaves, TextureModel};
use texcore::noise::{split, BasisKind, Fade, NoiseBasis};
use texcore::quadric::Quadric;
use texcore::span::{EvalMode, EvalOptions, Span, SpanEvaluator};
use texcore::table::TableWrap;
use texcore::transform::Affine3;

/// Every preset on its check plane, default configuration (csat, nearest, L2, auto): at least
/// 99.9% of pixels within one 8-bit step of the reference per channel, and the largest error
/// bounded per preset (measured values in the comments).
#[test]
fn presets_within_one_step() {
    let bounds = [
        ("wood", 2.0),          // measured 0.56
        ("marble", 2.0),        // 1.07
        ("clouds", 2.0),        // 0.94
        ("water", 2.0),         // 0.74
        ("fire", 2.5),          // 1.38
        ("planet", 24.0),       // 22.7 (the sharp coastline of the legend, band-limited)
        ("planet-clouds", 2.0), // 0.58
        ("zoneplate", 2.0),     // 1.34
        ("mn-marble", 2.0),     // 0.69
        ("mn-wood", 2.0),       // 0.52
    ];
    for (name, max_bound) in bounds {
        for hash in [HashKind::Permutation, HashKind::Integer] {
            let m = unit::preset_material(name, hash).unwrap();
            let r = unit::check_material(&m, &UnitConfig::default(), 256).unwrap();
            let mm = &r.metrics;
            // The planet's legend has a sharp coastline: band-limiting fades its octaves by
            // `floor(2^32 / reach)` where the reference takes `1 / reach`, and the last bit of a
            // faded amplitude moves pixels across the coastline (about 3% of the check plane).
            let within = if name == "planet" { 0.97 } else { 0.999 };
            assert!(
                mm.within_one_step >= within,
                "{name} ({hash:?}): within one step {}",
                mm.within_one_step
            );
            assert!(
                mm.max_error <= max_bound,
                "{name} ({hash:?}): max error {} > {max_bound}",
                mm.max_error
            );
        }
    }
}

/// The unfiltered zone plate is exact: f = 50 s^2 + 50 t^2 is computed exactly in fixed point.
#[test]
fn zone_plate_unfiltered_is_exact() {
    let m = unit::preset_material("zoneplate", HashKind::default()).unwrap();
    let cfg = UnitConfig {
        aa: texcore::filter::Antialias::None,
        ..UnitConfig::default()
    };
    let r = unit::check_material(&m, &cfg, 256).unwrap();
    assert_eq!(r.metrics.max_error, 0.0);
    assert_eq!(r.metrics.within_one_step, 1.0);
}

fn lcg(s: &mut u64) -> f64 {
    *s = s
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*s >> 11) as f64 / (1u64 << 53) as f64
}

/// texcore's analytic derivative of each basis agrees with central finite differences of the f64
/// reference noise at the same lattice point.
#[test]
fn noise_gradients_match_reference_finite_differences() {
    let kinds = [BasisKind::Value, BasisKind::Gradient, BasisKind::Modified];
    let fades = [Fade::Linear, Fade::Smooth, Fade::Quintic];
    let mut st = 99u64;
    for kind in kinds {
        for fade in fades {
            for hash in [HashKind::Permutation, HashKind::Integer] {
                let b = NoiseBasis { kind, fade, hash };
                let mut worst: f64 = 0.0;
                for _ in 0..400 {
                    let u = [0, 1, 2].map(|_| lcg(&mut st) * 64.0 - 32.0);
                    // Stay away from cell faces so the difference does not straddle one.
                    let u = u.map(|v| v.floor() + 0.05 + 0.9 * (v - v.floor()));
                    let raw = u.map(|v| (v * 65536.0).round() as i32);
                    let dir = [0, 1, 2].map(|_| (lcg(&mut st) - 0.5) * 0.02);
                    let draw = dir.map(|v| (v * 65536.0).round() as i32);
                    let (cell, frac) = split(raw);
                    // Unit amplitude, fv = 13: the derivative has 61 fraction bits per pixel.
                    let data = b.cell(cell, 1 << 16, 13);
                    let got = b.derivative(&data, frac, draw, 1 << 16, 13) as f64 / 2f64.powi(61);
                    let h = 1e-4;
                    let uf = raw.map(|v| f64::from(v) / 65536.0);
                    let d = draw.map(|v| f64::from(v) / 65536.0);
                    let at = |t: f64| {
                        let p = [0, 1, 2].map(|k| uf[k] + t * d[k]);
                        noise::noise(
                            bridge::basis(kind),
                            p,
                            bridge::fade(fade),
                            hash,
                            noise::MNOISE_SCALE,
                        )
                        .value
                    };
                    let fd = (at(h) - at(-h)) / (2.0 * h);
                    worst = worst.max((got - fd).abs());
                }
                // Per-pixel steps up to 0.01 cells give slopes up to ~0.05 per pixel; the measured
                // worst error is 1.6e-6 (quintic value noise), asserted below 1e-5.
                assert!(worst < 1e-5, "{kind:?} {fade:?} {hash:?}: worst {worst}");
            }
        }
    }
}

/// A `mod` table wraps a quadric that overflows the I16F16 range and stays exact mod 1; a
/// `clamp` table saturates it.
#[test]
fn quadric_wraps_for_mod_and_saturates_for_clamp() {
    // q = 3000 s^2: at s = 100, q = 3e7, far past I16F16.
    let q = Quadric::from_f64([3000.0, 0., 0., 0., 0., 0., 0., 0., 0., 0.25]).unwrap();
    for wrap in [TableWrap::Mod, TableWrap::Clamp] {
        let m: TextureModel<1> = TextureModel::new(q, wrap);
        let span = Span {
            s0: TexPoint::from_f64(99.0, 0.0, 0.0),
            ds: TexPoint::from_f64(0.0078125, 0.0, 0.0), // 1/128: exact
            dsdy: TexPoint::ZERO,
            len: 300,
        };
        let mut ev = SpanEvaluator::new(&m, EvalOptions::default());
        let mut i = 0i64;
        ev.eval(&span, |smp| {
            let s = 99.0 + i as f64 / 128.0;
            let exact = 3000.0 * s * s + 0.25; // exactly representable in f64 here
            match wrap {
                TableWrap::Mod => {
                    let frac = f64::from(smp.f.to_bits() & 0xFFFF) / 65536.0;
                    let want = exact.rem_euclid(1.0);
                    assert!(
                        (frac - want).abs() < 1.0 / 65536.0,
                        "s={s}: {frac} vs {want}"
                    );
                }
                TableWrap::Clamp => assert_eq!(smp.f.to_bits(), i32::MAX, "s={s}"),
            }
            i += 1;
        });
        assert_eq!(i, 300);
    }
}

/// The named hard cases agree with the f64 reference within the documented tolerance: `f` within
/// `1e-3` (lattice steps rounded to 2^-16 drift by at most `len / 2` raw units per term, documented
/// in `docs/model.md` section 3; these spans keep that below the tolerance).
#[test]
fn hard_cases_agree_with_reference() {
    let marble: TextureModel<8> = TextureModel::new(
        Quadric::from_f64([0., 0., 0., 0., 0., 0., 0., 0., 0.5, 0.]).unwrap(),
        TableWrap::Clamp,
    )
    .with_octaves(&Octaves {
        count: 4,
        base: Affine3::IDENTITY,
        amplitude: Amplitude::ONE,
        rotate: false,
        basis: NoiseBasis::trilinear(HashKind::Permutation),
        turbulence: false,
    })
    .unwrap();
    let r = bridge::ref_model(&marble);
    let p = |s: f64, t: f64, r: f64| TexPoint::from_f64(s, t, r);
    let cases = [
        (
            "zoom in",
            p(3.0, 5.0, 7.0),
            TexPoint::from_bits(16, 0, 0),
            4095u16,
        ),
        (
            "crossing zero",
            p(-1.5, -0.25, -2.0),
            TexPoint::from_bits(128, 64, 256),
            1000,
        ),
        (
            "wholly negative",
            p(-900.5, -300.25, -2.5),
            TexPoint::from_bits(128, 64, 32),
            800,
        ),
        (
            "backwards",
            p(1.5, 0.25, 2.5),
            TexPoint::from_bits(-128, -64, -256),
            1000,
        ),
        ("zero step", p(1.5, 0.25, 2.5), TexPoint::ZERO, 100),
        (
            "axis s",
            p(0.25, 0.5, 0.75),
            TexPoint::from_bits(256, 0, 0),
            600,
        ),
        (
            "axis t",
            p(0.25, 0.5, 0.75),
            TexPoint::from_bits(0, 256, 0),
            600,
        ),
        (
            "axis r",
            p(0.25, 0.5, 0.75),
            TexPoint::from_bits(0, 0, 256),
            600,
        ),
        (
            "oblique",
            p(0.25, 0.5, 0.75),
            TexPoint::from_bits(192, -128, 64),
            600,
        ),
        (
            "near limit",
            TexPoint::from_bits(i32::MAX - (1 << 20), 5 << 16, 0),
            TexPoint::from_bits(64, 0, 0),
            1000,
        ),
    ];
    for (name, s0, ds, len) in cases {
        for mode in [EvalMode::Direct, EvalMode::Fd, EvalMode::Auto] {
            let mut ev = SpanEvaluator::new(
                &marble,
                EvalOptions {
                    mode,
                    gradients: false,
                    cull: false,
                    ..Default::default()
                },
            );
            let mut i = 0i64;
            let mut worst: f64 = 0.0;
            let s0f = s0.to_bits().map(|v| f64::from(v) / 65536.0);
            let dsf = ds.to_bits().map(|v| f64::from(v) / 65536.0);
            ev.eval(
                &Span {
                    s0,
                    ds,
                    dsdy: TexPoint::ZERO,
                    len,
                },
                |smp| {
                    let s = [0, 1, 2].map(|k| s0f[k] + i as f64 * dsf[k]);
                    let want = r.f(s);
                    worst = worst.max((smp.f.to_num::<f64>() - want).abs());
                    i += 1;
                },
            );
            assert_eq!(i, i64::from(len));
            assert!(
                worst < 1e-3,
                "{name} ({mode:?}): worst |f - f_ref| = {worst}"
            );
        }
    }
}

/// A steep quadric (thousands of wood rings across the span) against the reference, mod table:
/// the fixed-point `f mod 1` stays within 2^-15 of the exact value.
#[test]
fn steep_quadric_rings_match_reference() {
    let q = Quadric::from_f64([4000.0, 0., 0., 0., 4000.0, 0., 0., 0., 0., 0.]).unwrap();
    let m: TextureModel<8> = TextureModel::new(q, TableWrap::Mod)
        .with(NoiseTerm::new(
            Amplitude::ONE,
            Affine3::scale3(
                MatrixEntry::from_num(4),
                MatrixEntry::from_num(4),
                MatrixEntry::ONE,
            ),
            NoiseBasis::trilinear(HashKind::Permutation),
        ))
        .unwrap();
    let r: RefModel = bridge::ref_model(&m);
    let _unused: Option<RefTerm> = None;
    let s0 = TexPoint::from_f64(-1.0, 0.25, 0.0);
    let ds = TexPoint::from_bits(64, 0, 0);
    let mut ev = SpanEvaluator::new(
        &m,
        EvalOptions {
            gradients: false,
            ..EvalOptions::default()
        },
    );
    let mut i = 0.0;
    let mut worst: f64 = 0.0;
    ev.eval(
        &Span {
            s0,
            ds,
            dsdy: TexPoint::ZERO,
            len: 2000,
        },
        |smp| {
            let s = [-1.0 + i * 64.0 / 65536.0, 0.25, 0.0];
            let want = r.f(s).rem_euclid(1.0);
            let got = f64::from(smp.f.to_bits() & 0xFFFF) / 65536.0;
            let d = (got - want).abs();
            worst = worst.max(d.min(1.0 - d));
            i += 1.0;
        },
    );
    assert!(worst < 1e-3, "worst {worst}");
}

/// Every built-in scene (still frame, default knobs) against the f64 reference rendered over the
/// same geometry: at least 99.9% of pixels within one 8-bit step, the largest error bounded
/// (measured values in the comments).
#[test]
fn builtin_scenes_within_one_step() {
    let bounds = [
        ("wood", 1.5),      // measured 0.56
        ("marble", 1.5),    // 0.86
        ("seascape", 1.5),  // 0.68
        ("fire", 2.0),      // 1.00
        ("planet", 64.0),   // 49.7 (the sharp coastline of the legend, band-limited)
        ("moonrise", 3.0),  // 1.85
        ("zoneplate", 2.0), // 1.34
        ("torus", 1.5),     // 0.54
    ];
    assert_eq!(bounds.len(), texcore::scene::BUILTIN.len());
    for (name, bound) in bounds {
        let scene = texcore::scene::by_name(name).unwrap();
        let m = host_sim::scenes::check_scene(
            &scene,
            scene.still(),
            &UnitConfig::default(),
            HashKind::Permutation,
        )
        .unwrap();
        // The planet's coastline: see `presets_within_one_step`.
        let within = if name == "planet" { 0.99 } else { 0.999 };
        assert!(
            m.within_one_step >= within,
            "{name}: within one step {}",
            m.within_one_step
        );
        assert!(
            m.max_error <= bound,
            "{name}: max error {} > {bound}",
            m.max_error
        );
    }
}

/// The precision knobs (`docs/model.md` 3.2) against the reference's model of them: every
/// quadric-plus-noise preset on its check plane (64x64 pixels at the 256-pixel scale, 16-pixel
/// spans as `texsim check` renders them), coordinate fraction bits and lattice value bits each in
/// {4, 8, 12, 16}. texcore's `f` (table argument) agrees with [`RefModel::f_on_span`] within the
/// 5e-4 of the native preset test (measured worst over all 16 settings: 3.3e-4), and at 16/16
/// the reference is the ideal model: `f_on_span` equals `f_at` of the pixel footprint exactly.
#[test]
fn precision_knobs_agree_with_reference() {
    use host_sim::reference::model::{Footprint, Nyquist, RefPrecision};
    use host_sim::reference::table::Wrap;
    use texcore::model::Precision;
    const SIZE: u32 = 64;
    const SEG: u32 = 16;
    for name in texcore::presets::NAMES {
        let Some(p) = texcore::presets::by_name(name, HashKind::Permutation) else {
            continue;
        };
        let r = bridge::ref_model(&p.model);
        let f64v = |raw: [i32; 3]| raw.map(|v| f64::from(v) / 65536.0);
        let (dsx, dsy) = (f64v(p.plane.step_x), f64v(p.plane.step_y));
        for cb in [4u32, 8, 12, 16] {
            for vb in [4u32, 8, 12, 16] {
                let m = p
                    .model
                    .clone()
                    .with_precision(Precision::new(cb, vb).unwrap());
                let rp = RefPrecision {
                    coord_bits: cb,
                    value_bits: vb,
                };
                let mut ev = SpanEvaluator::new(
                    &m,
                    EvalOptions {
                        mode: EvalMode::Auto,
                        gradients: false,
                        cull: true,
                        ..Default::default()
                    },
                );
                let (mut worst, mut bad, mut n) = (0.0f64, 0u32, 0u32);
                for y in 0..SIZE {
                    for x0 in (0..SIZE).step_by(SEG as usize) {
                        let span = unit::plane_span(&p.plane, x0, y, SEG);
                        let s0 = f64v(span.s0.to_bits());
                        let mut i = 0u32;
                        ev.eval(&span, |smp| {
                            let want = r.f_on_span(s0, dsx, dsy, i, rp, Nyquist::Cull);
                            if cb == 16 && vb == 16 {
                                let s = [0, 1, 2].map(|k| s0[k] + f64::from(i) * dsx[k]);
                                let fp = Footprint {
                                    s,
                                    dsdx: dsx,
                                    dsdy: dsy,
                                };
                                assert_eq!(want, r.f_at(&fp, Nyquist::Cull), "{name}");
                            }
                            let (g, w) = (r.table_arg(smp.f.to_num::<f64>()), r.table_arg(want));
                            let mut d = (g - w).abs();
                            if r.wrap == Wrap::Mod {
                                d = d.min(1.0 - d);
                            }
                            worst = worst.max(d);
                            bad += u32::from(d >= 5e-4);
                            n += 1;
                            i += 1;
                        });
                    }
                }
                assert_eq!(n, SIZE * SIZE);
                assert!(
                    bad == 0,
                    "{name} F={cb} V={vb}: {bad} of {n} pixels off by 5e-4 or more (worst {worst})"
                );
            }
        }
    }
}
