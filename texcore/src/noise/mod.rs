//! Noise bases (raw kernels): lattice value noise, Perlin's gradient noise and Olano's mNoise,
//! with their fades and analytic gradients.
//!
//! A basis is evaluated in two steps so that spans can cache the expensive part:
//! [`NoiseBasis::cell`] hashes the eight corners of a lattice cell once ([`CellData`]), and
//! [`NoiseBasis::sample`] / [`NoiseBasis::derivative`] interpolate inside it per pixel. Both steps
//! are the model of `docs/model.md` section 4, bit for bit, on every target.
//!
//! Output units: a term's contribution has `48 + fv` fraction bits (the model's noise accumulator),
//! where `fv` is chosen per model from the amplitudes so that sums never overflow.

pub mod fade;
#[cfg(any(feature = "gradient-noise", feature = "mnoise"))]
pub mod gradient;
#[cfg(feature = "mnoise")]
pub mod mnoise;
pub mod value;

pub use fade::Fade;

use crate::hash::HashKind;

/// Which kind of lattice noise a basis is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BasisKind {
    /// Lattice value noise (random values at lattice points, interpolated).
    #[default]
    Value,
    /// Perlin's improved gradient noise (edge-centre gradients).
    #[cfg(feature = "gradient-noise")]
    Gradient,
    /// Olano's mNoise: corner gradients with the table-free `x^2 mod 61` hash; dimension reducible.
    #[cfg(feature = "mnoise")]
    Modified,
}

/// A noise basis: kind, fade and lattice hash. Every combination is valid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NoiseBasis {
    /// Value, gradient or mNoise.
    pub kind: BasisKind,
    /// The interpolant.
    pub fade: Fade,
    /// The lattice hash (ignored by mNoise, which always uses `x^2 mod 61`).
    pub hash: HashKind,
}

/// The hashed corners of one lattice cell, cached while a span stays inside the cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellData {
    /// Amplitude-scaled value-noise corner values `v'_c`.
    Value([i32; 8]),
    /// Corner gradients of gradient noise or mNoise.
    #[cfg(any(feature = "gradient-noise", feature = "mnoise"))]
    Gradient([gradient::Grad; 8]),
}

/// Splits a lattice point (raw 16.16 per axis, wrapping) into its cell and fraction.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn split(u: [i32; 3]) -> ([u16; 3], [u32; 3]) {
    (
        [
            (u[0] >> 16) as u16,
            (u[1] >> 16) as u16,
            (u[2] >> 16) as u16,
        ],
        [
            (u[0] & 0xFFFF) as u32,
            (u[1] & 0xFFFF) as u32,
            (u[2] & 0xFFFF) as u32,
        ],
    )
}

/// Saturates an i128 to the i64 range. One out-of-line copy in the size-lean shape with filter
/// widths (feature `gradients`: most callers saturate gradients); left to the compiler in the
/// lean builds without them (one or two callers).
#[cfg_attr(not(texcore_lean), inline(always))]
#[cfg_attr(all(texcore_lean, feature = "gradients"), inline(never))]
pub(crate) fn saturate_i64(x: i128) -> i64 {
    if x > i128::from(i64::MAX) {
        i64::MAX
    } else if x < i128::from(i64::MIN) {
        i64::MIN
    } else {
        x as i64
    }
}

/// `a * b` of two `i64` in `i128`: in the size-lean shape (`lean`) through the shared
/// out-of-line [`crate::wide::mul_wide`].
#[inline(always)]
fn mul64(a: i64, b: i64, lean: bool) -> i128 {
    if lean {
        crate::wide::mul_wide(a, b)
    } else {
        i128::from(a) * i128::from(b)
    }
}

/// `a * b` in `i128` (the callers' products stay in range): in the size-lean shape (`lean`)
/// through the shared out-of-line [`crate::wide::mul_i128`].
#[inline(always)]
fn mul(a: i128, b: i64, lean: bool) -> i128 {
    if lean {
        crate::wide::mul_i128(a, i128::from(b))
    } else {
        a * i128::from(b)
    }
}

