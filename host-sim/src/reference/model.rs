//! The f64 texture model `f(s) = q(s) + sum_k a_k n_k(T_k s)`, its analytic gradient and the
//! filter width (`docs/model.md` sections 6 and 8, ideal math).
//!
//! Differences from the fixed-point model are deliberate: lattice points are `u = M s + t` exactly
//! (the contract rounds `U0`, `DU` and steps `u(i) = U0 + i DU` along a span), fades, interpolation,
//! the quadric and `f` are exact reals, and the filter width is `N * norm` with no intermediate
//! saturation other than the final `min(w, N)`. The deviations of texcore from this are what the
//! accuracy reports measure.

use texcore::hash::HashKind;

use super::noise::{noise, noise_bits, Basis, Fade, NoiseSample, MNOISE_SCALE};
use super::quadric;
use super::table::{Filter, Lookup, RefTable, Rgba, Wrap};

/// One noise term `a n(M s + t)` (or `a |n(M s + t)|` with turbulence).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefTerm {
    /// `a_k`.
    pub amplitude: f64,
    /// The 3x4 affine `T_k`: row `i` is `[M_i0, M_i1, M_i2, t_i]`, `u_i = M_i . s + t_i`.
    pub matrix: [[f64; 4]; 3],
    /// Noise basis.
    pub basis: Basis,
    /// Fade of the basis.
    pub fade: Fade,
    /// Lattice hash (ignored by [`Basis::MNoise`], which always uses `hash61`).
    pub hash: HashKind,
    /// Turbulence: the term is `a |n|` (gradient `a sign(n) grad n`).
    pub turbulence: bool,
}

impl RefTerm {
    /// A term with `T = diag(freq) + offset`, smooth fade, the default hash and no turbulence.
    pub fn scaled(amplitude: f64, basis: Basis, freq: f64, offset: [f64; 3]) -> RefTerm {
        RefTerm {
            amplitude,
            matrix: [
                [freq, 0.0, 0.0, offset[0]],
                [0.0, freq, 0.0, offset[1]],
                [0.0, 0.0, freq, offset[2]],
            ],
            basis,
            fade: Fade::Smooth,
            hash: HashKind::default(),
            turbulence: false,
        }
    }

    /// The lattice point `u = M s + t`.
    pub fn lattice_point(&self, s: [f64; 3]) -> [f64; 3] {
        self.matrix
            .map(|row| row[0] * s[0] + row[1] * s[1] + row[2] * s[2] + row[3])
    }

    /// The lattice step `M ds` of a texture-space step `ds` (linear part only).
    pub fn lattice_step(&self, ds: [f64; 3]) -> [f64; 3] {
        self.matrix
            .map(|row| row[0] * ds[0] + row[1] * ds[1] + row[2] * ds[2])
    }

    /// The term's reach (`docs/model.md` 8): the largest magnitude of the components of `M dsdx`
    /// and `M dsdy`, in cells a pixel.
    pub fn reach(&self, dsdx: [f64; 3], dsdy: [f64; 3]) -> f64 {
        let dx = self.lattice_step(dsdx);
        let dy = self.lattice_step(dsdy);
        dx.iter().chain(dy.iter()).fold(0.0, |m, c| m.max(c.abs()))
    }

    /// The fade weight of a term past one cell a pixel (`docs/model.md` 8.1): one over the square
    /// root of the cells its footprint covers, `1 / sqrt(max(lx, 1) max(ly, 1))` with `lx`, `ly`
    /// its reaches along `dsdx` and `dsdy`, at least [`FADE_FLOOR`].
    pub fn fade_weight(&self, dsdx: [f64; 3], dsdy: [f64; 3]) -> f64 {
        let along = |d: [f64; 3]| {
            self.lattice_step(d)
                .iter()
                .fold(1.0f64, |m, c| m.max(c.abs()))
        };
        (1.0 / (along(dsdx) * along(dsdy)).sqrt()).max(FADE_FLOOR)
    }

