//! The job lists of the peer-comparison firmware (feature `peers`): every row of
//! [`crate::peers::rows`] as `peers:<workload>:<implementation>` with its `/setup` job, then
//! `peers:fold` (see [`crate::peers`]), over the whole plane ([`PLANE`]) or one band ([`BAND`]).
//!
//! The firmware links one of the two lists (`peers` or `peers-band`); the other is never
//! referenced and not linked.

use crate::job::{Ctx, Job, HASH};
use crate::peers::{fold_only, run, Implementation};
use texcore::texture::workload::peers::{self as wl, Workload};

/// Rows of the plane each job of [`PLANE`] evaluates: the whole plane.
pub const PLANE_ROWS: u16 = wl::SIZE;
/// Rows of the plane each job of [`BAND`] evaluates: one band.
pub const BAND_ROWS: u16 = wl::BAND;

fn job<const W: usize, const I: usize, const ROWS: u16>(ctx: &mut Ctx) -> u32 {
    let (Some(&w), Some(&i)) = (Workload::ALL.get(W), Implementation::ALL.get(I)) else {
        return 0;
    };
    run(w, i, HASH, ROWS, &mut ctx.line)
}

fn fold_job<const ROWS: u16>(ctx: &mut Ctx) -> u32 {
    fold_only(ROWS, &mut ctx.line)
}

/// A row's job and its `/setup` job (no rows): workload index `W` in `Workload::ALL` named `$w`,
/// implementation index `I` in `Implementation::ALL` named `$i`, `$rows` rows.
macro_rules! row {
    ($rows:ident, $w:literal, $i:literal, $wn:literal, $in:literal) => {
        [
            crate::job!(concat!("peers:", $wn, ":", $in), job::<$w, $i, $rows>),
            crate::job!(concat!("peers:", $wn, ":", $in, "/setup"), job::<$w, $i, 0>),
        ]
    };
}

/// Every row of the three texcore modes (indices 0..3).
macro_rules! texcore_rows {
    ($rows:ident, $w:literal, $wn:literal) => {
        [
            row!($rows, $w, 0, $wn, "texcore-fd"),
            row!($rows, $w, 1, $wn, "texcore-auto"),
            row!($rows, $w, 2, $wn, "texcore-direct"),
        ]
    };
}

/// Jobs in a list: `peers:fold` and its set-up, the 27 texcore rows of the three exact modes,
/// the 2 `texcore-fused` rows, the 2 `texcore-ramp` and 2 `texcore-ramp-diff` rows and the 6
/// fastnoise-lite rows, each with its set-up.
const LEN: usize = 2 * (27 + 2 + 2 + 2 + 6) + 2;

/// The job list with `ROWS` rows a job, in report order.
const fn list<const ROWS: u16>() -> [Job; LEN] {
    let texcore: [[[Job; 2]; 3]; 9] = [
        texcore_rows!(ROWS, 0, "value-1oct"),
        texcore_rows!(ROWS, 1, "value-4oct"),
        texcore_rows!(ROWS, 2, "value-4oct-grad"),
        texcore_rows!(ROWS, 3, "value-4oct-span16"),
        texcore_rows!(ROWS, 4, "marble-csat-rgb565"),
        texcore_rows!(ROWS, 5, "marble-csat-rgb565-span16"),
        texcore_rows!(ROWS, 6, "smooth-1oct"),
        texcore_rows!(ROWS, 7, "perlin-1oct"),
        texcore_rows!(ROWS, 8, "perlin-4oct"),
    ];
    let others: [[Job; 2]; 12] = [
        row!(ROWS, 7, 3, "perlin-1oct", "texcore-fused"),
        row!(ROWS, 8, 3, "perlin-4oct", "texcore-fused"),
        row!(ROWS, 4, 4, "marble-csat-rgb565", "texcore-ramp"),
        row!(ROWS, 5, 4, "marble-csat-rgb565-span16", "texcore-ramp"),
        row!(ROWS, 4, 5, "marble-csat-rgb565", "texcore-ramp-diff"),
        row!(ROWS, 5, 5, "marble-csat-rgb565-span16", "texcore-ramp-diff"),
        row!(ROWS, 0, 6, "value-1oct", "fastnoise-lite"),
        row!(ROWS, 1, 6, "value-4oct", "fastnoise-lite"),
        row!(ROWS, 3, 6, "value-4oct-span16", "fastnoise-lite"),
        row!(ROWS, 6, 6, "smooth-1oct", "fastnoise-lite"),
        row!(ROWS, 7, 6, "perlin-1oct", "fastnoise-lite"),
        row!(ROWS, 8, 6, "perlin-4oct", "fastnoise-lite"),
    ];
    let mut out = [crate::job!("peers:fold", fold_job::<ROWS>); LEN];
    out[1] = crate::job!("peers:fold/setup", fold_job::<0>);
    let mut k = 2;
    let mut w = 0;
    while w < texcore.len() {
        let mut i = 0;
        while i < texcore[w].len() {
            out[k] = texcore[w][i][0];
            out[k + 1] = texcore[w][i][1];
            k += 2;
            i += 1;
        }
        w += 1;
    }
    let mut f = 0;
    while f < others.len() {
        out[k] = others[f][0];
        out[k + 1] = others[f][1];
        k += 2;
        f += 1;
    }
    out
}

/// Every peer-comparison job over the whole plane ([`PLANE_ROWS`] rows a job): `peers:fold`, the
/// texcore rows of the exact modes, then the `texcore-fused`, the `texcore-ramp`, the
/// `texcore-ramp-diff` and the fastnoise-lite rows.
pub static PLANE: &[Job] = &PLANE_LIST;
static PLANE_LIST: [Job; LEN] = list::<PLANE_ROWS>();

/// The same jobs over one band of the plane ([`BAND_ROWS`] rows a job).
pub static BAND: &[Job] = &BAND_LIST;
static BAND_LIST: [Job; LEN] = list::<BAND_ROWS>();
