//! Range-checked values of a scene file: numbers, coordinates, matrices, colours and names, each
//! converted to its texcore format, each error ([`Fail`]) naming its field and where it is.

use super::*;

/// A semantic error: where, which field, what.
#[derive(Debug)]
pub(crate) struct Fail {
    pub span: Range<usize>,
    pub field: String,
    pub message: String,
}

pub(crate) type R<T> = Result<T, Fail>;

pub(crate) fn fail<T>(
    span: Range<usize>,
    field: impl Into<String>,
    message: impl Into<String>,
) -> R<T> {
    Err(Fail {
        span,
        field: field.into(),
        message: message.into(),
    })
}

/// Largest world coordinate, texture translation or matrix entry magnitude (`Q16.16` holds
/// `[-32768, 32768)`).
pub const COORD_MAX: f64 = 32767.0;
/// Largest image side in pixels.
pub const SIZE_MAX: i64 = 4096;
/// Most animation frames.
pub const FRAMES_MAX: i64 = 10_000;
/// Largest rotation magnitude in degrees (1000 turns).
pub const DEGREES_MAX: f64 = 360_000.0;
/// Largest noise amplitude or material amplitude factor magnitude (texcore's amplitude budget).
pub const AMPLITUDE_MAX: f64 = 512.0;
/// Capacity of a material's noise terms.
pub const TERMS_MAX: usize = texcore::presets::PRESET_TERMS;

/// `x` as raw `Q16.16`, rounded to nearest (the caller has checked the range).
pub(crate) fn q16(x: f64) -> i64 {
    (x * 65536.0).round() as i64
}

/// Degrees as raw angle units (`2^32` per turn), rounded to nearest.
pub(crate) fn angle_units(deg: f64) -> i64 {
    (deg * 4_294_967_296.0 / 360.0).round() as i64
}

/// A real as echoed in a message: shortened to scientific notation when long (`1e300`, not its
/// 301 digits).
pub(super) fn number(v: f64) -> String {
    let s = format!("{v}");
    if s.len() <= 16 {
        return s;
    }
    let e = format!("{v:e}");
    if e.len() <= 16 {
        e
    } else {
        format!("{v:.6e}")
    }
}

/// A real in a range (`ok`), described by `range` in the message.
pub(in crate::scenefile) fn real(
    v: &S<f64>,
    field: &str,
    ok: impl Fn(f64) -> bool,
    range: &str,
) -> R<f64> {
    let x = *v.get_ref();
    if !x.is_finite() || !ok(x) {
        return fail(
            v.span(),
            field,
            format!("{} is out of range ({range})", number(x)),
        );
    }
    Ok(x)
}

/// An integer in `lo..=hi`.
pub(super) fn int(v: &S<i64>, field: &str, lo: i64, hi: i64, what: &str) -> R<i64> {
    let x = *v.get_ref();
    if x < lo || x > hi {
        return fail(
            v.span(),
            field,
            format!("{x} is out of range ({lo} <= {what} <= {hi})"),
        );
    }
    Ok(x)
}

pub(super) fn coord_ok(x: f64) -> bool {
    x.abs() <= COORD_MAX
}

pub(super) const COORD_RANGE: &str = "|v| <= 32767";

/// Three coordinates within `±32767`, as raw `Q16.16`.
pub(in crate::scenefile) fn coord3(v: &S<[f64; 3]>, field: &str) -> R<[i64; 3]> {
    let mut out = [0i64; 3];
    for (k, x) in v.get_ref().iter().enumerate() {
        if !x.is_finite() || !coord_ok(*x) {
            return fail(
                v.span(),
                format!("{field}[{k}]"),
                format!("{} is out of range ({COORD_RANGE})", number(*x)),
            );
        }
        out[k] = q16(*x);
    }
    Ok(out)
}

/// A number or three numbers from a TOML value.
pub(super) fn num_or_vec3(v: &S<Value>, field: &str) -> R<[f64; 3]> {
    let n = |x: &Value| match x {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    };
    match v.get_ref() {
        Value::Array(a) if a.len() == 3 => {
            let mut out = [0.0; 3];
            for (k, x) in a.iter().enumerate() {
                match n(x) {
                    Some(f) => out[k] = f,
                    None => {
                        return fail(
                            v.span(),
                            format!("{field}[{k}]"),
                            format!("expected a number, found {}", x.type_str()),
                        )
                    }
                }
            }
            Ok(out)
        }
        x => match n(x) {
            Some(f) => Ok([f; 3]),
            None => fail(
                v.span(),
                field,
                format!(
                    "expected a number or an array of 3 numbers, found {}",
                    describe(x)
                ),
            ),
        },
    }
}

pub(super) fn describe(v: &Value) -> String {
    match v {
        Value::Array(a) => format!("an array of {} values", a.len()),
        x => x.type_str().to_string(),
    }
}

