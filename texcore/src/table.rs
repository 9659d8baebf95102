//! Colour tables: `N` [`Rgba8888`] entries (`N` a power of two, 2 to 1024) built from key colours and
//! looked up by the texture value `f` (`docs/model.md` section 7).
//!
//! Guarantees:
//! - `N` is checked once, when a [`ColorTable`] is built ([`TableError::InvalidSize`] otherwise);
//!   a `ColorTable<N>` value therefore always has a valid `N`, and every look-up is total: indices
//!   are masked (`& (N - 1)`, `mod`) or clamped (`min(.., N - 1)`, `clamp`) so no input, including
//!   `f = I16F16::MIN / MAX` and any `TableCoord`, can index out of bounds or panic.
//! - No floating point in any look-up or in the `const fn` builders; only
//!   [`ColorTable::from_keys_f64`] (a host convenience) takes `f64`, and it converts the key positions
//!   to fixed point (round to nearest) before the integer builder runs, so its entries are
//!   deterministic.
//! - Builders are `const fn` (except the `f64` one): tables can be evaluated at compile time and
//!   placed in flash.
//!
//! Table coordinates ([`ColorTable::coord`]): `g = f mod 1` (raw `f & 0xFFFF`) for
//! [`TableWrap::Mod`], `clamp(f, 0, 1)` (raw 0..=65536) for [`TableWrap::Clamp`]; `x = g * N`
//! (`TableCoord`, raw `g << log2 N`, so `x` is in `[0, N]`). Nearest picks entry `floor(x)`, linear
//! interpolates between entry centres with an 8-bit weight; both are defined bit-exactly in the
//! model.

use crate::color::Rgba8888;
use crate::format::{TableCoord, TexValue};

/// Smallest supported table size.
pub const MIN_ENTRIES: usize = 2;
/// Largest supported table size.
pub const MAX_ENTRIES: usize = 1024;

/// How `f` outside `[0, 1)` maps into the table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableWrap {
    /// `f mod 1`: the table repeats (wood rings, marble veins).
    #[default]
    Mod,
    /// `clamp(f, 0, 1)`: the end entries extend (clouds, fire).
    Clamp,
}

/// How a table coordinate selects a colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableLookup {
    /// Entry `floor(x)`.
    #[default]
    Nearest,
    /// Linear interpolation between entry centres (8-bit weight).
    Linear,
}

/// How key positions given to [`ColorTable::from_keys_spaced`] are placed in the table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum KeySpacing {
    /// A key given for value `c` sits at `c`.
    #[default]
    Linear,
    /// A key given for value `c` sits at `c^2` (Miné & Neyret): a texture whose `f` is a squared
    /// distance (wood: `f = x^2 + z^2`) then shows the colours at the unsquared distance, without
    /// a square root per pixel. Computed exactly (no rounding of `c^2`).
    Squared,
}

/// Why a colour table (or a colour stage built on it) could not be built.
///
/// `Display` renders a short English sentence for each variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableError {
    /// The table size `n` is not a power of two in `2..=1024`.
    InvalidSize {
        /// The rejected size.
        n: usize,
    },
    /// No key colours were given.
    NoKeys,
    /// Key `index` has a position outside `[0, 1]` (or not a finite number).
    KeyOutOfRange {
        /// Index of the offending key.
        index: usize,
    },
    /// Key `index` has a smaller position than key `index - 1` (positions must not decrease).
    KeysOutOfOrder {
        /// Index of the offending key.
        index: usize,
    },
    /// The requested antialiasing filter was not compiled in (features `csat` / `mip`).
    FilterDisabled,
}

impl core::fmt::Display for TableError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            TableError::InvalidSize { n } => write!(
                f,
                "colour table size {n} is not a power of two in {MIN_ENTRIES}..={MAX_ENTRIES}"
            ),
            TableError::NoKeys => f.write_str("no key colours given"),
            TableError::KeyOutOfRange { index } => {
                write!(f, "key {index} has a position outside [0, 1]")
            }
            TableError::KeysOutOfOrder { index } => {
                write!(f, "key {index} is placed before the key preceding it")
            }
            TableError::FilterDisabled => {
                f.write_str("the requested antialiasing filter is not compiled in")
            }
        }
    }
}

