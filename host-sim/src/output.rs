//! Image output: PNG stills and animations (APNG or GIF), written atomically.
//!
//! Every writer renders into a temporary file beside the destination and renames it into place
//! only when the whole image is written, so a failure (or Ctrl-C) never leaves a half-written file
//! and never clobbers an existing one. Two destinations cannot be written that way and are
//! written directly: `-` (standard output, always PNG/APNG) and an existing file that is not a
//! regular file (`/dev/null`, a FIFO).
//!
//! Animations are streamed: [`AnimationEncoder`] takes one frame at a time, so memory does not
//! grow with the frame count. APNG frames use the `png` crate's fast compression (fdeflate with
//! its matching filter), which encodes a frame faster than the GIF encoder's colour quantisation.

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
    /// A frame could not be rendered (nothing was written).
    #[error("{0}")]
    Frame(String),
    /// Stopped by Ctrl-C (nothing was written).
    #[error("interrupted; no file written")]
    Interrupted,
}

/// The standard-output destination (`-o -`).
pub const STDOUT: &str = "-";

/// Whether `path` names standard output (`-`).
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == STDOUT
}

/// Image formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// PNG, or APNG when animated.
    Png,
    /// GIF.
    Gif,
}

impl Format {
    /// The format of a destination: by extension (`.png`, `.apng`, `.gif`, any case); PNG for
    /// standard output (`-`) and for an existing file that is not a regular file (`/dev/null`).
    pub fn of(path: &Path) -> Result<Format, OutputError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "png" | "apng" => Ok(Format::Png),
            "gif" => Ok(Format::Gif),
            _ if is_stdout(path) || is_special(path) => Ok(Format::Png),
            _ => Err(OutputError::Format {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// An existing file that is not a regular file (a device such as `/dev/null`, a FIFO): it cannot
/// be replaced by a rename, so it is written directly.
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Writes the destination `path`: standard output for `-`, directly for an existing file that is
/// not a regular file, otherwise atomically ([`write_atomic`]).
pub fn write_dest<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut dyn Write) -> Result<(), OutputError>,
{
    if is_stdout(path) {
        let mut out = std::io::stdout().lock();
        write(&mut out)?;
        return out.flush().map_err(io(path));
    }
    if is_special(path) {
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(io(path))?;
        let mut w = BufWriter::new(f);
        write(&mut w)?;
        return w.flush().map_err(io(path));
    }
    write_atomic(path, |w| write(w))
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

/// Writes a PNG still (to any destination of [`write_dest`]).
pub fn write_png(path: &Path, frame: &Frame) -> Result<(), OutputError> {
    write_dest(path, |w| {
        let mut e = png::Encoder::new(w, frame.width, frame.height);
        e.set_color(png::ColorType::Rgba);
        e.set_depth(png::BitDepth::Eight);
        let mut pw = e.write_header().map_err(enc(path))?;
        pw.write_image_data(&frame.bytes()).map_err(enc(path))?;
        pw.finish().map_err(enc(path))
    })
}

/// Writes an animation: APNG for `.png`, GIF for `.gif`; `delay_ms` per frame, looping forever.
/// Any destination of [`write_dest`].
pub fn write_animation(path: &Path, frames: &[Frame], delay_ms: u16) -> Result<(), OutputError> {
    let format = Format::of(path)?;
    let Some(first) = frames.first() else {
        return Err(OutputError::Encode {
            path: path.to_path_buf(),
            message: "no frames".into(),
        });
    };
    let count = u32::try_from(frames.len()).map_err(enc(path))?;
    write_dest(path, |w| {
        let mut e = AnimationEncoder::new(w, path, format, first, count, delay_ms)?;
        for f in frames {
            e.write_frame(f)?;
        }
        e.finish()
    })
}

enum Encoder<W: Write> {
    Apng(png::Writer<W>),
    Gif(image::codecs::gif::GifEncoder<W>),
}

/// A streaming animation encoder: frames go in one at a time, in order, and are encoded at once
/// (APNG: one fdAT chunk per frame; GIF: one quantised frame). Every frame has the first frame's
/// size; APNG needs the frame count up front.
pub struct AnimationEncoder<W: Write> {
    enc: Encoder<W>,
    path: PathBuf,
    width: u32,
    height: u32,
    delay_ms: u16,
    left: u32,
}

impl<W: Write> AnimationEncoder<W> {
    /// Starts an animation of `count` frames of `size`'s size on `w` (`path` names it in
    /// errors).
    pub fn new(
        w: W,
        path: &Path,
        format: Format,
        size: &Frame,
        count: u32,
        delay_ms: u16,
    ) -> Result<Self, OutputError> {
        let enc = match format {
            Format::Png => {
                let mut e = png::Encoder::new(w, size.width, size.height);
                e.set_color(png::ColorType::Rgba);
                e.set_depth(png::BitDepth::Eight);
                e.set_compression(png::Compression::Fast);
                e.set_animated(count, 0).map_err(enc(path))?;
                e.set_frame_delay(delay_ms, 1000).map_err(enc(path))?;
                Encoder::Apng(e.write_header().map_err(enc(path))?)
            }
            Format::Gif => {
                use image::codecs::gif::{GifEncoder, Repeat};
                let mut g = GifEncoder::new_with_speed(w, 10);
                g.set_repeat(Repeat::Infinite).map_err(enc(path))?;
                Encoder::Gif(g)
            }
        };
        Ok(AnimationEncoder {
            enc,
            path: path.to_path_buf(),
            width: size.width,
            height: size.height,
            delay_ms,
            left: count,
        })
    }

    /// Encodes the next frame.
    pub fn write_frame(&mut self, f: &Frame) -> Result<(), OutputError> {
        let path = self.path.as_path();
        if (f.width, f.height) != (self.width, self.height) || self.left == 0 {
            return Err(OutputError::Encode {
                path: path.to_path_buf(),
                message: "frame size or count mismatch".into(),
            });
        }
        self.left -= 1;
        match &mut self.enc {
            Encoder::Apng(pw) => pw.write_image_data(&f.bytes()).map_err(enc(path)),
            Encoder::Gif(g) => {
                let buf =
                    image::RgbaImage::from_raw(f.width, f.height, f.bytes()).ok_or_else(|| {
                        OutputError::Encode {
                            path: path.to_path_buf(),
                            message: "frame size mismatch".into(),
                        }
                    })?;
                let delay = image::Delay::from_numer_denom_ms(u32::from(self.delay_ms), 1);
                g.encode_frame(image::Frame::from_parts(buf, 0, 0, delay))
                    .map_err(enc(path))
            }
        }
    }

    /// Ends the animation (every announced frame must have been written).
    pub fn finish(self) -> Result<(), OutputError> {
        let path = self.path.as_path();
        if self.left != 0 {
            return Err(OutputError::Encode {
                path: path.to_path_buf(),
                message: format!("{} frames missing", self.left),
            });
        }
        match self.enc {
            Encoder::Apng(pw) => pw.finish().map_err(enc(path)),
            Encoder::Gif(g) => {
                drop(g);
                Ok(())
            }
        }
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
