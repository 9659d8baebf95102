//! Whole-scene tests: built-in scenes (triangles, guard band, determinism, animation), the zone
//! plate's exact pixel-centre coordinates, and watertightness of the tessellated teapot as seen
//! by the rasterizer.

extern crate std;

use super::camera::{CamVertex, ClipOutcome};
use super::math::{milli, units, Angle, Vec3, ONE};
use super::*;
use crate::raster::{Rasterizer, Rect, Reject, Segment, GUARD_BAND};
use crate::transform::Affine3;
use std::collections::{HashMap, HashSet, VecDeque};
use std::vec::Vec;

type Tri = (usize, [ScreenVertex; 3]);

fn collect(s: &Scene, frame: u32) -> (Vec<Tri>, SceneCounters) {
    let mut out = Vec::new();
    let c = s.for_each_triangle(frame, |o, t| out.push((o, *t)));
    (out, c)
}

fn in_guard_band(t: &[ScreenVertex; 3]) -> bool {
    t.iter().all(|v| {
        v.x.to_bits().unsigned_abs() < GUARD_BAND && v.y.to_bits().unsigned_abs() < GUARD_BAND
    })
}

#[test]
fn builtin_list_and_lookup() {
    for name in BUILTIN {
        let s = by_name(name).unwrap();
        assert_eq!(s.name, name);
        assert!(s.frames() >= 1 && s.still() < s.frames());
        for o in &s.objects {
            let slot = s.slots.get(o.slot as usize).expect("slot exists");
            assert!(
                crate::presets::NAMES.contains(&slot.material),
                "{name}: unknown material {}",
                slot.material
            );
        }
        let expect = if name == "zoneplate" {
            (256, 256)
        } else {
            (320, 240)
        };
        assert_eq!(s.size(), expect, "{name}");
    }
    assert!(by_name("nope").is_none());
}

/// Every built-in scene emits triangles, all inside the rasterizer's guard band, identically on
/// two runs; the counters add up.
#[test]
fn builtin_scenes_emit_deterministic_triangles_in_guard_band() {
    for name in BUILTIN {
        let s = by_name(name).unwrap();
        let mesh_tris: u32 = s.objects.iter().map(|o| o.mesh.triangle_count()).sum();
        for frame in [0, s.still(), s.frames() - 1, s.frames() + 3] {
            let (a, ca) = collect(&s, frame);
            let (b, cb) = collect(&s, frame);
            assert_eq!(a, b, "{name} frame {frame}: not deterministic");
            assert_eq!(ca, cb);
            assert!(!a.is_empty(), "{name}: no triangles");
            assert_eq!(ca.generated as usize, a.len());
            assert_eq!(ca.input, mesh_tris, "{name}");
            assert_eq!(ca.objects as usize, s.objects.len());
            assert!(ca.rejected + ca.clipped <= ca.input);
            let mut rast = Rasterizer::new(Rect::from_size(s.size().0, s.size().1));
            for (o, t) in &a {
                assert!(in_guard_band(t), "{name}: {t:?}");
                // Far inside it, in fact: 2^24 pixels plus the image.
                for v in t {
                    assert!(v.x.to_bits().unsigned_abs() < (1 << 28) + (1 << 20));
                    assert!(v.y.to_bits().unsigned_abs() < (1 << 28) + (1 << 20));
                    assert!(v.inv_w.to_bits() <= 1 << 31);
                }
                let opts = s.objects[*o].options();
                assert_ne!(rast.setup(t, &opts), Err(Reject::OutsideGuardBand));
            }
        }
        // Each object contributes.
        let (a, _) = collect(&s, s.still());
        for k in 0..s.objects.len() {
            assert!(
                a.iter().any(|(o, _)| *o == k),
                "{name}: object {k} invisible"
            );
        }
    }
}

#[test]
fn triangle_budget() {
    for name in BUILTIN {
        let s = by_name(name).unwrap();
        let n: u32 = s.objects.iter().map(|o| o.mesh.triangle_count()).sum();
        assert!(n <= 2000, "{name}: {n} triangles");
    }
    let teapot = by_name("wood").unwrap().objects[0].mesh.triangle_count();
    assert_eq!(teapot, 64 * 25 - 8 * 5);
}

