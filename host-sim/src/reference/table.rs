//! f64 colour table: point look-ups, exact box filter and MIP look-up (`docs/model.md` section 7).
//!
//! A [`RefTable`] holds `N` RGBA8 entries (`N` a power of two, 1..=1024 accepted); entry `j` covers
//! `[j, j + 1)` in table coordinates. The table argument `g` is `f mod 1` ([`Wrap::Mod`]) or
//! `clamp(f, 0, 1)` ([`Wrap::Clamp`]) and the table coordinate is `x = g N`. Every look-up returns
//! `[f64; 4]` in 0..255 units, with no rounding anywhere:
//!
//! - nearest: entry `floor(x)` (`mod` wraps, `clamp` takes `min(floor(x), N - 1)`);
//! - linear: between entry centres, `y = x - 1/2`, `j = floor(y)`, `t = frac(y)` exactly;
//! - box: the exact average of the piecewise-constant table over `[x - w/2, x + w/2]`, continued
//!   periodically (`mod`) or by its end entries (`clamp`, centred on the unclamped `x = f N`);
//!   `w >= N` gives the table mean (both wraps,
//!   as in the contract and the paper), `w <= 0` the nearest entry;
//! - MIP: level `l` has `N >> l` entries, each the exact mean of its `2^l` level-0 entries;
//!   `l = floor(log2 w)` clamped to `[0, log2 N]`, blended with level `l + 1` by
//!   `t = clamp(w / 2^l - 1, 0, 1)` (no blend at the top level), each level looked up with the
//!   nearest/linear mode at `x / 2^l`.

/// How `f` maps into the table: `f mod 1` or `clamp(f, 0, 1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// `g = f mod 1`; the table repeats.
    Mod,
    /// `g = clamp(f, 0, 1)`; the table extends its end entries.
    Clamp,
}

impl Wrap {
    /// The table argument `g` in `[0, 1]` for a texture value `f`.
    pub fn arg(self, f: f64) -> f64 {
        match self {
            Wrap::Mod => f - f.floor(),
            Wrap::Clamp => f.clamp(0.0, 1.0),
        }
    }
}

/// Point look-up mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Lookup {
    /// The entry containing `x`.
    Nearest,
    /// Linear interpolation between entry centres.
    Linear,
}

/// How a pixel's colour is taken from the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filter {
    /// No filtering: a point look-up at `f`.
    Point(Lookup),
    /// Exact box filter of width `w` (what the summed-area colour table computes).
    Box,
    /// Colour-table MIP map, each level looked up with the given mode.
    Mip(Lookup),
    /// The pre-filtered ramp (`texcore::filter::ramp`): the box at the width rounded to a power
    /// of two in the log domain, centred on the level's sample that covers the entry.
    Ramp,
}

/// A colour table could not be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TableError {
    /// The entry count is not a power of two in 1..=1024.
    #[error("colour table has {0} entries; need a power of two in 1..=1024")]
    BadLength(usize),
}

/// Colour in 0..255 units per channel (R, G, B, A).
pub type Rgba = [f64; 4];

/// An f64 colour table with its MIP levels and running sums.
#[derive(Clone, Debug, PartialEq)]
pub struct RefTable {
    /// MIP levels; `levels[0]` are the entries, `levels[l]` has `N >> l` exact means.
    levels: Vec<Vec<Rgba>>,
    /// `prefix[j] = sum of entries 0..j` (length `N + 1`).
    prefix: Vec<Rgba>,
}

fn add(a: Rgba, b: Rgba) -> Rgba {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

fn sub(a: Rgba, b: Rgba) -> Rgba {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
}

fn scale(a: Rgba, k: f64) -> Rgba {
    a.map(|c| c * k)
}

/// `a + t (b - a)` per channel.
pub fn mix(a: Rgba, b: Rgba, t: f64) -> Rgba {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
        a[3] + t * (b[3] - a[3]),
    ]
}

