//! Summed-area colour table (`csat`, Hart et al. 1999 section 3.3.2): the box filter of
//! `docs/model.md` section 7, exactly, in two layouts.
//!
//! - [`Csat`]: prefix sums over the `N` entries, with the paper's case analysis at run time for
//!   windows crossing either end of the table (`mod`: wrap around; `clamp`: extend the end entries).
//!   Either wrap can be chosen per look-up.
//! - [`Csat3`]: prefix sums over the three-times-long extended table (entries `-N .. 2N - 1`, built
//!   for one wrap), so a look-up is one subtraction of two prefix sums with no case analysis.
//!
//! Both compute, bit for bit, the model's box filter: with `lo = (x - w/2 + 128) >> 8` and
//! `hi = (x + w/2 + 128) >> 8` (units of 1/256 entry), `w >= N` gives the table mean
//! `(sum + N/2) / N`, `hi == lo` gives the nearest entry at `x`, and otherwise each channel is
//! `(I(hi) - I(lo) + (hi - lo)/2) / (hi - lo)` with `I` the exact integral (times 256) of the
//! piecewise-constant extended table. The fractional end pieces are integrated exactly
//! (`256 * whole entries + r_hi * c[k_hi] - r_lo * c[k_lo]`), so the only rounding is the final
//! division.
//!
//! Storage and exactness: each prefix sum packs the four channels in 16-bit lanes of one `u64`
//! (`r` in bits 0..16, then `g`, `b`, `a`), accumulated with wrapping `u64` addition. The packed
//! sums are exact modulo 2^16 per lane, so the difference of two prefix sums is the exact per-lane
//! window sum whenever each lane's true window sum is below 65536, i.e. for windows of up to 257
//! entries. Windows are therefore taken in pieces of at most 256 entries (one piece for `N <= 256`;
//! up to four for `N = 1024`), each unpacked and added in `u32` lanes. Every intermediate fits in
//! `u32` (`I(hi) - I(lo) <= 255 * 256 * N < 2^26`).
//!
//! `clamp` tables centre the box on the unclamped coordinate `x = f N` ([`clamp_box_x`], model
//! section 7): a pixel whose `f` lies past an end of the table is shown the end entry extended
//! over the part of its window beyond the end (wholly, when the window lies past the end), never
//! the entries inside the end that its footprint does not reach. [`Csat::box_filter_clamp_at`]
//! and [`Csat3::box_filter_at`] take that signed coordinate; inside `[0, N]` it is the same box as
//! the look-ups at a `TableCoord`.
//!
//! Input ranges: any `TableCoord` and `FilterWidth` are accepted. `x` is first brought into the
//! table's coordinate range (`x mod N` for `mod`, `min(x, N)` for `clamp`), which is what
//! [`ColorTable::coord`] always produces; every index is then bounded by construction, and prefix
//! sums are read with `get` (falling back to the final sum), so no look-up can panic.
//!
//! Memory (bytes, `size_of`): [`Csat`] `8 N + 16`, [`Csat3`] `24 N + 16` (for `N = 256`: 2064 and
//! 6160), plus the colour table (`4 N`) kept by the colour stage for unfiltered look-ups.

use crate::color::Rgba8888;
use crate::format::{FilterWidth, TableCoord, TexValue};
use crate::table::{ColorTable, TableWrap};

/// Packs `[r, g, b, a]` into four 16-bit lanes.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn pack(c: Rgba8888) -> u64 {
    c.r as u64 | (c.g as u64) << 16 | (c.b as u64) << 32 | (c.a as u64) << 48
}

/// Unpacks four 16-bit lanes.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn unpack(p: u64) -> [u32; 4] {
    [
        (p & 0xFFFF) as u32,
        ((p >> 16) & 0xFFFF) as u32,
        ((p >> 32) & 0xFFFF) as u32,
        (p >> 48) as u32,
    ]
}

/// Prefix sum `S(i)`: `s[i]` for `i < s.len()`, else `last` (`S(len)`).
#[cfg_attr(not(texcore_lean), inline(always))]
fn prefix(s: &[u64], last: u64, i: usize) -> u64 {
    match s.get(i) {
        Some(&v) => v,
        None => last,
    }
}