#[cfg(any(feature = "gradient-noise", feature = "mnoise"))]
#[cfg_attr(not(texcore_lean), inline(always))]
fn scale_n16(n16: i64, amp_raw: i32, fv: u32) -> i64 {
    (i64::from(amp_raw) * n16) << (16 + fv)
}

impl NoiseBasis {
    /// Trilinear value noise with the default hash: the papers' hardware noise, exactly a cubic
    /// along a span.
    pub const fn trilinear(hash: HashKind) -> Self {
        NoiseBasis {
            kind: BasisKind::Value,
            fade: Fade::Linear,
            hash,
        }
    }

    /// Whether this basis is exactly a cubic polynomial along a span inside one cell (trilinear
    /// value noise), so that forward differencing reproduces it bit for bit.
    #[inline]
    pub const fn is_cubic(&self) -> bool {
        matches!(self.kind, BasisKind::Value) && self.fade.is_linear()
    }

    /// Hashes the corners of `cell`. `amp_raw` (raw I16F16) and `fv` scale value-noise corners.
    #[inline]
    pub fn cell(&self, cell: [u16; 3], amp_raw: i32, fv: u32) -> CellData {
        self.cell_bits(cell, amp_raw, fv, 16)
    }

    /// [`NoiseBasis::cell`] with value-noise corner values quantised to `value_bits` bits
    /// ([`value::quantize_value`]; 16 is native). Gradient corners are unaffected.
    #[inline]
    pub fn cell_bits(&self, cell: [u16; 3], amp_raw: i32, fv: u32, value_bits: u32) -> CellData {
        match self.kind {
            BasisKind::Value => CellData::Value(value::scaled_corners_bits(
                self.hash, cell, amp_raw, fv, value_bits,
            )),
            #[cfg(feature = "gradient-noise")]
            BasisKind::Gradient => {
                let mut g = [[0i8; 3]; 8];
                for (c, gc) in g.iter_mut().enumerate() {
                    let bits = crate::hash::gradient_bits(
                        self.hash,
                        cell[0].wrapping_add((c & 1) as u16),
                        cell[1].wrapping_add(((c >> 1) & 1) as u16),
                        cell[2].wrapping_add(((c >> 2) & 1) as u16),
                    );
                    *gc = gradient::perlin_gradient(bits);
                }
                CellData::Gradient(g)
            }
            #[cfg(feature = "mnoise")]
            BasisKind::Modified => CellData::Gradient(mnoise::cell_gradients(cell)),
        }
    }

