//! A stage a scene does not use costs nothing: these workloads switch stages off at run time
//! (no antialiasing: no gradient or filter work; the zone plate: no noise; opaque objects: no
//! blending; affine objects: no perspective divides). Run the benchmark twice, once with every
//! feature and once with the optional stages compiled out, and compare (`docs/performance.md`):
//!
//! ```sh
//! cargo bench -p texcore --bench stages -- --warm-up-time 1 --measurement-time 3
//! cargo bench -p texcore --bench stages --no-default-features --features perm-hash -- \
//!     --warm-up-time 1 --measurement-time 3
//! ```
//!
//! The `marble` case runs in both builds; with `--features lighting` the group also has
//! `marble+lit` (compare `marble` in builds with and without `lighting` for the cost of the stage to a scene
//! without lights, `marble+lit` against `marble` for the cost of lighting).
//!
//! With `count CASE` as arguments it runs one case once, for an instruction counter
//! (`valgrind --tool=callgrind target/release/deps/stages-* count zoneplate`). With the
//! `lighting` feature, `count marble+lit` renders the marble scene with a light (the lighting
//! stage's cost is its difference from `count marble`; `count marble` itself must cost what it
//! costs without the feature: a scene without lights pays nothing for the stage).

use std::hint::black_box;

use criterion::{criterion_group, Criterion, Throughput};
use texcore::color::Rgba8888;
use texcore::filter::Antialias;
use texcore::hash::HashKind;
use texcore::render::Renderer;
use texcore::sink::ChecksumSink;
use texcore::texture::Texture;

/// A preset as a texture with no antialiasing.
fn texture(name: &str) -> Texture<8, 256> {
    let p = texcore::presets::by_name(name, HashKind::Permutation).expect("preset");
    texcore::ready::Material::model(p.model, p.keys)
        .texture(Antialias::None)
        .expect("texture")
}

/// Renders a built-in scene (still frame) with every slot's preset unfiltered; returns the
/// checksum and the pixel count.
///
/// `NAME+lit` (feature `lighting`): the scene with a directional light and ambient added (the
/// lighting stage's cost is the difference from `NAME`).
fn render_scene(name: &str) -> (u32, u64) {
    let (base, lit) = match name.strip_suffix("+lit") {
        Some(b) => (b, true),
        None => (name, false),
    };
    let scene = texcore::scene::by_name(base).expect("scene");
    #[allow(unused_mut)]
    let mut s = scene.at_frame(scene.still());
    if lit {
        #[cfg(feature = "lighting")]
        {
            use texcore::scene::math::ONE;
            let mut l = texcore::light::Lighting::new()
                .with_ambient([ONE / 8; 3])
                .expect("ambient");
            let sun = texcore::light::Light::directional(
                texcore::scene::Vec3::new(-ONE, ONE, ONE),
                [ONE; 3],
                ONE,
            )
            .expect("light");
            l.try_add(sun).expect("light");
            s.set_lighting(l);
        }
        #[cfg(not(feature = "lighting"))]
        panic!("{name}: build with --features lighting");
    }
    let textures: Vec<Texture<8, 256>> = s.slots.iter().map(|t| texture(t.material)).collect();
    let r = Renderer::new(&textures);
    let mut sink = ChecksumSink::new();
    let (w, h) = s.size();
    let n = usize::from(w) * usize::from(h);
    let stats = match r.needs_bands(&s) {
        Ok(false) => r.render_streamed(&s, &mut sink),
        _ => {
            let mut band = vec![Rgba8888::BLACK; usize::from(w) * 16];
            let mut depth = vec![0u16; usize::from(w) * 16];
            r.render_banded(&s, &mut band, &mut depth, 16, &mut sink)
        }
    }
    .expect("render");
    let _ = n;
    (sink.checksum(), stats.shade.span.pixels)
}

const CASES: [&str; 3] = ["zoneplate", "fire", "wood"];

/// With the `lighting` feature: the marble scene without lights (it must cost what it costs in a
/// build without the feature) and with a light (the lighting stage's cost is the difference).
#[cfg(feature = "lighting")]
const LIGHTING_CASES: [&str; 2] = ["marble", "marble+lit"];
#[cfg(not(feature = "lighting"))]
const LIGHTING_CASES: [&str; 1] = ["marble"];

fn stages(c: &mut Criterion) {
    let mut g = c.benchmark_group("stages-off");
    for case in CASES.into_iter().chain(LIGHTING_CASES) {
        let (_, pixels) = render_scene(case);
        g.throughput(Throughput::Elements(pixels));
        g.bench_function(case, |b| {
            b.iter(|| black_box(render_scene(black_box(case))))
        });
    }
    g.finish();
}

criterion_group!(benches, stages);

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "count") {
        let case = args.get(i + 1).map(String::as_str).unwrap_or("zoneplate");
        let (sum, px) = render_scene(case);
        println!("{case}: checksum {sum:08x}, {px} pixels");
        return;
    }
    benches();
    criterion::Criterion::default()
        .configure_from_args()
        .final_summary();
}
