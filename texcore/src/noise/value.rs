//! Lattice value noise: exact interpolation of amplitude-scaled corner values.
//!
//! `P = sum_c v'_c * wx_c * wy_c * wz_c` (`docs/model.md` 4.2) is computed with wrapping i64
//! arithmetic in lerp form, which is an exact integer identity with the sum form. The true value
//! always fits in i64 (the model bounds `|v'|`), so the wrapping result is the exact value. The
//! same functions evaluate the polynomial just outside the cell (fractions `< 0` or `>= 1`), which
//! the forward-difference set-up uses; there the result is exact modulo 2^64, which is all the
//! forward differences need.
//!
//! Corner order: index `c = cx | cy << 1 | cz << 2`.

use crate::hash::HashKind;

/// Amplitude-scaled corner values of the cell at `cell`: `v'_c = (amp * v_c + 2^(30-fv)) >> (31-fv)`.
///
/// `amp_raw` is the raw I16F16 amplitude, `fv` (<= 16) the model's noise fraction bits.
#[inline]
pub fn scaled_corners(hash: HashKind, cell: [u16; 3], amp_raw: i32, fv: u32) -> [i32; 8] {
    scaled_corners_bits(hash, cell, amp_raw, fv, 16)
}

/// A corner value `v` (`v / 32768` in `[-1, 1)`) quantised to `bits` bits (`docs/model.md` 3.2):
/// rounded half up to a multiple of `2^(16 - bits)` and saturated to the largest such value below
/// 32768; the identity for `bits >= 16`.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn quantize_value(v: i16, bits: u32) -> i16 {
    if bits >= 16 {
        return v;
    }
    let sh = 16 - bits;
    let step = 1i32 << sh;
    let q = (v as i32 + (step >> 1)) & !(step - 1);
    if q > 32768 - step {
        (32768 - step) as i16
    } else {
        q as i16
    }
}

/// [`scaled_corners`] with the corner values quantised to `value_bits` bits first
/// ([`quantize_value`]; `16` is the native format, no quantisation).
#[inline]
pub fn scaled_corners_bits(
    hash: HashKind,
    cell: [u16; 3],
    amp_raw: i32,
    fv: u32,
    value_bits: u32,
) -> [i32; 8] {
    let shift = 31 - fv.min(16);
    let round = 1i64 << (shift - 1);
    let mut raw = corner_values(hash, cell);
    if value_bits < 16 {
        for v in raw.iter_mut() {
            *v = quantize_value(*v, value_bits);
        }
    }
    let mut out = [0i32; 8];
    for (o, v) in out.iter_mut().zip(raw) {
        *o = scale_bits(v, amp_raw, shift, round);
    }
    out
}

/// `(amp * v + round) >> shift` as i32 (`15 <= shift <= 31`).
#[cfg_attr(not(texcore_lean), inline(always))]
fn scale_bits(v: i16, amp_raw: i32, shift: u32, round: i64) -> i32 {
    let x = i64::from(amp_raw) * i64::from(v) + round;
    // `(x >> shift) as i32` from the two 32-bit halves (`15 <= shift <= 31`): a 32-bit core
    // needs no general 64-bit shift.
    let (lo, hi) = (x as u32, (x >> 32) as u32);
    (lo.wrapping_shr(shift) | hi.wrapping_shl(32 - shift)) as i32
}

