//! Golden images: every built-in scene's still frame with the default knobs, the zone plate
//! without antialiasing and the torus's filter widths, rendered small and compared **exactly**
//! with the PNGs checked in under `tests/golden/` (the pipeline is deterministic integer
//! arithmetic, so any difference is a change of behaviour).
//!
//! `TEXSIM_BLESS=1 cargo test -p texcore-tests --test golden` rewrites the images. Otherwise a
//! mismatch fails with the number of differing pixels and writes the actual image to
//! `target/golden-actual/NAME.png` for inspection.

use std::path::{Path, PathBuf};

use host_sim::output::{write_png, Frame};
use host_sim::scenes;
use host_sim::unit::UnitConfig;
use texcore::filter::Antialias;
use texcore::hash::HashKind;
use texcore::render::Output;

/// One golden image.
struct Case {
    /// File name (without `.png`).
    file: &'static str,
    /// Built-in scene.
    scene: &'static str,
    /// Colour-table antialiasing.
    aa: Antialias,
    /// What the pixels show.
    output: Output,
    /// Size: the scene's camera is given this image size (same view, proportional).
    size: (u16, u16),
}

const SMALL: (u16, u16) = (160, 120);
const PLATE: (u16, u16) = (128, 128);

fn cases() -> Vec<Case> {
    let mut v: Vec<Case> = texcore::scene::BUILTIN
        .iter()
        .map(|&s| Case {
            file: s,
            scene: s,
            aa: Antialias::Csat,
            output: Output::Color,
            size: if s == "zoneplate" { PLATE } else { SMALL },
        })
        .collect();
    v.push(Case {
        file: "zoneplate-aa-none",
        scene: "zoneplate",
        aa: Antialias::None,
        output: Output::Color,
        size: PLATE,
    });
    v.push(Case {
        file: "torus-widths",
        scene: "torus",
        aa: Antialias::Csat,
        output: Output::FilterWidth,
        size: SMALL,
    });
    v
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

fn actual_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
            manifest.parent().unwrap_or(manifest).join("target")
        });
    target.join("golden-actual")
}

fn render(c: &Case) -> Frame {
    let mut scene = texcore::scene::by_name(c.scene).unwrap();
    scene.camera.width = c.size.0;
    scene.camera.height = c.size.1;
    let cfg = UnitConfig {
        aa: c.aa,
        ..UnitConfig::default()
    };
    scenes::render_frame(&scene, scene.still(), &cfg, HashKind::Permutation, c.output)
        .unwrap()
        .frame
}

/// Decodes an 8-bit RGBA PNG.
fn read_png(path: &Path) -> Result<Frame, String> {
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut r = png::Decoder::new(std::io::BufReader::new(f))
        .read_info()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut buf = vec![0; r.output_buffer_size().unwrap_or(0)];
    let info = r
        .next_frame(&mut buf)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight {
        return Err(format!("{}: not 8-bit RGBA", path.display()));
    }
    Ok(Frame {
        width: info.width,
        height: info.height,
        pixels: buf[..info.buffer_size()]
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect(),
    })
}

#[test]
fn builtin_scenes_match_golden_images() {
    let bless = std::env::var("TEXSIM_BLESS").is_ok_and(|v| v == "1");
    let dir = golden_dir();
    let mut failures = Vec::new();
    for c in cases() {
        let actual = render(&c);
        let path = dir.join(format!("{}.png", c.file));
        if bless {
            std::fs::create_dir_all(&dir).unwrap();
            write_png(&path, &actual).unwrap();
            continue;
        }
        let problem = match read_png(&path) {
            Err(e) => Some(format!(
                "{e} (run with TEXSIM_BLESS=1 to create the golden images)"
            )),
            Ok(want) if (want.width, want.height) != (actual.width, actual.height) => {
                Some(format!(
                    "{}: golden image is {}x{}, rendered {}x{}",
                    c.file, want.width, want.height, actual.width, actual.height
                ))
            }
            Ok(want) => {
                let differing = want
                    .pixels
                    .iter()
                    .zip(&actual.pixels)
                    .filter(|(a, b)| a != b)
                    .count();
                (differing > 0).then(|| {
                    format!(
                        "{}: {differing} of {} pixels differ",
                        c.file,
                        actual.pixels.len()
                    )
                })
            }
        };
        if let Some(p) = problem {
            let out = actual_dir();
            let _ = std::fs::create_dir_all(&out);
            let file = out.join(format!("{}.png", c.file));
            let _ = write_png(&file, &actual);
            failures.push(format!("{p}; actual image: {}", file.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "golden images differ (TEXSIM_BLESS=1 regenerates them if the change is intended):\n{}",
        failures.join("\n")
    );
}

/// The golden images stay small: well under 1 MB together.
#[test]
fn golden_images_are_small() {
    let total: u64 = cases()
        .iter()
        .map(|c| {
            std::fs::metadata(golden_dir().join(format!("{}.png", c.file)))
                .map(|m| m.len())
                .unwrap_or(0)
        })
        .sum();
    assert!(total < 512 * 1024, "golden images total {total} bytes");
}