/// The entry `k` recovered from the prefix sums, `S(k + 1) - S(k)` (paper eq. 14), per channel.
#[cfg_attr(not(texcore_lean), inline(always))]
fn entry(s: &[u64], last: u64, k: usize) -> [u32; 4] {
    unpack(prefix(s, last, k + 1).wrapping_sub(prefix(s, last, k)))
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn add4(a: [u32; 4], b: [u32; 4]) -> [u32; 4] {
    [
        a[0].wrapping_add(b[0]),
        a[1].wrapping_add(b[1]),
        a[2].wrapping_add(b[2]),
        a[3].wrapping_add(b[3]),
    ]
}

/// Longest window whose packed difference is exact (lane sums <= 255 * 256 < 65536).
const PIECE: usize = 256;

/// Per-channel sum of entries `ka .. kb` (`ka <= kb`), in pieces of at most [`PIECE`] entries.
#[cfg_attr(not(texcore_lean), inline(always))]
fn window(s: &[u64], last: u64, ka: usize, kb: usize) -> [u32; 4] {
    let mut a = ka;
    let mut acc = [0u32; 4];
    // At most ceil(N / 256) <= 4 pieces for the windows used here (kb - ka <= N); for N <= 256 the
    // loop body never runs.
    while kb > a + PIECE {
        let next = a + PIECE;
        acc = add4(
            acc,
            unpack(prefix(s, last, next).wrapping_sub(prefix(s, last, a))),
        );
        a = next;
    }
    if kb > a {
        acc = add4(
            acc,
            unpack(prefix(s, last, kb).wrapping_sub(prefix(s, last, a))),
        );
    }
    acc
}

/// `I(b) - I(a)` per channel, `0 <= a <= b`, positions in 1/256 entry from the start of the prefix
/// array: `256 * sum(entries ka .. kb) + rb * c[kb] - ra * c[ka]`. Non-negative by construction
/// (when `kb > ka` the whole entries cover `ra * c[ka]`; when `kb == ka`, `rb >= ra`).
#[cfg_attr(not(texcore_lean), inline(always))]
fn integral(s: &[u64], last: u64, a: u32, b: u32) -> [u32; 4] {
    let (ka, ra) = ((a >> 8) as usize, a & 255);
    let (kb, rb) = ((b >> 8) as usize, b & 255);
    let whole = window(s, last, ka, kb);
    let ca = entry(s, last, ka);
    let cb = if rb == 0 { [0; 4] } else { entry(s, last, kb) };
    let mut out = [0u32; 4];
    let mut i = 0;
    while i < 4 {
        out[i] = (whole[i] * 256 + rb * cb[i]).wrapping_sub(ra * ca[i]);
        i += 1;
    }
    out
}

/// Final rounding `(num + d/2) / d` per channel (`d >= 1`, result <= 255).
#[cfg_attr(not(texcore_lean), inline(always))]
fn divide(num: [u32; 4], d: u32) -> Rgba8888 {
    let d = if d == 0 { 1 } else { d };
    let h = d / 2;
    Rgba8888::new(
        ((num[0] + h) / d) as u8,
        ((num[1] + h) / d) as u8,
        ((num[2] + h) / d) as u8,
        ((num[3] + h) / d) as u8,
    )
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn from_lanes(c: [u32; 4]) -> Rgba8888 {
    Rgba8888::new(c[0] as u8, c[1] as u8, c[2] as u8, c[3] as u8)
}

/// Brings `x` (raw U16F16) into `[0, N)` (`mod`) or `[0, N]` (`clamp`).
#[cfg_attr(not(texcore_lean), inline(always))]
const fn normalise_x(x: u32, n_log2: u32, wrap: TableWrap) -> u32 {
    let full = 1u32 << (16 + n_log2);
    match wrap {
        TableWrap::Mod => x & (full - 1),
        TableWrap::Clamp => {
            if x > full {
                full
            } else {
                x
            }
        }
    }
}

/// The window `[lo, hi]` in 1/256 entry for a normalised `x` and `w < N` (so both fit `i32`).
#[cfg_attr(not(texcore_lean), inline(always))]
const fn endpoints(x: u32, w: u32) -> (i32, i32) {
    let x = x as i32;
    let half = (w / 2) as i32;
    ((x - half + 128) >> 8, (x + half + 128) >> 8)
}

/// The box's centre for a `clamp` table (raw 16.16 entries, signed): `x = f N` unclamped, limited
/// to `[-(w/2) - 1, N + w/2 + 1]` entries (every window further out lies wholly past the end, so
/// the limit changes no colour and keeps every intermediate in `i32`). `n_log2 <= 10`.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn clamp_box_x(f: TexValue, w: FilterWidth, n_log2: u32) -> i32 {
    let x = (f.to_bits() as i64) << n_log2;
    let half = (w.to_bits() / 2) as i64 + (1 << 16);
    let full = 1i64 << (16 + n_log2);
    let x = if x < -half {
        -half
    } else if x > full + half {
        full + half
    } else {
        x
    };
    x as i32
}

/// Summed-area colour table over the `N` entries: the box filter with the paper's case analysis.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Csat<const N: usize> {
    /// Exclusive packed prefix sums `S(0) .. S(N - 1)` (`S(0) = 0`).
    sums: [u64; N],
    /// `S(N)`, the packed sum of all entries.
    total: u64,
    /// The table mean, for `w >= N`.
    mean: Rgba8888,
}

