//! Meshed texture atlases: exhaustive ownership of texels, the seam test (a mesh drawn from its
//! atlas at many angles, distances and look-ups never reads an unused texel), and the bad-mesh
//! and atlas command lines.

use host_sim::atlas::view::{draw, Orbit, Source};
use host_sim::atlas::{self, AtlasKind, Layout, Sampling};
use host_sim::mesh::TriMesh;
use texcore::atlas::sample::{AtlasImage, MipAtlas};

fn meshes() -> Vec<(&'static str, TriMesh)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let bunny = host_sim::mesh::load(&root.join("examples/meshes/bunny.obj")).unwrap();
    let mut v = vec![("bunny", bunny)];
    for name in ["teapot", "sphere", "torus"] {
        v.push((name, host_sim::atlas::cli::builtin_mesh(name).unwrap()));
    }
    v
}

/// No texel is owned by two triangles, every owned texel is inside the atlas, and every
/// triangle owns its whole footprint region (texcore's unit test checks the footprint of every
/// point inside a block's triangles; here every layout of every test mesh is checked to give
/// disjoint blocks).
#[test]
fn no_two_triangles_share_a_texel() {
    for (name, m) in meshes() {
        for (kind, size, gutter) in [
            (AtlasKind::Uniform, 512, 1),
            (AtlasKind::Uniform, 256, 0),
            (AtlasKind::Area, 512, 1),
            (AtlasKind::Length, 512, 1),
            (AtlasKind::Mip, 1024, 1),
        ] {
            let l = match Layout::new(&m, kind, size, gutter) {
                Ok(l) => l,
                Err(e) => panic!("{name} {kind:?} {size}: {e}"),
            };
            let mut owner = vec![u32::MAX; (size * size) as usize];
            for (t, at) in l.triangles.iter().enumerate() {
                let (_, y, _, h) = at.block();
                for j in y..y + h {
                    let Some((x0, n)) = at.row(j) else { continue };
                    for i in x0..x0 + n {
                        assert!((i as u32) < size && (j as u32) < size, "{name} {kind:?}");
                        let o = &mut owner[j as usize * size as usize + i as usize];
                        assert_eq!(*o, u32::MAX, "{name} {kind:?}: texel ({i}, {j}) twice");
                        *o = t as u32;
                    }
                }
            }
        }
    }
}

/// The seam test: every mesh drawn from a mask atlas (owned texels opaque, the rest the loud
/// unused colour with alpha 0) at 8 yaws, 3 pitches and 3 distances, with nearest, bilinear and
/// MIP look-ups, never reads an unused texel with a non-zero weight.
#[test]
fn no_seams_at_any_angle_distance_or_lookup() {
    for (name, m) in meshes() {
        for (kind, size, gutter, samplings) in [
            (
                AtlasKind::Uniform,
                512u32,
                1u8,
                &[Sampling::Nearest, Sampling::Bilinear][..],
            ),
            (AtlasKind::Uniform, 256, 0, &[Sampling::Nearest][..]),
            (AtlasKind::Length, 512, 1, &[Sampling::Bilinear][..]),
            (
                AtlasKind::Mip,
                1024,
                1,
                &[Sampling::Nearest, Sampling::Bilinear, Sampling::Mip][..],
            ),
        ] {
            let l = Layout::new(&m, kind, size, gutter).unwrap();
            let mask = atlas::mask(&l);
            let pyr = atlas::pyramid(&mask).unwrap();
            let mut shaded = 0;
            for &sampling in samplings {
                let source = if sampling == Sampling::Mip {
                    Source::Mip(MipAtlas::new(&pyr, size as u16).unwrap(), u8::MAX)
                } else {
                    Source::Flat(AtlasImage::new(&mask.texels, size as u16, size as u16).unwrap())
                };
                for yaw in (0..8).map(|k| 45.0 * k as f64 + 7.0) {
                    for pitch in [-35.0, 10.0, 60.0] {
                        for distance in [1.6, 3.0, 12.0] {
                            let cam = Orbit {
                                yaw,
                                pitch,
                                distance,
                                size: 96,
                            };
                            let f = draw(&m, &l, &source, sampling, &cam);
                            assert_eq!(
                                f.loud, 0,
                                "{name} {kind:?} {size} {sampling:?} yaw {yaw} pitch {pitch} distance {distance}"
                            );
                            shaded += f.shaded;
                        }
                    }
                }
            }
            assert!(
                shaded > 10_000,
                "{name} {kind:?}: only {shaded} pixels drawn"
            );
        }
    }
}

/// The test above can fail: without its gutter (bilinear look-ups in a nearest-only layout)
/// the same walk finds unused texels.
#[test]
fn the_seam_test_sees_seams_without_a_gutter() {
    let m = host_sim::atlas::cli::builtin_mesh("sphere").unwrap();
    let l = Layout::new(&m, AtlasKind::Uniform, 256, 0).unwrap();
    let mask = atlas::mask(&l);
    let img = AtlasImage::new(&mask.texels, 256, 256).unwrap();
    let cam = Orbit {
        yaw: 20.0,
        pitch: 15.0,
        distance: 1.6,
        size: 128,
    };
    let f = draw(&m, &l, &Source::Flat(img), Sampling::Bilinear, &cam);
    assert!(f.loud > 0);
}
