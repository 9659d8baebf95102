//! The seed materials of Hart et al. (1999) section 2.2 (and Miné & Neyret's marble and wood) as
//! ready-made models with their colour keys.
//!
//! Every preset is plain data plus a builder: the model (quadric and noise terms), the colour
//! table's wrap flag and key colours, and the plane of solid coordinates that `texsim check` uses
//! for it. Presets take the lattice hash as a parameter so that a ROM-less build (`HashKind::Integer`)
//! gets the same materials with another (equally random) lattice.
//!
//! | preset | model | table |
//! |---|---|---|
//! | `wood` | `s^2 + t^2 + n(4s, 4t, r)` | mod, earlywood to latewood |
//! | `marble` | `r + sum_{i<4} 2^-i n(2^i s)` | mod, marble cross-section |
//! | `clouds` | `0.45 + 0.6 sum_{i<4} 2^-i n(2^i s)` | clamp, blue to white |
//! | `water` | as clouds | clamp, blue to black |
//! | `fire` | `t + 0.8 sum_{i<4} 2^-i n(2^i (s, t - phase, r))` | clamp, black-red-yellow-white |
//! | `planet` | `0.5 + 0.7 sum_{i<6} 2^-i n(2^i s)` | clamp, cartographic legend |
//! | `planet-clouds` | `0.35 + 0.8 sum_{i<5} 2^-i n(2^i s)` (rotated octaves) | clamp, alpha 0 to 0.85 white |
//! | `zoneplate` | `50 s^2 + 50 t^2` | mod, zebra (N = 256) |
//!
//! Noise basis: every preset uses trilinear value noise, whose lattice shows as axis-aligned
//! blocks in `fire` and the cloud layers (as in the paper's reduced unit, its section 4.4). The
//! smooth bases are a priced choice, not the default: on the accuracy report's check plane
//! (`docs/accuracy.md`, Cortex-M4F instructions a pixel) trilinear value noise costs 620, the
//! smooth fade 5005 and gradient noise 9256 (8 and 15 times: only the trilinear basis is forward
//! differenced), against the goal of a filtered image at no more than 1.5 times the unfiltered
//! cost; a scene file can choose them per material.

use crate::format::{Amplitude, MatrixEntry, QuadricCoeff};
use crate::hash::HashKind;
use crate::model::{ModelError, NoiseTerm, Octaves, TextureModel};
use crate::noise::NoiseBasis;
use crate::quadric::Quadric;
use crate::table::TableWrap;
use crate::transform::Affine3;

/// Capacity of the preset models (the papers use 4 to 8 noise terms).
pub const PRESET_TERMS: usize = 8;

/// A key colour: position in `[0, 1]` as U0F16 raw (`65536` = 1.0) and RGBA.
pub type Key = (u32, [u8; 4]);

/// The plane of solid coordinates a preset is checked on: pixel `(x, y)` of a `size x size` image
/// has `s = origin + (x + 1/2) * step_x + (y + 1/2) * step_y` (raw 16.16 components).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CheckPlane {
    /// Solid coordinates of the image's corner (before the half-pixel offset), raw 16.16.
    pub origin: [i32; 3],
    /// Step per pixel along x, raw 16.16.
    pub step_x: [i32; 3],
    /// Step per pixel along y, raw 16.16.
    pub step_y: [i32; 3],
}

/// The unit square in `(s, t)` at `r = 1/2`, 256 pixels a side: `s = (x + 0.5) / 256`.
pub const UNIT_PLANE: CheckPlane = CheckPlane {
    origin: [0, 0, 32768],
    step_x: [256, 0, 0],
    step_y: [0, 256, 0],
};

/// Everything a preset defines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Preset {
    /// Name (`wood`, `marble`, ...).
    pub name: &'static str,
    /// The texture model.
    pub model: TextureModel<PRESET_TERMS>,
    /// Key colours of the colour table (sorted by position).
    pub keys: &'static [Key],
    /// Colour-table size.
    pub table_size: usize,
    /// Whether the keys are placed at `c^2` (wood without a square root).
    pub squared_keys: bool,
    /// The check plane for a 256x256 image.
    pub plane: CheckPlane,
}