/// Look up `x` (in entries of `level`) in one level with `lookup` and `wrap`.
fn point_in(level: &[Rgba], x: f64, lookup: Lookup, wrap: Wrap) -> Rgba {
    let n = level.len() as i64;
    let index = |j: i64| -> Rgba {
        let j = match wrap {
            Wrap::Mod => j.rem_euclid(n),
            Wrap::Clamp => j.clamp(0, n - 1),
        };
        level[j as usize]
    };
    match lookup {
        Lookup::Nearest => {
            let j = x.floor() as i64;
            match wrap {
                Wrap::Mod => index(j),
                Wrap::Clamp => index(j.min(n - 1)),
            }
        }
        Lookup::Linear => {
            let y = x - 0.5;
            let j = y.floor();
            let t = y - j;
            let j = j as i64;
            mix(index(j), index(j + 1), t)
        }
    }
}

impl RefTable {
    /// Build from RGBA8 entries (`N` a power of two, 1..=1024).
    pub fn new(entries: &[[u8; 4]]) -> Result<RefTable, TableError> {
        let n = entries.len();
        if !n.is_power_of_two() || n > 1024 {
            return Err(TableError::BadLength(n));
        }
        let level0: Vec<Rgba> = entries.iter().map(|e| e.map(f64::from)).collect();
        let mut prefix = Vec::with_capacity(n + 1);
        let mut acc = [0.0; 4];
        prefix.push(acc);
        for &e in &level0 {
            acc = add(acc, e);
            prefix.push(acc);
        }
        let mut levels = vec![level0];
        while levels.last().map_or(0, Vec::len) > 1 {
            let prev = levels.last().expect("non-empty");
            let next: Vec<Rgba> = prev
                .chunks_exact(2)
                .map(|p| scale(add(p[0], p[1]), 0.5))
                .collect();
            levels.push(next);
        }
        Ok(RefTable { levels, prefix })
    }

    /// Number of entries `N`.
    pub fn len(&self) -> usize {
        self.levels[0].len()
    }

    /// Always false (a table has at least one entry); for API symmetry with [`RefTable::len`].
    pub fn is_empty(&self) -> bool {
        false
    }

    /// `log2 N`, the index of the top (one-entry) MIP level.
    pub fn max_level(&self) -> u32 {
        self.len().trailing_zeros()
    }

    /// The entries as f64.
    pub fn entries(&self) -> &[Rgba] {
        &self.levels[0]
    }

    /// MIP level `l` (`N >> l` exact means), `l` clamped to `0..=log2 N`.
    pub fn mip_level(&self, l: u32) -> &[Rgba] {
        &self.levels[l.min(self.max_level()) as usize]
    }

    /// The mean of all entries.
    pub fn mean(&self) -> Rgba {
        scale(self.prefix[self.len()], 1.0 / self.len() as f64)
    }

    /// Table coordinate `x = g N` of a texture value `f`.
    pub fn coord(&self, f: f64, wrap: Wrap) -> f64 {
        wrap.arg(f) * self.len() as f64
    }

    /// Point look-up at table coordinate `x` (in entries).
    pub fn point_at(&self, x: f64, lookup: Lookup, wrap: Wrap) -> Rgba {
        point_in(&self.levels[0], x, lookup, wrap)
    }

    /// Point look-up of texture value `f`.
    pub fn point(&self, f: f64, lookup: Lookup, wrap: Wrap) -> Rgba {
        self.point_at(self.coord(f, wrap), lookup, wrap)
    }

    /// Nearest entry at `f`.
    pub fn nearest(&self, f: f64, wrap: Wrap) -> Rgba {
        self.point(f, Lookup::Nearest, wrap)
    }

    /// Linear interpolation between entry centres at `f`.
    pub fn linear(&self, f: f64, wrap: Wrap) -> Rgba {
        self.point(f, Lookup::Linear, wrap)
    }

    /// Entry `j` of the continued table: periodic (`mod`) or end-extended (`clamp`).
    pub fn continued(&self, j: i64, wrap: Wrap) -> Rgba {
        let n = self.len() as i64;
        let j = match wrap {
            Wrap::Mod => j.rem_euclid(n),
            Wrap::Clamp => j.clamp(0, n - 1),
        };
        self.levels[0][j as usize]
    }

