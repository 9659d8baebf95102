//! Materials in one call: a preset (or any model) and its colour keys become a ready
//! [`Texture`] with one call that names the table size and the filter.
//!
//! ```
//! use texcore::filter::Antialias;
//! use texcore::ready::{Material, PresetName};
//!
//! let marble = Material::preset(PresetName::Marble).texture::<256>(Antialias::Csat)?;
//! # let _ = marble;
//! # Ok::<(), texcore::ready::MaterialError>(())
//! ```
//!
//! A [`Material`] is a shader (a [`TextureModel`] or a perturbed material), the key colours of its
//! colour table, the table's wrap and key spacing, and the plane of solid coordinates its preset
//! is checked on. [`Material::texture`] builds the colour table of `N` entries from the keys,
//! precomputes the filter's data and returns the texture with the defaults of the whole project
//! (nearest look-up, L2 gradient norm, [`EvalMode::Auto`], octave culling on);
//! [`Material::texture_with`] takes the other knobs.
//!
//! Guarantees: no allocation, no floating point, no panic; every failure (a table size that is
//! not a power of two, keys out of order, a filter that is not compiled in, more than
//! [`MAX_KEYS`] keys, an invalid perturbed material) is a [`MaterialError`] value with `Display`.
//! The texture is exactly the one the parts would build by hand (same table entries, same
//! samples), so checksums do not depend on the way a texture was made.

use crate::color::Rgba8888;
use crate::filter::{Antialias, ColorStage, GradientNorm};
use crate::format::TexValue;
use crate::hash::HashKind;
use crate::model::{ModelError, TextureModel};
use crate::presets::{self, CheckPlane, Key, PRESET_TERMS, UNIT_PLANE};
use crate::span::EvalMode;
use crate::table::{ColorTable, KeySpacing, TableError, TableLookup, TableWrap};
use crate::texture::{Shader, Texture};

/// Most key colours a [`Material`] may have (the keys are converted on the stack).
pub const MAX_KEYS: usize = 64;

/// The built-in materials ([`crate::presets`]), by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PresetName {
    /// `s^2 + t^2 + n(4s, 4t, r)`: wood rings.
    Wood,
    /// `r + sum_{i<4} 2^-i n(2^i s)`: marble.
    Marble,
    /// Blue sky to white clouds.
    Clouds,
    /// Blue to black water.
    Water,
    /// Fire at phase 0 (animate with [`crate::presets::set_fire_phase`] on the texture's model).
    Fire,
    /// A planet's cartographic colours.
    Planet,
    /// A planet's cloud layer (alpha).
    PlanetClouds,
    /// The zone plate `50 s^2 + 50 t^2` with the zebra table.
    Zoneplate,
    /// Miné & Neyret's domain-perturbed marble (feature `perturb`).
    #[cfg(feature = "perturb")]
    MnMarble,
    /// Miné & Neyret's domain-perturbed wood (feature `perturb`).
    #[cfg(feature = "perturb")]
    MnWood,
}

impl PresetName {
    /// Every preset, in [`crate::presets::NAMES`] order.
    pub const ALL: &'static [PresetName] = &[
        PresetName::Wood,
        PresetName::Marble,
        PresetName::Clouds,
        PresetName::Water,
        PresetName::Fire,
        PresetName::Planet,
        PresetName::PlanetClouds,
        PresetName::Zoneplate,
        #[cfg(feature = "perturb")]
        PresetName::MnMarble,
        #[cfg(feature = "perturb")]
        PresetName::MnWood,
    ];

    /// The preset's name as in [`crate::presets::NAMES`] (`"planet-clouds"`, `"mn-marble"`).
    pub const fn as_str(self) -> &'static str {
        match self {
            PresetName::Wood => "wood",
            PresetName::Marble => "marble",
            PresetName::Clouds => "clouds",
            PresetName::Water => "water",
            PresetName::Fire => "fire",
            PresetName::Planet => "planet",
            PresetName::PlanetClouds => "planet-clouds",
            PresetName::Zoneplate => "zoneplate",
            #[cfg(feature = "perturb")]
            PresetName::MnMarble => "mn-marble",
            #[cfg(feature = "perturb")]
            PresetName::MnWood => "mn-wood",
        }
    }

    /// The preset called `name`, if there is one (and it is compiled in).
    pub fn from_name(name: &str) -> Option<PresetName> {
        PresetName::ALL.iter().copied().find(|p| p.as_str() == name)
    }
}

