//! Domain-perturbed materials (Miné & Neyret 1999): `C(f(T1 (x - x0) + S2 t(T3 (x - x1))))`.
//!
//! `t` is a vector turbulence: three uncorrelated channels of normalised fBm,
//! `t_c(x) = sum_{i<n} 2^-i s_c(R^i 2^i x) / sum_{i<n} 2^-i`, where channel `c` is the material's
//! noise basis evaluated on a lattice shifted by [`CHANNEL_OFFSETS`]`[c]` cells (so the channels are
//! decorrelated without extra tables). `S2 = diag(alpha_0, alpha_1, alpha_2)` scales the
//! perturbation and `R` is [`crate::transform::OCTAVE_ROTATION`] (optional).
//!
//! Each perturbed coordinate `y_c = (T1 (x - x0))_c + alpha_c t_c(...)` is itself a quadric-plus-noise
//! model (a linear quadric and `n` octaves), so it is evaluated by the span evaluator, exactly and
//! with forward differencing. The characteristic function then combines them per pixel:
//! - [`Characteristic::Planes`] (marble): `f = y_0`, so the material *is* one texture model;
//! - [`Characteristic::Cylinders`] (wood): `f = (y_0^2 + y_2^2) / R^2` with no square root: the colour
//!   table stores the key for radius `c` at `c^2` (see `ColorTable::from_keys` with squared
//!   positions), covering `R` rings. `f` saturates (I16F16); its gradient is `2 (y_0 grad y_0 + y_2 grad y_2) / R^2`.

use crate::format::{Amplitude, MatrixEntry, QuadricCoeff, TexValue};
use crate::model::{ModelError, Octaves, Precision, TextureModel};
use crate::noise::NoiseBasis;
use crate::quadric::Quadric;
use crate::span::{EvalOptions, Sample, Span, SpanEvaluator, SpanInfo, SpanStats};
use crate::table::TableWrap;
use crate::transform::Affine3;
use crate::wide::{div_rem_euclid_i128, mul_wide};

/// Lattice offsets (in cells) that decorrelate the three turbulence channels.
pub const CHANNEL_OFFSETS: [[i32; 3]; 3] = [[0, 0, 0], [37, 59, 101], [211, 13, 173]];

/// The material's characteristic function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Characteristic {
    /// Marble: parallel planes, `f = y_0`.
    Planes,
    /// Wood: concentric cylinders, `f = (y_0^2 + y_2^2) / rings^2`.
    Cylinders {
        /// Number of rings the colour table covers (1..=64).
        rings: u8,
    },
}

/// Parameters of a perturbed material (host- or firmware-side description).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PerturbedParams {
    /// `T1` including the `-x0` translation: maps `x` to the unperturbed pattern space.
    pub t1: Affine3,
    /// `T3` including the `-x1` translation: maps `x` to the turbulence's lattice space.
    pub t3: Affine3,
    /// Diagonal of `S2`: perturbation amplitude per channel.
    pub alpha: [Amplitude; 3],
    /// Octaves of the turbulence (1..=8).
    pub octaves: u8,
    /// Rotate successive octaves.
    pub rotate: bool,
    /// Noise basis of the turbulence.
    pub basis: NoiseBasis,
    /// Marble or wood.
    pub characteristic: Characteristic,
}

/// A perturbed material with up to `T` octaves per channel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PerturbedMaterial<const T: usize> {
    characteristic: Characteristic,
    /// Channel 0 (`y_0`), and channel 2 (`y_2`, wood only).
    y0: TextureModel<T>,
    y2: Option<TextureModel<T>>,
    wrap: TableWrap,
}

/// The normalisation `1 / sum_{i<n} 2^-i = 2^(n-1) / (2^n - 1)` as a raw I16F16 (rounded).
const fn turbulence_norm(n: u8) -> i64 {
    let n = n as i64;
    ((1i64 << (n - 1 + 16)) + ((1i64 << n) - 1) / 2) / ((1i64 << n) - 1)
}

