//! Per-vertex (Gouraud) lighting in exact integer arithmetic: ambient + Lambert diffuse +
//! optional Blinn-Phong specular from directional and point lights, and the colour modulation
//! that multiplies a texture colour by the interpolated light.
//!
//! Guarantees:
//! - No floating point: every result is a pure function of its `Q16.16` inputs, so the host and
//!   the device produce the same bits.
//! - Capacity in the type: a [`Lighting<N>`] holds at most `N` lights, checked by
//!   [`Lighting::try_add`] (an error value, never a silent drop); evaluation never panics.
//! - Light per channel is `Q16.16` clamped to `[0, ONE]` (`ONE` = full texture colour); a normal
//!   facing a white light of intensity `ONE` with no ambient gives exactly `ONE`, a normal facing
//!   away gives exactly the ambient term.
//! - Normals: [`analytic_normal`] gives the exact-direction normal of the procedural meshes whose
//!   surface has a closed form (sphere, torus, cube, quad, plane); [`smooth_normals`] averages
//!   face normals for meshes given as positions + triangle indices (loaded meshes).

use crate::scene::math::{mul_q16, Vec3, ONE};
use crate::scene::Mesh;
use core::fmt;

/// A linear RGB light colour, each channel `Q16.16` (`ONE` = full).
pub type LightRgb = [i32; 3];

/// What a light is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LightKind {
    /// Parallel light arriving from `direction` (the unit vector *towards* the light).
    Directional {
        /// Unit vector towards the light, `Q16.16`.
        direction: Vec3,
    },
    /// Light from a point (no distance attenuation).
    Point {
        /// World position, `Q16.16`.
        position: Vec3,
    },
}

/// One light: kind, colour and intensity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Light {
    kind: LightKind,
    color: LightRgb,
}

/// Why a light or lighting set-up was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LightError {
    /// A directional light with a zero direction.
    ZeroDirection,
    /// A colour channel or intensity outside `[0, 16]` units.
    OutOfRange,
    /// More lights than the set-up's capacity.
    Full,
    /// Normals: an index past the end of the positions, or output of the wrong length.
    BadMesh,
}

impl fmt::Display for LightError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LightError::ZeroDirection => "a directional light needs a non-zero direction",
            LightError::OutOfRange => "light colour and intensity must lie in [0, 16]",
            LightError::Full => "too many lights for this scene's capacity",
            LightError::BadMesh => "normals: a vertex index is out of range or the output length differs from the positions'",
        })
    }
}

const MAX_LEVEL: i32 = 16 * ONE;

const fn in_range(v: i32) -> bool {
    v >= 0 && v <= MAX_LEVEL
}

impl Light {
    /// A directional light towards `direction` (normalised here), colour `color` scaled by
    /// `intensity` (all `Q16.16`, in `[0, 16]`).
    pub fn directional(
        direction: Vec3,
        color: LightRgb,
        intensity: i32,
    ) -> Result<Light, LightError> {
        let direction = direction.normalized().ok_or(LightError::ZeroDirection)?;
        Light::checked(LightKind::Directional { direction }, color, intensity)
    }

    /// A point light at `position`, colour `color` scaled by `intensity`.
    pub fn point(position: Vec3, color: LightRgb, intensity: i32) -> Result<Light, LightError> {
        Light::checked(LightKind::Point { position }, color, intensity)
    }

    fn checked(kind: LightKind, color: LightRgb, intensity: i32) -> Result<Light, LightError> {
        if !in_range(intensity) || !color.iter().all(|&c| in_range(c)) {
            return Err(LightError::OutOfRange);
        }
        let color = color.map(|c| mul_q16(c, intensity));
        Ok(Light { kind, color })
    }

    /// The kind (with its normalised direction or position).
    pub const fn kind(&self) -> LightKind {
        self.kind
    }

    /// The colour times the intensity, `Q16.16` per channel.
    pub const fn color(&self) -> LightRgb {
        self.color
    }

