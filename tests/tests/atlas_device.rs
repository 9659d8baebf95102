//! The device's atlas jobs (`workloads::atlas`) on the host: the marble scene baked into the
//! device's 128 x 128 RGB565 atlas and its frame drawn from it resembles the procedurally shaded
//! frame, the checksum form and the row form of the draw agree, and the jobs' checksums are what
//! the report compares the devices with (`tests/tests/firmware_qemu.rs` checks device = host).

use host_sim::report::{self, atlas, scenes};
use host_sim::unit::UnitConfig;
use texcore::color::{Rgb565, Rgba8888};
use texcore::hash::HashKind;
use texcore::render::{GroupRows, Output};

/// The marble frame drawn from the device atlas, as RGBA rows, and its checksum.
fn atlas_frame(hash: HashKind) -> (Vec<[u8; 4]>, u32, u32) {
    let scene = scenes::builtin_frame(atlas::SCENE).expect("marble");
    let mut texels = Box::new([0u16; atlas::TEXELS]);
    let baked = atlas::bake_scene(&scene, hash, &mut texels, true);
    let mut bins = vec![GroupRows::EMPTY; scenes::SCENE_GROUPS];
    let mut px = Vec::new();
    assert!(atlas::draw_scene_rows(&scene, &texels, &mut bins, |row| px
        .extend(
            row.iter().map(|p| Rgb565(*p).to_rgba8888().to_array())
        )));
    let c = atlas::draw_scene(&scene, &texels, &mut bins);
    (px, c, baked)
}

fn psnr(a: &[[u8; 4]], b: &[[u8; 4]]) -> f64 {
    let mut se = 0f64;
    for (p, q) in a.iter().zip(b) {
        for k in 0..3 {
            let d = f64::from(p[k]) - f64::from(q[k]);
            se += d * d;
        }
    }
    let mse = se / (a.len() * 3) as f64;
    10.0 * (255.0f64 * 255.0 / mse.max(1e-12)).log10()
}

#[test]
fn device_atlas_frame_resembles_the_procedural_frame() {
    let hash = HashKind::Integer;
    let scene = texcore::scene::by_name(atlas::SCENE).unwrap();
    let procedural = host_sim::scenes::render_frame(
        &scene,
        scene.still(),
        &UnitConfig::default(),
        hash,
        Output::Color,
    )
    .unwrap()
    .frame;
    let (px, checksum, baked) = atlas_frame(hash);
    let frame = scenes::builtin_frame(atlas::SCENE).unwrap();
    let layout = atlas::scene_layout(&frame).expect("the marble scene fits the device atlas");
    assert_eq!(px.len(), procedural.pixels.len());
    // The checksum of the rows is the draw's checksum.
    let mut sink = texcore::sink::ChecksumSink::new();
    for p in &px {
        sink.add_rgb565(Rgba8888::from_array(*p).to_rgb565().to_bits());
    }
    assert_eq!(sink.checksum(), checksum);
    assert_eq!(u64::from(baked), u64::from(atlas::owned_texels(&frame)));
    // Against the procedural frame (the same RGB565 quantisation on both sides).
    let q = |p: &[u8; 4]| {
        Rgba8888::from_array(*p)
            .to_rgb565()
            .to_rgba8888()
            .to_array()
    };
    let proc565: Vec<[u8; 4]> = procedural.pixels.iter().map(q).collect();
    let db = psnr(&px, &proc565);
    let bg = q(&[36, 38, 48, 255]);
    let same_bg = px
        .iter()
        .zip(&proc565)
        .filter(|(a, b)| (**a == bg) == (**b == bg))
        .count();
    eprintln!(
        "marble from the device atlas ({} x {}, leg {}, {baked} texels baked): PSNR {db:.2} dB \
         against the procedural frame; coverage agreement {:.2}%",
        atlas::SIDE,
        atlas::SIDE,
        layout.leg(),
        100.0 * same_bg as f64 / px.len() as f64
    );
    assert!(db > 20.0, "PSNR {db:.2} dB");
    // The report's checksum of the job is this frame's.
    assert_eq!(report::host_checksum("atlas:marble", hash), Some(checksum));
    for h in [HashKind::Permutation, HashKind::Integer] {
        for job in ["atlas:marble-bake", "atlas:marble"] {
            eprintln!(
                "{h:?} {job}: host checksum {:#010x}",
                report::host_checksum(job, h).unwrap()
            );
        }
    }
}
