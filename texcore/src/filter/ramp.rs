//! Pre-filtered RGB565 colour ramp (feature `ramp`; `docs/model.md` section 7.3): an
//! *approximate* colour-table filter that turns `(f, w)` into a display pixel with one table
//! read, for shading straight to RGB565.
//!
//! Level `l` (`0..=L`, `L = log2 N`) holds the table box-filtered over `2^l` entries, already
//! reduced to RGB565. Levels 0 to 2 hold one sample per entry, centred on the entry's centre;
//! level `l >= 3` holds one sample every `S_l = 2^(l-2)` entries (four a box width), centred on
//! `(j + 1/2) S_l`. Each sample is the exact box average of the table (piecewise constant, as the
//! model integrates it; entries outside `[0, N)` wrapped by `mod` or clamped to the end entries
//! by `clamp`), rounded half up per channel to 8 bits and then to RGB565
//! ([`Rgba8888::to_rgb565`]). Level `L` is the table's mean ([`ColorTable::mean`]) at every
//! position, as the summed-area filter gives for widths of `N` and more.
//!
//! Look-up of `f` at width `w` (entries, raw `U16F16`): the level is `w` rounded to a power of two
//! in the log domain (`round(log2 w)`, ties at `w = 2^(k + 1/2)` upwards; 0 below `sqrt(2)/2`
//! entries, `L` from `2^(L - 1/2)` up: [`level_of_width`]), the entry is the table coordinate's
//! `floor(x)` (`x = f N`, wrapped or clamped as the table's wrap says), and the sample is the
//! level's sample that covers it.
//!
//! What it approximates: the summed-area filter ([`super::csat`]) of the same table at the same
//! `(f, w)`. The box's width is off by at most a factor `sqrt(2)` and its centre by at most half
//! an entry (levels 0 to 2) or `S_l / 2` (an eighth of the box, above); the colour is rounded to
//! RGB565. `texsim report accuracy` (knob `antialiasing`, row `ramp`) measures what it costs in
//! error and saves in instructions.
//!
//! Guarantees: integer only, `const fn` construction (a ramp can live in flash), total for every
//! `TableCoord` and level (indices wrapped or clamped). Memory: `4 N` RGB565 samples, `8 N` bytes
//! (levels `>= 3` packed back to back in the fourth row, `N - 4` samples used).

use crate::color::{Rgb565, Rgba8888};
use crate::format::{FilterWidth, TableCoord};
use crate::table::{ColorTable, TableWrap};

/// The RGB565 samples of every level of a colour table (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Ramp565<const N: usize> {
    /// Levels 0, 1 and 2 (one sample an entry), then levels `3..=L` back to back (level `l` at
    /// offset `N - (N >> (l - 3))`, `N >> (l - 2)` samples).
    rows: [[Rgb565; N]; 4],
    /// For each half bit length `h` of the squared L2 width's root ([`level_of_sq`], `0..=17`;
    /// the table is 32 long so that `h & 31` needs no bounds check), the place of level
    /// `min(L, max(0, h + L - 16))`: `(row N + offset) << 5 | shift`.
    by_half_bits: [u32; 32],
    /// The wrap the samples were filtered with (the look-up wraps or clamps entries the same way).
    wrap: TableWrap,
}

/// `ceil(sqrt(2^(b-1)))^2` for every even bit length `b` in `2..=36` (index `b`), 0 elsewhere
/// (64 long, so that a bit length indexes it without a bounds check): the smallest square at or
/// above `2^(b-1)`, where the floor square root of a value crosses a level boundary, so a value
/// of bit length `b` below it has a floor root whose square has bit length `b - 1`
/// ([`level_of_sq`]).
const BELOW_BY_BITS: [u64; 64] = {
    let mut t = [0u64; 64];
    let mut b = 2;
    while b <= 36 {
        // 2^(b-1) with b - 1 odd is not a square: its root's floor is below it.
        let r = super::isqrt(1u64 << (b - 1));
        t[b] = (r + 1) * (r + 1);
        b += 2;
    }
    t
};

