//! The `texsim` command line, run as a separate process: this test binary re-executes itself
//! with the command line in an environment variable, and its `texsim_child` test runs
//! `host_sim::cli::run` on it and exits with its status (no `cargo run`, no stale binary under
//! `target/`). The parent sees the real exit status, stdout, stderr and output files.

use std::path::{Path, PathBuf};

use texcore_tests::child::{s, texsim, tmp_dir, Run};

texcore_tests::texsim_child_test!();

/// A fresh temporary directory for one test.
fn tmp(name: &str) -> PathBuf {
    tmp_dir("texsim-cli", name)
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn example(name: &str) -> String {
    root()
        .join("examples/scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// Decodes a PNG (the first frame of an APNG) to RGBA8.
fn read_png(path: &Path) -> (u32, u32, Vec<[u8; 4]>) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    let (w, h) = img.dimensions();
    (w, h, img.pixels().map(|p| p.0).collect())
}

fn ok(r: &Run, what: &str) {
    assert_eq!(r.status, 0, "{what}: exit {}: {}", r.status, r.stderr);
}

#[test]
fn scenes_lists_the_builtin_scenes_and_animations_name_first() {
    let r = texsim(&["scenes"]);
    ok(&r, "scenes");
    let names: Vec<&str> = r
        .stdout
        .lines()
        .map(|l| l.split_whitespace().next().unwrap_or(""))
        .collect();
    assert_eq!(
        names,
        [
            "wood",
            "marble",
            "seascape",
            "fire",
            "planet",
            "moonrise",
            "zoneplate",
            "torus",
            "flight"
        ]
    );
}

/// `texsim render zoneplate --aa none`: 256x256, pixel `(x, y)` is white exactly where
/// `f mod 1 < 1/2` and black elsewhere, for `f = 50 s^2 + 50 t^2`, `s = (x + 0.5) / 256`,
/// `t = (y + 0.5) / 256`, computed exactly in f64 (`f = 50 ((2x+1)^2 + (2y+1)^2) / 2^18`).
#[test]
fn zone_plate_without_antialiasing_is_exact() {
    let dir = tmp("zoneplate");
    let out = dir.join("zp.png");
    ok(
        &texsim(&["render", "zoneplate", "--aa", "none", "-o", s(&out)]),
        "render zoneplate",
    );
    let (w, h, px) = read_png(&out);
    assert_eq!((w, h), (256, 256));
    let m =
        host_sim::unit::preset_material("zoneplate", texcore::hash::HashKind::default()).unwrap();
    let table = host_sim::unit::table::<256>(&m).unwrap();
    let entries: Vec<[u8; 4]> = table.entries().iter().map(|c| c.to_array()).collect();
    // The zebra table: entries 0..127 white, 128..255 black.
    for (k, e) in entries.iter().enumerate() {
        let want = if k < 128 {
            [255, 255, 255, 255]
        } else {
            [0, 0, 0, 255]
        };
        assert_eq!(*e, want, "entry {k}");
    }
    let mut wrong = 0;
    let mut white = 0;
    for y in 0..256u32 {
        for x in 0..256u32 {
            let s = (f64::from(x) + 0.5) / 256.0;
            let t = (f64::from(y) + 0.5) / 256.0;
            let f = 50.0 * s * s + 50.0 * t * t;
            let frac = f.rem_euclid(1.0);
            let p = px[(y * 256 + x) as usize];
            let want = if frac < 0.5 {
                [255, 255, 255, 255]
            } else {
                [0, 0, 0, 255]
            };
            if p != want {
                wrong += 1;
            }
            white += usize::from(frac < 0.5);
        }
    }
    assert_eq!(wrong, 0, "{wrong} pixels differ from the exact zone plate");
    assert!(white > 30_000 && white < 36_000);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn forward_differencing_equals_direct_evaluation_for_every_builtin_scene() {
    let dir = tmp("eval");
    for name in texcore::scene::BUILTIN {
        let a = dir.join(format!("{name}-fd.png"));
        let b = dir.join(format!("{name}-direct.png"));
        ok(
            &texsim(&["render", name, "--eval", "fd", "-o", s(&a)]),
            name,
        );
        ok(
            &texsim(&["render", name, "--eval", "direct", "-o", s(&b)]),
            name,
        );
        let (pa, pb) = (read_png(&a), read_png(&b));
        assert!(pa == pb, "{name}: --eval fd and --eval direct differ");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `texsim render <scene> --checksum` prints the frame checksum the device's strip jobs must
/// add up to (`host_sim::report::host_builtin_scene_checksum`, which `texsim report cycles` and
/// the firmware test compare the device with), for both lattice hashes.
#[test]
fn render_checksum_is_the_device_frame_checksum() {
    use texcore::hash::HashKind;
    for name in texcore::scene::BUILTIN {
        for (hash, args) in [
            (HashKind::Permutation, &[][..]),
            (HashKind::Integer, &["--hash", "int"][..]),
        ] {
            let mut cmd = vec!["render", name, "--checksum"];
            cmd.extend_from_slice(args);
            let r = texsim(&cmd);
            ok(&r, name);
            let want = host_sim::report::host_builtin_scene_checksum(name, hash).unwrap();
            assert_eq!(r.stdout.trim(), format!("{want:08x}"), "{cmd:?}");
        }
    }
}

fn stats(args: &[&str]) -> serde_json::Value {
    let r = texsim(args);
    ok(&r, &args.join(" "));
    let v: serde_json::Value = serde_json::from_str(r.stdout.trim())
        .unwrap_or_else(|e| panic!("{args:?}: not JSON ({e}): {}", r.stdout));
    assert!(v.is_object());
    v
}

fn count(v: &serde_json::Value, key: &str) -> u64 {
    v.get(key)
        .and_then(serde_json::Value::as_u64)
        .unwrap_or_else(|| panic!("no `{key}` in {v}"))
}

#[test]
fn stats_json_counts_only_the_stages_that_run() {
    let dir = tmp("stats");
    let out = dir.join("out.png");
    let out = s(&out);
    let opaque = ["wood", "marble", "seascape", "fire", "zoneplate", "torus"];
    for name in texcore::scene::BUILTIN {
        let v = stats(&["render", name, "--stats", "--json", "-o", out]);
        let noise = count(&v, "noise_evaluations");
        let grad = count(&v, "gradient_evaluations");
        if name == "zoneplate" {
            assert_eq!(noise, 0, "the zone plate has no noise");
        } else {
            assert!(noise > 0, "{name}");
        }
        assert!(grad > 0, "{name}: antialiasing needs gradients");
        if opaque.contains(&name) {
            assert_eq!(count(&v, "blended_pixels"), 0, "{name} is opaque");
        } else {
            assert!(count(&v, "blended_pixels") > 0, "{name} blends");
        }
        let v = stats(&[
            "render", name, "--aa", "none", "--stats", "--json", "-o", out,
        ]);
        assert_eq!(count(&v, "gradient_evaluations"), 0, "{name} --aa none");
    }
    // Scene files: affine-only objects need no perspective divides; the teapot does.
    for file in ["fire.toml", "zoneplate.toml"] {
        let v = stats(&["render", &example(file), "--stats", "--json", "-o", out]);
        assert_eq!(count(&v, "perspective_divides"), 0, "{file}");
        assert!(count(&v, "pixels") > 0);
    }
    let affine = dir.join("affine.toml");
    std::fs::write(
        &affine,
        "[camera]\neye = [0, 1, 5]\n[materials.m]\npreset = \"marble\"\n\
         [[objects]]\nmesh = \"cube\"\nperspective = \"affine\"\n\
         [[objects]]\nmesh = { kind = \"sphere\", radius = 0.5 }\nposition = [1, 1, 1]\nperspective = \"affine\"\n",
    )
    .unwrap();
    let v = stats(&["render", s(&affine), "--stats", "--json", "-o", out]);
    assert_eq!(count(&v, "perspective_divides"), 0);
    assert!(count(&v, "triangles") > 12);
    let v = stats(&[
        "render",
        &example("wood-teapot.toml"),
        "--stats",
        "--json",
        "-o",
        out,
    ]);
    assert!(count(&v, "perspective_divides") > 0);
    assert_eq!(count(&v, "blended_pixels"), 0);
    let v = stats(&[
        "render",
        &example("layer.toml"),
        "--stats",
        "--json",
        "-o",
        out,
    ]);
    assert!(count(&v, "blended_pixels") > 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gallery_writes_one_png_per_builtin_scene() {
    let dir = tmp("gallery");
    let g = dir.join("g");
    let r = texsim(&["gallery", s(&g)]);
    ok(&r, "gallery");
    let mut files: Vec<String> = std::fs::read_dir(&g)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut want: Vec<String> = texcore::scene::BUILTIN
        .iter()
        .map(|n| format!("{n}.png"))
        .chain(["torus-widths.png".to_string()])
        .collect();
    want.sort();
    assert_eq!(files, want);
    for name in texcore::scene::BUILTIN {
        let (w, h, _) = read_png(&g.join(format!("{name}.png")));
        let scene = texcore::scene::by_name(name).unwrap();
        assert_eq!(
            (w, h),
            (u32::from(scene.size().0), u32::from(scene.size().1))
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_scene_files_exit_2_and_write_nothing() {
    let dir = tmp("bad");
    let cases: [(&str, &str, &str); 7] = [
        ("syntax.toml", "[camera\neye = [0, 1, 5]\n", "syntax.toml:1:8"),
        (
            "range.toml",
            "[camera]\neye = [0, 1, 5]\nfov = 0\n",
            "range.toml:3:7: camera.fov: 0 is out of range (0 < fov < 180 degrees)",
        ),
        (
            "unknown.toml",
            "[camera]\neye = [0, 1, 5]\n[materials.m]\npreset = \"wood\"\ncolour = 1\n",
            "unknown.toml:5:1: materials.m.colour: unknown field `colour`",
        ),
        (
            "type.toml",
            "width = \"wide\"\n[camera]\neye = [0, 1, 5]\n",
            "type.toml:1:9: width: invalid type",
        ),
        (
            "reference.toml",
            "[camera]\neye = [0, 1, 5]\n[materials.m]\npreset = \"wood\"\n[[objects]]\nmesh = \"cube\"\nmaterial = \"oak\"\n",
            "reference.toml:7:12: objects[0].material: no material `oak`",
        ),
        (
            "mesh.toml",
            "[camera]\neye = [0, 1, 5]\n[materials.m]\npreset = \"wood\"\n[[objects]]\nmesh = { kind = \"teapot\", level = 0 }\n",
            "mesh.toml:6:35: objects[0].mesh.level: 0 is out of range (1 <= level <= 16)",
        ),
        (
            "animation.toml",
            "frames = 4\n[camera]\neye = [0, 1, 5]\n[materials.m]\npreset = \"wood\"\n[[objects]]\nmesh = \"cube\"\n\
             [[animate]]\nparam = \"materials.m.amplitude\"\nfrom = 0\nto = 1000\n",
            "animation.toml:11:6: animate[0].to: 1000 is out of range",
        ),
    ];
    let old = dir.join("existing.png");
    std::fs::write(&old, b"not touched").unwrap();
    for (file, text, want) in cases {
        let path = dir.join(file);
        std::fs::write(&path, text).unwrap();
        let fresh = dir.join("fresh.png");
        for out in [&fresh, &old] {
            let r = texsim(&["render", s(&path), "-o", s(out)]);
            assert_eq!(r.status, 2, "{file}: {}", r.stderr);
            let want = format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR) + want;
            assert!(
                r.stderr.contains(&want),
                "{file}: expected `{want}` in `{}`",
                r.stderr
            );
            assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
        }
        assert!(!fresh.exists(), "{file}: wrote an output file");
        assert_eq!(std::fs::read(&old).unwrap(), b"not touched", "{file}");
        // `texsim check` rejects it the same way.
        let r = texsim(&["check", s(&path)]);
        assert_eq!(r.status, 2, "check {file}");
    }
    // No temporary files are left behind.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
    // A missing file and an unknown scene name.
    let r = texsim(&["render", s(&dir.join("missing.toml")), "-o", s(&old)]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("missing.toml"));
    let r = texsim(&["render", "teapot", "-o", s(&old)]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("unknown scene `teapot`"));
    assert_eq!(std::fs::read(&old).unwrap(), b"not touched");
    let _ = std::fs::remove_dir_all(&dir);
}

fn apng_frames(path: &Path) -> (u32, Vec<Vec<u8>>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let n = r.info().animation_control().unwrap().num_frames;
    let mut frames = Vec::new();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    while let Ok(info) = r.next_frame(&mut buf) {
        frames.push(buf[..info.buffer_size()].to_vec());
    }
    (n, frames)
}

fn gif_frames(path: &Path) -> usize {
    use image::AnimationDecoder;
    let f = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(f)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap()
        .len()
}

#[test]
fn frames_write_apng_and_gif_animations() {
    let dir = tmp("frames");
    for scene in ["fire".to_string(), example("fire.toml")] {
        let a = dir.join("anim.png");
        let g = dir.join("anim.gif");
        ok(
            &texsim(&["render", &scene, "--frames", "3", "-o", s(&a)]),
            "apng",
        );
        ok(
            &texsim(&["render", &scene, "--frames", "3", "-o", s(&g)]),
            "gif",
        );
        let (n, frames) = apng_frames(&a);
        assert_eq!(n, 3, "{scene}");
        assert_eq!(frames.len(), 3, "{scene}");
        assert!(
            frames[0] != frames[1] && frames[1] != frames[2],
            "{scene} is animated"
        );
        assert_eq!(gif_frames(&g), 3, "{scene}");
    }
    // A file's animation frames are its own: the fire file equals the built-in fire.
    let a = dir.join("a.png");
    let b = dir.join("b.png");
    ok(
        &texsim(&["render", "fire", "--frames", "3", "-o", s(&a)]),
        "fire",
    );
    ok(
        &texsim(&[
            "render",
            &example("fire.toml"),
            "--frames",
            "3",
            "-o",
            s(&b),
        ]),
        "fire.toml",
    );
    assert!(apng_frames(&a).1 == apng_frames(&b).1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_and_single_frames_of_scene_files() {
    let r = texsim(&["check", &example("zoneplate.toml"), "--json"]);
    ok(&r, "check");
    let v: serde_json::Value = serde_json::from_str(r.stdout.trim()).unwrap();
    assert_eq!(v["name"], "zoneplate-file");
    assert!(v["within_one_step"].as_f64().unwrap() > 0.99);
    let a = texsim(&["render", &example("marble-forming.toml"), "--checksum"]);
    let b = texsim(&[
        "render",
        &example("marble-forming.toml"),
        "--frame",
        "63",
        "--checksum",
    ]);
    let c = texsim(&[
        "render",
        &example("marble-forming.toml"),
        "--frame",
        "0",
        "--checksum",
    ]);
    ok(&a, "still");
    assert_eq!(a.stdout, b.stdout, "the still is frame 63");
    assert_ne!(a.stdout, c.stdout);
}

#[test]
fn check_against_the_supersampled_truth() {
    let r = texsim(&[
        "check",
        "seascape",
        "--supersampled",
        "2",
        "--image-size",
        "64x48",
        "--json",
    ]);
    ok(&r, "check --supersampled");
    let v: serde_json::Value = serde_json::from_str(r.stdout.trim()).unwrap();
    assert_eq!(v["name"], "seascape");
    assert_eq!(v["width"], 64);
    assert_eq!(v["height"], 48);
    assert_eq!(v["supersampled"], 2);
    for k in ["psnr_filtered", "psnr_unfiltered", "gain_db"] {
        assert!(v[k].as_f64().unwrap().is_finite(), "{k}");
    }
    assert!(v["longest_flat_band"].as_u64().is_some());
    // Out-of-range factors and sizes are refused.
    for bad in [
        &["check", "seascape", "--supersampled", "0"][..],
        &["check", "seascape", "--supersampled", "17"],
        &[
            "check",
            "seascape",
            "--supersampled",
            "2",
            "--image-size",
            "0x10",
        ],
        &[
            "check",
            "seascape",
            "--supersampled",
            "2",
            "--image-size",
            "64",
        ],
    ] {
        let r = texsim(bad);
        assert_eq!(r.status, 2, "{bad:?}: {}", r.stderr);
    }
}

/// Lighting from a scene file: the lit example is lit (every shaded pixel counted), its image
/// is pinned by its device checksum, the same scene without `[[lights]]` draws no lit pixel, and
/// a bad light exits 2 naming the field and writing nothing.
#[test]
fn lit_scene_file_renders_and_bad_lights_exit_2() {
    let dir = tmp("lit");
    let out = dir.join("lit.png");
    let out = s(&out);
    let v = stats(&[
        "render",
        &example("lit-marble.toml"),
        "--stats",
        "--json",
        "-o",
        out,
    ]);
    let pixels = count(&v, "pixels");
    assert!(pixels > 10_000);
    assert_eq!(count(&v, "lit_pixels"), pixels);
    // Pinned: the lighting stage is integer arithmetic, the same bits on every target.
    // (8fcaed2f since the footprint fade of docs/model.md 8.1; 414df048 before.)
    assert_eq!(v["checksum"], "8fcaed2f", "lit-marble.toml's image changed");
    let src = std::fs::read_to_string(example("lit-marble.toml")).unwrap();
    let unlit_src = src.split("[lighting]").next().unwrap().to_string()
        + &src[src.find("[[objects]]").unwrap()..];
    let unlit = dir.join("unlit.toml");
    std::fs::write(&unlit, unlit_src).unwrap();
    let u = stats(&["render", s(&unlit), "--stats", "--json", "-o", out]);
    assert_eq!(count(&u, "lit_pixels"), 0);
    assert_eq!(count(&u, "pixels"), pixels);
    assert_ne!(u["checksum"], v["checksum"]);
    // The f64 reference applies the same light: check agrees as for unlit scenes.
    let r = texsim(&["check", &example("lit-marble.toml"), "--json"]);
    ok(&r, "check lit-marble");
    let c: serde_json::Value = serde_json::from_str(r.stdout.trim()).unwrap();
    let within = c["within_one_step"].as_f64().unwrap();
    assert!(within > 0.99, "{c}");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, src.replace("intensity = 1\n", "intensity = 40\n")).unwrap();
    let fresh = dir.join("fresh.png");
    let r = texsim(&["render", s(&bad), "-o", s(&fresh)]);
    assert_eq!(r.status, 2, "{}", r.stderr);
    assert!(
        r.stderr
            .contains("lights[0].intensity: 40 is out of range (0 <= v <= 16)"),
        "{}",
        r.stderr
    );
    assert!(!fresh.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--widths differences`: a preset's check plane keeps nearly the accuracy of the gradients
/// (the marble plane within 1 dB of them, against the same reference: other widths), a perturbed
/// material's plane renders too, and so do scenes (`Renderer::with_differences`): the fire with
/// the ramp gives the checksum of the device's `scene:fire~ramp-diff` job (`docs/cycles.md`), and
/// with csat a frame other than the gradients'.
#[test]
fn filter_widths_from_differences_on_planes_and_scenes() {
    let psnr = |args: &[&str]| -> f64 {
        let r = texsim(args);
        ok(&r, &args.join(" "));
        let v: serde_json::Value = serde_json::from_str(r.stdout.trim()).unwrap();
        v["psnr"].as_f64().unwrap()
    };
    let grads = psnr(&["check", "marble", "--json"]);
    let diffs = psnr(&["check", "marble", "--json", "--widths", "differences"]);
    assert!((grads - diffs).abs() < 1.0, "{grads} {diffs}");
    assert_ne!(grads, diffs);
    let perturbed = psnr(&["check", "mn-marble", "--json", "--widths", "differences"]);
    assert!(perturbed > 40.0, "{perturbed}");
    let dir = tmp("widths");
    let out = dir.join("fire.png");
    let checksum = |extra: &[&str]| {
        let mut args = vec!["render", "fire", "--checksum", "-o", s(&out)];
        args.extend_from_slice(extra);
        let r = texsim(&args);
        ok(&r, &args.join(" "));
        assert!(out.exists());
        r.stdout.trim().to_string()
    };
    assert_eq!(
        checksum(&["--aa", "ramp", "--widths", "differences"]),
        "e668a2be"
    );
    assert_ne!(
        checksum(&["--widths", "differences"]),
        checksum(&["--widths", "gradients"])
    );
    let _ = std::fs::remove_dir_all(&dir);
}
