//! Colour tables: N entries (a power of two, 2 to 1024) built from key colours, looked up by `f`.

/// How `f` indexes a colour table (Hart et al. eq. 2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableWrap {
    /// `f mod 1`: the table repeats (wood rings, marble veins, zebra).
    #[default]
    Mod,
    /// `clamp(f, 0, 1)`: the ends extend (clouds, water, fire).
    Clamp,
}
