//! `texsim` under hostile input and long runs, as a separate process (this test binary re-executes
//! itself with the command line in an environment variable, as `cli.rs` does): endless and huge
//! scene files, long strings, huge and tiny numbers, NaN and out-of-range flags, a missing `-o`,
//! `-o -` and `-o /dev/null`; animations that stream many frames, bit-identical output for any
//! number of threads, and Ctrl-C that leaves no file behind.

use std::io::Write;
use std::path::{Path, PathBuf};

use std::process::Command;

use texcore_tests::child::{command, finish, s, texsim, tmp_dir, Run};

texcore_tests::texsim_child_test!();

/// A fresh temporary directory for one test.
fn tmp(name: &str) -> PathBuf {
    tmp_dir("texsim-limits", name)
}

/// `texsim ARGS` with `threads` worker threads (the default when `None`).
fn texsim_threads(args: &[&str], threads: Option<usize>) -> Run {
    let mut cmd = command(args);
    if let Some(n) = threads {
        cmd.env("RAYON_NUM_THREADS", n.to_string());
    }
    finish(cmd)
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Exit 2, `want` in the message, no panic, and no output file.
fn refused(r: &Run, want: &str, out: &Path, what: &str) {
    assert_eq!(r.status, 2, "{what}: {}", r.stderr);
    assert!(
        r.stderr.contains(want),
        "{what}: expected `{want}` in `{}`",
        r.stderr
    );
    assert!(!r.stderr.contains("panicked"), "{what}: {}", r.stderr);
    assert!(
        r.stderr.len() < 600,
        "{what}: a long message ({} bytes)",
        r.stderr.len()
    );
    assert!(!out.exists(), "{what}: wrote {}", out.display());
}

const CAMERA: &str = "[camera]\neye = [0, 1, 5]\n";

#[test]
fn hostile_scene_files_exit_2_naming_the_problem_and_the_place() {
    let dir = tmp("hostile");
    let out = dir.join("out.png");
    let long = "n".repeat(300);
    let name65 = "n".repeat(65);
    let cases: Vec<(&str, String, String)> = vec![
        (
            "long-string.toml",
            format!("name = \"{long}\"\n{CAMERA}"),
            "long-string.toml:1:8: name: a string of 300 bytes is too long".into(),
        ),
        (
            "long-key.toml",
            format!("{CAMERA}[materials.{long}]\npreset = \"wood\"\n"),
            "long-key.toml:3:12: materials: a key of 300 bytes is too long".into(),
        ),
        (
            "long-name.toml",
            format!("name = \"{name65}\"\n{CAMERA}"),
            "long-name.toml:1:8: name: a scene name of 65 bytes is too long (names are at most 64 bytes)"
                .into(),
        ),
        (
            "long-material.toml",
            format!("{CAMERA}[materials.{name65}]\npreset = \"wood\"\n"),
            "long-material.toml:3:1: materials.".to_string() + &name65 + ": a name of 65 bytes",
        ),
        (
            "near.toml",
            "[camera]\neye = [0, 1, 5]\nnear = 0.000001\n".into(),
            "near.toml:3:8: camera.near: 0.000001 is out of range (1/65536 = 0.0000153 <= near"
                .into(),
        ),
        (
            "huge.toml",
            "[camera]\neye = [1e300, 1, 5]\n".into(),
            "huge.toml:2:7: camera.eye[0]: 1e300 is out of range (|v| <= 32767)".into(),
        ),
        (
            "integer.toml",
            format!("width = \"wide\"\n{CAMERA}"),
            "integer.toml:1:9: width: invalid type: string \"wide\", expected an integer".into(),
        ),
        (
            "table.toml",
            "camera = 1\n".into(),
            "table.toml:1:10: camera: invalid type: integer `1`, expected a table".into(),
        ),
        (
            "string.toml",
            format!("{CAMERA}[materials.m]\npreset = 7\n"),
            "string.toml:4:10: materials.m.preset: invalid type: integer `7`, expected a string"
                .into(),
        ),
    ];
    for (file, text, want) in &cases {
        let path = dir.join(file);
        std::fs::write(&path, text).unwrap();
        let r = texsim(&["render", s(&path), "-o", s(&out)]);
        let want = format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR) + want;
        refused(&r, &want, &out, file);
        assert!(!r.stderr.contains("i64"), "{file}: {}", r.stderr);
        let r = texsim(&["check", s(&path)]);
        assert_eq!(r.status, 2, "check {file}: {}", r.stderr);
    }
    // Larger than 1 MiB: a regular file, /dev/zero behind a symlink, an endless FIFO. Each is
    // refused after reading 1 MiB + 1 byte (an unbounded read of /dev/zero would not end).
    let big = dir.join("big.toml");
    let mut text = format!("{CAMERA}# ");
    text.push_str(&"x".repeat(1 << 20));
    std::fs::write(&big, text).unwrap();
    let want = "the file is larger than 1048576 bytes, the limit of scene files";
    refused(
        &texsim(&["render", s(&big), "-o", s(&out)]),
        want,
        &out,
        "big",
    );
    #[cfg(unix)]
    {
        let zero = dir.join("zero.toml");
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        refused(
            &texsim(&["render", s(&zero), "-o", s(&out)]),
            &format!("{}: {want}", zero.display()),
            &out,
            "zero",
        );
        let fifo = dir.join("fifo.toml");
        let made = Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|st| st.success()) {
            let path = fifo.clone();
            // An endless writer; it stops when the reader closes the pipe.
            let writer = std::thread::spawn(move || {
                if let Ok(mut f) = std::fs::OpenOptions::new().write(true).open(&path) {
                    let chunk = vec![b'#'; 65536];
                    while f.write_all(&chunk).is_ok() {}
                }
            });
            refused(
                &texsim(&["render", s(&fifo), "-o", s(&out)]),
                want,
                &out,
                "fifo",
            );
            writer.join().unwrap();
        }
    }
    assert!(files(&dir).iter().all(|n| !n.ends_with(".tmp")));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn numeric_flags_are_range_checked() {
    let dir = tmp("flags");
    let out = dir.join("out.png");
    let o = s(&out);
    let cases: [(&[&str], &str); 9] = [
        (&["check", "marble", "--min-within", "nan"], "--min-within"),
        (&["check", "marble", "--min-within", "2"], "out of range"),
        (&["check", "marble", "--min-within=-0.5"], "out of range"),
        (&["check", "marble", "--min-within", "inf"], "out of range"),
        (&["check", "marble", "--size", "0"], "--size"),
        (
            &["render", "marble", "--table-size", "3", "-o", o],
            "power of two",
        ),
        (
            &["render", "marble", "--table-size", "4096", "-o", o],
            "out of range",
        ),
        (
            &["render", "fire", "--frames", "2000000", "-o", o],
            "out of range",
        ),
        (&["render", "fire", "--delay", "70000", "-o", o], "--delay"),
    ];
    for (args, want) in cases {
        refused(&texsim(args), want, &out, &format!("{args:?}"));
    }
    // A long number is shortened in the message.
    let long = format!("1{}", "0".repeat(300));
    let r = texsim(&["check", "marble", "--min-within", &long]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("(301 characters)"), "{}", r.stderr);
    assert!(
        !r.stderr.contains(&long),
        "the whole number is echoed: {}",
        r.stderr
    );
    // In range: accepted.
    let r = texsim(&["check", "marble", "--size", "16", "--min-within", "0"]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_outputs_a_file_standard_output_or_dev_null_and_needs_one() {
    let dir = tmp("dest");
    let r = texsim(&["render", "zoneplate"]);
    assert_eq!(r.status, 2);
    assert!(r.stderr.contains("give -o FILE"), "{}", r.stderr);
    assert!(files(&dir).is_empty());
    // `-o -`: the PNG on standard output, identical to the file.
    let file = dir.join("z.png");
    let r = texsim(&["render", "zoneplate", "-o", s(&file)]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    let r = texsim(&["render", "zoneplate", "-o", "-"]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    assert_eq!(r.bytes, std::fs::read(&file).unwrap());
    // An animation to standard output is an APNG.
    let r = texsim(&["render", "fire", "--frames", "2", "-o", "-"]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    let dec = png::Decoder::new(std::io::Cursor::new(r.bytes));
    let reader = dec.read_info().unwrap();
    assert_eq!(reader.info().animation_control().unwrap().num_frames, 2);
    // /dev/null: written (and left) as it is.
    #[cfg(unix)]
    for args in [
        &["render", "zoneplate", "-o", "/dev/null"][..],
        &["render", "fire", "--frames", "2", "-o", "/dev/null"],
    ] {
        let r = texsim(args);
        assert_eq!(r.status, 0, "{args:?}: {}", r.stderr);
        use std::os::unix::fs::FileTypeExt;
        let t = std::fs::metadata("/dev/null").unwrap().file_type();
        assert!(t.is_char_device(), "/dev/null was replaced");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 32x24 fire scene of 4 frames, the phase advancing 1/32 a frame (smaller images cull every
/// octave, so the phase would not show).
fn tiny_fire(dir: &Path) -> PathBuf {
    let p = dir.join("tiny-fire.toml");
    std::fs::write(
        &p,
        "width = 32\nheight = 24\nframes = 4\n\
         [camera]\neye = [0, 0, 5]\nfov = 36.5244\nnear = 0.5\nfar = 20\n\
         [materials.flame]\npreset = \"fire\"\n\
         [[objects]]\n\
         mesh = { kind = \"quad\", corners = [[-2.3, -1.75, 0], [2.3, -1.75, 0], [2.3, 1.75, 0], [-2.3, 1.75, 0]] }\n\
         depth_test = false\ndepth_write = false\n\
         texture = { scale = [0.333, 0.37, 0], translate = [0.5, 0.648, 0.5] }\n\
         [[animate]]\nparam = \"materials.flame.phase\"\nfrom = 0\nto = 0.09375\n",
    )
    .unwrap();
    p
}

fn apng_frames(bytes: &[u8]) -> Vec<Vec<u8>> {
    let dec = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut r = dec.read_info().unwrap();
    let n = r.info().animation_control().unwrap().num_frames;
    let mut frames = Vec::new();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    while let Ok(info) = r.next_frame(&mut buf) {
        frames.push(buf[..info.buffer_size()].to_vec());
    }
    assert_eq!(frames.len() as u32, n);
    frames
}

/// Many frames stream through the encoder in order: frame `k` of a 600-frame run of a 4-frame
/// loop is the loop's frame `k mod 4`.
#[test]
fn many_frames_stream_in_order() {
    let dir = tmp("many");
    let scene = tiny_fire(&dir);
    let out = dir.join("many.png");
    let r = texsim(&["render", s(&scene), "--frames", "600", "-o", s(&out)]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    let frames = apng_frames(&std::fs::read(&out).unwrap());
    assert_eq!(frames.len(), 600);
    assert!(frames[0] != frames[1] && frames[1] != frames[2] && frames[2] != frames[3]);
    for (k, f) in frames.iter().enumerate() {
        assert!(*f == frames[k % 4], "frame {k}");
    }
    let gif = dir.join("many.gif");
    let r = texsim(&["render", s(&scene), "--frames", "300", "-o", s(&gif)]);
    assert_eq!(r.status, 0, "{}", r.stderr);
    use image::AnimationDecoder;
    let f = std::io::BufReader::new(std::fs::File::open(&gif).unwrap());
    let n = image::codecs::gif::GifDecoder::new(f)
        .unwrap()
        .into_frames()
        .count();
    assert_eq!(n, 300);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Frames render in parallel; the file is the same bytes on one thread and on several.
#[test]
fn parallel_output_is_bit_identical_to_one_thread() {
    let dir = tmp("threads");
    for ext in ["png", "gif"] {
        let mut outputs = Vec::new();
        for threads in [1, 3] {
            let out = dir.join(format!("fire-{threads}.{ext}"));
            let r = texsim_threads(
                &["render", "fire", "--frames", "7", "-o", s(&out)],
                Some(threads),
            );
            assert_eq!(r.status, 0, "{}", r.stderr);
            outputs.push(std::fs::read(&out).unwrap());
        }
        assert!(outputs[0] == outputs[1], "{ext}: threads change the bytes");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Ctrl-C (SIGINT) stops an animation between frames: exit status 130, no output file, no
/// temporary file.
#[cfg(unix)]
#[test]
fn ctrl_c_leaves_no_file() {
    let dir = tmp("ctrlc");
    let scene = tiny_fire(&dir);
    let out = dir.join("long.gif");
    let mut c = command(&["render", s(&scene), "--frames", "1000000", "-o", s(&out)])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the temporary file exists (the animation is being written).
    let start = std::time::Instant::now();
    while !files(&dir).iter().any(|n| n.ends_with(".tmp")) {
        assert!(
            start.elapsed().as_secs() < 120,
            "no temporary file appeared"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let ok = Command::new("kill")
        .args(["-INT", &c.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
    let status = c.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut c.stderr.take().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted"), "{stderr}");
    assert_eq!(files(&dir), vec!["tiny-fire.toml".to_string()]);
    let _ = std::fs::remove_dir_all(&dir);
}
