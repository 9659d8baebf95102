//! The job suite's rows of the peers' plane (`peers:<workload>` in `texsim report cycles`): the
//! workloads of `texcore::texture::workload::peers` evaluated by its own row kernel
//! ([`peers::value_plane`]), the very code of `texsim report peers`' `texcore-fd` and
//! `texcore-direct` rows (`crate::peers`, feature `peers`), so that both reports measure one thing.
//!
//! A 256 x 256 plane, pixel `(x, y)` at `s = (x / 32, y / 32, 0.37)` (8 octave-0 cells across
//! the image), `f = sum_{i < octaves} 2^-i n(2^i s)`, evaluated through
//! [`SpanEvaluator::eval_values`] as a values-only user would (with gradients
//! [`SpanEvaluator::eval_chunks`]), every sample stored to a row buffer (`f`; with gradients
//! [`peers::grad_word`]). Each finished row is folded into an
//! FNV-1a checksum.
//!
//! Every workload `run(hash, work)` first builds its model; with `work == false` it stops there
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

use texcore::format::TexValue;
use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload::peers::{self, Workload};

use crate::job::{fold, FNV_OFFSET};

/// One workload of the peers' plane in the job suite.
#[derive(Clone, Copy, Debug)]
pub struct PeerWorkload {
    /// Name (the device job is `peers:<name>`).
    pub name: &'static str,
    /// The workload (model, span length, gradients).
    pub workload: Workload,
    /// Evaluation mode.
    pub mode: EvalMode,
}

impl PeerWorkload {
    /// Samples evaluated (the units of the per-sample figure).
    pub const fn samples(&self) -> u32 {
        peers::SIZE as u32 * peers::SIZE as u32
    }

    /// Runs the workload with `hash` (`work == false`: builds the model, folds zero rows); 0
    /// when this build has no such model (a basis compiled out).
    pub fn run(&self, hash: HashKind, work: bool) -> u32 {
        let Some(model) = peers::model(self.workload, hash) else {
            return 0;
        };
        let model = core::hint::black_box(model);
        let opts = EvalOptions {
            mode: self.mode,
            gradients: self.workload.gradients(),
            ..Default::default()
        };
        let mut ev = SpanEvaluator::new(&model, opts);
        plane(&mut ev, self.workload, work)
    }
}

/// Every row of the plane through [`peers::value_plane`] (`work == false`: zero rows), each folded.
#[inline(never)]
fn plane(
    ev: &mut SpanEvaluator<'_, { texcore::texture::workload::TERMS }>,
    w: Workload,
    work: bool,
) -> u32 {
    let mut line = [TexValue::ZERO; peers::SIZE as usize];
    let mut acc = FNV_OFFSET;
    let mut fold_row = |row: &[TexValue]| {
        let row = core::hint::black_box(row);
        acc = row.iter().fold(acc, |a, v| fold(a, v.to_bits() as u32));
    };
    if work {
        peers::value_plane(ev, w, peers::SIZE, &mut line, |_, row| fold_row(row));
    } else {
        for _ in 0..peers::SIZE {
            fold_row(&line);
        }
    }
    acc
}

macro_rules! workloads {
    ($($name:literal => $w:ident, $mode:ident;)*) => {
        [$(PeerWorkload {
            name: $name,
            workload: Workload::$w,
            mode: EvalMode::$mode,
        },)*]
    };
}

/// Every workload, in firmware order.
pub const WORKLOADS: [PeerWorkload; 7] = workloads! {
    "value-1oct" => Value1, Fd;
    "value-4oct" => Value4, Fd;
    "value-4oct-grad" => Value4Grad, Fd;
    "value-4oct-span16" => Value4Span16, Fd;
    "value-1oct-direct" => Value1, Direct;
    "smooth-1oct" => Smooth1, Fd;
    "perlin-1oct" => Perlin1, Fd;
};

/// The workload named `name` (without the `peers:` prefix).
pub fn workload(name: &str) -> Option<&'static PeerWorkload> {
    WORKLOADS.iter().find(|w| w.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_workloads_but_for_direct() {
        for w in WORKLOADS {
            let expect = match w.mode {
                EvalMode::Direct => "value-1oct",
                _ => w.name,
            };
            assert_eq!(w.workload.name(), expect);
            assert_eq!(
                w.name.strip_prefix(expect).unwrap_or("?"),
                match w.mode {
                    EvalMode::Direct => "-direct",
                    _ => "",
                }
            );
            assert_eq!(workload(w.name).map(|x| x.workload), Some(w.workload));
        }
        assert!(workload("nope").is_none());
    }

    #[cfg(feature = "peers")]
    #[test]
    fn the_suite_and_the_peers_report_run_the_same_rows() {
        // Both harnesses' checksums over the whole plane: the same kernel, the same words.
        for w in WORKLOADS {
            let mut line = [0u32; peers::SIZE as usize];
            let imp = match w.mode {
                EvalMode::Direct => crate::peers::Implementation::TexcoreDirect,
                _ => crate::peers::Implementation::TexcoreFd,
            };
            let report =
                crate::peers::run(w.workload, imp, HashKind::Integer, peers::SIZE, &mut line);
            assert_eq!(w.run(HashKind::Integer, true), report, "{}", w.name);
            assert_ne!(report, 0, "{}", w.name);
        }
    }
}
