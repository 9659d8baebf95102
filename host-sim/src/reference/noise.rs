//! f64 lattice noise bases with analytic gradients (`docs/model.md` sections 2 and 4, ideal math).
//!
//! Every basis is evaluated at a lattice point `u` (a noise term's `T_k s`, exactly, no rounding):
//! the cell index of each axis is `floor(u)` taken mod 2^16 as a `u16` (as the contract does), the
//! fraction is `u - floor(u)` in `[0, 1)`, and the eight corners are `cell + {0, 1}` with `u16`
//! wrapping. Corner values and gradient selectors come from [`texcore::hash`], which the fixed-point
//! model shares, so both sides see the same lattice.
//!
//! Interpolation is the staged lerp of the contract (x first, then y, then z) done exactly in f64
//! with the fade weights; for value noise this is the same number as the exact weighted sum of 4.2.
//! Each function returns a [`NoiseSample`]: the value and its analytic gradient with respect to `u`.
//!
//! - [`value_noise`]: corners `lattice_value(hash, ..) / 32768`, range `[-1, 1)`.
//! - [`gradient_noise`]: Perlin's improved noise, gradients from `gradient_bits(hash, ..) & 15`.
//! - [`mnoise_raw`] / [`mnoise`]: Olano's mNoise, gradients `(±1, ±1, ±1)` from bits 0, 1, 2 of
//!   `hash61`; [`mnoise`] multiplies by a scale ([`MNOISE_SCALE`]) and clamps to `[-1, 1]`.
//! - [`mnoise2_raw`]: the 2D mNoise (`hash61_2`), for the dimension-reducibility property.
//!
//! # Measured ranges (raw values, for the fixed-point normalisation)
//!
//! From `cargo test -p host-sim measure_noise_ranges -- --ignored --nocapture`: 2M uniformly
//! random lattice points per case, the 16 most extreme refined to their local extremum
//! ([`empirical_range`]); for mNoise also an exhaustive scan of every distinct cell (the hash has
//! period 61 per axis; plus the cells at the 2^16 seam); and the supremum over *any* assignment of
//! corner gradients from the basis's gradient set (no hash can exceed it).
//!
//! | basis, fade | Permutation hash | Integer hash | any-hash bound |
//! |---|---|---|---|
//! | gradient, Linear | -1.02083 .. 1.00717 | -1.03160 .. 1.03035 | ±1.06483 |
//! | gradient, Smooth | -1.01395 .. 1.00479 | -1.02131 .. 1.02032 | ±1.04491 |
//! | gradient, Quintic | -1.01117 .. 1.00384 | -1.01710 .. 1.01627 | ±1.03635 |
//! | mNoise, Linear | -1.38889 .. 1.19991 (exhaustive) | (hash61) | ±1.5 |
//! | mNoise, Smooth | -1.39548 .. 1.22975 (exhaustive) | (hash61) | ±1.5 |
//! | mNoise, Quintic | -1.40029 .. 1.25086 (exhaustive) | (hash61) | ±1.5 |
//! | value, any fade | corner values, within [-1, 1) | | [-1, 1) |
//!
//! Gradient noise therefore slightly exceeds [-1, 1] (by up to 3.6 % .. 6.5 % in the worst case).
//! An mNoise scale of `1 / 1.40029` (about 0.714) keeps the hash61 mNoise within [-1, 1] for every
//! fade; `2/3` does so for any hash.

use texcore::hash::{gradient_bits, hash61, hash61_2, lattice_value, HashKind};

/// Normalisation of raw mNoise into [-1, 1]: 2/3, as the fixed-point model (`docs/model.md` 4.3);
/// raw mNoise is bounded by 1.5 for any hash.
pub const MNOISE_SCALE: f64 = 2.0 / 3.0;

/// Fade (interpolation weight) function of a noise basis, `[0, 1] -> [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fade {
    /// `F(t) = t` (trilinear interpolation; the Bresenham-noise case).
    Linear,
    /// `F(t) = 3t^2 - 2t^3` (Perlin 1985, Olano's cubic fade).
    Smooth,
    /// `F(t) = 6t^5 - 15t^4 + 10t^3` (Perlin 2002).
    Quintic,
}

impl Fade {
    /// All fades, in declaration order.
    pub const ALL: [Fade; 3] = [Fade::Linear, Fade::Smooth, Fade::Quintic];

    /// `F(t)`.
    #[inline]
    pub fn value(self, t: f64) -> f64 {
        match self {
            Fade::Linear => t,
            Fade::Smooth => t * t * (3.0 - 2.0 * t),
            Fade::Quintic => t * t * t * (t * (6.0 * t - 15.0) + 10.0),
        }
    }

