//! Cell set-up of a trilinear term whose lattice step along the span has one nonzero axis (a
//! plane aligned with the lattice: unrotated octaves on an axis-aligned image plane).
//!
//! Along such a span the two other fractions are constant, so inside a cell the term is
//! **linear** in the pixel index: with `k` the moving axis, `w = f_k + j d_k` and `Phi_b` the
//! bilinear blend (over the two other axes, constant weights) of the cell's face `c_k = b`,
//!
//! `P(j) = Phi_0 (2^16 - w) + Phi_1 w = Phi_0 2^16 + (Phi_1 - Phi_0) f_k + (Phi_1 - Phi_0) d_k j`,
//!
//! and the derivative across the span (direction `e`) is `H_0 (2^16 - w) + H_1 w +
//! (Phi_1 - Phi_0) e_k` with `H_b` the directional derivative of the face blend. This is the
//! polynomial of [`cubic_poly`] (the same multilinear form of `docs/model.md` 4.2, expanded in
//! another order) with zero quadratic and cubic coefficients; every operation is a ring
//! operation modulo 2^64, so the coefficients are bit-identical to [`cubic_poly`]'s (tested),
//! and so are the forward differences and the samples. It costs 6 to 10 products instead of 22
//! to 41.
//!
//! The face blends depend only on the face's corners and the constant weights, so they are
//! exact per face: [`AxisFaces`] keeps the blends of the cell's two faces, and a term that steps
//! into the neighbouring cell along `k` reuses the shared face (4 of the 8 corners) instead of
//! hashing and blending it again.

use super::*;

/// The one nonzero axis of a lattice step, if exactly one is nonzero.
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn single_axis(du: [i32; 3]) -> Option<usize> {
    match (du[0] != 0, du[1] != 0, du[2] != 0) {
        (true, false, false) => Some(0),
        (false, true, false) => Some(1),
        (false, false, true) => Some(2),
        _ => None,
    }
}

/// The scaled corners of the face `c_k = b` of `cell` ([`scaled_face_bits`], specialised per
/// axis so the permutation chain's shared look-ups are found at compile time).
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn face_bits(
    k: usize,
    hash: HashKind,
    cell: [u16; 3],
    b: usize,
    amp: i32,
    fv: u32,
    vb: u32,
) -> [i32; 4] {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    let b = b as u16;
    match k {
        0 => scaled_face_bits::<0>(hash, cell, b, amp, fv, vb),
        1 => scaled_face_bits::<1>(hash, cell, b, amp, fv, vb),
        _ => scaled_face_bits::<2>(hash, cell, b, amp, fv, vb),
    }
}

/// The two axes other than `k`, in ascending order.
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn others(k: usize) -> (usize, usize) {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    match k {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The blend of one face (`Phi`) and its derivative across the span (`H`), exact mod 2^64.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Face {
    phi: i64,
    h: i64,
}

impl Face {
    /// The blend `Phi`.
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    pub(super) fn phi(&self) -> i64 {
        self.phi
    }

    /// The blend's derivative across the span (`h`).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    pub(super) fn h(&self) -> i64 {
        self.h
    }
}

/// The four corners of the face `c_k = b` of the cell corners `v` (corner order
/// `cx | cy << 1 | cz << 2`), in the face order `ca | cc << 1` (`a < c` the two other axes).
#[cfg(test)]
fn face_corners(v: &[i32; 8], k: usize, b: usize) -> [i32; 4] {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    let (a, c) = others(k);
    core::array::from_fn(|i| v[(b << k) | ((i & 1) << a) | ((i >> 1) << c)])
}

/// Blends a face of a cell (its four scaled corners `w` in the order `ca | cc << 1`, `a < c` the
/// two axes other than `k`): lerps along axis `a`, then along axis `c`, with the constant
/// fractions `f`, carrying the derivative along `e` as the dual part (only when `grads`).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn face(w: &[i32; 4], k: usize, f: [u32; 3], e: [i32; 3], grads: bool) -> Face {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    let (a, c) = others(k);
    // Level a: t = v0 2^16 + (v1 - v0) f_a (v' fits 26 bits, model 4.4: exact 32 x 32 -> 64).
    let fa = i64::from(f[a]);
    let lerp_a = |v0: i32, v1: i32| -> (i64, i64) {
        let dv = i64::from(v1.wrapping_sub(v0));
        (
            wadd(i64::from(v0) << 16, dv * fa),
            wmul(dv, i64::from(e[a])),
        )
    };
    let (t0, dt0) = lerp_a(w[0], w[1]);
    let (t1, dt1) = lerp_a(w[2], w[3]);
    let fc = i64::from(f[c]);
    let d = wsub(t1, t0);
    let phi = wadd(t0 << 16, wmul(d, fc));
    if !(GRADIENTS && grads) {
        return Face { phi, h: 0 };
    }
    let h = wadd(
        wadd(dt0 << 16, wmul(wsub(dt1, dt0), fc)),
        wmul(d, i64::from(e[c])),
    );
    Face { phi, h }
}