/// The level of a filter width: `round(log2 w)` in entries (`w` raw `U16F16`), ties at
/// `2^(k + 1/2)` upwards, below one entry 0, at most `max_level`. That is
/// `min(max_level, max(0, floor(bitlen(w^2) / 2) - 16))`, with `bitlen` the number of
/// significant bits.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn level_of_width(w: FilterWidth, max_level: u32) -> u32 {
    let w = w.to_bits() as u64;
    let half_bits = (64 - (w * w).leading_zeros()) >> 1;
    let l = half_bits.saturating_sub(16);
    if l > max_level {
        max_level
    } else {
        l
    }
}

/// `floor(bitlen(floor(sqrt(s))^2) / 2)`, the half bit length of the square of `s`'s floor
/// root, from `s` without the root: `floor(bitlen(s) / 2)`, less one when `bitlen(s)` is even and
/// `s` lies below the first square at or above `2^(bitlen(s) - 1)`. For `s < 2^36`.
///
/// Why: with `B = bitlen(s)` and `g = floor(sqrt(s))`, `g^2 <= s < 2^B`. For odd `B`, `2^(B-1)`
/// is a square at or below `s`, so `g^2 >= 2^(B-1)` and `bitlen(g^2) = B`. For even `B`
/// (`k = B - 1` odd), `g^2 >= 2^k` exactly when `s` reaches the next square `ceil(sqrt(2^k))^2`;
/// below it `g^2 >= (sqrt(2^k) - 1)^2 >= 2^(k-1)`, so `bitlen(g^2) = k`.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn level_of_sq(s: u64) -> u32 {
    let b = 64 - s.leading_zeros();
    // b <= 36 for every s this takes; b = 64 reads a 0 (never below).
    let below = s < BELOW_BY_BITS[(b & 63) as usize];
    (b >> 1) - below as u32
}

/// The level of the L2 filter width of the saturated gradient magnitudes `a`, `b` and the spread
/// `e` (raw `U16F16`, as [`super::WidthStream`] takes them) in a table of `2^n_log2` entries
/// (`n_log2 <= 15`): [`level_of_width`] of that width, without its square root.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn level_of_l2(a: u32, b: u32, e: u32, n_log2: u32) -> u32 {
    if a >= 1 << 16 || b >= 1 << 16 || e >= 1 << 16 {
        // The width is capped at N: level log2 N.
        return n_log2;
    }
    let s = (a * a) as u64 + (b * b) as u64 + (e * e) as u64;
    // g = floor(sqrt(s)) and w = g << n_log2 below the cap (w = N << 16 from g >= 2^16, level
    // n_log2 either way): bitlen(w^2) = bitlen(g^2) + 2 n_log2 for g > 0; s = 0 gives level 0
    // (n_log2 <= 15), as w = 0 does.
    let l = (level_of_sq(s) + n_log2).saturating_sub(16);
    if l > n_log2 {
        n_log2
    } else {
        l
    }
}

/// Offset and shift of level `l` in `rows`: `(row, offset, shift)`.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn place(n: usize, l: u32) -> (usize, usize, u32) {
    if l < 3 {
        (l as usize, 0, 0)
    } else {
        (3, n - (n >> (l - 3)), l - 2)
    }
}

/// Entry `k` of `table` (any integer), wrapped or clamped.
const fn entry_at<const N: usize>(table: &ColorTable<N>, k: i64, wrap: TableWrap) -> Rgba8888 {
    let i = match wrap {
        TableWrap::Mod => (k & (N as i64 - 1)) as usize,
        TableWrap::Clamp => {
            if k < 0 {
                0
            } else if k >= N as i64 {
                N - 1
            } else {
                k as usize
            }
        }
    };
    table.entries()[i]
}