impl<const T: usize> PerturbedMaterial<T> {
    /// Builds the material. `wrap` is the colour-table flag of the final `f`.
    pub fn new(p: &PerturbedParams, wrap: TableWrap) -> Result<Self, ModelError> {
        if p.octaves == 0 || p.octaves > 8 {
            return Err(ModelError::OutOfRange {
                what: "turbulence octaves (1..=8)",
            });
        }
        if usize::from(p.octaves) > T {
            return Err(ModelError::TooManyTerms { capacity: T });
        }
        let norm = turbulence_norm(p.octaves);
        let channel = |c: usize, channel_wrap: TableWrap| -> Result<TextureModel<T>, ModelError> {
            let m = p.t1.matrix();
            let t = p.t1.translation();
            // (T1 x)_c as a linear quadric: 2D s + 2G t + 2I r + J with D = m[c][0]/2 ...
            let half = |e: MatrixEntry| QuadricCoeff::from_bits(e.to_bits() >> 1);
            let z = QuadricCoeff::ZERO;
            let q = Quadric::from_coefficients([
                z,
                z,
                z,
                half(m[c][0]),
                z,
                z,
                half(m[c][1]),
                z,
                half(m[c][2]),
                t[c],
            ]);
            let amp = Amplitude::from_bits(
                ((i64::from(p.alpha[c].to_bits()) * norm + (1 << 15)) >> 16) as i32,
            );
            let off = CHANNEL_OFFSETS[c];
            let t3t = p.t3.translation();
            let base = p.t3.with_translation([
                MatrixEntry::from_bits(t3t[0].to_bits().wrapping_add(off[0] << 16)),
                MatrixEntry::from_bits(t3t[1].to_bits().wrapping_add(off[1] << 16)),
                MatrixEntry::from_bits(t3t[2].to_bits().wrapping_add(off[2] << 16)),
            ]);
            TextureModel::new(q, channel_wrap).with_octaves(&Octaves {
                count: p.octaves,
                base,
                amplitude: amp,
                rotate: p.rotate,
                basis: p.basis,
                turbulence: false,
            })
        };
        let (y0, y2) = match p.characteristic {
            Characteristic::Planes => (channel(0, wrap)?, None),
            Characteristic::Cylinders { rings } => {
                if rings == 0 || rings > 64 {
                    return Err(ModelError::OutOfRange {
                        what: "wood rings (1..=64)",
                    });
                }
                (
                    channel(0, TableWrap::Clamp)?,
                    Some(channel(2, TableWrap::Clamp)?),
                )
            }
        };
        Ok(PerturbedMaterial {
            characteristic: p.characteristic,
            y0,
            y2,
            wrap,
        })
    }

    /// The characteristic function.
    pub const fn characteristic(&self) -> Characteristic {
        self.characteristic
    }

    /// The colour-table wrap flag of `f`.
    pub const fn wrap(&self) -> TableWrap {
        self.wrap
    }

    /// The arithmetic precision of the turbulence channels (`docs/model.md` 3.2; all channels
    /// carry the same).
    pub const fn precision(&self) -> Precision {
        self.y0.precision()
    }

    /// Sets the arithmetic precision of every channel.
    pub fn set_precision(&mut self, precision: Precision) {
        self.y0.set_precision(precision);
        if let Some(y2) = &mut self.y2 {
            y2.set_precision(precision);
        }
    }

    /// The same material at another arithmetic precision (builder style).
    pub fn with_precision(mut self, precision: Precision) -> Self {
        self.set_precision(precision);
        self
    }

    /// The channel models (`y_0`, and `y_2` for wood).
    pub fn channels(&self) -> (&TextureModel<T>, Option<&TextureModel<T>>) {
        (&self.y0, self.y2.as_ref())
    }
}

/// Evaluates spans of a [`PerturbedMaterial`] with the span evaluator (bit-identical in every mode).
#[derive(Debug)]
pub struct MaterialEvaluator<'m, const T: usize> {
    material: &'m PerturbedMaterial<T>,
    e0: SpanEvaluator<'m, T>,
    e2: Option<SpanEvaluator<'m, T>>,
}

/// Squares of I16F16 values in i64 with 16 fraction bits, combined and divided by `rings^2`.
#[cfg_attr(not(texcore_lean), inline(always))]
fn cylinder(y0: TexValue, y2: TexValue, rings: u8) -> TexValue {
    let a = i64::from(y0.to_bits());
    let b = i64::from(y2.to_bits());
    // `rings` is 1..=64 (checked at construction); `max(1)` only removes the division-by-zero
    // panic path the compiler cannot rule out.
    let r2 = (i64::from(rings) * i64::from(rings)).max(1);
    let v = ((a * a + b * b) / r2) >> 16;
    TexValue::from_bits(v.min(i64::from(i32::MAX)) as i32)
}