/// Names of all presets, in gallery order.
pub const NAMES: [&str; 10] = [
    "wood",
    "marble",
    "clouds",
    "water",
    "fire",
    "planet",
    "planet-clouds",
    "zoneplate",
    "mn-marble",
    "mn-wood",
];

const fn key(pos: f64, rgba: u32) -> Key {
    (
        (pos * 65536.0) as u32,
        [
            (rgba >> 24) as u8,
            (rgba >> 16) as u8,
            (rgba >> 8) as u8,
            rgba as u8,
        ],
    )
}

/// Light earlywood to dark latewood and back (mod).
pub const WOOD_KEYS: [Key; 5] = [
    key(0.0, 0xE8B878FF),
    key(0.55, 0xD9A35FFF),
    key(0.78, 0x9A5B2AFF),
    key(0.9, 0x7A4220FF),
    key(1.0, 0xE8B878FF),
];
/// A cross-section of white marble with grey-green veins (mod).
pub const MARBLE_KEYS: [Key; 7] = [
    key(0.0, 0xF2F0EAFF),
    key(0.3, 0xE6E3DAFF),
    key(0.42, 0x8F978CFF),
    key(0.47, 0x3E4A44FF),
    key(0.52, 0x9AA197FF),
    key(0.7, 0xEDEAE2FF),
    key(1.0, 0xF2F0EAFF),
];
/// Clamped blue to white.
pub const CLOUD_KEYS: [Key; 3] = [
    key(0.0, 0x2F62C8FF),
    key(0.45, 0x6E95DCFF),
    key(1.0, 0xFFFFFFFF),
];
/// Clamped blue to black.
pub const WATER_KEYS: [Key; 3] = [
    key(0.0, 0x0A1E3CFF),
    key(0.5, 0x1F4F8CFF),
    key(1.0, 0x000000FF),
];
/// Black, red, orange, yellow, white.
pub const FIRE_KEYS: [Key; 5] = [
    key(0.0, 0xFFFFF0FF),
    key(0.25, 0xFFE040FF),
    key(0.5, 0xF07010FF),
    key(0.75, 0x901008FF),
    key(1.0, 0x000000FF),
];
/// Cartographic legend: deep sea to snow, with a sharp coastline.
pub const PLANET_KEYS: [Key; 10] = [
    key(0.0, 0x08164AFF),
    key(0.35, 0x1A4A9AFF),
    key(0.48, 0x3FA7C9FF),
    key(0.5, 0x3FA7C9FF),
    key(0.502, 0xD8C890FF),
    key(0.55, 0x5C9A3CFF),
    key(0.7, 0x2F6B2AFF),
    key(0.82, 0x7A5A3AFF),
    key(0.92, 0x9A9A9AFF),
    key(1.0, 0xFFFFFFFF),
];
/// Clear to 85% opaque white.
pub const PLANET_CLOUD_KEYS: [Key; 3] = [
    key(0.0, 0xFFFFFF00),
    key(0.45, 0xFFFFFF00),
    key(1.0, 0xFFFFFFD9),
];
/// Zebra: white below 1/2, black above: with N = 256, entries 0..127 white and 128..255 black
/// (keys at the centres of entries 127 and 128, so the step falls between them).
pub const ZEBRA_KEYS: [Key; 4] = [
    key(0.0, 0xFFFFFFFF),
    key(127.5 / 256.0, 0xFFFFFFFF),
    key(128.5 / 256.0, 0x000000FF),
    key(1.0, 0x000000FF),
];

fn e(v: f64) -> MatrixEntry {
    MatrixEntry::checked_from_num(v).unwrap_or(MatrixEntry::ZERO)
}

fn q(c: [f64; 10]) -> Quadric {
    let mut out = [QuadricCoeff::ZERO; 10];
    for (o, v) in out.iter_mut().zip(c) {
        *o = QuadricCoeff::checked_from_num(v).unwrap_or(QuadricCoeff::ZERO);
    }
    Quadric::from_coefficients(out)
}

