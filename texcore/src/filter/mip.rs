//! Colour-table MIP map (Hart et al. 1999 section 3.3.1; `docs/model.md` section 7).
//!
//! Level 0 is the colour table itself (`N` entries); level `l` (`1..=log2 N`) has `N >> l` entries,
//! entry `j` being the exact mean of level-0 entries `j 2^l .. (j + 1) 2^l - 1` rounded half up
//! (`(sum + 2^(l-1)) >> l` per channel, the model's definition). Computing every level from level 0,
//! not from pair averages of the level below, keeps the rounding error of every entry within 1/2:
//! chained pair averages `(a + b + 1) >> 1` drift upwards by up to `l/2`. The last level is
//! therefore exactly [`ColorTable::mean`].
//!
//! Look-up at width `w` (`FilterWidth`, in entries): `l = floor(log2 w)` clamped to
//! `[0, log2 N]` (`l = 0` for `w < 1`), `t = (w / 2^l - 1)` in 8 bits (`((w.raw >> l) - 2^16) >> 8`,
//! 0 for `w < 1` and at the last level); levels `l` and `l + 1` are looked up at `x / 2^l` (raw
//! `x >> l`) with the table's wrap, level 0 with the table's nearest / linear mode and every
//! higher level linearly (they are prefiltered: a nearest look-up in a coarse level would bring
//! back its blocks, which is what kept a two-colour table's levels pure), and blended with the model's 8-bit
//! lerp `(c_l (256 - t) + c_{l+1} t + 128) >> 8`. `w = 1` therefore gives the plain table look-up
//! and `w >= N` the last level.
//!
//! Guarantees: integer only, `const fn` construction, total for every `TableCoord` and
//! `FilterWidth` (level indices masked or clamped to each level's size). Memory: the table
//! (`4 N` bytes) plus `4 N` bytes for levels 1.. (`N - 1` entries used), `8 N` bytes in all.

use crate::color::Rgba8888;
use crate::format::{FilterWidth, TableCoord};
use crate::table::{lerp8, lookup_in, ColorTable, TableLookup, TableWrap};

/// A colour table with its MIP levels.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ColorMip<const N: usize> {
    table: ColorTable<N>,
    /// Levels `1..=log2 N` back to back: level `l` at offset `N - (N >> (l - 1))`; the last slot is
    /// unused.
    upper: [Rgba8888; N],
}

/// The look-up mode of level `l`: the table's own at level 0, linear above it.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn level_mode(l: u32, mode: TableLookup) -> TableLookup {
    if l == 0 {
        mode
    } else {
        TableLookup::Linear
    }
}

/// Offset of level `l >= 1` in `upper`.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn level_offset(n: usize, l: u32) -> usize {
    n - (n >> (l - 1))
}

impl<const N: usize> ColorMip<N> {
    /// Bytes of this structure (the table included).
    pub const BYTES: usize = core::mem::size_of::<Self>();
    /// Number of levels, `log2 N + 1`.
    pub const LEVELS: u32 = N.trailing_zeros() + 1;

    /// Builds the MIP levels of `table`.
    pub const fn new(table: ColorTable<N>) -> Self {
        let n_log2 = N.trailing_zeros();
        let mut upper = [Rgba8888::TRANSPARENT; N];
        let mut l = 1;
        while l <= n_log2 {
            let dst = level_offset(N, l);
            let len = N >> l;
            let mut j = 0;
            while j < len {
                // The exact mean of the 2^l level-0 entries, rounded half up (no bias
                // accumulates from level to level).
                let mut sum = [0u32; 4];
                let mut k = j << l;
                while k < (j + 1) << l {
                    let c = table.entries()[k];
                    sum[0] += c.r as u32;
                    sum[1] += c.g as u32;
                    sum[2] += c.b as u32;
                    sum[3] += c.a as u32;
                    k += 1;
                }
                let half = 1u32 << (l - 1);
                upper[dst + j] = Rgba8888::new(
                    ((sum[0] + half) >> l) as u8,
                    ((sum[1] + half) >> l) as u8,
                    ((sum[2] + half) >> l) as u8,
                    ((sum[3] + half) >> l) as u8,
                );
                j += 1;
            }
            l += 1;
        }
        ColorMip { table, upper }
    }