#[test]
fn animation() {
    // The wood teapot turns: geometry changes, and frame `frames` is frame 0 again.
    let w = by_name("wood").unwrap();
    assert_ne!(collect(&w, 0).0, collect(&w, 5).0);
    assert_eq!(collect(&w, 0).0, collect(&w, w.frames()).0);
    // The fire's phase is a slot parameter; its geometry is static.
    let f = by_name("fire").unwrap();
    assert_eq!(f.at_frame(0).slots[0].phase, 0);
    assert_eq!(f.at_frame(3).slots[0].phase, 3 * ONE / 32);
    assert_eq!(collect(&f, 0).0, collect(&f, 7).0);
    // Marble: the noise amplitude grows from 0 to 1, the still is the finished marble.
    let m = by_name("marble").unwrap();
    assert_eq!(m.at_frame(0).slots[0].amplitude, 0);
    assert_eq!(m.at_frame(m.still()).slots[0].amplitude, ONE);
    // Seascape: the textures drift, the planes stay.
    let s = by_name("seascape").unwrap();
    let (a, b) = (collect(&s, 0).0, collect(&s, 9).0);
    assert_eq!(a.len(), b.len());
    assert!(a
        .iter()
        .zip(&b)
        .all(|(p, q)| p.1[0].x == q.1[0].x && p.1[0].y == q.1[0].y));
    assert_ne!(a, b);
    // The moon rises: its triangles move up the screen.
    let mr = by_name("moonrise").unwrap();
    let top = |f: u32| {
        collect(&mr, f)
            .0
            .iter()
            .filter(|(o, _)| *o == 2)
            .flat_map(|(_, t)| t.iter().map(|v| v.y.to_bits()))
            .min()
            .unwrap()
    };
    assert!(top(100) < top(0));
}

/// The zone plate's quad, rasterized, gives exactly `s = (x + 0.5) / 256`, `t = (y + 0.5) / 256`,
/// `r = 0` at every pixel centre, each pixel once.
#[test]
fn zoneplate_pixel_centres_exact() {
    let s = by_name("zoneplate").unwrap();
    let (tris, c) = collect(&s, 0);
    assert_eq!(c.generated, 2);
    let mut rast = Rasterizer::new(Rect::from_size(256, 256));
    let mut seen = std::vec![0u8; 256 * 256];
    for (o, t) in &tris {
        let opts = s.objects[*o].options();
        rast.draw(t, &opts, &mut |seg: &Segment| {
            for i in 0..seg.len {
                let (x, y) = ((seg.x0 + i) as i64, seg.y as i64);
                assert_eq!(
                    seg.s_at(i),
                    [(2 * x + 1) * 128, (2 * y + 1) * 128, 0],
                    "pixel {x} {y}"
                );
                seen[(y * 256 + x) as usize] += 1;
            }
        });
    }
    assert!(seen.iter().all(|&n| n == 1));
    // The vertices are the image corners with s, t in {0, 1}.
    for (_, t) in &tris {
        for v in t {
            let (x, y) = (v.x.to_bits(), v.y.to_bits());
            assert!(x == 0 || x == 256 * 16);
            assert!(y == 0 || y == 256 * 16);
            assert_eq!(v.tex.s.to_bits(), x * 16);
            assert_eq!(v.tex.t.to_bits(), y * 16);
        }
    }
}

