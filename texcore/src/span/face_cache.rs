//! Face blends kept across spans: [`FaceCache`], for [`SpanEvaluator::eval_values_cached`](crate::span::SpanEvaluator::eval_values_cached).
//!
//! A single-axis trilinear term (a row across an axis-aligned plane, the lane kernel) blends
//! the four hashed corners of each cell face it crosses (`axis::face`): `Phi = lerp_c(lerp_a)`,
//! `a < c` the two axes other than the moving one. Written out in the ring of 64-bit integers,
//! that blend is `Phi = A + B f_a` with
//!
//! - `A = (w0 << 32) + f_c ((w2 - w0) << 16)`,
//! - `B = ((w1 - w0) << 16) + f_c ((w3 - w2) - (w1 - w0))`,
//!
//! (`w` the face's scaled corners, `w1 - w0` and `w3 - w2` wrapping in `i32` as the blend takes
//! them, everything else wrapping in `i64`), the very value of the blend modulo 2^64, and so
//! bit for bit the blend itself. `A` and `B` depend on the face's lattice cell, the term's
//! hash, amplitude and value precision and the fraction `f_c`, not on `f_a`: the next rows of
//! a plane whose rows step along axis `a` cross the same faces with another `f_a`, and take
//! `Phi` from the cache with one multiplication instead of hashing, scaling and blending four
//! corners again.
//!
//! # Guarantees
//!
//! - **Exact**: a cached blend is the blend (the identity above; the unit tests compare cached
//!   and uncached values and `Direct` evaluation over many rows, caches of every size, and
//!   caches shared between models).
//! - An entry is found by everything its `A` and `B` depend on (its full key is stored and
//!   compared), so a cache may be shared by any evaluators and models, and a collision only
//!   costs the recomputation.
//! - Capacity in the type: `N` entries of 32 bytes, `N` a power of two (checked at compile
//!   time), and the lanes of up to `L` terms (`lanes`: a span that goes on along the row of
//!   the span before reuses the face blends its cells already hold); no allocation, never
//!   panics.

#[cfg(not(texcore_lean))]
use super::axis::{face_bits, others};
#[cfg(not(texcore_lean))]
use super::lanes::VALUE_RUN;
#[cfg(not(texcore_lean))]
use super::lanes::{Carried, ValueLane};
#[cfg(not(texcore_lean))]
use crate::hash::HashKind;

/// One cached face: its key (`0` when empty) and the blend's `A` and `B`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct FaceEntry {
    key: [u32; 4],
    a: i64,
    b: i64,
}

impl FaceEntry {
    const EMPTY: FaceEntry = FaceEntry {
        key: [0; 4],
        a: 0,
        b: 0,
    };
}

/// Face blends of single-axis trilinear terms kept across spans (see the module
/// documentation): `N` entries of 32 bytes, `N` a power of two (checked at compile time), the
/// lanes of the last span of up to `L` terms (128 bytes a lane; see
/// [`SpanEvaluator::eval_values_cached`](crate::span::SpanEvaluator::eval_values_cached)) and the
/// lane kernel's accumulators (a run of 64 pixels, 512 bytes, so that no span clears its own).
///
/// Give one to [`SpanEvaluator::eval_values_cached`](crate::span::SpanEvaluator::eval_values_cached) for the rows of a plane: from the second
/// row on, every face the rows share is read back instead of hashed and blended again, and a
/// span that goes on along the row of the span before starts from the cells that span ended
/// in. The values are those of [`SpanEvaluator::eval_values`](crate::span::SpanEvaluator::eval_values), bit for bit, whatever the cache holds.
/// Size it to the faces one row crosses (for `k` octaves of `2^i c` cells across a row about
/// `c 2^k` entries; 128 covers four octaves of 8 cells), and `L` to the model's terms.
#[derive(Clone, Debug)]
pub struct FaceCache<const N: usize, const L: usize = 4> {
    entries: [FaceEntry; N],
    /// The lanes of the last span (fast shape only).
    #[cfg(not(texcore_lean))]
    lanes: [ValueLane; L],
    #[cfg(not(texcore_lean))]
    carried: Carried,
    /// The lane kernel's accumulators for a run of a span (written before they are read).
    #[cfg(not(texcore_lean))]
    acc: [i64; VALUE_RUN],
}

