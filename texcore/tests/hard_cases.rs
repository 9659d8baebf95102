//! Hard cases that the other suites did not hold, and the regression tests of the fuzz targets'
//! findings (`fuzz/`, `docs/reliability.md`): the longest span a [`Span`] can describe, and
//! triangles seen at grazing angles (slivers a sub-pixel high and thousands of pixels long, with
//! the widest `1/w` ratio the format holds).

use texcore::format::TexPoint;
use texcore::format::{Amplitude, MatrixEntry, QuadricCoeff};
use texcore::hash::HashKind;
use texcore::model::{Octaves, TextureModel};
use texcore::noise::NoiseBasis;
use texcore::quadric::Quadric;
use texcore::raster::{Perspective, Rasterizer, Rect, ScreenVertex, Segment, TriangleOptions};
use texcore::span::{EvalMode, EvalOptions, Sample, Span, SpanEvaluator};
use texcore::table::TableWrap;
use texcore::transform::Affine3;

fn eval(m: &TextureModel<8>, mode: EvalMode, span: &Span) -> Vec<Sample> {
    let mut ev = SpanEvaluator::new(
        m,
        EvalOptions {
            mode,
            gradients: true,
            cull: true,
            ..Default::default()
        },
    );
    let mut out = Vec::with_capacity(usize::from(span.len));
    ev.eval(span, |s| out.push(s));
    out
}

/// A span of `u16::MAX` pixels (the longest a `Span` holds) crossing many cells of a 4-octave
/// marble: every exact mode equals direct evaluation.
#[test]
fn longest_span_is_exact() {
    let m: TextureModel<8> = TextureModel::new(
        Quadric::linear(
            QuadricCoeff::ZERO,
            QuadricCoeff::ZERO,
            QuadricCoeff::ONE,
            QuadricCoeff::ZERO,
        ),
        TableWrap::Mod,
    )
    .with_octaves(&Octaves {
        count: 4,
        base: Affine3::scale(MatrixEntry::from_num(1.5)),
        amplitude: Amplitude::ONE,
        rotate: true,
        basis: NoiseBasis::trilinear(HashKind::Integer),
        turbulence: true,
    })
    .unwrap();
    let span = Span {
        s0: TexPoint::from_f64(-300.25, 17.5, -0.125),
        ds: TexPoint::from_bits(611, -37, 5),
        dsdy: TexPoint::from_bits(3, 400, -2),
        len: u16::MAX,
    };
    let direct = eval(&m, EvalMode::Direct, &span);
    assert_eq!(direct.len(), usize::from(u16::MAX));
    for mode in [EvalMode::Fd, EvalMode::Auto] {
        assert!(
            eval(&m, mode, &span) == direct,
            "{mode:?} differs from Direct"
        );
    }
}

/// Exact top-left coverage of pixel centre `(cx, cy)` (raw 28.4) by `p` (raw 28.4).
fn covered(p: [[i64; 2]; 3], cx: i64, cy: i64) -> bool {
    let a = (p[1][0] - p[0][0]) as i128 * (p[2][1] - p[0][1]) as i128
        - (p[2][0] - p[0][0]) as i128 * (p[1][1] - p[0][1]) as i128;
    if a == 0 {
        return false;
    }
    let p = if a > 0 { p } else { [p[0], p[2], p[1]] };
    (0..3).all(|i| {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        let (dx, dy) = ((b[0] - a[0]) as i128, (b[1] - a[1]) as i128);
        let e = dx * (cy - a[1]) as i128 - dy * (cx - a[0]) as i128;
        e > 0 || (e == 0 && (dy < 0 || (dy == 0 && dx > 0)))
    })
}

/// A floor plane seen at a grazing angle: slivers under a pixel high and 4000 pixels long, one
/// end near (`1/w` at the top of `U1F31`), the other at the smallest non-zero `1/w` (a ratio of
/// 2^31). Every perspective mode covers exactly the reference's pixels once, inside the clip,
/// without panicking; `Affine` keeps the texture coordinates within the vertices' range (the
/// perspective modes' documented error bound grows with the `1/w` ratio, here 2^31).
#[test]
fn grazing_angle_slivers() {
    let clip = Rect::from_size(4096, 8);
    let tex = |s: i32| TexPoint::from_bits(s, 0, -s);
    for (y0, y1, y2) in [(0, 5, 12), (16 * 3 + 7, 16 * 3 + 9, 16 * 4), (1, 1, 127)] {
        let v = [
            ScreenVertex::from_bits(0, y0, 0, u32::MAX, tex(0)),
            ScreenVertex::from_bits(16 * 4000, y1, 65535, 1, tex(1 << 30)),
            ScreenVertex::from_bits(16 * 4000 + 5, y2, 65535, 1, tex(1 << 30)),
        ];
        let p = v.map(|q| [i64::from(q.x.to_bits()), i64::from(q.y.to_bits())]);
        for mode in [
            Perspective::Exact,
            Perspective::Every8,
            Perspective::Every16,
            Perspective::Affine,
        ] {
            let mut r = Rasterizer::new(clip);
            let mut segs = Vec::new();
            r.draw(&v, &TriangleOptions::new(mode), &mut |s: &Segment| {
                segs.push(*s)
            });
            let mut count = vec![0u8; 4096 * 8];
            for s in &segs {
                assert!(s.len >= 1 && u32::from(s.x0) + u32::from(s.len) <= 4096 && s.y < 8);
                for i in 0..s.len {
                    count[usize::from(s.y) * 4096 + usize::from(s.x0 + i)] += 1;
                    if mode == Perspective::Affine {
                        // Within the vertices' range [0, 2^30], up to the documented drift of
                        // half an LSB a step.
                        let [a, _, c] = s.s_at(i);
                        let slack = i64::from(i) + 2;
                        assert!(a >= -slack && a <= (1 << 30) + slack, "s = {a} at {s:?}");
                        assert!(c <= slack && c >= -(1 << 30) - slack, "r = {c} at {s:?}");
                    }
                }
            }
            for y in 0..8u16 {
                for x in 0..4096u16 {
                    let want = covered(p, 16 * i64::from(x) + 8, 16 * i64::from(y) + 8);
                    assert_eq!(
                        count[usize::from(y) * 4096 + usize::from(x)],
                        u8::from(want),
                        "{mode:?} ({x}, {y})"
                    );
                }
            }
        }
    }
}