fn fbm(
    quadric: Quadric,
    wrap: TableWrap,
    count: u8,
    amplitude: f64,
    base: Affine3,
    rotate: bool,
    hash: HashKind,
) -> Result<TextureModel<PRESET_TERMS>, ModelError> {
    TextureModel::new(quadric, wrap).with_octaves(&Octaves {
        count,
        base,
        amplitude: Amplitude::checked_from_num(amplitude).unwrap_or(Amplitude::ZERO),
        rotate,
        basis: NoiseBasis::trilinear(hash),
        turbulence: false,
    })
}

/// `f = s^2 + t^2 + n(4s, 4t, r)`, checked on `[-3, 3]^2`.
pub fn wood(hash: HashKind) -> Preset {
    let model = TextureModel::new(
        q([1.0, 0., 0., 0., 1.0, 0., 0., 0., 0., 0.]),
        TableWrap::Mod,
    )
    .with(NoiseTerm::new(
        Amplitude::ONE,
        Affine3::scale3(e(4.0), e(4.0), e(1.0)),
        NoiseBasis::trilinear(hash),
    ))
    .unwrap_or_else(|_| unreachable_model());
    Preset {
        name: "wood",
        model,
        keys: &WOOD_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: CheckPlane {
            origin: [-3 << 16, -3 << 16, 32768],
            step_x: [1536, 0, 0],
            step_y: [0, 1536, 0],
        },
    }
}

/// `f = r + sum_{i<4} 2^-i n(2^i s)`, checked on the `(s, r)` square `[0, 2]^2`.
pub fn marble(hash: HashKind) -> Preset {
    let model = fbm(
        q([0., 0., 0., 0., 0., 0., 0., 0., 0.5, 0.]),
        TableWrap::Mod,
        4,
        1.0,
        Affine3::IDENTITY,
        false,
        hash,
    )
    .unwrap_or_else(|_| unreachable_model());
    Preset {
        name: "marble",
        model,
        keys: &MARBLE_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: CheckPlane {
            origin: [0, 32768, 0],
            step_x: [512, 0, 0],
            step_y: [0, 0, 512],
        },
    }
}

fn cloud_model(hash: HashKind) -> TextureModel<PRESET_TERMS> {
    fbm(
        q([0., 0., 0., 0., 0., 0., 0., 0., 0., 0.45]),
        TableWrap::Clamp,
        4,
        0.6,
        Affine3::scale(e(2.0)),
        false,
        hash,
    )
    .unwrap_or_else(|_| unreachable_model())
}

/// Clouds: a clamped 1/f sum of four octaves, blue to white.
pub fn clouds(hash: HashKind) -> Preset {
    Preset {
        name: "clouds",
        model: cloud_model(hash),
        keys: &CLOUD_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: UNIT_PLANE,
    }
}

/// Water: the cloud texture with a blue-to-black table.
pub fn water(hash: HashKind) -> Preset {
    Preset {
        name: "water",
        model: cloud_model(hash),
        keys: &WATER_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: UNIT_PLANE,
    }
}

/// Fire: `f = t + 0.8 sum_{i<4} 2^-i n(2^i (s, t - phase, r))`, animated by `phase` (raw 16.16).
pub fn fire(hash: HashKind, phase: i32) -> Preset {
    let mut model = fbm(
        q([0., 0., 0., 0., 0., 0., 0.5, 0., 0., 0.]),
        TableWrap::Clamp,
        4,
        0.8,
        Affine3::scale(e(3.0)),
        false,
        hash,
    )
    .unwrap_or_else(|_| unreachable_model());
    set_fire_phase(&mut model, phase);
    Preset {
        name: "fire",
        model,
        keys: &FIRE_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: CheckPlane {
            origin: [0, 0, 32768],
            step_x: [256, 0, 0],
            step_y: [0, 256, 0],
        },
    }
}

/// Moves the fire's noise by `phase` along `t` (raw 16.16): octave `i` is translated by
/// `-2^i * 3 * phase` in its lattice space.
pub fn set_fire_phase(model: &mut TextureModel<PRESET_TERMS>, phase: i32) {
    for k in 0..model.terms().len() {
        let scale = model.terms()[k].transform.matrix()[1][1].to_bits();
        let shift = -((i64::from(scale) * i64::from(phase)) >> 16);
        let shift = shift.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32;
        let t = [
            MatrixEntry::ZERO,
            MatrixEntry::from_bits(shift),
            MatrixEntry::ZERO,
        ];
        // Every index exists, so this cannot fail.
        let _ = model.set_translation(k, t);
    }
}