/// The parts of a face cache as the kernels take them (`entries` empty and no lanes: no
/// cache).
#[cfg_attr(texcore_lean, allow(dead_code))]
#[derive(Debug)]
pub(crate) struct Faces<'a> {
    pub(super) entries: &'a mut [FaceEntry],
    /// The carried lanes' slots and what they hold.
    #[cfg(not(texcore_lean))]
    pub(super) lanes: &'a mut [ValueLane],
    #[cfg(not(texcore_lean))]
    pub(super) carried: Option<&'a mut Carried>,
    /// Accumulators for the lane kernel's short spans (any contents; empty: none).
    #[cfg(not(texcore_lean))]
    pub(super) acc: &'a mut [i64],
}

impl Faces<'_> {
    /// No cache.
    pub(crate) fn none() -> Faces<'static> {
        Faces {
            entries: &mut [],
            #[cfg(not(texcore_lean))]
            lanes: &mut [],
            #[cfg(not(texcore_lean))]
            carried: None,
            #[cfg(not(texcore_lean))]
            acc: &mut [],
        }
    }
}

impl<const N: usize, const L: usize> FaceCache<N, L> {
    const POWER_OF_TWO: () = assert!(
        N.is_power_of_two(),
        "FaceCache capacity must be a power of two"
    );

    /// An empty cache.
    pub const fn new() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::POWER_OF_TWO;
        FaceCache {
            entries: [FaceEntry::EMPTY; N],
            #[cfg(not(texcore_lean))]
            lanes: [ValueLane::IDLE; L],
            #[cfg(not(texcore_lean))]
            carried: Carried::NONE,
            #[cfg(not(texcore_lean))]
            acc: [0; VALUE_RUN],
        }
    }

    /// Number of face entries.
    pub const fn capacity(&self) -> usize {
        N
    }

    /// Forgets every entry and the carried lanes (never needed for correctness: entries are
    /// found by their full key, and a lane is carried only into the cells it describes).
    pub fn clear(&mut self) {
        *self = Self::new();
    }

    /// The parts, as the kernels take them.
    #[cfg_attr(texcore_lean, allow(dead_code))]
    pub(crate) fn parts(&mut self) -> Faces<'_> {
        Faces {
            entries: &mut self.entries,
            #[cfg(not(texcore_lean))]
            lanes: &mut self.lanes,
            #[cfg(not(texcore_lean))]
            carried: Some(&mut self.carried),
            #[cfg(not(texcore_lean))]
            acc: &mut self.acc,
        }
    }
}

impl<const N: usize, const L: usize> Default for FaceCache<N, L> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(not(texcore_lean))]
/// `A` and `B` of the blend of the scaled face corners `w` (order `ca | cc << 1`) at fraction
/// `fc` along the face's higher other axis (see the module documentation).
#[inline(always)]
pub(super) fn blend_ab(w: &[i32; 4], fc: u32) -> (i64, i64) {
    let fc = i64::from(fc);
    let d01 = i64::from(w[1].wrapping_sub(w[0]));
    let d23 = i64::from(w[3].wrapping_sub(w[2]));
    let (w0, w2) = (i64::from(w[0]), i64::from(w[2]));
    let a = (w0 << 32).wrapping_add(fc.wrapping_mul(w2.wrapping_sub(w0) << 16));
    let b = (d01 << 16).wrapping_add(fc.wrapping_mul(d23.wrapping_sub(d01)));
    (a, b)
}

/// The part of a face's key and slot that is constant along a term's span (everything but the
/// face's coordinate along the moving axis `k`), made once per span.
///
/// Key layout: word 0 the moving coordinate, `k` and the used mark (bit 31: an empty entry is
/// all zero); word 1 the cell's two other coordinates; word 2 the amplitude; word 3 the
/// fraction `f_c`, the hash, the noise fraction bits and the value precision.
#[cfg(not(texcore_lean))]
#[derive(Clone, Copy, Debug)]
pub(super) struct FaceKey {
    /// Key word 0 without the moving coordinate, and words 1 to 3.
    w0: u32,
    words: [u32; 3],
    /// The fraction along the lower other axis (`Phi = A + B f_a`).
    fa: u32,
    /// The entries of the term's share of the cache: `base + (coordinate & mask)`.
    base: usize,
    mask: usize,
}

