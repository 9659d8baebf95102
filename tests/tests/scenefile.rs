//! Scene files: every example loads and renders (and is quoted in docs/scenes.md), files that
//! reproduce built-in scenes render identically, custom materials are exactly the texcore models
//! they describe, animations interpolate as documented, and every kind of bad file is rejected
//! with the file, line, column and field, without panicking.

use std::path::{Path, PathBuf};

use host_sim::scenefile::{self, SceneFileError};
use host_sim::scenes::{self, HostScene};
use host_sim::unit::{ShaderSpec, UnitConfig};
use texcore::format::{Amplitude, MatrixEntry, QuadricCoeff};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, Octaves, TextureModel};
use texcore::noise::{BasisKind, Fade, NoiseBasis};
use texcore::quadric::Quadric;
use texcore::render::Output;
use texcore::scene::{Angle, Vec3};
use texcore::table::TableWrap;
use texcore::transform::Affine3;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("examples/scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

fn parse(src: &str) -> Result<HostScene, SceneFileError> {
    scenefile::parse(src, "scene.toml")
}

fn render(s: &HostScene, frame: u32) -> Vec<[u8; 4]> {
    scenes::render_host_frame(
        s,
        frame,
        &UnitConfig::default(),
        HashKind::Permutation,
        Output::Color,
    )
    .unwrap()
    .frame
    .pixels
}

/// A copy of a scene at a smaller size (same view).
fn shrink(s: &HostScene, w: u16, h: u16) -> HostScene {
    let mut s = s.clone();
    s.scene.camera.width = w;
    s.scene.camera.height = h;
    s
}

#[test]
fn every_example_loads_renders_and_is_documented() {
    let docs = std::fs::read_to_string(root().join("docs/scenes.md")).unwrap();
    let files = examples();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    for required in [
        "wood-teapot",
        "depth",
        "layer",
        "fire",
        "marble-forming",
        "flyover",
        "turbulence",
    ] {
        assert!(
            names.iter().any(|n| n == required),
            "missing example {required}"
        );
    }
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(
            docs.contains(text.trim()),
            "docs/scenes.md does not quote {} verbatim",
            path.display()
        );
        let s = scenefile::load(path).unwrap_or_else(|e| panic!("{e}"));
        let (w, h) = s.scene.size();
        let bg = s.scene.background;
        let mut frames = vec![s.scene.still()];
        if s.scene.frames() > 1 {
            frames.extend([0, s.scene.frames() / 2, s.scene.frames() - 1]);
        }
        for f in frames {
            let px = render(&s, f);
            assert_eq!(px.len(), usize::from(w) * usize::from(h));
            let covered = px.iter().filter(|p| **p != bg).count();
            assert!(
                covered * 10 > px.len(),
                "{}: frame {f} shows almost nothing ({covered} pixels)",
                path.display()
            );
        }
    }
}

#[test]
fn example_files_reproduce_builtin_scenes_exactly() {
    let fire_file = scenefile::load(&root().join("examples/scenes/fire.toml")).unwrap();
    let fire = HostScene::builtin(texcore::scene::by_name("fire").unwrap());
    assert_eq!(fire_file.scene.frames(), 64);
    for f in (0..64).step_by(9).chain([63]) {
        assert!(render(&fire_file, f) == render(&fire, f), "fire frame {f}");
    }
    let zp_file = scenefile::load(&root().join("examples/scenes/zoneplate.toml")).unwrap();
    let zp = HostScene::builtin(texcore::scene::by_name("zoneplate").unwrap());
    assert!(render(&zp_file, 0) == render(&zp, 0));
    let mf = scenefile::load(&root().join("examples/scenes/marble-forming.toml")).unwrap();
    let marble = HostScene::builtin(texcore::scene::by_name("marble").unwrap());
    // Amplitude 0 and 1 are exact in both (in between, the built-in rounds down, files to
    // nearest).
    assert!(render(&mf, 0) == render(&marble, 0));
    assert!(render(&mf, 63) == render(&marble, 63));
}

const CAMERA: &str = "[camera]\neye = [0, 2, 6]\n";