/// Three reals each satisfying `ok`.
pub(in crate::scenefile) fn reals3(
    v: &S<Value>,
    field: &str,
    ok: impl Fn(f64) -> bool,
    range: &str,
) -> R<[f64; 3]> {
    let a = num_or_vec3(v, field)?;
    for (k, x) in a.iter().enumerate() {
        if !x.is_finite() || !ok(*x) {
            let f = if matches!(v.get_ref(), Value::Array(_)) {
                format!("{field}[{k}]")
            } else {
                field.to_string()
            };
            return fail(
                v.span(),
                f,
                format!("{} is out of range ({range})", number(*x)),
            );
        }
    }
    Ok(a)
}

pub(super) fn entry(x: i64) -> MatrixEntry {
    MatrixEntry::from_bits(x as i32)
}

/// A 3x3 or 3x4 matrix of `Q16.16` entries (rows); the fourth column is a translation.
/// A matrix (rows) and the translation of its fourth column, raw `Q16.16`.
type MatrixFx = ([[i64; 3]; 3], Option<[i64; 3]>);

pub(super) fn matrix(v: &Rows, field: &str) -> R<MatrixFx> {
    let rows = v.get_ref();
    let cols = rows.first().map_or(0, Vec::len);
    if rows.len() != 3 || !(cols == 3 || cols == 4) || rows.iter().any(|r| r.len() != cols) {
        return fail(
            v.span(),
            field,
            "expected 3 rows of 3 numbers (or of 4: the last column is the translation)",
        );
    }
    let mut m = [[0i64; 3]; 3];
    let mut t = [0i64; 3];
    for (i, row) in rows.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            if !x.is_finite() || !coord_ok(*x) {
                return fail(
                    v.span(),
                    format!("{field}[{i}][{j}]"),
                    format!("{} is out of range ({COORD_RANGE})", number(*x)),
                );
            }
            if j < 3 {
                m[i][j] = q16(*x);
            } else {
                t[i] = q16(*x);
            }
        }
    }
    Ok((m, (cols == 4).then_some(t)))
}

/// An affine map from `scale` (number or 3 numbers) or `matrix` (3x3 or 3x4) and `translate`.
pub(super) fn affine(
    scale: Option<&S<Value>>,
    scale_name: &str,
    mat: Option<&S<Vec<Vec<f64>>>>,
    translate: Option<&S<[f64; 3]>>,
    field: &str,
) -> R<([[i64; 3]; 3], [i64; 3])> {
    let mut m = [[65536, 0, 0], [0, 65536, 0], [0, 0, 65536]];
    let mut t = [0i64; 3];
    match (scale, mat) {
        (Some(_), Some(mm)) => {
            return fail(
                mm.span(),
                format!("{field}.matrix"),
                format!("give either `{scale_name}` or `matrix`, not both"),
            )
        }
        (Some(s), None) => {
            let k = reals3(s, &format!("{field}.{scale_name}"), coord_ok, COORD_RANGE)?;
            for i in 0..3 {
                m[i][i] = q16(k[i]);
            }
        }
        (None, Some(mm)) => {
            let (mx, tx) = matrix(mm, &format!("{field}.matrix"))?;
            m = mx;
            if let Some(tx) = tx {
                if let Some(tr) = translate {
                    return fail(
                        tr.span(),
                        format!("{field}.translate"),
                        "the matrix has 4 columns: its last column is already the translation",
                    );
                }
                t = tx;
            }
        }
        (None, None) => {}
    }
    if let Some(tr) = translate {
        t = coord3(tr, &format!("{field}.translate"))?;
    }
    Ok((m, t))
}

pub(crate) fn to_affine(m: &[[i64; 3]; 3], t: &[i64; 3]) -> Affine3 {
    Affine3::new(
        [
            [entry(m[0][0]), entry(m[0][1]), entry(m[0][2])],
            [entry(m[1][0]), entry(m[1][1]), entry(m[1][2])],
            [entry(m[2][0]), entry(m[2][1]), entry(m[2][2])],
        ],
        [entry(t[0]), entry(t[1]), entry(t[2])],
    )
}

/// `#rrggbb` or `#rrggbbaa`.
pub(super) fn colour(v: &S<String>, field: &str) -> R<[u8; 4]> {
    let s = v.get_ref();
    let hex = s.strip_prefix('#').unwrap_or("");
    let ok = (hex.len() == 6 || hex.len() == 8) && hex.chars().all(|c| c.is_ascii_hexdigit());
    if !ok {
        return fail(
            v.span(),
            field,
            format!("`{s}` is not a colour (\"#rrggbb\" or \"#rrggbbaa\", hexadecimal)"),
        );
    }
    let b = |k: usize| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).unwrap_or(0);
    Ok([b(0), b(1), b(2), if hex.len() == 8 { b(3) } else { 255 }])
}

/// Names of materials and objects: used in animation parameters, so no dots or spaces.
pub(super) fn check_name(name: &str, span: Range<usize>, field: &str) -> R<()> {
    if name.len() > NAME_MAX {
        return fail(
            span,
            field,
            format!(
                "a name of {} bytes is too long (names are at most {NAME_MAX} bytes)",
                name.len()
            ),
        );
    }
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && !name.chars().all(|c| c.is_ascii_digit());
    if !ok {
        return fail(
            span,
            field,
            format!("`{name}` is not a valid name (letters, digits, `_` and `-`, not only digits)"),
        );
    }
    Ok(())
}
