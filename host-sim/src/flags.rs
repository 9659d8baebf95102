//! Range-checked values of the numeric command-line flags (clap value parsers): a value out of
//! its documented range, NaN or an infinity is refused by the parser with a message giving the
//! range, so a command never starts on a bad number. Echoed numbers are shortened
//! ([`short_number`]): [`Checked`] reports the parser's message without clap's echo of the whole
//! value.

use clap::builder::TypedValueParser;

/// Longest number echoed whole in a message; longer ones are shortened.
const ECHO_MAX: usize = 24;

/// `text` as echoed in a message: itself when short, else its first characters, an ellipsis and
/// its length.
pub fn short_number(text: &str) -> String {
    if text.chars().count() <= ECHO_MAX {
        text.to_string()
    } else {
        let head: String = text.chars().take(12).collect();
        format!("{head}... ({} characters)", text.chars().count())
    }
}

/// A real number in `0..=1` (a fraction: `check --min-within`).
pub fn fraction(text: &str) -> Result<f64, String> {
    let x: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", short_number(text)))?;
    if x.is_nan() || !(0.0..=1.0).contains(&x) {
        return Err(format!(
            "{} is out of range (a fraction from 0 to 1)",
            short_number(text)
        ));
    }
    Ok(x)
}

/// Most frames of `render --frames` (animations are streamed, so this bounds the run time and
/// the output size, not memory).
pub const FRAMES_MAX: u32 = 1_000_000;

/// An unsigned integer in `lo..=hi`.
fn int_in(text: &str, lo: u64, hi: u64, what: &str) -> Result<u64, String> {
    let x: u64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a whole number", short_number(text)))?;
    if x < lo || x > hi {
        return Err(format!(
            "{} is out of range ({lo} <= {what} <= {hi})",
            short_number(text)
        ));
    }
    Ok(x)
}

/// A frame count of `render --frames`: `0..=FRAMES_MAX` (0: the scene's own count).
pub fn frame_count(text: &str) -> Result<u32, String> {
    int_in(text, 0, u64::from(FRAMES_MAX), "frames").map(|x| x as u32)
}

/// A colour-table size (`--table-size`): a power of two from 2 to 1024.
pub fn table_size(text: &str) -> Result<usize, String> {
    let x = int_in(text, 2, 1024, "table size")?;
    if !x.is_power_of_two() {
        return Err(format!("{x} is not a power of two (2, 4, 8, ..., 1024)"));
    }
    Ok(x as usize)
}

/// A frame index (`--frame`): any `u32` (animations wrap around).
pub fn frame_index(text: &str) -> Result<u32, String> {
    int_in(text, 0, u64::from(u32::MAX), "frame").map(|x| x as u32)
}

/// Milliseconds per animation frame (`--delay`): `0..=65535`.
pub fn delay_ms(text: &str) -> Result<u16, String> {
    int_in(text, 0, u64::from(u16::MAX), "delay").map(|x| x as u16)
}

/// The side of a check plane in pixels (`check --size`): `1..=4096`.
pub fn plane_size(text: &str) -> Result<u32, String> {
    int_in(text, 1, 4096, "size").map(|x| x as u32)
}

/// A clap value parser from a checking function; its errors name the flag and give the
/// function's message (which shortens long values) instead of clap's echo of the whole value.
#[derive(Clone, Copy)]
pub struct Checked<T>(pub fn(&str) -> Result<T, String>);

impl<T: Clone + Send + Sync + 'static> TypedValueParser for Checked<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<T, clap::Error> {
        let flag = arg.map_or_else(|| "a value".to_string(), |a| format!("'{a}'"));
        let text = value.to_str().ok_or_else(|| {
            clap::Error::raw(
                clap::error::ErrorKind::InvalidUtf8,
                format!("invalid value for {flag}: not UTF-8\n"),
            )
            .with_cmd(cmd)
        })?;
        (self.0)(text).map_err(|e| {
            clap::Error::raw(
                clap::error::ErrorKind::ValueValidation,
                format!("invalid value for {flag}: {e}\n"),
            )
            .with_cmd(cmd)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractions_refuse_nan_infinities_and_out_of_range() {
        assert_eq!(fraction("0.5"), Ok(0.5));
        assert_eq!(fraction("0"), Ok(0.0));
        assert_eq!(fraction("1"), Ok(1.0));
        for bad in [
            "nan",
            "NaN",
            "inf",
            "-inf",
            "2",
            "-0.1",
            "1.0000001",
            "x",
            "",
        ] {
            assert!(fraction(bad).is_err(), "{bad}");
        }
        let long = format!("1{}", "0".repeat(300));
        let e = fraction(&long).unwrap_err();
        assert!(e.len() < 80, "{e}");
        assert!(e.contains("301 characters"), "{e}");
    }

    #[test]
    fn integers_are_range_checked() {
        assert_eq!(frame_count("0"), Ok(0));
        assert_eq!(frame_count("1000000"), Ok(1_000_000));
        assert!(frame_count("1000001").is_err());
        assert!(frame_count("-1").is_err());
        assert!(frame_count("1e3").is_err());
        assert_eq!(table_size("256"), Ok(256));
        assert_eq!(table_size("2"), Ok(2));
        for bad in ["0", "1", "3", "2048", "100", "nan"] {
            assert!(table_size(bad).is_err(), "{bad}");
        }
    }
}