#[test]
fn custom_material_is_the_texcore_model_it_describes() {
    let src = format!(
        r##"{CAMERA}
[materials.m]
wrap = "mod"
quadric = [1, 0.5, 0, -0.25, 2, 0, 0, 0, 0.5, 3]
keys = [[0, "#102030"], [0.25, "#405060ff"], [1, "#ffffff80"]]
key_spacing = "squared"
hash = "int"

[[materials.m.noise]]
amplitude = 0.75
scale = [4, 2, 1]
translate = [1, 2, 3]
basis = "gradient"
fade = "smooth"
turbulence = true

[[materials.m.noise]]
amplitude = -0.5
matrix = [[1, 2, 3, 4], [5, 6, 7, 8], [9, 10, 11, 12]]
basis = "mnoise"
fade = "quintic"
hash = "perm"

[[materials.m.octaves]]
count = 3
amplitude = 0.5
frequency = 1.5
rotate = true
turbulence = true

[[objects]]
mesh = "sphere"
"##
    );
    let s = parse(&src).unwrap();
    let (scene, mats) = s.frame(0, HashKind::Permutation).unwrap();
    assert_eq!(scene.slots.len(), 1);
    assert_eq!(mats.len(), 1);
    let m = &mats[0];
    let e = MatrixEntry::from_num;
    let q = |v: f64| QuadricCoeff::from_num(v);
    let mut want: TextureModel<8> = TextureModel::new(
        Quadric::from_coefficients([
            q(1.0),
            q(0.5),
            q(0.0),
            q(-0.25),
            q(2.0),
            q(0.0),
            q(0.0),
            q(0.0),
            q(0.5),
            q(3.0),
        ]),
        TableWrap::Mod,
    );
    want.push(NoiseTerm {
        amplitude: Amplitude::from_num(0.75),
        transform: Affine3::scale3(e(4), e(2), e(1)).with_translation([e(1), e(2), e(3)]),
        basis: NoiseBasis {
            kind: BasisKind::Gradient,
            fade: Fade::Smooth,
            hash: HashKind::Integer,
        },
        turbulence: true,
    })
    .unwrap();
    want.push(NoiseTerm {
        amplitude: Amplitude::from_num(-0.5),
        transform: Affine3::new(
            [[e(1), e(2), e(3)], [e(5), e(6), e(7)], [e(9), e(10), e(11)]],
            [e(4), e(8), e(12)],
        ),
        basis: NoiseBasis {
            kind: BasisKind::Modified,
            fade: Fade::Quintic,
            hash: HashKind::Permutation,
        },
        turbulence: false,
    })
    .unwrap();
    want.push_octaves(&Octaves {
        count: 3,
        base: Affine3::scale(MatrixEntry::from_num(1.5)),
        amplitude: Amplitude::from_num(0.5),
        rotate: true,
        basis: NoiseBasis::trilinear(HashKind::Integer),
        turbulence: true,
    })
    .unwrap();
    match &m.shader {
        ShaderSpec::Model(model) => assert_eq!(**model, want),
        other => panic!("not a model: {other:?}"),
    }
    assert_eq!(m.wrap, TableWrap::Mod);
    assert!(m.squared_keys);
    assert_eq!(
        m.keys,
        vec![
            (0, [0x10, 0x20, 0x30, 255]),
            (16384, [0x40, 0x50, 0x60, 255]),
            (65536, [255, 255, 255, 0x80])
        ]
    );
    // It renders.
    let px = render(&shrink(&s, 64, 48), 0);
    assert_eq!(px.len(), 64 * 48);
}