impl core::error::Error for TableError {}

/// Checks a table size: `Ok(log2 n)` if `n` is a power of two in `2..=1024`.
pub const fn check_size(n: usize) -> Result<u32, TableError> {
    if n >= MIN_ENTRIES && n <= MAX_ENTRIES && n.is_power_of_two() {
        Ok(n.trailing_zeros())
    } else {
        Err(TableError::InvalidSize { n })
    }
}

/// Per-channel `(a * (256 - t) + b * t + 128) >> 8` for `t` in 0..=256 (the model's 8-bit lerp).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(crate) const fn lerp8(a: Rgba8888, b: Rgba8888, t: u32) -> Rgba8888 {
    let t = if t > 256 { 256 } else { t };
    let s = 256 - t;
    Rgba8888::new(
        ((a.r as u32 * s + b.r as u32 * t + 128) >> 8) as u8,
        ((a.g as u32 * s + b.g as u32 * t + 128) >> 8) as u8,
        ((a.b as u32 * s + b.b as u32 * t + 128) >> 8) as u8,
        ((a.a as u32 * s + b.a as u32 * t + 128) >> 8) as u8,
    )
}

/// Nearest and linear look-up in a power-of-two array of `len = 1 << log2` colours (`len <=
/// entries.len()`), shared by the table and the MIP levels. `x` is in entries of this array.
#[inline]
pub(crate) const fn lookup_in(
    entries: &[Rgba8888],
    log2: u32,
    x: u32,
    wrap: TableWrap,
    mode: TableLookup,
) -> Rgba8888 {
    let last = (1usize << log2) - 1;
    match mode {
        TableLookup::Nearest => {
            let j = (x >> 16) as usize;
            let j = match wrap {
                TableWrap::Mod => j & last,
                TableWrap::Clamp => min_usize(j, last),
            };
            get_or_black(entries, j)
        }
        TableLookup::Linear => {
            let y = x as i64 - 32768;
            let j = y >> 16;
            let t = ((y >> 8) & 255) as u32;
            let (j0, j1) = match wrap {
                TableWrap::Mod => ((j & last as i64) as usize, ((j + 1) & last as i64) as usize),
                TableWrap::Clamp => (clamp_index(j, last), clamp_index(j + 1, last)),
            };
            lerp8(get_or_black(entries, j0), get_or_black(entries, j1), t)
        }
    }
}

#[cfg_attr(not(texcore_lean), inline(always))]
const fn min_usize(a: usize, b: usize) -> usize {
    if a < b {
        a
    } else {
        b
    }
}

#[cfg_attr(not(texcore_lean), inline(always))]
const fn clamp_index(j: i64, last: usize) -> usize {
    if j < 0 {
        0
    } else if j > last as i64 {
        last
    } else {
        j as usize
    }
}

/// `entries[j]`, or black if `j` is out of range (never happens for the masked / clamped indices
/// used here; this keeps the look-ups panic-free by construction).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(crate) const fn get_or_black(entries: &[Rgba8888], j: usize) -> Rgba8888 {
    if j < entries.len() {
        entries[j]
    } else {
        Rgba8888::BLACK
    }
}

/// A colour table of `N` entries (`N` a power of two in `2..=1024`); entry `j` covers table
/// coordinates `[j, j + 1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ColorTable<const N: usize> {
    entries: [Rgba8888; N],
}

impl<const N: usize> ColorTable<N> {
    /// Number of entries.
    pub const LEN: usize = N;
    /// `log2 N` (meaningful for the valid sizes only, which are the only ones that build).
    pub const LOG2: u32 = N.trailing_zeros();

    /// A table with the given entries.
    pub const fn from_entries(entries: [Rgba8888; N]) -> Result<Self, TableError> {
        match check_size(N) {
            Ok(_) => Ok(ColorTable { entries }),
            Err(e) => Err(e),
        }
    }

    /// A table with every entry `colour`.
    pub const fn solid(colour: Rgba8888) -> Result<Self, TableError> {
        Self::from_entries([colour; N])
    }