/// The cell polynomial of a single-axis term from its two face blends: `frac` at local pixel 0,
/// `d` the step along axis `k`, `e` the lattice step across the span.
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn poly(
    faces: &[Face; 2],
    k: usize,
    frac: [u32; 3],
    d: i32,
    e: [i32; 3],
    grads: bool,
) -> CubicPoly {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    let [f0, f1] = faces;
    let dphi = wsub(f1.phi, f0.phi);
    let fk = i64::from(frac[k]);
    let g = [
        wadd(f0.phi << 16, wmul(dphi, fk)),
        wmul(dphi, i64::from(d)),
        0,
        0,
    ];
    if !(GRADIENTS && grads) {
        return CubicPoly { g, h: [0; 3] };
    }
    let dh = wsub(f1.h, f0.h);
    let h = [
        wadd(wadd(f0.h << 16, wmul(dh, fk)), wmul(dphi, i64::from(e[k]))),
        wmul(dh, i64::from(d)),
        0,
    ];
    CubicPoly { g, h }
}

/// Adds the forward-difference state at local pixel 0 of a linear cell polynomial (`poly`'s
/// output: `g2 = g3 = h2 = 0`) to the merged state: what `sum.add(&fd_start(c, grads))` adds,
/// without the words that are zero.
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn linear_add(sum: &mut Cubic, c: &CubicPoly, grads: bool) {
    sum.p[0] = wadd(sum.p[0], c.g[0]);
    sum.p[1] = wadd(sum.p[1], c.g[1]);
    if GRADIENTS && grads {
        sum.gx[0] = wadd(sum.gx[0], c.g[1]);
        sum.gy[0] = wadd(sum.gy[0], c.h[0]);
        sum.gy[1] = wadd(sum.gy[1], c.h[1]);
    }
}

/// Subtracts the state of a linear cell polynomial at local pixel `l` from the merged state:
/// what `sum.sub(&fd_at(c, l, grads))` subtracts, without the words that are zero.
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn linear_sub(sum: &mut Cubic, c: &CubicPoly, l: u32, grads: bool) {
    let l = i64::from(l);
    sum.p[0] = wsub(sum.p[0], wadd(c.g[0], wmul(c.g[1], l)));
    sum.p[1] = wsub(sum.p[1], c.g[1]);
    if GRADIENTS && grads {
        sum.gx[0] = wsub(sum.gx[0], c.g[1]);
        sum.gy[0] = wsub(sum.gy[0], wadd(c.h[0], wmul(c.h[1], l)));
        sum.gy[1] = wsub(sum.gy[1], c.h[1]);
    }
}

/// The face blends of a single-axis term's current cell, kept across its cell events.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct AxisFaces {
    /// Cell the faces belong to (when `known`; not an `Option`: with every byte defined a new
    /// set of faces is a plain clear, not a copy of undefined bytes through `memcpy`).
    cell: [u16; 3],
    known: bool,
    faces: [Face; 2],
}

impl AxisFaces {
    /// The polynomial of the term in `cell` (fractions `frac` at local pixel 0, steps `du` along
    /// and `dy` across the span, moving axis `k`), reusing the shared face when the previous
    /// cell is the neighbour along `k`. `face_of(cell, b)` hashes and scales the four corners of
    /// a cell's face `c_k = b` (`noise::value::scaled_face_bits`).
    #[allow(clippy::too_many_arguments)]
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn enter(
        &mut self,
        cell: [u16; 3],
        frac: [u32; 3],
        k: usize,
        du: [i32; 3],
        dy: [i32; 3],
        grads: bool,
        face_of: impl Fn([u16; 3], usize) -> [i32; 4],
    ) -> CubicPoly {
        let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
        self.blend(cell, frac, k, dy, grads, face_of);
        poly(&self.faces, k, frac, du[k], dy, grads)
    }

    /// Blends the faces of `cell` (see [`AxisFaces::enter`]), reusing the shared face.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn blend(
        &mut self,
        cell: [u16; 3],
        frac: [u32; 3],
        k: usize,
        dy: [i32; 3],
        grads: bool,
        face_of: impl Fn([u16; 3], usize) -> [i32; 4],
    ) {
        let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
        let step = if self.known && same_but(self.cell, cell, k) {
            cell[k].wrapping_sub(self.cell[k])
        } else {
            0
        };
        let blend = |b: usize| face(&face_of(cell, b), k, frac, dy, grads);
        // A step of +1 along k: the old face 1 is the new face 0, and -1 the reverse.
        self.faces = match step {
            1 => [self.faces[1], blend(1)],
            0xFFFF => [blend(0), self.faces[0]],
            _ => [blend(0), blend(1)],
        };
        self.cell = cell;
        self.known = true;
    }

    /// The term's value at fraction `fk` along the moving axis of the current cell:
    /// `Phi_0 2^16 + (Phi_1 - Phi_0) fk`, exactly `noise::value::interpolate` there.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn value_at(&self, fk: u32) -> i64 {
        let [f0, f1] = &self.faces;
        wadd(f0.phi << 16, wmul(wsub(f1.phi, f0.phi), i64::from(fk)))
    }
}

