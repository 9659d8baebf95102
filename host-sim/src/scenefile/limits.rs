//! Size limits of scene files, checked before anything else looks at the content: the file size
//! ([`FILE_MAX`], checked while reading, so an endless input such as `/dev/zero` or a FIFO is
//! never read past the limit), the length of every string and key ([`STRING_MAX`]) and of names
//! ([`NAME_MAX`], checked in `convert`). Also: TOML's words for serde's type errors.

use std::io::Read;
use std::ops::Range;
use std::path::Path;

use toml::de::{DeTable, DeValue};

/// Largest scene file in bytes (1 MiB).
pub const FILE_MAX: u64 = 1 << 20;
/// Longest string value or key of a scene file, in bytes.
pub const STRING_MAX: usize = 256;
/// Longest name (the scene's `name`, material and object names), in bytes.
pub const NAME_MAX: usize = 64;

/// Reads at most `max + 1` bytes of `path`: the text, or a message when it is larger than `max`
/// bytes, unreadable or not UTF-8.
pub(crate) fn read_limited(path: &Path, max: u64) -> Result<String, String> {
    let f = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut buf = Vec::new();
    f.take(max.saturating_add(1))
        .read_to_end(&mut buf)
        .map_err(|e| e.to_string())?;
    if buf.len() as u64 > max {
        return Err(format!(
            "the file is larger than {max} bytes, the limit of scene files; it was not read \
             further"
        ));
    }
    String::from_utf8(buf).map_err(|e| {
        format!(
            "the file is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// The first string value or key longer than [`STRING_MAX`] bytes: its span, field and message.
/// `None` when there is none, or when the text is not valid TOML (the parser reports that).
pub(crate) fn long_string(source: &str) -> Option<(Range<usize>, String, String)> {
    fn too_long(n: usize, what: &str) -> String {
        format!("{what} of {n} bytes is too long (strings in scene files are at most {STRING_MAX} bytes)")
    }
    fn walk(
        v: &DeValue<'_>,
        span: Range<usize>,
        path: &str,
    ) -> Option<(Range<usize>, String, String)> {
        match v {
            DeValue::String(s) if s.len() > STRING_MAX => {
                Some((span, path.to_string(), too_long(s.len(), "a string")))
            }
            DeValue::Table(t) => t.iter().find_map(|(k, val)| {
                let key: &str = k.get_ref();
                if key.len() > STRING_MAX {
                    return Some((k.span(), path.to_string(), too_long(key.len(), "a key")));
                }
                let p = if path.is_empty() {
                    key.to_string()
                } else {
                    format!("{path}.{key}")
                };
                walk(val.get_ref(), val.span(), &p)
            }),
            DeValue::Array(a) => a
                .iter()
                .enumerate()
                .find_map(|(i, val)| walk(val.get_ref(), val.span(), &format!("{path}[{i}]"))),
            _ => None,
        }
    }
    let doc = DeTable::parse(source).ok()?;
    let span = doc.span();
    walk(&DeValue::Table(doc.into_inner()), span, "")
}

/// A serde type error in TOML's words: `expected i64` becomes `expected an integer`, `u8` an
/// integer from 0 to 255, `f64` a number, a sequence an array, a map or struct a table.
pub(crate) fn toml_words(message: &str) -> String {
    const WORDS: [(&str, &str); 20] = [
        ("floating point", "float"),
        ("expected i8", "expected an integer from -128 to 127"),
        ("expected i16", "expected an integer from -32768 to 32767"),
        (
            "expected i32",
            "expected an integer from -2147483648 to 2147483647",
        ),
        ("expected i64", "expected an integer"),
        ("expected u8", "expected an integer from 0 to 255"),
        ("expected u16", "expected an integer from 0 to 65535"),
        ("expected u32", "expected an integer from 0 to 4294967295"),
        ("expected u64", "expected a non-negative integer"),
        ("expected usize", "expected a non-negative integer"),
        ("expected f32", "expected a number"),
        ("expected f64", "expected a number"),
        ("expected a sequence", "expected an array"),
        ("expected a map", "expected a table"),
        ("expected struct", "expected a table"),
        (
            "expected a tuple of size 2",
            "expected an array of 2 values",
        ),
        (
            "expected a tuple of size 3",
            "expected an array of 3 values",
        ),
        (
            "expected an array of length 3",
            "expected an array of 3 values",
        ),
        ("expected a borrowed string", "expected a string"),
        ("expected a character", "expected a string"),
    ];
    let mut m = message.to_string();
    for (rust, toml) in WORDS {
        let mut out = String::with_capacity(m.len());
        let mut rest = m.as_str();
        while let Some(k) = rest.find(rust) {
            let after = &rest[k + rust.len()..];
            // Whole words only (`expected i64` but not `expected i640`).
            let ends_word = after.chars().next().is_none_or(|c| !c.is_alphanumeric());
            out.push_str(&rest[..k]);
            out.push_str(if ends_word { toml } else { rust });
            rest = after;
        }
        out.push_str(rest);
        m = out;
    }
    // `expected a table` may be followed by the Rust struct's name.
    if let Some(k) = m.find("expected a table ") {
        let tail = &m[k + "expected a table ".len()..];
        let name_len = tail
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(tail.len());
        m = format!("{}expected a table{}", &m[..k], &tail[name_len..]);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_errors_speak_toml() {
        assert_eq!(
            toml_words("invalid type: string \"wide\", expected i64"),
            "invalid type: string \"wide\", expected an integer"
        );
        assert_eq!(
            toml_words("invalid type: floating point `1.5`, expected u8"),
            "invalid type: float `1.5`, expected an integer from 0 to 255"
        );
        assert_eq!(
            toml_words("invalid type: integer `1`, expected struct CameraDef"),
            "invalid type: integer `1`, expected a table"
        );
        assert_eq!(
            toml_words("invalid type: string \"x\", expected a sequence"),
            "invalid type: string \"x\", expected an array"
        );
        assert_eq!(toml_words("expected i640"), "expected i640");
    }

    #[test]
    fn long_strings_and_keys_are_found_with_their_field() {
        let long = "x".repeat(STRING_MAX + 1);
        let ok = "y".repeat(STRING_MAX);
        assert!(long_string(&format!("name = \"{ok}\"\n")).is_none());
        let (span, field, msg) = long_string(&format!("a = 1\nname = \"{long}\"\n")).unwrap();
        assert_eq!(field, "name");
        assert_eq!(span.start, 13);
        assert!(msg.contains("257 bytes"), "{msg}");
        let (_, field, msg) =
            long_string(&format!("[materials.{long}]\npreset = \"wood\"\n")).unwrap();
        assert_eq!(field, "materials");
        assert!(msg.starts_with("a key"), "{msg}");
        let (_, field, _) = long_string(&format!(
            "[[objects]]\nmesh = \"cube\"\n[[objects]]\nmaterial = \"{long}\"\n"
        ))
        .unwrap();
        assert_eq!(field, "objects[1].material");
        assert!(long_string("a = [").is_none());
    }

    #[test]
    fn reading_stops_after_the_limit() {
        let r = read_limited(Path::new("/dev/zero"), 1000);
        assert!(r.unwrap_err().contains("larger than"));
        let dir = std::env::temp_dir().join(format!("texsim-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.toml");
        std::fs::write(&p, "a = 1\n").unwrap();
        assert_eq!(read_limited(&p, 6).unwrap(), "a = 1\n");
        assert!(read_limited(&p, 5).is_err());
        std::fs::write(&p, b"a = \"\xff\"\n").unwrap();
        assert!(read_limited(&p, 100).unwrap_err().contains("offset 5"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
