//! The peers' plane workload: the noise workloads on which texcore is compared with other noise
//! libraries (shared with the host, like `stages`; the plane and the models are
//! `texcore::texture::workload::{peers_model, peers_span}`).
//!
//! A 256 x 256 plane, pixel `(x, y)` at `s = (x / 32, y / 32, 0.37)` (8 octave-0 cells across
//! the image), `f = sum_{i < octaves} 2^-i n(2^i s)`, evaluated through
//! [`SpanEvaluator::eval`] as a user would, every sample stored to a row buffer (`f` raw; with
//! gradients the whole [`Sample`]). Each finished row is folded into an FNV-1a checksum.
//!
//! Every workload `f(hash, work)` first builds its model; with `work == false` it stops there
//! and folds the same number of (zero) rows, so the host's difference of the two counts is the
//! evaluation and the stores alone, per sample: the checksum fold is not part of the figure.
//!
//! | workload | basis | octaves | mode | gradients | spans |
//! |---|---|---:|---|---|---|
//! | `value-1oct` | trilinear value noise | 1 | `Fd` | no | whole rows |
//! | `value-4oct` | trilinear value noise | 4 | `Fd` | no | whole rows |
//! | `value-4oct-grad` | trilinear value noise | 4 | `Fd` | `gx`, `gy` | whole rows |
//! | `value-4oct-span16` | trilinear value noise | 4 | `Fd` | no | 16 pixels |
//! | `value-1oct-direct` | trilinear value noise | 1 | `Direct` | no | whole rows |
//! | `smooth-1oct` | value noise, smooth fade | 1 | `Fd` | no | whole rows |
//! | `perlin-1oct` | Perlin gradient noise, quintic fade | 1 | `Fd` | no | whole rows |

use texcore::hash::HashKind;
use texcore::noise::{BasisKind, Fade, NoiseBasis};
use texcore::span::{EvalMode, EvalOptions, Sample, SampleChunk, SpanEvaluator};
use texcore::texture::workload::{self, PEERS_SIZE};

/// FNV-1a 32-bit offset basis.
const FNV_OFFSET: u32 = 0x811C_9DC5;

#[inline(always)]
fn fold(acc: u32, word: u32) -> u32 {
    (acc ^ word).wrapping_mul(0x0100_0193)
}

/// The noise basis of a workload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// Trilinear value noise.
    Value,
    /// Value noise with the smooth (`3u^2 - 2u^3`) fade.
    Smooth,
    /// Perlin's improved gradient noise with the quintic fade.
    Perlin,
}

impl Basis {
    fn noise(self, hash: HashKind) -> NoiseBasis {
        match self {
            Basis::Value => NoiseBasis::trilinear(hash),
            Basis::Smooth => NoiseBasis {
                kind: BasisKind::Value,
                fade: Fade::Smooth,
                hash,
            },
            Basis::Perlin => NoiseBasis {
                kind: BasisKind::Gradient,
                fade: Fade::Quintic,
                hash,
            },
        }
    }
}

/// One workload of the peers' plane.
#[derive(Clone, Copy, Debug)]
pub struct PeerWorkload {
    /// Name (the device job is `peers:<name>`; the peers report's `workload` column).
    pub name: &'static str,
    /// Basis.
    pub basis: Basis,
    /// Octaves.
    pub octaves: u8,
    /// Evaluation mode.
    pub mode: EvalMode,
    /// Filter-width gradients on.
    pub gradients: bool,
    /// Span length in pixels (a divisor of 256).
    pub span: u16,
}

impl PeerWorkload {
    /// Samples evaluated (the units of the per-sample figure).
    pub const fn samples(&self) -> u32 {
        PEERS_SIZE as u32 * PEERS_SIZE as u32
    }

    /// Runs the workload with `hash` (`work == false`: builds the model, folds zero rows).
    pub fn run(&self, hash: HashKind, work: bool) -> u32 {
        let model =
            core::hint::black_box(workload::peers_model(self.octaves, self.basis.noise(hash)));
        let opts = EvalOptions {
            mode: self.mode,
            gradients: self.gradients,
            cull: true,
            ..Default::default()
        };
        let mut ev = SpanEvaluator::new(&model, opts);
        if self.gradients {
            plane_samples(&mut ev, self.span, work)
        } else {
            plane_values(&mut ev, self.span, work)
        }
    }
}