/// Planet surface: six octaves on a sphere, cartographic legend.
pub fn planet(hash: HashKind) -> Preset {
    let model = fbm(
        q([0., 0., 0., 0., 0., 0., 0., 0., 0., 0.5]),
        TableWrap::Clamp,
        6,
        0.7,
        Affine3::scale(e(1.5)),
        true,
        hash,
    )
    .unwrap_or_else(|_| unreachable_model());
    Preset {
        name: "planet",
        model,
        keys: &PLANET_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: CheckPlane {
            origin: [-2 << 16, -2 << 16, 0],
            step_x: [1024, 0, 0],
            step_y: [0, 1024, 0],
        },
    }
}

/// The planet's cloud layer, rendered over it with alpha.
pub fn planet_clouds(hash: HashKind) -> Preset {
    let model = fbm(
        q([0., 0., 0., 0., 0., 0., 0., 0., 0., 0.35]),
        TableWrap::Clamp,
        5,
        0.8,
        Affine3::scale(e(2.5)).with_translation([e(17.0), e(3.0), e(-5.0)]),
        true,
        hash,
    )
    .unwrap_or_else(|_| unreachable_model());
    Preset {
        name: "planet-clouds",
        model,
        keys: &PLANET_CLOUD_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: CheckPlane {
            origin: [-2 << 16, -2 << 16, 0],
            step_x: [1024, 0, 0],
            step_y: [0, 1024, 0],
        },
    }
}

/// The zone plate `f = 50 s^2 + 50 t^2` with the zebra table, on the unit square.
pub fn zoneplate() -> Preset {
    Preset {
        name: "zoneplate",
        model: TextureModel::new(
            q([50.0, 0., 0., 0., 50.0, 0., 0., 0., 0., 0.]),
            TableWrap::Mod,
        ),
        keys: &ZEBRA_KEYS,
        table_size: 256,
        squared_keys: false,
        plane: UNIT_PLANE,
    }
}

/// A model that cannot fail to build was asked to fail: return an empty one instead of panicking.
fn unreachable_model() -> TextureModel<PRESET_TERMS> {
    TextureModel::new(Quadric::ZERO, TableWrap::Clamp)
}

/// A preset by name (`fire` at phase 0). `None` for unknown names and for the perturbed
/// materials, which are `crate::material` values (see `mn_marble`, `mn_wood`; feature
/// `perturb`).
pub fn by_name(name: &str, hash: HashKind) -> Option<Preset> {
    Some(match name {
        "wood" => wood(hash),
        "marble" => marble(hash),
        "clouds" => clouds(hash),
        "water" => water(hash),
        "fire" => fire(hash, 0),
        "planet" => planet(hash),
        "planet-clouds" => planet_clouds(hash),
        "zoneplate" => zoneplate(),
        _ => return None,
    })
}

/// The check plane of the perturbed materials: the `(s, r)` square `[-1, 1]^2` at `t = -1`.
pub const PERTURBED_PLANE: CheckPlane = CheckPlane {
    origin: [-65536, -65536, -65536],
    step_x: [512, 0, 0],
    step_y: [0, 0, 512],
};

/// A perturbed-material preset: parameters, colour keys, table wrap and key spacing.
#[cfg(feature = "perturb")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PerturbedPreset {
    /// Name (`mn-marble`, `mn-wood`).
    pub name: &'static str,
    /// The material's parameters.
    pub params: crate::material::PerturbedParams,
    /// Key colours of the colour table.
    pub keys: &'static [Key],
    /// Colour-table wrap of `f`.
    pub wrap: TableWrap,
    /// Whether the keys are placed at `c^2` (wood without a square root).
    pub squared_keys: bool,
    /// The check plane for a 256x256 image ([`PERTURBED_PLANE`]).
    pub plane: CheckPlane,
}