/// The marble cube and teapot are cut from one block: the texture coordinates of every vertex
/// are the block's mapping of its world position, so a corner shared by three faces carries one
/// texture coordinate and the veins continue across edges.
#[test]
fn marble_block_alignment() {
    let s = by_name("marble").unwrap();
    let block = builtin::MARBLE_BLOCK;
    for o in &s.objects {
        for t in o.mesh.triangles().take(300) {
            for p in t {
                let world = o.transform.saturating_apply(p);
                let direct = block.apply_point(crate::format::TexPoint::from_bits(
                    world.x, world.y, world.z,
                ));
                let via = o
                    .tex_map
                    .apply_point(crate::format::TexPoint::from_bits(p.x, p.y, p.z));
                for k in 0..3 {
                    assert!((direct[k] - via[k]).abs() <= 8, "{direct:?} vs {via:?}");
                }
            }
        }
    }
    // On screen: a cube vertex position always carries the same texture coordinates.
    let (tris, _) = collect(&s, s.still());
    let mut at: HashMap<(i32, i32), crate::format::TexPoint> = HashMap::new();
    for (o, t) in &tris {
        if *o != 0 {
            continue;
        }
        for v in t {
            let prev = at.entry((v.x.to_bits(), v.y.to_bits())).or_insert(v.tex);
            assert_eq!(*prev, v.tex);
        }
    }
    assert!(at.len() >= 7, "cube corners seen: {}", at.len());
}

// ---------------------------------------------------------------------------------------------
// Horizon planes and the guard band.

fn lcg(state: &mut u64) -> u32 {
    (crate::test_rng::lcg64(state) >> 33) as u32
}

/// A huge ground plane seen from many cameras (low and high, looking up, down and along it, wide
/// and narrow fields of view): every triangle is clipped into the guard band, no triangle is
/// rejected by the rasterizer's guard band, and the near plane keeps depth and 1/w in range.
#[test]
fn horizon_plane_stays_in_guard_band() {
    let mut rng = 0x5eed_u64;
    let mut clipped = 0;
    let mut pixels = 0u64;
    for i in 0..120 {
        let h = milli(1 + (lcg(&mut rng) % 50_000) as i32); // 0.001 .. 50 units
        let pitch = Angle::from_millidegrees(-89_000 + (lcg(&mut rng) % 178_000) as i32);
        let yaw = Angle(lcg(&mut rng));
        let fov = Angle::from_degrees(15 + (lcg(&mut rng) % 130) as i32);
        let (sp, cp) = pitch.sin_cos();
        let (sy, cy) = yaw.sin_cos();
        let dir = Vec3::new(
            super::math::q30_to_q16(((cp as i64 * sy as i64) >> 30) as i32),
            super::math::q30_to_q16(sp),
            super::math::q30_to_q16(((cp as i64 * cy as i64) >> 30) as i32),
        );
        let eye = Vec3::new((lcg(&mut rng) % (1 << 20)) as i32, h, -(1 << 19));
        let cam = Camera::perspective(
            eye,
            eye.add(dir.scale(units(10))),
            Vec3::Y,
            focal_from_fov(fov),
            milli(10 + (i % 3) * 200),
            units(30_000),
            320,
            240,
        );
        let mut s = Scene::new("plane", cam);
        s.add_slot(TextureSlot::preset("water")).unwrap();
        // Alternately a geometric grid and one single quad 32000 units wide.
        let mut o = Object::new(if i % 2 == 0 {
            Mesh::Plane {
                half_size: units(16_000),
                rings: 12,
            }
        } else {
            let e = units(16_000);
            Mesh::Quad {
                corners: [
                    Vec3::new(-e, 0, e),
                    Vec3::new(e, 0, e),
                    Vec3::new(e, 0, -e),
                    Vec3::new(-e, 0, -e),
                ],
            }
        });
        o.tex_map = Affine3::IDENTITY;
        s.add(o).unwrap();
        let mut rast = Rasterizer::new(Rect::from_size(320, 240));
        let c = s.for_each_triangle(0, |_, t| {
            for v in t {
                assert!(
                    v.x.to_bits().unsigned_abs() < (1 << 28) + (1 << 20),
                    "{v:?}"
                );
                assert!(
                    v.y.to_bits().unsigned_abs() < (1 << 28) + (1 << 20),
                    "{v:?}"
                );
                assert!(v.inv_w.to_bits() <= 1 << 31 && v.inv_w.to_bits() > 0);
            }
            assert_ne!(
                rast.setup(t, &TriangleOptions::new(Perspective::Every16)),
                Err(Reject::OutsideGuardBand)
            );
            rast.draw(
                t,
                &TriangleOptions::new(Perspective::Every16),
                &mut |seg: &Segment| pixels += seg.len as u64,
            );
        });
        clipped += c.clipped;
        assert_eq!(rast.counters().outside_guard_band, 0);
    }
    assert!(
        clipped > 100,
        "the test should exercise clipping ({clipped})"
    );
    assert!(pixels > 0);
}