    /// The "zebra" map of the zone-plate test (Hart et al. 1999, fig. 8): entries `0 .. N/2 - 1`
    /// white, the rest black (for `N = 256`: 0..=127 white, 128..=255 black).
    pub const fn zebra() -> Result<Self, TableError> {
        let mut entries = [Rgba8888::BLACK; N];
        let mut j = 0;
        while j < N / 2 {
            entries[j] = Rgba8888::WHITE;
            j += 1;
        }
        Self::from_entries(entries)
    }

    /// A table interpolated linearly between key colours; see [`ColorTable::from_keys_spaced`].
    pub const fn from_keys(keys: &[(TexValue, Rgba8888)]) -> Result<Self, TableError> {
        Self::from_keys_spaced(keys, KeySpacing::Linear)
    }

    /// A table interpolated linearly between key colours.
    ///
    /// `keys` are `(position, colour)` with positions in `[0, 1]` (raw 0..=65536), not decreasing.
    /// With [`KeySpacing::Squared`] a key given at `c` is placed at `c^2`. Entry `j` takes the
    /// colour at its centre `p = (j + 1/2) / N`: the first key's colour before the first key, the
    /// last key's colour from the last key on, and between consecutive keys `k`, `k+1` with
    /// `pos_k <= p < pos_{k+1}` the linear interpolation, rounded half up per channel from the
    /// exact rational value (i64). Equal positions make a hard edge (the later key wins from that
    /// position on).
    pub const fn from_keys_spaced(
        keys: &[(TexValue, Rgba8888)],
        spacing: KeySpacing,
    ) -> Result<Self, TableError> {
        if let Err(e) = check_size(N) {
            return Err(e);
        }
        if keys.is_empty() {
            return Err(TableError::NoKeys);
        }
        let mut i = 0;
        while i < keys.len() {
            let p = keys[i].0.to_bits();
            if p < 0 || p > 0x1_0000 {
                return Err(TableError::KeyOutOfRange { index: i });
            }
            if i > 0 && p < keys[i - 1].0.to_bits() {
                return Err(TableError::KeysOutOfOrder { index: i });
            }
            i += 1;
        }
        // Positions in units of 2^-32 / (2N): entry centre j is (2j + 1) << 32.
        let two_n = 2 * N as i64;
        let mut entries = [Rgba8888::BLACK; N];
        let last = keys.len() - 1;
        let mut k = 0;
        let mut j = 0;
        while j < N {
            let p = (2 * j as i64 + 1) << 32;
            while k < last && key_pos(keys[k + 1].0, spacing) * two_n <= p {
                k += 1;
            }
            // k <= last always; `min` lets the compiler see it (no bounds-check panic path).
            let k = if k < last { k } else { last };
            let pk = key_pos(keys[k].0, spacing) * two_n;
            entries[j] = if pk > p {
                keys[0].1
            } else if k == last {
                keys[last].1
            } else {
                // k < last here, so k + 1 < keys.len(); the test lets the compiler see it (no
                // bounds-check panic path).
                let k1 = if k + 1 < keys.len() { k + 1 } else { last };
                let d = key_pos(keys[k1].0, spacing) * two_n - pk; // > 0: pos_{k+1} > p >= pos_k
                let t = p - pk;
                let (a, b) = (keys[k].1, keys[k1].1);
                Rgba8888::new(
                    lerp_exact(a.r, b.r, t, d),
                    lerp_exact(a.g, b.g, t, d),
                    lerp_exact(a.b, b.b, t, d),
                    lerp_exact(a.a, b.a, t, d),
                )
            };
            j += 1;
        }
        Ok(ColorTable { entries })
    }

    /// Host convenience: [`ColorTable::from_keys_spaced`] with `f64` positions, each converted to
    /// fixed point first (round to nearest; NaN or outside `[0, 1]` is
    /// [`TableError::KeyOutOfRange`]). At most 64 keys. The entries are computed by the integer
    /// builder, so they are deterministic.
    pub fn from_keys_f64(
        keys: &[(f64, Rgba8888)],
        spacing: KeySpacing,
    ) -> Result<Self, TableError> {
        let mut fixed_keys = [(TexValue::ZERO, Rgba8888::BLACK); 64];
        if keys.len() > fixed_keys.len() {
            return Err(TableError::KeyOutOfRange {
                index: fixed_keys.len(),
            });
        }
        for (i, (slot, &(p, c))) in fixed_keys.iter_mut().zip(keys).enumerate() {
            match TexValue::checked_from_num(p) {
                Some(v) => *slot = (v, c),
                None => return Err(TableError::KeyOutOfRange { index: i }),
            }
        }
        Self::from_keys_spaced(&fixed_keys[..keys.len()], spacing)
    }

