//! Image output: PNG stills and animations (APNG or GIF), written atomically.
//!
//! Every writer renders into a temporary file beside the destination and renames it into place
//! only when the whole image is written, so a failure never leaves a half-written file and never
//! clobbers an existing one.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Errors writing an image.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File system error, with the path.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// Encoder error, with the path.
    #[error("{path}: {message}")]
    Encode {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Unsupported extension.
    #[error("{path}: unsupported output format (use .png, or .gif for animations)")]
    Format {
        /// The file.
        path: PathBuf,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn enc<E: std::fmt::Display>(path: &Path) -> impl FnOnce(E) -> OutputError + '_ {
    move |e| OutputError::Encode {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Writes `path` atomically: `write` fills a temporary file in the same directory, which is
/// renamed over `path` only if `write` succeeds.
pub fn write_atomic<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
{
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let f = File::create(&tmp).map_err(io(&tmp))?;
        let mut w = BufWriter::new(f);
        write(&mut w)?;
        w.flush().map_err(io(&tmp))?;
        let f = w.into_inner().map_err(|e| OutputError::Io {
            path: tmp.clone(),
            source: e.into_error(),
        })?;
        f.sync_all().map_err(io(&tmp))?;
        std::fs::rename(&tmp, path).map_err(io(path))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// An RGBA8 frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Row-major RGBA8 pixels.
    pub pixels: Vec<[u8; 4]>,
}

impl Frame {
    fn bytes(&self) -> Vec<u8> {
        self.pixels.iter().flatten().copied().collect()
    }
}

/// Writes a PNG still.
pub fn write_png(path: &Path, frame: &Frame) -> Result<(), OutputError> {
    write_atomic(path, |w| {
        let mut e = png::Encoder::new(w, frame.width, frame.height);
        e.set_color(png::ColorType::Rgba);
        e.set_depth(png::BitDepth::Eight);
        let mut pw = e.write_header().map_err(enc(path))?;
        pw.write_image_data(&frame.bytes()).map_err(enc(path))?;
        pw.finish().map_err(enc(path))
    })
}

/// Writes an animation: APNG for `.png`, GIF for `.gif`; `delay_ms` per frame, looping forever.
pub fn write_animation(path: &Path, frames: &[Frame], delay_ms: u16) -> Result<(), OutputError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let Some(first) = frames.first() else {
        return Err(OutputError::Encode {
            path: path.to_path_buf(),
            message: "no frames".into(),
        });
    };
    match ext.as_str() {
        "png" | "apng" => write_atomic(path, |w| {
            let mut e = png::Encoder::new(w, first.width, first.height);
            e.set_color(png::ColorType::Rgba);
            e.set_depth(png::BitDepth::Eight);
            e.set_animated(frames.len() as u32, 0).map_err(enc(path))?;
            e.set_frame_delay(delay_ms, 1000).map_err(enc(path))?;
            let mut pw = e.write_header().map_err(enc(path))?;
            for f in frames {
                pw.write_image_data(&f.bytes()).map_err(enc(path))?;
            }
            pw.finish().map_err(enc(path))
        }),
        "gif" => write_atomic(path, |w| {
            use image::codecs::gif::{GifEncoder, Repeat};
            let mut g = GifEncoder::new_with_speed(w, 10);
            g.set_repeat(Repeat::Infinite).map_err(enc(path))?;
            for f in frames {
                let buf =
                    image::RgbaImage::from_raw(f.width, f.height, f.bytes()).ok_or_else(|| {
                        OutputError::Encode {
                            path: path.to_path_buf(),
                            message: "frame size mismatch".into(),
                        }
                    })?;
                let delay = image::Delay::from_numer_denom_ms(u32::from(delay_ms), 1);
                g.encode_frame(image::Frame::from_parts(buf, 0, 0, delay))
                    .map_err(enc(path))?;
            }
            Ok(())
        }),
        _ => Err(OutputError::Format {
            path: path.to_path_buf(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(v: u8) -> Frame {
        Frame {
            width: 4,
            height: 3,
            pixels: vec![[v, 255 - v, 7, 255]; 12],
        }
    }

    #[test]
    fn png_round_trip_and_atomicity() {
        let dir = std::env::temp_dir().join(format!("texsim-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.png");
        write_png(&p, &frame(10)).unwrap();
        let img = image::open(&p).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (4, 3));
        assert_eq!(img.get_pixel(1, 1).0, [10, 245, 7, 255]);
        // A failing writer leaves the old file untouched and no temporary behind.
        let r = write_atomic(&p, |_| {
            Err(OutputError::Encode {
                path: p.clone(),
                message: "boom".into(),
            })
        });
        assert!(r.is_err());
        assert_eq!(
            image::open(&p).unwrap().to_rgba8().get_pixel(0, 0).0,
            [10, 245, 7, 255]
        );
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty());
        // Animations.
        let frames = [frame(0), frame(100), frame(200)];
        write_animation(&dir.join("a.gif"), &frames, 40).unwrap();
        write_animation(&dir.join("b.png"), &frames, 40).unwrap();
        let dec = png::Decoder::new(std::io::BufReader::new(
            File::open(dir.join("b.png")).unwrap(),
        ));
        let reader = dec.read_info().unwrap();
        assert_eq!(reader.info().animation_control().unwrap().num_frames, 3);
        assert!(matches!(
            write_animation(&dir.join("c.bmp"), &frames, 40),
            Err(OutputError::Format { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