/// The seascape's planes reach the horizon: near the horizon row the sky and the sea are both
/// drawn (within a pixel), and their texture coordinates stay in range.
#[test]
fn seascape_reaches_horizon() {
    let s = by_name("seascape").unwrap();
    let (w, h) = s.size();
    let mut rast = Rasterizer::new(Rect::from_size(w, h));
    let mut rows: [HashSet<u16>; 2] = [HashSet::new(), HashSet::new()];
    let (tris, c) = collect(&s, 0);
    assert!(c.clipped > 0 && c.rejected > 0);
    for (o, t) in &tris {
        let opts = s.objects[*o].options();
        rast.draw(t, &opts, &mut |seg: &Segment| {
            rows[*o].insert(seg.y);
        });
    }
    let sky_lowest = *rows[0].iter().max().unwrap();
    let sea_highest = *rows[1].iter().min().unwrap();
    assert!(
        sea_highest <= sky_lowest + 2,
        "sky to row {sky_lowest}, sea from {sea_highest}"
    );
    assert!(rows[0].contains(&0) && rows[1].contains(&(h - 1)));
    // The eye looks 2.6 degrees up: horizon about 12 rows below the centre.
    assert!((125..=140).contains(&sky_lowest), "{sky_lowest}");
}

// ---------------------------------------------------------------------------------------------
// Teapot watertightness.

/// The triangles of teapot patches `patches` at `level` (same split as [`Mesh::triangles`]).
fn patch_triangles(level: u8, patches: core::ops::Range<u32>) -> Vec<[Vec3; 3]> {
    let m = Mesh::Teapot { level };
    let n = level as u32;
    let mut out = Vec::new();
    for q in patches.start * n * n..patches.end * n * n {
        let [a, b, c, d] = m.quad(q).unwrap();
        for t in [[a, b, c], [a, c, d]] {
            if t[0] != t[1] && t[1] != t[2] && t[2] != t[0] {
                out.push(t);
            }
        }
    }
    out
}

/// Rasterizes object-space triangles through an orthographic camera; returns per-pixel
/// coverage counts.
fn coverage(tris: &[[Vec3; 3]], cam: &Camera, cull: CullMode) -> Vec<u32> {
    let view = cam.view().unwrap();
    let (w, h) = view.size();
    let mut rast = Rasterizer::new(Rect::from_size(w, h));
    let mut cov = std::vec![0u32; w as usize * h as usize];
    let mut opts = TriangleOptions::new(Perspective::Affine);
    opts.cull = cull;
    for t in tris {
        let cv = t.map(|p| CamVertex {
            p: view.to_camera(p),
            tex: [0; 3],
        });
        let out = view.clip_project(&cv, &mut |st: &[ScreenVertex; 3]| {
            rast.draw(st, &opts, &mut |seg: &Segment| {
                for i in 0..seg.len {
                    cov[seg.y as usize * w as usize + (seg.x0 + i) as usize] += 1;
                }
            });
        });
        assert_eq!(out, ClipOutcome::Inside);
    }
    cov
}

/// Uncovered pixels that cannot be reached from the image border through uncovered pixels.
fn enclosed_holes(cov: &[u32], w: usize, h: usize) -> Vec<(usize, usize)> {
    let mut outside = std::vec![false; w * h];
    let mut queue = VecDeque::new();
    for y in 0..h {
        for x in 0..w {
            if (x == 0 || y == 0 || x == w - 1 || y == h - 1) && cov[y * w + x] == 0 {
                outside[y * w + x] = true;
                queue.push_back((x, y));
            }
        }
    }
    while let Some((x, y)) = queue.pop_front() {
        let n = [
            (x.wrapping_sub(1), y),
            (x + 1, y),
            (x, y.wrapping_sub(1)),
            (x, y + 1),
        ];
        for (nx, ny) in n {
            if nx < w && ny < h && cov[ny * w + nx] == 0 && !outside[ny * w + nx] {
                outside[ny * w + nx] = true;
                queue.push_back((nx, ny));
            }
        }
    }
    (0..w * h)
        .filter(|&i| cov[i] == 0 && !outside[i])
        .map(|i| (i % w, i / w))
        .collect()
}