    /// The entries.
    pub const fn entries(&self) -> &[Rgba8888; N] {
        &self.entries
    }

    /// Entry `j`, or `None` if `j >= N`.
    pub const fn get(&self, j: usize) -> Option<Rgba8888> {
        if j < N {
            Some(self.entries[j])
        } else {
            None
        }
    }

    /// The table coordinate of `f` (model section 7): raw `(f & 0xFFFF) << log2 N` for `Mod`,
    /// `clamp(f, 0, 1) << log2 N` for `Clamp`. Always in `[0, N]` (`[0, N)` for `Mod`).
    pub const fn coord(&self, f: TexValue, wrap: TableWrap) -> TableCoord {
        let raw = f.to_bits();
        let g = match wrap {
            TableWrap::Mod => (raw & 0xFFFF) as u32,
            TableWrap::Clamp => {
                if raw < 0 {
                    0
                } else if raw > 0x1_0000 {
                    0x1_0000
                } else {
                    raw as u32
                }
            }
        };
        // g <= 2^16 and LOG2 <= 10 for every valid table: no overflow.
        TableCoord::from_bits(g << Self::LOG2)
    }

    /// Nearest look-up: entry `floor(x)`, wrapped (`& (N - 1)`) or clamped (`min(.., N - 1)`).
    /// Total for every `x`.
    pub const fn nearest(&self, x: TableCoord, wrap: TableWrap) -> Rgba8888 {
        lookup_in(
            &self.entries,
            Self::LOG2,
            x.to_bits(),
            wrap,
            TableLookup::Nearest,
        )
    }

    /// Linear look-up between entry centres: `y = x - 1/2`, `j = floor(y)`, `t = (y.raw >> 8) & 255`,
    /// `c = (c_j (256 - t) + c_{j+1} t + 128) >> 8` per channel, `j` and `j + 1` wrapped (`Mod`) or
    /// clamped to `[0, N - 1]` (`Clamp`). Total for every `x`.
    pub const fn linear(&self, x: TableCoord, wrap: TableWrap) -> Rgba8888 {
        lookup_in(
            &self.entries,
            Self::LOG2,
            x.to_bits(),
            wrap,
            TableLookup::Linear,
        )
    }

    /// [`ColorTable::nearest`] or [`ColorTable::linear`].
    pub const fn lookup(&self, x: TableCoord, wrap: TableWrap, mode: TableLookup) -> Rgba8888 {
        lookup_in(&self.entries, Self::LOG2, x.to_bits(), wrap, mode)
    }

    /// The unfiltered colour of `f`: `lookup(coord(f, wrap), wrap, mode)`.
    pub const fn shade(&self, f: TexValue, wrap: TableWrap, mode: TableLookup) -> Rgba8888 {
        self.lookup(self.coord(f, wrap), wrap, mode)
    }

    /// The table mean, `(sum + N/2) / N` per channel (exact, rounded half up).
    pub const fn mean(&self) -> Rgba8888 {
        let sums = self.channel_sums();
        let half = (N / 2) as u32;
        let n = N as u32;
        Rgba8888::new(
            ((sums[0] + half) / n) as u8,
            ((sums[1] + half) / n) as u8,
            ((sums[2] + half) / n) as u8,
            ((sums[3] + half) / n) as u8,
        )
    }

    /// Per-channel sums `[r, g, b, a]` of all entries (at most `255 * 1024`).
    pub const fn channel_sums(&self) -> [u32; 4] {
        let mut s = [0u32; 4];
        let mut j = 0;
        while j < N {
            let c = self.entries[j];
            s[0] += c.r as u32;
            s[1] += c.g as u32;
            s[2] += c.b as u32;
            s[3] += c.a as u32;
            j += 1;
        }
        s
    }
}