    /// The level-0 table.
    pub const fn table(&self) -> &ColorTable<N> {
        &self.table
    }

    /// The entries of level `l` (`N >> l` of them), or `None` for `l > log2 N`.
    pub fn level(&self, l: u32) -> Option<&[Rgba8888]> {
        if l == 0 {
            Some(self.table.entries())
        } else if l < Self::LEVELS {
            let off = level_offset(N, l);
            self.upper.get(off..off + (N >> l))
        } else {
            None
        }
    }

    /// Look-up in level `l` (clamped to the last level) at level-0 coordinate `x` (so at `x >> l`
    /// in the level), with the table's mode and wrap.
    pub fn level_lookup(
        &self,
        l: u32,
        x: TableCoord,
        wrap: TableWrap,
        mode: TableLookup,
    ) -> Rgba8888 {
        let n_log2 = N.trailing_zeros();
        let l = if l > n_log2 { n_log2 } else { l };
        let entries = match self.level(l) {
            Some(e) => e,
            None => self.table.entries(), // unreachable: l <= log2 N
        };
        lookup_in(entries, n_log2 - l, x.to_bits() >> l, wrap, mode)
    }

    /// The MIP-filtered colour at table coordinate `x` for width `w` (see the module docs).
    pub fn lookup(
        &self,
        x: TableCoord,
        w: FilterWidth,
        wrap: TableWrap,
        mode: TableLookup,
    ) -> Rgba8888 {
        let n_log2 = N.trailing_zeros();
        let w = w.to_bits();
        let l = if w < 0x1_0000 {
            0
        } else {
            let l = 15 - w.leading_zeros();
            if l > n_log2 {
                n_log2
            } else {
                l
            }
        };
        let t = if l >= n_log2 {
            0
        } else {
            let t = ((w >> l) as i64 - 0x1_0000) >> 8;
            t.clamp(0, 255) as u32
        };
        // Levels above 0 are prefiltered: they are always interpolated linearly (a nearest
        // look-up in a coarse level would bring the blocks of the level back).
        let c0 = self.level_lookup(l, x, wrap, level_mode(l, mode));
        if t == 0 {
            c0
        } else {
            lerp8(
                c0,
                self.level_lookup(l + 1, x, wrap, TableLookup::Linear),
                t,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use fixed::types::{I16F16, U16F16};
    use std::vec::Vec;

    fn grey(v: u8) -> Rgba8888 {
        Rgba8888::new(v, v, v, v)
    }

    use crate::test_rng::lcg_table;

    #[test]
    fn level_contents() {
        let t = ColorTable::from_entries([
            grey(0),
            grey(1),
            grey(10),
            grey(20),
            grey(255),
            grey(254),
            grey(7),
            grey(7),
        ])
        .unwrap();
        let m = ColorMip::new(t);
        assert_eq!(ColorMip::<8>::LEVELS, 4);
        assert_eq!(m.level(0).unwrap(), t.entries());
        assert_eq!(
            m.level(1).unwrap(),
            &[grey(1), grey(15), grey(255), grey(7)]
        );
        // (0+1+10+20)/4 = 7.75 -> 8; (255+254+7+7)/4 = 130.75 -> 131
        assert_eq!(m.level(2).unwrap(), &[grey(8), grey(131)]);
        // 554/8 = 69.25 -> 69 (chained pair averages would give 70)
        assert_eq!(m.level(3).unwrap(), &[grey(69)]);
        assert_eq!(m.level(4), None);
    }

    #[test]
    fn levels_match_independent_pyramid() {
        fn go<const N: usize>(seed: u64) {
            let t = lcg_table::<N>(seed);
            let m = ColorMip::new(t);
            let mut cur: Vec<[u32; 4]> = t
                .entries()
                .iter()
                .map(|c| c.to_array().map(u32::from))
                .collect();
            let mut l = 0;
            while !cur.is_empty() {
                let got: Vec<[u32; 4]> = m
                    .level(l)
                    .unwrap()
                    .iter()
                    .map(|c| c.to_array().map(u32::from))
                    .collect();
                assert_eq!(got, cur, "N={N} level {l}");
                // The next level from level 0 directly: the rounded exact mean of 2^(l+1) entries.
                let span = 1usize << (l + 1);
                cur = (0..N / span)
                    .map(|j| {
                        [0, 1, 2, 3].map(|ch| {
                            let s: u32 = t.entries()[j * span..(j + 1) * span]
                                .iter()
                                .map(|e| e.to_array()[ch] as u32)
                                .sum();
                            (2 * s + span as u32) / (2 * span as u32)
                        })
                    })
                    .collect();
                l += 1;
            }
            assert_eq!(l, ColorMip::<N>::LEVELS);
        }
        for seed in 0..8 {
            go::<2>(seed);
            go::<16>(seed);
            go::<256>(seed);
            go::<1024>(seed);
        }
    }

    #[test]
    fn top_level_is_the_rounded_mean() {
        // Chained pair averages would give 2 here (bias 9/8); the exact mean 7/8 rounds to 1.
        let t = ColorTable::from_entries([
            grey(2),
            grey(1),
            grey(2),
            grey(1),
            grey(1),
            grey(0),
            grey(0),
            grey(0),
        ])
        .unwrap();
        let m = ColorMip::new(t);
        assert_eq!(t.mean(), grey(1)); // 7/8
        assert_eq!(m.level(3).unwrap(), &[grey(1)]);
    }

    #[test]
    fn width_one_is_plain_lookup() {
        let t = lcg_table::<16>(9);
        let m = ColorMip::new(t);
        for w in [0u32, 1, 0xFFFF, 0x1_0000, 0x1_00FF] {
            for x in (0..=(16u32 << 16)).step_by(97) {
                for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                    let xc = U16F16::from_bits(x);
                    let wc = U16F16::from_bits(w);
                    assert_eq!(
                        m.lookup(xc, wc, wrap, TableLookup::Nearest),
                        t.nearest(xc, wrap)
                    );
                    assert_eq!(
                        m.lookup(xc, wc, wrap, TableLookup::Linear),
                        t.linear(xc, wrap)
                    );
                }
            }
        }
    }

    #[test]
    fn huge_width_is_top_level() {
        let t = lcg_table::<256>(4);
        let m = ColorMip::new(t);
        let top = m.level(8).unwrap()[0];
        for w in [256u32 << 16, (256 << 16) + 1, 1000 << 16, u32::MAX] {
            for x in [0u32, 12345, 255 << 16, 256 << 16, u32::MAX] {
                for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                    for mode in [TableLookup::Nearest, TableLookup::Linear] {
                        assert_eq!(
                            m.lookup(U16F16::from_bits(x), U16F16::from_bits(w), wrap, mode),
                            top
                        );
                    }
                }
            }
        }
        // Which is the table mean.
        assert_eq!(top, t.mean());
        // A solid table's MIP is the colour at every width.
        let s = ColorMip::new(ColorTable::<64>::solid(Rgba8888::new(9, 99, 199, 255)).unwrap());
        for w in (0..=u32::MAX).step_by(0x0F0F_0F0F) {
            let c = s.lookup(
                U16F16::from_num(3),
                U16F16::from_bits(w),
                TableWrap::Mod,
                TableLookup::Linear,
            );
            assert_eq!(c, Rgba8888::new(9, 99, 199, 255));
        }
    }

    #[test]
    fn blending_between_levels() {
        let t = lcg_table::<32>(1);
        let m = ColorMip::new(t);
        for wrap in [TableWrap::Mod, TableWrap::Clamp] {
            for mode in [TableLookup::Nearest, TableLookup::Linear] {
                for x in (0..=(32u32 << 16)).step_by(4099) {
                    let xc = U16F16::from_bits(x);
                    for w in (0x1_0000u32..(40 << 16)).step_by(5003) {
                        let l = 31 - w.leading_zeros() - 16;
                        let l = l.min(5);
                        // Level 0 in the table's mode, every higher level linearly.
                        let lm = |l: u32| if l == 0 { mode } else { TableLookup::Linear };
                        let want = if l == 5 {
                            m.level_lookup(5, xc, wrap, lm(5))
                        } else {
                            let t = ((w >> l) - 0x1_0000) >> 8;
                            let a = m.level_lookup(l, xc, wrap, lm(l)).to_array();
                            let b = m.level_lookup(l + 1, xc, wrap, lm(l + 1)).to_array();
                            Rgba8888::from_array([0, 1, 2, 3].map(|i| {
                                ((a[i] as u32 * (256 - t) + b[i] as u32 * t + 128) >> 8) as u8
                            }))
                        };
                        assert_eq!(m.lookup(xc, U16F16::from_bits(w), wrap, mode), want);
                    }
                }
            }
        }
        // Width 2 at the centre of level 1's entry 0 (x = 1): that entry exactly.
        let c = m.lookup(
            U16F16::ONE,
            U16F16::from_num(2),
            TableWrap::Mod,
            TableLookup::Nearest,
        );
        assert_eq!(c, m.level(1).unwrap()[0]);
        // Width 1.5: half way (t = 128) between level 0 (nearest: entry 1) and level 1 (linear,
        // at its entry 0's centre).
        let c = m.lookup(
            U16F16::ONE,
            U16F16::from_num(1.5),
            TableWrap::Mod,
            TableLookup::Nearest,
        );
        let (a, b) = (t.entries()[1].to_array(), m.level(1).unwrap()[0].to_array());
        assert_eq!(
            c.to_array(),
            [0, 1, 2, 3].map(|i| ((a[i] as u32 + b[i] as u32 + 1) >> 1) as u8)
        );
    }

    #[test]
    fn level_lookup_wraps_per_level() {
        let t = lcg_table::<8>(2);
        let m = ColorMip::new(t);
        let l2 = m.level(2).unwrap();
        let x = |e: f64| U16F16::from_num(e);
        // Level 2 has 2 entries; x = 7.9 is level entry 1; x = 8 wraps to 0 (mod) or holds 1 (clamp).
        assert_eq!(
            m.level_lookup(2, x(7.9), TableWrap::Mod, TableLookup::Nearest),
            l2[1]
        );
        assert_eq!(
            m.level_lookup(2, x(8.0), TableWrap::Mod, TableLookup::Nearest),
            l2[0]
        );
        assert_eq!(
            m.level_lookup(2, x(8.0), TableWrap::Clamp, TableLookup::Nearest),
            l2[1]
        );
        // Linear at a level-2 entry boundary (x = 4) is the mean of the two level entries.
        let c = m
            .level_lookup(2, x(4.0), TableWrap::Mod, TableLookup::Linear)
            .to_array();
        let (a, b) = (l2[0].to_array(), l2[1].to_array());
        assert_eq!(
            c,
            [0, 1, 2, 3].map(|i| ((a[i] as u32 + b[i] as u32 + 1) >> 1) as u8)
        );
        // Levels past the last clamp to it; extreme inputs are total.
        assert_eq!(
            m.level_lookup(99, x(1.0), TableWrap::Mod, TableLookup::Linear),
            m.level(3).unwrap()[0]
        );
        for f in [I16F16::MIN, I16F16::MAX, I16F16::ZERO] {
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                for w in [U16F16::ZERO, U16F16::MAX, U16F16::DELTA] {
                    for mode in [TableLookup::Nearest, TableLookup::Linear] {
                        let _ = m.lookup(t.coord(f, wrap), w, wrap, mode);
                        let _ = m.lookup(U16F16::MAX, w, wrap, mode);
                    }
                }
            }
        }
    }
}