/// Every workload, in firmware order.
pub const WORKLOADS: [PeerWorkload; 7] = [
    PeerWorkload {
        name: "value-1oct",
        basis: Basis::Value,
        octaves: 1,
        mode: EvalMode::Fd,
        gradients: false,
        span: PEERS_SIZE,
    },
    PeerWorkload {
        name: "value-4oct",
        basis: Basis::Value,
        octaves: 4,
        mode: EvalMode::Fd,
        gradients: false,
        span: PEERS_SIZE,
    },
    PeerWorkload {
        name: "value-4oct-grad",
        basis: Basis::Value,
        octaves: 4,
        mode: EvalMode::Fd,
        gradients: true,
        span: PEERS_SIZE,
    },
    PeerWorkload {
        name: "value-4oct-span16",
        basis: Basis::Value,
        octaves: 4,
        mode: EvalMode::Fd,
        gradients: false,
        span: 16,
    },
    PeerWorkload {
        name: "value-1oct-direct",
        basis: Basis::Value,
        octaves: 1,
        mode: EvalMode::Direct,
        gradients: false,
        span: PEERS_SIZE,
    },
    PeerWorkload {
        name: "smooth-1oct",
        basis: Basis::Smooth,
        octaves: 1,
        mode: EvalMode::Fd,
        gradients: false,
        span: PEERS_SIZE,
    },
    PeerWorkload {
        name: "perlin-1oct",
        basis: Basis::Perlin,
        octaves: 1,
        mode: EvalMode::Fd,
        gradients: false,
        span: PEERS_SIZE,
    },
];

/// The workload named `name` (without the `peers:` prefix).
pub fn workload(name: &str) -> Option<&'static PeerWorkload> {
    WORKLOADS.iter().find(|w| w.name == name)
}

/// `f` of every sample into a row buffer, the row folded (raw `f` words, `x` ascending).
#[inline(never)]
fn plane_values(ev: &mut SpanEvaluator<'_, { workload::TERMS }>, span: u16, work: bool) -> u32 {
    let mut line = [0u32; PEERS_SIZE as usize];
    let span = span.clamp(1, PEERS_SIZE);
    let mut acc = FNV_OFFSET;
    for y in 0..PEERS_SIZE {
        if work {
            let mut x0 = 0u16;
            while x0 < PEERS_SIZE {
                let len = span.min(PEERS_SIZE - x0);
                // The chunks' `f` slices copied into the row (the values-only consumer's path:
                // no `Sample` built a pixel).
                let mut x = usize::from(x0);
                ev.eval_chunks(&workload::peers_span(x0, y, len), &mut |c: &SampleChunk| {
                    let f = c.f();
                    if let Some(dst) = line.get_mut(x..x + f.len()) {
                        for (d, v) in dst.iter_mut().zip(f) {
                            *d = v.to_bits() as u32;
                        }
                    }
                    x += f.len();
                });
                x0 += len;
            }
        }
        let row = core::hint::black_box(&line);
        acc = row.iter().fold(acc, |a, &w| fold(a, w));
    }
    acc
}

/// Every sample into a row buffer, the row folded (per sample `f`, then `gx` and `gy`, each low
/// word then high word).
#[inline(never)]
fn plane_samples(ev: &mut SpanEvaluator<'_, { workload::TERMS }>, span: u16, work: bool) -> u32 {
    let zero = Sample {
        f: texcore::format::TexValue::ZERO,
        gx: 0,
        gy: 0,
    };
    let mut line = [zero; PEERS_SIZE as usize];
    let span = span.clamp(1, PEERS_SIZE);
    let mut acc = FNV_OFFSET;
    for y in 0..PEERS_SIZE {
        if work {
            let mut x0 = 0u16;
            while x0 < PEERS_SIZE {
                let len = span.min(PEERS_SIZE - x0);
                let mut x = usize::from(x0);
                ev.eval_chunks(&workload::peers_span(x0, y, len), &mut |c: &SampleChunk| {
                    if let Some(dst) = line.get_mut(x..x + c.len()) {
                        for (d, s) in dst.iter_mut().zip(c.iter()) {
                            *d = s;
                        }
                    }
                    x += c.len();
                });
                x0 += len;
            }
        }
        let row = core::hint::black_box(&line);
        acc = row.iter().fold(acc, |a, s| {
            let a = fold(a, s.f.to_bits() as u32);
            let a = fold(fold(a, s.gx as u32), (s.gx >> 32) as u32);
            fold(fold(a, s.gy as u32), (s.gy >> 32) as u32)
        });
    }
    acc
}