    /// Past the Nyquist limit, half a cell a pixel (`docs/model.md` 8): the term widens the filter
    /// by (part of) its variance instead of its gradient, and past one cell it is faded.
    pub fn past_nyquist(&self, dsdx: [f64; 3], dsdy: [f64; 3]) -> bool {
        self.reach(dsdx, dsdy) > 0.5
    }

    /// The standard deviation of the term's basis values (texcore's `bandlimit::basis_sigma`).
    pub fn sigma(&self) -> f64 {
        let (plain, turb) = match self.basis {
            Basis::Value => (22938.0, 13763.0),
            Basis::Gradient => (17039.0, 9830.0),
            Basis::MNoise => (13763.0, 7864.0),
        };
        (if self.turbulence { turb } else { plain }) / 65536.0
    }

    /// The term's band for a pixel with screen steps `dsdx`, `dsdy` (`docs/model.md` 8): the
    /// factor its value enters `f` with (0: culled), whether its gradient widens the filter, and
    /// the variance it adds to the filter instead.
    pub fn band(&self, dsdx: [f64; 3], dsdy: [f64; 3], nyquist: Nyquist) -> Band {
        let l = self.reach(dsdx, dsdy);
        if nyquist == Nyquist::Evaluate || l <= 0.5 {
            return Band {
                weight: 1.0,
                gradient: true,
                variance: 0.0,
            };
        }
        let full = (self.amplitude * self.sigma()).powi(2);
        if nyquist == Nyquist::Cull && l <= 1.0 {
            // Unfaded; half its variance instead of its gradient.
            return Band {
                weight: 1.0,
                gradient: false,
                variance: 0.5 * full,
            };
        }
        if nyquist == Nyquist::Widen {
            return Band {
                weight: 1.0,
                gradient: false,
                variance: full,
            };
        }
        let w = self.fade_weight(dsdx, dsdy);
        if (self.amplitude * w).abs() < CULL_AMPLITUDE {
            return Band {
                weight: 0.0,
                gradient: false,
                variance: full,
            };
        }
        Band {
            weight: w,
            gradient: false,
            variance: full * FADED_PART * (1.0 - w * w),
        }
    }

    /// The basis value at `s` (`n` or `|n|`, without the amplitude) and its gradient with respect
    /// to the lattice point `u`.
    pub fn basis_at(&self, s: [f64; 3], mnoise_scale: f64) -> NoiseSample {
        let u = self.lattice_point(s);
        let n = noise(self.basis, u, self.fade, self.hash, mnoise_scale);
        if self.turbulence {
            let sign = if n.value < 0.0 { -1.0 } else { 1.0 };
            NoiseSample {
                value: n.value.abs(),
                grad: n.grad.map(|g| sign * g),
            }
        } else {
            n
        }
    }

    /// The term's contribution at pixel `i` of a span starting at `s0` with step `ds`, at
    /// precision `p`: the lattice point is `Q_F(M s0 + t) + i Q_F(M ds)` (exactly `M s(i) + t`
    /// for `F = 16`), corner values quantised to `V` bits.
    pub fn value_on_span(
        &self,
        s0: [f64; 3],
        ds: [f64; 3],
        i: u32,
        p: RefPrecision,
        mnoise_scale: f64,
    ) -> f64 {
        let u = if p.coord_bits >= 16 {
            let s = [0, 1, 2].map(|k| s0[k] + f64::from(i) * ds[k]);
            self.lattice_point(s)
        } else {
            let u0 = self.lattice_point(s0).map(|c| p.quantize_coord(c));
            let du = self.lattice_step(ds).map(|c| p.quantize_coord(c));
            [0, 1, 2].map(|k| u0[k] + f64::from(i) * du[k])
        };
        let n = noise_bits(
            self.basis,
            u,
            self.fade,
            self.hash,
            mnoise_scale,
            p.value_bits,
        )
        .value;
        let n = if self.turbulence { n.abs() } else { n };
        self.amplitude * n
    }