impl core::fmt::Display for PresetName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a material could not become a texture. `Display` names the problem in a short sentence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MaterialError {
    /// The colour table or its filter could not be built (size, keys, filter not compiled in).
    Table(TableError),
    /// The shader could not be built (a perturbed material's parameters).
    Model(ModelError),
    /// More key colours than [`MAX_KEYS`].
    TooManyKeys {
        /// How many keys were given.
        count: usize,
    },
}

impl core::fmt::Display for MaterialError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MaterialError::Table(e) => write!(f, "colour table: {e}"),
            MaterialError::Model(e) => write!(f, "texture model: {e}"),
            MaterialError::TooManyKeys { count } => {
                write!(f, "{count} key colours given, at most {MAX_KEYS} allowed")
            }
        }
    }
}

impl core::error::Error for MaterialError {}

impl From<TableError> for MaterialError {
    fn from(e: TableError) -> Self {
        MaterialError::Table(e)
    }
}

impl From<ModelError> for MaterialError {
    fn from(e: ModelError) -> Self {
        MaterialError::Model(e)
    }
}

/// The knobs of a texture besides its table size and filter. The default is the project's
/// default unit: nearest look-up, L2 gradient norm, [`EvalMode::Auto`], octave culling on with
/// the default band-limiting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TextureOptions {
    /// Nearest or linear colour-table look-up.
    pub lookup: TableLookup,
    /// The gradient norm of the filter width.
    pub norm: GradientNorm,
    /// The span evaluation mode.
    pub mode: EvalMode,
    /// Cull noise octaves past the Nyquist limit.
    pub cull: bool,
    /// How culling fades and spreads the octaves past the Nyquist limit (the measured best by
    /// default; an accuracy knob).
    pub band_limit: crate::bandlimit::BandLimit,
}

impl Default for TextureOptions {
    fn default() -> Self {
        TextureOptions {
            lookup: TableLookup::Nearest,
            norm: GradientNorm::L2,
            mode: EvalMode::Auto,
            cull: true,
            band_limit: crate::bandlimit::BandLimit::DEFAULT,
        }
    }
}

/// A shader with its colour keys: what a texture is made of, before its table size and filter
/// are chosen. `T` is the shader's noise-term capacity (the presets' is [`PRESET_TERMS`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Material<'k, const T: usize = PRESET_TERMS> {
    shader: Result<Shader<T>, ModelError>,
    keys: &'k [Key],
    spacing: KeySpacing,
    wrap: TableWrap,
    plane: CheckPlane,
}

impl Material<'static, PRESET_TERMS> {
    /// The built-in material `name` with the default lattice hash.
    pub fn preset(name: PresetName) -> Self {
        Self::preset_with_hash(name, HashKind::default())
    }

    /// The built-in material `name` with lattice hash `hash` (the permutation table or the
    /// table-free integer hash: another, equally random, lattice).
    pub fn preset_with_hash(name: PresetName, hash: HashKind) -> Self {
        match Self::by_name(name.as_str(), hash) {
            Some(m) => m,
            // Every `PresetName` is a preset name (tested); an unreachable fallback that does
            // not panic: the zone plate.
            None => Self::model(presets::zoneplate().model, &presets::ZEBRA_KEYS),
        }
    }

    /// The built-in material called `name` (as in [`crate::presets::NAMES`]); `None` for an
    /// unknown name.
    pub fn by_name(name: &str, hash: HashKind) -> Option<Self> {
        if let Some(p) = presets::by_name(name, hash) {
            let spacing = spacing_of(p.squared_keys);
            return Some(Material {
                wrap: p.model.wrap(),
                shader: Ok(Shader::Model(p.model)),
                keys: p.keys,
                spacing,
                plane: p.plane,
            });
        }
        #[cfg(feature = "perturb")]
        if let Some(p) = presets::perturbed_by_name(name, hash) {
            return Some(Material {
                shader: crate::material::PerturbedMaterial::new(&p.params, p.wrap)
                    .map(Shader::Perturbed),
                keys: p.keys,
                spacing: spacing_of(p.squared_keys),
                wrap: p.wrap,
                plane: p.plane,
            });
        }
        None
    }
}