/// The perturbed-material preset `name` (`mn-marble`, `mn-wood`), `None` for other names.
#[cfg(feature = "perturb")]
pub fn perturbed_by_name(name: &str, hash: HashKind) -> Option<PerturbedPreset> {
    let (name, params, keys, wrap, squared_keys): (_, _, &'static [Key], _, _) = match name {
        "mn-marble" => (
            "mn-marble",
            mn_marble(hash),
            &MARBLE_KEYS,
            TableWrap::Mod,
            false,
        ),
        "mn-wood" => ("mn-wood", mn_wood(hash), &WOOD_KEYS, TableWrap::Clamp, true),
        _ => return None,
    };
    Some(PerturbedPreset {
        name,
        params,
        keys,
        wrap,
        squared_keys,
        plane: PERTURBED_PLANE,
    })
}

/// Miné & Neyret's marble: planes `x[0]` perturbed by 4-octave vector turbulence.
#[cfg(feature = "perturb")]
pub fn mn_marble(hash: HashKind) -> crate::material::PerturbedParams {
    use crate::material::{Characteristic, PerturbedParams};
    PerturbedParams {
        t1: Affine3::scale(e(2.0)),
        t3: Affine3::scale(e(3.0)),
        alpha: [Amplitude::checked_from_num(0.6).unwrap_or(Amplitude::ZERO); 3],
        octaves: 4,
        rotate: true,
        basis: NoiseBasis::trilinear(hash),
        characteristic: Characteristic::Planes,
    }
}

/// Miné & Neyret's wood: cylinders `x[0]^2 + x[2]^2` perturbed by turbulence, 8 rings, colour keys
/// at `c^2`.
#[cfg(feature = "perturb")]
pub fn mn_wood(hash: HashKind) -> crate::material::PerturbedParams {
    use crate::material::{Characteristic, PerturbedParams};
    PerturbedParams {
        t1: Affine3::scale(e(4.0)),
        t3: Affine3::scale3(e(1.0), e(6.0), e(1.0)),
        alpha: [Amplitude::checked_from_num(0.25).unwrap_or(Amplitude::ZERO); 3],
        octaves: 3,
        rotate: true,
        basis: NoiseBasis::trilinear(hash),
        characteristic: Characteristic::Cylinders { rings: 8 },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_named_presets_build() {
        for name in NAMES {
            if name.starts_with("mn-") {
                continue;
            }
            let p = by_name(name, HashKind::default()).unwrap();
            assert_eq!(p.name, name);
            assert!(
                p.keys.windows(2).all(|w| w[0].0 <= w[1].0),
                "{name} keys sorted"
            );
            assert!(p.table_size.is_power_of_two());
        }
        assert!(by_name("nope", HashKind::default()).is_none());
    }

    #[test]
    fn paper_formulas() {
        let w = wood(HashKind::default());
        assert_eq!(w.model.terms().len(), 1);
        assert_eq!(w.model.quadric().coefficients()[0], QuadricCoeff::ONE);
        let m = marble(HashKind::default());
        assert_eq!(m.model.terms().len(), 4);
        assert_eq!(m.model.terms()[3].amplitude.to_bits(), 65536 >> 3);
        let z = zoneplate();
        assert!(z.model.terms().is_empty());
        // The zebra table: entries 0..127 white, 128..255 black.
        let keys: heapless::Vec<_, 8> = z
            .keys
            .iter()
            .map(|(p, c)| {
                (
                    crate::format::TexValue::from_bits(*p as i32),
                    crate::color::Rgba8888::from_array(*c),
                )
            })
            .collect();
        let t = crate::table::ColorTable::<256>::from_keys(&keys).unwrap();
        assert_eq!(
            t.entries(),
            crate::table::ColorTable::<256>::zebra().unwrap().entries()
        );
        assert_eq!(
            z.model.quadric().coefficients()[4],
            QuadricCoeff::from_num(50)
        );
    }

    #[test]
    fn fire_phase_moves_noise() {
        let f0 = fire(HashKind::default(), 0);
        let f1 = fire(HashKind::default(), 65536 / 4);
        assert_ne!(f0.model.terms()[0].transform, f1.model.terms()[0].transform);
        // octave 0 has scale 3: shift -3/4 in t
        assert_eq!(
            f1.model.terms()[0].transform.translation()[1].to_bits(),
            -(3 * 65536 / 4)
        );
    }
}
