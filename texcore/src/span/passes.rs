//! The pixel kernels of the merged loop: short loops over registers, specialised per span
//! (gradients on or off, affine quadric or not), so nothing is tested per pixel.

use super::*;

/// `seg` pixels of the merged loop, specialised per span (gradients on or off, affine quadric or
/// not) so that nothing is tested per pixel; `extra` adds per-pixel (direct) terms. No addition
/// here can saturate (see [`SpanEvaluator::run_merged`]), so all are wrapping.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn pixel_loop<F: FnMut(Sample), X: FnMut(&mut i64, &mut i64, &mut i64)>(
    lean: bool,
    seg: u32,
    fv: u32,
    grads: bool,
    affine: bool,
    s: &mut Cubic,
    q: &mut QuadStep,
    emit: &mut F,
    extra: X,
) {
    if lean {
        return pixels(grads, affine, seg, fv, s, q, emit, extra);
    }
    match (grads, affine) {
        (true, true) => pixels(true, true, seg, fv, s, q, emit, extra),
        (true, false) => pixels(true, false, seg, fv, s, q, emit, extra),
        (false, true) => pixels(false, true, seg, fv, s, q, emit, extra),
        (false, false) => pixels(false, false, seg, fv, s, q, emit, extra),
    }
}

#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn pixels<F, X>(
    grads: bool,
    affine: bool,
    seg: u32,
    fv: u32,
    s: &mut Cubic,
    q: &mut QuadStep,
    emit: &mut F,
    mut extra: X,
) where
    F: FnMut(Sample),
    X: FnMut(&mut i64, &mut i64, &mut i64),
{
    // fv <= 16 (model 4.4): saying so lets 32-bit targets shift a 64-bit value in four
    // instructions instead of a general sequence with a test for shifts of 32 and more.
    let fv = fv & 31;
    for _ in 0..seg {
        let (mut n, mut gxn, mut gyn) = (s.p[0], s.gx[0], s.gy[0]);
        extra(&mut n, &mut gxn, &mut gyn);
        let f48 = q.q.wrapping_add(n >> fv);
        let f = TexValue::from_bits((f48 >> 32) as i32);
        if grads {
            emit(Sample {
                f,
                gx: q.gx.wrapping_add(gxn >> fv),
                gy: q.gy.wrapping_add(gyn >> fv),
            });
        } else {
            emit(Sample { f, gx: 0, gy: 0 });
        }
        s.p[0] = s.p[0].wrapping_add(s.p[1]);
        s.p[1] = s.p[1].wrapping_add(s.p[2]);
        s.p[2] = s.p[2].wrapping_add(s.p[3]);
        q.q = q.q.wrapping_add(q.dq);
        if !affine {
            q.dq = q.dq.wrapping_add(q.ddq);
        }
        if grads {
            s.gx[0] = s.gx[0].wrapping_add(s.gx[1]);
            s.gx[1] = s.gx[1].wrapping_add(s.gx[2]);
            s.gy[0] = s.gy[0].wrapping_add(s.gy[1]);
            s.gy[1] = s.gy[1].wrapping_add(s.gy[2]);
            if !affine {
                q.gx = q.gx.wrapping_add(q.dgx);
                q.gy = q.gy.wrapping_add(q.dgy);
            }
        }
    }
}

