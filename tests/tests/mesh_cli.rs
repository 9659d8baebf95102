//! `texsim mesh pack` and `texsim atlas` as separate processes (the harness of `cli.rs`): bad
//! meshes exit 2 naming the file and line and write nothing; good ones pack and lay out.

use std::path::{Path, PathBuf};

use texcore_tests::child::{s, texsim, tmp_dir};

texcore_tests::texsim_child_test!();

/// A fresh temporary directory for one test.
fn tmp(name: &str) -> PathBuf {
    tmp_dir("texsim-mesh", name)
}

fn bunny() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/meshes/bunny.obj")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn bad_meshes_exit_2_naming_file_and_line_and_write_nothing() {
    let d = tmp("bad");
    let ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let mut over = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for _ in 0..70000 {
        over.push_str("f 1 2 3\n");
    }
    let cases: Vec<(&str, String, Option<&str>)> = vec![
        ("malformed.obj", "v 0 0 0\nv 1 zero 0\n".into(), Some(":2:")),
        (
            "nan.obj",
            "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n".into(),
            Some(":3:"),
        ),
        (
            "huge.obj",
            "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n".into(),
            Some(":2:"),
        ),
        (
            "degenerate.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n".into(),
            Some(":4:"),
        ),
        (
            "repeated.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 3\n".into(),
            Some(":4:"),
        ),
        (
            "duplicate.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 3 1 2\n".into(),
            Some(":7:"),
        ),
        (
            "range.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n".into(),
            Some(":4:"),
        ),
        ("over.obj", over, Some(":")),
        ("empty.obj", String::new(), None),
        ("empty.ply", String::new(), None),
        (
            "malformed.ply",
            "ply\nformat ascii 1.0\nelement vertex x\n".into(),
            Some(":3:"),
        ),
        (
            "range.ply",
            format!("{ply_head}0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n"),
            Some(":13:"),
        ),
        (
            "nan.ply",
            format!("{ply_head}0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n"),
            Some(":12:"),
        ),
    ];
    for (file, text, line) in &cases {
        let path = d.join(file);
        std::fs::write(&path, text).unwrap();
        let out = d.join(format!("{file}.mesh"));
        let r = texsim(&["mesh", "pack", s(&path), "-o", s(&out)]);
        assert_eq!(r.status, 2, "{file}: {} {}", r.stdout, r.stderr);
        assert!(r.stderr.contains(file), "{file}: {}", r.stderr);
        if let Some(l) = line {
            assert!(
                r.stderr.contains(&format!("{file}{l}")),
                "{file}: {}",
                r.stderr
            );
        }
        assert!(!out.exists(), "{file}: output written");
        // The atlas command refuses it too, writing nothing.
        let png = d.join(format!("{file}.png"));
        let r = texsim(&["atlas", s(&path), "--size", "64", "-o", s(&png)]);
        assert_eq!(r.status, 2, "{file}: {}", r.stderr);
        assert!(!png.exists());
    }
    assert!(std::fs::read_dir(&d).unwrap().all(|e| {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        !n.ends_with(".mesh") && !n.ends_with(".png") && !n.contains(".tmp")
    }));
}