    /// The unit vector from `p` towards the light, or `None` at the light's own position.
    pub fn direction_from(&self, p: Vec3) -> Option<Vec3> {
        match self.kind {
            LightKind::Directional { direction } => Some(direction),
            LightKind::Point { position } => position.sub(p).normalized_rt(),
        }
    }
}

/// A scene's lighting: ambient colour, up to `N` lights, optional Blinn-Phong specular.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lighting<const N: usize> {
    ambient: LightRgb,
    lights: heapless::Vec<Light, N>,
    specular_exponent: u8,
    specular_strength: i32,
}

impl<const N: usize> Default for Lighting<N> {
    fn default() -> Self {
        Lighting::new()
    }
}

impl<const N: usize> Lighting<N> {
    /// No lights, no ambient, no specular.
    pub const fn new() -> Self {
        Lighting {
            ambient: [0; 3],
            lights: heapless::Vec::new(),
            specular_exponent: 0,
            specular_strength: 0,
        }
    }

    /// Sets the ambient colour (`Q16.16`, each in `[0, 16]`).
    pub fn with_ambient(mut self, ambient: LightRgb) -> Result<Self, LightError> {
        if !ambient.iter().all(|&c| in_range(c)) {
            return Err(LightError::OutOfRange);
        }
        self.ambient = ambient;
        Ok(self)
    }

    /// Enables Blinn-Phong specular `strength (n.h)^exponent` (exponent `0` disables it).
    pub fn with_specular(mut self, exponent: u8, strength: i32) -> Result<Self, LightError> {
        if !in_range(strength) {
            return Err(LightError::OutOfRange);
        }
        self.specular_exponent = exponent;
        self.specular_strength = strength;
        Ok(self)
    }

    /// Adds a light, or [`LightError::Full`] when `N` are already there.
    pub fn try_add(&mut self, light: Light) -> Result<(), LightError> {
        self.lights.push(light).map_err(|_| LightError::Full)
    }

    /// The lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The ambient colour.
    pub const fn ambient(&self) -> LightRgb {
        self.ambient
    }

    /// The specular exponent (0: no specular).
    pub const fn specular_exponent(&self) -> u8 {
        self.specular_exponent
    }

    /// Whether a scene with this set-up needs any lighting work (false: no lights).
    pub fn is_lit(&self) -> bool {
        !self.lights.is_empty()
    }

    /// The light reaching a vertex at `p` with unit normal `n`, seen from `eye`: ambient +
    /// `sum(color max(0, n.l))` + specular, each channel clamped to `[0, ONE]`.
    pub fn shade(&self, p: Vec3, n: Vec3, eye: Vec3) -> LightRgb {
        let mut acc = [
            self.ambient[0] as i64,
            self.ambient[1] as i64,
            self.ambient[2] as i64,
        ];
        let view = eye.sub(p).normalized_rt();
        for light in self.lights.iter() {
            let Some(l) = light.direction_from(p) else {
                continue;
            };
            let diffuse = n.dot(l);
            if diffuse <= 0 {
                continue;
            }
            let mut k = diffuse as i64;
            if self.specular_exponent > 0 {
                if let Some(h) = view.and_then(|v| l.add(v).normalized_rt()) {
                    let s = pow_q16(n.dot(h).max(0), self.specular_exponent);
                    k += mul_q16(s, self.specular_strength) as i64;
                }
            }
            for (a, c) in acc.iter_mut().zip(light.color.iter()) {
                *a += (k * *c as i64 + (1 << 15)) >> 16;
            }
        }
        acc.map(|a| a.clamp(0, ONE as i64) as i32)
    }
}

/// `x^e` for `x` in `[0, ONE]` (`Q16.16`) by repeated squaring, rounded at each step.
pub const fn pow_q16(x: i32, mut e: u8) -> i32 {
    let mut base = x;
    let mut r = ONE;
    while e > 0 {
        if e & 1 == 1 {
            r = mul_q16(r, base);
        }
        base = mul_q16(base, base);
        e >>= 1;
    }
    r
}