    /// `F'(t)`.
    #[inline]
    pub fn derivative(self, t: f64) -> f64 {
        match self {
            Fade::Linear => 1.0,
            Fade::Smooth => 6.0 * t * (1.0 - t),
            Fade::Quintic => {
                let u = t * (1.0 - t);
                30.0 * u * u
            }
        }
    }
}

/// A noise basis (`docs/model.md` section 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Basis {
    /// Lattice value noise.
    Value,
    /// Perlin's improved gradient noise.
    Gradient,
    /// Olano's mNoise (the hash is always `hash61`; a term's `HashKind` is ignored).
    MNoise,
}

/// A noise value and its analytic gradient with respect to the lattice point `u`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseSample {
    /// `n(u)`.
    pub value: f64,
    /// `dn/du`.
    pub grad: [f64; 3],
}

/// Cell index (`floor(u) mod 2^16` as `u16`) and fraction (`u - floor(u)`, in `[0, 1)`) of one
/// lattice coordinate.
#[inline]
pub fn cell_and_fraction(u: f64) -> (u16, f64) {
    let fl = u.floor();
    (fl.rem_euclid(65536.0) as u16, u - fl)
}

/// Perlin's improved-noise gradient for selector bits `bits` (only `bits & 15` is used): the
/// vector `g` with `grad(bits, d) = g . d` for the `grad` function of `docs/model.md` 2.4.
pub fn perlin_gradient(bits: u8) -> [f64; 3] {
    let g = bits & 15;
    let u_axis = if g < 8 { 0 } else { 1 };
    let v_axis = if g < 4 {
        1
    } else if g == 12 || g == 14 {
        0
    } else {
        2
    };
    let mut v = [0.0; 3];
    v[u_axis] += if g & 1 != 0 { -1.0 } else { 1.0 };
    v[v_axis] += if g & 2 != 0 { -1.0 } else { 1.0 };
    v
}

/// mNoise corner gradient `(±1, ±1, ±1)` for a `hash61` value: bit 0, 1, 2 negate x, y, z.
pub fn mnoise_gradient(m: u32) -> [f64; 3] {
    let sign = |bit: u32| if m & bit != 0 { -1.0 } else { 1.0 };
    [sign(1), sign(2), sign(4)]
}

/// A value together with its gradient: the node type of the staged interpolation.
#[derive(Clone, Copy, Debug)]
struct Dual {
    v: f64,
    g: [f64; 3],
}

/// `p + w (q - p)` along `axis`, whose weight `w` has derivative `dw` along that axis.
#[inline]
fn lerp(w: f64, dw: f64, axis: usize, p: Dual, q: Dual) -> Dual {
    let diff = q.v - p.v;
    let mut g = [0.0; 3];
    for (i, gi) in g.iter_mut().enumerate() {
        *gi = p.g[i] + w * (q.g[i] - p.g[i]);
    }
    g[axis] += dw * diff;
    Dual {
        v: p.v + w * diff,
        g,
    }
}

/// Per-axis cell, fraction, fade weight and fade derivative.
struct Axis {
    cell: u16,
    frac: f64,
    w: f64,
    dw: f64,
}

impl Axis {
    fn new(u: f64, fade: Fade) -> Axis {
        let (cell, frac) = cell_and_fraction(u);
        Axis {
            cell,
            frac,
            w: fade.value(frac),
            dw: fade.derivative(frac),
        }
    }

    /// Corner cell index (`c` = 0 or 1, wrapping) and the offset from that corner to the point.
    #[inline]
    fn corner(&self, c: u16) -> (u16, f64) {
        (self.cell.wrapping_add(c), self.frac - f64::from(c))
    }
}

/// One x-y layer: `lerp_y(lerp_x(c00, c10), lerp_x(c01, c11))`; `corner(cx, cy)` gives the corner
/// node. Shared by the 2D and 3D bases so that a 3D slice at integer z is bit-identical to 2D.
#[inline]
fn layer(ax: &Axis, ay: &Axis, corner: impl Fn(u16, u16) -> Dual) -> Dual {
    let y0 = lerp(ax.w, ax.dw, 0, corner(0, 0), corner(1, 0));
    let y1 = lerp(ax.w, ax.dw, 0, corner(0, 1), corner(1, 1));
    lerp(ay.w, ay.dw, 1, y0, y1)
}

