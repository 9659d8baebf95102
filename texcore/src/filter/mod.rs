//! Colour-table antialiasing (Hart et al. 1999 section 3.3; `docs/model.md` sections 7 and 8):
//! the filter width from the gradient of `f` ([`width`]), the colour-table MIP map (`mip`,
//! feature `mip`) and the summed-area colour table in its two layouts (`csat`, feature `csat`),
//! combined with a colour table into a [`ColorStage`] that turns `(f, w)` into a colour.
//!
//! Guarantees:
//! - Every filter is integer-only, bit-exact with the model, and total: any `TexValue` (including
//!   `I16F16::MIN` / `MAX`) and any `FilterWidth` (0 to `U16F16::MAX`) gives a colour without
//!   panicking. Widths `>= N` give the table mean (csat) or the last MIP level.
//! - Construction is `const fn`: a whole stage, sums and levels included, can be computed at
//!   compile time and placed in flash.
//! - Memory is reported per filter by [`ColorStage::bytes_for`]; for `N = 256`: no filter 1024
//!   bytes, MIP 2048, csat 3088, three-times-long csat 7184 (plus 3 bytes of configuration).
//!   `size_of::<ColorStage<N>>()` is that of the largest filter compiled in (disable `csat` to drop
//!   the csat variants); for the smallest footprint with a fixed filter, use the parts
//!   (`csat::Csat`, `mip::ColorMip`) directly. The stage and the filter structures are `Clone`
//!   but deliberately not `Copy`, so a multi-kilobyte copy is never implicit.

#[cfg(feature = "csat")]
pub mod csat;
#[cfg(feature = "mip")]
pub mod mip;
#[cfg(feature = "ramp")]
pub mod ramp;
pub mod width;

#[cfg(feature = "csat")]
pub use csat::{Csat, Csat3};
#[cfg(feature = "mip")]
pub use mip::ColorMip;
#[cfg(feature = "ramp")]
pub use ramp::Ramp565;
pub use width::{filter_width, filter_width_spread, isqrt, GradientNorm, WidthSource, WidthStream};

use crate::color::Rgba8888;
use crate::format::{FilterWidth, TexValue};
use crate::table::{ColorTable, TableError, TableLookup, TableWrap};

/// Which colour-table antialiasing filter a [`ColorStage`] applies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Antialias {
    /// No filtering: the table's nearest / linear look-up, `w` ignored.
    #[default]
    None,
    /// Colour-table MIP map with blending between levels (feature `mip`).
    Mip,
    /// Summed-area colour table with run-time case analysis (feature `csat`).
    Csat,
    /// Three-times-long summed-area colour table, no case analysis (feature `csat`).
    Csat3,
    /// Pre-filtered RGB565 ramp (feature `ramp`): an approximation of the summed-area filter
    /// with one table read a pixel (the width rounded to a power of two, the colour to RGB565;
    /// [`ramp`]). Unlike the other filters the variant exists only with its feature: with it,
    /// the enum's matches (names, stage set-up) took 142 more bytes of `full`'s texcore code,
    /// past its budget.
    #[cfg(feature = "ramp")]
    Ramp,
}

impl Antialias {
    /// Whether this filter is compiled in.
    pub const fn is_available(self) -> bool {
        match self {
            Antialias::None => true,
            Antialias::Mip => cfg!(feature = "mip"),
            Antialias::Csat | Antialias::Csat3 => cfg!(feature = "csat"),
            #[cfg(feature = "ramp")]
            Antialias::Ramp => true,
        }
    }
}

// Sized for the largest filter compiled in, by design: no allocation to box a variant into
// (`docs/size.md` counts the instance at that size).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Filter<const N: usize> {
    None(ColorTable<N>),
    #[cfg(feature = "mip")]
    Mip(ColorMip<N>),
    #[cfg(feature = "csat")]
    Csat(ColorTable<N>, Csat<N>),
    #[cfg(feature = "csat")]
    Csat3(ColorTable<N>, Csat3<N>),
    #[cfg(feature = "ramp")]
    Ramp(ColorTable<N>, Ramp565<N>),
}