#[cfg(not(texcore_lean))]
impl FaceKey {
    /// The key of an idle lane (never used to read the cache).
    pub(super) const NONE: FaceKey = FaceKey {
        w0: 0,
        words: [0; 3],
        fa: 0,
        base: 0,
        mask: 0,
    };

    /// The constant part of the keys of a term moving along `k` through cells `cell` (the
    /// coordinate along `k` ignored) with fractions `frac`, hash, amplitude and precision;
    /// the term's share of the cache is the `share` entries from `base` ([`FaceKey::share`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn new(
        base: usize,
        share: usize,
        k: usize,
        hash: HashKind,
        cell: [u16; 3],
        frac: [u32; 3],
        amp: i32,
        fv: u32,
        vb: u32,
    ) -> FaceKey {
        let k = k.min(2);
        let (a, c) = others(k);
        let h: u32 = match hash {
            #[cfg(feature = "perm-hash")]
            HashKind::Permutation => 1,
            HashKind::Integer => 2,
        };
        FaceKey {
            w0: (k as u32) << 16 | 1 << 31,
            words: [
                u32::from(cell[a]) | u32::from(cell[c]) << 16,
                amp as u32,
                (frac[c] & 0xFFFF) | h << 16 | (fv & 63) << 18 | (vb & 31) << 24,
            ],
            fa: frac[a],
            base,
            mask: share.wrapping_sub(1),
        }
    }

    /// The share of a cache of `n` entries (a power of two) for a term stepping `d` lattice
    /// units a pixel among terms stepping `total` together: the faces a row crosses are in
    /// proportion to the step, so the share is the power of two `2^(log2 n + floor(log2 d) -
    /// floor(log2 total) - 1)`, at most `n d / total` (so that the shares of all the terms add
    /// up to at most `n`) and more than a quarter of it; at least 1. No division (a 64-bit
    /// division is a library call on the devices).
    #[inline(always)]
    pub(super) fn share(n: usize, d: u32, total: u64) -> usize {
        if n == 0 || d == 0 || total == 0 {
            return 1;
        }
        let bits = |x: u64| 63 - x.leading_zeros();
        let e = n.trailing_zeros() + bits(u64::from(d));
        let t = bits(total) + 1;
        if e > t {
            1 << (e - t).min(n.trailing_zeros())
        } else {
            1
        }
    }
}

/// The entry of face `b` of `cell` under `key` (a miss: out of line, one copy for every place
/// that reads the cache).
#[cfg(not(texcore_lean))]
#[allow(clippy::too_many_arguments)]
#[inline(never)]
pub(super) fn fill(
    key: [u32; 4],
    k: usize,
    hash: HashKind,
    cell: [u16; 3],
    b: usize,
    amp: i32,
    fv: u32,
    vb: u32,
) -> FaceEntry {
    let w = face_bits(k.min(2), hash, cell, b, amp, fv, vb);
    let (a, b) = blend_ab(&w, key[3] & 0xFFFF);
    FaceEntry { key, a, b }
}

