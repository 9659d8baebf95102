//! The multipass buffer and its passes (the raw kernel; module documentation of
//! [`crate::multipass`]).
//!
//! Every pass is a plain loop over the band's slices with no branch on data and no call, so the
//! compiler can vectorize it on hosts with SIMD units (`docs/multipass.md` says what it does).

use super::{axis_random, axis_third, MultipassConfig, PassHash, PassPrecision};
use crate::hash::{lattice_value, HashKind};
use crate::noise::value::quantize_value;
use crate::noise::Fade;

/// One value-noise term as the passes see it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassTerm {
    /// The term's lattice hash (used by [`PassHash::Texcore`]).
    pub hash: HashKind,
    /// The interpolant.
    pub fade: Fade,
    /// Raw I16F16 amplitude (`|a|` for a turbulent term).
    pub amp_raw: i32,
    /// The model's noise fraction bits `fv` (`0..=16`).
    pub fv: u32,
    /// Corner value bits of the model's precision (`1..=16`; 16 is native).
    pub value_bits: u32,
    /// Precision and hash of the passes.
    pub config: MultipassConfig,
    /// Run the partial-derivative passes (for [`Band::derivative_into`]).
    pub gradients: bool,
}

/// A band of up to `N` lattice points evaluated pass by pass (capacity in the type; a band holds
/// `min(len, N)` points and never panics).
#[derive(Clone, Debug)]
pub struct Band<const N: usize> {
    len: usize,
    /// `solid_int` per axis (4 bits at [`PassPrecision::Bits8`], 16 otherwise).
    cell: [[u16; N]; 3],
    /// The fraction per axis in native units (`0..65536`, quantised to the format).
    frac: [[u32; N]; 3],
    /// The weight of corner 1 per axis in native units (`0..=65536`).
    w: [[u32; N]; 3],
    /// The weight in the format's units (reduced precisions: `0..=256` or `0..=255`).
    wf: [[u16; N]; 3],
    /// Per-axis random values of `solid_int` and `solid_int + 1` (summed and XOR hashes).
    rnd: [[[u8; N]; 2]; 3],
    /// The current corner's value scaled by the amplitude (`v'`).
    vs: [i32; N],
    /// The current corner's random byte (reduced precisions).
    byte: [u16; N],
    /// The weighted sum: the term's contribution with `48 + fv` fraction bits once finished.
    acc: [i64; N],
    /// The weighted sum in the reduced format.
    accf: [i32; N],
    /// The partial derivatives of the interpolant by the three weights.
    part: [[i64; N]; 3],
    passes: u32,
}

impl<const N: usize> Default for Band<N> {
    fn default() -> Self {
        Self::new()
    }
}

/// `round(a b / 255)` for `a, b <= 255`: the framebuffer's modulate blend.
#[inline(always)]
fn modulate8(a: u32, b: u32) -> u32 {
    let t = a * b + 128;
    (t + (t >> 8)) >> 8
}

impl<const N: usize> Band<N> {
    /// An empty band.
    pub const fn new() -> Self {
        Band {
            len: 0,
            cell: [[0; N]; 3],
            frac: [[0; N]; 3],
            w: [[0; N]; 3],
            wf: [[0; N]; 3],
            rnd: [[[0; N]; 2]; 3],
            vs: [0; N],
            byte: [0; N],
            acc: [0; N],
            accf: [0; N],
            part: [[0; N]; 3],
            passes: 0,
        }
    }

    /// Points held by the last [`Band::run`].
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the band holds no point.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Passes run since the band was made (each a loop over the whole band).
    pub const fn passes(&self) -> u32 {
        self.passes
    }