    /// The term's contribution `a n(T s)` to `f` and its gradient `a M^T grad n` with respect to `s`.
    pub fn eval(&self, s: [f64; 3], mnoise_scale: f64) -> (f64, [f64; 3]) {
        let n = self.basis_at(s, mnoise_scale);
        let a = self.amplitude;
        let mut g = [0.0; 3];
        for (j, gj) in g.iter_mut().enumerate() {
            *gj = a
                * (self.matrix[0][j] * n.grad[0]
                    + self.matrix[1][j] * n.grad[1]
                    + self.matrix[2][j] * n.grad[2]);
        }
        (a * n.value, g)
    }
}

/// The arithmetic precision the reference models (`docs/model.md` 3.2): coordinate fraction
/// bits `F` and lattice value bits `V`. At 16 (the native format) nothing is quantised: the
/// reference is the ideal model, as without this.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RefPrecision {
    /// Lattice-coordinate fraction bits `F` (16: exact).
    pub coord_bits: u32,
    /// Corner-value bits `V` (16: the lattice values as they are).
    pub value_bits: u32,
}

impl RefPrecision {
    /// The ideal (unquantised) reference.
    pub const IDEAL: RefPrecision = RefPrecision {
        coord_bits: 16,
        value_bits: 16,
    };

    /// A lattice coordinate as the quantised span set-up has it: `x` rounded half up to 16
    /// fraction bits (the native `U0`, `DU`), then to `F` (`docs/model.md` 3.2); the identity at
    /// `F >= 16`, where the reference stays ideal.
    pub fn quantize_coord(&self, x: f64) -> f64 {
        if self.coord_bits >= 16 {
            return x;
        }
        let x16 = (x * 65536.0 + 0.5).floor() / 65536.0;
        let k = 2f64.powi(self.coord_bits as i32);
        (x16 * k + 0.5).floor() / k
    }
}

impl Default for RefPrecision {
    fn default() -> Self {
        Self::IDEAL
    }
}

/// Norm combining the two screen derivatives of `f` into a filter width.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Norm {
    /// `|gx| + |gy|`.
    L1,
    /// `sqrt(gx^2 + gy^2)`.
    L2,
    /// `max(|gx|, |gy|)`.
    Max,
}

impl Norm {
    /// The norm of `(gx, gy)`.
    pub fn apply(self, gx: f64, gy: f64) -> f64 {
        match self {
            Norm::L1 => gx.abs() + gy.abs(),
            Norm::L2 => gx.hypot(gy),
            Norm::Max => gx.abs().max(gy.abs()),
        }
    }
}

/// The smallest fade weight of a band-limited term (texcore's `bandlimit::FADE_FLOOR`).
pub const FADE_FLOOR: f64 = 0.25;
/// The share of a faded term's within-footprint variance `1 - w^2` that widens the filter
/// (texcore's `bandlimit::FADED_PART`).
pub const FADED_PART: f64 = 0.75;
/// Faded amplitudes below this are culled (texcore's `bandlimit::CULL_AMPLITUDE`).
pub const CULL_AMPLITUDE: f64 = 1.0 / 256.0;

/// How a term enters one pixel ([`RefTerm::band`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Factor of the term's value in `f` (1: unfaded, 0: culled).
    pub weight: f64,
    /// Its gradient widens the filter.
    pub gradient: bool,
    /// Variance (in `f` units squared) it adds to the filter instead.
    pub variance: f64,
}

/// What to do with a noise term past one cell a pixel ([`RefTerm::band`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Nyquist {
    /// Ideal: evaluate it and use its analytic derivative (the reference default).
    Evaluate,
    /// The contract with culling off: evaluate it at full amplitude, but it widens the filter by
    /// its variance `a^2 sigma^2` instead of its derivative.
    Widen,
    /// The contract with culling on (band-limiting): it enters `f` faded by
    /// `w = max(1 / reach, 1/4)` (culled when `|a w| < 1/256`) and widens the filter by
    /// `(1 - w/2) a^2 sigma^2` of its variance (half of it between half a cell and one cell a
    /// pixel, unfaded).
    Cull,
}

impl Nyquist {
    /// `Cull` if `cull_nyquist`, else `Evaluate`.
    pub fn from_cull(cull_nyquist: bool) -> Nyquist {
        if cull_nyquist {
            Nyquist::Cull
        } else {
            Nyquist::Evaluate
        }
    }
}

