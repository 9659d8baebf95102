//! Per-sample cost of the span evaluator and the full texture path (`docs/performance.md`).
//!
//! `cargo bench -p texcore --bench span -- --warm-up-time 1 --measurement-time 3`
//!
//! Every benchmark evaluates a whole 256x256 plane (65536 samples) per iteration; criterion's
//! throughput is in samples per second, so ns/sample = 1e9 / throughput.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload;

const SIZE: u16 = 256;

fn modes() -> [(&'static str, EvalMode); 4] {
    [
        ("direct", EvalMode::Direct),
        ("fd", EvalMode::Fd),
        ("auto", EvalMode::Auto),
        ("fd32", EvalMode::Fd32),
    ]
}

fn plane(c: &mut Criterion) {
    let cases: [(&str, u8, i32); 4] = [
        ("1oct_8cells", 1, workload::CELLS_8),
        ("4oct_8cells", 4, workload::CELLS_8),
        ("4oct_zoom_in", 4, workload::ZOOM_IN),
        ("4oct_zoom_out", 4, workload::ZOOM_OUT),
    ];
    let mut g = c.benchmark_group("span");
    g.throughput(Throughput::Elements(u64::from(SIZE) * u64::from(SIZE)));
    for (name, oct, step) in cases {
        let model = workload::value_fbm(oct, HashKind::Permutation);
        for (mname, mode) in modes() {
            g.bench_with_input(BenchmarkId::new(name, mname), &mode, |b, &mode| {
                b.iter(|| {
                    let mut ev = SpanEvaluator::new(
                        &model,
                        EvalOptions {
                            mode,
                            gradients: true,
                            cull: true,
                            ..Default::default()
                        },
                    );
                    let mut acc = workload::FNV_OFFSET;
                    for y in 0..SIZE {
                        let span = workload::plane_span(step, y, SIZE);
                        ev.eval(&span, |s| acc = workload::fold_sample(acc, &s));
                    }
                    black_box(acc)
                })
            });
        }
    }
    g.finish();
}

fn texture(c: &mut Criterion) {
    let mut g = c.benchmark_group("texture");
    g.throughput(Throughput::Elements(u64::from(SIZE) * u64::from(SIZE)));
    for (mname, mode) in modes() {
        let Some(tex) = workload::marble_csat(HashKind::Permutation, mode) else {
            continue;
        };
        g.bench_function(BenchmarkId::new("marble_csat", mname), |b| {
            b.iter(|| {
                let mut ev = tex.evaluator();
                let mut acc = workload::FNV_OFFSET;
                for y in 0..SIZE {
                    let span = workload::marble_span(y, SIZE);
                    ev.shade(&span, |c| acc = workload::fold(acc, c.to_u32()));
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, plane, texture);
criterion_main!(benches);