    /// `I(k)` at an integer `k`: the sum of the continued table over `[0, k)` (negative for
    /// `k < 0`). Integer-valued, hence exact in f64 for any realistic `k`.
    fn integral_int(&self, k: i64, wrap: Wrap) -> Rgba {
        let n = self.len() as i64;
        let total = self.prefix[self.len()];
        match wrap {
            Wrap::Mod => {
                let periods = k.div_euclid(n);
                let r = k.rem_euclid(n) as usize;
                add(scale(total, periods as f64), self.prefix[r])
            }
            Wrap::Clamp => {
                if k < 0 {
                    scale(self.levels[0][0], k as f64)
                } else if k > n {
                    add(total, scale(self.levels[0][self.len() - 1], (k - n) as f64))
                } else {
                    self.prefix[k as usize]
                }
            }
        }
    }

    /// `I(y)`: the integral from 0 to `y` (table coordinates) of the continued table.
    pub fn integral(&self, y: f64, wrap: Wrap) -> Rgba {
        let j = y.floor();
        add(
            self.integral_int(j as i64, wrap),
            scale(self.continued(j as i64, wrap), y - j),
        )
    }

    /// Exact box filter of width `w` (entries) centred at table coordinate `x`: `w >= N` gives
    /// the mean, `w <= 0` the nearest entry.
    ///
    /// Computed as the two partial end entries plus the whole entries between them (an exact
    /// integer sum), divided by `w`, so the result is accurate to a few ulps even for tiny `w`.
    pub fn box_at(&self, x: f64, w: f64, wrap: Wrap) -> Rgba {
        let nf = self.len() as f64;
        if w >= nf {
            return self.mean();
        }
        if w <= 0.0 || w.is_nan() {
            return self.point_at(x, Lookup::Nearest, wrap);
        }
        let lo = x - 0.5 * w;
        let hi = x + 0.5 * w;
        let jl = lo.floor();
        let jh = hi.floor();
        let (il, ih) = (jl as i64, jh as i64);
        if il == ih {
            return self.continued(il, wrap);
        }
        let ends = add(
            scale(self.continued(il, wrap), jl + 1.0 - lo),
            scale(self.continued(ih, wrap), hi - jh),
        );
        let whole = sub(self.integral_int(ih, wrap), self.integral_int(il + 1, wrap));
        scale(add(ends, whole), 1.0 / w)
    }

    /// Exact box filter of width `w` (entries) at texture value `f`; a `clamp` table's box is
    /// centred on the unclamped `x = f N` (its window extends the end entries).
    pub fn box_filter(&self, f: f64, w: f64, wrap: Wrap) -> Rgba {
        let x = match wrap {
            Wrap::Clamp if f.is_finite() => f * self.len() as f64,
            _ => self.coord(f, wrap),
        };
        self.box_at(x, w, wrap)
    }

    /// MIP look-up at table coordinate `x` for width `w` (entries).
    pub fn mip_at(&self, x: f64, w: f64, lookup: Lookup, wrap: Wrap) -> Rgba {
        let top = self.max_level();
        let l = if w > 0.0 {
            w.log2().floor().clamp(0.0, f64::from(top)) as u32
        } else {
            0
        };
        let size = f64::from(1u32 << l);
        // Levels above 0 are always interpolated linearly (texcore's `ColorMip`).
        let here_lookup = if l == 0 { lookup } else { Lookup::Linear };
        let here = point_in(self.mip_level(l), x / size, here_lookup, wrap);
        if l == top {
            return here;
        }
        let t = (w / size - 1.0).clamp(0.0, 1.0);
        if t == 0.0 {
            return here;
        }
        let up = point_in(
            self.mip_level(l + 1),
            x / (2.0 * size),
            Lookup::Linear,
            wrap,
        );
        mix(here, up, t)
    }

    /// MIP look-up of texture value `f` for width `w` (entries).
    pub fn mip(&self, f: f64, w: f64, lookup: Lookup, wrap: Wrap) -> Rgba {
        self.mip_at(self.coord(f, wrap), w, lookup, wrap)
    }

