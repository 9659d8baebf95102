//! What an evaluation hands over besides its values: a sample with its screen gradient
//! ([`Sample`]), a span's facts for the shading stage ([`SpanInfo`]) and the activity counters
//! ([`SpanStats`]).

use crate::format::TexValue;

/// The texture function and its screen gradient at one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// `f`.
    pub f: TexValue,
    /// `df/dx` with 48 fraction bits (saturating); zero when gradients are off or not compiled
    /// in (crate feature `gradients`).
    pub gx: i64,
    /// `df/dy` with 48 fraction bits (saturating); zero when gradients are off or not compiled
    /// in.
    pub gy: i64,
}

/// Per-span facts the shading stage needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpanInfo {
    /// Extra filter width from culled or aliasing octaves, in `f` units with 48 fraction bits
    /// (always 0 in builds without feature `gradients`: they have no filter to widen).
    pub extra_width48: i64,
}

/// Activity counters (pixels, set-ups, evaluations), for `--stats` and cost accounting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpanStats {
    /// Pixels evaluated.
    pub pixels: u64,
    /// Spans evaluated.
    pub spans: u64,
    /// Lattice cell set-ups (corner hashing), per term.
    pub cell_setups: u64,
    /// Noise term samples produced (per term per pixel).
    pub noise_evaluations: u64,
    /// Octaves culled by band-limiting (per term per span; [`crate::bandlimit`]).
    pub culled_octaves: u64,
    /// Octaves faded by band-limiting (per term per span; [`crate::bandlimit`]).
    pub faded_octaves: u64,
    /// Gradient samples (per pixel, counting the quadric and each term).
    pub gradient_evaluations: u64,
    /// Pixels produced by forward differencing of at least one term.
    pub fd_pixels: u64,
}

impl SpanStats {
    /// Adds another set of counters.
    pub fn add(&mut self, o: &SpanStats) {
        self.pixels += o.pixels;
        self.spans += o.spans;
        self.cell_setups += o.cell_setups;
        self.noise_evaluations += o.noise_evaluations;
        self.culled_octaves += o.culled_octaves;
        self.faded_octaves += o.faded_octaves;
        self.gradient_evaluations += o.gradient_evaluations;
        self.fd_pixels += o.fd_pixels;
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Sample {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Sample(f raw {=i32}, gx {=i64}, gy {=i64})",
            self.f.to_bits(),
            self.gx,
            self.gy
        );
    }
}