    /// Evaluates `term` at the lattice points `u0 + i du` (raw 16.16 per axis, wrapping),
    /// `i < min(len, N)`, pass by pass; the contributions are then [`Band::values`].
    pub fn run(&mut self, term: &PassTerm, u0: [i32; 3], du: [i32; 3], len: usize) {
        let n = len.min(N);
        self.len = n;
        let prec = term.config.precision;
        let axes = self.cell.iter_mut().zip(&mut self.frac);
        let axes = axes.zip(self.w.iter_mut().zip(&mut self.wf));
        // The passes walk the band's first `n <= N` points (iterators: no index, no slicing).
        for (((cell, frac), (w, wf)), (u0, du)) in axes.zip(u0.into_iter().zip(du)) {
            self.passes += 1;
            decompose(cell, frac, w, wf, n, u0, du, prec);
            if !term.fade.is_linear() {
                self.passes += 1;
                fade_pass(frac, w, wf, n, term.fade, prec);
            }
        }
        if term.config.hash != PassHash::Texcore {
            for (axis, (cell, rnd)) in self.cell.iter().zip(&mut self.rnd).enumerate() {
                for (side, out) in rnd.iter_mut().enumerate() {
                    self.passes += 1;
                    let (axis, side) = (axis as u32, side as u16);
                    axis_field(cell, out, n, axis, side, term.config.hash, prec);
                }
            }
        }
        self.acc.iter_mut().take(n).for_each(|a| *a = 0);
        self.accf.iter_mut().take(n).for_each(|a| *a = 0);
        if term.gradients {
            for p in self.part.iter_mut() {
                p.iter_mut().take(n).for_each(|a| *a = 0);
            }
        }
        for k in 0..8 {
            self.corner(k, term);
            self.weigh(k, prec);
            if term.gradients {
                self.partials(k);
            }
        }
        self.finish(term);
    }

    /// The term's contribution at each point (`48 + fv` fraction bits).
    pub fn values(&self) -> &[i64] {
        self.acc.get(..self.len).unwrap_or(&[])
    }

    /// The directional derivative of the contribution along the lattice step `d` (per pixel, the
    /// units of [`crate::noise::NoiseBasis::derivative`]) into `out` (one per point; zeros unless
    /// the last [`Band::run`] had `gradients`).
    pub fn derivative_into(&mut self, fade: Fade, d: [i32; 3], out: &mut [i64]) {
        self.passes += 1;
        let n = self.len.min(N);
        let [p0, p1, p2] = &self.part;
        let parts = p0.iter().zip(p1).zip(p2).take(n);
        if fade.is_linear() {
            let d = d.map(i64::from);
            for (o, ((&a, &b), &c)) in out.iter_mut().zip(parts) {
                *o = a
                    .wrapping_mul(d[0])
                    .wrapping_add(b.wrapping_mul(d[1]))
                    .wrapping_add(c.wrapping_mul(d[2]));
            }
        } else {
            // The chain rule through the fade, in i128, as the direct derivative.
            let [f0, f1, f2] = &self.frac;
            let fracs = f0.iter().zip(f1).zip(f2);
            for (o, (((&a, &b), &c), ((&x, &y), &z))) in out.iter_mut().zip(parts.zip(fracs)) {
                let mut acc: i128 = 0;
                for ((p, f), d) in [a, b, c].into_iter().zip([x, y, z]).zip(d) {
                    acc += i128::from(p) * i128::from(fade.derivative(f)) * i128::from(d);
                }
                *o = (acc >> 16) as i64;
            }
        }
    }

    /// Stage image: `solid_int` of `axis` (0, 1, 2) after the last [`Band::run`].
    pub fn int_part(&self, axis: usize) -> &[u16] {
        self.cell
            .get(axis)
            .and_then(|c| c.get(..self.len))
            .unwrap_or(&[])
    }

    /// Stage image: the weight of corner 1 on `axis` after the last [`Band::run`] (native units,
    /// `0..=65536`: the fraction, through the fade when it is not linear).
    pub fn weight(&self, axis: usize) -> &[u32] {
        self.w
            .get(axis)
            .and_then(|w| w.get(..self.len))
            .unwrap_or(&[])
    }

    /// Stage image: the random field of corner `k` (`0..8`, bit 0 on `s`, bit 1 on `t`, bit 2 on
    /// `r`) of the last [`Band::run`]'s points, as bytes (`0..=255` for `[0, 1]`). Runs the
    /// corner pass again (the sum is not changed).
    pub fn random_field(&mut self, term: &PassTerm, k: usize) -> &[u16] {
        self.corner(k & 7, term);
        self.byte.get(..self.len).unwrap_or(&[])
    }