/// The 3D staged interpolation over the eight corners. `corner(cell, offset)` gives a corner node.
fn lattice3(u: [f64; 3], fade: Fade, corner: impl Fn([u16; 3], [f64; 3]) -> Dual) -> NoiseSample {
    let ax = Axis::new(u[0], fade);
    let ay = Axis::new(u[1], fade);
    let az = Axis::new(u[2], fade);
    let z_layer = |cz: u16| {
        let (z, dz) = az.corner(cz);
        layer(&ax, &ay, |cx, cy| {
            let (x, dx) = ax.corner(cx);
            let (y, dy) = ay.corner(cy);
            corner([x, y, z], [dx, dy, dz])
        })
    };
    let d = lerp(az.w, az.dw, 2, z_layer(0), z_layer(1));
    NoiseSample {
        value: d.v,
        grad: d.g,
    }
}

#[inline]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Lattice value noise at `u`: corner values `lattice_value(hash, corner) / 32768`.
pub fn value_noise(u: [f64; 3], fade: Fade, hash: HashKind) -> NoiseSample {
    lattice3(u, fade, |c, _| Dual {
        v: f64::from(lattice_value(hash, c[0], c[1], c[2])) / 32768.0,
        g: [0.0; 3],
    })
}

/// A corner value `v` (an integer in `[-32768, 32767]`) quantised to `bits` bits as
/// `docs/model.md` 3.2 defines it: rounded half up to a multiple of `2^(16 - bits)`, saturated to
/// `32768 - 2^(16 - bits)`; unchanged for `bits >= 16`.
pub fn quantize_value(v: f64, bits: u32) -> f64 {
    if bits >= 16 {
        return v;
    }
    let step = 2f64.powi(16 - bits as i32);
    let q = ((v + step / 2.0) / step).floor() * step;
    q.min(32768.0 - step)
}

/// [`value_noise`] with corner values quantised to `value_bits` bits ([`quantize_value`]).
pub fn value_noise_bits(u: [f64; 3], fade: Fade, hash: HashKind, value_bits: u32) -> NoiseSample {
    lattice3(u, fade, |c, _| Dual {
        v: quantize_value(f64::from(lattice_value(hash, c[0], c[1], c[2])), value_bits) / 32768.0,
        g: [0.0; 3],
    })
}

/// Perlin's improved gradient noise at `u` (unnormalised: the contract uses it as is).
pub fn gradient_noise(u: [f64; 3], fade: Fade, hash: HashKind) -> NoiseSample {
    lattice3(u, fade, |c, d| {
        let g = perlin_gradient(gradient_bits(hash, c[0], c[1], c[2]));
        Dual { v: dot(g, d), g }
    })
}

/// Raw (unscaled, unclamped) 3D mNoise at `u`.
pub fn mnoise_raw(u: [f64; 3], fade: Fade) -> NoiseSample {
    lattice3(u, fade, |c, d| {
        let g = mnoise_gradient(hash61(c[0], c[1], c[2]));
        // Summed x, y, z in that order, so an integer-z slice (dz = 0) equals the 2D sum exactly.
        Dual {
            v: (g[0] * d[0] + g[1] * d[1]) + g[2] * d[2],
            g,
        }
    })
}

/// Scaled mNoise: `clamp(scale * raw, -1, 1)`, gradient `scale * grad raw` (zero where clamped).
pub fn mnoise_scaled(u: [f64; 3], fade: Fade, scale: f64) -> NoiseSample {
    let raw = mnoise_raw(u, fade);
    let v = raw.value * scale;
    if v.abs() > 1.0 {
        NoiseSample {
            value: v.clamp(-1.0, 1.0),
            grad: [0.0; 3],
        }
    } else {
        NoiseSample {
            value: v,
            grad: raw.grad.map(|g| g * scale),
        }
    }
}

/// mNoise with the default scale [`MNOISE_SCALE`]: `clamp(MNOISE_SCALE * raw, -1, 1)`.
pub fn mnoise(u: [f64; 3], fade: Fade) -> NoiseSample {
    mnoise_scaled(u, fade, MNOISE_SCALE)
}

/// Raw 2D mNoise at `p` (hash `hash61_2`, gradients `(±1, ±1)` from bits 0, 1): the value and
/// `[dn/dx, dn/dy]`. Equals [`mnoise_raw`] at `(p, 0)` exactly.
pub fn mnoise2_raw(p: [f64; 2], fade: Fade) -> (f64, [f64; 2]) {
    let ax = Axis::new(p[0], fade);
    let ay = Axis::new(p[1], fade);
    let d = layer(&ax, &ay, |cx, cy| {
        let (x, dx) = ax.corner(cx);
        let (y, dy) = ay.corner(cy);
        let g = mnoise_gradient(hash61_2(x, y));
        Dual {
            v: g[0] * dx + g[1] * dy,
            g: [g[0], g[1], 0.0],
        }
    });
    (d.v, [d.g[0], d.g[1]])
}

