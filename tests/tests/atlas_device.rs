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

/// The frame list (one walk a frame, every band drawn from the listed quads) draws exactly what
/// the general way (every band walks the quads its bins name) draws: the marble frame seen from
/// eight directions at three distances, the nearest cutting the teapot with the near plane (a
/// clipped triangle sends the frame the general way), with a list large enough, with none, and
/// with one too small for the frame, each band's quads found through the band index, or (no
/// index, or one too small) by scanning the list.
#[test]
fn frame_list_draws_what_the_walk_draws() {
    use atlas::FrameQuad;
    let base = scenes::builtin_frame(atlas::SCENE).unwrap();
    let mut texels = Box::new([0u16; atlas::TEXELS]);
    atlas::bake_scene(&base, HashKind::Integer, &mut texels, true);
    let mut bins = vec![GroupRows::EMPTY; scenes::SCENE_GROUPS];
    let (eye, target) = (base.camera.eye, base.camera.target);
    let (dx, dz) = (f64::from(eye.x - target.x), f64::from(eye.z - target.z));
    let (mut listed_frames, mut walked_frames) = (0, 0);
    for k in 0..8 {
        for scale in [1.0, 0.6, 0.12] {
            let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
            let (s, c) = a.sin_cos();
            let mut scene = base.clone();
            scene.camera.eye.x = target.x + ((dx * c - dz * s) * scale) as i32;
            scene.camera.eye.z = target.z + ((dx * s + dz * c) * scale) as i32;
            scene.camera.eye.y = target.y + (f64::from(eye.y - target.y) * scale) as i32;
            let mut draw = |list: &mut [FrameQuad], refs: &mut [u16]| {
                let mut px = Vec::new();
                assert!(atlas::draw_scene_rows_with(
                    &scene,
                    &texels,
                    &mut bins,
                    list,
                    refs,
                    &mut vec![0u16; atlas::DRAW_PIXELS],
                    |r| px.extend_from_slice(r)
                ));
                px
            };
            let mut list = vec![FrameQuad::EMPTY; atlas::FRAME_QUADS];
            let mut refs = vec![u16::MAX; atlas::FRAME_REFS];
            let listed = draw(&mut list, &mut refs);
            let walked = draw(&mut [], &mut []);
            // The list scanned in every band (no band index, or one too small for the frame).
            for n in [0, atlas::FRAME_REFS / 4] {
                let mut list = vec![FrameQuad::EMPTY; atlas::FRAME_QUADS];
                let what = format!("direction {k}, distance {scale}, {n} band refs");
                assert_eq!(draw(&mut list, &mut vec![0; n]), walked, "{what}");
            }
            let what = format!("direction {k}, distance {scale}");
            assert_eq!(listed.len(), 320 * 240, "{what}");
            assert_eq!(
                listed, walked,
                "{what}: the listed frame differs from the walked one"
            );
            let used = list.iter().filter(|q| **q != FrameQuad::EMPTY).count();
            if used > 1 {
                let mut small = vec![FrameQuad::EMPTY; used / 2];
                assert_eq!(
                    draw(&mut small, &mut refs),
                    walked,
                    "{what}: a list too small"
                );
            }
            // A frame with a clipped triangle cannot be listed exactly (the general way draws
            // it); the others are drawn from the list.
            let mut clipped = false;
            scene.for_each_triangle_with_corners(&mut |_| true, &mut |_, _, _, c| {
                clipped |= c.is_none()
            });
            if clipped {
                walked_frames += 1;
            } else {
                assert!(used > 100, "{what}: {used} quads listed");
                // The bands found their quads through the index (its entries were written).
                let indexed = refs.iter().filter(|&&r| r != u16::MAX).count();
                assert!(
                    indexed >= used,
                    "{what}: {indexed} band refs for {used} quads"
                );
                listed_frames += 1;
            }
        }
    }
    eprintln!("{listed_frames} frames drawn from the list, {walked_frames} with clipped triangles");
    // Both kinds of frame occur: the far views list, the nearest cut the near plane.
    assert!(listed_frames >= 16, "{listed_frames}");
    assert!(walked_frames >= 1, "{walked_frames}");
}
