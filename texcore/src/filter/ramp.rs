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
//! What it approximates: the summed-area filter (`filter::csat`, feature `csat`) of the same
//! table at the same `(f, w)`. The box's width is off by at most a factor `sqrt(2)` and its centre
//! by at most half an entry (levels 0 to 2) or `S_l / 2` (an eighth of the box, above); the colour
//! is rounded to RGB565. `texsim report accuracy` (knob `antialiasing`, row `ramp`) measures
//! what it costs in error and saves in instructions.
//!
//! Guarantees: integer only, `const fn` construction (a ramp can live in flash), total for every
//! `TableCoord` and level (indices wrapped or clamped). Memory: `4 N` RGB565 samples, `8 N` bytes
//! (levels `>= 3` packed back to back in the fourth row, `N - 4` samples used), and a level
//! table of 272 bytes (a threshold and a place for each bit length of a squared width).

use crate::color::{Rgb565, Rgba8888};
use crate::format::{FilterWidth, TableCoord};
use crate::table::{ColorTable, TableWrap};

/// The RGB565 samples of every level of a colour table (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Ramp565<const N: usize> {
    /// Levels 0, 1 and 2 (one sample an entry), then levels `3..=L` back to back (level `l` at
    /// offset `N - (N >> (l - 3))`, `N >> (l - 2)` samples).
    rows: [[Rgb565; N]; 4],
    /// The level look-up of a 32-bit squared L2 norm `s` by its leading zeros `c` (`0..=32`):
    /// entry `c` holds the threshold below which `s` of bit length `b = 32 - c` has a floor
    /// root of one bit length less ([`level_of_sq32`]; 0 where none: odd `b`, `b = 0`) and the
    /// place of the level of half bit length `h = b >> 1`; the level of `s` below the threshold
    /// is entry `c + 1`'s (half bit length `(b - 1) >> 1 = h - 1` for even `b`). A place is
    /// `(row N + offset) << 5 | shift` of level `min(L, max(0, h + L - 16))`. Entry 33 only
    /// completes the pairs (entry 32's threshold is 0).
    by_clz: [[u32; 2]; 34],
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

/// A gradient of 48 fraction bits as a magnitude of 16 fraction bits, saturated as the filter
/// width saturates it and then limited to `2^16 - 1`: the width is capped at `N` from a
/// magnitude of `2^16` (level `L`), and a magnitude of `2^16 - 1` alone already has a square of
/// half bit length 16 (level `L`, [`level_of_sq32`]), so the limit changes no level; below it
/// the squares are the width's own and fit in 32 bits.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn magnitude48(g: i64) -> u32 {
    let a = g.unsigned_abs() >> 32;
    if a > 0xFFFF {
        0xFFFF
    } else {
        a as u32
    }
}

/// The squared L2 norm of magnitudes `a`, `b` (at most `2^16 - 1`) and the square `e2` of the
/// spread's, saturated at `u32::MAX`: below `2^32` it is the exact sum, and at or above it both
/// the sum and `u32::MAX` have half bit length 16 or more (level `L`).
#[cfg_attr(not(texcore_lean), inline(always))]
const fn norm2(a: u32, b: u32, e2: u32) -> u32 {
    (a * a).saturating_add(b * b).saturating_add(e2)
}

/// The squared L2 norm of the differences `dx`, `dy` (16 fraction bits) and the spread's square
/// `e2` (`e2 <= (2^16 - 1)^2`), saturated at `u32::MAX`: the exact sum (below 2^63 in `u64`,
/// two products and two additions, no branch) where it is below 2^32. It has the level of
/// [`norm2`] of the differences' magnitudes capped at `2^16 - 1` (as [`magnitude48`] caps a
/// gradient's, the width the other ramp paths take): where no magnitude is capped and
/// the sum is below 2^32 the two are the same number; otherwise both are at least
/// `(2^16 - 1)^2`, above the last threshold (`46341^2`), so both have half bit length 16
/// ([`level_of_sq32`], level `L`).
#[cfg_attr(not(texcore_lean), inline(always))]
fn norm_sq(dx: i32, dy: i32, e2: u32) -> u32 {
    let sq = |d: i32| i64::from(d).wrapping_mul(i64::from(d)) as u64;
    let s = sq(dx) + sq(dy) + u64::from(e2);
    u32::try_from(s).unwrap_or(u32::MAX)
}

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