/// One component of the wood gradient, `grad f = 2 (y0 grad y0 + y2 grad y2) / R^2` (48 fraction
/// bits; `R = rings`, 1..=64): the numerator is below 2^96 in magnitude (`|y| < 2^31`, `|g| <= 2^63`),
/// divided with truncation, then shifted (floor) and saturated.
///
/// `lean` (the size-lean shape, `cfg(texcore_lean)`) multiplies and divides with the shared
/// out-of-line routines of [`crate::wide`] (the truncated quotient from the Euclidean one) instead
/// of the compiler's inline 128-bit division; both give the same result (tested).
#[cfg_attr(not(texcore_lean), inline(always))]
fn cylinder_gradient(y0: TexValue, g0: i64, y2: TexValue, g2: i64, rings: u8, lean: bool) -> i64 {
    // `max(1)` only removes the division-by-zero path (`rings` is checked at construction).
    let r2 = (i128::from(rings) * i128::from(rings)).max(1);
    let q = if lean {
        let n = (mul_wide(i64::from(y0.to_bits()), g0) + mul_wide(i64::from(y2.to_bits()), g2)) * 2;
        // 0 < r2 < 2^16: the truncated quotient is the Euclidean one plus 1 for a negative n with a
        // remainder (|q| < 2^96: no overflow).
        let (q, r) = div_rem_euclid_i128(n, r2);
        if n < 0 && r != 0 {
            q + 1
        } else {
            q
        }
    } else {
        ((i128::from(y0.to_bits()) * i128::from(g0) + i128::from(y2.to_bits()) * i128::from(g2))
            * 2)
        .checked_div(r2)
        .unwrap_or(0)
    };
    crate::noise::saturate_i64(q >> 16)
}

impl<'m, const T: usize> MaterialEvaluator<'m, T> {
    /// An evaluator for `material`.
    pub fn new(material: &'m PerturbedMaterial<T>, opts: EvalOptions) -> Self {
        MaterialEvaluator {
            material,
            e0: SpanEvaluator::new(&material.y0, opts),
            e2: material.y2.as_ref().map(|m| SpanEvaluator::new(m, opts)),
        }
    }

    /// The counters of all channels.
    pub fn stats(&self) -> SpanStats {
        let mut s = *self.e0.stats();
        if let Some(e) = &self.e2 {
            s.add(e.stats());
        }
        s
    }

    /// The extra filter width of `span` from culled octaves, in `f` units (48 fraction bits): the
    /// sum over the channels, scaled for wood by the characteristic's derivative bound
    /// `2 max(|y0|, |y2|) / R^2` taken as 2 (a conservative constant for `|y| <= R`).
    pub fn extra_width48(&self, span: &Span) -> i64 {
        let e0 = self.e0.extra_width48(span);
        match &self.e2 {
            Some(e2) => e0.saturating_add(e2.extra_width48(span)).saturating_mul(2),
            None => e0,
        }
    }

    /// Evaluates `span`, calling `emit` once per pixel in order.
    ///
    /// In the size-lean shape (crate documentation, "Code size") one copy of the evaluation serves
    /// every `emit` (called through a trait object); the fast shape specialises it per `emit`.
    #[cfg_attr(not(texcore_lean), allow(unused_mut))]
    pub fn eval<F: FnMut(Sample)>(&mut self, span: &Span, mut emit: F) -> SpanInfo {
        #[cfg(texcore_lean)]
        return self.eval_with(span, &mut emit as &mut dyn FnMut(Sample));
        #[cfg(not(texcore_lean))]
        self.eval_with(span, emit)
    }

    /// The values of `span` (its first `min(len, out.len())` pixels) into `out`, as
    /// [`MaterialEvaluator::eval`] gives them (the samples' gradients are made and dropped).
    pub(crate) fn eval_values(&mut self, span: &Span, out: &mut [TexValue]) -> SpanInfo {
        let mut px = out.iter_mut();
        self.eval(span, |s| {
            if let Some(p) = px.next() {
                *p = s.f;
            }
        })
    }