/// `0 <= f <= 1`: a `clamp` table's box is centred on the clamped coordinate only there
/// (outside, on the unclamped one: [`csat::clamp_box_x`]).
#[cfg(feature = "csat")]
#[cfg_attr(not(texcore_lean), inline(always))]
const fn in_unit(f: TexValue) -> bool {
    let raw = f.to_bits();
    raw >= 0 && raw <= 1 << 16
}

/// `log2 N` of a power-of-two table size.
#[cfg(feature = "csat")]
#[cfg_attr(not(texcore_lean), inline(always))]
const fn t_log2<const N: usize>() -> u32 {
    N.trailing_zeros()
}

/// The colour stage of the pixel path: a colour table with its wrap, look-up mode and
/// antialiasing filter, holding exactly the data that filter needs (the table; the table and its
/// MIP levels; the table and its prefix sums; the table and its three-times-long prefix sums).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ColorStage<const N: usize> {
    filter: Filter<N>,
    wrap: TableWrap,
    lookup: TableLookup,
}

impl<const N: usize> ColorStage<N> {
    /// Builds the stage, precomputing what `antialias` needs.
    /// [`TableError::FilterDisabled`] if that filter is not compiled in.
    pub const fn new(
        table: ColorTable<N>,
        wrap: TableWrap,
        lookup: TableLookup,
        antialias: Antialias,
    ) -> Result<Self, TableError> {
        let filter = match antialias {
            Antialias::None => Filter::None(table),
            #[cfg(feature = "mip")]
            Antialias::Mip => Filter::Mip(ColorMip::new(table)),
            #[cfg(feature = "csat")]
            Antialias::Csat => Filter::Csat(table, Csat::new(&table)),
            #[cfg(feature = "csat")]
            Antialias::Csat3 => Filter::Csat3(table, Csat3::new(&table, wrap)),
            #[cfg(feature = "ramp")]
            Antialias::Ramp => Filter::Ramp(table, Ramp565::new(&table, wrap)),
            #[allow(unreachable_patterns)]
            _ => return Err(TableError::FilterDisabled),
        };
        Ok(ColorStage {
            filter,
            wrap,
            lookup,
        })
    }

    /// The filter this stage applies.
    pub const fn antialias(&self) -> Antialias {
        match self.filter {
            Filter::None(_) => Antialias::None,
            #[cfg(feature = "mip")]
            Filter::Mip(_) => Antialias::Mip,
            #[cfg(feature = "csat")]
            Filter::Csat(..) => Antialias::Csat,
            #[cfg(feature = "csat")]
            Filter::Csat3(..) => Antialias::Csat3,
            #[cfg(feature = "ramp")]
            Filter::Ramp(..) => Antialias::Ramp,
        }
    }

    /// The colour table.
    pub const fn table(&self) -> &ColorTable<N> {
        match &self.filter {
            Filter::None(t) => t,
            #[cfg(feature = "mip")]
            Filter::Mip(m) => m.table(),
            #[cfg(feature = "csat")]
            Filter::Csat(t, _) => t,
            #[cfg(feature = "csat")]
            Filter::Csat3(t, _) => t,
            #[cfg(feature = "ramp")]
            Filter::Ramp(t, _) => t,
        }
    }

    /// How `f` maps into the table.
    pub const fn wrap(&self) -> TableWrap {
        self.wrap
    }

    /// The table's look-up mode (used unfiltered and by the MIP levels; the box filters integrate
    /// the piecewise-constant table, as the model defines).
    pub const fn lookup(&self) -> TableLookup {
        self.lookup
    }

