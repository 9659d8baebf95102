//! The quadric along a span: its matrix, the sparse matrix-vector set-up and the 64-bit
//! stepping state with its exactness bound ([`fits`]).

/// The quadric's symmetric matrix (raw 16.16 entries).
pub(super) fn quadric_matrix(q: &crate::quadric::Quadric) -> [[i32; 4]; 4] {
    let [a, b, c, d, e, f, g, h, i, j] = q.coefficients().map(|k| k.to_bits());
    [[a, b, c, d], [b, e, f, g], [c, f, h, i], [d, g, i, j]]
}

/// The nonzero entries of `m`: bit `4 r + c` for entry `(r, c)`.
pub(super) fn quadric_mask(m: &[[i32; 4]; 4]) -> u16 {
    m.iter()
        .flatten()
        .enumerate()
        .fold(0, |acc, (k, &q)| if q != 0 { acc | 1 << k } else { acc })
}

/// `Q v` for a homogeneous vector of 32-bit components (as i64), visiting only the entries in
/// `mask` (the nonzero ones, [`quadric_mask`]); exact. The size-lean shape sums into the
/// array (smaller code).
#[cfg(texcore_lean)]
pub(super) fn mat_vec(m: &[[i32; 4]; 4], mask: u16, v: &[i64; 4]) -> [i128; 4] {
    let mut out = [0i128; 4];
    let mut bits = mask;
    while bits != 0 {
        let k = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let (r, c) = (k >> 2, k & 3);
        if let (Some(o), Some(&q), Some(&x)) = (
            out.get_mut(r),
            m.get(r).and_then(|row| row.get(c)),
            v.get(c),
        ) {
            // |q| < 2^31 and |x| <= 2^31 (span coordinates are raw i32): exact in i64.
            *o = o.wrapping_add(i128::from(i64::from(q).wrapping_mul(x)));
        }
    }
    out
}

/// `Q v` for a homogeneous vector of 32-bit components (as i64), visiting only the entries in
/// `mask` (the nonzero ones, [`quadric_mask`]); exact. The fast shape sums into four scalars
/// (the size-lean shape's sums): an array filled in place is cleared first by a library call
/// on the Cortex-M.
#[cfg(not(texcore_lean))]
pub(super) fn mat_vec(m: &[[i32; 4]; 4], mask: u16, v: &[i64; 4]) -> [i128; 4] {
    let mut out = (0i128, 0i128, 0i128, 0i128);
    let mut bits = mask;
    while bits != 0 {
        let k = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let (r, c) = (k >> 2, k & 3);
        if let (Some(&q), Some(&x)) = (m.get(r).and_then(|row| row.get(c)), v.get(c)) {
            // |q| < 2^31 and |x| <= 2^31 (span coordinates are raw i32): exact in i64.
            let p = i128::from(i64::from(q).wrapping_mul(x));
            let o = match r {
                0 => &mut out.0,
                1 => &mut out.1,
                2 => &mut out.2,
                _ => &mut out.3,
            };
            *o = o.wrapping_add(p);
        }
    }
    [out.0, out.1, out.2, out.3]
}

/// `v . w` in wrapping i128, skipping zero products. Out of line in the fast shape on the
/// Cortex-M (a set-up takes up to five: one copy of the four 128-bit products instead of one
/// each, 2.3 KB smaller and a few instructions a span cheaper); inlined on rv32imc, whose many
/// registers keep the products' operands (out of line it measured 6 to 12% dearer on
/// `stage:quadric`).
#[cfg_attr(all(not(texcore_lean), not(target_arch = "riscv32")), inline(never))]
pub(super) fn dot(v: &[i64; 4], w: &[i128; 4]) -> i128 {
    let mut acc: i128 = 0;
    for (&a, &b) in v.iter().zip(w) {
        if a != 0 && b != 0 {
            acc = acc.wrapping_add(mul_i64(b, a));
        }
    }
    acc
}

/// `b a`, wrapping.
#[inline(always)]
pub(super) fn mul_i64(b: i128, a: i64) -> i128 {
    b.wrapping_mul(i128::from(a))
}

/// The quadric (48 fraction bits) and its two screen derivatives along a span, stepped in i64.
#[derive(Clone, Copy)]
pub(super) struct QuadStep {
    pub(super) q: i64,
    pub(super) dq: i64,
    pub(super) ddq: i64,
    pub(super) gx: i64,
    pub(super) dgx: i64,
    pub(super) gy: i64,
    pub(super) dgy: i64,
}

impl QuadStep {
    /// The quadric of a span's set-up at its pixel 0: value, first and second forward
    /// differences, gradients and their steps (wrapped to `i64`).
    #[inline(always)]
    pub(super) fn new<const T: usize>(setup: &super::Setup<T>) -> QuadStep {
        let qc = setup.quadric().quad.c;
        QuadStep {
            q: qc[0] as i64,
            dq: qc[1].wrapping_add(qc[2]) as i64,
            ddq: qc[2].wrapping_mul(2) as i64,
            gx: setup.quadric().gqx[0] as i64,
            dgx: setup.quadric().gqx[1] as i64,
            gy: setup.quadric().gqy[0] as i64,
            dgy: setup.quadric().gqy[1] as i64,
        }
    }

    /// The value's three words and the quadric's kind along the span: 0 zero, 1 affine, 2
    /// curved (word by word: an array comparison is a library call on the devices).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    pub(super) fn value_kind<const T: usize>(setup: &super::Setup<T>) -> ([i64; 3], u8) {
        let qc = setup.quadric().quad.c;
        let q = [
            qc[0] as i64,
            qc[1].wrapping_add(qc[2]) as i64,
            qc[2].wrapping_mul(2) as i64,
        ];
        let kind = match ((q[0] | q[1] | q[2]) == 0, qc[2] == 0) {
            (true, _) => 0u8,
            (false, true) => 1,
            (false, false) => 2,
        };
        (q, kind)
    }
}

/// Whether the polynomial `sum_m c_m i^m` (degree <= 2) provably stays below 2^62 in magnitude for
/// `i` in `0..len` (`len <= 65535`), then its wrapping i64 forward differences are exact values
/// and adding a value below 2^62 cannot overflow. Conservative and cheap (no wide
/// multiplications, which are library calls on 32-bit cores): each nonzero term must satisfy
/// `|c_m| len^m < 2^60`, checked on bit lengths (`bits(|c_m|) + 16 m <= 60`).
pub(super) fn fits(c: &[i128], len: u32) -> bool {
    let lbits = 32 - len.leading_zeros(); // len < 2^lbits
    c.iter().enumerate().all(|(m, &cm)| {
        cm == 0 || (128 - cm.unsigned_abs().leading_zeros()) + lbits * m as u32 <= 60
    })
}
