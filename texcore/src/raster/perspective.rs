//! Span output: the interpolation modes of [`Perspective`], turning a covered run into linear
//! segments.
//!
//! Perspective quotient at a pixel, per component `c` (planes of `setup`):
//!
//! ```text
//! q'    = max(1, round_half_up(Q >> qshift_c))          (1/w with 32 - qshift_c extra bits)
//! delta = round_half_up(P_c / q')                        (i64 division)
//! s     = clamp(s_0 + delta, min_i s_i, max_i s_i)
//! ```
//!
//! Jacobian at a pixel (perspective modes), per component and direction `d`:
//! `round_half_up((dP_c/dd - (delta * dQ/dd) >> qshift_c) / q')`, saturated to `i32`
//! (numerator in saturating `i128`).

// Per-component loops index several parallel `[_; 3]` arrays.
#![allow(clippy::needless_range_loop)]

use super::setup::{AffineInterp, Interp, PerspInterp, TriangleSetup};
use super::{
    div_round_i128, div_round_i64, sat_i32, tex_point, Counters, Perspective, Segment, SegmentSink,
};

/// The perspective-correct coordinates at one pixel, with what the Jacobian needs.
#[derive(Clone, Copy, Debug)]
struct PerspPoint {
    /// Clamped raw texture coordinates.
    s: [i64; 3],
    /// Unclamped quotients.
    delta: [i64; 3],
    /// Divisors used.
    q: [i64; 3],
}

fn persp_at(
    setup: &TriangleSetup,
    p: &PerspInterp,
    px: i64,
    py: i64,
    ctr: &mut Counters,
) -> PerspPoint {
    ctr.persp_points = ctr.persp_points.wrapping_add(1);
    ctr.divides = ctr.divides.wrapping_add(3);
    let qq = p.q.at(px, py);
    let mut out = PerspPoint {
        s: [0; 3],
        delta: [0; 3],
        q: [1; 3],
    };
    for c in 0..3 {
        let sh = p.qshift[c];
        let qc = if sh == 0 {
            qq
        } else {
            qq.wrapping_add(1 << (sh - 1)) >> sh
        }
        .max(1);
        let d = div_round_i64(p.p[c].at(px, py), qc);
        out.q[c] = qc;
        out.delta[c] = d;
        out.s[c] = setup.base[c]
            .saturating_add(d)
            .max(setup.lo[c])
            .min(setup.hi[c]);
    }
    out
}

/// The analytic derivative of the perspective mapping at `pt` along x (`y == false`) or y.
fn persp_deriv(p: &PerspInterp, pt: &PerspPoint, y: bool, ctr: &mut Counters) -> [i32; 3] {
    ctr.divides = ctr.divides.wrapping_add(3);
    let gq = if y { p.q.gy } else { p.q.gx };
    let mut out = [0i32; 3];
    for c in 0..3 {
        let gp = if y { p.p[c].gy } else { p.p[c].gx };
        // A gradient that fits 64 bits (every one in practice) takes the widening 64 x 64-bit
        // product, which cannot saturate; the general saturating 128-bit product otherwise.
        let prod = match i64::try_from(gq) {
            Ok(g) => crate::wide::mul_wide(pt.delta[c], g),
            Err(_) => (pt.delta[c] as i128).saturating_mul(gq),
        };
        let num = gp.saturating_sub(prod >> p.qshift[c]);
        out[c] = match i64::try_from(num) {
            Ok(n) => sat_i32(div_round_i64(n, pt.q[c]) as i128),
            Err(_) => sat_i32(div_round_i128(num, pt.q[c] as i128)),
        };
    }
    out
}

fn affine_at(setup: &TriangleSetup, a: &AffineInterp, px: i64, py: i64) -> [i64; 3] {
    let mut s = [0i64; 3];
    for c in 0..3 {
        let sh = a.shift[c];
        let v = a.planes[c].at(px, py).wrapping_add(1 << (sh - 1)) >> sh;
        s[c] = setup.base[c]
            .saturating_add(v)
            .max(setup.lo[c])
            .min(setup.hi[c]);
    }
    s
}

/// Builds a segment from raw values (all within range: see the callers).
#[inline]
fn seg(y: u16, x0: i64, len: i64, s0: [i64; 3], ds: [i32; 3], dsdy: [i32; 3]) -> Segment {
    Segment {
        y,
        x0: x0 as u16,
        len: len as u16,
        s0: tex_point(s0),
        ds: tex_point(ds.map(|v| v as i64)),
        dsdy: tex_point(dsdy.map(|v| v as i64)),
    }
}