    /// [`MaterialEvaluator::eval`] with `emit` as given (a trait object in the size-lean shape).
    #[cfg_attr(texcore_lean, inline(never))]
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn eval_with<F: FnMut(Sample)>(&mut self, span: &Span, mut emit: F) -> SpanInfo {
        match (self.material.characteristic, &mut self.e2) {
            (Characteristic::Cylinders { rings }, Some(e2)) => {
                // Channel 2 first into a bounded chunk, then channel 0 combines; chunks keep the
                // state on the stack small and the two channels in lockstep.
                const CHUNK: usize = 64;
                let mut buf = [Sample::default(); CHUNK];
                let mut info = SpanInfo::default();
                let mut start = 0u16;
                while start < span.len {
                    let n = (span.len - start).min(CHUNK as u16);
                    let sub = Span {
                        s0: advance(span, start),
                        len: n,
                        ..*span
                    };
                    let mut k = 0usize;
                    let i2 = e2.eval(&sub, |s| {
                        if let Some(b) = buf.get_mut(k) {
                            *b = s;
                        }
                        k += 1;
                    });
                    let mut k = 0usize;
                    let i0 = self.e0.eval(&sub, |s0| {
                        let s2 = buf.get(k).copied().unwrap_or_default();
                        k += 1;
                        let f = cylinder(s0.f, s2.f, rings);
                        let g = |g0: i64, g2: i64| {
                            cylinder_gradient(s0.f, g0, s2.f, g2, rings, cfg!(texcore_lean))
                        };
                        let (gx, gy) = if crate::span::GRADIENTS {
                            (g(s0.gx, s2.gx), g(s0.gy, s2.gy))
                        } else {
                            (0, 0)
                        };
                        emit(Sample { f, gx, gy });
                    });
                    info.extra_width48 = info
                        .extra_width48
                        .max(i0.extra_width48.saturating_add(i2.extra_width48));
                    start += n;
                }
                info
            }
            _ => self.e0.eval(span, emit),
        }
    }
}