/// A key position (raw 0..=65536) in units of 2^-32: `c << 16` or `c^2`.
const fn key_pos(c: TexValue, spacing: KeySpacing) -> i64 {
    let c = c.to_bits() as i64;
    match spacing {
        KeySpacing::Linear => c << 16,
        KeySpacing::Squared => c * c,
    }
}

/// `round((a (d - t) + b t) / d)`, half up, for `0 <= t < d`, `d < 2^44`.
const fn lerp_exact(a: u8, b: u8, t: i64, d: i64) -> u8 {
    if d <= 0 {
        return a;
    }
    let num = a as i64 * (d - t) + b as i64 * t;
    ((2 * num + d) / (2 * d)) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixed::types::I16F16;

    fn tv(raw: i32) -> TexValue {
        TexValue::from_bits(raw)
    }

    fn grey(v: u8) -> Rgba8888 {
        Rgba8888::new(v, v, v, v)
    }

    fn ramp<const N: usize>() -> ColorTable<N> {
        let mut e = [Rgba8888::BLACK; N];
        for (j, c) in e.iter_mut().enumerate() {
            let v = (j * 255 / (N - 1)) as u8;
            *c = Rgba8888::new(v, 255 - v, (j * 37 % 256) as u8, 255);
        }
        ColorTable::from_entries(e).unwrap()
    }

    #[test]
    fn sizes_are_checked() {
        assert_eq!(check_size(2), Ok(1));
        assert_eq!(check_size(256), Ok(8));
        assert_eq!(check_size(1024), Ok(10));
        for n in [0usize, 1, 3, 6, 255, 257, 2048, usize::MAX] {
            assert_eq!(check_size(n), Err(TableError::InvalidSize { n }));
        }
        assert!(ColorTable::<3>::solid(Rgba8888::WHITE).is_err());
        assert!(ColorTable::<1>::zebra().is_err());
        assert!(ColorTable::<2048>::from_keys(&[(tv(0), Rgba8888::WHITE)]).is_err());
        assert!(ColorTable::<0>::from_entries([]).is_err());
        assert!(ColorTable::<1024>::solid(Rgba8888::WHITE).is_ok());
    }

    #[test]
    fn error_display() {
        extern crate std;
        use std::string::ToString;
        assert_eq!(
            TableError::InvalidSize { n: 3 }.to_string(),
            "colour table size 3 is not a power of two in 2..=1024"
        );
        assert!(TableError::KeysOutOfOrder { index: 2 }
            .to_string()
            .contains('2'));
    }

    #[test]
    fn const_construction() {
        const Z: ColorTable<256> = match ColorTable::zebra() {
            Ok(t) => t,
            Err(_) => panic!(),
        };
        assert_eq!(Z.entries()[127], Rgba8888::WHITE);
        assert_eq!(Z.entries()[128], Rgba8888::BLACK);
        assert_eq!(Z.mean(), Rgba8888::new(128, 128, 128, 255));
    }

    #[test]
    fn coord_mod_and_clamp() {
        let t = ColorTable::<256>::zebra().unwrap();
        assert_eq!(t.coord(tv(0), TableWrap::Mod).to_bits(), 0);
        assert_eq!(t.coord(tv(0x8000), TableWrap::Mod).to_bits(), 128 << 16);
        assert_eq!(t.coord(tv(0x1_0000), TableWrap::Mod).to_bits(), 0);
        assert_eq!(t.coord(tv(-1), TableWrap::Mod).to_bits(), 0xFFFF << 8);
        assert_eq!(t.coord(tv(0x1_0000), TableWrap::Clamp).to_bits(), 256 << 16);
        assert_eq!(t.coord(tv(-5), TableWrap::Clamp).to_bits(), 0);
        for f in [I16F16::MIN, I16F16::MAX, I16F16::DELTA, -I16F16::DELTA] {
            assert!(t.coord(f, TableWrap::Mod).to_bits() < 256 << 16);
            assert!(t.coord(f, TableWrap::Clamp).to_bits() <= 256 << 16);
        }
        assert_eq!(t.coord(I16F16::MAX, TableWrap::Clamp).to_bits(), 256 << 16);
        assert_eq!(t.coord(I16F16::MIN, TableWrap::Clamp).to_bits(), 0);
    }

    #[test]
    fn nearest_wraps_and_clamps() {
        let t = ramp::<8>();
        let e = *t.entries();
        let x = |v: u32| TableCoord::from_bits(v);
        assert_eq!(t.nearest(x(0), TableWrap::Mod), e[0]);
        assert_eq!(t.nearest(x((3 << 16) + 0xFFFF), TableWrap::Mod), e[3]);
        assert_eq!(t.nearest(x(8 << 16), TableWrap::Mod), e[0]);
        assert_eq!(t.nearest(x(8 << 16), TableWrap::Clamp), e[7]);
        assert_eq!(t.nearest(x(u32::MAX), TableWrap::Clamp), e[7]);
        assert_eq!(t.nearest(x(u32::MAX), TableWrap::Mod), e[7]);
        // Via f.
        assert_eq!(
            t.shade(tv(0x1_0000), TableWrap::Clamp, TableLookup::Nearest),
            e[7]
        );
        assert_eq!(
            t.shade(tv(0x1_0000), TableWrap::Mod, TableLookup::Nearest),
            e[0]
        );
        assert_eq!(t.shade(tv(-1), TableWrap::Mod, TableLookup::Nearest), e[7]);
    }

    #[test]
    fn linear_endpoints_and_wrap() {
        let e = [grey(0), grey(100), grey(200), grey(40)];
        let t = ColorTable::from_entries(e).unwrap();
        let x = |v: u32| TableCoord::from_bits(v);
        // Entry centres give the entries exactly.
        for j in 0..4u32 {
            let c = (j << 16) + 0x8000;
            assert_eq!(t.linear(x(c), TableWrap::Mod), e[j as usize]);
            assert_eq!(t.linear(x(c), TableWrap::Clamp), e[j as usize]);
        }
        // Half way between centres 0 and 1.
        assert_eq!(t.linear(x(1 << 16), TableWrap::Mod), grey(50));
        // Below the first centre: Mod blends with the last entry, Clamp holds the first.
        assert_eq!(t.linear(x(0), TableWrap::Mod), grey(20));
        assert_eq!(t.linear(x(0), TableWrap::Clamp), grey(0));
        // At x = N: Mod is x = 0 again, Clamp holds the last.
        assert_eq!(t.linear(x(4 << 16), TableWrap::Mod), grey(20));
        assert_eq!(t.linear(x(4 << 16), TableWrap::Clamp), grey(40));
        // Quarter step: t = 64.
        assert_eq!(
            t.linear(x(0x8000 + 0x4000), TableWrap::Clamp),
            grey(((100 * 64 + 128) >> 8) as u8) // 0 * 192 + 100 * 64
        );
        // Just below an entry centre: t = 255.
        assert_eq!(
            t.linear(x(0x1_8000 - 1), TableWrap::Clamp),
            grey(((100 * 255 + 128) >> 8) as u8) // 0 * 1 + 100 * 255
        );
        // Extreme coordinates never panic.
        for v in [0, 1, 0x7FFF, 0x8000, u32::MAX, u32::MAX - 0x8000] {
            let _ = t.linear(x(v), TableWrap::Mod);
            let _ = t.linear(x(v), TableWrap::Clamp);
        }
        assert_eq!(t.linear(x(u32::MAX), TableWrap::Clamp), grey(40));
        // Via f, the clamp ends.
        for f in [I16F16::MIN, I16F16::MAX] {
            for w in [TableWrap::Mod, TableWrap::Clamp] {
                let _ = t.shade(f, w, TableLookup::Linear);
            }
        }
        assert_eq!(
            t.shade(I16F16::MAX, TableWrap::Clamp, TableLookup::Linear),
            grey(40)
        );
        assert_eq!(
            t.shade(I16F16::MIN, TableWrap::Clamp, TableLookup::Linear),
            grey(0)
        );
    }

    #[test]
    fn linear_matches_formula_everywhere() {
        let t = ramp::<16>();
        let e = *t.entries();
        for raw in (0u32..=(16 << 16)).step_by(61) {
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                let y = raw as i64 - 0x8000;
                let j = y.div_euclid(0x1_0000);
                let tt = (y.rem_euclid(0x1_0000) >> 8) as u32;
                let (a, b) = match wrap {
                    TableWrap::Mod => (
                        e[j.rem_euclid(16) as usize],
                        e[(j + 1).rem_euclid(16) as usize],
                    ),
                    TableWrap::Clamp => {
                        (e[j.clamp(0, 15) as usize], e[(j + 1).clamp(0, 15) as usize])
                    }
                };
                let want =
                    |p: u8, q: u8| ((p as u32 * (256 - tt) + q as u32 * tt + 128) / 256) as u8;
                let w = Rgba8888::new(
                    want(a.r, b.r),
                    want(a.g, b.g),
                    want(a.b, b.b),
                    want(a.a, b.a),
                );
                assert_eq!(
                    t.linear(TableCoord::from_bits(raw), wrap),
                    w,
                    "{raw} {wrap:?}"
                );
            }
        }
    }

    #[test]
    fn keys_interpolate_over_entry_centres() {
        let keys = [(tv(0), grey(0)), (tv(0x1_0000), grey(255))];
        let t = ColorTable::<4>::from_keys(&keys).unwrap();
        // Centres 1/8, 3/8, 5/8, 7/8 -> 31.875, 95.625, 159.375, 223.125.
        assert_eq!(t.entries(), &[grey(32), grey(96), grey(159), grey(223)]);
        // A single key is a solid table.
        let s = ColorTable::<8>::from_keys(&[(tv(0x4000), grey(7))]).unwrap();
        assert_eq!(s, ColorTable::solid(grey(7)).unwrap());
        // Hard edge at 1/2, and colours held beyond the first / last key.
        let keys = [
            (tv(0x4000), grey(10)),
            (tv(0x8000), grey(10)),
            (tv(0x8000), grey(200)),
            (tv(0xC000), grey(200)),
        ];
        let t = ColorTable::<8>::from_keys(&keys).unwrap();
        assert_eq!(t.entries()[..4], [grey(10); 4]);
        assert_eq!(t.entries()[4..], [grey(200); 4]);
        // Rounding half up: centre 1/2 of [0, 1] between 0 and 1 -> 0.5 -> 1.
        let t =
            ColorTable::<2>::from_keys(&[(tv(0x4000), grey(0)), (tv(0xC000), grey(1))]).unwrap();
        assert_eq!(t.entries(), &[grey(0), grey(1)]);
        let t = ColorTable::<4>::from_keys(&[(tv(0), grey(0)), (tv(0x1_0000), grey(1))]).unwrap();
        assert_eq!(t.entries(), &[grey(0), grey(0), grey(1), grey(1)]);
    }

    #[test]
    fn keys_reference_random() {
        // Against an f64 evaluation of the same definition (exact enough: values are far from .5).
        let keys = [
            (tv(0x0800), Rgba8888::new(255, 0, 10, 255)),
            (tv(0x3000), Rgba8888::new(0, 255, 20, 128)),
            (tv(0x9123), Rgba8888::new(30, 40, 250, 0)),
            (tv(0xF000), Rgba8888::new(200, 100, 0, 255)),
        ];
        for spacing in [KeySpacing::Linear, KeySpacing::Squared] {
            let t = ColorTable::<64>::from_keys_spaced(&keys, spacing).unwrap();
            let pos = |k: usize| {
                let c = keys[k].0.to_bits() as f64 / 65536.0;
                match spacing {
                    KeySpacing::Linear => c,
                    KeySpacing::Squared => c * c,
                }
            };
            for j in 0..64 {
                let p = (j as f64 + 0.5) / 64.0;
                let want = if p < pos(0) {
                    keys[0].1.to_array().map(|v| v as f64)
                } else if p >= pos(3) {
                    keys[3].1.to_array().map(|v| v as f64)
                } else {
                    let k = (0..3).rev().find(|&k| pos(k) <= p).unwrap();
                    let s = (p - pos(k)) / (pos(k + 1) - pos(k));
                    let (a, b) = (keys[k].1.to_array(), keys[k + 1].1.to_array());
                    [0, 1, 2, 3].map(|i| a[i] as f64 + (b[i] as f64 - a[i] as f64) * s)
                };
                let got = t.entries()[j].to_array();
                for i in 0..4 {
                    assert!(
                        (got[i] as f64 - want[i]).abs() <= 0.5 + 1e-9,
                        "{spacing:?} {j} {i}"
                    );
                }
            }
        }
    }

    #[test]
    fn squared_positions_place_keys_at_c_squared() {
        // A key at c = 1/2 lands at 1/4: with N = 8 entries 0 and 1 (centres 1/16, 3/16) are before it.
        let keys = [(tv(0x8000), grey(100)), (tv(0x8000), grey(200))];
        let t = ColorTable::<8>::from_keys_spaced(&keys, KeySpacing::Squared).unwrap();
        assert_eq!(t.entries()[..2], [grey(100); 2]);
        assert_eq!(t.entries()[2..], [grey(200); 6]);
        let t = ColorTable::<8>::from_keys_spaced(&keys, KeySpacing::Linear).unwrap();
        assert_eq!(t.entries()[..4], [grey(100); 4]);
    }

    #[test]
    fn key_errors() {
        let c = Rgba8888::WHITE;
        assert_eq!(ColorTable::<4>::from_keys(&[]), Err(TableError::NoKeys));
        assert_eq!(
            ColorTable::<4>::from_keys(&[(tv(0), c), (tv(0x1_0001), c)]),
            Err(TableError::KeyOutOfRange { index: 1 })
        );
        assert_eq!(
            ColorTable::<4>::from_keys(&[(tv(-1), c)]),
            Err(TableError::KeyOutOfRange { index: 0 })
        );
        assert_eq!(
            ColorTable::<4>::from_keys(&[(tv(5), c), (tv(4), c)]),
            Err(TableError::KeysOutOfOrder { index: 1 })
        );
        assert_eq!(
            ColorTable::<4>::from_keys_f64(&[(0.0, c), (f64::NAN, c)], KeySpacing::Linear),
            Err(TableError::KeyOutOfRange { index: 1 })
        );
        assert_eq!(
            ColorTable::<4>::from_keys_f64(&[(1.5, c)], KeySpacing::Linear),
            Err(TableError::KeyOutOfRange { index: 0 })
        );
    }

    #[test]
    fn keys_f64_matches_fixed() {
        let a = Rgba8888::new(250, 230, 180, 255);
        let b = Rgba8888::new(120, 70, 30, 255);
        let t64 =
            ColorTable::<256>::from_keys_f64(&[(0.0, a), (0.6, b), (1.0, a)], KeySpacing::Squared)
                .unwrap();
        let tf = ColorTable::<256>::from_keys_spaced(
            &[(tv(0), a), (TexValue::from_num(0.6), b), (tv(0x1_0000), a)],
            KeySpacing::Squared,
        )
        .unwrap();
        assert_eq!(t64, tf);
    }

    #[test]
    fn zebra_solid_mean() {
        let z = ColorTable::<8>::zebra().unwrap();
        assert_eq!(z.entries()[..4], [Rgba8888::WHITE; 4]);
        assert_eq!(z.entries()[4..], [Rgba8888::BLACK; 4]);
        let s = ColorTable::<16>::solid(Rgba8888::new(1, 2, 3, 4)).unwrap();
        assert_eq!(s.mean(), Rgba8888::new(1, 2, 3, 4));
        let t = ColorTable::from_entries([grey(0), grey(1), grey(1), grey(1)]).unwrap();
        assert_eq!(t.mean(), grey(1)); // 0.75 -> 1
        let t = ColorTable::from_entries([grey(0), grey(0), grey(1), grey(1)]).unwrap();
        assert_eq!(t.mean(), grey(1)); // 0.5 -> 1 (half up)
        let t = ColorTable::from_entries([grey(0), grey(0), grey(0), grey(1)]).unwrap();
        assert_eq!(t.mean(), grey(0));
        assert_eq!(
            ColorTable::<1024>::solid(Rgba8888::WHITE).unwrap().mean(),
            Rgba8888::WHITE
        );
        assert_eq!(z.get(7), Some(Rgba8888::BLACK));
        assert_eq!(z.get(8), None);
    }
}