/// The colour table of `N` entries interpolated between preset-style keys (U0F16 positions,
/// RGBA bytes; at most [`MAX_KEYS`]): [`ColorTable::from_keys_spaced`] of the converted keys.
pub fn key_table<const N: usize>(
    keys: &[Key],
    spacing: KeySpacing,
) -> Result<ColorTable<N>, MaterialError> {
    let mut k = [(TexValue::ZERO, Rgba8888::BLACK); MAX_KEYS];
    let Some(slots) = k.get_mut(..keys.len()) else {
        return Err(MaterialError::TooManyKeys { count: keys.len() });
    };
    for (slot, (p, c)) in slots.iter_mut().zip(keys) {
        // Positions past 1.0 (or past `i32`) stay out of range for the table's check.
        *slot = (
            TexValue::from_bits(i32::try_from(*p).unwrap_or(i32::MAX)),
            Rgba8888::from_array(*c),
        );
    }
    Ok(ColorTable::from_keys_spaced(slots, spacing)?)
}

const fn spacing_of(squared: bool) -> KeySpacing {
    if squared {
        KeySpacing::Squared
    } else {
        KeySpacing::Linear
    }
}

impl<'k, const T: usize> Material<'k, T> {
    /// A material of any shader: colour keys `keys` (positions not decreasing, U0F16 raw),
    /// table wrap `wrap`, linear key spacing, the unit square as its plane.
    pub fn new(shader: Shader<T>, wrap: TableWrap, keys: &'k [Key]) -> Self {
        Material {
            shader: Ok(shader),
            keys,
            spacing: KeySpacing::Linear,
            wrap,
            plane: UNIT_PLANE,
        }
    }

    /// A material of a texture model with the model's own wrap.
    pub fn model(model: TextureModel<T>, keys: &'k [Key]) -> Self {
        let wrap = model.wrap();
        Self::new(Shader::Model(model), wrap, keys)
    }