/// The four scaled corner values of the face `c_k = b` of `cell` (`K = k`, `0..3`), exactly the
/// entries `(b << k) | (ca << a) | (cc << c)` of [`scaled_corners_bits`] (`a < c` the two other
/// axes), in the order `ca | cc << 1`: half the hashing of a cell, for a span that steps into the
/// neighbouring cell along `k` and keeps the shared face. The permutation chain shares its
/// look-ups between the face's corners (7 to 10 instead of 12).
#[cfg_attr(not(texcore_lean), inline(always))]
pub fn scaled_face_bits<const K: usize>(
    hash: HashKind,
    cell: [u16; 3],
    b: u16,
    amp_raw: i32,
    fv: u32,
    value_bits: u32,
) -> [i32; 4] {
    let shift = 31 - fv.min(16);
    let round = 1i64 << (shift - 1);
    // The corner offsets of face corner `i` along x, y and z.
    let off = |i: usize| -> [u16; 3] {
        let (ca, cc) = ((i & 1) as u16, (i >> 1) as u16);
        match K {
            0 => [b, ca, cc],
            1 => [ca, b, cc],
            _ => [ca, cc, b],
        }
    };
    let raw: [i16; 4] = match hash {
        #[cfg(feature = "perm-hash")]
        HashKind::Permutation => {
            let p = &crate::hash::PERMUTATION;
            let [x, y, z] = cell.map(|c| c as u8);
            let h = |o: [u16; 3]| {
                let a = p[usize::from(x.wrapping_add(o[0] as u8))];
                let bb = p[usize::from(a.wrapping_add(y.wrapping_add(o[1] as u8)))];
                p[usize::from(bb.wrapping_add(z.wrapping_add(o[2] as u8)))]
            };
            let v = |i: usize| (i32::from(h(off(i))) * 257 - 32768) as i16;
            corners4(v)
        }
        HashKind::Integer => corners4(|i: usize| {
            let o = off(i);
            crate::hash::lattice_value(
                HashKind::Integer,
                cell[0].wrapping_add(o[0]),
                cell[1].wrapping_add(o[1]),
                cell[2].wrapping_add(o[2]),
            )
        }),
    };
    let scale = |v: i16| {
        let v = if value_bits < 16 {
            quantize_value(v, value_bits)
        } else {
            v
        };
        scale_bits(v, amp_raw, shift, round)
    };
    // The fast shape writes the corners out rather than `raw.map(..)`: the array map is not
    // always inlined (a call per face in the span kernels).
    #[cfg(not(texcore_lean))]
    return [scale(raw[0]), scale(raw[1]), scale(raw[2]), scale(raw[3])];
    #[cfg(texcore_lean)]
    raw.map(scale)
}

/// `[v(0), v(1), v(2), v(3)]`: written out in the fast shape (`core::array::from_fn` is not
/// always inlined there), `from_fn` in the size-lean one.
#[cfg_attr(not(texcore_lean), inline(always))]
fn corners4(v: impl Fn(usize) -> i16) -> [i16; 4] {
    #[cfg(not(texcore_lean))]
    return [v(0), v(1), v(2), v(3)];
    #[cfg(texcore_lean)]
    core::array::from_fn(v)
}

