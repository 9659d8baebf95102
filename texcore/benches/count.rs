//! Deterministic host cost: runs one workload of `texcore::texture::workload` once, for an
//! instruction counter (`docs/performance.md`):
//!
//! ```sh
//! cargo bench -p texcore --bench count --no-run   # prints the binary's path
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/deps/count-* span_4oct_fd
//! ```
//!
//! Case names are those of the device jobs without the hash suffix (`span_<case>_<mode>`,
//! `marble_csat_<mode>`); the plane is 256x256 with the permutation hash. Without an argument
//! (as `cargo bench` runs it) it runs every case once and prints the checksums.

use std::hint::black_box;
use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload;

const SIZE: u16 = 256;

fn mode(m: &str) -> Option<EvalMode> {
    Some(match m {
        "direct" => EvalMode::Direct,
        "fd" => EvalMode::Fd,
        "auto" => EvalMode::Auto,
        "fd32" => EvalMode::Fd32,
        _ => return None,
    })
}

fn run(case: &str) -> Option<u32> {
    let (what, m) = case.rsplit_once('_')?;
    let m = mode(m)?;
    let mut acc = workload::FNV_OFFSET;
    if what == "marble_csat" {
        let tex = workload::marble_csat(HashKind::Permutation, m)?;
        let mut ev = tex.evaluator();
        for y in 0..SIZE {
            ev.shade(&workload::marble_span(y, SIZE), |c| {
                acc = workload::fold(acc, c.to_u32())
            });
        }
        return Some(acc);
    }
    let (oct, step) = match what {
        "span_1oct" => (1, workload::CELLS_8),
        "span_4oct" => (4, workload::CELLS_8),
        "span_zoomin4" => (4, workload::ZOOM_IN),
        "span_zoomout4" => (4, workload::ZOOM_OUT),
        _ => return None,
    };
    let model = workload::value_fbm(oct, HashKind::Permutation);
    let mut ev = SpanEvaluator::new(
        &model,
        EvalOptions {
            mode: m,
            gradients: true,
            cull: true,
            ..Default::default()
        },
    );
    for y in 0..SIZE {
        ev.eval(&workload::plane_span(step, y, SIZE), |s| {
            acc = workload::fold_sample(acc, &s)
        });
    }
    Some(acc)
}

fn main() {
    let cases: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let all = [
        "span_1oct",
        "span_4oct",
        "span_zoomin4",
        "span_zoomout4",
        "marble_csat",
    ];
    let cases = if cases.is_empty() {
        all.iter()
            .flat_map(|c| ["direct", "fd", "auto", "fd32"].map(|m| format!("{c}_{m}")))
            .collect()
    } else {
        cases
    };
    for c in cases {
        match run(&c) {
            Some(sum) => println!("{c} {:#010x}", black_box(sum)),
            None => eprintln!("unknown case {c}"),
        }
    }
}