/// A pixel's footprint in texture space: the point and the screen Jacobian columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Solid texture coordinate `s` of the pixel centre.
    pub s: [f64; 3],
    /// `ds/dx` (one pixel step along the scanline).
    pub dsdx: [f64; 3],
    /// `ds/dy` (one scanline down).
    pub dsdy: [f64; 3],
}

/// The reference texture model.
#[derive(Clone, Debug, PartialEq)]
pub struct RefModel {
    /// Quadric coefficients `[A, B, C, D, E, F, G, H, I, J]` (see [`quadric`]).
    pub quadric: [f64; 10],
    /// Noise terms.
    pub terms: Vec<RefTerm>,
    /// How `f` maps into the colour table.
    pub wrap: Wrap,
    /// mNoise scale (default [`MNOISE_SCALE`]); mNoise terms use `clamp(scale * raw, -1, 1)`.
    pub mnoise_scale: f64,
}

impl Default for RefModel {
    /// `f = 0`, mod table, default mNoise scale.
    fn default() -> Self {
        RefModel {
            quadric: [0.0; 10],
            terms: Vec::new(),
            wrap: Wrap::Mod,
            mnoise_scale: MNOISE_SCALE,
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl RefModel {
    /// A model with the given quadric, terms and wrap and the default mNoise scale.
    pub fn new(quadric: [f64; 10], terms: Vec<RefTerm>, wrap: Wrap) -> RefModel {
        RefModel {
            quadric,
            terms,
            wrap,
            mnoise_scale: MNOISE_SCALE,
        }
    }

    /// `f(s)` and `grad f(s)`, every term included, optionally skipping terms for which
    /// `skip(term)` holds.
    fn f_grad_filtered(&self, s: [f64; 3], skip: impl Fn(&RefTerm) -> bool) -> (f64, [f64; 3]) {
        let mut f = quadric::value(&self.quadric, s);
        let mut g = quadric::gradient(&self.quadric, s);
        for term in self.terms.iter().filter(|t| !skip(t)) {
            let (v, tg) = term.eval(s, self.mnoise_scale);
            f += v;
            for i in 0..3 {
                g[i] += tg[i];
            }
        }
        (f, g)
    }

    /// `f(s)` with every term.
    pub fn f(&self, s: [f64; 3]) -> f64 {
        self.f_grad_filtered(s, |_| false).0
    }

    /// The analytic `grad f(s)` with every term.
    pub fn grad(&self, s: [f64; 3]) -> [f64; 3] {
        self.f_grad_filtered(s, |_| false).1
    }

    /// `f(s)` and `grad f(s)` with every term.
    pub fn f_and_grad(&self, s: [f64; 3]) -> (f64, [f64; 3]) {
        self.f_grad_filtered(s, |_| false)
    }

    /// `f` at a pixel: with [`Nyquist::Cull`] the terms past one cell a pixel are faded or
    /// culled ([`RefTerm::band`]).
    pub fn f_at(&self, fp: &Footprint, nyquist: Nyquist) -> f64 {
        match nyquist {
            Nyquist::Cull => {
                let mut f = quadric::value(&self.quadric, fp.s);
                for term in &self.terms {
                    let b = term.band(fp.dsdx, fp.dsdy, nyquist);
                    if b.weight > 0.0 {
                        f += b.weight * term.eval(fp.s, self.mnoise_scale).0;
                    }
                }
                f
            }
            Nyquist::Evaluate | Nyquist::Widen => self.f(fp.s),
        }
    }

    /// `f` at pixel `i` of a span (`s(i) = s0 + i ds`, screen steps `ds` and `dsdy` for the
    /// Nyquist test) at precision `p` (`docs/model.md` 3.2): the quadric at `s(i)` exactly, every
    /// term at its quantised lattice point ([`RefTerm::value_on_span`]); with [`Nyquist::Cull`]
    /// terms past the Nyquist limit are left out. At [`RefPrecision::IDEAL`] this is
    /// [`RefModel::f_at`] of the pixel's footprint.
    pub fn f_on_span(
        &self,
        s0: [f64; 3],
        ds: [f64; 3],
        dsdy: [f64; 3],
        i: u32,
        p: RefPrecision,
        nyquist: Nyquist,
    ) -> f64 {
        let s = [0, 1, 2].map(|k| s0[k] + f64::from(i) * ds[k]);
        let mut f = quadric::value(&self.quadric, s);
        for term in &self.terms {
            let b = term.band(ds, dsdy, nyquist);
            if b.weight > 0.0 {
                f += b.weight * term.value_on_span(s0, ds, i, p, self.mnoise_scale);
            }
        }
        f
    }

    /// The table argument `g` (`f mod 1` or `clamp(f, 0, 1)`) of a value `f`.
    pub fn table_arg(&self, f: f64) -> f64 {
        self.wrap.arg(f)
    }

    /// The screen derivatives `(df/dx, df/dy)` at a pixel, leaving out terms past one cell a
    /// pixel unless `nyquist` is [`Nyquist::Evaluate`], and the spread width `sqrt(12 var)` of
    /// the variance those terms add ([`RefTerm::band`]).
    pub fn screen_derivatives(&self, fp: &Footprint, nyquist: Nyquist) -> (f64, f64, f64) {
        let mut var = 0.0;
        let mut g = quadric::gradient(&self.quadric, fp.s);
        for term in &self.terms {
            let b = term.band(fp.dsdx, fp.dsdy, nyquist);
            var += b.variance;
            if !b.gradient {
                continue;
            }
            let (_, tg) = term.eval(fp.s, self.mnoise_scale);
            for i in 0..3 {
                g[i] += tg[i];
            }
        }
        (dot(g, fp.dsdx), dot(g, fp.dsdy), (12.0 * var).sqrt())
    }

    /// Filter width in entries for an `n_entries` table: `w = N sqrt(norm(df/dx, df/dy)^2 + e^2)`,
    /// saturated at `N`, `e` the spread width of the terms past one cell a pixel. With
    /// `cull_nyquist` those terms are band-limited ([`Nyquist::Cull`]); without it every term is
    /// differentiated (the ideal reference).
    pub fn filter_width(
        &self,
        fp: &Footprint,
        n_entries: usize,
        norm: Norm,
        cull_nyquist: bool,
    ) -> f64 {
        self.filter_width_with(fp, n_entries, norm, Nyquist::from_cull(cull_nyquist))
    }

    /// [`RefModel::filter_width`] with an explicit Nyquist policy.
    pub fn filter_width_with(
        &self,
        fp: &Footprint,
        n_entries: usize,
        norm: Norm,
        nyquist: Nyquist,
    ) -> f64 {
        let n = n_entries as f64;
        let (gx, gy, extra) = self.screen_derivatives(fp, nyquist);
        let w = n * norm.apply(gx, gy).hypot(extra);
        if w.is_nan() {
            n
        } else {
            w.min(n)
        }
    }

    /// Unfiltered colour at a point: the table's point look-up at `f(s)`. For supersampling.
    pub fn point_color(&self, s: [f64; 3], table: &RefTable, lookup: Lookup) -> Rgba {
        table.point(self.f(s), lookup, self.wrap)
    }

    /// The colour of a pixel: `f` (see [`RefModel::f_at`]) looked up with `filter` and the width
    /// from [`RefModel::filter_width_with`].
    pub fn pixel_color(
        &self,
        fp: &Footprint,
        table: &RefTable,
        filter: Filter,
        norm: Norm,
        nyquist: Nyquist,
    ) -> Rgba {
        let f = self.f_at(fp, nyquist);
        let w = match filter {
            Filter::Point(_) => 0.0,
            Filter::Box | Filter::Mip(_) | Filter::Ramp => {
                self.filter_width_with(fp, table.len(), norm, nyquist)
            }
        };
        table.sample(f, w, filter, self.wrap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::noise::{gradient_noise, SplitMix64};
    use proptest::prelude::*;

    const BASES: [Basis; 3] = [Basis::Value, Basis::Gradient, Basis::MNoise];

    fn random_model(seed: u64, terms: usize) -> RefModel {
        let mut rng = SplitMix64(seed);
        let mut r = |a: f64| (rng.next_f64() * 2.0 - 1.0) * a;
        let quadric = [(); 10].map(|_| r(3.0));
        let mut ts = Vec::new();
        for k in 0..terms {
            let matrix = [(); 3].map(|_| [r(4.0), r(4.0), r(4.0), r(50.0)]);
            ts.push(RefTerm {
                amplitude: r(1.0),
                matrix,
                basis: BASES[k % 3],
                fade: Fade::ALL[(k / 3) % 3],
                hash: if k % 2 == 0 {
                    HashKind::Permutation
                } else {
                    HashKind::Integer
                },
                turbulence: k % 4 == 1,
            });
        }
        RefModel {
            quadric,
            terms: ts,
            wrap: Wrap::Mod,
            mnoise_scale: 0.6,
        }
    }

    /// True when `s` is safely inside one cell of every term and away from |n| = 0 kinks and the
    /// mNoise clamp, so a central difference of step `h` sees one smooth polynomial.
    fn smooth_at(m: &RefModel, s: [f64; 3], h: f64) -> bool {
        m.terms.iter().all(|t| {
            let reach: f64 = t
                .matrix
                .iter()
                .map(|row| row[..3].iter().map(|v| v.abs()).sum::<f64>())
                .fold(0.0, f64::max)
                * h
                * 4.0;
            let u = t.lattice_point(s);
            let in_cell = u.iter().all(|c| {
                let fr = c - c.floor();
                fr > reach && fr < 1.0 - reach
            });
            let n = t.basis_at(s, m.mnoise_scale).value;
            in_cell
                && (!t.turbulence || n.abs() > 1e-6)
                && (t.basis != Basis::MNoise || n.abs() < 0.999)
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        #[test]
        fn model_gradient_matches_finite_differences(
            seed in any::<u64>(), nterms in 0usize..7,
            s in prop::array::uniform3(-4.0f64..4.0),
        ) {
            let m = random_model(seed, nterms);
            let h = 1e-6;
            prop_assume!(smooth_at(&m, s, h));
            let (_, g) = m.f_and_grad(s);
            for i in 0..3 {
                let mut a = s;
                let mut b = s;
                a[i] += h;
                b[i] -= h;
                let fd = (m.f(a) - m.f(b)) / (2.0 * h);
                prop_assert!((fd - g[i]).abs() <= 1e-5 * (1.0 + g[i].abs()),
                    "axis {}: analytic {} fd {} (seed {}, {} terms)", i, g[i], fd, seed, nterms);
            }
        }

        #[test]
        fn filter_width_is_n_times_norm(
            seed in any::<u64>(), s in prop::array::uniform3(-4.0f64..4.0),
            dsdx in prop::array::uniform3(-0.01f64..0.01), dsdy in prop::array::uniform3(-0.01f64..0.01),
        ) {
            let m = random_model(seed, 4);
            let fp = Footprint { s, dsdx, dsdy };
            let g = m.grad(s);
            let gx = dot(g, dsdx);
            let gy = dot(g, dsdy);
            for (norm, v) in [(Norm::L1, gx.abs() + gy.abs()), (Norm::L2, (gx * gx + gy * gy).sqrt()), (Norm::Max, gx.abs().max(gy.abs()))] {
                let w = m.filter_width(&fp, 256, norm, false);
                prop_assert!((w - (256.0 * v).min(256.0)).abs() <= 1e-9 * (1.0 + w));
            }
            // Steps this small never pass the Nyquist limit (|M| <= 4 per entry, 3 entries).
            prop_assert_eq!(m.filter_width(&fp, 256, Norm::L2, true), m.filter_width(&fp, 256, Norm::L2, false));
        }
    }

    #[test]
    fn zone_plate_width() {
        // Hart et al. 1999 3.4: f = 50 s^2 + 50 t^2, ds/dx = dt/dy = 1/256: df/dx = 100 s / 256.
        let m = RefModel::new(
            [50.0, 0.0, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            Vec::new(),
            Wrap::Mod,
        );
        let fp = Footprint {
            s: [0.25, 0.5, 0.5],
            dsdx: [1.0 / 256.0, 0.0, 0.0],
            dsdy: [0.0, 1.0 / 256.0, 0.0],
        };
        let gx = 100.0 * 0.25 / 256.0;
        let gy = 100.0 * 0.5 / 256.0;
        assert_eq!(m.f(fp.s), 50.0 * (0.0625 + 0.25));
        assert!((m.filter_width(&fp, 16, Norm::L1, false) - 16.0 * (gx + gy)).abs() < 1e-12);
        assert!((m.filter_width(&fp, 16, Norm::Max, false) - 16.0 * gy).abs() < 1e-12);
        assert!((m.filter_width(&fp, 16, Norm::L2, false) - 16.0 * gx.hypot(gy)).abs() < 1e-12);
        // Saturates at N.
        assert_eq!(
            m.filter_width(&fp, 1024, Norm::L1, false),
            1024.0 * (gx + gy)
        );
        let far = Footprint {
            s: [20.0, 20.0, 0.0],
            ..fp
        };
        assert_eq!(m.filter_width(&far, 16, Norm::L1, false), 16.0);
    }

    #[test]
    fn nyquist_rule() {
        let term = RefTerm::scaled(0.25, Basis::Gradient, 64.0, [0.5, 0.25, 0.125]);
        let m = RefModel::new(
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0],
            vec![term],
            Wrap::Mod,
        );
        let s = [0.3, 0.7, 0.2];
        // 64 / 128 = 1/2 cell per pixel: resolved.
        let fine = Footprint {
            s,
            dsdx: [1.0 / 128.0, 0.0, 0.0],
            dsdy: [0.0, 1.0 / 256.0, 0.0],
        };
        assert!(!term.past_nyquist(fine.dsdx, fine.dsdy));
        assert_eq!(m.f_at(&fine, Nyquist::Cull), m.f(s));
        // Exactly half a cell a pixel is still resolved; one cell is past the limit but unfaded.
        assert!(!term.past_nyquist([1.0 / 128.0, 0.0, 0.0], [0.0; 3]));
        assert!(term.past_nyquist([1.0 / 64.0, 0.0, 0.0], [0.0; 3]));
        assert_eq!(
            term.band([1.0 / 64.0, 0.0, 0.0], [0.0; 3], Nyquist::Cull)
                .weight,
            1.0
        );
        // 64 / 16 = 4 cells a pixel along y, a quarter along x: the footprint covers four cells,
        // faded to 1 / sqrt(4) = 1/2.
        let coarse = Footprint {
            s,
            dsdx: [1.0 / 256.0, 0.0, 0.0],
            dsdy: [0.0, 1.0 / 16.0, 0.0],
        };
        assert!(term.past_nyquist(coarse.dsdx, coarse.dsdy));
        assert_eq!(term.reach(coarse.dsdx, coarse.dsdy), 4.0);
        let q = s[2]; // f without the noise: the quadric 2 I r = r
        let u = term.lattice_point(s);
        let n = gradient_noise(u, Fade::Smooth, HashKind::default()).value;
        assert!((m.f_at(&coarse, Nyquist::Cull) - (q + 0.25 * 0.5 * n)).abs() < 1e-15);
        assert!((m.f_at(&coarse, Nyquist::Widen) - (q + 0.25 * n)).abs() < 1e-15);
        assert_eq!(m.f_at(&coarse, Nyquist::Evaluate), m.f(s));
        // Far away the weight stops at 1/4; a small term is culled there.
        let far = [0.0, 1.0, 0.0];
        assert_eq!(term.band([0.0; 3], far, Nyquist::Cull).weight, 0.25);
        let small = RefTerm::scaled(1.0 / 128.0, Basis::Gradient, 64.0, [0.0; 3]);
        assert_eq!(small.band([0.0; 3], far, Nyquist::Cull).weight, 0.0);
        // Width: quadric part N * |dr/dx, dr/dy| = 0 here, plus the spread sqrt(12 var).
        let n_entries = 64;
        let sigma = term.sigma();
        let full = (0.25 * sigma).powi(2);
        let w_cull = m.filter_width(&coarse, n_entries, Norm::L1, true);
        assert!((w_cull - 64.0 * (12.0 * full * 0.75 * (1.0 - 0.25)).sqrt()).abs() < 1e-12);
        let w_widen = m.filter_width_with(&coarse, n_entries, Norm::L1, Nyquist::Widen);
        assert!((w_widen - 64.0 * (12.0 * full).sqrt()).abs() < 1e-12);
        let (gx, gy, extra) = m.screen_derivatives(&coarse, Nyquist::Evaluate);
        assert_eq!(extra, 0.0);
        let w_eval = m.filter_width(&coarse, n_entries, Norm::L1, false);
        assert!((w_eval - (64.0 * (gx.abs() + gy.abs())).min(64.0)).abs() < 1e-12);
    }

    #[test]
    fn turbulence_and_chain_rule() {
        let mut term = RefTerm::scaled(-0.5, Basis::Value, 3.0, [0.1, 0.2, 0.3]);
        term.fade = Fade::Quintic;
        term.hash = HashKind::Integer;
        let s = [0.45, 1.3, -0.7];
        let u = term.lattice_point(s);
        assert_eq!(u, [3.0 * 0.45 + 0.1, 3.0 * 1.3 + 0.2, 3.0 * -0.7 + 0.3]);
        let n = noise(Basis::Value, u, Fade::Quintic, HashKind::Integer, 1.0);
        let (v, g) = term.eval(s, 1.0);
        assert_eq!(v, -0.5 * n.value);
        assert_eq!(g, n.grad.map(|c| -0.5 * 3.0 * c));
        term.turbulence = true;
        let (vt, gt) = term.eval(s, 1.0);
        assert_eq!(vt, -0.5 * n.value.abs());
        let sign = n.value.signum();
        assert_eq!(gt, n.grad.map(|c| -0.5 * 3.0 * c * sign));
        assert!(vt <= 0.0);
    }

    #[test]
    fn mnoise_scale_is_used() {
        let term = RefTerm::scaled(1.0, Basis::MNoise, 1.0, [0.0; 3]);
        let mut m = RefModel::new([0.0; 10], vec![term], Wrap::Clamp);
        let s = [10.3, 4.6, 7.2];
        m.mnoise_scale = 1.0;
        let a = m.f(s);
        m.mnoise_scale = 0.5;
        assert_eq!(m.f(s), 0.5 * a);
        assert_eq!(m.table_arg(-3.0), 0.0);
        assert_eq!(m.table_arg(0.25), 0.25);
    }

    #[test]
    fn pixel_color_point_box_mip() {
        let entries: Vec<[u8; 4]> = (0..16u8).map(|i| [i * 16, 255 - i * 16, 7, 255]).collect();
        let table = RefTable::new(&entries).unwrap();
        let m = RefModel::new(
            [50.0, 0.0, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            Vec::new(),
            Wrap::Mod,
        );
        let fp = Footprint {
            s: [0.3, 0.1, 0.5],
            dsdx: [1.0 / 256.0, 0.0, 0.0],
            dsdy: [0.0, 1.0 / 256.0, 0.0],
        };
        let f = m.f(fp.s);
        let w = m.filter_width(&fp, 16, Norm::L2, false);
        assert_eq!(
            m.pixel_color(
                &fp,
                &table,
                Filter::Point(Lookup::Nearest),
                Norm::L2,
                Nyquist::Evaluate
            ),
            table.nearest(f, Wrap::Mod)
        );
        assert_eq!(
            m.point_color(fp.s, &table, Lookup::Linear),
            table.linear(f, Wrap::Mod)
        );
        assert_eq!(
            m.pixel_color(&fp, &table, Filter::Box, Norm::L2, Nyquist::Evaluate),
            table.box_filter(f, w, Wrap::Mod)
        );
        assert_eq!(
            m.pixel_color(
                &fp,
                &table,
                Filter::Mip(Lookup::Linear),
                Norm::L2,
                Nyquist::Evaluate
            ),
            table.mip(f, w, Lookup::Linear, Wrap::Mod)
        );
    }
}