/// The eight corner values `lattice_value(hash, cell + c)` (corner order `cx | cy << 1 | cz << 2`),
/// sharing the hash work between corners: the permutation chain looks up 2 + 4 + 8 entries
/// instead of 24, the integer hash multiplies each coordinate once per value instead of per corner.
#[inline]
pub fn corner_values(hash: HashKind, cell: [u16; 3]) -> [i16; 8] {
    let mut out = [0i16; 8];
    match hash {
        #[cfg(feature = "perm-hash")]
        HashKind::Permutation => {
            let p = &crate::hash::PERMUTATION;
            let [x, y, z] = cell.map(|c| c as u8);
            let a = [p[usize::from(x)], p[usize::from(x.wrapping_add(1))]];
            let b = |cx: usize, cy: u8| p[usize::from(a[cx].wrapping_add(y.wrapping_add(cy)))];
            let bs = [b(0, 0), b(1, 0), b(0, 1), b(1, 1)];
            for (c, o) in out.iter_mut().enumerate() {
                let h = p[usize::from(bs[c & 3].wrapping_add(z.wrapping_add((c >> 2) as u8)))];
                *o = (i32::from(h) * 257 - 32768) as i16;
            }
        }
        HashKind::Integer => {
            let m = |v: u16, k: u32| {
                [
                    u32::from(v).wrapping_mul(k),
                    u32::from(v.wrapping_add(1)).wrapping_mul(k),
                ]
            };
            let hx = m(cell[0], 0x9E37_79B1);
            let hy = m(cell[1], 0x85EB_CA77);
            let hz = m(cell[2], 0xC2B2_AE3D);
            for (c, o) in out.iter_mut().enumerate() {
                let mut h = hx[c & 1] ^ hy[(c >> 1) & 1] ^ hz[c >> 2];
                h ^= h >> 15;
                h = h.wrapping_mul(0x2C1B_3C6D);
                h ^= h >> 12;
                h = h.wrapping_mul(0x297A_2D39);
                h ^= h >> 15;
                *o = (h >> 16) as u16 as i16;
            }
        }
    }
    out
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn lerp_exact(p: i64, q: i64, w: i64) -> i64 {
    p.wrapping_mul(1 << 16)
        .wrapping_add(q.wrapping_sub(p).wrapping_mul(w))
}

/// Exact interpolation of the eight corner values with weights `w` (the weight of corner 1 on each
/// axis, `0..=65536` inside the cell). Result has `48 + fv` fraction bits.
#[inline]
pub fn interpolate(v: &[i32; 8], w: [i64; 3]) -> i64 {
    let e = |i: usize| lerp_exact(i64::from(v[i]), i64::from(v[i + 1]), w[0]);
    let f0 = lerp_exact(e(0), e(2), w[1]);
    let f1 = lerp_exact(e(4), e(6), w[1]);
    lerp_exact(f0, f1, w[2])
}

/// The partial derivatives `dP/dw_axis` (each in units of `P` per 2^-16 of weight), exact.
#[inline]
pub fn weight_partials(v: &[i32; 8], w: [i64; 3]) -> [i64; 3] {
    let d = |i: usize, j: usize| i64::from(v[j]).wrapping_sub(i64::from(v[i]));
    let bil = |p00: i64, p10: i64, p01: i64, p11: i64, x: i64, y: i64| {
        let a = lerp_exact(p00, p10, x);
        let b = lerp_exact(p01, p11, x);
        lerp_exact(a, b, y)
    };
    // d/dwx: differences along x, interpolated in (y, z).
    let px = bil(d(0, 1), d(2, 3), d(4, 5), d(6, 7), w[1], w[2]);
    // d/dwy: differences along y, interpolated in (x, z).
    let py = bil(d(0, 2), d(1, 3), d(4, 6), d(5, 7), w[0], w[2]);
    // d/dwz: differences along z, interpolated in (x, y).
    let pz = bil(d(0, 4), d(1, 5), d(2, 6), d(3, 7), w[0], w[1]);
    [px, py, pz]
}

/// Directional derivative: `sum_axis dP/dw_axis * dw_axis`, with `dw` the change of each weight per
/// pixel (raw 16.16). For the linear fade `dw` is the lattice step itself and the result is exact.
#[inline]
pub fn directional(v: &[i32; 8], w: [i64; 3], dw: [i64; 3]) -> i64 {
    let p = weight_partials(v, w);
    p[0].wrapping_mul(dw[0])
        .wrapping_add(p[1].wrapping_mul(dw[1]))
        .wrapping_add(p[2].wrapping_mul(dw[2]))
}

/// The trilinear interpolant of one cell in monomial form, for evaluation at many points of
/// the cell: `P = 2^48 c0 + 2^32 (c1 x + c2 y + c3 z) + 2^16 (c4 xy + c5 xz + c6 yz) + c7 xyz`
/// with `x, y, z` the weights of corner 1 (`0..2^16`) and `c` differences of the corner values.
///
/// Guarantees: [`CellPoly::value`] equals [`interpolate`] and [`CellPoly::directional`] equals
/// [`directional`] bit for bit (the same integer polynomial, every step a ring operation modulo
/// 2^64), for corner values below 2^27 in magnitude (the model bounds them by about 2^13,
/// `docs/model.md` 4.4) and weights below 2^16. A point costs four weight products and eight
/// coefficient products instead of seven exact 64-bit lerps (nine more for a derivative).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct CellPoly {
    c: [i32; 8],
}

