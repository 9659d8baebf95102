//! How a scene file's object is shaded: `shading = "procedural"` (the default: the solid texture
//! evaluated at every pixel) or `shading = "atlas"` (the texture baked once into a uniform atlas
//! over the object's mesh and every pixel read from it, [`super::scene`]), with an optional
//! `atlas = { size = 512, sampling = "bilinear", kind = "uniform" }` (size a power of two from
//! [`SIZE_MIN`] to [`SIZE_MAX`], default [`SIZE_DEFAULT`]; sampling `nearest`, `bilinear`
//! (default) or `mip`; layout `uniform` (default), `area`, `length` or `mip`, as
//! `texsim atlas --kind`).
//!
//! Guarantees: a bad value is an error naming its field and position (file:line through the
//! scene loader); `atlas` without `shading = "atlas"` is an error rather than silently ignored,
//! and so is `shading = "atlas"` on a `blend = "over"` object (an atlas texel's alpha marks
//! whether a triangle owns it, so atlases hold opaque colour only: blended objects are shaded
//! procedurally).

use serde::Deserialize;

use super::Sampling;
use crate::scenefile::convert::{fail, R};
use crate::scenefile::schema::S;

/// Smallest atlas side a scene file may ask for.
pub const SIZE_MIN: i64 = 16;
/// Largest atlas side a scene file may ask for (4 M texels, 16 MB RGBA).
pub const SIZE_MAX: i64 = 2048;
/// Atlas side when a scene file gives none.
pub const SIZE_DEFAULT: u32 = 512;

/// `shading` of an object.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ShadingDef {
    /// The solid texture at every pixel.
    Procedural,
    /// From a baked atlas.
    Atlas,
}

/// `sampling` of an object's atlas.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SamplingDef {
    /// Nearest texel.
    Nearest,
    /// Bilinear.
    Bilinear,
    /// MIP levels blended.
    Mip,
}

/// `kind` of an object's atlas (the layout).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum KindDef {
    /// Every triangle the same size.
    Uniform,
    /// Area-weighted.
    Area,
    /// Length-weighted.
    Length,
    /// MIP-mappable.
    Mip,
}

/// `atlas = { ... }` of an object.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AtlasDef {
    /// Side in texels.
    pub size: Option<S<i64>>,
    /// Look-up.
    pub sampling: Option<S<SamplingDef>>,
    /// Layout.
    pub kind: Option<S<KindDef>>,
}

/// An object drawn from its atlas: side, look-up and layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AtlasShading {
    /// Atlas side in texels (a power of two).
    pub size: u32,
    /// Look-up.
    pub sampling: Sampling,
    /// Layout.
    pub kind: super::AtlasKind,
}

/// The shading of an object from its `shading` and `atlas` fields (`field` is the object's
/// path, `objects[2]`; `blend_over`: the object has `blend = "over"`): `None` for procedural
/// shading.
pub(crate) fn convert(
    shading: Option<&S<ShadingDef>>,
    atlas: Option<&S<AtlasDef>>,
    blend_over: bool,
    field: &str,
) -> R<Option<AtlasShading>> {
    let is_atlas = shading.is_some_and(|s| *s.get_ref() == ShadingDef::Atlas);
    if !is_atlas {
        if let Some(a) = atlas {
            return fail(
                a.span(),
                format!("{field}.atlas"),
                "an atlas needs `shading = \"atlas\"`",
            );
        }
        return Ok(None);
    }
    if blend_over {
        if let Some(s) = shading {
            return fail(
                s.span(),
                format!("{field}.shading"),
                "an atlas holds opaque colour only: a `blend = \"over\"` object is shaded \
                 procedurally",
            );
        }
    }
    let mut out = AtlasShading {
        size: SIZE_DEFAULT,
        sampling: Sampling::Bilinear,
        kind: super::AtlasKind::Uniform,
    };
    if let Some(a) = atlas.map(|a| a.get_ref()) {
        if let Some(s) = &a.size {
            let n = *s.get_ref();
            if !(SIZE_MIN..=SIZE_MAX).contains(&n) || (n as u64).count_ones() != 1 {
                return fail(
                    s.span(),
                    format!("{field}.atlas.size"),
                    format!("{n} is not a power of two from {SIZE_MIN} to {SIZE_MAX}"),
                );
            }
            out.size = n as u32;
        }
        if let Some(s) = &a.sampling {
            out.sampling = match s.get_ref() {
                SamplingDef::Nearest => Sampling::Nearest,
                SamplingDef::Bilinear => Sampling::Bilinear,
                SamplingDef::Mip => Sampling::Mip,
            };
        }
        if let Some(k) = &a.kind {
            out.kind = match k.get_ref() {
                KindDef::Uniform => super::AtlasKind::Uniform,
                KindDef::Area => super::AtlasKind::Area,
                KindDef::Length => super::AtlasKind::Length,
                KindDef::Mip => super::AtlasKind::Mip,
            };
        }
    }
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use crate::scenefile;

    /// Ten lines; an object's fields follow from line 11.
    const BASE: &str = "[camera]\neye = [0, 0, 6]\ntarget = [0, 0, 0]\n\n[materials.m]\n\
                        preset = \"marble\"\n\n[[objects]]\nmesh = \"sphere\"\nmaterial = \"m\"\n";

    #[test]
    fn atlas_shading_is_read_and_bad_values_name_their_line() {
        let ok = format!(
            "{BASE}shading = \"atlas\"\natlas = {{ size = 256, sampling = \"mip\", kind = \"mip\" }}\n"
        );
        let s = scenefile::parse(&ok, "a.toml").unwrap();
        let plan = super::super::scene::atlas_plan(&s).expect("an atlas-shaded object");
        assert_eq!(plan.len(), 1);
        assert_eq!(plan[0].map(|a| a.size), Some(256));
        assert_eq!(plan[0].map(|a| a.kind), Some(super::super::AtlasKind::Mip));
        let none = scenefile::parse(BASE, "a.toml").unwrap();
        assert!(super::super::scene::atlas_plan(&none).is_none());
        for (bad, line, what) in [
            (
                "shading = \"atlas\"\natlas = { size = 300 }\n",
                12,
                "atlas.size",
            ),
            (
                "shading = \"atlas\"\natlas = { size = 4096 }\n",
                12,
                "atlas.size",
            ),
            ("atlas = { size = 256 }\n", 11, "atlas"),
            ("shading = \"baked\"\n", 11, "shading"),
            (
                "shading = \"atlas\"\natlas = { sampling = \"cubic\" }\n",
                12,
                "sampling",
            ),
            (
                "shading = \"atlas\"\natlas = { kind = \"hexagonal\" }\n",
                12,
                "kind",
            ),
            (
                "blend = \"over\"\nshading = \"atlas\"\n",
                12,
                "blend = \"over\"",
            ),
        ] {
            let e = scenefile::parse(&format!("{BASE}{bad}"), "a.toml").unwrap_err();
            let text = e.to_string();
            assert_eq!(e.line, line, "{bad}: {text}");
            assert!(text.contains(&format!("a.toml:{line}:")), "{bad}: {text}");
            assert!(text.contains(what), "{bad}: {text}");
        }
    }
}