/// `s0 + k ds` as a TexPoint (wrapping): the start of a sub-span. Sub-spans of a span keep
/// `s(i)` exact only while it stays in range, which the chunked wood evaluation respects by
/// evaluating both channels on the same sub-spans.
fn advance(span: &Span, k: u16) -> crate::format::TexPoint {
    let a = span.s0.to_bits();
    let d = span.ds.to_bits();
    let k = i32::from(k);
    crate::format::TexPoint::from_bits(
        a[0].wrapping_add(d[0].wrapping_mul(k)),
        a[1].wrapping_add(d[1].wrapping_mul(k)),
        a[2].wrapping_add(d[2].wrapping_mul(k)),
    )
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::TexPoint;
    use crate::hash::HashKind;
    use crate::span::EvalMode;

    fn params(characteristic: Characteristic) -> PerturbedParams {
        PerturbedParams {
            t1: Affine3::scale(MatrixEntry::from_num(2)),
            t3: Affine3::scale(MatrixEntry::from_num(4)),
            alpha: [Amplitude::from_num(0.3); 3],
            octaves: 4,
            rotate: true,
            basis: NoiseBasis::trilinear(HashKind::Integer),
            characteristic,
        }
    }

    fn run(m: &PerturbedMaterial<8>, mode: EvalMode, span: &Span) -> Vec<Sample> {
        let mut ev = MaterialEvaluator::new(
            m,
            EvalOptions {
                mode,
                ..EvalOptions::default()
            },
        );
        let mut v = Vec::new();
        ev.eval(span, |s| v.push(s));
        v
    }

    #[test]
    fn norm_constant() {
        assert_eq!(turbulence_norm(1), 65536);
        assert_eq!(turbulence_norm(2), 43691); // 2/3
        assert_eq!(turbulence_norm(4), 34953); // 8/15
    }

    #[test]
    fn modes_agree_for_marble_and_wood() {
        let span = Span {
            s0: TexPoint::from_f64(0.3, -0.2, 0.9),
            ds: TexPoint::from_f64(0.004, 0.001, -0.002),
            dsdy: TexPoint::from_f64(0.0, 0.004, 0.0),
            len: 300,
        };
        for ch in [
            Characteristic::Planes,
            Characteristic::Cylinders { rings: 8 },
        ] {
            let m = PerturbedMaterial::<8>::new(&params(ch), TableWrap::Mod).unwrap();
            let d = run(&m, EvalMode::Direct, &span);
            assert_eq!(d.len(), 300);
            assert_eq!(d, run(&m, EvalMode::Fd, &span), "{ch:?}");
            assert_eq!(d, run(&m, EvalMode::Auto, &span), "{ch:?}");
        }
    }

    #[test]
    fn wood_matches_squares_of_channels() {
        let m = PerturbedMaterial::<8>::new(
            &params(Characteristic::Cylinders { rings: 4 }),
            TableWrap::Clamp,
        )
        .unwrap();
        let (c0, c2) = m.channels();
        let s = TexPoint::from_f64(0.7, 0.1, -0.4);
        let one = Span {
            s0: s,
            ds: TexPoint::ZERO,
            dsdy: TexPoint::ZERO,
            len: 1,
        };
        let mut y = [TexValue::ZERO; 2];
        for (k, model) in [c0, c2.unwrap()].into_iter().enumerate() {
            let mut ev = SpanEvaluator::new(model, EvalOptions::default());
            ev.eval(&one, |smp| y[k] = smp.f);
        }
        let got = run(&m, EvalMode::Direct, &one)[0].f.to_num::<f64>();
        let want = (y[0].to_num::<f64>().powi(2) + y[1].to_num::<f64>().powi(2)) / 16.0;
        assert!((got - want).abs() < 1e-4, "{got} vs {want}");
        // Unperturbed part: y0 ~ 2 s = 1.4 plus a perturbation of at most 0.3.
        assert!((y[0].to_num::<f64>() - 1.4).abs() <= 0.31);
    }

    #[test]
    fn cylinder_gradient_shapes_agree() {
        let ys = [0, 1, -1, 65536, -65536, 12345, -98765, i32::MAX, i32::MIN];
        let gs = [
            0i64,
            1,
            -1,
            (1 << 47) + 3,
            -(1 << 47) - 5,
            123_456_789_012,
            -987_654_321_098,
            i64::MAX,
            i64::MIN,
        ];
        for rings in [0u8, 1, 3, 8, 64, 255] {
            let r2 = (i128::from(rings) * i128::from(rings)).max(1);
            for (&a, &b) in ys.iter().zip(ys.iter().rev()) {
                for &g0 in &gs {
                    for &g2 in &gs {
                        let (y0, y2) = (TexValue::from_bits(a), TexValue::from_bits(b));
                        let want = {
                            let n = (i128::from(a) * i128::from(g0)
                                + i128::from(b) * i128::from(g2))
                                * 2;
                            crate::noise::saturate_i64((n / r2) >> 16)
                        };
                        assert_eq!(cylinder_gradient(y0, g0, y2, g2, rings, false), want);
                        assert_eq!(cylinder_gradient(y0, g0, y2, g2, rings, true), want);
                    }
                }
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn cylinder_gradient_shapes_match(
            a in proptest::prelude::any::<i32>(),
            b in proptest::prelude::any::<i32>(),
            g0 in proptest::prelude::any::<i64>(),
            g2 in proptest::prelude::any::<i64>(),
            rings in proptest::prelude::any::<u8>(),
        ) {
            let (y0, y2) = (TexValue::from_bits(a), TexValue::from_bits(b));
            proptest::prop_assert_eq!(
                cylinder_gradient(y0, g0, y2, g2, rings, true),
                cylinder_gradient(y0, g0, y2, g2, rings, false)
            );
        }
    }

    #[test]
    fn rejects_bad_parameters() {
        let mut p = params(Characteristic::Planes);
        p.octaves = 0;
        assert!(PerturbedMaterial::<8>::new(&p, TableWrap::Mod).is_err());
        p.octaves = 9;
        assert!(PerturbedMaterial::<8>::new(&p, TableWrap::Mod).is_err());
        let p = params(Characteristic::Cylinders { rings: 0 });
        assert!(PerturbedMaterial::<8>::new(&p, TableWrap::Mod).is_err());
    }
}