/// The exact box average of `table` over `[c2 - w, c2 + w]`, in units of half an entry (a box
/// `w` entries wide centred on entry coordinate `c2 / 2`; `w >= 1`), rounded half up per
/// channel. Each entry weighs the half entries of its `[k, k + 1)` inside the box.
const fn box_average<const N: usize>(
    table: &ColorTable<N>,
    c2: i64,
    w: i64,
    wrap: TableWrap,
) -> Rgba8888 {
    let (lo, hi) = (c2 - w, c2 + w);
    let mut sum = [0u64; 4];
    // Entries k with [2k, 2k + 2] meeting [lo, hi].
    let mut k = lo.div_euclid(2);
    while 2 * k < hi {
        let a = if 2 * k > lo { 2 * k } else { lo };
        let b = if 2 * k + 2 < hi { 2 * k + 2 } else { hi };
        if b > a {
            let weight = (b - a) as u64;
            let c = entry_at(table, k, wrap);
            sum[0] += weight * c.r as u64;
            sum[1] += weight * c.g as u64;
            sum[2] += weight * c.b as u64;
            sum[3] += weight * c.a as u64;
        }
        k += 1;
    }
    // The weights add up to the box's length in half entries, 2w.
    let total = (2 * w) as u64;
    let half = total / 2;
    Rgba8888::new(
        ((sum[0] + half) / total) as u8,
        ((sum[1] + half) / total) as u8,
        ((sum[2] + half) / total) as u8,
        ((sum[3] + half) / total) as u8,
    )
}

impl<const N: usize> Ramp565<N> {
    /// Bytes of this structure.
    pub const BYTES: usize = core::mem::size_of::<Self>();
    /// The last level, `log2 N`.
    pub const MAX_LEVEL: u32 = N.trailing_zeros();

    /// The ramp of `table` under `wrap` (`N` a power of two, as every colour table).
    pub const fn new(table: &ColorTable<N>, wrap: TableWrap) -> Self {
        let mut rows = [[Rgb565::BLACK; N]; 4];
        let top = Self::MAX_LEVEL;
        let mean = table.mean().to_rgb565();
        let mut l = 0;
        while l <= top {
            let (row, offset, shift) = place(N, l);
            let count = N >> shift;
            // Box width 2^l entries = 2^(l+1) half entries; sample j centred on (j + 1/2) S.
            let stride = 1i64 << shift;
            let mut j = 0;
            while j < count {
                let c = if l == top {
                    mean
                } else {
                    box_average(table, (2 * j as i64 + 1) * stride, 1i64 << l, wrap).to_rgb565()
                };
                rows[row][offset + j] = c;
                j += 1;
            }
            l += 1;
        }
        let mut by_half_bits = [0u32; 32];
        let mut h = 0;
        while h < 32 {
            let l = (h + top).saturating_sub(16);
            let l = if l > top { top } else { l };
            let (row, offset, shift) = place(N, l);
            by_half_bits[h as usize] = (((row * N + offset) as u32) << 5) | shift;
            h += 1;
        }
        Ramp565 {
            rows,
            by_half_bits,
            wrap,
        }
    }

    /// The wrap the ramp was built for.
    pub const fn wrap(&self) -> TableWrap {
        self.wrap
    }

    /// The sample at flat index `i` (row `i / N`, column `i mod N`), `i` taken modulo `4 N` (every
    /// index the ramp makes is below it, so the mask only spares the bounds check).
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn flat(&self, i: usize) -> Rgb565 {
        let all = self.rows.as_flattened();
        match all.get(i & (all.len() - 1)) {
            Some(&c) => c,
            None => Rgb565::BLACK,
        }
    }

