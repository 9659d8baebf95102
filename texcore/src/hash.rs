//! Lattice hashes: map an integer lattice cell corner to pseudo-random bits.
//!
//! Three hashes, all defined bit for bit in `docs/model.md` section 2:
//! - `perm_hash`: Ken Perlin's 256-entry permutation table, chained three times (period 256);
//!   needs a 256-byte ROM (feature `perm-hash`).
//! - [`int_hash`]: a table-free integer mixer (period 2^16) for builds with no ROM tables, such as
//!   FPGA soft-cores.
//! - [`hash61`]: Olano's `x^2 mod 61` hash for mNoise (period 61; dimension reducible).
//!
//! Guarantees: every function is total (defined for all inputs), branch-free apart from the
//! mod-61 reduction, never panics, and is identical on every target.

/// Which hash a lattice noise basis uses to pick its corner values or gradients.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HashKind {
    /// Perlin's permutation table (256-byte ROM), period 256.
    #[cfg(feature = "perm-hash")]
    Permutation,
    /// Table-free integer hash, period 2^16.
    Integer,
}

impl Default for HashKind {
    fn default() -> Self {
        #[cfg(feature = "perm-hash")]
        return HashKind::Permutation;
        #[cfg(not(feature = "perm-hash"))]
        return HashKind::Integer;
    }
}

/// Ken Perlin's reference permutation ("Improving Noise", 2002).
#[cfg(feature = "perm-hash")]
pub const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// Permutation hash of a lattice point: `P[(P[(P[x] + y) & 255] + z) & 255]` on the low 8 bits.
#[cfg(feature = "perm-hash")]
#[inline]
pub fn perm_hash(x: u16, y: u16, z: u16) -> u8 {
    let p = &PERMUTATION;
    let a = p[usize::from(x as u8)];
    let b = p[usize::from(a.wrapping_add(y as u8))];
    p[usize::from(b.wrapping_add(z as u8))]
}

/// Table-free integer hash of a lattice point (32 well-mixed bits, period 2^16 per axis).
#[inline]
pub fn int_hash(x: u16, y: u16, z: u16) -> u32 {
    let mut h = u32::from(x).wrapping_mul(0x9E37_79B1)
        ^ u32::from(y).wrapping_mul(0x85EB_CA77)
        ^ u32::from(z).wrapping_mul(0xC2B2_AE3D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297A_2D39);
    h ^= h >> 15;
    h
}

/// Olano's one-dimensional mNoise hash `h(x) = (x mod 61)^2 mod 61`.
#[inline]
pub fn h61(x: u32) -> u32 {
    let m = x % 61;
    (m * m) % 61
}

/// Olano's mNoise lattice hash `h(x + h(y + h(z)))`, in `0..61`.
#[inline]
pub fn hash61(x: u16, y: u16, z: u16) -> u32 {
    h61(u32::from(x) + h61(u32::from(y) + h61(u32::from(z))))
}

/// The two-dimensional mNoise hash `h(x + h(y))`: equal to `hash61(x, y, 0)`.
#[inline]
pub fn hash61_2(x: u16, y: u16) -> u32 {
    h61(u32::from(x) + h61(u32::from(y)))
}

/// Value-noise corner value for a lattice point: `v / 32768` in `[-1, 1)` (`docs/model.md` 2.4).
#[inline]
pub fn lattice_value(kind: HashKind, x: u16, y: u16, z: u16) -> i16 {
    match kind {
        #[cfg(feature = "perm-hash")]
        HashKind::Permutation => (i32::from(perm_hash(x, y, z)) * 257 - 32768) as i16,
        HashKind::Integer => (int_hash(x, y, z) >> 16) as u16 as i16,
    }
}

/// Gradient selector bits for a lattice point (the low 4 bits pick one of Perlin's gradients).
#[inline]
pub fn gradient_bits(kind: HashKind, x: u16, y: u16, z: u16) -> u8 {
    match kind {
        #[cfg(feature = "perm-hash")]
        HashKind::Permutation => perm_hash(x, y, z),
        HashKind::Integer => int_hash(x, y, z) as u8,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "perm-hash")]
    #[test]
    fn permutation_is_a_permutation() {
        let mut seen = [false; 256];
        for &v in PERMUTATION.iter() {
            assert!(!seen[usize::from(v)], "duplicate {v}");
            seen[usize::from(v)] = true;
        }
        assert_eq!(PERMUTATION[0], 151);
        assert_eq!(PERMUTATION[255], 180);
    }

    #[cfg(feature = "perm-hash")]
    #[test]
    fn perm_hash_period_256() {
        for (x, y, z) in [(0u16, 0u16, 0u16), (17, 200, 3), (255, 255, 255)] {
            let h = perm_hash(x, y, z);
            assert_eq!(
                h,
                perm_hash(x + 256, y.wrapping_add(512), z.wrapping_add(65280))
            );
        }
        // P[P[P[0]]] with P[0]=151, P[151]=..
        let p = &PERMUTATION;
        assert_eq!(perm_hash(0, 0, 0), p[usize::from(p[usize::from(p[0])])]);
    }

    #[test]
    fn int_hash_mixes() {
        // Neighbouring lattice points differ in about half their bits on average.
        let mut total = 0u32;
        let mut n = 0u32;
        for x in 0..64u16 {
            for y in 0..8u16 {
                total += (int_hash(x, y, 3) ^ int_hash(x + 1, y, 3)).count_ones();
                total += (int_hash(x, y, 3) ^ int_hash(x, y + 1, 3)).count_ones();
                total += (int_hash(x, y, 3) ^ int_hash(x, y, 4)).count_ones();
                n += 3;
            }
        }
        let mean = total as f64 / n as f64;
        assert!((14.0..18.0).contains(&mean), "mean flipped bits {mean}");
        assert_ne!(int_hash(0, 0, 0), int_hash(1, 0, 0));
    }

    #[test]
    fn hash61_dimension_reducible() {
        for x in 0..200u16 {
            for y in 0..200u16 {
                assert_eq!(hash61(x, y, 0), hash61_2(x, y));
                let k = 37u16;
                assert_eq!(
                    hash61(x, y, k),
                    h61(u32::from(x) + h61(u32::from(y) + h61(u32::from(k))))
                );
            }
        }
        assert_eq!(h61(0), 0);
        assert_eq!(h61(61 + 5), 25);
        assert!((0..65535u32).all(|x| h61(x) < 61));
    }

    #[test]
    fn lattice_values_cover_range() {
        let mut min = i16::MAX;
        let mut max = i16::MIN;
        let mut sum = 0i64;
        for x in 0..256u16 {
            let v = lattice_value(HashKind::Integer, x, 7, 9);
            min = min.min(v);
            max = max.max(v);
            sum += i64::from(v);
        }
        assert!(min < -28000 && max > 28000, "{min} {max}");
        assert!((sum / 256).abs() < 4000);
        #[cfg(feature = "perm-hash")]
        {
            // A permutation: the 256 values at fixed y, z are 257*h - 32768 for every h.
            let mut vals: [i16; 256] = [0; 256];
            for x in 0..256u16 {
                vals[usize::from(x)] = lattice_value(HashKind::Permutation, x, 0, 0);
            }
            vals.sort_unstable();
            for (h, v) in vals.iter().enumerate() {
                assert_eq!(i32::from(*v), h as i32 * 257 - 32768);
            }
        }
    }
}