    /// The colour of `f` box-filtered over width `w` (in table entries) by the stage's filter.
    /// With [`Antialias::None`], `w` is ignored.
    #[cfg_attr(not(any(feature = "csat", feature = "mip")), allow(unused_variables))]
    pub fn shade(&self, f: TexValue, w: FilterWidth) -> Rgba8888 {
        match &self.filter {
            Filter::None(t) => t.shade(f, self.wrap, self.lookup),
            #[cfg(feature = "mip")]
            Filter::Mip(m) => m.lookup(m.table().coord(f, self.wrap), w, self.wrap, self.lookup),
            #[cfg(feature = "csat")]
            Filter::Csat(t, c) => {
                if self.wrap == TableWrap::Clamp && !in_unit(f) {
                    c.box_filter_clamp_at(csat::clamp_box_x(f, w, t_log2::<N>()), w)
                } else {
                    c.box_filter_in(t.entries(), t.coord(f, self.wrap), w, self.wrap)
                }
            }
            #[cfg(feature = "csat")]
            Filter::Csat3(t, c) => {
                if self.wrap == TableWrap::Clamp && !in_unit(f) {
                    c.box_filter_at(csat::clamp_box_x(f, w, t_log2::<N>()), w)
                } else {
                    c.box_filter(t.coord(f, self.wrap), w)
                }
            }
            #[cfg(feature = "ramp")]
            Filter::Ramp(t, r) => r.lookup(t.coord(f, self.wrap), w).to_rgba8888(),
        }
    }

    /// [`ColorStage::shade`] of each pair `(f[i], w[i])` in order, handed to `emit`: the same
    /// colours, with the filter (and for csat the wrap) chosen once for the whole run instead of
    /// per pixel. Stops at the shorter slice.
    #[cfg_attr(not(any(feature = "csat", feature = "mip")), allow(unused_variables))]
    #[inline]
    pub fn shade_each<F: FnMut(Rgba8888)>(&self, f: &[TexValue], w: &[FilterWidth], emit: F) {
        // The size-lean shape keeps one copy of the per-filter code: `shade` per pair.
        #[cfg(texcore_lean)]
        {
            let mut emit = emit;
            for (&f, &w) in f.iter().zip(w) {
                emit(self.shade(f, w));
            }
        }
        #[cfg(not(texcore_lean))]
        self.shade_each_fast(f, w, emit);
    }

    /// [`ColorStage::shade_each`] with the filter chosen once for the run (the fast shape).
    #[cfg(not(texcore_lean))]
    #[cfg_attr(not(any(feature = "csat", feature = "mip")), allow(unused_variables))]
    #[inline]
    fn shade_each_fast<F: FnMut(Rgba8888)>(&self, f: &[TexValue], w: &[FilterWidth], mut emit: F) {
        let pairs = f.iter().zip(w);
        let (wrap, lookup) = (self.wrap, self.lookup);
        match &self.filter {
            Filter::None(t) => {
                for (&f, _) in pairs {
                    emit(t.shade(f, wrap, lookup));
                }
            }
            #[cfg(feature = "mip")]
            Filter::Mip(m) => {
                for (&f, &w) in pairs {
                    emit(m.lookup(m.table().coord(f, wrap), w, wrap, lookup));
                }
            }
            #[cfg(feature = "csat")]
            Filter::Csat(t, c) => match wrap {
                TableWrap::Mod => {
                    for (&f, &w) in pairs {
                        let x = t.coord(f, TableWrap::Mod);
                        emit(c.box_filter_in(t.entries(), x, w, TableWrap::Mod));
                    }
                }
                TableWrap::Clamp => {
                    for (&f, &w) in pairs {
                        if in_unit(f) {
                            let x = t.coord(f, TableWrap::Clamp);
                            emit(c.box_filter_in(t.entries(), x, w, TableWrap::Clamp));
                        } else {
                            let x = csat::clamp_box_x(f, w, t_log2::<N>());
                            emit(c.box_filter_clamp_at(x, w));
                        }
                    }
                }
            },
            #[cfg(feature = "csat")]
            Filter::Csat3(t, c) => {
                for (&f, &w) in pairs {
                    if wrap == TableWrap::Clamp && !in_unit(f) {
                        emit(c.box_filter_at(csat::clamp_box_x(f, w, t_log2::<N>()), w));
                    } else {
                        emit(c.box_filter(t.coord(f, wrap), w));
                    }
                }
            }
            #[cfg(feature = "ramp")]
            Filter::Ramp(t, r) => {
                for (&f, &w) in pairs {
                    emit(r.lookup(t.coord(f, wrap), w).to_rgba8888());
                }
            }
        }
    }