    /// The corner pass of corner `k`: its lattice point, hashed to a random value, scaled by the
    /// amplitude (native) or kept as a byte (reduced precisions).
    fn corner(&mut self, k: usize, term: &PassTerm) {
        self.passes += 1;
        let n = self.len.min(N);
        let prec = term.config.precision;
        let mask = lattice_mask(prec);
        let bits = [(k & 1) as u16, ((k >> 1) & 1) as u16, ((k >> 2) & 1) as u16];
        let shift = 31 - term.fv.min(16);
        let round = 1i64 << (shift - 1);
        let amp = i64::from(term.amp_raw);
        let [c0, c1, c2] = &self.cell;
        // The per-axis random fields of the corner's side on each axis (`& 1`: in range).
        let [r0, r1, r2] = &self.rnd;
        let (r0, r1, r2) = (&r0[k & 1], &r1[(k >> 1) & 1], &r2[(k >> 2) & 1]);
        let points = c0.iter().zip(c1).zip(c2).zip(r0.iter().zip(r1).zip(r2));
        let outs = self.byte.iter_mut().zip(self.vs.iter_mut());
        for ((((&x, &y), &z), ((&ra, &rb), &rc)), (byte_out, vs_out)) in points.zip(outs).take(n) {
            let v16: i16 = match term.config.hash {
                PassHash::Texcore => {
                    let x = x.wrapping_add(bits[0]) & mask;
                    let y = y.wrapping_add(bits[1]) & mask;
                    let z = z.wrapping_add(bits[2]) & mask;
                    quantize_value(lattice_value(term.hash, x, y, z), term.value_bits)
                }
                PassHash::SummedRandom => {
                    let r = u32::from(ra) + u32::from(rb) + u32::from(rc);
                    (r * 257) as u16 as i16 ^ i16::MIN
                }
                PassHash::Xor => {
                    let r = ra ^ rb ^ rc;
                    (u32::from(r) * 257) as u16 as i16 ^ i16::MIN
                }
            };
            // The random byte of a reduced format, and the value the gradients see.
            let byte = (v16 as u16 ^ 0x8000) >> 8;
            let v = match prec {
                PassPrecision::Native => v16,
                PassPrecision::Fixed16_8 => (byte << 8) as i16 ^ i16::MIN,
                PassPrecision::Bits8 => (byte * 257) as i16 ^ i16::MIN,
            };
            *byte_out = byte;
            *vs_out = ((amp * i64::from(v) + round) >> shift) as i32;
        }
    }

    /// The weight pass of corner `k`: the corner's value times its three weights, added into the
    /// sum.
    fn weigh(&mut self, k: usize, prec: PassPrecision) {
        self.passes += 1;
        let n = self.len.min(N);
        let sel = [k & 1 != 0, (k >> 1) & 1 != 0, (k >> 2) & 1 != 0];
        match prec {
            PassPrecision::Native => {
                let [w0, w1, w2] = &self.w;
                let pick = |w: u32, s: bool| i64::from(if s { w } else { 65536 - w });
                let terms = w0.iter().zip(w1).zip(w2).zip(&self.vs);
                for ((((&a, &b), &c), &v), acc) in terms.zip(self.acc.iter_mut()).take(n) {
                    let wxy = pick(a, sel[0]) * pick(b, sel[1]);
                    let p = i64::from(v).wrapping_mul(wxy).wrapping_mul(pick(c, sel[2]));
                    *acc = acc.wrapping_add(p);
                }
            }
            PassPrecision::Fixed16_8 => {
                let [w0, w1, w2] = &self.wf;
                let pick = |w: u16, s: bool| i32::from(if s { w } else { 256 - w });
                let terms = w0.iter().zip(w1).zip(w2).zip(&self.byte);
                for ((((&a, &b), &c), &byte), acc) in terms.zip(self.accf.iter_mut()).take(n) {
                    let mut p = i32::from(byte);
                    p = (p * pick(a, sel[0]) + 128) >> 8;
                    p = (p * pick(b, sel[1]) + 128) >> 8;
                    p = (p * pick(c, sel[2]) + 128) >> 8;
                    *acc += p;
                }
            }
            PassPrecision::Bits8 => {
                let [w0, w1, w2] = &self.wf;
                let pick = |w: u16, s: bool| u32::from(if s { w } else { 255 - w });
                let terms = w0.iter().zip(w1).zip(w2).zip(&self.byte);
                for ((((&a, &b), &c), &byte), acc) in terms.zip(self.accf.iter_mut()).take(n) {
                    let mut p = u32::from(byte);
                    p = modulate8(p, pick(a, sel[0]));
                    p = modulate8(p, pick(b, sel[1]));
                    p = modulate8(p, pick(c, sel[2]));
                    *acc = (*acc + p as i32).min(255);
                }
            }
        }
    }