/// Whether `a` and `b` agree on every axis but `k`.
#[cfg_attr(not(texcore_lean), inline(always))]
fn same_but(a: [u16; 3], b: [u16; 3], k: usize) -> bool {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    (0..3).all(|i| i == k || a[i] == b[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn corners() -> impl proptest::strategy::Strategy<Value = [i32; 8]> {
        // Scaled corner values fit 26 bits (model 4.4).
        proptest::array::uniform8(-(1i32 << 25)..(1i32 << 25))
    }

    proptest! {
        #[test]
        fn single_axis_poly_is_cubic_poly(
            v in corners(),
            frac in proptest::array::uniform3(0u32..65536),
            k in 0usize..3,
            d in -32768i32..=32768,
            dy in proptest::array::uniform3(-32768i32..=32768),
            grads: bool,
        ) {
            let d = if d == 0 { 1 } else { d };
            let mut du = [0; 3];
            du[k] = d;
            prop_assert_eq!(single_axis(du), Some(k));
            let faces = [
                face(&face_corners(&v, k, 0), k, frac, dy, grads),
                face(&face_corners(&v, k, 1), k, frac, dy, grads),
            ];
            let want = cubic_poly(&v, frac, du, dy, grads);
            let got = poly(&faces, k, frac, d, dy, grads);
            prop_assert_eq!(got.g, want.g);
            if GRADIENTS && grads {
                prop_assert_eq!(got.h, want.h);
            }
        }
    }

    proptest! {
        #[test]
        fn linear_state_updates_are_fd_start_and_fd_at(
            v in corners(),
            frac in proptest::array::uniform3(0u32..65536),
            k in 0usize..3,
            d in 1i32..=32768,
            dy in proptest::array::uniform3(-32768i32..=32768),
            l in 0u32..65536,
            grads: bool,
        ) {
            let faces = [
                face(&face_corners(&v, k, 0), k, frac, dy, grads),
                face(&face_corners(&v, k, 1), k, frac, dy, grads),
            ];
            let c = poly(&faces, k, frac, d, dy, grads);
            let mut a = Cubic::default();
            let mut b = Cubic::default();
            linear_add(&mut a, &c, grads);
            b.add(&fd_start(&c, grads));
            prop_assert_eq!((a.p, a.gx, a.gy), (b.p, b.gx, b.gy));
            linear_sub(&mut a, &c, l, grads);
            b.sub(&fd_at(&c, l, grads));
            prop_assert_eq!((a.p, a.gx, a.gy), (b.p, b.gx, b.gy));
        }
    }

    proptest! {
        #[test]
        fn face_value_is_interpolate(
            v in corners(),
            frac in proptest::array::uniform3(0u32..65536),
            k in 0usize..3,
        ) {
            let mut af = AxisFaces::default();
            af.blend([3, 4, 5], frac, k, [0; 3], false, |_, b| face_corners(&v, k, b));
            let w = frac.map(i64::from);
            prop_assert_eq!(af.value_at(frac[k]), crate::noise::value::interpolate(&v, w));
        }
    }

    #[test]
    fn shared_face_is_reused_and_exact() {
        // Corners of a cell as a function of the cell: any deterministic function will do.
        let at = |c: [u16; 3]| -> [i32; 8] {
            core::array::from_fn(|i| {
                let x = i32::from(c[0]) + (i as i32 & 1);
                let y = i32::from(c[1]) + (i as i32 >> 1 & 1);
                let z = i32::from(c[2]) + (i as i32 >> 2);
                ((x * 7919 + y * 104_729 + z * 1_299_709) % 8191) << 12
            })
        };
        for k in 0..3 {
            for d in [2048, -2048] {
                let mut du = [0; 3];
                du[k] = d;
                let dy = [100, -300, 500];
                let mut faces = AxisFaces::default();
                let mut cell = [5u16, 9, 13];
                let frac = [123, 45_678, 9_999];
                let mut first = true;
                for _ in 0..6 {
                    let hashed = core::cell::Cell::new(0);
                    let got = faces.enter(cell, frac, k, du, dy, true, |c, b| {
                        hashed.set(hashed.get() + 1);
                        face_corners(&at(c), k, b)
                    });
                    // The shared face is reused after the first cell.
                    assert_eq!(hashed.get(), if first { 2 } else { 1 });
                    first = false;
                    let want = cubic_poly(&at(cell), frac, du, dy, true);
                    assert_eq!(got.g, want.g);
                    if GRADIENTS {
                        assert_eq!(got.h, want.h);
                    }
                    cell[k] = if d > 0 {
                        cell[k].wrapping_add(1)
                    } else {
                        cell[k].wrapping_sub(1)
                    };
                }
            }
        }
    }
}
