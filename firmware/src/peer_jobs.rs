//! The job list of the peer-comparison firmware (feature `peers`): every row of
//! [`crate::peers::rows`] as `peers:<workload>:<implementation>` with its `/setup` job, then
//! `peers:fold` (see [`crate::peers`]).

use crate::peers::{fold_only, run, Implementation};
use texcore::texture::workload::peers::{self as wl, Workload};
use workloads::job::{Ctx, Job, HASH};

/// Rows of the plane each job evaluates: the whole plane.
#[cfg(not(feature = "peers-band"))]
pub const ROWS: u16 = wl::SIZE;
/// Rows of the plane each job evaluates (feature `peers-band`: one band).
#[cfg(feature = "peers-band")]
pub const ROWS: u16 = wl::BAND;

fn job<const W: usize, const I: usize, const WORK: bool>(ctx: &mut Ctx) -> u32 {
    let (Some(&w), Some(&i)) = (Workload::ALL.get(W), Implementation::ALL.get(I)) else {
        return 0;
    };
    run(w, i, HASH, if WORK { ROWS } else { 0 }, &mut ctx.line)
}

fn fold_job<const WORK: bool>(ctx: &mut Ctx) -> u32 {
    fold_only(if WORK { ROWS } else { 0 }, &mut ctx.line)
}

/// A row's job and its `/setup` job: workload index `W` in `Workload::ALL` named `$w`,
/// implementation index `I` in `Implementation::ALL` named `$i`.
macro_rules! row {
    ($w:literal, $i:literal, $wn:literal, $in:literal) => {
        [
            Job {
                name: concat!("peers:", $wn, ":", $in),
                run: job::<$w, $i, true>,
            },
            Job {
                name: concat!("peers:", $wn, ":", $in, "/setup"),
                run: job::<$w, $i, false>,
            },
        ]
    };
}

/// Every row of the three texcore modes (indices 0..3).
macro_rules! texcore_rows {
    ($w:literal, $wn:literal) => {
        [
            row!($w, 0, $wn, "texcore-fd"),
            row!($w, 1, $wn, "texcore-auto"),
            row!($w, 2, $wn, "texcore-direct"),
        ]
    };
}

const R: [[[Job; 2]; 3]; 9] = [
    texcore_rows!(0, "value-1oct"),
    texcore_rows!(1, "value-4oct"),
    texcore_rows!(2, "value-4oct-grad"),
    texcore_rows!(3, "value-4oct-span16"),
    texcore_rows!(4, "marble-csat-rgb565"),
    texcore_rows!(5, "marble-csat-rgb565-span16"),
    texcore_rows!(6, "smooth-1oct"),
    texcore_rows!(7, "perlin-1oct"),
    texcore_rows!(8, "perlin-4oct"),
];

const F: [[Job; 2]; 5] = [
    row!(0, 3, "value-1oct", "fastnoise-lite"),
    row!(1, 3, "value-4oct", "fastnoise-lite"),
    row!(3, 3, "value-4oct-span16", "fastnoise-lite"),
    row!(6, 3, "smooth-1oct", "fastnoise-lite"),
    row!(7, 3, "perlin-1oct", "fastnoise-lite"),
];

const P4: [Job; 2] = row!(8, 3, "perlin-4oct", "fastnoise-lite");

const fn flatten() -> [Job; 2 * (27 + 6) + 2] {
    let mut out = [Job {
        name: "peers:fold",
        run: fold_job::<true>,
    }; 2 * (27 + 6) + 2];
    out[1] = Job {
        name: "peers:fold/setup",
        run: fold_job::<false>,
    };
    let mut k = 2;
    let mut w = 0;
    while w < 9 {
        let mut i = 0;
        while i < 3 {
            out[k] = R[w][i][0];
            out[k + 1] = R[w][i][1];
            k += 2;
            i += 1;
        }
        w += 1;
    }
    let mut f = 0;
    while f < 5 {
        out[k] = F[f][0];
        out[k + 1] = F[f][1];
        k += 2;
        f += 1;
    }
    out[k] = P4[0];
    out[k + 1] = P4[1];
    out
}

/// Every peer-comparison job: `peers:fold`, the texcore rows, then the fastnoise-lite rows.
pub static JOBS: &[Job] = &ALL;

static ALL: [Job; 2 * (27 + 6) + 2] = flatten();