    /// The partials pass of corner `k`: its value's share of `dP/dw` on each axis.
    fn partials(&mut self, k: usize) {
        self.passes += 1;
        let n = self.len.min(N);
        let sel = [k & 1 != 0, (k >> 1) & 1 != 0, (k >> 2) & 1 != 0];
        let [w0, w1, w2] = &self.w;
        let pick = |w: u32, s: bool| i64::from(if s { w } else { 65536 - w });
        let sign = |s: bool| if s { 1i64 } else { -1 };
        let [p0, p1, p2] = &mut self.part;
        let terms = w0.iter().zip(w1).zip(w2).zip(&self.vs);
        let parts = p0.iter_mut().zip(p1.iter_mut()).zip(p2.iter_mut());
        for ((((&a, &b), &c), &v), ((p0, p1), p2)) in terms.zip(parts).take(n) {
            let v = i64::from(v);
            let (x, y, z) = (pick(a, sel[0]), pick(b, sel[1]), pick(c, sel[2]));
            *p0 = p0.wrapping_add(v.wrapping_mul(sign(sel[0]) * y * z));
            *p1 = p1.wrapping_add(v.wrapping_mul(sign(sel[1]) * x * z));
            *p2 = p2.wrapping_add(v.wrapping_mul(sign(sel[2]) * x * y));
        }
    }

    /// The finish pass: a reduced format's sum back into the model's noise units.
    fn finish(&mut self, term: &PassTerm) {
        let n = self.len.min(N);
        let prec = term.config.precision;
        if prec == PassPrecision::Native {
            return;
        }
        self.passes += 1;
        let amp = i64::from(term.amp_raw);
        let sh = 17 + term.fv.min(16);
        for (a, &s) in self.acc.iter_mut().zip(&self.accf).take(n) {
            let v16 = match prec {
                PassPrecision::Bits8 => s * 257 - 32768,
                _ => s * 256 - 32768,
            };
            *a = amp.wrapping_mul(i64::from(v16)).wrapping_shl(sh);
        }
    }
}

/// Decompose (one axis): `solid_int`, the fraction and the linear weight of the first `n`
/// points `u0 + i du`.
#[allow(clippy::too_many_arguments)]
fn decompose(
    cell: &mut [u16],
    frac: &mut [u32],
    w: &mut [u32],
    wf: &mut [u16],
    n: usize,
    u0: i32,
    du: i32,
    prec: PassPrecision,
) {
    let mut u = u0;
    for (((c, f), w), wf) in cell.iter_mut().zip(frac).zip(w).zip(wf).take(n) {
        match prec {
            PassPrecision::Native => {
                *c = (u >> 16) as u16;
                *f = (u & 0xFFFF) as u32;
                *w = *f;
            }
            PassPrecision::Fixed16_8 => {
                let f8 = ((u >> 8) & 0xFF) as u32;
                *c = (u >> 16) as u16;
                *f = f8 << 8;
                *w = *f;
                *wf = f8 as u16;
            }
            PassPrecision::Bits8 => {
                // One 8-bit channel: 4 integer bits, 4 fraction bits.
                let c8 = ((u >> 12) & 0xFF) as u32;
                *c = (c8 >> 4) as u16;
                *f = (c8 & 15) << 12;
                *w = *f;
                *wf = ((c8 & 15) << 4) as u16;
            }
        }
        u = u.wrapping_add(du);
    }
}

/// The smooth curve (one axis, the first `n` points): the weight through the fade (rounded to
/// the format).
fn fade_pass(
    frac: &[u32],
    w: &mut [u32],
    wf: &mut [u16],
    n: usize,
    fade: Fade,
    prec: PassPrecision,
) {
    for ((&f, w), wf) in frac.iter().zip(w).zip(wf).take(n) {
        let s = fade.apply(f) as u32;
        match prec {
            PassPrecision::Native => *w = s,
            PassPrecision::Fixed16_8 => {
                let q = (s + 128) >> 8;
                *wf = q as u16;
                *w = q << 8;
            }
            PassPrecision::Bits8 => {
                let q = (s * 255 + 32768) >> 16;
                *wf = q as u16;
                *w = q * 257;
            }
        }
    }
}

/// The per-axis random field of `solid_int + side` (summed and XOR hashes; one axis, one side,
/// the first `n` points).
fn axis_field(
    cell: &[u16],
    out: &mut [u8],
    n: usize,
    axis: u32,
    side: u16,
    hash: PassHash,
    prec: PassPrecision,
) {
    let mask = lattice_mask(prec);
    for (o, &c) in out.iter_mut().zip(cell).take(n) {
        let x = c.wrapping_add(side) & mask;
        *o = match hash {
            PassHash::SummedRandom => axis_third(x, axis),
            _ => axis_random(x, axis),
        };
    }
}