/// The value pass of the merged loop over `out.len()` pixels: `f = (q + (N >> fv)) >> 32` per
/// pixel, stepping the merged cubic `p` (three additions) and the quadric (one, or two when not
/// affine). State: 20 words, which fits a 32-bit core's registers (the whole merged state does
/// not). Specialised per segment: `LINEAR` when the merged polynomial is linear over it (every
/// merged term is a single-axis term, `axis`: `p[2] = p[3] = 0`, one addition a pixel) and
/// `NOQ` when the quadric is zero over it (`f = N >> (32 + fv)`, one shift of the high word).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn value_pass<const AFFINE: bool, const LINEAR: bool, const NOQ: bool>(
    out: &mut [TexValue],
    fv: u32,
    p: &mut [i64; 4],
    q: &mut QuadStep,
) {
    let fv = fv & 31;
    let (mut p0, mut p1, mut p2, p3) = (p[0], p[1], p[2], p[3]);
    let (mut qq, mut dq, ddq) = (q.q, q.dq, q.ddq);
    for o in out.iter_mut() {
        let f = if NOQ {
            (p0 >> (fv + 32)) as i32
        } else {
            (qq.wrapping_add(p0 >> fv) >> 32) as i32
        };
        *o = TexValue::from_bits(f);
        p0 = p0.wrapping_add(p1);
        if !LINEAR {
            p1 = p1.wrapping_add(p2);
            p2 = p2.wrapping_add(p3);
        }
        if !NOQ {
            qq = qq.wrapping_add(dq);
            if !AFFINE {
                dq = dq.wrapping_add(ddq);
            }
        }
    }
    p[0] = p0;
    p[1] = p1;
    p[2] = p2;
    q.q = qq;
    q.dq = dq;
}

/// [`value_pass`] in the specialisation the segment allows (see there).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn value_pass_for(
    out: &mut [TexValue],
    fv: u32,
    p: &mut [i64; 4],
    q: &mut QuadStep,
    affine: bool,
) {
    let linear = p[2] == 0 && p[3] == 0;
    let noq = q.q == 0 && q.dq == 0 && q.ddq == 0;
    match (noq, linear, affine) {
        (true, true, _) => value_pass::<true, true, true>(out, fv, p, q),
        (true, false, _) => value_pass::<true, false, true>(out, fv, p, q),
        (false, true, true) => value_pass::<true, true, false>(out, fv, p, q),
        (false, true, false) => value_pass::<false, true, false>(out, fv, p, q),
        (false, false, true) => value_pass::<true, false, false>(out, fv, p, q),
        (false, false, false) => value_pass::<false, false, false>(out, fv, p, q),
    }
}

/// [`value_pass`] of a linear merged state (the axial kernel's: every term a single-axis term),
/// specialised for a zero quadric and an affine one.
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn value_pass_linear(
    out: &mut [TexValue],
    fv: u32,
    p: &mut [i64; 4],
    q: &mut QuadStep,
    affine: bool,
) {
    let noq = q.q == 0 && q.dq == 0 && q.ddq == 0;
    match (noq, affine) {
        (true, _) => value_pass::<true, true, true>(out, fv, p, q),
        (false, true) => value_pass::<true, true, false>(out, fv, p, q),
        (false, false) => value_pass::<false, true, false>(out, fv, p, q),
    }
}

/// A gradient pass of the merged loop: `g_out = qg + (G >> fv)` per pixel, stepping the merged
/// quadratic `g` (two additions) and the quadric's gradient `qg` (constant when affine).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn grad_pass<const AFFINE: bool, const LINEAR: bool>(
    out: &mut [i64],
    fv: u32,
    g: &mut [i64; 3],
    qg: &mut i64,
    dqg: i64,
) {
    let fv = fv & 31;
    let (mut g0, mut g1, g2) = (g[0], g[1], g[2]);
    let mut q = *qg;
    for o in out.iter_mut() {
        *o = q.wrapping_add(g0 >> fv);
        g0 = g0.wrapping_add(g1);
        if !LINEAR {
            g1 = g1.wrapping_add(g2);
        }
        if !AFFINE {
            q = q.wrapping_add(dqg);
        }
    }
    g[0] = g0;
    g[1] = g1;
    *qg = q;
}

/// [`grad_pass`], `LINEAR` when the merged gradient is linear over the segment (`g[2] = 0`: one
/// addition a pixel).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn grad_pass_for(
    out: &mut [i64],
    fv: u32,
    g: &mut [i64; 3],
    qg: &mut i64,
    dqg: i64,
    affine: bool,
) {
    match (affine, g[2] == 0) {
        (true, true) => grad_pass::<true, true>(out, fv, g, qg, dqg),
        (true, false) => grad_pass::<true, false>(out, fv, g, qg, dqg),
        (false, true) => grad_pass::<false, true>(out, fv, g, qg, dqg),
        (false, false) => grad_pass::<false, false>(out, fv, g, qg, dqg),
    }
}