#[test]
fn bunny_packs_and_lays_out() {
    let d = tmp("good");
    let out = d.join("bunny.mesh");
    let r = texsim(&["mesh", "pack", &bunny(), "-o", s(&out)]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    let bytes = std::fs::read(&out).unwrap();
    let m = texcore::packed_mesh::PackedMesh::new(&bytes).unwrap();
    assert_eq!((m.vertex_count(), m.triangle_count()), (1839, 3674));
    let png = d.join("atlas.png");
    let r = texsim(&[
        "atlas",
        &bunny(),
        "--kind",
        "length",
        "--size",
        "256",
        "-o",
        s(&png),
        "--json",
    ]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    let j: serde_json::Value = serde_json::from_str(r.stdout.trim()).unwrap();
    assert_eq!(j["triangles"], 3674);
    assert_eq!(j["size"], 256);
    let c = j["coverage"].as_f64().unwrap();
    assert!(c > 0.0 && c <= 1.0, "{c}");
    assert!(j["relative_scale"].as_f64().unwrap() > 0.0);
    assert!(png.exists());
    // Too small an atlas is bad input.
    let r = texsim(&["atlas", &bunny(), "--kind", "mip", "--size", "64"]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("do not fit"), "{}", r.stderr);
}

/// A scene file's mesh file: loaded relative to the scene file; a bad one is bad input naming
/// the mesh file and line, and nothing is written.
#[test]
fn scene_files_take_mesh_files() {
    let d = tmp("scene");
    std::fs::create_dir_all(d.join("m")).unwrap();
    std::fs::write(
        d.join("m/tet.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    std::fs::write(d.join("m/bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").unwrap();
    let scene = |mesh: &str| {
        format!(
            "[camera]\neye = [2, 2, 3]\ntarget = [0.3, 0.3, 0.3]\n[materials.m]\npreset = \"marble\"\n[[objects]]\nmesh = {{ file = \"{mesh}\" }}\n"
        )
    };
    std::fs::write(d.join("good.toml"), scene("m/tet.obj")).unwrap();
    std::fs::write(d.join("bad.toml"), scene("m/bad.obj")).unwrap();
    std::fs::write(d.join("missing.toml"), scene("m/none.obj")).unwrap();
    let png = d.join("good.png");
    let r = texsim(&["render", s(&d.join("good.toml")), "-o", s(&png), "--stats"]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    assert!(png.exists());
    for (file, what) in [("bad.toml", "bad.obj:4:"), ("missing.toml", "none.obj")] {
        let out = d.join(format!("{file}.png"));
        let r = texsim(&["render", s(&d.join(file)), "-o", s(&out)]);
        assert_eq!(r.status, 2, "{file}");
        assert!(r.stderr.contains(what), "{file}: {}", r.stderr);
        assert!(
            r.stderr.contains("objects[0].mesh.file"),
            "{file}: {}",
            r.stderr
        );
        assert!(!out.exists());
    }
}

/// `shading = "atlas"` draws an object from its baked atlas (here a bunny next to a procedural
/// cube): the frame is written and compared with the all-procedural one; a bad atlas size exits
/// 2 naming the file and line, writing nothing.
#[test]
fn scene_files_draw_objects_from_atlases() {
    let d = tmp("shading");
    let scene = |extra: &str| {
        format!(
            "width = 160\nheight = 120\n[camera]\neye = [0, 2.2, 7]\ntarget = [0, 1.4, 0]\nfov = 40\n\
             [materials.m]\npreset = \"marble\"\n\
             [[objects]]\nmesh = \"cube\"\nmaterial = \"m\"\nposition = [-2.2, 0.5, 0]\n\
             [[objects]]\nmesh = {{ file = \"{}\" }}\nmaterial = \"m\"\nscale = 0.3\n\
             texture = {{ scale = 0.25 }}\nshading = \"atlas\"\n{extra}",
            bunny().replace('\\', "/")
        )
    };
    std::fs::write(
        d.join("good.toml"),
        scene("atlas = { size = 512, sampling = \"bilinear\" }\n"),
    )
    .unwrap();
    std::fs::write(d.join("bad.toml"), scene("atlas = { size = 500 }\n")).unwrap();
    let png = d.join("good.png");
    let r = texsim(&["render", s(&d.join("good.toml")), "-o", s(&png), "--json"]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    assert!(png.exists());
    let j: serde_json::Value = serde_json::from_str(r.stdout.trim()).unwrap();
    let psnr = j["psnr_vs_procedural"].as_f64().unwrap();
    assert!(j["baked_texels"].as_u64().unwrap() > 10_000, "{j}");
    assert!(psnr > 25.0 && psnr < 99.0, "{j}");
    let out = d.join("bad.png");
    let r = texsim(&["render", s(&d.join("bad.toml")), "-o", s(&out)]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("bad.toml:19:"), "{}", r.stderr);
    assert!(r.stderr.contains("objects[1].atlas.size"), "{}", r.stderr);
    assert!(!out.exists());
}