/// [`level_of_sq`] of a 32-bit `s` (the same level: the thresholds up to bit length 32 fit in
/// 32 bits).
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn level_of_sq32(s: u32) -> u32 {
    let b = 32 - s.leading_zeros();
    // Below the threshold only for an even `b >= 2` (odd and zero bit lengths read 0), where
    // `(b - 1) >> 1` is `(b >> 1) - 1`: one subtraction with the comparison's borrow.
    let below = s < BELOW_BY_BITS[(b & 63) as usize] as u32;
    (b - below as u32) >> 1
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
        let mut by_clz = [[0u32; 2]; 34];
        let mut c = 0;
        while c < 34 {
            // Bit length b = 32 - c (entry 33: b = 0 as well, never read as a threshold).
            let b = 32u32.saturating_sub(c);
            let threshold = if c <= 32 {
                BELOW_BY_BITS[b as usize] as u32
            } else {
                0
            };
            let l = ((b >> 1) + top).saturating_sub(16);
            let l = if l > top { top } else { l };
            let (row, offset, shift) = place(N, l);
            by_clz[c as usize] = [threshold, (((row * N + offset) as u32) << 5) | shift];
            c += 1;
        }
        Ramp565 { rows, by_clz, wrap }
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
        emit: F,
    ) {
        let e = magnitude48(extra48);
        match self.wrap {
            TableWrap::Mod => self.shade_gradients::<false, F>(f, gx, gy, e * e, emit),
            TableWrap::Clamp => self.shade_gradients::<true, F>(f, gx, gy, e * e, emit),
        }
    }

    /// [`Ramp565::shade_l2`] with the wrap `CLAMP` and the spread's square `e2`.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn shade_gradients<const CLAMP: bool, F: FnMut(Rgb565)>(
        &self,
        f: &[crate::format::TexValue],
        gx: &[i64],
        gy: &[i64],
        e2: u32,
        mut emit: F,
    ) {
        for ((&f, &gx), &gy) in f.iter().zip(gx).zip(gy) {
            emit(self.sample::<CLAMP>(f, magnitude48(gx), magnitude48(gy), e2));
        }
    }

    /// The colours of the values `f` of a span under `above` (the same pixels one row up) with
    /// the filter-width gradients from their differences (16 fraction bits, wrapping): pixel
    /// `i`'s `gx` is `f[i + 1] - f[i]` (the last pixel's, its left neighbour's; 0 for a span of
    /// one), its `gy` is `f[i] - above[i]`, and the spread `extra48` is added in quadrature. Each
    /// colour is that of [`Ramp565::shade_l2`] given those differences as gradients (shifted to
    /// 48 fraction bits), bit for bit. `N <= 2^15`. Stops at the shorter slice.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn shade_differences_l2<F: FnMut(Rgb565)>(
        &self,
        f: &[crate::format::TexValue],
        above: &[crate::format::TexValue],
        extra48: i64,
        emit: F,
    ) {
        let e = magnitude48(extra48);
        match self.wrap {
            TableWrap::Mod => self.shade_differences::<false, F>(f, above, e * e, emit),
            TableWrap::Clamp => self.shade_differences::<true, F>(f, above, e * e, emit),
        }
    }

    /// [`Ramp565::shade_differences_l2`] written into `dst` (`dst[i] = put(colour of pixel
    /// i)`): the same colours, bit for bit, for the first `min(f.len(), above.len(), dst.len())`
    /// pixels (the last of them taking its left neighbour's `gx` when `f` ends there). One loop
    /// over the values and the destination together, compiled apart from its caller (its own
    /// register file: the table, the spread and the three slices stay in registers). `N <=
    /// 2^15`.
    #[cfg_attr(not(texcore_lean), inline(never))]
    pub fn shade_differences_l2_into<D, P: Fn(Rgb565) -> D>(
        &self,
        f: &[crate::format::TexValue],
        above: &[crate::format::TexValue],
        extra48: i64,
        dst: &mut [D],
        put: P,
    ) {
        let n = f.len().min(above.len()).min(dst.len());
        let (Some(above), Some(dst)) = (above.get(..n), dst.get_mut(..n)) else {
            return;
        };
        let e = magnitude48(extra48);
        match (self.wrap, e == 0) {
            (TableWrap::Mod, true) => self.differences_into::<false, D, P>(f, above, 0, dst, put),
            (TableWrap::Mod, false) => {
                self.differences_into::<false, D, P>(f, above, e * e, dst, put)
            }
            (TableWrap::Clamp, true) => self.differences_into::<true, D, P>(f, above, 0, dst, put),
            (TableWrap::Clamp, false) => {
                self.differences_into::<true, D, P>(f, above, e * e, dst, put)
            }
        }
    }

    /// The loop of [`Ramp565::shade_differences_l2_into`]: `above` and `dst` of one length
    /// `n <= f.len()`.
    #[inline(always)]
    fn differences_into<const CLAMP: bool, D, P: Fn(Rgb565) -> D>(
        &self,
        f: &[crate::format::TexValue],
        above: &[crate::format::TexValue],
        e2: u32,
        dst: &mut [D],
        put: P,
    ) {
        let d = |a: crate::format::TexValue, b: crate::format::TexValue| {
            a.to_bits().wrapping_sub(b.to_bits())
        };
        // Pixels with a right neighbour in `f`, then (when `f` ends with the destination) the
        // last with its left neighbour's difference.
        let inner = dst.len().min(f.len().saturating_sub(1));
        let (Some(up), Some(head)) = (above.get(..inner), dst.get_mut(..inner)) else {
            return;
        };
        // The destination, the pairs of neighbours and the row above zipped: no bounds checks.
        let mut dx = 0;
        for ((o, w), &u) in head.iter_mut().zip(f.windows(2)).zip(up) {
            let [v, r] = [w[0], w[1]];
            dx = d(r, v);
            *o = put(self.sample_sq::<CLAMP>(v, norm_sq(dx, d(v, u), e2)));
        }
        if let (Some(o), Some(&v), Some(&u)) = (dst.get_mut(inner), f.get(inner), above.get(inner))
        {
            *o = put(self.sample_sq::<CLAMP>(v, norm_sq(dx, d(v, u), e2)));
        }
    }

    /// [`Ramp565::shade_differences_l2`] with the wrap `CLAMP` and the spread's square `e2`.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn shade_differences<const CLAMP: bool, F: FnMut(Rgb565)>(
        &self,
        f: &[crate::format::TexValue],
        above: &[crate::format::TexValue],
        e2: u32,
        mut emit: F,
    ) {
        let n = f.len().min(above.len());
        let (Some(f), Some(above)) = (f.get(..n), above.get(..n)) else {
            return;
        };
        let norm = |dx: i32, dy: i32| norm_sq(dx, dy, e2);
        let d = |a: crate::format::TexValue, b: crate::format::TexValue| {
            a.to_bits().wrapping_sub(b.to_bits())
        };
        // Every pixel but the last: the difference to its right neighbour.
        let mut dx = 0;
        for ((&v, &r), &u) in f.iter().zip(f.iter().skip(1)).zip(above) {
            dx = d(r, v);
            emit(self.sample_sq::<CLAMP>(v, norm(dx, d(v, u))));
        }
        if let (Some(&v), Some(&u)) = (f.last(), above.last()) {
            emit(self.sample_sq::<CLAMP>(v, norm(dx, d(v, u))));
        }
    }

    /// The colour of value `f` (wrap `CLAMP`) with gradient magnitudes `a`, `b` and the spread's
    /// square `e2` ([`magnitude48`]) by the L2 norm: one read.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn sample<const CLAMP: bool>(
        &self,
        f: crate::format::TexValue,
        a: u32,
        b: u32,
        e2: u32,
    ) -> Rgb565 {
        self.sample_sq::<CLAMP>(f, norm2(a, b, e2))
    }

    /// The place (`(row N + offset) << 5 | shift`) of the level of the squared norm `s`: level
    /// `min(L, max(0, h + L - 16))` of half bit length `h = level_of_sq32(s)`, from one
    /// threshold and one place read (`by_clz`).
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn place_of_sq(&self, s: u32) -> u32 {
        let c = (s.leading_zeros() as usize).min(32);
        let [threshold, above] = self.by_clz[c];
        if s < threshold {
            self.by_clz[c + 1][1]
        } else {
            above
        }
    }

    /// The colour of value `f` (wrap `CLAMP`) at the level of the squared norm `s` (saturated
    /// at `u32::MAX`, [`norm2`]): one read.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn sample_sq<const CLAMP: bool>(&self, f: crate::format::TexValue, s: u32) -> Rgb565 {
        let p = self.place_of_sq(s);
        let n_log2 = Self::MAX_LEVEL;
        let k = if CLAMP {
            // Entry min(floor(clamp(f, 0, 1) N), N - 1).
            (f.to_bits().clamp(0, 0xFFFF) as u32) >> (16 - n_log2)
        } else {
            // Entry floor(frac(f) N).
            ((f.to_bits() as u32) & 0xFFFF) >> (16 - n_log2)
        };
        self.flat(((p >> 5) + (k >> (p & 31))) as usize)
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

    /// `n` values of `next`'s high words shifted right by `scale` (0..32).
    fn random_values(
        next: &mut impl FnMut() -> u64,
        n: usize,
        scale: u64,
    ) -> std::vec::Vec<crate::format::TexValue> {
        (0..n)
            .map(|_| crate::format::TexValue::from_bits(((next() >> 32) as i32) >> scale))
            .collect()
    }

    /// A 64-bit linear congruential generator from `seed`: each call its next state.
    fn lcg(seed: u64) -> impl FnMut() -> u64 {
        let mut s = seed;
        move || crate::test_rng::lcg64(&mut s)
    }

    fn lcg_table<const N: usize>(seed: u64) -> ColorTable<N> {
        let mut next = lcg(seed);
        let mut e = [Rgba8888::TRANSPARENT; N];
        for c in e.iter_mut() {
            let mut b = [0u8; 4];
            for v in b.iter_mut() {
                *v = (next() >> 56) as u8;
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

    /// The level table's place of every bit length's edges and of random squares is that of
    /// `level_of_sq32` through `place`.
    #[test]
    fn level_places_are_level_of_sq32() {
        fn check<const N: usize>(r: &Ramp565<N>, s: u32) {
            let top = Ramp565::<N>::MAX_LEVEL;
            let l = (level_of_sq32(s) + top).saturating_sub(16).min(top);
            let (row, offset, shift) = place(N, l);
            let want = (((row * N + offset) as u32) << 5) | shift;
            assert_eq!(r.place_of_sq(s), want, "N = {N}, s = {s}");
        }
        let small = Ramp565::new(&lcg_table::<64>(5), TableWrap::Mod);
        let large = Ramp565::new(&lcg_table::<256>(6), TableWrap::Clamp);
        let mut edges = std::vec![0, 1, u32::MAX];
        for b in 1..=32u32 {
            let p = 1u64 << (b - 1);
            let t = BELOW_BY_BITS[b as usize];
            for v in [p, p + 1, p - 1, t, t + 1, t.saturating_sub(1)] {
                if let Ok(v) = u32::try_from(v) {
                    edges.push(v);
                }
            }
        }
        let mut next = lcg(11);
        edges.extend((0..20_000).map(|_| (next() >> (32 + next() % 32)) as u32));
        for &s in &edges {
            check(&small, s);
            check(&large, s);
        }
    }

    /// [`magnitude48`] of a difference of 16 fraction bits (the magnitude of the difference
    /// shifted to 48 fraction bits).
    fn magnitude16(d: i32) -> u32 {
        d.unsigned_abs().min(0xFFFF)
    }

    /// The branch-free squared norm of differences has the level of `norm2` of the capped
    /// magnitudes (the width the gradient paths take), and is that very number below the caps.
    #[test]
    fn difference_norm_has_the_level_of_the_capped_magnitudes() {
        let mut next = lcg(23);
        let edges = [
            0,
            1,
            -1,
            0x7FFF,
            -0x8000,
            0x8000,
            0xB504,
            0xB505,
            0xFFFF,
            -0xFFFF,
            0x1_0000,
            -0x1_0000,
            i32::MAX,
            i32::MIN,
        ];
        let mut cases = std::vec::Vec::new();
        for &a in &edges {
            for &b in &edges {
                for e in [0u32, 1, 0x7FFF, 0xB505, 0xFFFF] {
                    cases.push((a, b, e));
                }
            }
        }
        for _ in 0..50_000 {
            let mut value = || {
                let x = next();
                (x >> 32) as i32 >> (x % 32)
            };
            let (a, b) = (value(), value());
            let x = next();
            cases.push((a, b, ((x >> 48) as u32) >> (x % 17)));
        }
        for (a, b, e) in cases {
            let capped = norm2(magnitude16(a), magnitude16(b), e * e);
            let s = norm_sq(a, b, e * e);
            assert_eq!(level_of_sq32(s), level_of_sq32(capped), "{a} {b} {e}");
            if a.unsigned_abs() <= 0xFFFF && b.unsigned_abs() <= 0xFFFF && capped < u32::MAX {
                assert_eq!(s, capped, "{a} {b} {e}");
            }
        }
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
        let mut lcg = lcg(11);
        let mut next = |bound: u64| (lcg() >> 20) % bound;
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
            let mut next = lcg(seed);
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

    /// The differences path is [`Ramp565::shade_l2`] given the differences as gradients: rows of
    /// every scale (differences past 2^15 and wrapping ones), spreads below and above 2^15,
    /// lengths 0, 1 and more, both wraps and several table sizes.
    #[test]
    fn shade_differences_l2_is_shade_l2_of_the_differences() {
        fn check<const N: usize>(seed: u64) {
            let t = lcg_table::<N>(seed);
            let mut next = lcg(seed);
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                let r = Ramp565::new(&t, wrap);
                for round in 0..300 {
                    let len = [0usize, 1, 2, 31][round % 4];
                    let scale = next() % 32;
                    let (f, above) = (
                        random_values(&mut next, len, scale),
                        random_values(&mut next, len, scale),
                    );
                    let extra = match round % 5 {
                        0 => 0,
                        1 => (1i64 << 47) - 1,
                        2 => 1i64 << 47,
                        3 => i64::MAX,
                        _ => (next() >> 1) as i64 >> (next() % 63),
                    };
                    let d = |a: crate::format::TexValue, b: crate::format::TexValue| {
                        i64::from(a.to_bits().wrapping_sub(b.to_bits())) << 32
                    };
                    let gx: std::vec::Vec<i64> = (0..len)
                        .map(|i| match (i + 1 < len, i > 0) {
                            (true, _) => d(f[i + 1], f[i]),
                            (false, true) => d(f[i], f[i - 1]),
                            _ => 0,
                        })
                        .collect();
                    let gy: std::vec::Vec<i64> = (0..len).map(|i| d(f[i], above[i])).collect();
                    let mut want = std::vec::Vec::new();
                    r.shade_l2(&f, &gx, &gy, extra, |c| want.push(c));
                    let mut got = std::vec::Vec::new();
                    r.shade_differences_l2(&f, &above, extra, |c| got.push(c));
                    assert_eq!(got, want, "N {N} {wrap:?} round {round}");
                }
            }
        }
        check::<16>(6);
        check::<256>(7);
        check::<1024>(8);
    }

    #[test]
    fn shade_differences_l2_into_writes_the_emitted_colours() {
        fn check<const N: usize>(seed: u64) {
            let t = lcg_table::<N>(seed);
            let mut next = lcg(seed ^ 0x5EED);
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                let r = Ramp565::new(&t, wrap);
                for round in 0..400 {
                    let len = [0usize, 1, 2, 3, 17, 64][round % 6];
                    // Small differences (the unsaturated norm), then any.
                    let scale = if round % 3 == 0 {
                        20 + next() % 12
                    } else {
                        next() % 32
                    };
                    let (f, above) = (
                        random_values(&mut next, len, scale),
                        random_values(&mut next, len, scale),
                    );
                    let extra = match round % 4 {
                        0 => 0,
                        1 => (1i64 << 47) - 1,
                        2 => i64::MAX,
                        _ => (next() >> 1) as i64 >> (next() % 63),
                    };
                    let mut want = std::vec::Vec::new();
                    r.shade_differences_l2(&f, &above, extra, |c| want.push(c.0));
                    // A destination as long as the values, shorter (its last pixel keeps its
                    // right neighbour's difference) and longer (untouched past the values).
                    for dlen in [len, len.saturating_sub(1), len + 2] {
                        let mut got = std::vec![0xA5A5_u32; dlen];
                        r.shade_differences_l2_into(&f, &above, extra, &mut got, |c| {
                            u32::from(c.0) | 1 << 16
                        });
                        for (i, g) in got.iter().enumerate() {
                            let w = if i < len {
                                u32::from(want[i]) | 1 << 16
                            } else {
                                0xA5A5
                            };
                            assert_eq!(*g, w, "N {N} {wrap:?} round {round} dlen {dlen} i {i}");
                        }
                    }
                    // `above` shorter than the values: only its pixels are written.
                    let mut got = std::vec![0u16; len];
                    let short = &above[..len / 2];
                    r.shade_differences_l2_into(&f, short, extra, &mut got, |c| c.0);
                    assert_eq!(got[..len / 2], want[..len / 2], "N {N} round {round}");
                    assert!(got[len / 2..].iter().all(|&g| g == 0));
                }
            }
        }
        check::<16>(16);
        check::<256>(17);
        check::<1024>(18);
    }

    #[test]
    fn the_32_bit_level_is_the_64_bit_one() {
        for b in 0..=32u32 {
            let p = if b == 0 { 0 } else { 1u64 << (b - 1) };
            for s in [p, p + 1, p.saturating_sub(1), BELOW_BY_BITS[b as usize]] {
                for s in [s.saturating_sub(1), s, s + 1] {
                    if let Ok(s32) = u32::try_from(s) {
                        assert_eq!(level_of_sq32(s32), level_of_sq(s), "s = {s}");
                    }
                }
            }
        }
        let mut rng = crate::test_rng::XorShift32::new(0x9E37_79B9);
        for _ in 0..200_000 {
            let x = rng.next_u32();
            let s = x >> (x % 32);
            assert_eq!(level_of_sq32(s), level_of_sq(u64::from(s)), "s = {s}");
        }
        // The saturated norm has the level of the exact one (capped at half bit length 16).
        for (a, b, e) in [
            (0xFFFF, 0, 0),
            (0xFFFF, 0xFFFF, 0xFFFF),
            (0xB505, 0xB505, 0),
            (0, 0, 0),
        ] {
            let exact =
                u64::from(a) * u64::from(a) + u64::from(b) * u64::from(b) + u64::from(e * e);
            assert_eq!(
                level_of_sq32(norm2(a, b, e * e)),
                level_of_sq(exact).min(16)
            );
        }
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
