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

/// The texels a look-up at `(u, v)` (`Q16.16` texels) reads with a non-zero weight: nearest,
/// or with `bilinear` the texels `AtlasImage::bilinear` weighs (texel `(x, y)` always, its
/// right and lower neighbours when the 8-bit fractions are non-zero).
fn footprint(u: i32, v: i32, bilinear: bool) -> impl Iterator<Item = (i32, i32)> {
    let half = if bilinear { 1 << 15 } else { 0 };
    let (u, v) = (u - half, v - half);
    let (x, y) = (u >> 16, v >> 16);
    let fx = bilinear && (u >> 8) & 255 > 0;
    let fy = bilinear && (v >> 8) & 255 > 0;
    [(0, 0, true), (1, 0, fx), (0, 1, fy), (1, 1, fx && fy)]
        .into_iter()
        .filter_map(move |(dx, dy, w)| w.then_some((x + dx, y + dy)))
}

/// Looks up the owners of the texels the look-ups over triangle `t` of `layout` read (its atlas
/// coordinates `Layout::uv` as the renderer rounds them, the corners and every 1/16 texel along
/// the edges and a 1/4-texel grid inside): the first texel not owned by `t`, if any.
fn foreign_texel(layout: &Layout, owner: &[u32], t: usize) -> Option<(i32, i32)> {
    let size = layout.size as i32;
    let c = layout
        .uv(t)
        .map(|p| p.map(|x| (x * 65536.0).round() as i64));
    let l = i64::from(layout.triangles[t].leg());
    let mut points = Vec::new();
    for (a, b) in [(0, 1), (1, 2), (2, 0)] {
        let n = 16 * l;
        for s in 0..n {
            points.push([0, 1].map(|d| c[a][d] + (c[b][d] - c[a][d]) * s / n));
        }
    }
    let n = 4 * l;
    for s in 0..=n {
        for q in 0..=n - s {
            points.push(
                [0, 1].map(|d| c[0][d] + ((c[1][d] - c[0][d]) * s + (c[2][d] - c[0][d]) * q) / n),
            );
        }
    }
    for p in points {
        for bilinear in [false, layout.gutter == 1] {
            for (i, j) in footprint(p[0] as i32, p[1] as i32, bilinear) {
                let inside = (0..size).contains(&i) && (0..size).contains(&j);
                if !inside || owner[(j * size + i) as usize] != t as u32 {
                    return Some((i, j));
                }
            }
        }
    }
    None
}

/// No texel is owned by two triangles, every owned texel is inside the atlas, and every
/// look-up the renderer makes over a triangle (nearest; bilinear too with the gutter) reads
/// only texels that triangle owns, checked at its inset atlas coordinates (`foreign_texel`)
/// for every triangle of every layout of every test mesh (texcore's unit test checks the
/// look-ups at every point of a fine grid of a block's triangles).
#[test]
fn no_two_triangles_share_a_texel() {
    for (name, m) in meshes() {
        for (kind, size, gutter) in [
            (AtlasKind::Uniform, 512, 1),
            (AtlasKind::Uniform, 256, 0),
            (AtlasKind::Area, 512, 1),
            (AtlasKind::Length, 512, 1),
            (AtlasKind::Area, 256, 0),
            (AtlasKind::Mip, 1024, 1),
            (AtlasKind::Mip, 512, 0),
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
            for t in 0..l.triangles.len() {
                let e = foreign_texel(&l, &owner, t);
                assert_eq!(
                    e, None,
                    "{name} {kind:?} {size} gutter {gutter}: triangle {t}"
                );
            }
        }
    }
}

/// The look-up check above can fail: with the bilinear look-ups of a gutter-0 layout, and with
/// every owner map shifted by one texel, it finds foreign texels.
#[test]
fn the_ownership_check_sees_foreign_texels() {
    let m = host_sim::atlas::cli::builtin_mesh("sphere").unwrap();
    let l = Layout::new(&m, AtlasKind::Uniform, 256, 0).unwrap();
    let mut owner = vec![u32::MAX; 256 * 256];
    let mut shifted = owner.clone();
    for (t, at) in l.triangles.iter().enumerate() {
        let (_, y, _, h) = at.block();
        for j in y..y + h {
            let Some((x0, n)) = at.row(j) else { continue };
            for i in x0..x0 + n {
                owner[j as usize * 256 + i as usize] = t as u32;
                shifted[j as usize * 256 + (i as usize + 1).min(255)] = t as u32;
            }
        }
    }
    assert!((0..l.triangles.len()).all(|t| foreign_texel(&l, &owner, t).is_none()));
    assert!((0..l.triangles.len()).all(|t| foreign_texel(&l, &shifted, t).is_some()));
    let bilinear = Layout {
        gutter: 1,
        ..l.clone()
    };
    let seen = (0..l.triangles.len())
        .filter(|&t| foreign_texel(&bilinear, &owner, t).is_some())
        .count();
    assert!(seen > l.triangles.len() / 2, "{seen}");
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