/// A texture colour channel times a light channel (`Q16.16` in `[0, ONE]`), rounded.
pub const fn modulate_channel(c: u8, light: i32) -> u8 {
    let l = if light < 0 {
        0
    } else if light > ONE {
        ONE
    } else {
        light
    };
    ((c as i64 * l as i64 + (1 << 15)) >> 16) as u8
}

/// An RGB colour modulated by a light: the colour-modulation stage after the colour table.
pub const fn modulate(rgb: [u8; 3], light: LightRgb) -> [u8; 3] {
    [
        modulate_channel(rgb[0], light[0]),
        modulate_channel(rgb[1], light[1]),
        modulate_channel(rgb[2], light[2]),
    ]
}

/// The outward unit normal of a procedural mesh at an object-space surface point `p`, for the
/// meshes with a closed-form surface; `None` for the teapot and loaded (packed) meshes (use
/// [`smooth_normals`] on their vertices, or the face normals the scene walk falls back to) and for degenerate points (a sphere's centre, a torus's axis).
pub fn analytic_normal(mesh: &Mesh, p: Vec3) -> Option<Vec3> {
    match *mesh {
        Mesh::Sphere { .. } => p.normalized_rt(),
        Mesh::Torus { major, .. } => {
            let radial = Vec3::new(p.x, 0, p.z).normalized_rt()?;
            p.sub(radial.scale(major)).normalized_rt()
        }
        Mesh::Cube { .. } => {
            let (ax, ay, az) = (p.x.unsigned_abs(), p.y.unsigned_abs(), p.z.unsigned_abs());
            Some(if ax >= ay && ax >= az {
                Vec3::new(ONE * p.x.signum(), 0, 0)
            } else if ay >= az {
                Vec3::new(0, ONE * p.y.signum(), 0)
            } else {
                Vec3::new(0, 0, ONE * p.z.signum())
            })
        }
        Mesh::Plane { .. } => Some(Vec3::Y),
        Mesh::Quad { corners } => corners[1]
            .sub(corners[0])
            .cross(corners[3].sub(corners[0]))
            .normalized_rt(),
        Mesh::Teapot { .. } => None,
        #[cfg(feature = "atlas")]
        Mesh::Packed(_) => None,
    }
}

/// Smooth per-vertex normals of a triangle mesh: each vertex's normal is the normalised sum of
/// the unit normals of the (counter-clockwise) triangles that use it; a vertex used by no
/// non-degenerate triangle gets the zero vector. `out` must have the length of `positions`.
pub fn smooth_normals(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    out: &mut [Vec3],
) -> Result<(), LightError> {
    if out.len() != positions.len() {
        return Err(LightError::BadMesh);
    }
    let n = positions.len();
    if triangles.iter().flatten().any(|&i| i as usize >= n) {
        return Err(LightError::BadMesh);
    }
    out.fill(Vec3::ZERO);
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let Some(face) = face_normal(a, b, c) else {
            continue;
        };
        for &i in t {
            out[i as usize] = out[i as usize].add(face);
        }
    }
    for v in out.iter_mut() {
        *v = v.normalized_rt().unwrap_or(Vec3::ZERO);
    }
    Ok(())
}

