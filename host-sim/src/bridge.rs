//! Conversions from texcore's fixed-point descriptions to the f64 reference.
//!
//! Only parameters cross this bridge (coefficients, amplitudes, transforms, basis choices, table
//! entries); the reference evaluates them with its own, independent arithmetic.

use texcore::model::TextureModel;
use texcore::noise::{BasisKind, Fade};
use texcore::presets::CheckPlane;
use texcore::table::TableWrap;

use crate::reference::model::{RefModel, RefTerm};
use crate::reference::noise::{Basis, Fade as RefFade};
use crate::reference::plane::Plane;
use crate::reference::table::Wrap;

/// The reference's wrap flag.
pub fn wrap(w: TableWrap) -> Wrap {
    match w {
        TableWrap::Mod => Wrap::Mod,
        TableWrap::Clamp => Wrap::Clamp,
    }
}

/// The reference's fade.
pub fn fade(f: Fade) -> RefFade {
    match f {
        Fade::Linear => RefFade::Linear,
        Fade::Smooth => RefFade::Smooth,
        Fade::Quintic => RefFade::Quintic,
    }
}

/// The reference's basis.
pub fn basis(b: BasisKind) -> Basis {
    match b {
        BasisKind::Value => Basis::Value,
        BasisKind::Gradient => Basis::Gradient,
        BasisKind::Modified => Basis::MNoise,
    }
}

/// The f64 reference of a fixed-point model, with the same parameters.
pub fn ref_model<const T: usize>(m: &TextureModel<T>) -> RefModel {
    let quadric = m.quadric().coefficients().map(|c| c.to_num::<f64>());
    let terms = m
        .terms()
        .iter()
        .map(|t| {
            let mm = t.transform.matrix();
            let tt = t.transform.translation();
            let row = |i: usize| {
                [
                    mm[i][0].to_num::<f64>(),
                    mm[i][1].to_num::<f64>(),
                    mm[i][2].to_num::<f64>(),
                    tt[i].to_num::<f64>(),
                ]
            };
            RefTerm {
                amplitude: t.amplitude.to_num::<f64>(),
                matrix: [row(0), row(1), row(2)],
                basis: basis(t.basis.kind),
                fade: fade(t.basis.fade),
                hash: t.basis.hash,
                turbulence: t.turbulence,
            }
        })
        .collect();
    RefModel::new(quadric, terms, wrap(m.wrap()))
}

/// The reference plane of a preset's check plane at `width x height` pixels: the same pixel
/// centres as the fixed-point spans (`origin + (x + 1/2) step_x + (y + 1/2) step_y`).
pub fn ref_plane(p: &CheckPlane, width: u32, height: u32) -> Plane {
    let f = |raw: i32| f64::from(raw) / 65536.0;
    Plane {
        origin: p.origin.map(f),
        x_axis: p.step_x.map(|v| f(v) * f64::from(width)),
        y_axis: p.step_y.map(|v| f(v) * f64::from(height)),
        width,
        height,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::model::Nyquist;
    use texcore::format::TexPoint;
    use texcore::hash::HashKind;
    use texcore::span::{EvalOptions, Span, SpanEvaluator};

    #[test]
    fn preset_models_agree_with_reference_f() {
        for name in texcore::presets::NAMES {
            let Some(p) = texcore::presets::by_name(name, HashKind::default()) else {
                continue;
            };
            let r = ref_model(&p.model);
            let plane = ref_plane(&p.plane, 64, 64);
            let mut ev = SpanEvaluator::new(&p.model, EvalOptions::default());
            let mut worst: f64 = 0.0;
            for y in 0..64u32 {
                let s0 = [0, 1, 2].map(|i| {
                    p.plane.origin[i]
                        + p.plane.step_x[i] / 2
                        + p.plane.step_y[i] * (2 * y as i32 + 1) / 2
                });
                let span = Span {
                    s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
                    ds: TexPoint::from_bits(
                        p.plane.step_x[0],
                        p.plane.step_x[1],
                        p.plane.step_x[2],
                    ),
                    dsdy: TexPoint::from_bits(
                        p.plane.step_y[0],
                        p.plane.step_y[1],
                        p.plane.step_y[2],
                    ),
                    len: 64,
                };
                let mut x = 0u32;
                ev.eval(&span, |smp| {
                    let want = r.table_arg(r.f_at(&plane.footprint(x, y), Nyquist::Cull));
                    let got = r.table_arg(smp.f.to_num::<f64>());
                    let mut d = (got - want).abs();
                    if r.wrap == Wrap::Mod {
                        d = d.min(1.0 - d);
                    }
                    worst = worst.max(d);
                    x += 1;
                });
            }
            // Measured worst: 3.3e-4 (planet); zone plate exact.
            assert!(
                worst < 5e-4,
                "{name}: worst |f - f_ref| (table arg) = {worst}"
            );
        }
    }
}