impl<const N: usize> Csat<N> {
    /// Bytes of this structure.
    pub const BYTES: usize = core::mem::size_of::<Self>();

    /// Builds the prefix sums of `table` (`csat[i] = csat[i-1] + clut[i]`).
    pub const fn new(table: &ColorTable<N>) -> Self {
        let e = table.entries();
        let mut sums = [0u64; N];
        let mut acc = 0u64;
        let mut j = 0;
        while j < N {
            sums[j] = acc;
            acc = acc.wrapping_add(pack(e[j]));
            j += 1;
        }
        Csat {
            sums,
            total: acc,
            mean: table.mean(),
        }
    }

    /// The table mean `(sum + N/2) / N` (the result for `w >= N`).
    pub const fn mean(&self) -> Rgba8888 {
        self.mean
    }

    /// Entry `j` of the table (wrapped `& (N - 1)`), recovered from the sums.
    pub fn entry(&self, j: usize) -> Rgba8888 {
        from_lanes(entry(&self.sums, self.total, j & (N - 1)))
    }

    /// The box-filtered colour at table coordinate `x`, width `w` (model section 7), windows
    /// crossing an end of the table resolved by case analysis for `wrap`.
    pub fn box_filter(&self, x: TableCoord, w: FilterWidth, wrap: TableWrap) -> Rgba8888 {
        let n_log2 = N.trailing_zeros();
        let w = w.to_bits();
        if w >= 1u32 << (16 + n_log2) {
            return self.mean;
        }
        let x = normalise_x(x.to_bits(), n_log2, wrap);
        let (lo, hi) = endpoints(x, w);
        let s = &self.sums[..];
        let t = self.total;
        if hi == lo {
            let k = (x >> 16) as usize;
            let k = match wrap {
                TableWrap::Mod => k & (N - 1),
                TableWrap::Clamp => k.min(N - 1),
            };
            return from_lanes(entry(s, t, k));
        }
        let d = (hi - lo) as u32;
        // 256 N: the end of the table in 1/256 entry. Here lo >= -128 N and hi <= 384 N.
        let end = (N as i32) << 8;
        let num = match wrap {
            TableWrap::Mod => {
                if hi > end {
                    // f + w/2 >= N: csat[f + w/2 - N] + csat[N - 1] - csat[f - w/2 - 1]
                    add4(
                        integral(s, t, lo as u32, end as u32),
                        integral(s, t, 0, (hi - end) as u32),
                    )
                } else if lo < 0 {
                    // f - w/2 < 0: csat[f + w/2] + csat[N - 1] - csat[N + f - w/2 - 1]
                    add4(
                        integral(s, t, (lo + end) as u32, end as u32),
                        integral(s, t, 0, hi as u32),
                    )
                } else {
                    integral(s, t, lo as u32, hi as u32)
                }
            }
            TableWrap::Clamp => return self.clamp_window(lo, hi),
        };
        divide(num, d)
    }

    /// The end-extended table (entry 0 before it, entry `N - 1` after it) averaged over
    /// `[lo, hi]` in 1/256 entry, `lo < hi`, `-256 (N + 1) <= lo` and `hi <= 256 (2 N + 1)`
    /// (every lane product and sum then fits `u32`): a `clamp` table's window crossing its ends.
    #[cfg_attr(texcore_lean, inline(never))]
    fn clamp_window(&self, lo: i32, hi: i32) -> Rgba8888 {
        let (s, t) = (&self.sums[..], self.total);
        let end = (N as i32) << 8;
        let mut acc = [0u32; 4];
        let a = if lo < 0 {
            // -(f - w/2) clut[0]
            let c0 = entry(s, t, 0);
            let k = lo.unsigned_abs();
            acc = [k * c0[0], k * c0[1], k * c0[2], k * c0[3]];
            0
        } else {
            lo
        };
        let b = if hi > end {
            // (f + w/2 - (N - 1)) clut[N - 1]
            let cl = entry(s, t, N - 1);
            let k = (hi - end) as u32;
            acc = add4(acc, [k * cl[0], k * cl[1], k * cl[2], k * cl[3]]);
            end
        } else {
            hi
        };
        divide(
            add4(acc, integral(s, t, a as u32, b as u32)),
            (hi - lo) as u32,
        )
    }
}

