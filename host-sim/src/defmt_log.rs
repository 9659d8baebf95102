//! `texsim defmt-decode ELF`: decodes a firmware's defmt stream (read from standard input as it
//! arrives) into text lines, one per frame, printed as soon as each frame is complete.
//!
//! This is what the device runner (`firmware/qemu-run.sh`, the cargo runner of the device
//! targets) pipes QEMU's semihosting output through when `defmt-print` is not installed, so that
//! `cargo run -p firmware` prints readable lines out of the box. The string table comes from the
//! ELF's `.defmt` section (the same decoder as [`crate::device::decode_defmt`]).
//!
//! Guarantees: bounded memory (the stream is consumed in 4 KiB chunks; the decoder keeps at most
//! one incomplete frame), a clear error naming the file for an unreadable ELF or one without a
//! `.defmt` table (exit 2), malformed frames reported in place and skipped when the encoding can
//! resynchronise, otherwise an error (exit 1). A truncated final frame is ignored.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

/// `texsim defmt-decode`.
#[derive(Clone, Debug, Args)]
pub struct DefmtDecodeArgs {
    /// The firmware ELF whose `.defmt` table decodes the stream.
    pub elf: PathBuf,
}

/// Why decoding stopped.
#[derive(Debug)]
pub enum DecodeStreamError {
    /// The ELF could not be read or has no defmt table (bad input).
    Elf(String),
    /// The stream had a malformed frame the encoding cannot skip.
    Malformed,
    /// Reading the stream or writing the lines failed.
    Io(std::io::Error),
}

impl std::fmt::Display for DecodeStreamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DecodeStreamError::Elf(m) => f.write_str(m),
            DecodeStreamError::Malformed => f.write_str("malformed defmt frame in the stream"),
            DecodeStreamError::Io(e) => write!(f, "reading or writing the log: {e}"),
        }
    }
}

/// Decodes `input` with the defmt table of the ELF at `elf`, writing one line per frame to `out`
/// (flushed after each chunk). Returns the number of frames decoded.
pub fn decode_stream(
    elf: &Path,
    mut input: impl Read,
    mut out: impl Write,
) -> Result<u64, DecodeStreamError> {
    let bytes = std::fs::read(elf)
        .map_err(|e| DecodeStreamError::Elf(format!("reading {}: {e}", elf.display())))?;
    let table = defmt_decoder::Table::parse(&bytes)
        .map_err(|e| {
            DecodeStreamError::Elf(format!(
                "{}: not a firmware ELF with a defmt table: {e:#}",
                elf.display()
            ))
        })?
        .ok_or_else(|| {
            DecodeStreamError::Elf(format!("{}: the ELF has no .defmt section", elf.display()))
        })?;
    let mut decoder = table.new_stream_decoder();
    let mut buf = [0u8; 4096];
    let mut frames = 0u64;
    loop {
        let n = match input.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(DecodeStreamError::Io(e)),
        };
        decoder.received(&buf[..n]);
        loop {
            match decoder.decode() {
                Ok(frame) => {
                    writeln!(out, "{}", frame.display_message()).map_err(DecodeStreamError::Io)?;
                    frames += 1;
                }
                Err(defmt_decoder::DecodeError::UnexpectedEof) => break,
                Err(defmt_decoder::DecodeError::Malformed) => {
                    if table.encoding().can_recover() {
                        writeln!(out, "<malformed defmt frame skipped>")
                            .map_err(DecodeStreamError::Io)?;
                    } else {
                        return Err(DecodeStreamError::Malformed);
                    }
                }
            }
        }
        out.flush().map_err(DecodeStreamError::Io)?;
    }
    Ok(frames)
}

/// Runs `texsim defmt-decode`: standard input to standard output.
pub fn run(args: &DefmtDecodeArgs) -> ExitCode {
    let stdin = std::io::stdin().lock();
    let stdout = std::io::stdout().lock();
    match decode_stream(&args.elf, stdin, stdout) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e @ DecodeStreamError::Elf(_)) => crate::cli::bad_input(e),
        Err(e) => {
            eprintln!("texsim: error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_that_is_not_an_elf_is_named_in_the_error() {
        let dir = std::env::temp_dir().join(format!("texsim-defmt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("not-an-elf");
        std::fs::write(&path, b"hello").unwrap();
        let err = decode_stream(&path, &b""[..], Vec::new()).unwrap_err();
        assert!(matches!(err, DecodeStreamError::Elf(_)));
        assert!(err.to_string().contains("not-an-elf"), "{err}");
        let missing = dir.join("missing.elf");
        let err = decode_stream(&missing, &b""[..], Vec::new()).unwrap_err();
        assert!(err.to_string().contains("missing.elf"), "{err}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
