//! `texsim` multipass options, run as a separate process as in `cli.rs` (this test binary
//! re-executes itself with the command line in an environment variable): `--eval multipass`
//! with each `--multipass-precision`, `--show multipass-stages` and `texsim report multipass`.

use std::path::PathBuf;

use texcore_tests::child::{s, texsim, tmp_dir, Run};

texcore_tests::texsim_child_test!();

/// A fresh temporary directory for one test.
fn tmp(name: &str) -> PathBuf {
    tmp_dir("texsim-mp", name)
}

fn ok(r: &Run, what: &str) {
    assert_eq!(r.status, 0, "{what}: exit {}: {}", r.status, r.stderr);
}

fn checksum(args: &[&str]) -> String {
    let mut a = vec!["render"];
    a.extend_from_slice(args);
    a.push("--checksum");
    let r = texsim(&a);
    ok(&r, &args.join(" "));
    r.stdout.trim().to_string()
}

/// Native multipass is bit-identical to direct evaluation on every built-in scene, with both
/// lattice hashes; the reduced precisions render and differ from it.
#[test]
fn multipass_native_equals_direct_on_every_scene() {
    for name in texcore::scene::BUILTIN {
        for hash in ["perm", "int"] {
            let direct = checksum(&[name, "--eval", "direct", "--hash", hash]);
            let mp = checksum(&[name, "--eval", "multipass", "--hash", hash]);
            assert_eq!(direct, mp, "{name} --hash {hash}");
            let explicit = checksum(&[
                name,
                "--eval",
                "multipass",
                "--multipass-precision",
                "native",
                "--hash",
                hash,
            ]);
            assert_eq!(direct, explicit, "{name} --hash {hash}");
        }
    }
}

#[test]
fn reduced_precisions_render_and_differ() {
    let dir = tmp("reduced");
    let direct = checksum(&["marble", "--eval", "direct"]);
    let mut seen = vec![direct];
    for p in ["16.8", "8"] {
        let out = dir.join(format!("marble-{p}.png"));
        let c = checksum(&[
            "marble",
            "--eval",
            "multipass",
            "--multipass-precision",
            p,
            "-o",
            s(&out),
        ]);
        assert!(
            !seen.contains(&c),
            "--multipass-precision {p} gave an earlier image"
        );
        seen.push(c);
        assert!(out.is_file());
    }
    // The hashes of the passes make other noise.
    for h in ["summed", "xor"] {
        let c = checksum(&["marble", "--eval", "multipass", "--multipass-hash", h]);
        assert!(
            !seen.contains(&c),
            "--multipass-hash {h} gave an earlier image"
        );
        seen.push(c);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_multipass_settings_are_rejected() {
    let r = texsim(&[
        "render",
        "marble",
        "--eval",
        "multipass",
        "--multipass-precision",
        "12",
    ]);
    assert_eq!(r.status, 2, "{}", r.stderr);
    assert!(r.stderr.contains("12"), "{}", r.stderr);
    let r = texsim(&["render", "marble", "--show", "multipass-stages"]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("-o"), "{}", r.stderr);
}

#[test]
fn stage_contact_sheet_is_written() {
    let dir = tmp("stages");
    for (p, h) in [("native", "texcore"), ("8", "summed"), ("16.8", "xor")] {
        let out = dir.join(format!("stages-{p}-{h}.png"));
        let r = texsim(&[
            "render",
            "wood",
            "--show",
            "multipass-stages",
            "--multipass-precision",
            p,
            "--multipass-hash",
            h,
            "-o",
            s(&out),
        ]);
        ok(&r, p);
        let img = image::open(&out).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (4 * 256 + 40, 256 + 32));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn report_multipass_prints_the_measured_pass_table() {
    let dir = tmp("report");
    let png = dir.join("hist.png");
    let r = texsim(&["report", "multipass", "--histogram", s(&png)]);
    ok(&r, "report multipass");
    assert!(
        r.stdout.contains("| native | texcore | linear | 19 | 29 |"),
        "{}",
        r.stdout
    );
    assert!(r.stdout.contains("| 8 | summed | smooth |"), "{}", r.stdout);
    assert!(png.is_file());
    // Without --histogram or --write-docs it only prints.
    let r = texsim(&["report", "multipass"]);
    ok(&r, "report multipass");
    assert!(!r.stdout.contains("wrote"), "{}", r.stdout);
    let _ = std::fs::remove_dir_all(&dir);
}