/// The derivative of a [`CellPoly`] along one direction `e`, as coefficients of the weight
/// monomials: `2^32 k + 2^16 (a x + b y + c z) + t0 yz + t1 xz + t2 xy`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct CellDirection {
    k: i64,
    a: i64,
    b: i64,
    c: i64,
    t: [i64; 3],
}

/// `c * p` modulo 2^64 for a 32-bit `c` and a 32-bit unsigned `p`.
#[cfg_attr(not(texcore_lean), inline(always))]
fn mul_iu(c: i32, p: u32) -> i64 {
    i64::from(c).wrapping_mul(i64::from(p))
}

/// `a * p` modulo 2^64 for a 64-bit `a` and a 32-bit unsigned `p`.
#[cfg_attr(not(texcore_lean), inline(always))]
fn mul_lu(a: i64, p: u32) -> i64 {
    a.wrapping_mul(i64::from(p))
}

impl CellPoly {
    /// The monomial form of the cell with corner values `v` (corner order `cx | cy << 1 | cz <<
    /// 2`, each below 2^27 in magnitude).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(crate) fn new(v: &[i32; 8]) -> CellPoly {
        debug_assert!(v.iter().all(|x| x.unsigned_abs() < 1 << 27));
        let [v0, v1, v2, v3, v4, v5, v6, v7] = *v;
        let c1 = v1.wrapping_sub(v0);
        let c2 = v2.wrapping_sub(v0);
        let c3 = v4.wrapping_sub(v0);
        let c4 = v3.wrapping_sub(v2).wrapping_sub(c1);
        let c5 = v5.wrapping_sub(v4).wrapping_sub(c1);
        let c6 = v6.wrapping_sub(v4).wrapping_sub(c2);
        let c7 = v7
            .wrapping_sub(v6)
            .wrapping_sub(v5)
            .wrapping_add(v4)
            .wrapping_sub(c4);
        CellPoly {
            c: [v0, c1, c2, c3, c4, c5, c6, c7],
        }
    }

    /// The derivative along `e` (the change of each weight per step, raw 16.16).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(crate) fn direction(&self, e: [i32; 3]) -> CellDirection {
        let [_, c1, c2, c3, c4, c5, c6, c7] = self.c;
        let m = |c: i32, e: i32| i64::from(c).wrapping_mul(i64::from(e));
        let [ex, ey, ez] = e;
        CellDirection {
            k: m(c1, ex).wrapping_add(m(c2, ey)).wrapping_add(m(c3, ez)),
            a: m(c4, ey).wrapping_add(m(c5, ez)),
            b: m(c4, ex).wrapping_add(m(c6, ez)),
            c: m(c5, ex).wrapping_add(m(c6, ey)),
            t: [m(c7, ex), m(c7, ey), m(c7, ez)],
        }
    }

    /// `P` at weights `w` (each below 2^16): [`interpolate`]'s value.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(crate) fn value(&self, w: [u32; 3]) -> i64 {
        let [c0, c1, c2, c3, c4, c5, c6, c7] = self.c;
        let [x, y, z] = w;
        let (xy, xz, yz) = (x * y, x * z, y * z);
        let xyz = (u64::from(xy) * u64::from(z)) as i64;
        let lin = mul_iu(c1, x)
            .wrapping_add(mul_iu(c2, y))
            .wrapping_add(mul_iu(c3, z));
        let bil = mul_iu(c4, xy)
            .wrapping_add(mul_iu(c5, xz))
            .wrapping_add(mul_iu(c6, yz));
        (i64::from(c0) << 48)
            .wrapping_add(lin << 32)
            .wrapping_add(bil << 16)
            .wrapping_add(xyz.wrapping_mul(i64::from(c7)))
    }

    /// The derivative along `d` (from [`CellPoly::direction`]) at weights `w` (each below
    /// 2^16): [`directional`]'s value.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(crate) fn directional(d: &CellDirection, w: [u32; 3]) -> i64 {
        let [x, y, z] = w;
        let (xy, xz, yz) = (x * y, x * z, y * z);
        let lin = mul_lu(d.a, x)
            .wrapping_add(mul_lu(d.b, y))
            .wrapping_add(mul_lu(d.c, z));
        (d.k << 32)
            .wrapping_add(lin << 16)
            .wrapping_add(mul_lu(d.t[0], yz))
            .wrapping_add(mul_lu(d.t[1], xz))
            .wrapping_add(mul_lu(d.t[2], xy))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::lattice_value;

    fn corners() -> [i32; 8] {
        [1000, -2000, 3000, 8191, -8192, 17, 0, -5000]
    }

    #[test]
    fn face_values_are_the_cell_corners() {
        let kinds = [
            HashKind::Integer,
            #[cfg(feature = "perm-hash")]
            HashKind::Permutation,
        ];
        for hash in kinds {
            for cell in [[0u16, 0, 0], [255, 7, 65535], [1234, 40000, 99]] {
                for (amp, fv, vb) in [(65536, 16, 16), (-12345, 3, 9), (32768, 0, 12)] {
                    let all = scaled_corners_bits(hash, cell, amp, fv, vb);
                    for k in 0..3 {
                        let (a, c) = [(1, 2), (0, 2), (0, 1)][k];
                        for b in 0..2 {
                            let f = match k {
                                0 => scaled_face_bits::<0>(hash, cell, b as u16, amp, fv, vb),
                                1 => scaled_face_bits::<1>(hash, cell, b as u16, amp, fv, vb),
                                _ => scaled_face_bits::<2>(hash, cell, b as u16, amp, fv, vb),
                            };
                            for (i, v) in f.iter().enumerate() {
                                let idx = (b << k) | ((i & 1) << a) | ((i >> 1) << c);
                                assert_eq!(*v, all[idx], "{hash:?} {cell:?} k {k} b {b} i {i}");
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn interpolation_hits_corners() {
        let v = corners();
        for c in 0..8 {
            let w = [
                (c & 1) as i64 * 65536,
                ((c >> 1) & 1) as i64 * 65536,
                ((c >> 2) & 1) as i64 * 65536,
            ];
            assert_eq!(interpolate(&v, w), i64::from(v[c]) << 48);
        }
    }

    #[test]
    fn interpolation_equals_weighted_sum() {
        let v = corners();
        for &(a, b, c) in &[
            (0i64, 0, 0),
            (1, 2, 3),
            (65535, 12345, 40000),
            (32768, 32768, 32768),
        ] {
            let mut want: i128 = 0;
            for (k, &vk) in v.iter().enumerate() {
                let wx = if k & 1 == 1 { a } else { 65536 - a };
                let wy = if k & 2 == 2 { b } else { 65536 - b };
                let wz = if k & 4 == 4 { c } else { 65536 - c };
                want += i128::from(vk) * i128::from(wx) * i128::from(wy) * i128::from(wz);
            }
            assert_eq!(i128::from(interpolate(&v, [a, b, c])), want);
        }
    }

    #[test]
    fn partials_match_differences() {
        // P is multilinear in the weights, so dP/dw is exactly P(w + 1) - P(w) along that axis.
        let v = corners();
        let w = [1234i64, 54321, 999];
        let p = weight_partials(&v, w);
        for axis in 0..3 {
            let mut w1 = w;
            w1[axis] += 1;
            assert_eq!(
                p[axis],
                interpolate(&v, w1) - interpolate(&v, w),
                "axis {axis}"
            );
        }
        let d = [7i64, -3, 11];
        assert_eq!(directional(&v, w, d), p[0] * 7 - p[1] * 3 + p[2] * 11);
    }

    #[test]
    fn corner_values_are_the_lattice_values() {
        let kinds = [
            HashKind::Integer,
            #[cfg(feature = "perm-hash")]
            HashKind::Permutation,
        ];
        let mut st = 5u32;
        for kind in kinds {
            for k in 0..3000u32 {
                st = st.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let mut cell = [(st >> 16) as u16, st as u16, (st >> 8) as u16];
                if k % 7 == 0 {
                    cell[(k % 3) as usize] = 0xFFFF; // wrap at the top of the lattice
                }
                let got = corner_values(kind, cell);
                for (c, &g) in got.iter().enumerate() {
                    let want = lattice_value(
                        kind,
                        cell[0].wrapping_add((c & 1) as u16),
                        cell[1].wrapping_add(((c >> 1) & 1) as u16),
                        cell[2].wrapping_add(((c >> 2) & 1) as u16),
                    );
                    assert_eq!(g, want, "{kind:?} {cell:?} corner {c}");
                }
            }
        }
    }

    #[test]
    fn value_quantisation() {
        assert_eq!(quantize_value(12345, 16), 12345);
        // 4 bits: multiples of 4096, half up, saturated below 32768.
        assert_eq!(quantize_value(2047, 4), 0);
        assert_eq!(quantize_value(2048, 4), 4096);
        assert_eq!(quantize_value(-2048, 4), 0);
        assert_eq!(quantize_value(-2049, 4), -4096);
        assert_eq!(quantize_value(32767, 4), 28672);
        assert_eq!(quantize_value(-32768, 4), -32768);
        assert_eq!(quantize_value(32767, 8), 32512);
        for bits in 1..=16u32 {
            let step = 1i32 << (16 - bits);
            for v in (-32768i32..32768).step_by(7) {
                let q = i32::from(quantize_value(v as i16, bits));
                assert_eq!(q % step, 0, "{v} {bits}");
                assert!((q - v).abs() <= step, "{v} {bits} {q}");
                assert!(q >= -32768 && q <= 32768 - step);
            }
        }
        let a = scaled_corners(HashKind::Integer, [5, 6, 7], 1 << 16, 13);
        assert_eq!(
            a,
            scaled_corners_bits(HashKind::Integer, [5, 6, 7], 1 << 16, 13, 16)
        );
        assert_ne!(
            a,
            scaled_corners_bits(HashKind::Integer, [5, 6, 7], 1 << 16, 13, 4)
        );
    }

    #[test]
    fn scaled_values() {
        // amplitude 1.0 with fv = 13: v' = v / 4 rounded.
        let c = scaled_corners(HashKind::Integer, [5, 6, 7], 1 << 16, 13);
        for (k, &vk) in c.iter().enumerate() {
            let v = i64::from(lattice_value(
                HashKind::Integer,
                5 + (k & 1) as u16,
                6 + ((k >> 1) & 1) as u16,
                7 + ((k >> 2) & 1) as u16,
            ));
            assert_eq!(i64::from(vk), (v * 65536 + (1 << 17)) >> 18);
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
        /// The monomial form evaluates exactly as the lerp form, value and derivative.
        #[test]
        fn cell_poly_equals_lerp_form(
            v in proptest::array::uniform8(-(1i32 << 26)..(1 << 26)),
            w in proptest::array::uniform3(0u32..65536),
            e in proptest::array::uniform3(proptest::prelude::any::<i32>()),
        ) {
            let p = CellPoly::new(&v);
            let wi = w.map(i64::from);
            proptest::prop_assert_eq!(p.value(w), interpolate(&v, wi));
            let d = p.direction(e);
            proptest::prop_assert_eq!(
                CellPoly::directional(&d, w),
                directional(&v, wi, e.map(i64::from))
            );
        }
    }

    #[test]
    fn cell_poly_extremes() {
        let big = (1 << 27) - 1;
        for v in [
            [big; 8],
            [-big; 8],
            [big, -big, big, -big, -big, big, -big, big],
        ] {
            let p = CellPoly::new(&v);
            for w in [[0, 0, 0], [65535; 3], [65535, 0, 65535], [1, 65535, 2]] {
                let wi = w.map(i64::from);
                assert_eq!(p.value(w), interpolate(&v, wi));
                for e in [[i32::MAX, i32::MIN, -1], [65536, -65536, 0]] {
                    let d = p.direction(e);
                    assert_eq!(
                        CellPoly::directional(&d, w),
                        directional(&v, wi, e.map(i64::from))
                    );
                }
            }
        }
    }
}