/// Evaluate `basis` at `u`. `hash` is ignored by [`Basis::MNoise`], `mnoise_scale` by the others.
pub fn noise(
    basis: Basis,
    u: [f64; 3],
    fade: Fade,
    hash: HashKind,
    mnoise_scale: f64,
) -> NoiseSample {
    match basis {
        Basis::Value => value_noise(u, fade, hash),
        Basis::Gradient => gradient_noise(u, fade, hash),
        Basis::MNoise => mnoise_scaled(u, fade, mnoise_scale),
    }
}

/// [`noise`] with value-noise corner values quantised to `value_bits` bits (the other bases have
/// integer corner gradients, which the precision knob leaves alone).
pub fn noise_bits(
    basis: Basis,
    u: [f64; 3],
    fade: Fade,
    hash: HashKind,
    mnoise_scale: f64,
    value_bits: u32,
) -> NoiseSample {
    match basis {
        Basis::Value => value_noise_bits(u, fade, hash, value_bits),
        _ => noise(basis, u, fade, hash, mnoise_scale),
    }
}

/// Raw basis value (mNoise unscaled and unclamped) — what [`empirical_range`] surveys.
pub fn noise_raw(basis: Basis, u: [f64; 3], fade: Fade, hash: HashKind) -> NoiseSample {
    match basis {
        Basis::Value => value_noise(u, fade, hash),
        Basis::Gradient => gradient_noise(u, fade, hash),
        Basis::MNoise => mnoise_raw(u, fade),
    }
}

/// Result of [`empirical_range`]: the smallest and largest values found and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseRange {
    /// Smallest value found.
    pub min: f64,
    /// A lattice point where `min` is attained.
    pub argmin: [f64; 3],
    /// Largest value found.
    pub max: f64,
    /// A lattice point where `max` is attained.
    pub argmax: [f64; 3],
}

/// SplitMix64: a small deterministic generator for surveys and tests.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` (53 bits).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Refine a local extremum of `basis` inside the cell containing `start` by projected gradient
/// steps (ascent for `sign = 1`, descent for `sign = -1`); returns the best point and value.
pub fn refine_extremum(
    basis: Basis,
    fade: Fade,
    hash: HashKind,
    start: [f64; 3],
    sign: f64,
) -> ([f64; 3], f64) {
    let lo = start.map(f64::floor);
    let eval = |p: [f64; 3]| noise_raw(basis, p, fade, hash);
    let mut p = start;
    let mut cur = eval(p);
    let mut step = 0.25;
    for _ in 0..400 {
        let g = cur.grad;
        let norm = dot(g, g).sqrt();
        if norm == 0.0 || step < 1e-13 {
            break;
        }
        let mut q = [0.0; 3];
        for i in 0..3 {
            // Stay inside the closed cell; the cell's polynomial is the noise there.
            q[i] = (p[i] + sign * step * g[i] / norm).clamp(lo[i], lo[i] + 1.0 - 1e-12);
        }
        let next = eval(q);
        if sign * next.value > sign * cur.value {
            p = q;
            cur = next;
            step *= 1.5;
        } else {
            step *= 0.5;
        }
    }
    (p, cur.value)
}

