//! f64 reference of Miné & Neyret's domain-perturbed materials:
//! `f = char(T1 x + S2 t(T3 x))`, `t_c(x) = sum_{i<n} 2^-i s_c(R^i 2^i x + o_c) / sum_{i<n} 2^-i`,
//! with `char = y_0` (planes) or `(y_0^2 + y_2^2) / R^2` (cylinders), computed from the material's
//! parameters with exact f64 transforms (the fixed-point side rounds each octave's matrix to 16
//! fraction bits; that rounding is part of what `check` measures).

use texcore::material::{Characteristic, PerturbedParams, CHANNEL_OFFSETS};
use texcore::transform::OCTAVE_ROTATION;

use super::model::{Footprint, Norm, RefTerm};
use super::noise::MNOISE_SCALE;
use super::table::{Filter, RefTable, Rgba, Wrap};
use crate::bridge;

/// The reference of a perturbed material.
#[derive(Clone, Debug, PartialEq)]
pub struct RefPerturbed {
    /// Linear part `T1` rows with translation.
    t1: [[f64; 4]; 3],
    /// Per channel, the octave terms (amplitude already includes `alpha_c` and the normalisation).
    channels: [Vec<RefTerm>; 3],
    characteristic: Characteristic,
    /// Wrap of the final `f`.
    pub wrap: Wrap,
}

fn mat(a: &texcore::transform::Affine3) -> [[f64; 4]; 3] {
    let m = a.matrix();
    let t = a.translation();
    [0, 1, 2].map(|i| {
        [
            m[i][0].to_num::<f64>(),
            m[i][1].to_num::<f64>(),
            m[i][2].to_num::<f64>(),
            t[i].to_num::<f64>(),
        ]
    })
}

/// `a * b` for affine maps given as rows with translation (apply `b`, then `a`).
fn compose(a: &[[f64; 4]; 3], b: &[[f64; 4]; 3]) -> [[f64; 4]; 3] {
    let mut out = [[0.0; 4]; 3];
    for i in 0..3 {
        for j in 0..4 {
            let mut v = if j == 3 { a[i][3] } else { 0.0 };
            for k in 0..3 {
                v += a[i][k] * b[k][j];
            }
            out[i][j] = v;
        }
    }
    out
}

impl RefPerturbed {
    /// From the material's parameters.
    pub fn new(p: &PerturbedParams, wrap: Wrap) -> RefPerturbed {
        let n = i32::from(p.octaves);
        let norm: f64 = 1.0 / (0..n).map(|i| 0.5f64.powi(i)).sum::<f64>();
        let rot = mat(&OCTAVE_ROTATION);
        let two = [
            [2.0, 0.0, 0.0, 0.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
        ];
        let t3 = mat(&p.t3);
        let channels = [0usize, 1, 2].map(|c| {
            let mut base = t3;
            for (i, row) in base.iter_mut().enumerate() {
                row[3] += f64::from(CHANNEL_OFFSETS[c][i]);
            }
            let mut terms = Vec::new();
            let mut m = base;
            for i in 0..n {
                terms.push(RefTerm {
                    amplitude: p.alpha[c].to_num::<f64>() * norm * 0.5f64.powi(i),
                    matrix: m,
                    basis: bridge::basis(p.basis.kind),
                    fade: bridge::fade(p.basis.fade),
                    hash: p.basis.hash,
                    turbulence: false,
                });
                m = compose(&two, &m);
                if p.rotate {
                    m = compose(&rot, &m);
                }
            }
            terms
        });
        RefPerturbed {
            t1: mat(&p.t1),
            channels,
            characteristic: p.characteristic,
            wrap,
        }
    }

    /// `y_c` and its gradient.
    fn channel(&self, c: usize, s: [f64; 3]) -> (f64, [f64; 3]) {
        let r = self.t1[c];
        let mut y = r[0] * s[0] + r[1] * s[1] + r[2] * s[2] + r[3];
        let mut g = [r[0], r[1], r[2]];
        for t in &self.channels[c] {
            let (v, gv) = t.eval(s, MNOISE_SCALE);
            y += v;
            for k in 0..3 {
                g[k] += gv[k];
            }
        }
        (y, g)
    }

    /// `f(s)` and its gradient.
    pub fn f_and_grad(&self, s: [f64; 3]) -> (f64, [f64; 3]) {
        match self.characteristic {
            Characteristic::Planes => self.channel(0, s),
            Characteristic::Cylinders { rings } => {
                let r2 = f64::from(rings) * f64::from(rings);
                let (y0, g0) = self.channel(0, s);
                let (y2, g2) = self.channel(2, s);
                let f = (y0 * y0 + y2 * y2) / r2;
                let g = [0, 1, 2].map(|k| 2.0 * (y0 * g0[k] + y2 * g2[k]) / r2);
                (f, g)
            }
        }
    }

    /// The colour of a pixel with the analytic filter (no octave culling: the ideal).
    pub fn pixel_color(
        &self,
        fp: &Footprint,
        table: &RefTable,
        filter: Filter,
        norm: Norm,
    ) -> Rgba {
        let (f, g) = self.f_and_grad(fp.s);
        let w = match filter {
            Filter::Point(_) => 0.0,
            Filter::Box | Filter::Mip(_) | Filter::Ramp => {
                let dot = |d: [f64; 3]| g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
                (table.len() as f64 * norm.apply(dot(fp.dsdx), dot(fp.dsdy)))
                    .min(table.len() as f64)
            }
        };
        table.sample(f, w, filter, self.wrap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use texcore::hash::HashKind;

    #[test]
    fn gradient_matches_differences() {
        for p in [
            texcore::presets::mn_marble(HashKind::default()),
            texcore::presets::mn_wood(HashKind::default()),
        ] {
            let r = RefPerturbed::new(&p, Wrap::Mod);
            let s = [0.31, -0.72, 0.45];
            let (_, g) = r.f_and_grad(s);
            for k in 0..3 {
                let h = 1e-6;
                let mut a = s;
                let mut b = s;
                a[k] += h;
                b[k] -= h;
                let fd = (r.f_and_grad(a).0 - r.f_and_grad(b).0) / (2.0 * h);
                assert!(
                    (fd - g[k]).abs() < 1e-4 * (1.0 + g[k].abs()),
                    "{k}: {fd} vs {}",
                    g[k]
                );
            }
        }
    }
}