    /// [`ColorStage::shade`] reduced to RGB565: the ramp's sample itself with `Antialias::Ramp`
    /// (which `shade` expands exactly), `shade(f, w).to_rgb565()` with every other filter.
    pub fn shade565(&self, f: TexValue, w: FilterWidth) -> crate::color::Rgb565 {
        match &self.filter {
            #[cfg(feature = "ramp")]
            Filter::Ramp(t, r) => r.lookup(t.coord(f, self.wrap), w),
            _ => self.shade(f, w).to_rgb565(),
        }
    }

    /// The table and ramp of a stage with [`Antialias::Ramp`].
    #[cfg(feature = "ramp")]
    pub(crate) const fn ramp(&self) -> Option<(&ColorTable<N>, &Ramp565<N>)> {
        match &self.filter {
            Filter::Ramp(t, r) => Some((t, r)),
            _ => None,
        }
    }

    /// The colour of `f` without filtering (the table's nearest / linear look-up).
    pub fn shade_unfiltered(&self, f: TexValue) -> Rgba8888 {
        self.table().shade(f, self.wrap, self.lookup)
    }

    /// Bytes of table, levels and sums held by a stage with filter `antialias` (0 if it is not
    /// compiled in). Configuration (wrap, look-up mode, variant tag) adds 3 bytes.
    pub const fn bytes_for(antialias: Antialias) -> usize {
        let table = core::mem::size_of::<ColorTable<N>>();
        match antialias {
            Antialias::None => table,
            #[cfg(feature = "mip")]
            Antialias::Mip => ColorMip::<N>::BYTES,
            #[cfg(feature = "csat")]
            Antialias::Csat => table + Csat::<N>::BYTES,
            #[cfg(feature = "csat")]
            Antialias::Csat3 => table + Csat3::<N>::BYTES,
            #[cfg(feature = "ramp")]
            Antialias::Ramp => table + Ramp565::<N>::BYTES,
            #[allow(unreachable_patterns)]
            _ => 0,
        }
    }

    /// Bytes of table, levels and sums this stage's filter uses ([`ColorStage::bytes_for`]).
    pub const fn memory_bytes(&self) -> usize {
        Self::bytes_for(self.antialias())
    }
}

#[cfg(all(test, feature = "csat", feature = "mip"))]
mod tests {
    use super::*;
    use crate::table::ColorTable;
    use fixed::types::{I16F16, U16F16};

    const ALL: [Antialias; 4] = [
        Antialias::None,
        Antialias::Mip,
        Antialias::Csat,
        Antialias::Csat3,
    ];

    use crate::test_rng::lcg_table;

    #[test]
    fn memory_report() {
        assert_eq!(ColorStage::<256>::bytes_for(Antialias::None), 1024);
        assert_eq!(ColorStage::<256>::bytes_for(Antialias::Mip), 2048);
        assert_eq!(ColorStage::<256>::bytes_for(Antialias::Csat), 1024 + 2064);
        assert_eq!(ColorStage::<256>::bytes_for(Antialias::Csat3), 1024 + 6160);
        assert!(ColorStage::<256>::bytes_for(Antialias::Csat) < 3200);
        let t = ColorTable::<256>::zebra().unwrap();
        for aa in ALL {
            let s = ColorStage::new(t, TableWrap::Mod, TableLookup::Nearest, aa).unwrap();
            assert_eq!(s.antialias(), aa);
            assert_eq!(s.memory_bytes(), ColorStage::<256>::bytes_for(aa));
            assert!(core::mem::size_of::<ColorStage<256>>() >= s.memory_bytes());
            assert!(aa.is_available());
        }
    }

    #[test]
    fn const_stage() {
        const STAGE: ColorStage<64> = match ColorTable::zebra() {
            Ok(t) => {
                match ColorStage::new(t, TableWrap::Mod, TableLookup::Nearest, Antialias::Csat3) {
                    Ok(s) => s,
                    Err(_) => panic!(),
                }
            }
            Err(_) => panic!(),
        };
        assert_eq!(STAGE.shade(I16F16::ZERO, U16F16::ZERO), Rgba8888::WHITE);
        assert_eq!(
            STAGE.shade(I16F16::ZERO, U16F16::from_num(64)),
            STAGE.table().mean()
        );
    }

