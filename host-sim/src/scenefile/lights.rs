//! Scene-file lights: the `[lighting]` table and the `[[lights]]` array, checked and converted
//! to texcore's [`Lighting`] (fixed point, once).
//!
//! ```toml
//! [lighting]
//! ambient = 0.15                # or [r, g, b]; each in [0, 16]
//! specular = 24                 # Blinn-Phong exponent, 0..=255 (0 or absent: none)
//! specular_strength = 0.6       # [0, 16]
//!
//! [[lights]]
//! direction = [-1, 1, 1]        # a directional light: towards the light, non-zero
//! color = [1, 0.95, 0.85]       # each in [0, 16]; default white
//! intensity = 1                 # [0, 16]; default 1
//!
//! [[lights]]
//! position = [0, 3, 2]          # a point light (no attenuation)
//! ```
//!
//! A light has exactly one of `direction` and `position`. `[lighting]` needs at least one light
//! (a scene without lights is drawn unlit, at no cost). Lights are not animated.

use serde::Deserialize;
use texcore::light::{Light, LightRgb, Lighting};
use texcore::scene::{Vec3, MAX_LIGHTS};
use toml::Value;

use super::convert::{coord3, fail, q16, real, reals3, R};
use super::schema::S;

/// Largest light colour channel, intensity, ambient or specular strength.
pub const LEVEL_MAX: f64 = 16.0;
const LEVEL_RANGE: &str = "0 <= v <= 16";

/// `[lighting]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightingDef {
    pub ambient: Option<S<Value>>,
    pub specular: Option<S<i64>>,
    pub specular_strength: Option<S<f64>>,
}

/// One of `[[lights]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightDef {
    pub direction: Option<S<[f64; 3]>>,
    pub position: Option<S<[f64; 3]>>,
    pub color: Option<S<Value>>,
    pub intensity: Option<S<f64>>,
}

fn level_ok(x: f64) -> bool {
    (0.0..=LEVEL_MAX).contains(&x)
}

/// One level in `[0, 16]` as raw `Q16.16`.
fn level(v: &S<f64>, field: &str) -> R<i32> {
    Ok(q16(real(v, field, level_ok, LEVEL_RANGE)?) as i32)
}

/// A level or three (`ambient = 0.2` or `ambient = [0.2, 0.2, 0.3]`), each in `[0, 16]`, as
/// raw `Q16.16`.
fn level_or_3(v: &S<Value>, field: &str) -> R<LightRgb> {
    let a = reals3(v, field, level_ok, LEVEL_RANGE)?;
    Ok(a.map(|x| q16(x) as i32))
}

/// The scene's lighting from `[lighting]` and `[[lights]]` (no lights: unlit).
pub(crate) fn lighting(
    table: Option<&S<LightingDef>>,
    lights: &[S<LightDef>],
) -> R<Lighting<MAX_LIGHTS>> {
    let mut out = Lighting::<MAX_LIGHTS>::new();
    if let Some(t) = table {
        if lights.is_empty() {
            return fail(
                t.span(),
                "lighting",
                "a [lighting] table needs at least one [[lights]] entry (a scene without lights is drawn unlit)",
            );
        }
        let d = t.get_ref();
        if let Some(a) = &d.ambient {
            let amb = level_or_3(a, "lighting.ambient")?;
            out = out
                .with_ambient(amb)
                .or_else(|e| fail(a.span(), "lighting.ambient", e.to_string()))?;
        }
        let exponent = match &d.specular {
            Some(e) => {
                let x = *e.get_ref();
                if !(0..=255).contains(&x) {
                    return fail(
                        e.span(),
                        "lighting.specular",
                        format!("{x} is out of range (0 <= specular <= 255)"),
                    );
                }
                x as u8
            }
            None => 0,
        };
        let strength = match &d.specular_strength {
            Some(s) => level(s, "lighting.specular_strength")?,
            None => q16(1.0) as i32,
        };
        out = out
            .with_specular(exponent, strength)
            .or_else(|e| fail(t.span(), "lighting", e.to_string()))?;
    }
    if lights.len() > MAX_LIGHTS {
        return fail(
            lights[MAX_LIGHTS].span(),
            format!("lights[{MAX_LIGHTS}]"),
            format!("a scene has at most {MAX_LIGHTS} lights"),
        );
    }
    for (i, l) in lights.iter().enumerate() {
        let field = format!("lights[{i}]");
        let light = light(l, &field)?;
        out.try_add(light)
            .or_else(|e| fail(l.span(), field.as_str(), e.to_string()))?;
    }
    Ok(out)
}