#[test]
fn presets_take_amplitude_phase_keys_and_overrides() {
    let src = format!(
        r##"{CAMERA}
[materials.f]
preset = "fire"
amplitude = 0.5
phase = 0.25
keys = [[0, "#000000"], [1, "#ff0000"]]

[materials.w]
preset = "wood"
quadric = [2, 0, 0, 0, 2, 0, 0, 0, 0, 0]

[materials.c]
preset = "clouds"
octaves = []

[[objects]]
mesh = "sphere"
material = "f"
[[objects]]
mesh = "cube"
material = "w"
[[objects]]
mesh = "torus"
material = "c"
"##
    );
    let s = parse(&src).unwrap();
    let (_, mats) = s.frame(0, HashKind::Integer).unwrap();
    // Fire: the preset at half amplitude, then its phase (texcore's own fire phase).
    let mut fire = texcore::presets::fire(HashKind::Integer, 0).model;
    for k in 0..fire.terms().len() {
        let a = Amplitude::from_bits(fire.terms()[k].amplitude.to_bits() / 2);
        fire.set_amplitude(k, a).unwrap();
    }
    texcore::presets::set_fire_phase(&mut fire, 16384);
    match &mats[0].shader {
        ShaderSpec::Model(m) => assert_eq!(**m, fire),
        _ => panic!(),
    }
    assert_eq!(
        mats[0].keys,
        vec![(0, [0, 0, 0, 255]), (65536, [255, 0, 0, 255])]
    );
    // Wood with another quadric keeps its noise.
    let wood = texcore::presets::wood(HashKind::Integer).model;
    match &mats[1].shader {
        ShaderSpec::Model(m) => {
            assert_eq!(m.terms(), wood.terms());
            assert_eq!(m.quadric().coefficients()[0], QuadricCoeff::from_num(2));
        }
        _ => panic!(),
    }
    assert_eq!(mats[1].keys, texcore::presets::WOOD_KEYS.to_vec());
    // An empty octave list removes the preset's noise.
    match &mats[2].shader {
        ShaderSpec::Model(m) => assert!(m.terms().is_empty()),
        _ => panic!(),
    }
    // The command line's hash reaches presets that do not name one.
    let (_, perm) = s.frame(0, HashKind::Permutation).unwrap();
    assert_ne!(perm[1].shader, mats[1].shader);
}

#[test]
fn animation_tracks_interpolate_integers() {
    let src = r#"
frames = 11
[camera]
eye = [0, 2, 6]
[materials.m]
preset = "marble"
[[objects]]
name = "a"
mesh = "cube"
[[objects]]
mesh = "sphere"
[[animate]]
param = "camera.eye"
from = [0, 2, 6]
to = [10, 2, 6]
[[animate]]
param = "objects.1.position"
from = [0, 0, 0]
to = [0, 5, 0]
start = 2
end = 7
[[animate]]
param = "objects.a.rotation"
from = [0, 0, 0]
to = [0, 360, 0]
loop = true
[[animate]]
param = "materials.m.amplitude"
from = 1
to = 0
[[animate]]
param = "camera.fov"
from = 20
to = 60
"#;
    let s = parse(src).unwrap();
    assert_eq!(s.scene.frames(), 11);
    for f in 0..11u32 {
        let (scene, mats) = s.frame(f, HashKind::Permutation).unwrap();
        // Eye: x = f exactly.
        assert_eq!(
            scene.camera.eye,
            Vec3::new(f as i32 * 65536, 2 << 16, 6 << 16)
        );
        // Position: held at 0 before frame 2 and at 5 after frame 7, linear (rounded) between.
        let y = scene.objects[1].transform.translation()[1].to_bits();
        let want = match f {
            0..=2 => 0,
            7.. => 5 << 16,
            _ => ((f as i64 - 2) * (5 << 16) * 2 + 5).div_euclid(10) as i32,
        };
        assert_eq!(y, want, "frame {f}");
        // Rotation loops: frame f is f/11 of a turn (frame 11 would be a whole turn).
        let a = Angle(((f as u64 * (1u64 << 32) * 2 + 11) / 22) as u32);
        assert_eq!(
            scene.objects[0].transform,
            Affine3::rotate_y(a),
            "frame {f}"
        );
        // Amplitude factor from 1 down to 0.
        let factor = 65536 - ((f as i64 * 65536 * 2 + 10) / 20);
        let marble = texcore::presets::marble(HashKind::Permutation).model;
        if let ShaderSpec::Model(m) = &mats[0].shader {
            for (t, t0) in m.terms().iter().zip(marble.terms()) {
                let want = (i64::from(t0.amplitude.to_bits()) * factor) >> 16;
                if factor != 65536 {
                    assert_eq!(i64::from(t.amplitude.to_bits()), want);
                }
            }
        }
        // Frames wrap around.
        let (again, _) = s.frame(f + 11, HashKind::Permutation).unwrap();
        assert_eq!(again.camera, scene.camera);
    }
    // The fov reaches 60 degrees at the last frame.
    let (last, _) = s.frame(10, HashKind::Permutation).unwrap();
    let want = texcore::scene::focal_from_fov(Angle::from_degrees(60));
    assert_eq!(
        last.camera.projection,
        texcore::scene::Projection::Perspective { focal: want }
    );
}