impl<const N: usize> Csat<N> {
    /// The box filter of a `clamp` table centred at the signed coordinate `x` ([`clamp_box_x`],
    /// raw 16.16 entries), width `w`: the average of the end-extended table over
    /// `[x - w/2, x + w/2]` (model section 7). For `0 <= x <= N` the same as
    /// [`Csat::box_filter`] with `TableWrap::Clamp`; a window wholly past an end gives that end's
    /// entry; `w >= N` gives the table mean.
    pub fn box_filter_clamp_at(&self, x: i32, w: FilterWidth) -> Rgba8888 {
        let n_log2 = N.trailing_zeros();
        let wb = w.to_bits();
        if wb >= 1u32 << (16 + n_log2) {
            return self.mean;
        }
        let full = 1i64 << (16 + n_log2);
        let half = i64::from(wb / 2) + (1 << 16);
        // The same limits as `clamp_box_x`, so any `x` is accepted.
        let x = i64::from(x).clamp(-half, full + half);
        if (0..=full).contains(&x) {
            return self.box_filter(TableCoord::from_bits(x as u32), w, TableWrap::Clamp);
        }
        let (s, t) = (&self.sums[..], self.total);
        let x = x as i32;
        let half = (wb / 2) as i32;
        let (lo, hi) = ((x - half + 128) >> 8, (x + half + 128) >> 8);
        let end = (N as i32) << 8;
        if hi <= 0 || (hi == lo && x < 0) {
            return from_lanes(entry(s, t, 0));
        }
        if lo >= end || hi == lo {
            return from_lanes(entry(s, t, N - 1));
        }
        // lo < 0 < hi <= end (x < 0) or 0 <= lo < end < hi (x > N): one end extended, and
        // lo >= -256 (N + 1), hi <= 256 (2 N + 1) (x is limited as `clamp_box_x` limits it).
        self.clamp_window(lo, hi)
    }

    /// [`Csat::box_filter`] for tables of at most 256 entries, with the two end entries read from
    /// `entries` (the table these sums were built from) instead of recovered from prefix-sum
    /// differences, and `mod` windows crossing an end of the table resolved by periodicity
    /// instead of case analysis: the window's whole entries are `S(kb mod N) - S(ka mod N)`, plus
    /// `S(N)` when the window wraps (it wraps at most once, as `w < N`). The same result as
    /// [`Csat::box_filter`] for every input (tested exhaustively on small tables and by property
    /// tests), in about half the instructions. Longer tables and `clamp` windows reaching past an
    /// end take [`Csat::box_filter`].
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(crate) fn box_filter_in(
        &self,
        entries: &[Rgba8888; N],
        x: TableCoord,
        w: FilterWidth,
        wrap: TableWrap,
    ) -> Rgba8888 {
        if N > PIECE || !N.is_power_of_two() {
            return self.box_filter(x, w, wrap);
        }
        let n_log2 = N.trailing_zeros();
        let wb = w.to_bits();
        if wb >= 1u32 << (16 + n_log2) {
            return self.mean;
        }
        let xn = normalise_x(x.to_bits(), n_log2, wrap);
        let (lo, hi) = endpoints(xn, wb);
        let mask = N - 1;
        if hi == lo {
            let k = (xn >> 16) as usize;
            let k = match wrap {
                TableWrap::Mod => k & mask,
                TableWrap::Clamp => k.min(mask),
            };
            return match entries.get(k) {
                Some(&c) => c,
                None => self.mean,
            };
        }
        if wrap == TableWrap::Clamp && (lo < 0 || hi > (N as i32) << 8) {
            return self.box_filter(x, w, wrap);
        }
        // Entries ka .. kb of the periodic table (for `clamp`, 0 <= ka <= kb <= N here, and
        // kb == N only with rb == 0: its "wrap" adds S(N) to S(0), and its entry weighs 0).
        let (ka, kb) = (lo >> 8, hi >> 8);
        let (ra, rb) = ((lo & 255) as u32, (hi & 255) as u32);
        let (ia, ib) = (ka as usize & mask, kb as usize & mask);
        let sa = match self.sums.get(ia) {
            Some(&v) => v,
            None => 0,
        };
        let sb = match self.sums.get(ib) {
            Some(&v) => v,
            None => 0,
        };
        let mut whole = sb.wrapping_sub(sa);
        if (kb >> n_log2) != (ka >> n_log2) {
            whole = whole.wrapping_add(self.total);
        }
        let wl = unpack(whole);
        let (ca, cb) = match (entries.get(ia), entries.get(ib)) {
            (Some(a), Some(b)) => (a.to_array(), b.to_array()),
            _ => return self.mean,
        };
        let mut num = [0u32; 4];
        let mut i = 0;
        while i < 4 {
            num[i] = (wl[i] * 256 + rb * cb[i] as u32).wrapping_sub(ra * ca[i] as u32);
            i += 1;
        }
        divide(num, (hi - lo) as u32)
    }
}