/// The unit normal of a counter-clockwise triangle, computed exactly in wide arithmetic (so
/// small triangles do not round to zero), or `None` when it is degenerate.
pub(crate) fn face_normal(a: Vec3, b: Vec3, c: Vec3) -> Option<Vec3> {
    let u = [(b.x - a.x) as i64, (b.y - a.y) as i64, (b.z - a.z) as i64];
    let v = [(c.x - a.x) as i64, (c.y - a.y) as i64, (c.z - a.z) as i64];
    let w = [
        u[1] as i128 * v[2] as i128 - u[2] as i128 * v[1] as i128,
        u[2] as i128 * v[0] as i128 - u[0] as i128 * v[2] as i128,
        u[0] as i128 * v[1] as i128 - u[1] as i128 * v[0] as i128,
    ];
    let m = w.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
    if m == 0 {
        return None;
    }
    // Shift into i32 range keeping ~30 bits of direction, then normalise.
    let bits = 128 - m.leading_zeros();
    let s = bits.saturating_sub(30);
    Vec3::new((w[0] >> s) as i32, (w[1] >> s) as i32, (w[2] >> s) as i32).normalized_rt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::math::Vec3;

    const WHITE: LightRgb = [ONE; 3];

    fn sun(dir: Vec3) -> Lighting<2> {
        let mut l = Lighting::<2>::new();
        l.try_add(Light::directional(dir, WHITE, ONE).unwrap())
            .unwrap();
        l
    }

    #[test]
    fn normal_facing_the_light_is_full() {
        let l = sun(Vec3::Z);
        assert_eq!(l.shade(Vec3::ZERO, Vec3::Z, Vec3::units(0, 0, 5)), [ONE; 3]);
    }

    #[test]
    fn facing_away_is_ambient_only() {
        let amb = [ONE / 5, ONE / 4, ONE / 3];
        let l = sun(Vec3::Z).with_ambient(amb).unwrap();
        assert_eq!(
            l.shade(Vec3::ZERO, Vec3::new(0, 0, -ONE), Vec3::units(0, 0, 5)),
            amb
        );
        // Grazing (perpendicular) too.
        assert_eq!(l.shade(Vec3::ZERO, Vec3::X, Vec3::units(0, 0, 5)), amb);
    }

    #[test]
    fn lambert_is_the_cosine() {
        let l = sun(Vec3::new(0, ONE, ONE));
        let s = l.shade(Vec3::ZERO, Vec3::Y, Vec3::units(0, 0, 5));
        // cos 45 deg = 0.70710678 -> 46341 in Q16.16.
        assert!((s[0] - 46341).abs() <= 2, "{s:?}");
    }

    #[test]
    fn specular_peaks_at_the_half_vector() {
        let l = sun(Vec3::new(0, ONE, ONE))
            .with_ambient([0; 3])
            .unwrap()
            .with_specular(32, ONE / 2)
            .unwrap();
        let eye = Vec3::units(0, 0, 10);
        // Normal along the half vector of light (0,1,1) and view (0,0,1).
        let h = Vec3::new(0, ONE, ONE)
            .normalized()
            .unwrap()
            .add(Vec3::Z)
            .normalized()
            .unwrap();
        let peak = l.shade(Vec3::ZERO, h, eye)[0];
        let off = l.shade(
            Vec3::ZERO,
            Vec3::new(0, ONE, ONE / 2).normalized().unwrap(),
            eye,
        )[0];
        let diffuse_only = sun(Vec3::new(0, ONE, ONE)).shade(Vec3::ZERO, h, eye)[0];
        assert_eq!(peak, ONE.min(diffuse_only + ONE / 2));
        assert!(off < peak);
        assert_eq!(pow_q16(ONE, 200), ONE);
        assert_eq!(pow_q16(ONE / 2, 2), ONE / 4);
    }

    #[test]
    fn point_light_direction_and_errors() {
        let p = Light::point(Vec3::units(0, 3, 0), WHITE, ONE).unwrap();
        assert_eq!(p.direction_from(Vec3::ZERO), Some(Vec3::Y));
        assert_eq!(p.direction_from(Vec3::units(0, 3, 0)), None);
        assert_eq!(
            Light::directional(Vec3::ZERO, WHITE, ONE),
            Err(LightError::ZeroDirection)
        );
        assert_eq!(
            Light::directional(Vec3::Z, [-1, 0, 0], ONE),
            Err(LightError::OutOfRange)
        );
        assert_eq!(
            Light::directional(Vec3::Z, WHITE, 17 * ONE),
            Err(LightError::OutOfRange)
        );
        let mut one = Lighting::<1>::new();
        one.try_add(p).unwrap();
        assert_eq!(one.try_add(p), Err(LightError::Full));
        assert!(one.is_lit());
        assert!(!Lighting::<1>::new().is_lit());
    }

    #[test]
    fn modulate_scales_the_colour() {
        assert_eq!(modulate([200, 100, 255], [ONE; 3]), [200, 100, 255]);
        assert_eq!(modulate([200, 100, 255], [0; 3]), [0, 0, 0]);
        assert_eq!(modulate([200, 100, 255], [ONE / 2; 3]), [100, 50, 128]);
    }

    #[test]
    fn sphere_shading_varies_across_the_disc() {
        // A lit sphere seen from +z: light from the upper left, intensity along a horizontal
        // line through the centre must vary (not a flat disc).
        let mesh = Mesh::Sphere {
            radius: ONE,
            stacks: 8,
            slices: 8,
        };
        let l = sun(Vec3::new(-ONE, ONE, ONE))
            .with_ambient([ONE / 10; 3])
            .unwrap();
        let eye = Vec3::units(0, 0, 5);
        let shades: [i32; 5] = core::array::from_fn(|i| {
            let x = (i as i32 - 2) * (ONE / 3);
            let z = crate::scene::math::isqrt_u64(
                (ONE as u64 * ONE as u64) - (x as i64 * x as i64) as u64,
            ) as i32;
            let p = Vec3::new(x, 0, z);
            l.shade(p, analytic_normal(&mesh, p).unwrap(), eye)[0]
        });
        assert!(shades.windows(2).all(|w| w[0] > w[1]), "{shades:?}");
    }

    #[test]
    fn analytic_normals_point_outwards() {
        let torus = Mesh::Torus {
            major: 2 * ONE,
            minor: ONE / 2,
            major_segments: 8,
            minor_segments: 8,
        };
        assert_eq!(
            analytic_normal(&torus, Vec3::new(2 * ONE + ONE / 2, 0, 0)),
            Some(Vec3::X)
        );
        let cube = Mesh::Cube {
            half: ONE,
            divisions: 1,
        };
        assert_eq!(
            analytic_normal(&cube, Vec3::new(ONE / 2, -ONE, 0)),
            Some(Vec3::new(0, -ONE, 0))
        );
        assert_eq!(analytic_normal(&Mesh::Teapot { level: 2 }, Vec3::X), None);
    }

    #[test]
    fn smooth_normals_of_a_tetrahedron_corner_and_bad_input() {
        // A square in z = 0 made of two CCW triangles: every normal is +z.
        let pos = [
            Vec3::units(0, 0, 0),
            Vec3::units(1, 0, 0),
            Vec3::units(1, 1, 0),
            Vec3::units(0, 1, 0),
        ];
        let tris = [[0, 1, 2], [0, 2, 3]];
        let mut out = [Vec3::ZERO; 4];
        smooth_normals(&pos, &tris, &mut out).unwrap();
        assert_eq!(out, [Vec3::Z; 4]);
        // A fold: two faces at right angles share an edge whose normals average to 45 deg.
        let pos = [
            Vec3::units(0, 0, 0),
            Vec3::units(1, 0, 0),
            Vec3::units(0, 1, 0),
            Vec3::units(0, 0, 1),
        ];
        let tris = [[0, 1, 2], [0, 1, 3]];
        let mut out = [Vec3::ZERO; 4];
        smooth_normals(&pos, &tris, &mut out).unwrap();
        assert_eq!(out[2], Vec3::Z);
        assert_eq!(out[3], Vec3::new(0, -ONE, 0));
        assert_eq!(out[0], Vec3::new(0, -ONE, ONE).normalized().unwrap());
        assert_eq!(
            smooth_normals(&pos, &[[0, 1, 9]], &mut out),
            Err(LightError::BadMesh)
        );
        assert_eq!(
            smooth_normals(&pos, &tris, &mut out[..3]),
            Err(LightError::BadMesh)
        );
    }
}