    /// The colours of samples `f` with filter-width gradients `gx`, `gy` (48 fraction bits) and
    /// the spread `extra48` in quadrature, by the L2 norm: for each, [`Ramp565::lookup`] of its
    /// table coordinate at [`super::WidthStream::width_with`]'s width, bit for bit, with the
    /// level from the squared norm ([`level_of_l2`], one table read) instead of the width's root.
    /// `N <= 2^15`. Stops at the shortest slice.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn shade_l2<F: FnMut(Rgb565)>(
        &self,
        f: &[crate::format::TexValue],
        gx: &[i64],
        gy: &[i64],
        extra48: i64,
        mut emit: F,
    ) {
        // Each magnitude saturated as the width saturates it, then limited to 2^16: any of them
        // at 2^16 makes the square at least 2^32 (half bit length >= 16, level L), as the width's
        // cap does; below, the squares are the width's own. The sum is below 3 * 2^32.
        let sat = |g: i64| {
            let a = g.unsigned_abs() >> 32;
            if a > 1 << 16 {
                1u32 << 16
            } else {
                a as u32
            }
        };
        let e = sat(extra48);
        let e2 = u64::from(e) * u64::from(e);
        let n_log2 = Self::MAX_LEVEL;
        let place = |a: u32, b: u32| {
            let s = u64::from(a) * u64::from(a) + u64::from(b) * u64::from(b) + e2;
            // h <= 17 (s < 3 * 2^32).
            self.by_half_bits[(level_of_sq(s) & 31) as usize]
        };
        let samples = f.iter().zip(gx).zip(gy);
        match self.wrap {
            TableWrap::Mod => {
                for ((&f, &gx), &gy) in samples {
                    let p = place(sat(gx), sat(gy));
                    // Entry floor(frac(f) N).
                    let k = ((f.to_bits() as u32) & 0xFFFF) >> (16 - n_log2);
                    emit(self.flat(((p >> 5) + (k >> (p & 31))) as usize));
                }
            }
            TableWrap::Clamp => {
                for ((&f, &gx), &gy) in samples {
                    let p = place(sat(gx), sat(gy));
                    // Entry min(floor(clamp(f, 0, 1) N), N - 1).
                    let raw = f.to_bits().clamp(0, 0xFFFF) as u32;
                    let k = raw >> (16 - n_log2);
                    emit(self.flat(((p >> 5) + (k >> (p & 31))) as usize));
                }
            }
        }
    }

    /// The sample of level `level` (clamped to [`Ramp565::MAX_LEVEL`]) covering entry
    /// `floor(x)` (wrapped or clamped by the ramp's wrap).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn at(&self, x: TableCoord, level: u32) -> Rgb565 {
        let k = (x.to_bits() >> 16) as usize;
        let k = match self.wrap {
            TableWrap::Mod => k & (N - 1),
            TableWrap::Clamp => k.min(N - 1),
        };
        let level = level.min(Self::MAX_LEVEL);
        let (row, offset, shift) = place(N, level);
        match self
            .rows
            .get(row)
            .and_then(|r| r.get(offset + (k >> shift)))
        {
            Some(&c) => c,
            None => Rgb565::BLACK,
        }
    }

    /// The sample for table coordinate `x` at filter width `w` ([`level_of_width`]).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn lookup(&self, x: TableCoord, w: FilterWidth) -> Rgb565 {
        self.at(x, level_of_width(w, Self::MAX_LEVEL))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::filter::{filter_width_spread, isqrt, GradientNorm};
    use fixed::types::U16F16;

    fn lcg_table<const N: usize>(seed: u64) -> ColorTable<N> {
        let mut s = seed;
        let mut e = [Rgba8888::TRANSPARENT; N];
        for c in e.iter_mut() {
            let mut b = [0u8; 4];
            for v in b.iter_mut() {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                *v = (s >> 56) as u8;
            }
            *c = Rgba8888::new(b[0], b[1], b[2], b[3]);
        }
        ColorTable::from_entries(e).unwrap()
    }

    /// The box average by the definition, in `f64` over a fine grid of the half-entry box.
    fn box_f64<const N: usize>(t: &ColorTable<N>, lo2: i64, hi2: i64, wrap: TableWrap) -> [f64; 4] {
        let mut sum = [0.0; 4];
        for h in lo2..hi2 {
            let c = entry_at(t, h.div_euclid(2), wrap).to_array();
            for (s, v) in sum.iter_mut().zip(c) {
                *s += f64::from(v);
            }
        }
        sum.map(|s| s / (hi2 - lo2) as f64)
    }

    #[test]
    fn levels_hold_the_box_averages() {
        let t = lcg_table::<64>(7);
        for wrap in [TableWrap::Mod, TableWrap::Clamp] {
            let r = Ramp565::new(&t, wrap);
            for l in 0..Ramp565::<64>::MAX_LEVEL {
                let (_, _, shift) = place(64, l);
                let stride = 1i64 << shift;
                for j in 0..(64 >> shift) as i64 {
                    let c2 = (2 * j + 1) * stride;
                    let want = box_f64(&t, c2 - (1 << l), c2 + (1 << l), wrap);
                    let want = Rgba8888::new(
                        (want[0] + 0.5).floor() as u8,
                        (want[1] + 0.5).floor() as u8,
                        (want[2] + 0.5).floor() as u8,
                        (want[3] + 0.5).floor() as u8,
                    );
                    let x = TableCoord::from_bits(((j * stride) as u32) << 16);
                    assert_eq!(r.at(x, l), want.to_rgb565(), "level {l} sample {j}");
                }
            }
            // The last level (and past it) is the mean everywhere.
            for k in 0..64u32 {
                let x = TableCoord::from_bits(k << 16);
                assert_eq!(r.at(x, 6), t.mean().to_rgb565());
                assert_eq!(r.at(x, 40), t.mean().to_rgb565());
            }
        }
    }

    #[test]
    fn level_zero_is_the_nearest_entry_and_coordinates_wrap_or_clamp() {
        let t = lcg_table::<256>(3);
        let m = Ramp565::new(&t, TableWrap::Mod);
        let c = Ramp565::new(&t, TableWrap::Clamp);
        for k in 0..256u32 {
            let want = t.entries()[k as usize].to_rgb565();
            for frac in [0, 1, 0x8000, 0xFFFF] {
                let x = TableCoord::from_bits((k << 16) | frac);
                assert_eq!(m.at(x, 0), want);
                assert_eq!(c.at(x, 0), want);
            }
        }
        // x = N (a clamp table's end) reads the last entry; any coordinate reads a sample.
        let end = TableCoord::from_bits(256 << 16);
        assert_eq!(c.at(end, 0), t.entries()[255].to_rgb565());
        assert_eq!(m.at(end, 0), t.entries()[0].to_rgb565());
        for l in 0..12 {
            for bits in [0, 1, u32::MAX, 0x8000_0000, 0xFFFF] {
                let x = TableCoord::from_bits(bits);
                let _ = m.at(x, l);
                let _ = c.at(x, l);
            }
        }
    }

    #[test]
    fn level_of_width_rounds_in_the_log_domain() {
        let w = |bits: u32| FilterWidth::from_bits(bits);
        assert_eq!(level_of_width(w(0), 8), 0);
        assert_eq!(level_of_width(w(1 << 16), 8), 0);
        assert_eq!(level_of_width(w(92681), 8), 0); // sqrt(2) entries, just below
        assert_eq!(level_of_width(w(92682), 8), 1); // just above
        assert_eq!(level_of_width(w(2 << 16), 8), 1);
        assert_eq!(level_of_width(w(3 << 16), 8), 2); // 3 > 2 sqrt(2)
        assert_eq!(level_of_width(w(256 << 16), 8), 8);
        assert_eq!(level_of_width(w(u32::MAX), 8), 8);
        for bits in (0..u32::MAX).step_by(9973).chain([u32::MAX]) {
            let l = level_of_width(w(bits), 15);
            let v = f64::from(bits) / 65536.0;
            let want = if v < 0.5f64.sqrt() {
                0.0
            } else {
                v.log2().round().max(0.0)
            };
            // Away from the ties the f64 rounding agrees.
            let frac = (v.log2() + 0.5).fract().abs();
            if v > 0.0 && frac > 1e-6 && frac < 1.0 - 1e-6 {
                assert_eq!(l as f64, want.min(15.0), "w = {bits}");
            }
        }
    }

    #[test]
    fn the_squares_level_is_the_roots_level() {
        let half_bits_of_root = |s: u64| {
            let g = isqrt(s);
            (64 - (g * g).leading_zeros()) >> 1
        };
        // Every value near every power of two and every square past it, and a stride through the
        // rest of the range the widths use.
        let mut values = std::vec::Vec::new();
        for k in 0..36u32 {
            let p = 1u64 << k;
            let r = isqrt(p);
            for base in [p, r * r, (r + 1) * (r + 1)] {
                for d in 0..4u64 {
                    values.push(base + d);
                    values.push(base.saturating_sub(d));
                }
            }
        }
        values.extend((0..(3u64 << 32)).step_by(1_000_003));
        for s in values {
            assert_eq!(level_of_sq(s), half_bits_of_root(s), "s = {s}");
        }
        for s in 0..100_000u64 {
            assert_eq!(level_of_sq(s), half_bits_of_root(s), "s = {s}");
        }
    }

    #[test]
    fn the_l2_level_is_the_level_of_the_l2_width() {
        let mut seed = 11u64;
        let mut next = |bound: u64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 20) % bound
        };
        for n_log2 in [2u32, 6, 8, 10] {
            for i in 0..20_000 {
                // Magnitudes of every scale, the cap included.
                let scale = 1u64 << next(22);
                let mag = |v: u64| (v % (scale + 1)) as i64;
                let (gx, gy) = (mag(next(1 << 40)) << 32, mag(next(1 << 40)) << 32);
                let e = if i % 3 == 0 {
                    mag(next(1 << 40)) << 32
                } else {
                    0
                };
                let w = filter_width_spread(gx, -gy, e, GradientNorm::L2, n_log2);
                let a = (gx >> 32) as u32;
                let b = (gy >> 32) as u32;
                let ev = (e >> 32) as u32;
                assert_eq!(
                    level_of_l2(a, b, ev, n_log2),
                    level_of_width(w, n_log2),
                    "gx {gx} gy {gy} e {e} n {n_log2}"
                );
            }
        }
        // The saturation and zero.
        assert_eq!(level_of_l2(0, 0, 0, 8), 0);
        assert_eq!(level_of_l2(u32::MAX, 0, 0, 8), 8);
        assert_eq!(level_of_l2(0xFFFF, 0xFFFF, 0xFFFF, 8), 8);
        let _ = U16F16::ZERO;
    }

    /// The chunk path (level from the squared norm, entries from the raw value) is the look-up
    /// at the stream's width, over gradients of every scale (the cap, `i64::MIN`), spreads and
    /// values of every range, both wraps and several table sizes.
    #[test]
    fn shade_l2_is_the_lookup_at_the_streams_width() {
        fn check<const N: usize>(seed: u64) {
            let t = lcg_table::<N>(seed);
            let mut s = seed;
            let mut next = move || {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                s
            };
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                let r = Ramp565::new(&t, wrap);
                for round in 0..200 {
                    let g = |k: u64, v: u64, sh: u64| -> i64 {
                        match k % 9 {
                            0 => i64::MIN,
                            1 => 0,
                            2 => (1i64 << 48) - 1,
                            3 => 1i64 << 48,
                            _ => (v as i64) >> (sh % 60),
                        }
                    };
                    let f: std::vec::Vec<_> = (0..32)
                        .map(|_| {
                            crate::format::TexValue::from_bits(
                                (next() >> 32) as i32 >> (next() % 20),
                            )
                        })
                        .collect();
                    let gx: std::vec::Vec<i64> =
                        (0..32).map(|_| g(next(), next(), next())).collect();
                    let gy: std::vec::Vec<i64> =
                        (0..32).map(|_| g(next(), next(), next())).collect();
                    let extra = if round % 2 == 0 {
                        0
                    } else {
                        g(next(), next(), next()).saturating_abs()
                    };
                    let mut got = std::vec::Vec::new();
                    r.shade_l2(&f, &gx, &gy, extra, |c| got.push(c));
                    let mut widths =
                        crate::filter::WidthStream::new(GradientNorm::L2, N.trailing_zeros());
                    let want: std::vec::Vec<_> = f
                        .iter()
                        .zip(&gx)
                        .zip(&gy)
                        .map(|((&f, &gx), &gy)| {
                            r.lookup(t.coord(f, wrap), widths.width_with(gx, gy, extra))
                        })
                        .collect();
                    assert_eq!(got, want, "N {N} {wrap:?} round {round}");
                }
            }
        }
        check::<16>(2);
        check::<64>(3);
        check::<256>(4);
        check::<1024>(5);
    }

    #[test]
    fn rgb565_round_trips_through_rgba8888() {
        for v in 0..=u16::MAX {
            let c = Rgb565(v);
            assert_eq!(c.to_rgba8888().to_rgb565(), c);
        }
    }

    #[test]
    fn construction_is_const() {
        const T: ColorTable<16> = match ColorTable::from_entries([Rgba8888::rgb(10, 20, 30); 16]) {
            Ok(t) => t,
            Err(_) => panic!(),
        };
        const R: Ramp565<16> = Ramp565::new(&T, TableWrap::Mod);
        let x = TableCoord::from_bits(5 << 16);
        for l in 0..6 {
            assert_eq!(R.at(x, l), Rgba8888::rgb(10, 20, 30).to_rgb565());
        }
    }
}