/// Summed-area colour table over the three-times-long extended table (entries `-N .. 2N - 1`,
/// extended by `wrap`): the same box filter as [`Csat`] without run-time case analysis.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Csat3<const N: usize> {
    /// Exclusive packed prefix sums `S3(0) .. S3(3N - 1)` of the extended table, where `S3(i)` sums
    /// the extended entries `-N .. i - N - 1`; read through `as_flattened`.
    sums: [[u64; N]; 3],
    /// `S3(3N)`.
    last: u64,
    /// The table mean, for `w >= N`.
    mean: Rgba8888,
    /// The wrap the extension was built for.
    wrap: TableWrap,
}

impl<const N: usize> Csat3<N> {
    /// Bytes of this structure.
    pub const BYTES: usize = core::mem::size_of::<Self>();

    /// Builds the prefix sums of the extended table: entry `j` in `-N .. 2N - 1` is
    /// `clut[j mod N]` (`Mod`) or `clut[clamp(j, 0, N - 1)]` (`Clamp`).
    pub const fn new(table: &ColorTable<N>, wrap: TableWrap) -> Self {
        let e = table.entries();
        let mut sums = [[0u64; N]; 3];
        let mut acc = 0u64;
        let mut i = 0;
        while i < 3 * N {
            sums[i / N][i % N] = acc;
            // Extended index j = i - N in -N .. 2N - 1.
            let k = match wrap {
                TableWrap::Mod => i % N,
                TableWrap::Clamp => {
                    if i < N {
                        0
                    } else if i >= 2 * N {
                        N - 1
                    } else {
                        i - N
                    }
                }
            };
            acc = acc.wrapping_add(pack(e[k]));
            i += 1;
        }
        Csat3 {
            sums,
            last: acc,
            mean: table.mean(),
            wrap,
        }
    }

    /// The wrap this table was built for.
    pub const fn wrap(&self) -> TableWrap {
        self.wrap
    }

    /// The table mean `(sum + N/2) / N` (the result for `w >= N`).
    pub const fn mean(&self) -> Rgba8888 {
        self.mean
    }

    /// The box-filtered colour at table coordinate `x`, width `w` (model section 7), for the wrap
    /// the table was built with. Identical to [`Csat::box_filter`] for every input.
    pub fn box_filter(&self, x: TableCoord, w: FilterWidth) -> Rgba8888 {
        let n_log2 = N.trailing_zeros();
        let w = w.to_bits();
        if w >= 1u32 << (16 + n_log2) {
            return self.mean;
        }
        let x = normalise_x(x.to_bits(), n_log2, self.wrap);
        let (lo, hi) = endpoints(x, w);
        let s = self.sums.as_flattened();
        // Offset of extended entry 0, in 1/256 entry: 256 N. With lo >= -128 N, hi <= 384 N both
        // shifted ends lie in [128 N, 640 N] inside the 768 N of the table.
        let off = (N as i32) << 8;
        if hi == lo {
            // The extended entry floor(x) is the nearest entry for either wrap (x < N for Mod,
            // x <= N with entry N = clut[N - 1] for Clamp).
            return from_lanes(entry(s, self.last, (x >> 16) as usize + N));
        }
        let num = integral(s, self.last, (lo + off) as u32, (hi + off) as u32);
        divide(num, (hi - lo) as u32)
    }