/// The lattice coordinates a format holds: 4 bits in an 8-bit channel, 16 otherwise.
const fn lattice_mask(prec: PassPrecision) -> u16 {
    match prec {
        PassPrecision::Bits8 => 15,
        _ => u16::MAX,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::{BasisKind, NoiseBasis};
    use proptest::prelude::*;

    fn fades() -> Vec<Fade> {
        vec![
            Fade::Linear,
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth,
            #[cfg(feature = "smooth-fade")]
            Fade::Quintic,
        ]
    }

    fn hashes() -> Vec<HashKind> {
        vec![
            HashKind::Integer,
            #[cfg(feature = "perm-hash")]
            HashKind::Permutation,
        ]
    }

    fn term(hash: HashKind, fade: Fade, amp: i32, fv: u32, config: MultipassConfig) -> PassTerm {
        PassTerm {
            hash,
            fade,
            amp_raw: amp,
            fv,
            value_bits: 16,
            config,
            gradients: true,
        }
    }

    /// Native multipass against the direct kernels of `noise`, value and both derivatives.
    fn check_native(u0: [i32; 3], du: [i32; 3], dy: [i32; 3], amp: i32, fv: u32) {
        for hash in hashes() {
            for fade in fades() {
                let t = term(hash, fade, amp, fv, MultipassConfig::EXACT);
                let mut band = Band::<16>::new();
                band.run(&t, u0, du, 16);
                let mut gx = [0i64; 16];
                let mut gy = [0i64; 16];
                band.derivative_into(fade, du, &mut gx);
                band.derivative_into(fade, dy, &mut gy);
                let basis = NoiseBasis {
                    kind: BasisKind::Value,
                    fade,
                    hash,
                };
                for i in 0..16 {
                    let u = [0, 1, 2].map(|a| u0[a].wrapping_add(du[a].wrapping_mul(i as i32)));
                    let (cell, frac) = crate::noise::split(u);
                    let data = basis.cell(cell, amp, fv);
                    assert_eq!(band.values()[i], basis.sample(&data, frac, amp, fv), "{i}");
                    assert_eq!(gx[i], basis.derivative(&data, frac, du, amp, fv));
                    assert_eq!(gy[i], basis.derivative(&data, frac, dy, amp, fv));
                }
            }
        }
    }

    #[test]
    fn native_is_the_direct_kernel() {
        check_native(
            [0x1_2345, -0x7_0001, 0x3_8000],
            [4096, -777, 19],
            [3, 5, -9000],
            1 << 16,
            8,
        );
        check_native(
            [i32::MAX - 5000, i32::MIN, 0],
            [-65535, 65535, 1 << 15],
            [0; 3],
            -(3 << 16),
            5,
        );
    }

    proptest! {
        #[test]
        fn native_is_bit_identical(
            u0 in prop::array::uniform3(any::<i32>()),
            du in prop::array::uniform3(-70000i32..70000),
            dy in prop::array::uniform3(-70000i32..70000),
            amp in -(1i32 << 20)..(1 << 20),
            fv in 0u32..10,
        ) {
            check_native(u0, du, dy, amp, fv);
        }
    }

    /// The unit-amplitude value (`2^-16` units) of a band run at `prec`.
    fn unit_values(
        prec: PassPrecision,
        hash: PassHash,
        fade: Fade,
        u0: [i32; 3],
        du: [i32; 3],
    ) -> Vec<i64> {
        let cfg = MultipassConfig {
            precision: prec,
            hash,
        };
        // Amplitude 1 with the model's `fv` for it (`docs/model.md` 4.4): 13.
        let t = term(HashKind::Integer, fade, 1 << 16, 13, cfg);
        let mut band = Band::<64>::new();
        band.run(&t, u0, du, 64);
        band.values().iter().map(|v| v >> 45).collect()
    }

    #[test]
    fn reduced_precisions_stay_near_native() {
        // Inside the first 16 cells (where the 4.4 channel does not wrap) both reduced formats
        // approximate the native value: 16.8 within 8-bit steps of its inputs, 8-bit coarser.
        for fade in fades() {
            let u0 = [0x2_3456, 0x5_1234, 0x7_0F00];
            let du = [517, 300, -211];
            let native = unit_values(PassPrecision::Native, PassHash::Texcore, fade, u0, du);
            let f168 = unit_values(PassPrecision::Fixed16_8, PassHash::Texcore, fade, u0, du);
            let b8 = unit_values(PassPrecision::Bits8, PassHash::Texcore, fade, u0, du);
            let max_err = |v: &[i64]| {
                v.iter()
                    .zip(&native)
                    .map(|(a, b)| (a - b).abs())
                    .max()
                    .unwrap()
            };
            // 16.8 (2^-16 units; one 8-bit step of the value is 512): half a step from the value,
            // 8 fraction bits of coordinate (slope at most 2 a cell: 512), half a step from each
            // of the 24 rounded products: below 7000 (0.11).
            eprintln!("{fade:?}: 16.8 {} 8-bit {}", max_err(&f168), max_err(&b8));
            assert!(max_err(&f168) < 7000, "{fade:?} 16.8 {}", max_err(&f168));
            // 8-bit: 4 fraction bits of coordinate (2/16 of a unit slope: 8192), weights up to
            // 240/255, 24 rounded blends (6144): below 0.5.
            assert!(max_err(&b8) < 32768, "{fade:?} 8-bit {}", max_err(&b8));
            assert!(max_err(&b8) > max_err(&f168));
        }
    }

    #[test]
    fn eight_bit_lattice_wraps_every_16_cells() {
        let cfg = MultipassConfig::with_precision(PassPrecision::Bits8);
        let t = term(HashKind::Integer, Fade::Linear, 1 << 16, 0, cfg);
        let mut a = Band::<8>::new();
        let mut b = Band::<8>::new();
        a.run(&t, [0x1_4000, 0x2_8000, 0x3_0000], [4096, 0, 0], 8);
        b.run(&t, [0x11_4000, 0x22_8000, -0xD_0000], [4096, 0, 0], 8);
        assert_eq!(a.values(), b.values());
    }

    #[test]
    fn summed_is_bell_shaped_xor_is_flat() {
        // Corner values only (lattice points): the summed hash piles up in the middle.
        let hist = |hash: PassHash| {
            let mut h = [0u32; 4];
            for z in 0..64 {
                let v = unit_values(
                    PassPrecision::Native,
                    hash,
                    Fade::Linear,
                    [0, 0, z << 16],
                    [1 << 16, 0, 0],
                );
                let v2 = unit_values(
                    PassPrecision::Native,
                    hash,
                    Fade::Linear,
                    [0, z << 16, 0],
                    [0, 0, 1 << 16],
                );
                for x in v.into_iter().chain(v2) {
                    h[((x + 65536) * 4 / 131072).clamp(0, 3) as usize] += 1;
                }
            }
            h
        };
        let s = hist(PassHash::SummedRandom);
        let x = hist(PassHash::Xor);
        // Sum of three uniforms: the outer quarters hold about 1/6 of the mass (vs 1/2 for XOR).
        let outer = |h: [u32; 4]| f64::from(h[0] + h[3]) / f64::from(h.iter().sum::<u32>());
        assert!(outer(s) < 0.25, "{s:?}");
        assert!(outer(x) > 0.4, "{x:?}");
    }

    #[test]
    fn pass_counts() {
        let count = |fade: Fade, hash: PassHash, grads: bool| {
            let cfg = MultipassConfig {
                precision: PassPrecision::Native,
                hash,
            };
            let mut t = term(HashKind::Integer, fade, 1 << 16, 0, cfg);
            t.gradients = grads;
            let mut band = Band::<4>::new();
            band.run(&t, [0; 3], [1; 3], 4);
            band.passes()
        };
        // 3 decompose + 8 x (corner + weight).
        assert_eq!(count(Fade::Linear, PassHash::Texcore, false), 19);
        // + 6 random fields.
        assert_eq!(count(Fade::Linear, PassHash::Xor, false), 25);
        // + 8 partials.
        assert_eq!(count(Fade::Linear, PassHash::Texcore, true), 27);
        #[cfg(feature = "smooth-fade")]
        assert_eq!(count(Fade::Smooth, PassHash::Texcore, false), 22);
    }

    #[test]
    fn short_and_oversized_bands() {
        let t = term(
            HashKind::Integer,
            Fade::Linear,
            1 << 16,
            0,
            MultipassConfig::EXACT,
        );
        let mut band = Band::<4>::new();
        band.run(&t, [0; 3], [1; 3], 100);
        assert_eq!(band.len(), 4);
        band.run(&t, [0; 3], [1; 3], 0);
        assert!(band.is_empty());
        assert!(band.values().is_empty());
        let mut out = [7i64; 2];
        band.derivative_into(Fade::Linear, [1; 3], &mut out);
        assert_eq!(out, [7, 7]);
    }
}
