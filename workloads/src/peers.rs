//! The peer-comparison kernels (feature `peers`, `texsim report peers`): texcore's evaluation
//! modes next to `fastnoise-lite` (f32, `no_std` with `libm`) on the workloads of
//! `texcore::texture::workload::peers`, over the same plane.
//!
//! The peers firmware runs them as the jobs of [`crate::peer_jobs`]; the host
//! (`host_sim::report::peers`) calls the same functions to recompute every device checksum and
//! to time the same kernels. No allocation and no panics (a too-short line or a row without an
//! equivalent returns 0).
//!
//! Jobs (in [`rows`] order), each with a `/setup` twin that builds the same model, texture or
//! noise generator and evaluates no row:
//! - `peers:<workload>:<implementation>`: `ROWS` rows of the plane, each row's stored words
//!   (one per pixel, see the workload module) folded into the checksum after the row;
//! - `peers:fold`: `ROWS` folds of a 256-word line alone (the checksum's own cost, which the
//!   report subtracts).
//!
//! Instructions per sample = `(job - setup - fold) / (ROWS * 256)`.
//!
//! `ROWS` is the whole plane (256, [`crate::peer_jobs::PLANE`]) or one 8-row band
//! ([`crate::peer_jobs::BAND`], the bound test `tests/tests/peers_qemu.rs`).

use fastnoise_lite::{FastNoiseLite, FractalType, NoiseType};
use texcore::format::TexValue;
use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload::peers::{self, Workload};

pub use crate::job::{fold, FNV_OFFSET};

/// An implementation in the comparison (the device ones; the host adds `noise`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Implementation {
    /// texcore, `EvalMode::Fd`.
    TexcoreFd,
    /// texcore, `EvalMode::Auto`.
    TexcoreAuto,
    /// texcore, `EvalMode::Direct`.
    TexcoreDirect,
    /// texcore, `EvalMode::Fused` (approximate; only the gradient-noise workloads, where it
    /// differs from `Fd`).
    TexcoreFused,
    /// texcore, `EvalMode::Fd` with the pre-filtered RGB565 ramp instead of the summed-area
    /// filter (approximate; only the marble workloads, the ones with a colour stage).
    TexcoreRamp,
    /// [`Implementation::TexcoreRamp`] with the filter widths from the differences of
    /// neighbouring values instead of the gradients (approximate; the marble workloads only).
    TexcoreRampDiff,
    /// `fastnoise-lite` (f32).
    FastnoiseLite,
}

impl Implementation {
    /// Every device implementation, in report order.
    pub const ALL: [Implementation; 7] = [
        Implementation::TexcoreFd,
        Implementation::TexcoreAuto,
        Implementation::TexcoreDirect,
        Implementation::TexcoreFused,
        Implementation::TexcoreRamp,
        Implementation::TexcoreRampDiff,
        Implementation::FastnoiseLite,
    ];

    /// Name in reports.
    pub const fn name(self) -> &'static str {
        match self {
            Implementation::TexcoreFd => "texcore-fd",
            Implementation::TexcoreAuto => "texcore-auto",
            Implementation::TexcoreDirect => "texcore-direct",
            Implementation::TexcoreFused => "texcore-fused",
            Implementation::TexcoreRamp => "texcore-ramp",
            Implementation::TexcoreRampDiff => "texcore-ramp-diff",
            Implementation::FastnoiseLite => "fastnoise-lite",
        }
    }

    /// texcore's evaluation mode (`None` for a peer).
    pub const fn mode(self) -> Option<EvalMode> {
        match self {
            Implementation::TexcoreFd => Some(EvalMode::Fd),
            Implementation::TexcoreAuto => Some(EvalMode::Auto),
            Implementation::TexcoreDirect => Some(EvalMode::Direct),
            Implementation::TexcoreFused => Some(EvalMode::Fused),
            Implementation::TexcoreRamp | Implementation::TexcoreRampDiff => Some(EvalMode::Fd),
            Implementation::FastnoiseLite => None,
        }
    }
}

/// fastnoise-lite configured for workload `w` at frequency 1 (seed 1337, its default): `Value`
/// (its value noise has the smooth `3u^2 - 2u^3` fade: the equivalent of `smooth-1oct`, and the
/// nearest of the trilinear workloads) or `Perlin` (quintic fade), FBm (gain 1/2, lacunarity 2)
/// for 4 octaves. `None` when it has no equivalent (gradients, colour stages).
pub fn fastnoise(w: Workload) -> Option<FastNoiseLite> {
    let (kind, octaves) = match w {
        Workload::Value1 | Workload::Smooth1 => (NoiseType::Value, 1),
        Workload::Value4 | Workload::Value4Span16 => (NoiseType::Value, 4),
        Workload::Perlin1 => (NoiseType::Perlin, 1),
        Workload::Perlin4 => (NoiseType::Perlin, 4),
        Workload::Value4Grad | Workload::MarbleCsat | Workload::MarbleCsatSpan16 => return None,
    };
    let mut n = FastNoiseLite::new();
    n.set_noise_type(Some(kind));
    n.set_frequency(Some(1.0));
    if octaves > 1 {
        n.set_fractal_type(Some(FractalType::FBm));
        n.set_fractal_octaves(Some(octaves));
        n.set_fractal_lacunarity(Some(2.0));
        n.set_fractal_gain(Some(0.5));
    }
    Some(n)
}

