//! Host cost of multipass noise (`docs/multipass.md`): a 320-pixel band of the 4-octave
//! value-noise plane through the span evaluator (`Direct`, `Fd`, `Multipass` at each precision,
//! with and without gradients), the raw band kernel (one octave, 320 points, every precision and
//! hash), and a 256x256 image of one octave (the paper's Table 1 workload).
//!
//! `cargo bench -p texcore --features multipass --bench multipass -- --warm-up-time 1 --measurement-time 3`
//!
//! Criterion's throughput is in pixels per second: ns/pixel = 1e9 / throughput.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use texcore::hash::HashKind;
use texcore::multipass::{Band, MultipassConfig, PassHash, PassPrecision, PassTerm};
use texcore::noise::Fade;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload;

const BAND: u16 = 320;

fn modes() -> Vec<(String, EvalMode)> {
    let mut v = vec![
        ("direct".to_string(), EvalMode::Direct),
        ("fd".to_string(), EvalMode::Fd),
    ];
    for p in PassPrecision::ALL {
        v.push((
            format!("multipass-{}", p.name()),
            EvalMode::Multipass(MultipassConfig::with_precision(p)),
        ));
    }
    v
}

fn band(c: &mut Criterion) {
    let model = workload::value_fbm(4, HashKind::Permutation);
    let mut g = c.benchmark_group("band320_4oct");
    g.throughput(Throughput::Elements(u64::from(BAND) * 8));
    for gradients in [true, false] {
        for (name, mode) in modes() {
            let id = format!("{name}{}", if gradients { "" } else { "-nograd" });
            g.bench_function(BenchmarkId::from_parameter(id), |b| {
                b.iter(|| {
                    let mut ev = SpanEvaluator::new(
                        &model,
                        EvalOptions {
                            mode,
                            gradients,
                            cull: true,
                            ..Default::default()
                        },
                    );
                    let mut acc = workload::FNV_OFFSET;
                    for y in 0..8 {
                        let span = workload::plane_span(workload::CELLS_8 / 2, y, BAND);
                        ev.eval(&span, |s| acc = workload::fold_sample(acc, &s));
                    }
                    black_box(acc)
                })
            });
        }
    }
    g.finish();
}

fn kernel(c: &mut Criterion) {
    let mut g = c.benchmark_group("kernel320_1oct");
    g.throughput(Throughput::Elements(u64::from(BAND)));
    for precision in PassPrecision::ALL {
        for hash in [PassHash::Texcore, PassHash::Xor] {
            for hk in [HashKind::Permutation, HashKind::Integer] {
                if hash != PassHash::Texcore && hk == HashKind::Integer {
                    continue;
                }
                let term = PassTerm {
                    hash: hk,
                    fade: Fade::Linear,
                    amp_raw: 1 << 16,
                    fv: 13,
                    value_bits: 16,
                    config: MultipassConfig { precision, hash },
                    gradients: false,
                };
                let hname = match (hash, hk) {
                    (PassHash::Texcore, HashKind::Permutation) => "perm",
                    (PassHash::Texcore, _) => "int",
                    _ => hash.name(),
                };
                let id = format!("{}-{hname}", precision.name());
                let mut b320 = Box::new(Band::<320>::new());
                g.bench_function(BenchmarkId::from_parameter(id), |b| {
                    b.iter(|| {
                        b320.run(&term, black_box([12345, 67890, 0x8040]), [3277, 0, 0], 320);
                        black_box(b320.values()[319])
                    })
                });
            }
        }
    }
    g.finish();
}

/// The paper's Table 1 workload: one octave of noise over a 256x256 image (the whole
/// span path, no gradients; `s, t` over 16 cells as in its Fig. 4).
fn image(c: &mut Criterion) {
    let model = workload::value_fbm(1, HashKind::Permutation);
    let mut g = c.benchmark_group("image256_1oct");
    g.throughput(Throughput::Elements(256 * 256));
    for (name, mode) in modes() {
        g.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| {
                let mut ev = SpanEvaluator::new(
                    &model,
                    EvalOptions {
                        mode,
                        gradients: false,
                        cull: true,
                        ..Default::default()
                    },
                );
                let mut acc = workload::FNV_OFFSET;
                for y in 0..256 {
                    let span = workload::plane_span(1 << 12, y, 256);
                    ev.eval(&span, |s| acc = workload::fold_sample(acc, &s));
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, band, kernel, image);
criterion_main!(benches);