fn light(l: &S<LightDef>, field: &str) -> R<Light> {
    let d = l.get_ref();
    let color = match &d.color {
        Some(c) => level_or_3(c, &format!("{field}.color"))?,
        None => [q16(1.0) as i32; 3],
    };
    let intensity = match &d.intensity {
        Some(v) => level(v, &format!("{field}.intensity"))?,
        None => q16(1.0) as i32,
    };
    let v3 = |c: [i64; 3]| Vec3::new(c[0] as i32, c[1] as i32, c[2] as i32);
    match (&d.direction, &d.position) {
        (Some(dir), None) => {
            let f = format!("{field}.direction");
            let v = v3(coord3(dir, &f)?);
            Light::directional(v, color, intensity).or_else(|e| fail(dir.span(), f, e.to_string()))
        }
        (None, Some(pos)) => {
            let f = format!("{field}.position");
            let v = v3(coord3(pos, &f)?);
            Light::point(v, color, intensity).or_else(|e| fail(pos.span(), f, e.to_string()))
        }
        (Some(_), Some(pos)) => fail(
            pos.span(),
            format!("{field}.position"),
            "a light has either a direction (directional) or a position (point), not both",
        ),
        (None, None) => fail(
            l.span(),
            field,
            "missing: a direction (a directional light) or a position (a point light)",
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    struct Doc {
        lighting: Option<S<LightingDef>>,
        #[serde(default)]
        lights: Vec<S<LightDef>>,
    }

    fn load(src: &str) -> R<Lighting<MAX_LIGHTS>> {
        let d: Doc = toml::from_str(src).expect("toml");
        lighting(d.lighting.as_ref(), &d.lights)
    }

    fn err(src: &str) -> (String, String) {
        let e = load(src).expect_err(src);
        (e.field, e.message)
    }

    #[test]
    fn lights_convert_to_fixed_point() {
        let l = load(
            "[lighting]\nambient = [0.25, 0.5, 1]\nspecular = 16\nspecular_strength = 0.5\n\
             [[lights]]\ndirection = [0, 0, 2]\ncolor = [1, 0.5, 0]\nintensity = 2\n\
             [[lights]]\nposition = [1, 2, 3]\n",
        )
        .unwrap();
        assert_eq!(l.ambient(), [16384, 32768, 65536]);
        assert_eq!(l.specular_exponent(), 16);
        assert_eq!(l.lights().len(), 2);
        assert_eq!(l.lights()[0].color(), [131072, 65536, 0]);
        assert_eq!(
            l.lights()[0].kind(),
            texcore::light::LightKind::Directional { direction: Vec3::Z }
        );
        assert_eq!(
            l.lights()[1].kind(),
            texcore::light::LightKind::Point {
                position: Vec3::units(1, 2, 3)
            }
        );
        assert!(!load("").unwrap().is_lit());
    }

    #[test]
    fn bad_lights_name_the_field() {
        let cases = [
            (
                "[[lights]]\ndirection = [0, 0, 0]\n",
                "lights[0].direction",
                "non-zero direction",
            ),
            (
                "[[lights]]\nintensity = 1\n",
                "lights[0]",
                "missing: a direction",
            ),
            (
                "[[lights]]\ndirection = [0, 1, 0]\nposition = [0, 1, 0]\n",
                "lights[0].position",
                "not both",
            ),
            (
                "[[lights]]\ndirection = [0, 1, 0]\nintensity = 17\n",
                "lights[0].intensity",
                "17 is out of range (0 <= v <= 16)",
            ),
            (
                "[[lights]]\ndirection = [0, 1, 0]\ncolor = [1, -1, 0]\n",
                "lights[0].color[1]",
                "-1 is out of range",
            ),
            (
                "[[lights]]\nposition = [0, 1e9, 0]\n",
                "lights[0].position[1]",
                "out of range",
            ),
            (
                "[lighting]\nambient = 0.2\n",
                "lighting",
                "at least one [[lights]]",
            ),
            (
                "[lighting]\nambient = \"dim\"\n[[lights]]\ndirection = [0, 1, 0]\n",
                "lighting.ambient",
                "expected a number or an array of 3 numbers",
            ),
            (
                "[lighting]\nspecular = 300\n[[lights]]\ndirection = [0, 1, 0]\n",
                "lighting.specular",
                "300 is out of range",
            ),
        ];
        for (src, field, msg) in cases {
            let (f, m) = err(src);
            assert_eq!(f, field, "{src}");
            assert!(m.contains(msg), "{src}: {m}");
        }
        let five = "[[lights]]\ndirection = [0, 1, 0]\n".repeat(MAX_LIGHTS + 1);
        let (f, m) = err(&five);
        assert_eq!(f, format!("lights[{MAX_LIGHTS}]"));
        assert!(m.contains("at most"), "{m}");
    }
}
