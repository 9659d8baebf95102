//! A scene's lights: the per-vertex light of every emitted triangle, for the renderer's lighting
//! stage ([`crate::gouraud`]).
//!
//! Guarantees:
//! - A scene without lights is walked exactly as before ([`Scene::is_lit`] is false and the
//!   renderer takes the unlit walk, which computes no normal and no light).
//! - Normals: [`crate::light::analytic_normal`] of the object's mesh at each quad corner
//!   (object space); the teapot and loaded (packed) meshes, which have no closed form, take
//!   their quad's face normal (faceted). Normals go to world space through the object's linear part and are
//!   renormalised (exact directions for rotations and uniform scales). Lighting is two-sided:
//!   a normal facing away from the eye is flipped, so a mesh's winding does not matter.
//! - Integer only: the same lights on every target. A triangle cut by the near, far or
//!   guard-band planes is lit flat with the mean of its three input corners' lights.

use super::{CornerValue, Object, Scene, SceneError, Vec3, MAX_LIGHTS};
use crate::light::{analytic_normal, face_normal, LightRgb, Lighting};

impl Scene {
    /// The scene's lighting.
    pub fn lighting(&self) -> &Lighting<MAX_LIGHTS> {
        &self.lighting
    }

    /// Sets the scene's lighting (ambient, lights, specular).
    pub fn set_lighting(&mut self, lighting: Lighting<MAX_LIGHTS>) {
        self.lighting = lighting;
    }

    /// Adds a light; [`SceneError::TooManyLights`] when the scene has [`MAX_LIGHTS`] (the
    /// scene is then unchanged).
    pub fn add_light(&mut self, light: crate::light::Light) -> Result<(), SceneError> {
        self.lighting
            .try_add(light)
            .map_err(|_| SceneError::TooManyLights)
    }

    /// Whether the scene has lights (the renderer runs its lighting stage only then).
    pub fn is_lit(&self) -> bool {
        self.lighting.is_lit()
    }

    /// [`Scene::for_each_triangle_by_quad`] with a function giving each emitted vertex's light
    /// (`Q16.16` per channel in `[0, ONE]`, see [`Lighting::shade`]), computed when asked for
    /// (each quad corner at most once per walk).
    pub fn for_each_lit_triangle_by_quad<K, F>(
        &self,
        keep: &mut K,
        f: &mut F,
    ) -> super::SceneCounters
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[crate::raster::ScreenVertex; 3], &dyn Fn() -> [LightRgb; 3]),
    {
        let corner = SceneLight {
            lighting: &self.lighting,
            eye: self.camera.eye,
        };
        self.walk_quads::<K, _, _, { super::corners::BAND_WALK_SLOTS }>(keep, f, &corner, true)
    }
}

/// The light of quad corners.
struct SceneLight<'a> {
    lighting: &'a Lighting<MAX_LIGHTS>,
    eye: Vec3,
}

impl CornerValue for SceneLight<'_> {
    type Value = LightRgb;

    fn at(&self, o: &Object, corners: &[Vec3; 4], i: usize) -> LightRgb {
        let p = corners[i & 3];
        let world = o.transform.saturating_apply(p);
        let n = analytic_normal(&o.mesh, p)
            .or_else(|| face_normal(corners[0], corners[1], corners[2]))
            .or_else(|| face_normal(corners[0], corners[2], corners[3]))
            .map(|n| o.transform.saturating_apply_vector(n))
            .and_then(Vec3::normalized)
            .unwrap_or(Vec3::ZERO);
        let n = if i64::from(n.dot(self.eye.sub(world))) < 0 {
            Vec3::ZERO.sub(n)
        } else {
            n
        };
        self.lighting.shade(world, n, self.eye)
    }

    fn mean(v: [LightRgb; 3]) -> LightRgb {
        core::array::from_fn(|c| {
            let s: i64 = v.iter().map(|l| i64::from(l[c])).sum();
            (s / 3) as i32
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::super::{by_name, Camera, Mesh, Object, Scene, Vec3};
    use super::*;
    use crate::light::Light;
    use crate::scene::math::ONE;
    use std::vec::Vec;

    fn lit_sphere() -> Scene {
        let cam = Camera::perspective(
            Vec3::units(0, 0, 4),
            Vec3::ZERO,
            Vec3::Y,
            super::super::focal_from_fov(super::super::Angle::from_degrees(45)),
            ONE / 4,
            100 * ONE,
            64,
            64,
        );
        let mut s = Scene::new("lit", cam);
        s.add(Object::new(Mesh::Sphere {
            radius: ONE,
            stacks: 8,
            slices: 12,
        }))
        .unwrap();
        s.add_light(Light::directional(Vec3::new(-ONE, ONE, ONE), [ONE; 3], ONE).unwrap())
            .unwrap();
        s
    }

    /// The lit walk emits exactly the unlit walk's triangles, with lights that vary over a
    /// sphere (not a flat disc), in `[0, ONE]`.
    #[test]
    fn lit_walk_is_the_walk_plus_light() {
        let s = lit_sphere();
        assert!(s.is_lit());
        let mut plain = Vec::new();
        let c0 = s.for_each_triangle_static(&mut |o, t| plain.push((o, *t)));
        let mut lit = Vec::new();
        let mut lights = Vec::new();
        let c1 = s.for_each_lit_triangle_by_quad(&mut |_| true, &mut |_, o, t, l| {
            lit.push((o, *t));
            lights.push(l());
        });
        assert_eq!(c0, c1);
        assert_eq!(plain, lit);
        let flat: Vec<i32> = lights.iter().flatten().map(|l| l[0]).collect();
        assert!(flat.iter().all(|&l| (0..=ONE).contains(&l)));
        let (lo, hi) = (flat.iter().min().unwrap(), flat.iter().max().unwrap());
        assert!(*hi > ONE * 9 / 10 && *lo < ONE / 10, "{lo} {hi}");
    }

    #[test]
    fn builtin_scenes_are_unlit_and_full_scenes_refuse_lights() {
        for name in super::super::BUILTIN {
            assert!(!by_name(name).unwrap().is_lit(), "{name}");
        }
        let mut s = lit_sphere();
        let l = *s.lighting().lights().first().unwrap();
        for _ in 1..MAX_LIGHTS {
            s.add_light(l).unwrap();
        }
        assert_eq!(s.add_light(l), Err(SceneError::TooManyLights));
        assert_eq!(s.lighting().lights().len(), MAX_LIGHTS);
    }

    /// The teapot (no closed-form normal) is lit with face normals, two-sided.
    #[test]
    fn teapot_is_lit() {
        let mut s = by_name("marble").unwrap();
        s.add_light(Light::directional(Vec3::new(0, ONE, ONE), [ONE; 3], ONE).unwrap())
            .unwrap();
        let mut n = 0;
        let mut bright = 0;
        s.for_each_lit_triangle_by_quad(&mut |_| true, &mut |_, _, _, l| {
            n += 1;
            bright += usize::from(l()[0][0] > ONE / 2);
        });
        assert!(n > 100 && bright > n / 4, "{bright} of {n}");
    }
}