/// The blend `Phi` of the face at coordinate `face` along the moving axis (`cell[k] + b` of a
/// term's cell, face `b`) under `key` (made for the term's other coordinates, fractions, hash,
/// amplitude and precision), through `cache`: the cached entry when its key matches, else the
/// entry `miss(key)` makes ([`fill`] of the same face: then stored), and `None` when the
/// cache is empty (the caller blends the face itself). The miss is a closure so that a hit
/// reads nothing of the term's cell.
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn cached_phi(
    cache: &mut [FaceEntry],
    key: &FaceKey,
    face: u16,
    miss: impl FnOnce([u32; 4]) -> FaceEntry,
) -> Option<i64> {
    let fk = u32::from(face);
    let w0 = key.w0 | fk;
    let i = key.base.wrapping_add(fk as usize & key.mask) & cache.len().wrapping_sub(1);
    let e = cache.get_mut(i)?;
    let [w1, w2, w3] = key.words;
    // Word by word (an array comparison is a library call on the devices).
    let differ = (e.key[0] ^ w0) | (e.key[1] ^ w1) | (e.key[2] ^ w2) | (e.key[3] ^ w3);
    if differ != 0 {
        *e = miss([w0, w1, w2, w3]);
    }
    Some(e.a.wrapping_add(e.b.wrapping_mul(i64::from(key.fa))))
}

#[cfg(all(test, not(texcore_lean)))]
mod tests {
    use super::super::axis::face;
    use super::*;

    #[test]
    fn the_expanded_blend_is_the_blend() {
        let mut rng = crate::test_rng::XorShift64::new(0x1234_5678_9abc_def0);
        let mut next = || rng.next_u64();
        for round in 0..20_000 {
            // Corners of the scaled range (below 2^26) and, every fourth round, any i32.
            let w: [i32; 4] = core::array::from_fn(|_| {
                let r = next() as i32;
                if round % 4 == 0 {
                    r
                } else {
                    r >> 6
                }
            });
            let f = [0, 1, 2].map(|_| (next() & 0xFFFF) as u32);
            for k in 0..3 {
                let (a, c) = others(k);
                let (ea, eb) = blend_ab(&w, f[c]);
                let phi = face(&w, k, f, [0; 3], false).phi();
                assert_eq!(ea.wrapping_add(eb.wrapping_mul(i64::from(f[a]))), phi);
            }
        }
    }

    #[test]
    fn shares_are_powers_of_two_in_proportion() {
        let d = [2048u32, 4096, 8192, 16384];
        let total: u64 = d.iter().map(|&x| u64::from(x)).sum();
        let shares = d.map(|x| FaceKey::share(128, x, total));
        assert_eq!(shares, [8, 16, 32, 64]);
        assert_eq!(FaceKey::share(256, 1, 1 << 20), 1);
        assert_eq!(FaceKey::share(256, 5, 0), 1);
        assert_eq!(FaceKey::share(0, 5, 5), 1);
        assert_eq!(FaceKey::share(64, 7, 7), 32);
        // A power of two, at most n d / total and more than a quarter of it (or 1).
        let mut rng = crate::test_rng::XorShift64::new(0x2545_f491_4f6c_dd1d);
        for _ in 0..10_000 {
            let x = rng.next_u64();
            let n = 1usize << (x % 12);
            let d = (x >> 8) as u32 >> ((x >> 40) % 31);
            let total = u64::from(d) + ((x >> 20) & 0xFF_FFFF);
            let s = FaceKey::share(n, d, total);
            assert!(s.is_power_of_two());
            let exact = (n as f64) * f64::from(d) / (total.max(1) as f64);
            assert!(
                s == 1 || (s as f64 <= exact && s as f64 * 4.0 > exact),
                "{n} {d} {total} {s}"
            );
            assert!(s <= n.max(1));
        }
    }

    #[test]
    fn capacity_and_clear() {
        let mut c = FaceCache::<8>::new();
        assert_eq!(c.capacity(), 8);
        let key = FaceKey::new(
            0,
            8,
            0,
            HashKind::Integer,
            [3, 4, 5],
            [100, 200, 300],
            1 << 16,
            16,
            16,
        );
        let v = cached_phi(&mut c.entries, &key, 4, |w| {
            fill(w, 0, HashKind::Integer, [3, 4, 5], 1, 1 << 16, 16, 16)
        });
        assert!(v.is_some());
        assert!(c.entries.iter().any(|e| e.key[0] >> 31 == 1));
        c.clear();
        assert!(c.entries.iter().all(|e| *e == FaceEntry::EMPTY));
        assert_eq!(
            cached_phi(&mut [], &key, 0, |_| unreachable!(
                "an empty cache fills nothing"
            )),
            None
        );
    }
}