    /// The ramp filter at table coordinate `x` and width `w` (entries): level
    /// `l = round(log2 w)` in `[0, log2 N]` (the mean at the last level), the box of width `2^l`
    /// centred on `(j + 1/2) S` with `S = max(1, 2^(l-2))` and `j = floor(floor(x) / S)`.
    pub fn ramp_at(&self, x: f64, w: f64, wrap: Wrap) -> Rgba {
        let top = self.max_level();
        let l = if w > 0.0 {
            w.log2().round().clamp(0.0, f64::from(top)) as u32
        } else {
            0
        };
        if l == top {
            return self.mean();
        }
        let n = self.len() as i64;
        let k = x.floor() as i64;
        let k = match wrap {
            Wrap::Mod => k.rem_euclid(n),
            Wrap::Clamp => k.clamp(0, n - 1),
        };
        let stride = if l < 3 {
            1.0
        } else {
            f64::from(1u32 << (l - 2))
        };
        let j = (k as f64 / stride).floor();
        self.box_at((j + 0.5) * stride, f64::from(1u32 << l), wrap)
    }

    /// The colour of texture value `f` with filter width `w` (ignored by [`Filter::Point`]).
    pub fn sample(&self, f: f64, w: f64, filter: Filter, wrap: Wrap) -> Rgba {
        match filter {
            Filter::Point(lookup) => self.point(f, lookup, wrap),
            Filter::Box => self.box_filter(f, w, wrap),
            Filter::Mip(lookup) => self.mip(f, w, lookup, wrap),
            Filter::Ramp => self.ramp_at(self.coord(f, wrap), w, wrap),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::noise::SplitMix64;
    use proptest::prelude::*;

    fn random_table(n: usize, seed: u64) -> Vec<[u8; 4]> {
        let mut rng = SplitMix64(seed);
        (0..n)
            .map(|_| {
                let b = rng.next_u64().to_le_bytes();
                [b[0], b[1], b[2], b[3]]
            })
            .collect()
    }

    /// Dense midpoint-rule average of the continued table over `[x - w/2, x + w/2]`.
    fn numeric_box(t: &RefTable, x: f64, w: f64, wrap: Wrap) -> Rgba {
        let n = t.len() as i64;
        let samples = 200_000;
        let mut acc = [0.0; 4];
        for i in 0..samples {
            let y = x - 0.5 * w + w * (f64::from(i) + 0.5) / f64::from(samples);
            let j = y.floor() as i64;
            let j = match wrap {
                Wrap::Mod => j.rem_euclid(n),
                Wrap::Clamp => j.clamp(0, n - 1),
            };
            acc = add(acc, t.entries()[j as usize]);
        }
        scale(acc, 1.0 / f64::from(samples))
    }

    fn close(a: Rgba, b: Rgba, tol: f64) -> bool {
        a.iter().zip(b.iter()).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn rejects_bad_lengths() {
        assert_eq!(RefTable::new(&[]), Err(TableError::BadLength(0)));
        assert_eq!(RefTable::new(&[[0; 4]; 3]), Err(TableError::BadLength(3)));
        assert_eq!(
            RefTable::new(&vec![[0; 4]; 2048]),
            Err(TableError::BadLength(2048))
        );
        assert!(RefTable::new(&[[1, 2, 3, 4]]).is_ok());
    }

    #[test]
    fn wrap_argument() {
        assert_eq!(Wrap::Mod.arg(2.25), 0.25);
        assert_eq!(Wrap::Mod.arg(-0.25), 0.75);
        assert_eq!(Wrap::Clamp.arg(-0.25), 0.0);
        assert_eq!(Wrap::Clamp.arg(1.5), 1.0);
        assert_eq!(Wrap::Clamp.arg(0.5), 0.5);
    }

    #[test]
    fn nearest_and_linear() {
        let e = [
            [0, 0, 0, 255],
            [100, 0, 0, 255],
            [200, 0, 0, 255],
            [40, 0, 0, 255],
        ];
        let t = RefTable::new(&e).unwrap();
        // x = 4 f.
        assert_eq!(t.nearest(0.3, Wrap::Mod)[0], 100.0);
        assert_eq!(t.nearest(1.3, Wrap::Mod)[0], 100.0);
        assert_eq!(t.nearest(-0.1, Wrap::Mod)[0], 40.0);
        assert_eq!(t.nearest(1.0, Wrap::Clamp)[0], 40.0); // min(floor(4), 3)
        assert_eq!(t.nearest(-3.0, Wrap::Clamp)[0], 0.0);
        // Linear: at an entry centre it is the entry; halfway between centres the mean.
        assert_eq!(t.linear(1.5 / 4.0, Wrap::Mod)[0], 100.0);
        assert_eq!(t.linear(2.0 / 4.0, Wrap::Mod)[0], 150.0);
        assert_eq!(t.linear(0.0, Wrap::Mod)[0], 20.0); // between entry 3 and entry 0
        assert_eq!(t.linear(0.0, Wrap::Clamp)[0], 0.0); // clamped to entry 0
        assert_eq!(t.linear(1.0, Wrap::Clamp)[0], 40.0);
        assert_eq!(t.linear(0.25 * 3.75, Wrap::Clamp)[0], 40.0);
        assert_eq!(
            t.linear(0.25 * 3.25, Wrap::Mod)[0],
            0.75 * 40.0 + 0.25 * 200.0
        );
        assert_eq!(t.nearest(0.3, Wrap::Mod)[3], 255.0);
    }

    #[test]
    fn box_filter_limits() {
        for wrap in [Wrap::Mod, Wrap::Clamp] {
            let t = RefTable::new(&random_table(64, 3)).unwrap();
            let mut rng = SplitMix64(11);
            for _ in 0..500 {
                let f = rng.next_f64() * 3.0 - 1.0;
                let x = t.coord(f, wrap);
                // w -> 0 gives the nearest entry (away from entry boundaries).
                if (x - x.floor() - 0.5).abs() < 0.49 && x < 63.99 {
                    assert!(close(t.box_filter(f, 1e-6, wrap), t.nearest(f, wrap), 1e-9));
                    assert!(close(
                        t.box_filter(f, 1e-12, wrap),
                        t.nearest(f, wrap),
                        1e-9
                    ));
                }
                assert_eq!(t.box_filter(f, 0.0, wrap), t.nearest(f, wrap));
                // w >= N gives the mean.
                assert_eq!(t.box_filter(f, 64.0, wrap), t.mean());
                assert_eq!(t.box_filter(f, 1e9, wrap), t.mean());
            }
        }
        // Mod: a window of exactly N - tiny is (nearly) the mean anywhere.
        let t = RefTable::new(&random_table(16, 5)).unwrap();
        assert!(close(
            t.box_filter(0.37, 16.0 - 1e-9, Wrap::Mod),
            t.mean(),
            1e-6
        ));
    }

    #[test]
    fn box_filter_matches_paper_formulas() {
        // The summed-area colour table cases of Hart et al. 1999, 3.3.2, with integer x +- w/2.
        let e = random_table(32, 9);
        let t = RefTable::new(&e).unwrap();
        let c = |j: usize| f64::from(e[j][0]);
        let csat = |j: i64| (0..=j).map(|i| c(i as usize)).sum::<f64>();
        let n = 32i64;
        // x + w/2 >= N, mod: (csat[x+w/2-N] + csat[N-1] - csat[x-w/2-1]) / w
        let (x, w) = (28.0, 10.0);
        let lo = 23i64;
        let hi = 33i64; // exclusive end of the window in entries: [23, 33)
        let mod_ref = (csat(hi - 1 - n) + csat(n - 1) - csat(lo - 1)) / w;
        assert!((t.box_at(x, w, Wrap::Mod)[0] - mod_ref).abs() < 1e-9);
        let clamp_ref = (f64::from((hi - n) as i32) * c(31) + csat(n - 1) - csat(lo - 1)) / w;
        assert!((t.box_at(x, w, Wrap::Clamp)[0] - clamp_ref).abs() < 1e-9);
        // x - w/2 < 0: window [-3, 7).
        let (x, w) = (2.0, 10.0);
        let mod_ref = (csat(6) + csat(n - 1) - csat(n - 3 - 1)) / w;
        assert!((t.box_at(x, w, Wrap::Mod)[0] - mod_ref).abs() < 1e-9);
        let clamp_ref = (3.0 * c(0) + csat(6)) / w;
        assert!((t.box_at(x, w, Wrap::Clamp)[0] - clamp_ref).abs() < 1e-9);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn box_filter_equals_dense_sampling(
            log_n in 0u32..8, seed in any::<u64>(), f in -2.0f64..3.0, frac_w in 0.0f64..1.0,
            clamp in any::<bool>(),
        ) {
            let n = 1usize << log_n;
            let wrap = if clamp { Wrap::Clamp } else { Wrap::Mod };
            let t = RefTable::new(&random_table(n, seed)).unwrap();
            let w = frac_w * n as f64;
            prop_assume!(w > 1e-3);
            let x = t.coord(f, wrap);
            let exact = t.box_at(x, w, wrap);
            let numeric = numeric_box(&t, x, w, wrap);
            // Midpoint rule error <= 255 * (cells crossed) / samples.
            let tol = 255.0 * (w + 2.0) / 200_000.0 + 1e-9;
            prop_assert!(close(exact, numeric, tol), "{:?} vs {:?} (n {} x {} w {})", exact, numeric, n, x, w);
            // The running integral I(y) gives the same average.
            let via_integral = scale(sub(t.integral(x + 0.5 * w, wrap), t.integral(x - 0.5 * w, wrap)), 1.0 / w);
            prop_assert!(close(exact, via_integral, 1e-6));
        }

        #[test]
        fn mip_levels_are_exact_means(log_n in 1u32..11, seed in any::<u64>()) {
            let n = 1usize << log_n;
            let e = random_table(n, seed);
            let t = RefTable::new(&e).unwrap();
            for l in 0..=t.max_level() {
                let level = t.mip_level(l);
                prop_assert_eq!(level.len(), n >> l);
                let span = 1usize << l;
                for (j, v) in level.iter().enumerate() {
                    let mean = (j * span..(j + 1) * span).map(|i| f64::from(e[i][1])).sum::<f64>() / span as f64;
                    prop_assert!((v[1] - mean).abs() < 1e-9);
                }
            }
            prop_assert!(close(t.mip_level(t.max_level())[0], t.mean(), 1e-9));
        }
    }

    #[test]
    fn mip_lookup() {
        let e = random_table(64, 21);
        let t = RefTable::new(&e).unwrap();
        for wrap in [Wrap::Mod, Wrap::Clamp] {
            for lookup in [Lookup::Nearest, Lookup::Linear] {
                for &f in &[0.0, 0.1, 0.37, 0.5, 0.99] {
                    let x = t.coord(f, wrap);
                    // w <= 1: level 0 only.
                    assert_eq!(t.mip(f, 0.5, lookup, wrap), t.point(f, lookup, wrap));
                    assert_eq!(t.mip(f, 1.0, lookup, wrap), t.point(f, lookup, wrap));
                    // Exact powers of two select one level.
                    // Levels above 0 are interpolated linearly.
                    let l2 = point_in(t.mip_level(2), x / 4.0, Lookup::Linear, wrap);
                    assert_eq!(t.mip(f, 4.0, lookup, wrap), l2);
                    // Halfway between 4 and 8 blends levels 2 and 3 equally.
                    let l3 = point_in(t.mip_level(3), x / 8.0, Lookup::Linear, wrap);
                    assert!(close(t.mip(f, 6.0, lookup, wrap), mix(l2, l3, 0.5), 1e-9));
                    // w >= N: the one-entry top level, the mean.
                    assert!(close(t.mip(f, 64.0, lookup, wrap), t.mean(), 1e-9));
                    assert!(close(t.mip(f, 1000.0, lookup, wrap), t.mean(), 1e-9));
                }
            }
        }
        assert_eq!(
            t.sample(0.3, 4.0, Filter::Mip(Lookup::Nearest), Wrap::Mod),
            t.mip(0.3, 4.0, Lookup::Nearest, Wrap::Mod)
        );
        assert_eq!(
            t.sample(0.3, 4.0, Filter::Box, Wrap::Mod),
            t.box_filter(0.3, 4.0, Wrap::Mod)
        );
        assert_eq!(
            t.sample(0.3, 4.0, Filter::Point(Lookup::Linear), Wrap::Mod),
            t.linear(0.3, Wrap::Mod)
        );
    }
}