#[inline]
fn emit<S: SegmentSink + ?Sized>(sink: &mut S, ctr: &mut Counters, seg: Segment) {
    ctr.segments = ctr.segments.wrapping_add(1);
    ctr.pixels = ctr.pixels.wrapping_add(seg.len as u64);
    sink.segment(&seg);
}

/// Emits pixels `xa..xb` of row `y` one by one with exact perspective values.
fn exact_pixels<S: SegmentSink + ?Sized>(
    setup: &TriangleSetup,
    p: &PerspInterp,
    y: u16,
    xa: i64,
    xb: i64,
    ctr: &mut Counters,
    sink: &mut S,
) {
    let py = y as i64;
    for x in xa..xb {
        let pt = persp_at(setup, p, x, py, ctr);
        let dx = persp_deriv(p, &pt, false, ctr);
        let dy = persp_deriv(p, &pt, true, ctr);
        emit(sink, ctr, seg(y, x, 1, pt.s, dx, dy));
    }
}

/// The rounded secant slope `(e - s) / steps` per component, `None` if one does not fit `i32`.
fn secant(s: &[i64; 3], e: &[i64; 3], steps: i64, ctr: &mut Counters) -> Option<[i32; 3]> {
    let mut out = [0i32; 3];
    let pow2 = steps & (steps - 1) == 0;
    if !pow2 {
        ctr.divides = ctr.divides.wrapping_add(3);
    }
    for c in 0..3 {
        let d = e[c] - s[c];
        let v = if pow2 {
            let sh = steps.trailing_zeros();
            if sh == 0 {
                d
            } else {
                (d + (1 << (sh - 1))) >> sh
            }
        } else {
            div_round_i64(d, steps)
        };
        out[c] = i32::try_from(v).ok()?;
    }
    Some(out)
}

/// Emits the covered pixels `[xa, xb)` of row `y` (all visible) as segments.
pub(crate) fn emit_run<S: SegmentSink + ?Sized>(
    setup: &TriangleSetup,
    y: u16,
    xa: u16,
    xb: u16,
    ctr: &mut Counters,
    sink: &mut S,
) {
    let (py, xa, xb) = (y as i64, xa as i64, xb as i64);
    match &setup.interp {
        Interp::Affine(a) => {
            if a.steep {
                for x in xa..xb {
                    emit(
                        sink,
                        ctr,
                        seg(y, x, 1, affine_at(setup, a, x, py), a.ds, a.dsdy),
                    );
                }
            } else {
                let s0 = affine_at(setup, a, xa, py);
                emit(sink, ctr, seg(y, xa, xb - xa, s0, a.ds, a.dsdy));
            }
        }
        Interp::Persp(p) => {
            let n: i64 = match setup.opts.perspective {
                Perspective::Every8 => 8,
                Perspective::Every16 => 16,
                // Exact (Affine never reaches here).
                _ => 1,
            };
            if n == 1 {
                exact_pixels(setup, p, y, xa, xb, ctr, sink);
                return;
            }
            let mut x = xa;
            let mut cur = persp_at(setup, p, x, py, ctr);
            while x < xb {
                // Segment ends on the next multiple of n (screen-aligned), or at the run end.
                let next = ((x / n + 1) * n).min(xb);
                let len = next - x;
                // Exact end point: the next segment's start, or the run's last pixel.
                let end_x = if next < xb { next } else { xb - 1 };
                let end = if end_x > x {
                    Some(persp_at(setup, p, end_x, py, ctr))
                } else {
                    None
                };
                match end {
                    Some(e) if len > 1 => match secant(&cur.s, &e.s, end_x - x, ctr) {
                        Some(ds) => {
                            let dsdy = persp_deriv(p, &cur, true, ctr);
                            emit(sink, ctr, seg(y, x, len, cur.s, ds, dsdy));
                        }
                        None => exact_pixels(setup, p, y, x, next, ctr, sink),
                    },
                    _ => {
                        let dsdx = persp_deriv(p, &cur, false, ctr);
                        let dsdy = persp_deriv(p, &cur, true, ctr);
                        emit(sink, ctr, seg(y, x, 1, cur.s, dsdx, dsdy));
                    }
                }
                if let (true, Some(e)) = (next < xb, end) {
                    cur = e;
                }
                x = next;
            }
        }
    }
}
