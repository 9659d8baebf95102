//! Olano's mNoise (2005): corner gradients `(±1, ±1, ±1)` chosen by the table-free hash
//! `h(x) = x^2 mod 61`. Dimension reducible: the 3D noise at integer `z = 0` equals the 2D noise
//! exactly, and at `z = k` equals the 2D noise at `y + h(k)` (period 61).
//!
//! The raw interpolant of corner-gradient noise is bounded by 1.5 for any hash (all eight corner
//! gradients pointing away from the cell centre); with `x^2 mod 61` an exhaustive scan of every
//! cell reaches -1.39 .. 1.20 (linear fade) and -1.40 .. 1.25 (quintic). It is normalised to
//! [-1, 1] by the constant [`MNOISE_SCALE`] = 2/3 (U0F16), so the clamp never acts. (Perlin's
//! gradient noise reaches 1.03 with these hashes and at most 1.065 with any; it is not scaled.)

use super::gradient::{self, corner_gradient, Grad};
use super::Fade;
use crate::hash::{hash61, hash61_2};

/// Normalisation of raw mNoise to `[-1, 1]`: 2/3 in U0F16.
pub const MNOISE_SCALE: i64 = 43691;

/// The corner gradients of the cell at `cell`.
#[inline]
pub fn cell_gradients(cell: [u16; 3]) -> [Grad; 8] {
    let mut g = [[0i8; 3]; 8];
    for (c, gc) in g.iter_mut().enumerate() {
        *gc = corner_gradient(hash61(
            cell[0].wrapping_add((c & 1) as u16),
            cell[1].wrapping_add(((c >> 1) & 1) as u16),
            cell[2].wrapping_add(((c >> 2) & 1) as u16),
        ));
    }
    g
}

/// Normalises a raw interpolant (units 2^-16) to `[-65536, 65536]`.
#[inline]
pub fn normalise(n16: i64) -> i64 {
    ((n16 * MNOISE_SCALE) >> 16).clamp(-65536, 65536)
}

/// Two-dimensional mNoise at lattice point `(x, y)` (raw 16.16), normalised, units 2^-16.
/// Its corners use [`hash61_2`] and 2D corner gradients `(±1, ±1)`.
pub fn noise2(x: i32, y: i32, fade: Fade) -> i64 {
    let cx = (x >> 16) as u16;
    let cy = (y >> 16) as u16;
    let mut g = [[0i8; 3]; 8];
    for (c, gc) in g.iter_mut().enumerate().take(4) {
        let m = hash61_2(
            cx.wrapping_add((c & 1) as u16),
            cy.wrapping_add(((c >> 1) & 1) as u16),
        );
        let full = corner_gradient(m);
        *gc = [full[0], full[1], 0];
    }
    // A 2D noise is the z = 0 face: the upper face's weight is zero, its gradients irrelevant.
    let frac = [(x & 0xFFFF) as u32, (y & 0xFFFF) as u32, 0];
    normalise(gradient::value(&g, frac, fade))
}

#[cfg(test)]
mod tests {
    use super::super::{BasisKind, NoiseBasis};
    use super::*;
    use crate::hash::{h61, HashKind};

    fn basis(fade: Fade) -> NoiseBasis {
        NoiseBasis {
            kind: BasisKind::Modified,
            fade,
            hash: HashKind::Integer,
        }
    }

    #[test]
    fn slice_at_integer_z_is_2d_noise() {
        for fade in [
            Fade::Linear,
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth,
        ] {
            let b = basis(fade);
            for i in 0..4000i32 {
                let x = i.wrapping_mul(7919 * 13) & 0x3F_FFFF;
                let y = i.wrapping_mul(104729 * 7) & 0x3F_FFFF;
                assert_eq!(
                    b.value16_at([x, y, 0]),
                    noise2(x, y, fade),
                    "z=0 at {x:#x},{y:#x}"
                );
                for k in [1u16, 5, 60] {
                    let shift = (h61(u32::from(k)) as i32) << 16;
                    assert_eq!(
                        b.value16_at([x, y, i32::from(k) << 16]),
                        noise2(x, y + shift, fade),
                        "z={k}"
                    );
                }
            }
        }
    }

    #[test]
    fn period_61() {
        let b = basis(Fade::Linear);
        for i in 0..500i32 {
            let p = [i * 40503, i * 9973 + 17, i * 3001 + 5];
            let q = [p[0] + (61 << 16), p[1], p[2] + (61 << 16)];
            assert_eq!(b.value16_at(p), b.value16_at(q));
        }
    }
}