/// Whether `imp` has an equivalent of `w` (a row of the report).
pub fn has(w: Workload, imp: Implementation) -> bool {
    match imp {
        Implementation::FastnoiseLite => fastnoise(w).is_some(),
        Implementation::TexcoreFused => matches!(w, Workload::Perlin1 | Workload::Perlin4),
        Implementation::TexcoreRamp | Implementation::TexcoreRampDiff => w.is_marble(),
        _ => true,
    }
}

/// The plane's `r` as the float peers see it (exact in `f32`).
pub const R: f32 = peers::R_BITS as f32 / 65536.0;

/// Row `y` of fastnoise-lite's `noise`: `get_noise_3d(x/32, y/32, R)` as `f32` bits.
#[inline(always)]
fn fastnoise_row(noise: &FastNoiseLite, y: u16, line: &mut [u32]) {
    let t = f32::from(y) * (1.0 / 32.0);
    for (x, p) in (0u16..).zip(line[..usize::from(peers::SIZE)].iter_mut()) {
        *p = noise
            .get_noise_3d(f32::from(x) * (1.0 / 32.0), t, R)
            .to_bits();
    }
}

/// Folds the first 256 words of `line`.
#[inline(always)]
fn fold_line(acc: u32, line: &[u32]) -> u32 {
    line[..usize::from(peers::SIZE)]
        .iter()
        .fold(acc, |a, &w| fold(a, w))
}

/// [`fold_line`] of a line of values (their raw bits).
fn fold_values(acc: u32, line: &[TexValue]) -> u32 {
    line.iter().fold(acc, |a, &v| fold(a, v.to_bits() as u32))
}

/// Runs `imp` on the first `rows` rows of workload `w` (lattice hash `hash` for texcore) into
/// `line` (at least 256 words), folding each row; `rows = 0` builds the model or generator and
/// stops (the `/setup` job). Returns the checksum, or 0 when the row does not exist in this build.
#[inline(never)]
pub fn run(w: Workload, imp: Implementation, hash: HashKind, rows: u16, line: &mut [u32]) -> u32 {
    if line.len() < usize::from(peers::SIZE) {
        return 0;
    }
    let mut acc = FNV_OFFSET;
    match imp.mode() {
        None => {
            let Some(noise) = fastnoise(w) else {
                return 0;
            };
            let noise = core::hint::black_box(noise);
            for y in 0..rows {
                fastnoise_row(&noise, y, line);
                acc = fold_line(acc, line);
            }
        }
        Some(mode) if w.is_marble() => {
            let ramp = matches!(
                imp,
                Implementation::TexcoreRamp | Implementation::TexcoreRampDiff
            );
            let tex = if ramp {
                marble_ramp(hash)
            } else {
                marble(hash)
            };
            let Some(mut tex) = tex else {
                return 0;
            };
            tex.set_mode(mode);
            let tex = core::hint::black_box(&tex);
            let mut ev = tex.evaluator();
            if imp == Implementation::TexcoreRampDiff {
                peers::marble_plane_differences(&mut ev, w, rows, line, |_, row| {
                    acc = fold_line(acc, row);
                });
            } else {
                peers::marble_plane(&mut ev, w, rows, line, |_, row| {
                    acc = fold_line(acc, row);
                });
            }
        }
        Some(mode) => {
            let Some(model) = peers::model(w, hash) else {
                return 0;
            };
            let model = core::hint::black_box(&model);
            let mut ev = SpanEvaluator::new(
                model,
                EvalOptions {
                    mode,
                    gradients: w.gradients(),
                    cull: true,
                    ..Default::default()
                },
            );
            // The values' own line (32-bit words as the other rows'), folded as they are.
            let mut values = [TexValue::ZERO; peers::SIZE as usize];
            peers::value_plane(&mut ev, w, rows, &mut values, |_, row| {
                acc = fold_values(acc, row);
            });
        }
    }
    acc
}

/// The marble + csat texture of the workload module (its check plane is not used: the peer
/// plane is).
fn marble(
    hash: HashKind,
) -> Option<texcore::texture::Texture<{ texcore::texture::workload::TERMS }, 256>> {
    texcore::texture::workload::marble_csat(hash, EvalMode::Auto)
}

/// The marble texture with the pre-filtered RGB565 ramp (`texcore-ramp`).
fn marble_ramp(
    hash: HashKind,
) -> Option<texcore::texture::Texture<{ texcore::texture::workload::TERMS }, 256>> {
    texcore::texture::workload::marble_ramp(hash, EvalMode::Fd)
}

/// `rows` folds of `line` alone (the `peers:fold` job).
#[inline(never)]
pub fn fold_only(rows: u16, line: &mut [u32]) -> u32 {
    let line = core::hint::black_box(line);
    let mut acc = FNV_OFFSET;
    if line.len() < usize::from(peers::SIZE) {
        return 0;
    }
    for _ in 0..rows {
        acc = fold_line(acc, line);
    }
    acc
}

/// Every `(workload, implementation)` row the device runs, in job order.
pub fn rows() -> impl Iterator<Item = (Workload, Implementation)> {
    Workload::ALL.into_iter().flat_map(|w| {
        Implementation::ALL
            .into_iter()
            .filter(move |&i| has(w, i))
            .map(move |i| (w, i))
    })
}