    #[test]
    fn stages_agree_with_their_parts() {
        let t = lcg_table::<32>(77);
        for wrap in [TableWrap::Mod, TableWrap::Clamp] {
            for lookup in [TableLookup::Nearest, TableLookup::Linear] {
                let st = ALL.map(|aa| ColorStage::new(t, wrap, lookup, aa).unwrap());
                let mip = ColorMip::new(t);
                let csat = Csat::new(&t);
                for f in (-0x1_8000i32..0x2_8000).step_by(313) {
                    let f = I16F16::from_bits(f);
                    let x = t.coord(f, wrap);
                    for w in (0u32..(40 << 16)).step_by(65_537 + 4096) {
                        let w = U16F16::from_bits(w);
                        let plain = t.shade(f, wrap, lookup);
                        assert_eq!(st[0].shade(f, w), plain);
                        assert_eq!(st[1].shade(f, w), mip.lookup(x, w, wrap, lookup));
                        // A clamp table's box past an end is centred on the unclamped `f N`.
                        let b = if wrap == TableWrap::Clamp && !in_unit(f) {
                            csat.box_filter_clamp_at(csat::clamp_box_x(f, w, 5), w)
                        } else {
                            csat.box_filter(x, w, wrap)
                        };
                        assert_eq!(st[2].shade(f, w), b);
                        assert_eq!(st[3].shade(f, w), b);
                        for s in &st {
                            assert_eq!(s.shade_unfiltered(f), plain);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn zero_width_is_nearest_and_huge_width_is_mean() {
        let t = lcg_table::<128>(5);
        for wrap in [TableWrap::Mod, TableWrap::Clamp] {
            let st = ALL.map(|aa| ColorStage::new(t, wrap, TableLookup::Nearest, aa).unwrap());
            for f in (i32::MIN..=i32::MAX).step_by(99_991) {
                let f = I16F16::from_bits(f);
                let near = t.shade(f, wrap, TableLookup::Nearest);
                for s in &st {
                    assert_eq!(s.shade(f, U16F16::ZERO), near);
                }
                assert_eq!(st[2].shade(f, U16F16::MAX), t.mean());
                assert_eq!(st[3].shade(f, U16F16::MAX), t.mean());
                assert_eq!(st[2].shade(f, U16F16::from_num(128)), t.mean());
            }
        }
    }

    #[test]
    fn extreme_inputs_never_panic() {
        fn go<const N: usize>() {
            let t = lcg_table::<N>(N as u64);
            let fs = [
                I16F16::MIN,
                I16F16::MAX,
                I16F16::ZERO,
                I16F16::ONE,
                -I16F16::DELTA,
                I16F16::DELTA,
            ];
            let ws = [
                U16F16::ZERO,
                U16F16::DELTA,
                U16F16::from_num(N / 2),
                U16F16::from_num(N) - U16F16::DELTA,
                U16F16::from_num(N),
                U16F16::MAX,
            ];
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                for lookup in [TableLookup::Nearest, TableLookup::Linear] {
                    for aa in ALL {
                        let s = ColorStage::new(t, wrap, lookup, aa).unwrap();
                        for f in fs {
                            for w in ws {
                                let _ = s.shade(f, w);
                            }
                            let _ = s.shade_unfiltered(f);
                        }
                    }
                }
            }
        }
        go::<2>();
        go::<4>();
        go::<256>();
        go::<1024>();
    }

    #[test]
    fn zone_plate_widths_blend_zebra_to_grey() {
        // The zebra map filtered over a whole stripe pair is mid grey, for every filter.
        let t = ColorTable::<256>::zebra().unwrap();
        for aa in [Antialias::Mip, Antialias::Csat, Antialias::Csat3] {
            let s = ColorStage::new(t, TableWrap::Mod, TableLookup::Nearest, aa).unwrap();
            let c = s.shade(I16F16::from_num(0.25), U16F16::from_num(256));
            assert!(c.r == 127 || c.r == 128, "{aa:?} {c:?}");
        }
    }
}