    /// For a `clamp` table: the box centred at the signed coordinate `x` ([`clamp_box_x`]),
    /// identical to [`Csat::box_filter_clamp_at`] for every input; a `mod` table takes
    /// [`Csat3::box_filter`] at `x mod N`.
    pub fn box_filter_at(&self, x: i32, w: FilterWidth) -> Rgba8888 {
        let n_log2 = N.trailing_zeros();
        let full = 1i64 << (16 + n_log2);
        if self.wrap == TableWrap::Mod {
            let xm = (i64::from(x) & (full - 1)) as u32;
            return self.box_filter(TableCoord::from_bits(xm), w);
        }
        let wb = w.to_bits();
        if wb >= 1u32 << (16 + n_log2) {
            return self.mean;
        }
        let half = i64::from(wb / 2) + (1 << 16);
        let x = i64::from(x).clamp(-half, full + half);
        if (0..=full).contains(&x) {
            return self.box_filter(TableCoord::from_bits(x as u32), w);
        }
        let s = self.sums.as_flattened();
        let x = x as i32;
        let half = (wb / 2) as i32;
        let (lo, hi) = ((x - half + 128) >> 8, (x + half + 128) >> 8);
        let (off, end) = ((N as i32) << 8, (N as i32) << 8);
        if hi <= 0 || (hi == lo && x < 0) {
            return from_lanes(entry(s, self.last, N));
        }
        if lo >= end || hi == lo {
            return from_lanes(entry(s, self.last, 2 * N - 1));
        }
        // -N < lo < hi < 2N (w < N): inside the extended table.
        let num = integral(s, self.last, (lo + off) as u32, (hi + off) as u32);
        divide(num, (hi - lo) as u32)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use fixed::types::{I16F16, U16F16};
    use proptest::prelude::*;
    use std::vec::Vec;

    /// Independent reference of the model's box filter: exact integration of the
    /// piecewise-constant table, entry by entry, in i64, round half up.
    fn reference(e: &[Rgba8888], x: u32, w: u32, wrap: TableWrap) -> Rgba8888 {
        let n = e.len() as i64;
        if w as i64 >= n * 65536 {
            let mut s = [0i64; 4];
            for c in e {
                for (i, v) in c.to_array().iter().enumerate() {
                    s[i] += *v as i64;
                }
            }
            return Rgba8888::from_array(s.map(|v| ((2 * v + n) / (2 * n)) as u8));
        }
        let x = match wrap {
            TableWrap::Mod => (x as i64).rem_euclid(n * 65536),
            TableWrap::Clamp => (x as i64).min(n * 65536),
        };
        reference_at(e, x, w, wrap)
    }

    /// The box at a coordinate taken as it is (a `clamp` table's unclamped centre).
    fn reference_at(e: &[Rgba8888], x: i64, w: u32, wrap: TableWrap) -> Rgba8888 {
        let n = e.len() as i64;
        let chans = |j: i64| -> [i64; 4] {
            let k = match wrap {
                TableWrap::Mod => j.rem_euclid(n),
                TableWrap::Clamp => j.clamp(0, n - 1),
            };
            e[k as usize].to_array().map(i64::from)
        };
        let half = (w / 2) as i64;
        let lo = (x - half + 128).div_euclid(256);
        let hi = (x + half + 128).div_euclid(256);
        if lo == hi {
            return Rgba8888::from_array(chans(x.div_euclid(65536)).map(|v| v as u8));
        }
        let mut sum = [0i64; 4];
        for j in lo.div_euclid(256)..=(hi - 1).div_euclid(256) {
            let len = hi.min(256 * (j + 1)) - lo.max(256 * j);
            assert!(len > 0);
            let c = chans(j);
            for i in 0..4 {
                sum[i] += len * c[i];
            }
        }
        let d = hi - lo;
        Rgba8888::from_array(sum.map(|v| ((2 * v + d) / (2 * d)) as u8))
    }

    use crate::test_rng::lcg_table;

    fn check_point<const N: usize>(
        t: &ColorTable<N>,
        c: &Csat<N>,
        c3: &[Csat3<N>; 2],
        x: u32,
        w: u32,
    ) {
        for (wrap, c3) in [TableWrap::Mod, TableWrap::Clamp].into_iter().zip(c3) {
            let want = reference(t.entries(), x, w, wrap);
            let got = c.box_filter(U16F16::from_bits(x), U16F16::from_bits(w), wrap);
            let got3 = c3.box_filter(U16F16::from_bits(x), U16F16::from_bits(w));
            assert_eq!(got, want, "csat N={N} x={x:#x} w={w:#x} {wrap:?}");
            assert_eq!(got3, want, "csat3 N={N} x={x:#x} w={w:#x} {wrap:?}");
            let fast = c.box_filter_in(
                t.entries(),
                U16F16::from_bits(x),
                U16F16::from_bits(w),
                wrap,
            );
            assert_eq!(
                fast, want,
                "csat (entries) N={N} x={x:#x} w={w:#x} {wrap:?}"
            );
        }
    }

    /// Every f over a full period at every 1/256-entry position of x, every w at 1/256 steps (plus
    /// the odd raw width just above, which rounds `w/2` differently) up to past N, both wraps.
    fn exhaustive<const N: usize>(t: &ColorTable<N>) {
        let c = Csat::new(t);
        let c3 = [
            Csat3::new(t, TableWrap::Mod),
            Csat3::new(t, TableWrap::Clamp),
        ];
        let step = (256 / N) as i32;
        let mut fs: Vec<i32> = (0..(65536 / step)).map(|k| k * step).collect();
        // Clamp: f outside [0, 1], and f = 1 exactly.
        fs.extend([65536, 65536 + 77, -1, -65536, i32::MIN, i32::MAX]);
        // The table coordinates of those f under either wrap (check_point tries both wraps).
        let mut xs: Vec<u32> = fs
            .iter()
            .flat_map(|&f| {
                [TableWrap::Mod, TableWrap::Clamp]
                    .map(|w| t.coord(I16F16::from_bits(f), w).to_bits())
            })
            .collect();
        xs.sort_unstable();
        xs.dedup();
        assert!(xs.len() > 256 * N); // every 1/256 position of [0, N], plus a few odd ones
        let wmax = (N as u32) * 256 + 2;
        for &x in &xs {
            for m in 0..=wmax {
                check_point(t, &c, &c3, x, m * 256);
                check_point(t, &c, &c3, x, m * 256 + 129);
            }
        }
    }

    #[test]
    fn exhaustive_n2() {
        for seed in 0..4 {
            exhaustive(&lcg_table::<2>(seed));
        }
        exhaustive(&ColorTable::<2>::solid(Rgba8888::new(255, 255, 255, 255)).unwrap());
    }

    #[test]
    fn exhaustive_n4() {
        for seed in 0..3 {
            exhaustive(&lcg_table::<4>(seed));
        }
    }

    #[test]
    fn exhaustive_n8() {
        exhaustive(&lcg_table::<8>(11));
        exhaustive(&ColorTable::<8>::zebra().unwrap());
    }

    #[test]
    fn exhaustive_n16() {
        exhaustive(&lcg_table::<16>(5));
    }

    #[test]
    fn extreme_inputs() {
        fn go<const N: usize>() {
            let t = lcg_table::<N>(3);
            let c = Csat::new(&t);
            let c3 = [
                Csat3::new(&t, TableWrap::Mod),
                Csat3::new(&t, TableWrap::Clamp),
            ];
            for x in [
                0,
                1,
                127,
                128,
                0x8000,
                (N as u32) << 16,
                u32::MAX,
                u32::MAX - 0x80,
            ] {
                for w in [
                    0,
                    1,
                    255,
                    256,
                    257,
                    ((N as u32) << 16) - 1,
                    (N as u32) << 16,
                    u32::MAX,
                ] {
                    check_point(&t, &c, &c3, x, w);
                }
            }
            assert_eq!(
                c.box_filter(U16F16::MAX, U16F16::MAX, TableWrap::Mod),
                t.mean()
            );
        }
        go::<2>();
        go::<256>();
        go::<512>();
        go::<1024>();
    }

    #[test]
    fn worst_case_lanes_large_tables() {
        // All channels 255: every window sum is as large as it gets; N > 256 needs the piece split.
        fn go<const N: usize>() {
            let t = ColorTable::<N>::solid(Rgba8888::new(255, 255, 255, 255)).unwrap();
            let c = Csat::new(&t);
            let c3 = [
                Csat3::new(&t, TableWrap::Mod),
                Csat3::new(&t, TableWrap::Clamp),
            ];
            for w in (0..=(N as u32) << 16).step_by(4093) {
                for x in [
                    0u32,
                    0x8000,
                    (N as u32) << 15,
                    ((N as u32) << 16) - 1,
                    (N as u32) << 16,
                ] {
                    check_point(&t, &c, &c3, x, w);
                    assert_eq!(
                        c.box_filter(U16F16::from_bits(x), U16F16::from_bits(w), TableWrap::Mod),
                        Rgba8888::new(255, 255, 255, 255)
                    );
                }
            }
            // Half white, half black: wide windows sum > 65535 in one lane for N > 256.
            let mut e = [Rgba8888::new(0, 0, 0, 0); N];
            for c in e.iter_mut().skip(N / 2) {
                *c = Rgba8888::new(255, 0, 255, 255);
            }
            let t = ColorTable::from_entries(e).unwrap();
            let c = Csat::new(&t);
            let c3 = [
                Csat3::new(&t, TableWrap::Mod),
                Csat3::new(&t, TableWrap::Clamp),
            ];
            for w in (0..=(N as u32) << 16).step_by(7919) {
                for x in (0..=(N as u32) << 16).step_by(N * 4099) {
                    check_point(&t, &c, &c3, x, w);
                }
            }
        }
        go::<256>();
        go::<512>();
        go::<1024>();
    }

    /// A `clamp` table's box centred past an end of the table: the end-extended table averaged
    /// over the window, by both layouts, exhaustively on a small table and at the far limits.
    #[test]
    fn clamp_boxes_centred_past_the_ends() {
        fn go<const N: usize>(seed: u64) {
            let t: ColorTable<N> = lcg_table(seed);
            let (c, c3) = (Csat::new(&t), Csat3::new(&t, TableWrap::Clamp));
            let full = (N as i64) << 16;
            let wstep = (N << 16) / 61 + 1;
            for w in (0..(N as u32) << 16)
                .step_by(wstep)
                .chain([1, 255, 256, 65535])
            {
                let fw = FilterWidth::from_bits(w);
                for x in (-2 * full..3 * full).step_by(full as usize / 97 + 1) {
                    let f = TexValue::from_bits((x >> N.trailing_zeros()) as i32);
                    let xb = clamp_box_x(f, fw, N.trailing_zeros());
                    let want = reference_at(t.entries(), i64::from(xb), w, TableWrap::Clamp);
                    assert_eq!(c.box_filter_clamp_at(xb, fw), want, "N {N} x {xb} w {w}");
                    assert_eq!(c3.box_filter_at(xb, fw), want, "N {N} x {xb} w {w}");
                    // The limit changes no colour: the box at the unlimited `f N`.
                    let xr = i64::from(f.to_bits()) << N.trailing_zeros();
                    let exact = reference_at(t.entries(), xr, w, TableWrap::Clamp);
                    assert_eq!(want, exact, "N {N} x {x} w {w}");
                }
            }
            for x in [i32::MIN, i32::MAX, 0, (full as i32)] {
                let fw = FilterWidth::from_bits(3 << 16);
                let _ = (c.box_filter_clamp_at(x, fw), c3.box_filter_at(x, fw));
            }
        }
        go::<4>(3);
        go::<16>(5);
        go::<256>(7);
    }

    #[test]
    fn zebra_full_period_is_mean() {
        let t = ColorTable::<256>::zebra().unwrap();
        let c = Csat::new(&t);
        // A window of exactly N entries (just below w = N) over a mod table is the exact mean.
        let w = U16F16::from_bits((256 << 16) - 1);
        for x in (0..256u32 << 16).step_by(65536 + 331) {
            let got = c.box_filter(U16F16::from_bits(x), w, TableWrap::Mod);
            assert!(got.r == 127 || got.r == 128, "{got:?}");
        }
        assert_eq!(
            c.box_filter(U16F16::ZERO, U16F16::from_num(256), TableWrap::Mod),
            t.mean()
        );
    }

    #[test]
    fn memory_sizes() {
        assert_eq!(Csat::<256>::BYTES, 256 * 8 + 16);
        assert_eq!(Csat3::<256>::BYTES, 3 * 256 * 8 + 16);
        const { assert!(Csat::<256>::BYTES + 4 * 256 < 4096) };
    }

    fn table_strategy<const N: usize>() -> impl Strategy<Value = ColorTable<N>> {
        prop::collection::vec(any::<u32>(), N).prop_map(|v| {
            ColorTable::from_entries(core::array::from_fn(|j| Rgba8888::from_u32(v[j]))).unwrap()
        })
    }

    fn width_strategy(n: u32) -> impl Strategy<Value = u32> {
        prop_oneof![
            8 => 0u32..(n << 16),
            1 => (n << 16) - 512..(n << 16) + 512,
            1 => any::<u32>(),
        ]
    }

    fn prop_check<const N: usize>(t: &ColorTable<N>, points: &[(i32, u32)]) {
        let c = Csat::new(t);
        let c3 = [
            Csat3::new(t, TableWrap::Mod),
            Csat3::new(t, TableWrap::Clamp),
        ];
        for &(f, w) in points {
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                let x = t.coord(I16F16::from_bits(f), wrap).to_bits();
                check_point(t, &c, &c3, x, w);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        #[test]
        fn random_tables_256(
            t in table_strategy::<256>(),
            points in prop::collection::vec(
                (prop_oneof![4 => -0x2_0000i32..0x3_0000, 1 => any::<i32>()], width_strategy(256)),
                200,
            ),
        ) {
            prop_check(&t, &points);
        }

        #[test]
        fn random_tables_1024(
            t in table_strategy::<1024>(),
            points in prop::collection::vec(
                (prop_oneof![4 => -0x2_0000i32..0x3_0000, 1 => any::<i32>()], width_strategy(1024)),
                100,
            ),
        ) {
            prop_check(&t, &points);
        }
    }
}