#[test]
fn world_space_texture_follows_the_transform() {
    let src = format!(
        r##"{CAMERA}
[materials.m]
preset = "marble"
[[objects]]
mesh = "cube"
position = [1, 2, 3]
rotation = [10, 20, 30]
scale = [1, 2, 0.5]
pivot = [0.5, 0, 0]
texture = {{ space = "world", matrix = [[1.2, 0, 0, 3.1], [0, 1.2, 0, 0.5], [0.6, 0.75, 0.35, 0.3]] }}
"##
    );
    let s = parse(&src).unwrap();
    let o = &s.scene.objects[0];
    let deg = Angle::from_degrees;
    let t = Affine3::translate(Vec3::new(-32768, 0, 0))
        .then(&Affine3::from_bits(
            [[65536, 0, 0], [0, 131072, 0], [0, 0, 32768]],
            [0; 3],
        ))
        .then(&Affine3::rotate_x(deg(10)))
        .then(&Affine3::rotate_y(deg(20)))
        .then(&Affine3::rotate_z(deg(30)))
        .then(&Affine3::translate(Vec3::units(1, 2, 3)));
    assert_eq!(o.transform, t);
    let block = Affine3::from_f64(
        [[1.2, 0.0, 0.0], [0.0, 1.2, 0.0], [0.6, 0.75, 0.35]],
        [3.1, 0.5, 0.3],
    );
    assert_eq!(o.tex_map, t.then(&block));
}

#[test]
fn defaults_and_drawing_options() {
    let src = format!(
        r##"{CAMERA}
[materials.m]
preset = "planet"
[[objects]]
mesh = "sphere"
blend = "over"
perspective = "exact"
cull = "ccw"
depth_test = false
depth_write = false
[[objects]]
mesh = {{ kind = "plane", rings = 3 }}
perspective = "every8"
cull = "cw"
"##
    );
    let s = parse(&src).unwrap();
    let sc = &s.scene;
    assert_eq!(sc.name, "scene");
    assert_eq!(sc.size(), (320, 240));
    assert_eq!(sc.background, [0, 0, 0, 255]);
    assert_eq!((sc.frames(), sc.still()), (1, 0));
    use texcore::raster::{CullMode, Perspective};
    use texcore::scene::{Blend, Mesh};
    let a = &sc.objects[0];
    assert_eq!(
        a.mesh,
        Mesh::Sphere {
            radius: 65536,
            stacks: 16,
            slices: 32
        }
    );
    assert_eq!(
        (a.blend, a.perspective, a.cull, a.depth_test, a.depth_write),
        (
            Blend::Over,
            Perspective::Exact,
            CullMode::CounterClockwise,
            false,
            false
        )
    );
    let b = &sc.objects[1];
    assert_eq!(
        b.mesh,
        Mesh::Plane {
            half_size: 12000 << 16,
            rings: 3
        }
    );
    assert_eq!(
        (b.blend, b.perspective, b.cull, b.depth_test, b.depth_write),
        (
            Blend::Opaque,
            Perspective::Every8,
            CullMode::Clockwise,
            true,
            true
        )
    );
    // The camera's defaults: target the origin, y up, 40 degrees, near 0.1, far 1000.
    let c = &sc.camera;
    assert_eq!(c.target, Vec3::ZERO);
    assert_eq!(c.up, Vec3::Y);
    assert_eq!(
        c.projection,
        texcore::scene::Projection::Perspective {
            focal: texcore::scene::focal_from_fov(Angle::from_degrees(40))
        }
    );
    assert_eq!((c.near, c.far), (6554, 1000 << 16));
}