    /// The same material with other key colours.
    pub fn with_keys<'j>(self, keys: &'j [Key]) -> Material<'j, T> {
        Material {
            shader: self.shader,
            keys,
            spacing: self.spacing,
            wrap: self.wrap,
            plane: self.plane,
        }
    }

    /// The same material with keys placed linearly or at `c^2`.
    pub fn with_spacing(mut self, spacing: KeySpacing) -> Self {
        self.spacing = spacing;
        self
    }

    /// The same material with another check plane.
    pub fn with_plane(mut self, plane: CheckPlane) -> Self {
        self.plane = plane;
        self
    }

    /// The shader, or why it could not be built.
    pub fn shader(&self) -> Result<&Shader<T>, MaterialError> {
        self.shader.as_ref().map_err(|e| MaterialError::Model(*e))
    }

    /// Mutable access to the shader (to set a precision or an animation phase before the
    /// texture is made); `None` if it could not be built.
    pub fn shader_mut(&mut self) -> Option<&mut Shader<T>> {
        self.shader.as_mut().ok()
    }

    /// The key colours.
    pub fn keys(&self) -> &'k [Key] {
        self.keys
    }

    /// How the keys are placed.
    pub fn spacing(&self) -> KeySpacing {
        self.spacing
    }

    /// The colour table's wrap.
    pub fn wrap(&self) -> TableWrap {
        self.wrap
    }

    /// The plane of solid coordinates the material is checked on (256 pixels a side; the unit
    /// square for materials that are not presets).
    pub fn plane(&self) -> CheckPlane {
        self.plane
    }

    /// The colour table of `N` entries interpolated between the keys ([`key_table`]).
    pub fn table<const N: usize>(&self) -> Result<ColorTable<N>, MaterialError> {
        key_table(self.keys, self.spacing)
    }

    /// The colour stage: the table of `N` entries with look-up `lookup` and filter `aa`.
    pub fn stage<const N: usize>(
        &self,
        aa: Antialias,
        lookup: TableLookup,
    ) -> Result<ColorStage<N>, MaterialError> {
        Ok(ColorStage::new(self.table()?, self.wrap, lookup, aa)?)
    }

    /// The texture with a table of `N` entries and filter `aa`, with the default
    /// [`TextureOptions`].
    pub fn texture<const N: usize>(&self, aa: Antialias) -> Result<Texture<T, N>, MaterialError> {
        self.texture_with(aa, TextureOptions::default())
    }

    /// The texture with a table of `N` entries, filter `aa` and the given options.
    pub fn texture_with<const N: usize>(
        &self,
        aa: Antialias,
        opts: TextureOptions,
    ) -> Result<Texture<T, N>, MaterialError> {
        let stage = self.stage(aa, opts.lookup)?;
        let shader = self.shader()?.clone();
        Ok(Texture::new(shader, stage, opts.norm, opts.mode)
            .with_culling(opts.cull)
            .with_band_limit(opts.band_limit))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;

    #[test]
    fn names_round_trip() {
        for &p in PresetName::ALL {
            assert_eq!(PresetName::from_name(p.as_str()), Some(p));
            assert!(presets::NAMES.contains(&p.as_str()));
            let m = Material::by_name(p.as_str(), HashKind::Integer).unwrap();
            assert_eq!(m, Material::preset_with_hash(p, HashKind::Integer));
        }
        assert_eq!(PresetName::from_name("nope"), None);
        assert!(Material::by_name("nope", HashKind::Integer).is_none());
    }

    /// The table is the one built by hand from the preset's keys.
    #[test]
    fn table_equals_hand_built() {
        for &name in PresetName::ALL {
            let m = Material::preset(name);
            let keys: Vec<_> = m
                .keys()
                .iter()
                .map(|(p, c)| (TexValue::from_bits(*p as i32), Rgba8888::from_array(*c)))
                .collect();
            let hand = ColorTable::<256>::from_keys_spaced(&keys, m.spacing()).unwrap();
            assert_eq!(m.table::<256>().unwrap(), hand, "{name}");
        }
        #[cfg(feature = "perturb")]
        assert_eq!(
            Material::preset(PresetName::MnWood).spacing(),
            KeySpacing::Squared
        );
    }

    #[cfg(feature = "csat")]
    #[test]
    fn marble_texture_is_the_workload() {
        use crate::texture::workload;
        let t = Material::preset_with_hash(PresetName::Marble, HashKind::Integer)
            .texture::<256>(Antialias::Csat)
            .unwrap();
        let w = workload::marble_csat(HashKind::Integer, EvalMode::Auto).unwrap();
        assert_eq!(t.shader(), w.shader());
        assert_eq!(t.stage(), w.stage());
        assert_eq!(t.options(), w.options());
    }

    #[test]
    fn errors_are_values() {
        let m = Material::preset(PresetName::Marble);
        assert_eq!(
            m.texture::<100>(Antialias::None).unwrap_err(),
            MaterialError::Table(TableError::InvalidSize { n: 100 })
        );
        let many = [(0u32, [0u8; 4]); MAX_KEYS + 1];
        let e = m.clone().with_keys(&many).table::<256>().unwrap_err();
        assert_eq!(
            e,
            MaterialError::TooManyKeys {
                count: MAX_KEYS + 1
            }
        );
        assert_eq!(
            std::format!("{e}"),
            "65 key colours given, at most 64 allowed"
        );
        let bad = [(0u32, [0u8; 4]), (70000, [0; 4])];
        let e = m.clone().with_keys(&bad).table::<256>().unwrap_err();
        assert_eq!(
            std::format!("{e}"),
            "colour table: key 1 has a position outside [0, 1]"
        );
        let none: [Key; 0] = [];
        assert!(m.with_keys(&none).table::<256>().is_err());
        if !Antialias::Mip.is_available() {
            let e = Material::preset(PresetName::Marble)
                .texture::<256>(Antialias::Mip)
                .unwrap_err();
            assert_eq!(e, MaterialError::Table(TableError::FilterDisabled));
        }
    }
}