fn ortho(eye: Vec3, target: Vec3, up: Vec3, half_height: i32, w: u16, h: u16) -> Camera {
    Camera::orthographic(eye, target, up, half_height, milli(100), units(40), w, h)
}

/// The lid and knob (patches 20..28) seen from above form a disc with no hole: the four knob
/// quadrants, the four lid quadrants and the knob-to-lid seam close exactly. (Nothing lies
/// behind them, so any crack would show.)
#[test]
fn teapot_lid_has_no_cracks() {
    for level in [2u8, 3, 5, 8] {
        let tris = patch_triangles(level, 20..28);
        let cam = ortho(
            Vec3::milli(0, 0, 10_000),
            Vec3::ZERO,
            Vec3::Y,
            milli(1400),
            97,
            97,
        );
        let cov = coverage(&tris, &cam, CullMode::None);
        let holes = enclosed_holes(&cov, 97, 97);
        assert!(holes.is_empty(), "level {level}: holes at {holes:?}");
        assert!(cov.iter().filter(|&&c| c > 0).count() > 97 * 97 / 2);
    }
}

/// The rim, body and bottom (patches 0..12 and 28..32) seen from the side with back faces
/// culled: the front faces alone must cover the silhouette without a hole, so every seam
/// between patches (around and between the rings, and body to bottom) is closed.
#[test]
fn teapot_body_has_no_cracks() {
    for level in [2u8, 4, 5, 7] {
        let mut tris = patch_triangles(level, 0..12);
        tris.extend(patch_triangles(level, 28..32));
        // z up in object space: look along +y, up = z.
        let cam = ortho(
            Vec3::milli(0, -10_000, 1300),
            Vec3::milli(0, 0, 1300),
            Vec3::Z,
            milli(1800),
            131,
            99,
        );
        let cov = coverage(&tris, &cam, CullMode::Clockwise);
        let holes = enclosed_holes(&cov, 131, 99);
        assert!(holes.is_empty(), "level {level}: holes at {holes:?}");
        assert!(cov.iter().filter(|&&c| c > 0).count() > 131 * 99 / 3);
    }
}

/// The whole teapot from above, every patch drawn: a silhouette without holes.
#[test]
fn teapot_top_view_has_no_holes() {
    let tris: Vec<[Vec3; 3]> = Mesh::Teapot { level: 4 }.triangles().collect();
    let cam = ortho(
        Vec3::milli(250, 0, 10_000),
        Vec3::milli(250, 0, 0),
        Vec3::Y,
        milli(2600),
        160,
        120,
    );
    let cov = coverage(&tris, &cam, CullMode::None);
    let holes = enclosed_holes(&cov, 160, 120);
    assert!(holes.is_empty(), "holes at {holes:?}");
}

/// The test above can fail: a teapot with one lid quad missing has a hole.
#[test]
fn hole_detector_bites() {
    let mut tris = patch_triangles(4, 20..28);
    let n = tris.len();
    // Drop the lid triangles between radius 0.81 and 1.2 in the +x +y quadrant (away from the
    // knob, which covers radius 0.8, and from the rim).
    let ring = |p: &Vec3| {
        let r2 = (p.x as i64).pow(2) + (p.y as i64).pow(2);
        p.x > 0 && p.y > 0 && r2 > (milli(810) as i64).pow(2) && r2 < (milli(1200) as i64).pow(2)
    };
    tris.retain(|t| !t.iter().all(ring));
    assert!(tris.len() < n);
    let cam = ortho(
        Vec3::milli(0, 0, 10_000),
        Vec3::ZERO,
        Vec3::Y,
        milli(1400),
        97,
        97,
    );
    let cov = coverage(&tris, &cam, CullMode::None);
    assert!(!enclosed_holes(&cov, 97, 97).is_empty());
}