/// `(file text, "line:column: field", message fragment)`.
fn bad_files() -> Vec<(String, &'static str, &'static str)> {
    let m = "[materials.m]\npreset = \"wood\"\n";
    let obj = "[[objects]]\nmesh = \"teapot\"\n";
    vec![
        // Syntax.
        ("[camera\neye = [0, 1, 2]\n".into(), "1:8", "expected"),
        (format!("{CAMERA}{m}{obj}level = = 3\n"), "7:9", ""),
        // Types and unknown fields.
        (
            "[camera]\neye = [0, 2, 6]\nfovv = 30\n".into(),
            "3:1: camera.fovv",
            "unknown field `fovv`",
        ),
        (
            "[camera]\neye = [0, 2, 6]\nfov = \"wide\"\n".into(),
            "3:7: camera.fov",
            "invalid type",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nmesh = {{ kind = \"sphere\", levl = 4 }}\n"),
            "6:27: objects[0].mesh.levl",
            "unknown field `levl`",
        ),
        (
            format!("{CAMERA}{m}{obj}blend = \"add\"\n"),
            "7:9: objects[0].blend",
            "unknown variant `add`",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nmaterial = \"m\"\n"),
            "5:1: objects[0]",
            "missing field `mesh`",
        ),
        ("width = 320\n".into(), "1:1", "missing field `camera`"),
        (
            format!("{CAMERA}{m}[[materials.m.noise]]\nscale = 2\nsize = 3\n"),
            "7:1: materials.m.noise[0].size",
            "unknown field `size`",
        ),
        (
            format!("{CAMERA}{m}{obj}[objects.texture]\nspace = \"world\"\nskew = 1\n"),
            "9:1: objects[0].texture.skew",
            "unknown field `skew`",
        ),
        (
            format!("frames = 2\n{CAMERA}{m}{obj}[[animate]]\nparam = \"camera.eye\"\nfrom = [0, 2, 6]\nto = [1, 2, 6]\nease = 1\n"),
            "12:1: animate[0].ease",
            "unknown field `ease`",
        ),
        // Ranges.
        (
            "[camera]\neye = [0, 2, 6]\nfov = 0\n".into(),
            "3:7: camera.fov",
            "0 is out of range (0 < fov < 180 degrees)",
        ),
        (
            "[camera]\neye = [0, 2, 6]\nfov = 180\n".into(),
            "3:7: camera.fov",
            "out of range",
        ),
        (
            "width = 5000\n[camera]\neye = [0, 2, 6]\n".into(),
            "1:9: width",
            "5000 is out of range (1 <= width <= 4096)",
        ),
        (
            "[camera]\neye = [0, 2, 6]\nnear = 2\nfar = 1\n".into(),
            "4:7: camera.far",
            "must be beyond near",
        ),
        (
            "[camera]\neye = [0, 40000, 6]\n".into(),
            "2:7: camera.eye[1]",
            "40000 is out of range",
        ),
        (
            "[camera]\neye = [0, 2, 6]\nnear = nan\n".into(),
            "3:8: camera.near",
            "NaN is out of range",
        ),
        (
            "[camera]\neye = [0, 2, 6]\nfar = inf\n".into(),
            "3:7: camera.far",
            "inf is out of range",
        ),
        (
            "frames = 3\nstill = 3\n[camera]\neye = [0, 2, 6]\n".into(),
            "2:9: still",
            "3 is out of range (0 <= still <= 2)",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nmesh = {{ kind = \"teapot\", level = 17 }}\n"),
            "6:35: objects[0].mesh.level",
            "17 is out of range (1 <= level <= 16)",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nmesh = {{ kind = \"teapot\", radius = 3 }}\n"),
            "6:36: objects[0].mesh.radius",
            "a teapot mesh has no radius",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nmesh = \"spher\"\n"),
            "6:8: objects[0].mesh.kind",
            "unknown mesh `spher`",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nmesh = {{ kind = \"quad\", corners = [[0, 0, 0]] }}\n"),
            "6:35: objects[0].mesh.corners",
            "expected 4 corners",
        ),
        (
            format!("{CAMERA}{m}{obj}scale = 0\n"),
            "7:9: objects[0].scale",
            "0 is out of range (0 < |scale| <= 32767)",
        ),
        (
            format!("{CAMERA}{m}{obj}scale = [1, 2]\n"),
            "7:9: objects[0].scale",
            "an array of 2 values",
        ),
        (
            format!("{CAMERA}{m}{obj}rotation = [0, 1e9, 0]\n"),
            "7:12: objects[0].rotation[1]",
            "out of range",
        ),
        (
            format!("{CAMERA}{m}{obj}texture = {{ scale = 2, matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]] }}\n"),
            "7:33: objects[0].texture.matrix",
            "either `scale` or `matrix`",
        ),
        (
            format!("{CAMERA}{m}{obj}texture = {{ matrix = [[1, 0], [0, 1]] }}\n"),
            "7:22: objects[0].texture.matrix",
            "expected 3 rows",
        ),
        // Materials.
        (
            format!("{CAMERA}[materials.m]\npreset = \"teak\"\n{obj}"),
            "4:10: materials.m.preset",
            "unknown preset `teak`",
        ),
        (
            format!("{CAMERA}[materials.m]\nquadric = [1, 0, 0]\n{obj}"),
            "3:1: materials.m.keys",
            "needs colour keys",
        ),
        (
            format!("{CAMERA}[materials.m]\nkeys = [[0, \"#000000\"]]\nquadric = [1, 0, 0]\n{obj}"),
            "5:11: materials.m.quadric",
            "expected 10 coefficients",
        ),
        (
            format!("{CAMERA}[materials.m]\nkeys = [[0.5, \"#000000\"], [0.25, \"#ffffff\"]]\n{obj}"),
            "4:28: materials.m.keys[1]",
            "keys must be in order",
        ),
        (
            format!("{CAMERA}[materials.m]\nkeys = [[0, \"#ggg000\"]]\n{obj}"),
            "4:13: materials.m.keys[0]",
            "is not a colour",
        ),
        (
            format!("{CAMERA}[materials.m]\nkeys = [[1.5, \"#000000\"]]\n{obj}"),
            "4:10: materials.m.keys[0]",
            "1.5 is out of range (0 <= position <= 1)",
        ),
        (
            format!("{CAMERA}{m}amplitude = 600\n{obj}"),
            "5:13: materials.m.amplitude",
            "600 is out of range (|amplitude| <= 512)",
        ),
        (
            format!("{CAMERA}{m}amplitude = 400\n[[materials.m.noise]]\namplitude = 300\n{obj}"),
            "5:13: materials.m.amplitude",
            "at most 512",
        ),
        (
            format!("{CAMERA}{m}[[materials.m.octaves]]\ncount = 9\n{obj}"),
            "6:9: materials.m.octaves[0].count",
            "9 is out of range (1 <= count <= 8)",
        ),
        (
            format!("{CAMERA}{m}[[materials.m.octaves]]\ncount = 6\n[[materials.m.octaves]]\ncount = 3\n{obj}"),
            "8:9: materials.m.octaves[1].count",
            "at most 8 noise terms",
        ),
        (
            format!("{CAMERA}[materials.m]\npreset = \"mn-marble\"\nphase = 1\n{obj}"),
            "5:9: materials.m.phase",
            "perturbed material",
        ),
        (
            format!("{CAMERA}[materials.\"a.b\"]\npreset = \"wood\"\n{obj}"),
            "3:1: materials.a.b",
            "not a valid name",
        ),
        // References.
        (
            format!("{CAMERA}{m}[[objects]]\nmesh = \"cube\"\nmaterial = \"x\"\n"),
            "7:12: objects[0].material",
            "no material `x`",
        ),
        (
            format!("{CAMERA}{m}[materials.n]\npreset = \"fire\"\n{obj}"),
            "7:1: objects[0].material",
            "missing",
        ),
        (
            format!("{CAMERA}{m}{}", obj.repeat(9)),
            "21:1: objects[8]",
            "at most 8 objects",
        ),
        (
            format!("{CAMERA}{m}[[objects]]\nname = \"a\"\nmesh = \"cube\"\n[[objects]]\nname = \"a\"\nmesh = \"cube\"\n"),
            "9:8: objects[1].name",
            "already named `a`",
        ),
        // Cameras.
        (
            "[camera]\neye = [0, 2, 6]\ntarget = [0, 2, 6]\n".into(),
            "3:10: camera.target",
            "target == eye",
        ),
        (
            "[camera]\neye = [0, 2, 6]\nup = [0, 0, 1]\ntarget = [0, 2, 0]\n".into(),
            "1:1: camera",
            "degenerate",
        ),
        (
            "[camera]\nprojection = \"orthographic\"\neye = [0, 2, 6]\n".into(),
            "1:1: camera.half_height",
            "needs half_height",
        ),
        (
            "[camera]\nprojection = \"orthographic\"\neye = [0, 2, 6]\nhalf_height = 1\nfov = 30\n".into(),
            "5:7: camera.fov",
            "no field of view",
        ),
        // Animation.
        (
            format!("{CAMERA}{m}{obj}[[animate]]\nparam = \"camera.eye\"\nfrom = [0, 2, 6]\nto = [1, 2, 6]\n"),
            "7:1: animate[0]",
            "one frame cannot be animated",
        ),
        (
            format!("frames = 4\n{CAMERA}{m}{obj}[[animate]]\nparam = \"camera.zoom\"\nfrom = 1\nto = 2\n"),
            "9:9: animate[0].param",
            "not an animatable parameter",
        ),
        (
            format!("frames = 4\n{CAMERA}{m}{obj}[[animate]]\nparam = \"objects.pot.rotation\"\nfrom = [0, 0, 0]\nto = [0, 1, 0]\n"),
            "9:9: animate[0].param",
            "no object `pot`",
        ),
        (
            format!("frames = 4\n{CAMERA}{m}{obj}[[animate]]\nparam = \"camera.eye\"\nfrom = 1\nto = [0, 1, 0]\n"),
            "10:8: animate[0].from",
            "expected an array of 3 numbers",
        ),
        (
            format!("frames = 4\n{CAMERA}{m}{obj}[[animate]]\nparam = \"camera.fov\"\nfrom = 10\nto = 200\n"),
            "11:6: animate[0].to",
            "200 is out of range (0 < fov < 180 degrees)",
        ),
        (
            format!("frames = 4\n{CAMERA}{m}{obj}[[animate]]\nparam = \"camera.eye\"\nfrom = [0, 2, 6]\nto = [0, 0, 0]\n"),
            "8:1: animate[0]",
            "at frame 3: the camera is degenerate",
        ),
        (
            format!("frames = 4\n{CAMERA}{m}{obj}[[animate]]\nparam = \"materials.m.amplitude\"\nfrom = 1\nto = 2\nstart = 2\nend = 1\n"),
            "13:7: animate[0].end",
            "must be after start",
        ),
    ]
}

#[test]
fn bad_files_name_file_line_column_and_field() {
    let mut wrong = Vec::new();
    for (src, at, msg) in bad_files() {
        let e = match parse(&src) {
            Ok(_) => panic!("accepted:\n{src}"),
            Err(e) => e,
        };
        let text = e.to_string();
        if !text.starts_with(&format!("scene.toml:{at}")) || !text.contains(msg) {
            wrong.push(format!(
                "expected `scene.toml:{at}...{msg}...`, got `{text}`"
            ));
        }
        assert!(e.line > 0 && e.column > 0);
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn unreadable_file_is_an_error() {
    let e = scenefile::load(Path::new("/nonexistent/scene.toml"))
        .err()
        .unwrap();
    assert_eq!(e.line, 0);
    assert!(e.to_string().starts_with("/nonexistent/scene.toml: "));
}

/// Every number of every example replaced by extreme values: loading never panics, and what
/// loads renders (small) without panicking.
#[test]
fn extreme_values_never_panic() {
    let extremes = [
        "0", "-0.0", "1e-9", "-1", "65535", "1e9", "-1e300", "nan", "inf", "-inf", "4097", "7",
    ];
    let mut loaded = 0;
    let mut rejected = 0;
    for path in examples() {
        let text = std::fs::read_to_string(&path).unwrap();
        // Byte ranges of the numbers outside comments and strings.
        let mut numbers = Vec::new();
        for (start, line) in text.split_inclusive('\n').scan(0, |pos, l| {
            let s = *pos;
            *pos += l.len();
            Some((s, l))
        }) {
            let code = line.split('#').next().unwrap_or("");
            let code = if line.contains('"') {
                // Keep it simple: only lines without strings (colours, names).
                ""
            } else {
                code
            };
            let b = code.as_bytes();
            let mut i = 0;
            while i < b.len() {
                let starts = (b[i].is_ascii_digit() || b[i] == b'-')
                    && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
                if starts {
                    let j = (i + 1..b.len())
                        .find(|&j| !(b[j].is_ascii_alphanumeric() || b[j] == b'.' || b[j] == b'-'))
                        .unwrap_or(b.len());
                    if b[i..j].iter().any(u8::is_ascii_digit) {
                        numbers.push(start + i..start + j);
                    }
                    i = j;
                } else {
                    i += 1;
                }
            }
        }
        for (k, r) in numbers.iter().enumerate() {
            let v = extremes[k % extremes.len()];
            let src = format!("{}{v}{}", &text[..r.start], &text[r.end..]);
            match scenefile::parse(&src, "x.toml") {
                Ok(s) => {
                    loaded += 1;
                    let s = shrink(&s, 24, 16);
                    let _ = scenes::render_host_frame(
                        &s,
                        s.scene.frames() - 1,
                        &UnitConfig::default(),
                        HashKind::Integer,
                        Output::Color,
                    );
                }
                Err(e) => {
                    rejected += 1;
                    assert!(e.line > 0, "{e}");
                }
            }
        }
    }
    assert!(
        loaded > 20 && rejected > 20,
        "{loaded} loaded, {rejected} rejected"
    );
}

#[test]
fn every_animatable_parameter_reaches_the_scene() {
    let src = r#"
frames = 3
[camera]
projection = "orthographic"
eye = [0, 0, 5]
half_height = 1
[materials.m]
preset = "clouds"
[[objects]]
name = "q"
mesh = "cube"
[[animate]]
param = "camera.target"
from = [0, 0, 0]
to = [2, 0, 0]
[[animate]]
param = "camera.half_height"
from = 1
to = 3
[[animate]]
param = "objects.q.scale"
from = 1
to = [1, 2, 3]
[[animate]]
param = "objects.q.texture.translate"
from = [0, 0, 0]
to = [4, 0, -4]
[[animate]]
param = "materials.m.phase"
from = 0
to = 0.5
"#;
    let s = parse(src).unwrap();
    let (sc, mats) = s.frame(1, HashKind::Permutation).unwrap();
    assert_eq!(sc.camera.target, Vec3::units(1, 0, 0));
    assert_eq!(
        sc.camera.projection,
        texcore::scene::Projection::Orthographic {
            half_height: 2 << 16
        }
    );
    assert_eq!(
        sc.objects[0].transform,
        Affine3::from_bits([[65536, 0, 0], [0, 98304, 0], [0, 0, 131072]], [0; 3])
    );
    let t = sc.objects[0].tex_map.translation();
    assert_eq!(t.map(|e| e.to_bits()), [2 << 16, 0, -2 << 16]);
    assert_eq!(sc.slots[0].phase, 16384);
    // The phase moved every noise term by -T_k (0, 0.25, 0).
    let clouds = texcore::presets::clouds(HashKind::Permutation).model;
    match &mats[0].shader {
        ShaderSpec::Model(m) => {
            for (a, b) in m.terms().iter().zip(clouds.terms()) {
                let ty = b.transform.matrix()[1][1].to_bits();
                assert_eq!(
                    a.transform.translation()[1].to_bits(),
                    -((i64::from(ty) * 16384) >> 16) as i32
                );
            }
        }
        _ => panic!(),
    }
}