/// Survey the range of a raw basis: `samples` uniformly random lattice points (cells uniform over
/// the whole `u16` lattice, fractions uniform) from `seed`, then the 16 lowest and 16 highest are
/// refined to their local extremum by [`refine_extremum`]. A lower bound on the true range.
pub fn empirical_range(
    basis: Basis,
    fade: Fade,
    hash: HashKind,
    samples: usize,
    seed: u64,
) -> NoiseRange {
    const KEEP: usize = 16;
    let mut rng = SplitMix64(seed);
    let mut lows: Vec<(f64, [f64; 3])> = Vec::new();
    let mut highs: Vec<(f64, [f64; 3])> = Vec::new();
    let push = |list: &mut Vec<(f64, [f64; 3])>, key: f64, p: [f64; 3]| {
        if list.len() < KEEP || key > list[KEEP - 1].0 {
            list.push((key, p));
            list.sort_by(|a, b| b.0.total_cmp(&a.0));
            list.truncate(KEEP);
        }
    };
    for _ in 0..samples {
        let mut p = [0.0; 3];
        for c in p.iter_mut() {
            *c = f64::from((rng.next_u64() >> 48) as u16) + rng.next_f64();
        }
        let v = noise_raw(basis, p, fade, hash).value;
        push(&mut highs, v, p);
        push(&mut lows, -v, p);
    }
    let mut range = NoiseRange {
        min: f64::INFINITY,
        argmin: [0.0; 3],
        max: f64::NEG_INFINITY,
        argmax: [0.0; 3],
    };
    for &(_, p) in &highs {
        let (q, v) = refine_extremum(basis, fade, hash, p, 1.0);
        if v > range.max {
            range.max = v;
            range.argmax = q;
        }
    }
    for &(_, p) in &lows {
        let (q, v) = refine_extremum(basis, fade, hash, p, -1.0);
        if v < range.min {
            range.min = v;
            range.argmin = q;
        }
    }
    range
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const HASHES: [HashKind; 2] = [HashKind::Permutation, HashKind::Integer];

    fn all_cases() -> Vec<(Basis, Fade, HashKind)> {
        let mut v = Vec::new();
        for basis in [Basis::Value, Basis::Gradient, Basis::MNoise] {
            for fade in Fade::ALL {
                for hash in HASHES {
                    v.push((basis, fade, hash));
                }
            }
        }
        v
    }

    #[test]
    fn fade_endpoints_and_derivatives() {
        for fade in Fade::ALL {
            assert_eq!(fade.value(0.0), 0.0, "{fade:?}");
            assert_eq!(fade.value(1.0), 1.0, "{fade:?}");
            assert!(
                (fade.value(0.5) - 0.5).abs() < 1e-15,
                "{fade:?} symmetric midpoint"
            );
            // Symmetry F(1 - t) = 1 - F(t) and monotonicity.
            let mut prev = 0.0;
            for i in 1..=1000 {
                let t = f64::from(i) / 1000.0;
                let v = fade.value(t);
                assert!(v >= prev, "{fade:?} not monotone at {t}");
                prev = v;
                assert!((fade.value(1.0 - t) - (1.0 - v)).abs() < 1e-14);
                // Derivative against a central difference.
                let h = 1e-6;
                let fd = (fade.value(t + h) - fade.value(t - h)) / (2.0 * h);
                assert!((fd - fade.derivative(t)).abs() < 1e-8, "{fade:?} F'({t})");
            }
        }
        assert_eq!(Fade::Linear.derivative(0.0), 1.0);
        for fade in [Fade::Smooth, Fade::Quintic] {
            assert_eq!(fade.derivative(0.0), 0.0);
            assert_eq!(fade.derivative(1.0), 0.0);
        }
        // Quintic has zero second derivative at the ends; smooth does not.
        let h = 1e-5;
        let second = |f: Fade, t: f64| (f.derivative(t + h) - f.derivative(t)) / h;
        assert!(second(Fade::Quintic, 0.0).abs() < 1e-3);
        assert!((second(Fade::Smooth, 0.0) - 6.0).abs() < 1e-3);
        assert!((second(Fade::Linear, 0.0)).abs() < 1e-12);
    }

    #[test]
    fn cell_index_wraps_mod_2_16() {
        assert_eq!(cell_and_fraction(2.25), (2, 0.25));
        assert_eq!(cell_and_fraction(-0.25), (65535, 0.75));
        assert_eq!(cell_and_fraction(65536.5), (0, 0.5));
        assert_eq!(cell_and_fraction(-65537.0), (65535, 0.0));
        // Noise is periodic in 2^16 per axis (any basis; mNoise included since the cell wraps).
        for (basis, fade, hash) in all_cases() {
            let p = [3.3, 100.7, 7.1];
            let a = noise_raw(basis, p, fade, hash).value;
            let b = noise_raw(basis, [p[0] + 65536.0, p[1] - 65536.0, p[2]], fade, hash).value;
            assert!((a - b).abs() < 1e-9, "{basis:?} {fade:?}");
        }
    }

    #[test]
    fn perlin_gradients_match_grad_function() {
        // docs/model.md 2.4 written out literally.
        let grad = |g: u8, dx: f64, dy: f64, dz: f64| {
            let g = g & 15;
            let u = if g < 8 { dx } else { dy };
            let v = if g < 4 {
                dy
            } else if g == 12 || g == 14 {
                dx
            } else {
                dz
            };
            (if g & 1 != 0 { -u } else { u }) + (if g & 2 != 0 { -v } else { v })
        };
        let d = [0.3, -0.55, 0.8125];
        for bits in 0..=255u8 {
            let g = perlin_gradient(bits);
            assert_eq!(dot(g, d), grad(bits, d[0], d[1], d[2]), "bits {bits}");
            // Twelve cube-edge directions: two unit components, one zero.
            assert_eq!(g.iter().filter(|c| c.abs() == 1.0).count(), 2);
        }
        assert_eq!(perlin_gradient(0), [1.0, 1.0, 0.0]);
        assert_eq!(perlin_gradient(12), [1.0, 1.0, 0.0]);
        assert_eq!(perlin_gradient(13), [0.0, -1.0, 1.0]);
        assert_eq!(perlin_gradient(7), [-1.0, 0.0, -1.0]);
        assert_eq!(perlin_gradient(0x1E), [-1.0, 1.0, 0.0]);
    }

    #[test]
    fn value_noise_interpolates_corner_values() {
        for fade in Fade::ALL {
            for hash in HASHES {
                for (x, y, z) in [
                    (0u16, 0u16, 0u16),
                    (5, 17, 250),
                    (65535, 3, 65535),
                    (300, 400, 500),
                ] {
                    let p = [f64::from(x), f64::from(y), f64::from(z)];
                    let n = value_noise(p, fade, hash).value;
                    let v = f64::from(lattice_value(hash, x, y, z)) / 32768.0;
                    assert_eq!(n, v, "{fade:?} {hash:?} at {p:?}");
                    if fade != Fade::Linear {
                        assert_eq!(value_noise(p, fade, hash).grad, [0.0; 3]);
                    }
                }
                // Negative lattice points wrap: -1 is cell 65535.
                let n = value_noise([-1.0, 2.0, -3.0], fade, hash).value;
                let v = f64::from(lattice_value(hash, 65535, 2, 65533)) / 32768.0;
                assert_eq!(n, v);
            }
        }
        // Trilinear at the cell centre is the mean of the eight corners.
        let hash = HashKind::Integer;
        let n = value_noise([10.5, 20.5, 30.5], Fade::Linear, hash).value;
        let mut mean = 0.0;
        for c in 0..8u16 {
            mean += f64::from(lattice_value(
                hash,
                10 + (c & 1),
                20 + (c >> 1 & 1),
                30 + (c >> 2),
            )) / 32768.0
                / 8.0;
        }
        assert!((n - mean).abs() < 1e-15);
    }

    #[test]
    fn gradient_noises_vanish_on_lattice() {
        for fade in Fade::ALL {
            for hash in HASHES {
                for p in [[0.0, 0.0, 0.0], [7.0, -3.0, 1000.0], [65535.0, 1.0, 2.0]] {
                    let g = gradient_noise(p, fade, hash);
                    assert_eq!(g.value, 0.0);
                    let c = p.map(|v| cell_and_fraction(v).0);
                    let m = mnoise_raw(p, fade);
                    assert_eq!(m.value, 0.0);
                    // With F'(0) = 0 the gradient at a lattice point is the corner's gradient
                    // (the linear fade also picks up the neighbours' values there).
                    if fade != Fade::Linear {
                        let pg = perlin_gradient(gradient_bits(hash, c[0], c[1], c[2]));
                        assert_eq!(g.grad, pg);
                        assert_eq!(m.grad, mnoise_gradient(hash61(c[0], c[1], c[2])));
                    }
                }
            }
        }
    }

    #[test]
    fn mnoise_dimension_reducible() {
        let mut rng = SplitMix64(7);
        for fade in Fade::ALL {
            for _ in 0..2000 {
                // Points of the I16F16 lattice-coordinate grid (exact in f64, also after adding
                // the integer shift h61(k) below).
                let x = (rng.next_u64() % (500 << 16)) as f64 / 65536.0;
                let y = (rng.next_u64() % (500 << 16)) as f64 / 65536.0;
                let (n2, g2) = mnoise2_raw([x, y], fade);
                let n3 = mnoise_raw([x, y, 0.0], fade);
                assert_eq!(n3.value, n2, "{fade:?} z=0 at {x} {y}");
                assert_eq!([n3.grad[0], n3.grad[1]], g2);
                // z = k: hash61(x, y, k) = hash61_2(x, y + h61(k)), so shift y by h61(k).
                let k = (rng.next_u64() % 1000) as u16;
                let shift = f64::from(texcore::hash::h61(u32::from(k)));
                let (n2k, g2k) = mnoise2_raw([x, y + shift], fade);
                let n3k = mnoise_raw([x, y, f64::from(k)], fade);
                assert_eq!(n3k.value, n2k, "{fade:?} z={k} at {x} {y}");
                assert_eq!([n3k.grad[0], n3k.grad[1]], g2k);
            }
        }
        // And not trivially: off the integer plane the values differ.
        let a = mnoise_raw([1.3, 2.7, 0.4], Fade::Smooth).value;
        let (b, _) = mnoise2_raw([1.3, 2.7], Fade::Smooth);
        assert_ne!(a, b);
    }

    #[test]
    fn mnoise_scale_and_clamp() {
        let p = [12.4, 33.6, 5.5];
        let raw = mnoise_raw(p, Fade::Smooth);
        assert_eq!(
            mnoise(p, Fade::Smooth),
            mnoise_scaled(p, Fade::Smooth, MNOISE_SCALE)
        );
        let half = mnoise_scaled(p, Fade::Smooth, 0.5);
        assert_eq!(half.value, raw.value * 0.5);
        assert_eq!(half.grad, raw.grad.map(|g| g * 0.5));
        let big = mnoise_scaled(p, Fade::Smooth, 1e6);
        assert_eq!(big.value.abs(), 1.0);
        assert_eq!(big.grad, [0.0; 3]);
    }

    #[test]
    fn ranges_are_bounded() {
        // Value noise is a convex combination of corners in [-1, 1); gradient-type noise is bounded
        // by sum_c W_c max|g . d| <= 2 (Perlin) or 3 (mNoise) and by much less in practice.
        for (basis, fade, hash) in all_cases() {
            let r = empirical_range(basis, fade, hash, 20_000, 1);
            let bound = match basis {
                Basis::Value => 1.0,
                Basis::Gradient => 1.1,
                Basis::MNoise => 3.0,
            };
            assert!(
                r.min >= -bound && r.max <= bound,
                "{basis:?} {fade:?} {r:?}"
            );
            assert!(r.min < -0.4 && r.max > 0.4, "{basis:?} {fade:?} {r:?}");
            assert_eq!(noise_raw(basis, r.argmax, fade, hash).value, r.max);
        }
    }

    /// `sup_p sum_c W_c(p) max_g g . (p - c)` over the unit cell: the largest value any
    /// assignment of corner gradients from the basis's set can reach (`best` gives the best dot
    /// product for an offset). Grid search then local grid refinement.
    fn any_hash_bound(fade: Fade, best: impl Fn([f64; 3]) -> f64) -> (f64, [f64; 3]) {
        let eval = |p: [f64; 3]| {
            let mut v = 0.0;
            for c in 0..8u32 {
                let cc = [c & 1, c >> 1 & 1, c >> 2 & 1].map(f64::from);
                let mut w = 1.0;
                let mut d = [0.0; 3];
                for i in 0..3 {
                    let f = fade.value(p[i]);
                    w *= if cc[i] == 0.0 { 1.0 - f } else { f };
                    d[i] = p[i] - cc[i];
                }
                v += w * best(d);
            }
            v
        };
        let mut best_p = [0.5; 3];
        let mut best_v = f64::NEG_INFINITY;
        let n = 40;
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=n {
                    let p = [i, j, k].map(|a| f64::from(a) / f64::from(n));
                    let v = eval(p);
                    if v > best_v {
                        best_v = v;
                        best_p = p;
                    }
                }
            }
        }
        let mut step = 1.0 / f64::from(n);
        while step > 1e-10 {
            let mut improved = false;
            for a in -1..=1 {
                for b in -1..=1 {
                    for c in -1..=1 {
                        let q = [
                            best_p[0] + f64::from(a) * step,
                            best_p[1] + f64::from(b) * step,
                            best_p[2] + f64::from(c) * step,
                        ]
                        .map(|x| x.clamp(0.0, 1.0));
                        let v = eval(q);
                        if v > best_v {
                            best_v = v;
                            best_p = q;
                            improved = true;
                        }
                    }
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
        (best_v, best_p)
    }

    /// Exhaustive raw mNoise range: every distinct cell configuration (cells 0..61 per axis, the
    /// hash has period 61, plus the cells at the 2^16 wrap seam), a 4^3 grid in each, the best
    /// 64 cells refined.
    fn mnoise_exhaustive(fade: Fade) -> (f64, [f64; 3], f64, [f64; 3]) {
        let mut cells: Vec<[u16; 3]> = Vec::new();
        let axis: Vec<u16> = (0..61).chain([65534, 65535]).collect();
        for &x in &axis {
            for &y in &axis {
                for &z in &axis {
                    cells.push([x, y, z]);
                }
            }
        }
        let mut highs: Vec<(f64, [f64; 3])> = Vec::new();
        let mut lows: Vec<(f64, [f64; 3])> = Vec::new();
        for c in cells {
            let mut hi = (f64::NEG_INFINITY, [0.0; 3]);
            let mut lo = (f64::INFINITY, [0.0; 3]);
            for g in 0..64u32 {
                let off = [g & 3, g >> 2 & 3, g >> 4].map(|a| (f64::from(a) + 0.5) / 4.0);
                let p = [0, 1, 2].map(|i| f64::from(c[i]) + off[i]);
                let v = mnoise_raw(p, fade).value;
                if v > hi.0 {
                    hi = (v, p);
                }
                if v < lo.0 {
                    lo = (v, p);
                }
            }
            highs.push(hi);
            lows.push((-lo.0, lo.1));
        }
        highs.sort_by(|a, b| b.0.total_cmp(&a.0));
        lows.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut max = (f64::NEG_INFINITY, [0.0; 3]);
        let mut min = (f64::INFINITY, [0.0; 3]);
        for &(_, p) in highs.iter().take(64) {
            let (q, v) = refine_extremum(Basis::MNoise, fade, HashKind::Integer, p, 1.0);
            if v > max.0 {
                max = (v, q);
            }
        }
        for &(_, p) in lows.iter().take(64) {
            let (q, v) = refine_extremum(Basis::MNoise, fade, HashKind::Integer, p, -1.0);
            if v < min.0 {
                min = (v, q);
            }
        }
        (min.0, min.1, max.0, max.1)
    }

    /// Measurement for the fixed-point side's normalisation (run with `--ignored --nocapture`).
    #[test]
    #[ignore = "measurement: prints the empirical noise ranges"]
    fn measure_noise_ranges() {
        let samples = 2_000_000;
        for basis in [Basis::Gradient, Basis::MNoise, Basis::Value] {
            for fade in Fade::ALL {
                for hash in HASHES {
                    if basis == Basis::MNoise && hash == HashKind::Integer {
                        continue; // mNoise ignores the hash
                    }
                    let r = empirical_range(basis, fade, hash, samples, 0x5EED);
                    println!(
                        "random {basis:?} {fade:?} {hash:?}: min {:.6} at {:?}, max {:.6} at {:?}",
                        r.min, r.argmin, r.max, r.argmax
                    );
                }
            }
        }
        for fade in Fade::ALL {
            let (min, pmin, max, pmax) = mnoise_exhaustive(fade);
            println!(
                "exhaustive mNoise {fade:?}: min {min:.6} at {pmin:?}, max {max:.6} at {pmax:?}"
            );
        }
        for fade in Fade::ALL {
            let (perlin, pp) = any_hash_bound(fade, |d| {
                let mut a = d.map(f64::abs);
                a.sort_by(|x, y| y.total_cmp(x));
                a[0] + a[1]
            });
            let (m, pm) = any_hash_bound(fade, |d| d.iter().map(|x| x.abs()).sum());
            println!(
                "any-hash bound {fade:?}: gradient {perlin:.6} at {pp:?}, mNoise {m:.6} at {pm:?}"
            );
        }
    }

    fn fd_grad(f: impl Fn([f64; 3]) -> f64, p: [f64; 3], h: f64) -> [f64; 3] {
        let mut g = [0.0; 3];
        for i in 0..3 {
            let mut a = p;
            let mut b = p;
            a[i] += h;
            b[i] -= h;
            g[i] = (f(a) - f(b)) / (2.0 * h);
        }
        g
    }

    fn lattice_point() -> impl Strategy<Value = [f64; 3]> {
        // Cells anywhere in the u16 lattice (plus some negative), fractions away from the faces so
        // the central difference does not straddle a cell boundary (Linear fade has kinks there).
        // Coordinates up to a few thousand keep the f64 rounding of p +- h far below the tolerance;
        // the 2^16 wrap itself is covered by `cell_index_wraps_mod_2_16`.
        let coord = (-300i32..3000, 0.001f64..0.999).prop_map(|(c, f)| f64::from(c) + f);
        [coord.clone(), coord.clone(), coord]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn analytic_gradients_match_finite_differences(p in lattice_point(), case in 0usize..18) {
            let (basis, fade, hash) = all_cases()[case];
            let n = noise_raw(basis, p, fade, hash);
            let fd = fd_grad(|q| noise_raw(basis, q, fade, hash).value, p, 1e-5);
            for i in 0..3 {
                prop_assert!((n.grad[i] - fd[i]).abs() < 1e-6,
                    "{:?} {:?} {:?} at {:?}: analytic {:?} fd {:?}", basis, fade, hash, p, n.grad, fd);
            }
        }

        #[test]
        fn mnoise2_gradient_matches_finite_differences(
            x in 0.0f64..1000.0, y in 0.0f64..1000.0, fi in 0usize..3,
        ) {
            prop_assume!((x.fract() - 0.5).abs() < 0.499 && (y.fract() - 0.5).abs() < 0.499);
            let fade = Fade::ALL[fi];
            let h = 1e-6;
            let (_, g) = mnoise2_raw([x, y], fade);
            let gx = (mnoise2_raw([x + h, y], fade).0 - mnoise2_raw([x - h, y], fade).0) / (2.0 * h);
            let gy = (mnoise2_raw([x, y + h], fade).0 - mnoise2_raw([x, y - h], fade).0) / (2.0 * h);
            prop_assert!((g[0] - gx).abs() < 1e-6 && (g[1] - gy).abs() < 1e-6);
        }
    }
}