    /// Interpolation weights of a value-noise cell.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn weights(&self, frac: [u32; 3]) -> [i64; 3] {
        [
            self.fade.apply(frac[0]),
            self.fade.apply(frac[1]),
            self.fade.apply(frac[2]),
        ]
    }

    /// Normalises a raw gradient-family interpolant: mNoise is scaled by 2/3 into `[-1, 1]`;
    /// gradient noise is used as is (bounded by 1.065 for any hash, so the accumulator budget of
    /// `docs/model.md` 4.4 still holds).
    #[cfg(any(feature = "gradient-noise", feature = "mnoise"))]
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn normalise(&self, n16: i64) -> i64 {
        match self.kind {
            #[cfg(feature = "mnoise")]
            BasisKind::Modified => mnoise::normalise(n16),
            _ => n16,
        }
    }

    /// The term's contribution at fraction `frac` of a cell, with `48 + fv` fraction bits.
    #[inline]
    #[cfg_attr(
        not(any(feature = "gradient-noise", feature = "mnoise")),
        allow(unused_variables)
    )]
    pub fn sample(&self, data: &CellData, frac: [u32; 3], amp_raw: i32, fv: u32) -> i64 {
        match data {
            CellData::Value(v) => value::interpolate(v, self.weights(frac)),
            #[cfg(any(feature = "gradient-noise", feature = "mnoise"))]
            CellData::Gradient(g) => {
                let n16 = self.normalise(gradient::value(g, frac, self.fade));
                scale_n16(n16, amp_raw, fv)
            }
        }
    }

    /// The directional derivative of [`NoiseBasis::sample`] along the lattice step `d` (raw 16.16
    /// lattice units per pixel), in the same units per pixel. For trilinear value noise it is the
    /// exact derivative of the cubic.
    #[inline]
    #[cfg_attr(
        not(any(feature = "gradient-noise", feature = "mnoise")),
        allow(unused_variables)
    )]
    pub fn derivative(
        &self,
        data: &CellData,
        frac: [u32; 3],
        d: [i32; 3],
        amp_raw: i32,
        fv: u32,
    ) -> i64 {
        self.derivative_shaped(data, frac, d, amp_raw, fv, cfg!(texcore_lean))
    }

    /// [`NoiseBasis::derivative`] in the size-lean shape (`lean`, `cfg(texcore_lean)`: the
    /// 128-bit products through the shared out-of-line routines of [`crate::wide`]) or the fast
    /// one (products inline); both give the same result (tested). Only an inlining hint: forced
    /// inline, its body would be copied into every call site of the fast shape's general loop.
    #[inline]
    #[cfg_attr(
        not(any(feature = "gradient-noise", feature = "mnoise")),
        allow(unused_variables)
    )]
    fn derivative_shaped(
        &self,
        data: &CellData,
        frac: [u32; 3],
        d: [i32; 3],
        amp_raw: i32,
        fv: u32,
        lean: bool,
    ) -> i64 {
        match data {
            CellData::Value(v) => {
                let w = self.weights(frac);
                if self.fade.is_linear() {
                    // Exact: the derivative of the cubic.
                    value::directional(v, w, [i64::from(d[0]), i64::from(d[1]), i64::from(d[2])])
                } else {
                    // Chain rule through the fade, in i128 so small steps keep their precision.
                    let p = value::weight_partials(v, w);
                    let mut acc: i128 = 0;
                    for axis in 0..3 {
                        acc += mul(
                            mul64(p[axis], self.fade.derivative(frac[axis]), lean),
                            i64::from(d[axis]),
                            lean,
                        );
                    }
                    (acc >> 16) as i64
                }
            }
            #[cfg(any(feature = "gradient-noise", feature = "mnoise"))]
            CellData::Gradient(g) => {
                let grad = gradient::gradient(g, frac, self.fade);
                // units 2^-32 per pixel; i128 so that small steps keep their precision.
                let mut acc: i128 = 0;
                for axis in 0..3 {
                    acc += mul64(grad[axis], i64::from(d[axis]), lean);
                }
                #[cfg(feature = "mnoise")]
                if matches!(self.kind, BasisKind::Modified) {
                    acc = mul(acc, mnoise::MNOISE_SCALE, lean) >> 16;
                }
                saturate_i64(mul(acc, i64::from(amp_raw), lean) << fv)
            }
        }
    }

    /// Convenience: the contribution at a lattice point (hashes the cell every call).
    #[inline]
    pub fn sample_at(&self, u: [i32; 3], amp_raw: i32, fv: u32) -> i64 {
        let (cell, frac) = split(u);
        self.sample(&self.cell(cell, amp_raw, fv), frac, amp_raw, fv)
    }

    /// Unit-amplitude noise value at a lattice point as a real number in 2^-16 units
    /// (`65536` = 1.0); for tests, statistics and reports.
    pub fn value16_at(&self, u: [i32; 3]) -> i64 {
        // amplitude 1.0 (raw 65536) with fv = 0: contribution has 48 fraction bits.
        self.sample_at(u, 1 << 16, 0) >> 32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bases() -> heapless::Vec<NoiseBasis, 16> {
        let mut v = heapless::Vec::new();
        let kinds = [
            BasisKind::Value,
            #[cfg(feature = "gradient-noise")]
            BasisKind::Gradient,
            #[cfg(feature = "mnoise")]
            BasisKind::Modified,
        ];
        let fades = [
            Fade::Linear,
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth,
            #[cfg(feature = "smooth-fade")]
            Fade::Quintic,
        ];
        for kind in kinds {
            for fade in fades {
                let _ = v.push(NoiseBasis {
                    kind,
                    fade,
                    hash: HashKind::Integer,
                });
            }
        }
        v
    }

    fn lcg(state: &mut u64) -> u32 {
        (crate::test_rng::lcg64(state) >> 32) as u32
    }

    /// A pseudo-random lattice point (raw 16.16 per axis, the whole i32 range).
    fn lcg_point(state: &mut u64) -> [i32; 3] {
        [lcg(state) as i32, lcg(state) as i32, lcg(state) as i32]
    }

    #[test]
    fn split_wraps() {
        assert_eq!(
            split([-1, 0x1_8000, i32::MIN]),
            ([0xFFFF, 1, 0x8000], [0xFFFF, 0x8000, 0])
        );
    }

    #[test]
    fn deterministic_and_ranged() {
        for b in bases() {
            let mut st = 42u64;
            let mut sum = 0i64;
            let n = 20000;
            for _ in 0..n {
                let u = lcg_point(&mut st);
                let v = b.value16_at(u);
                assert_eq!(v, b.value16_at(u));
                // Gradient noise reaches 1.065 at most (any hash), the others stay in [-1, 1].
                assert!((-69800..=69800).contains(&v), "{b:?} {u:?} {v}");
                sum += v;
            }
            let mean = sum as f64 / n as f64 / 65536.0;
            assert!(mean.abs() < 0.05, "{b:?} mean {mean}");
        }
    }

    #[test]
    fn derivative_shapes_agree() {
        for b in bases() {
            let mut st = 11u64;
            for _ in 0..500 {
                let u = lcg_point(&mut st);
                let d = [
                    (lcg(&mut st) as i32) >> (lcg(&mut st) % 32),
                    (lcg(&mut st) as i32) >> (lcg(&mut st) % 32),
                    (lcg(&mut st) as i32) >> (lcg(&mut st) % 32),
                ];
                let amp = (lcg(&mut st) % (1 << 17)) as i32 - (1 << 16);
                let fv = lcg(&mut st) % 9;
                let (cell, frac) = split(u);
                let data = b.cell(cell, amp, fv);
                let fast = b.derivative_shaped(&data, frac, d, amp, fv, false);
                let lean = b.derivative_shaped(&data, frac, d, amp, fv, true);
                assert_eq!(fast, lean, "{b:?} u={u:?} d={d:?} amp={amp} fv={fv}");
                assert_eq!(fast, b.derivative(&data, frac, d, amp, fv));
            }
        }
    }

    #[test]
    fn derivative_matches_differences() {
        for b in bases() {
            let mut st = 7u64;
            for _ in 0..300 {
                // A point well inside a cell so the difference stays in it.
                let base = lcg_point(&mut st);
                let u = [
                    (base[0] & !0xFFFF) | 0x4000 | (base[0] & 0x3FFF),
                    (base[1] & !0xFFFF) | 0x4000 | (base[1] & 0x3FFF),
                    (base[2] & !0xFFFF) | 0x4000 | (base[2] & 0x3FFF),
                ];
                let d = [
                    (lcg(&mut st) % 64) as i32 - 32,
                    (lcg(&mut st) % 64) as i32 - 32,
                    (lcg(&mut st) % 64) as i32 - 32,
                ];
                let (cell, frac) = split(u);
                let data = b.cell(cell, 1 << 16, 8);
                let g = b.derivative(&data, frac, d, 1 << 16, 8) as f64;
                let up = [u[0] + d[0] * 8, u[1] + d[1] * 8, u[2] + d[2] * 8];
                let dn = [u[0] - d[0] * 8, u[1] - d[1] * 8, u[2] - d[2] * 8];
                let fd = (b.sample_at(up, 1 << 16, 8) - b.sample_at(dn, 1 << 16, 8)) as f64 / 16.0;
                let scale = (1u64 << 56) as f64 / 65536.0 * 64.0; // ~ max slope per pixel step
                assert!(
                    (g - fd).abs() < 0.02 * scale,
                    "{b:?} u={u:?} d={d:?}: {g} vs {fd}"
                );
            }
        }
    }
}