/// Projection keeps the mesh's connectivity: in the wood scene, directed screen edges (keyed by
/// position, depth and texture coordinates of their ends) pair up exactly as the object-space
/// edges do; only the teapot's open boundaries (rim, lid edge, handle and spout ends: `16 n`
/// edges) are unpaired.
#[test]
fn teapot_screen_edges_pair_up() {
    let s = by_name("wood").unwrap();
    let (tris, c) = collect(&s, 0);
    assert_eq!(c.clipped, 0);
    type Key = (i32, i32, u16, [i32; 3]);
    let key = |v: &ScreenVertex| -> Key { (v.x.to_bits(), v.y.to_bits(), v.z, v.tex.to_bits()) };
    let mut edges: HashSet<(Key, Key)> = HashSet::new();
    for (_, t) in &tris {
        for k in 0..3 {
            assert!(
                edges.insert((key(&t[k]), key(&t[(k + 1) % 3]))),
                "repeated edge"
            );
        }
    }
    let open_screen = edges
        .iter()
        .filter(|(a, b)| !edges.contains(&(*b, *a)))
        .count();
    let mut obj: HashSet<(Vec3, Vec3)> = HashSet::new();
    for t in s.objects[0].mesh.triangles() {
        for k in 0..3 {
            obj.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let open_obj = obj.iter().filter(|(a, b)| !obj.contains(&(*b, *a))).count();
    assert_eq!(open_obj, 16 * 5);
    assert_eq!(open_screen, open_obj);
}

// ---------------------------------------------------------------------------------------------
// Robustness.

/// Degenerate cameras and absurd objects never panic; a degenerate camera emits nothing.
#[test]
fn degenerate_inputs_do_not_panic() {
    let mut s = by_name("wood").unwrap();
    s.camera.target = s.camera.eye;
    let (t, c) = collect(&s, 0);
    assert!(t.is_empty());
    assert_eq!(c.rejected, c.input);
    let mut s = by_name("planet").unwrap();
    s.camera.far = s.camera.near;
    assert!(collect(&s, 0).0.is_empty());
    // Objects far outside the world range, huge scales and transforms.
    let mut s = by_name("fire").unwrap();
    s.objects[0].transform = Affine3::scale(crate::format::MatrixEntry::MAX)
        .then(&Affine3::translate(Vec3::new(i32::MIN, i32::MAX, i32::MIN)));
    let _ = collect(&s, 0);
    s.objects[0].mesh = Mesh::Quad {
        corners: [Vec3::new(i32::MAX, i32::MIN, 0); 4],
    };
    let _ = collect(&s, 0);
    let mut s = by_name("seascape").unwrap();
    s.camera.projection = Projection::Perspective { focal: i32::MAX };
    s.camera.far = i32::MAX;
    s.camera.near = 1;
    let (tris, _) = collect(&s, 0);
    assert!(tris.iter().all(|(_, t)| in_guard_band(t)));
    s.camera.projection = Projection::Orthographic { half_height: 1 };
    let (tris, _) = collect(&s, 0);
    assert!(tris.iter().all(|(_, t)| in_guard_band(t)));
    // Extreme cameras and objects at the ends of the world range.
    for (eye, target, up) in [
        (
            Vec3::new(i32::MIN, i32::MIN, i32::MIN),
            Vec3::new(i32::MAX, i32::MAX, i32::MAX),
            Vec3::Y,
        ),
        (
            Vec3::new(i32::MAX, 0, 0),
            Vec3::new(i32::MIN, 1, 0),
            Vec3::new(0, i32::MIN, 1),
        ),
        (Vec3::ZERO, Vec3::new(0, 0, -1), Vec3::new(1, 1, 1)),
    ] {
        for name in ["moonrise", "marble", "zoneplate"] {
            let mut s = by_name(name).unwrap();
            s.camera.eye = eye;
            s.camera.target = target;
            s.camera.up = up;
            s.camera.near = 1;
            s.camera.far = i32::MAX;
            for o in s.objects.iter_mut() {
                o.transform = o.transform.with_translation(
                    Affine3::translate(Vec3::new(i32::MAX, i32::MIN, i32::MAX)).translation(),
                );
            }
            let (tris, _) = collect(&s, 0);
            assert!(tris.iter().all(|(_, t)| in_guard_band(t)));
            s.camera.projection = Projection::Orthographic {
                half_height: i32::MAX,
            };
            let (tris, _) = collect(&s, 0);
            assert!(tris.iter().all(|(_, t)| in_guard_band(t)));
        }
    }
}

/// Perspective-correct texture coordinates on the sea plane: at pixel centres the rasterized
/// coordinates (exact perspective mode) match an f64 ray cast through the same camera to the
/// plane `y = 0`, mapped by the same texture mapping.
#[test]
fn sea_texture_coordinates_match_ray_cast() {
    let mut s = by_name("seascape").unwrap();
    s.objects[1].perspective = Perspective::Exact;
    let cam = s.camera;
    let f = |v: Vec3| v.to_array().map(|c| c as f64 / 65536.0);
    let (eye, target) = (f(cam.eye), f(cam.target));
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let norm = |a: [f64; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|c| c / l)
    };
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let fw = norm(sub(target, eye));
    let rt = norm(cross(fw, [0.0, 1.0, 0.0]));
    let up = cross(rt, fw);
    let Projection::Perspective { focal } = cam.projection else {
        panic!()
    };
    let k = focal as f64 / 65536.0 * 120.0;
    let m = s.objects[1]
        .tex_map
        .matrix()
        .map(|r| r.map(|e| e.to_num::<f64>()));
    let t = s.objects[1]
        .tex_map
        .translation()
        .map(|e| e.to_num::<f64>());
    let (tris, _) = collect(&s, 0);
    let mut rast = Rasterizer::new(Rect::from_size(320, 240));
    let mut checked = 0;
    for (o, tri) in &tris {
        if *o != 1 {
            continue;
        }
        rast.draw(tri, &s.objects[1].options(), &mut |seg: &Segment| {
            if seg.y < 150 || seg.x0 % 7 != 0 {
                return; // well below the horizon, a sample of pixels
            }
            let (px, py) = (seg.x0 as f64 + 0.5, seg.y as f64 + 0.5);
            let (a, b) = ((px - 160.0) / k, (120.0 - py) / k);
            let d = [0, 1, 2].map(|i| fw[i] + a * rt[i] + b * up[i]);
            let l = -eye[1] / d[1];
            let p = [eye[0] + l * d[0], 0.0, eye[2] + l * d[2]];
            let ex = [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + t[i]);
            let got = seg.s_at(0).map(|c| c as f64 / 65536.0);
            // Tolerance: a sixteenth of a pixel's worth of texture change, plus rounding.
            let step = [seg.ds.s, seg.ds.t, seg.ds.r].map(|c| c.to_num::<f64>().abs());
            let stepy = [seg.dsdy.s, seg.dsdy.t, seg.dsdy.r].map(|c| c.to_num::<f64>().abs());
            for i in 0..3 {
                let tol = (step[i] + stepy[i]) / 16.0 + 1e-4 * (1.0 + ex[i].abs());
                assert!(
                    (got[i] - ex[i]).abs() <= tol,
                    "pixel ({px}, {py}) comp {i}: {} vs {} (tol {tol})",
                    got[i],
                    ex[i]
                );
            }
            checked += 1;
        });
    }
    assert!(checked > 500, "{checked}");
}

/// Golden checksums of the built-in scenes' triangles: integer arithmetic only, so these are the
/// values on every target (a device running the same scenes must reproduce them).
#[test]
fn golden_checksums() {
    let got: Vec<(&str, u32)> = BUILTIN
        .iter()
        .map(|&n| {
            let s = by_name(n).unwrap();
            (n, s.checksum(s.still()))
        })
        .collect();
    let expect: [(&str, u32); 8] = GOLDEN;
    assert_eq!(got, expect);
}

const GOLDEN: [(&str, u32); 8] = [
    ("wood", 0xCE8E_14CC),
    ("marble", 0x10D7_EF39),
    ("seascape", 0x85CD_F1AB),
    ("fire", 0x3A23_1730),
    ("planet", 0x1ED3_6ED0),
    ("moonrise", 0xD1A7_6EAD),
    ("zoneplate", 0xF597_B0E9),
    ("torus", 0xCF06_1DD8),
];

#[test]
fn builtins_build_and_scene_capacities_are_checked() {
    use super::{builtin, SceneError, MAX_OBJECTS, MAX_SLOTS};
    for name in super::BUILTIN {
        assert!(super::by_name(name).is_some(), "{name}");
    }
    assert_eq!(builtin::wood().map(|s| s.objects.len()), Ok(1));
    let mut s = builtin::wood().unwrap();
    assert_eq!(s.set_frames(0, 0), Err(SceneError::NoFrames));
    assert_eq!(
        s.set_frames(4, 4),
        Err(SceneError::StillOutOfRange {
            still: 4,
            frames: 4
        })
    );
    assert_eq!((s.frames(), s.still()), (64, 0));
    assert_eq!(s.set_frames(4, 3), Ok(()));
    assert_eq!((s.frames(), s.still()), (4, 3));
    let o = s.objects[0];
    for i in 1..MAX_OBJECTS {
        assert_eq!(s.add(o), Ok(i));
    }
    assert_eq!(s.add(o), Err(SceneError::TooManyObjects));
    assert_eq!(s.objects.len(), MAX_OBJECTS);
    let slot = s.slots[0];
    for i in 1..MAX_SLOTS {
        assert_eq!(s.add_slot(slot), Ok(i as u8));
    }
    assert_eq!(s.add_slot(slot), Err(SceneError::TooManySlots));
    assert!(SceneError::TooManyObjects
        .to_string()
        .contains("at most 8 objects"));
}

/// The flight is the seascape's planes and view with the eye flying towards the horizon: the
/// sea's `t = z / 5` falls by `0.2 D` and the clouds' `t` (on a plane turned over, whose object
/// `z` is the world's `-z`) rises by `D / 50`, for `D` = half a unit a frame; nothing else moves.
#[test]
fn flight_moves_the_textures_towards_the_eye() {
    assert!(super::ANIMATIONS.iter().all(|n| !BUILTIN.contains(n)));
    let sea = by_name("seascape").unwrap();
    let fl = by_name("flight").unwrap();
    assert_eq!(fl.name, "flight");
    assert_eq!((fl.frames(), fl.still()), (128, 0));
    assert_eq!(fl.camera, sea.camera);
    assert_eq!(fl.objects.len(), 2);
    let f0 = fl.at_frame(0);
    for (a, b) in f0.objects.iter().zip(&sea.objects) {
        assert_eq!(a.tex_map, b.tex_map);
        assert_eq!(a.transform, b.transform);
    }
    let k = 40;
    let fk = fl.at_frame(k);
    let t = |s: &Scene, o: usize| s.objects[o].tex_map.translation().map(|e| e.to_bits());
    let (c0, ck) = (t(&f0, 0), t(&fk, 0));
    let (w0, wk) = (t(&f0, 1), t(&fk, 1));
    let d = i64::from(k) * i64::from(super::builtin::FLIGHT_SPEED);
    // Within a rounding of the per-frame step (one raw unit a frame).
    let near = |got: i32, want: i64| (i64::from(got) - want).abs() <= i64::from(k);
    assert!(
        near(wk[1] - w0[1], -d / 5),
        "sea t {} {}",
        wk[1] - w0[1],
        -d / 5
    );
    assert_eq!((wk[0], wk[2]), (w0[0], w0[2]));
    assert!(
        near(ck[1] - c0[1], d / 50),
        "clouds t {} {}",
        ck[1] - c0[1],
        d / 50
    );
    assert_eq!((ck[0], ck[2]), (c0[0], c0[2]));
    assert_eq!(fk.camera, sea.camera);
}
