//! The hash, span and marble benchmark jobs: lattice hashes over a 256 x 256 plane, the span
//! evaluator over value-noise planes in each evaluation mode, and the marble + csat texture.
//!
//! Per target: the RISC-V soft-core class build runs only table-free code (no ROM tables); the
//! Cortex-M build additionally runs the 256-byte permutation-table hash.

// With feature `accuracy` the firmware runs the accuracy report's jobs instead of these.
#![cfg_attr(feature = "accuracy", allow(dead_code))]

use crate::job::{fold_line, Ctx, FNV_OFFSET, LINE, PLANE};
use texcore::hash::{hash61, int_hash, lattice_value, HashKind};
use texcore::span::{EvalMode, EvalOptions, Sample, SpanEvaluator};
use texcore::texture::workload;

/// A job with a bounds-checked index the optimiser cannot remove (only with feature
/// `panic-never-canary`).
#[cfg(feature = "panic-never-canary")]
pub fn panic_never_canary(ctx: &mut Ctx) -> u32 {
    let i = core::hint::black_box(LINE + 1);
    ctx.line[i]
}

/// Fills each row `y in 0..256` of the plane `z` with `f(x, y, z)` for `x in 0..256`, folding
/// each finished row (x ascending) into the checksum, rows in ascending `y`.
#[inline(always)]
fn plane(ctx: &mut Ctx, f: impl Fn(u16, u16, u16) -> u32) -> u32 {
    let z = ctx.z;
    let mut acc = FNV_OFFSET;
    for y in 0..LINE as u16 {
        for (x, px) in (0u16..).zip(ctx.line.iter_mut()) {
            *px = f(x, y, z);
        }
        acc = fold_line(acc, &ctx.line);
    }
    acc
}

/// `int_hash(x, y, 7)` over the 256x256 plane: folds the 32-bit hash.
pub fn int_hash_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, int_hash)
}

/// `lattice_value(Integer, x, y, 7)` over the plane: folds the i16 value zero-extended from its
/// 16-bit pattern (`v as u16 as u32`).
pub fn lattice_value_int_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, |x, y, z| {
        u32::from(lattice_value(HashKind::Integer, x, y, z) as u16)
    })
}

/// `hash61(x, y, 7)` (Olano's mod-61 hash, value in `0..61`) over the plane.
pub fn hash61_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, hash61)
}

/// `perm_hash(x, y, 7)` (256-byte permutation table) over the plane: folds the byte.
#[cfg(all(target_arch = "arm", feature = "perm-hash"))]
pub fn perm_hash_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, |x, y, z| u32::from(texcore::hash::perm_hash(x, y, z)))
}

/// `lattice_value(Permutation, x, y, 7)` over the plane, folded like
/// [`lattice_value_int_plane`].
#[cfg(all(target_arch = "arm", feature = "perm-hash"))]
pub fn lattice_value_perm_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, |x, y, z| {
        u32::from(lattice_value(HashKind::Permutation, x, y, z) as u16)
    })
}

/// Evaluation mode `Direct` of [`span_job`].
pub const DIRECT: u8 = 0;
/// Evaluation mode `Fd`.
pub const FD: u8 = 1;
/// Evaluation mode `Auto`.
pub const AUTO: u8 = 2;
/// Evaluation mode `Fd32`.
pub const FD32: u8 = 3;

const fn mode(m: u8) -> EvalMode {
    match m {
        DIRECT => EvalMode::Direct,
        FD => EvalMode::Fd,
        FD32 => EvalMode::Fd32,
        _ => EvalMode::Auto,
    }
}

/// One 32-bit word per sample: `f ^ gx_lo ^ rotl(gx_hi, 8) ^ rotl(gy_lo, 16) ^ rotl(gy_hi, 24)`
/// (a few instructions a pixel; the host check recomputes it).
#[inline(always)]
pub fn mix(s: &Sample) -> u32 {
    let (gx, gy) = (s.gx as u64, s.gy as u64);
    (s.f.to_bits() as u32)
        ^ (gx as u32)
        ^ ((gx >> 32) as u32).rotate_left(8)
        ^ (gy as u32).rotate_left(16)
        ^ ((gy >> 32) as u32).rotate_left(24)
}

/// The value-noise plane `PLANE x PLANE` of [`workload::plane_span`] with octave-0 step `STEP`
/// (model `ctx.fbm[M]`: 1 or 4 octaves; gradients on, culling on, mode `MODE`): each row's
/// [`mix`] words are written to the line and the row folded, rows in ascending `y`.
pub fn span_job<const M: usize, const STEP: i32, const MODE: u8>(ctx: &mut Ctx) -> u32 {
    span_plane(ctx, M, STEP, mode(MODE))
}

/// The body of [`span_job`], shared by every instance (one copy of the evaluator in flash).
#[inline(never)]
fn span_plane(ctx: &mut Ctx, m: usize, step: i32, mode: EvalMode) -> u32 {
    let Some(model) = ctx.fbm.get(m) else {
        return 0;
    };
    let mut ev = SpanEvaluator::new(
        model,
        EvalOptions {
            mode,
            gradients: true,
            cull: true,
            ..Default::default()
        },
    );
    let line = &mut ctx.line[..usize::from(PLANE)];
    let mut acc = FNV_OFFSET;
    for y in 0..PLANE {
        let span = workload::plane_span(step, y, PLANE);
        let mut px = line.iter_mut();
        ev.eval(&span, |s| {
            if let Some(p) = px.next() {
                *p = mix(&s);
            }
        });
        acc = fold_line(acc, line);
    }
    acc
}

/// The marble + csat texture (`ctx.marble[K]`: `Direct`, `Fd`, `Auto`) on the first
/// `PLANE x PLANE` pixels of the preset's check plane: colours (`Rgba8888::to_u32`) written to the
/// line, each row folded, rows in ascending `y`.
pub fn marble_job<const K: usize>(ctx: &mut Ctx) -> u32 {
    marble_plane(ctx, K)
}

/// The body of [`marble_job`], shared by every instance.
#[inline(never)]
fn marble_plane(ctx: &mut Ctx, k: usize) -> u32 {
    let Some(tex) = ctx.marble.as_mut() else {
        return 0;
    };
    tex.set_mode(match k {
        0 => EvalMode::Direct,
        1 => EvalMode::Fd,
        _ => EvalMode::Auto,
    });
    let tex = &*tex;
    let mut ev = tex.evaluator();
    let line = &mut ctx.line[..usize::from(PLANE)];
    let mut acc = FNV_OFFSET;
    for y in 0..PLANE {
        let span = workload::marble_span(y, PLANE);
        let mut px = line.iter_mut();
        ev.shade(&span, |c| {
            if let Some(p) = px.next() {
                *p = c.to_u32();
            }
        });
        acc = fold_line(acc, line);
    }
    acc
}
