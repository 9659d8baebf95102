//! Meshes generated in code: every mesh is a grid of quads computed on demand (no storage), walked
//! as an iterator of object-space triangles.
//!
//! Each quad has corners `c00, c10, c11, c01` (parameters `(u, v)`, `(u+1, v)`, `(u+1, v+1)`,
//! `(u, v+1)`) and is split into `(c00, c10, c11)` and `(c00, c11, c01)`. Every mesh is
//! parametrised so that `du x dv` points **outwards**: triangles are counter-clockwise seen from
//! outside (in the right-handed, y-up world of [`super::camera`]), i.e. counter-clockwise on the
//! screen when front-facing, so `CullMode::Clockwise` removes back faces. Triangles with two equal
//! corners (the poles of a sphere, the teapot's lid knob and bottom centre) are skipped.
//!
//! Vertex positions are a pure function of the mesh and the quad index (integer arithmetic only),
//! so a vertex shared by several quads is computed bit-identically by each of them: meshes are
//! watertight, including across seams (angles are exact fractions of a turn, so the last column
//! of a sphere or torus equals the first).

use super::math::{sat_i32, sin_cos, Angle, Vec3, ONE};
use super::teapot::{
    teapot_quad, teapot_right_edge, TeapotRow, MAX_TEAPOT_LEVEL, TEAPOT_PATCH_COUNT,
};

/// A procedural mesh in object space (`Q16.16` sizes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Mesh {
    /// The Utah teapot ([`super::teapot`]: z up, base at `z = 0`), each patch tessellated
    /// `level x level` (`1..=16`; `64 level^2 - 8 level` triangles).
    Teapot {
        /// Tessellation level.
        level: u8,
    },
    /// A latitude/longitude sphere of `radius` about the origin, poles on the y axis
    /// (`2 slices (stacks - 1)` triangles).
    Sphere {
        /// Radius, `Q16.16`.
        radius: i32,
        /// Bands of latitude (at least 2).
        stacks: u16,
        /// Meridian segments (at least 3).
        slices: u16,
    },
    /// A torus about the y axis (lying in the xz plane): tube of radius `minor` around a circle
    /// of radius `major` (`2 major_segments minor_segments` triangles).
    Torus {
        /// Radius of the centre circle, `Q16.16`.
        major: i32,
        /// Radius of the tube, `Q16.16`.
        minor: i32,
        /// Segments around the centre circle (at least 3).
        major_segments: u16,
        /// Segments around the tube (at least 3).
        minor_segments: u16,
    },
    /// An axis-aligned cube `[-half, half]^3`, each face split into `divisions^2` quads
    /// (`12 divisions^2` triangles).
    Cube {
        /// Half the edge length, `Q16.16`.
        half: i32,
        /// Quads along each face edge (at least 1).
        divisions: u8,
    },
    /// One planar (or not) quadrilateral, corners counter-clockwise seen from its front
    /// (2 triangles).
    Quad {
        /// The corners.
        corners: [Vec3; 4],
    },
    /// A large square in the plane `y = 0` facing `+y`, `[-half_size, half_size]^2`, on a grid
    /// whose lines are geometrically spaced away from the centre: line `i` (`-rings..=rings`) is
    /// at `sign(i) half_size (2^|i| - 1) / (2^rings - 1)`. Cells far away are large and cells
    /// near the centre small, so every triangle spans a bounded range of depth and `1/w` when
    /// seen from near the centre (`8 rings^2` triangles). For sea, sky and ground planes that
    /// reach the horizon.
    Plane {
        /// Half the side, `Q16.16`.
        half_size: i32,
        /// Grid lines on each side of the centre (`1..=20`).
        rings: u8,
    },
    /// A triangle mesh from a file ([`crate::packed_mesh`], feature `atlas`): each triangle
    /// `(a, b, c)` is the quad `(a, b, c, c)`, whose second half is degenerate and skipped, so
    /// quad `q` is triangle `q`.
    #[cfg(feature = "atlas")]
    Packed(crate::packed_mesh::PackedMesh<'static>),
}

const MIN_STACKS: u16 = 2;
const MIN_SEGMENTS: u16 = 3;
const MAX_RINGS: u8 = 20;

impl Mesh {
    /// The number of quads (a quad gives at most two triangles).
    pub fn quad_count(&self) -> u32 {
        match *self {
            Mesh::Teapot { level } => {
                let n = level.clamp(1, MAX_TEAPOT_LEVEL) as u32;
                TEAPOT_PATCH_COUNT as u32 * n * n
            }
            Mesh::Sphere { stacks, slices, .. } => {
                stacks.max(MIN_STACKS) as u32 * slices.max(MIN_SEGMENTS) as u32
            }
            Mesh::Torus {
                major_segments,
                minor_segments,
                ..
            } => major_segments.max(MIN_SEGMENTS) as u32 * minor_segments.max(MIN_SEGMENTS) as u32,
            Mesh::Cube { divisions, .. } => {
                let d = divisions.max(1) as u32;
                6 * d * d
            }
            Mesh::Quad { .. } => 1,
            Mesh::Plane { rings, .. } => {
                let r = rings.clamp(1, MAX_RINGS) as u32;
                4 * r * r
            }
            #[cfg(feature = "atlas")]
            Mesh::Packed(m) => m.triangle_count() as u32,
        }
    }

    /// The exact number of triangles the mesh yields (quads minus degenerate halves).
    pub fn triangle_count(&self) -> u32 {
        self.triangles().count() as u32
    }

    /// The corners `[c00, c10, c11, c01]` of quad `q` (`None` past the end).
    pub fn quad(&self, q: u32) -> Option<[Vec3; 4]> {
        if q >= self.quad_count() {
            return None;
        }
        Some(match *self {
            Mesh::Teapot { level } => {
                let n = level.clamp(1, MAX_TEAPOT_LEVEL) as u32;
                let (patch, r) = divrem(q, n * n);
                let (l, k) = divrem(r, n);
                teapot_quad(patch as usize, n, k, l)
            }
            Mesh::Sphere {
                radius,
                stacks,
                slices,
            } => {
                let (st, sl) = (
                    stacks.max(MIN_STACKS) as u32,
                    slices.max(MIN_SEGMENTS) as u32,
                );
                let (j, i) = divrem(q, sl);
                // Longitude i / slices turn, latitude j / (2 stacks) turn from the north pole.
                let ph = [i, i + 1].map(|i| sin_cos(Angle::from_turns_rt(i, sl)));
                let th = [j, j + 1].map(|j| sin_cos(Angle::from_turns_rt(j, 2 * st)));
                let p = |a: usize, b: usize| sphere_point(radius, ph[a], th[b]);
                [p(0, 0), p(1, 0), p(1, 1), p(0, 1)]
            }
            Mesh::Torus {
                major,
                minor,
                major_segments,
                minor_segments,
            } => {
                let (nu, nv) = (
                    major_segments.max(MIN_SEGMENTS) as u32,
                    minor_segments.max(MIN_SEGMENTS) as u32,
                );
                let (j, i) = divrem(q, nu);
                // Around the centre circle i / nu turn, around the tube j / nv turn.
                let ph = [i, i + 1].map(|i| sin_cos(Angle::from_turns_rt(i, nu)));
                let th = [j, j + 1].map(|j| sin_cos(Angle::from_turns_rt(j, nv)));
                let p = |a: usize, b: usize| torus_point(major, minor, ph[a], th[b]);
                [p(0, 0), p(1, 0), p(1, 1), p(0, 1)]
            }
            Mesh::Cube { half, divisions } => {
                let d = divisions.max(1) as u32;
                let (face, r) = divrem(q, d * d);
                let (j, i) = divrem(r, d);
                let face = face as usize;
                let p = |i: u32, j: u32| cube_point(half, d, face, i, j);
                [p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]
            }
            Mesh::Quad { corners } => corners,
            Mesh::Plane { half_size, rings } => {
                let r = rings.clamp(1, MAX_RINGS) as u32;
                let n = 2 * r;
                let (j, i) = divrem(q, n);
                // u runs along z, v along x: z x x = +y, facing up.
                let g = |k: u32| plane_line(half_size, r, k);
                let p = |i: u32, j: u32| Vec3::new(g(j), 0, g(i));
                [p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]
            }
            #[cfg(feature = "atlas")]
            Mesh::Packed(m) => {
                let [a, b, c] = m.triangle(q as u16);
                [a, b, c, c]
            }
        })
    }

    /// The corners of quad `q` (exactly [`Mesh::quad`]`(q)`) when `left` are corners 1 and 2 of
    /// quad `q - 1`: a quad that continues its predecessor's row of a teapot patch has them as
    /// its corners 0 and 3, so only its new edge (corners 1 and 2, a row of Bezier control
    /// points and two combinations instead of two and four) is computed; any other quad is
    /// computed whole. (The teapot only: the cheap parametric grids would double their code in
    /// flash for little.)
    pub fn quad_after(&self, q: u32, left: [Vec3; 2]) -> Option<[Vec3; 4]> {
        if q == 0 || q >= self.quad_count() {
            return self.quad(q);
        }
        let edge = match *self {
            Mesh::Teapot { level } => {
                let n = level.clamp(1, MAX_TEAPOT_LEVEL) as u32;
                let (patch, r) = divrem(q, n * n);
                let (l, k) = divrem(r, n);
                if k == 0 {
                    return self.quad(q);
                }
                teapot_right_edge(patch as usize, n, k, l)
            }
            _ => return self.quad(q),
        };
        Some([left[0], edge[0], edge[1], left[1]])
    }

    /// [`Mesh::quad`]`(q)` into `out` (`false`, `out` unchanged, past the end) for a walk over
    /// the quads in increasing order that keeps `cursor` from one quad to the next (a fresh
    /// [`QuadCursor`] for each mesh; any order is exact, increasing order is fast). A teapot
    /// quad takes its row's column curves from the cursor ([`TeapotRow`]: computed once a row
    /// of quads of a patch, taking over the row above's) and its left edge from the quad
    /// before when that is `q - 1` in the same row: one edge, two combinations, a quad. Every
    /// other mesh computes its quad whole. Out of line: one copy for every walk.
    #[inline(never)]
    pub(crate) fn quad_walked_into(
        &self,
        q: u32,
        cursor: &mut QuadCursor,
        out: &mut [Vec3; 4],
    ) -> bool {
        let Mesh::Teapot { level } = *self else {
            return self.quad_into(q, out);
        };
        if q >= self.quad_count() {
            return false;
        }
        let n = level.clamp(1, MAX_TEAPOT_LEVEL) as u32;
        let (patch, r) = divrem(q, n * n);
        let (l, k) = divrem(r, n);
        if !cursor.row.as_ref().is_some_and(|row| row.is(patch, n, l)) {
            cursor.row = TeapotRow::new(patch, n, l, cursor.row.as_ref());
        }
        let Some(row) = cursor.row.as_ref() else {
            // Not reached (`n`, `l` and `patch` are in range): the quad computed whole.
            return self.quad_into(q, out);
        };
        let left = match cursor.last {
            Some((lq, edge)) if k > 0 && lq.wrapping_add(1) == q => edge,
            _ => row.edge(k),
        };
        let right = row.edge(k + 1);
        *out = [left[0], right[0], right[1], left[1]];
        cursor.last = Some((q, right));
        true
    }

    /// [`Mesh::quad`] into `out` (`false`, `out` unchanged, past the end): the corners are
    /// stored where the caller keeps them rather than returned through a copy.
    pub(crate) fn quad_into(&self, q: u32, out: &mut [Vec3; 4]) -> bool {
        match self.quad(q) {
            Some(c) => {
                *out = c;
                true
            }
            None => false,
        }
    }

    /// The triangles, in a fixed order.
    pub fn triangles(&self) -> Triangles<'_> {
        Triangles {
            mesh: self,
            next_quad: 0,
            quad: [Vec3::ZERO; 4],
            half: 2,
        }
    }

    /// An axis-aligned box containing every vertex (`[min, max]`), from a walk over all quads.
    pub fn bounds(&self) -> [Vec3; 2] {
        let mut lo = Vec3::new(i32::MAX, i32::MAX, i32::MAX);
        let mut hi = Vec3::new(i32::MIN, i32::MIN, i32::MIN);
        for t in self.triangles() {
            for p in t {
                lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
                hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
            }
        }
        [lo, hi]
    }
}

/// What a walk over a mesh's quads keeps from one quad to the next
/// ([`Mesh::quad_walked_into`]): the last quad's index and right edge (its corners 1 and 2), and
/// the teapot row of quads it lies in.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct QuadCursor {
    last: Option<(u32, [Vec3; 2])>,
    row: Option<TeapotRow>,
}

/// The triangles of a [`Mesh`] (see the module documentation for the order and winding).
#[derive(Clone, Debug)]
pub struct Triangles<'a> {
    mesh: &'a Mesh,
    next_quad: u32,
    quad: [Vec3; 4],
    half: u8,
}

impl Iterator for Triangles<'_> {
    type Item = [Vec3; 3];

    fn next(&mut self) -> Option<[Vec3; 3]> {
        loop {
            if self.half >= 2 {
                self.quad = self.mesh.quad(self.next_quad)?;
                self.next_quad += 1;
                self.half = 0;
            }
            let [a, b, c, d] = self.quad;
            let t = if self.half == 0 { [a, b, c] } else { [a, c, d] };
            self.half += 1;
            if t[0] != t[1] && t[1] != t[2] && t[2] != t[0] {
                return Some(t);
            }
        }
    }
}

/// `(a / b, a % b)`; `(0, 0)` for `b == 0` (never happens: sizes are clamped; written so
/// that no division-by-zero panic path exists).
#[inline]
fn divrem(a: u32, b: u32) -> (u32, u32) {
    (a.checked_div(b).unwrap_or(0), a.checked_rem(b).unwrap_or(0))
}

/// `round(r * a * b)` for `r` in `Q16.16` and `a`, `b` in `Q2.30`, saturating.
fn mul3(r: i32, a: i32, b: i32) -> i32 {
    let v = r as i128 * a as i128 * b as i128;
    let v = (v + (1i128 << 59)) >> 60;
    sat_i32(v.clamp(i64::MIN as i128, i64::MAX as i128) as i64)
}

/// `round(r * a)` for `r` in `Q16.16`, `a` in `Q2.30`.
fn mul2(r: i32, a: i32) -> i32 {
    let v = r as i64 * a as i64;
    sat_i32((v + (1 << 29)) >> 30)
}

/// `(r sin(th) cos(ph), r cos(th), r sin(th) sin(ph))` from `(sin, cos)` of longitude `ph`
/// and colatitude `th`.
fn sphere_point(radius: i32, (sp, cp): (i32, i32), (st, ct): (i32, i32)) -> Vec3 {
    Vec3::new(mul3(radius, st, cp), mul2(radius, ct), mul3(radius, st, sp))
}

/// `((R + r cos(th)) cos(ph), -r sin(th), (R + r cos(th)) sin(ph))` from `(sin, cos)` of the
/// angle `ph` around the centre circle and `th` around the tube.
fn torus_point(major: i32, minor: i32, (sp, cp): (i32, i32), (st, ct): (i32, i32)) -> Vec3 {
    let ring = major.saturating_add(mul2(minor, ct)); // Q16.16
    Vec3::new(mul2(ring, cp), -mul2(minor, st), mul2(ring, sp))
}

/// Face `face` of the cube: centre `half n`, tangents `a`, `b` with `a x b = n`.
fn cube_point(half: i32, d: u32, face: usize, i: u32, j: u32) -> Vec3 {
    // (normal axis, sign, a axis, b axis): a x b = sign * e_normal.
    const FACES: [(usize, i32, usize, usize); 6] = [
        (0, 1, 1, 2),  // +x: y x z = x
        (0, -1, 2, 1), // -x: z x y = -x
        (1, 1, 2, 0),  // +y: z x x = y
        (1, -1, 0, 2), // -y: x x z = -y
        (2, 1, 0, 1),  // +z: x x y = z
        (2, -1, 1, 0), // -z: y x x = -z
    ];
    let Some(&(n, s, a, b)) = FACES.get(face) else {
        return Vec3::ZERO;
    };
    // Coordinate along a tangent: -half + 2 half k / d, exact rational rounded.
    let coord = |k: u32| -> i32 {
        let num = (half as i64) * (2 * k as i64 - d as i64);
        sat_i32(super::math::div_round_rt(num, d as i64))
    };
    let mut p = [0i32; 3];
    if let Some(v) = p.get_mut(n) {
        *v = if s > 0 { half } else { half.saturating_neg() };
    }
    if let Some(v) = p.get_mut(a) {
        *v = coord(i);
    }
    if let Some(v) = p.get_mut(b) {
        *v = coord(j);
    }
    Vec3::from_array(p)
}

/// Grid line `k` (`0..=2 rings`, centre at `rings`) of [`Mesh::Plane`].
fn plane_line(half_size: i32, rings: u32, k: u32) -> i32 {
    let i = k as i64 - rings as i64;
    let e = i.unsigned_abs() as u32;
    let num = half_size as i64 * ((1i64 << e) - 1);
    let v = sat_i32(super::math::div_round_rt(num, (1i64 << rings) - 1));
    if i < 0 {
        v.saturating_neg()
    } else {
        v
    }
}

/// A unit square quad in the xy plane facing `+z`, `[-half, half]^2` (convenience).
pub const fn square(half: i32) -> Mesh {
    Mesh::Quad {
        corners: [
            Vec3::new(-half, -half, 0),
            Vec3::new(half, -half, 0),
            Vec3::new(half, half, 0),
            Vec3::new(-half, half, 0),
        ],
    }
}

/// `ONE` re-exported for mesh sizes.
pub const UNIT: i32 = ONE;

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::vec::Vec;

    fn f(v: Vec3) -> [f64; 3] {
        v.to_array().map(|c| c as f64 / 65536.0)
    }

    fn normal(t: &[Vec3; 3]) -> [f64; 3] {
        let (a, b, c) = (f(t[0]), f(t[1]), f(t[2]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    }

    /// Every undirected edge of a closed mesh is used by exactly two triangles, once in each
    /// direction (consistent winding, no cracks).
    fn assert_closed(m: &Mesh) {
        let mut edges: HashMap<(Vec3, Vec3), i32> = HashMap::new();
        for t in m.triangles() {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "{m:?}: directed edge used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "{m:?}: edge without its twin");
        }
    }

    #[test]
    fn closed_meshes_are_watertight() {
        assert_closed(&Mesh::Sphere {
            radius: UNIT,
            stacks: 7,
            slices: 11,
        });
        assert_closed(&Mesh::Torus {
            major: UNIT,
            minor: UNIT / 3,
            major_segments: 13,
            minor_segments: 5,
        });
        assert_closed(&Mesh::Cube {
            half: UNIT,
            divisions: 3,
        });
    }

    #[test]
    fn counts() {
        let s = Mesh::Sphere {
            radius: UNIT,
            stacks: 8,
            slices: 16,
        };
        assert_eq!(s.triangle_count(), 2 * 16 * 7);
        let t = Mesh::Torus {
            major: UNIT,
            minor: UNIT / 4,
            major_segments: 20,
            minor_segments: 8,
        };
        assert_eq!(t.triangle_count(), 320);
        assert_eq!(
            Mesh::Cube {
                half: UNIT,
                divisions: 1
            }
            .triangle_count(),
            12
        );
        assert_eq!(square(UNIT).triangle_count(), 2);
        let p = Mesh::Plane {
            half_size: 1000 * UNIT,
            rings: 6,
        };
        assert_eq!(p.triangle_count(), 8 * 36);
        for level in [1u8, 4, 5, 6] {
            let n = level as u32;
            let tp = Mesh::Teapot { level };
            assert_eq!(tp.triangle_count(), 64 * n * n - 8 * n, "level {level}");
        }
        // Degenerate parameters are clamped, never panic.
        let z = Mesh::Sphere {
            radius: 0,
            stacks: 0,
            slices: 0,
        };
        assert_eq!(z.quad_count(), 6);
        assert_eq!(z.triangle_count(), 0); // every vertex at the origin
        assert_eq!(Mesh::Teapot { level: 200 }.quad_count(), 32 * 256);
        assert!(Mesh::Teapot { level: 0 }.quad(32).is_none());
    }

    #[test]
    fn outward_winding() {
        let meshes = [
            Mesh::Sphere {
                radius: 2 * UNIT,
                stacks: 6,
                slices: 9,
            },
            Mesh::Cube {
                half: UNIT,
                divisions: 2,
            },
        ];
        for m in meshes {
            for t in m.triangles() {
                let n = normal(&t);
                let c = f(t[0]);
                let d = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
                assert!(d > 0.0, "{m:?}: inward triangle {t:?}");
            }
        }
        let m = Mesh::Torus {
            major: 2 * UNIT,
            minor: UNIT / 2,
            major_segments: 12,
            minor_segments: 6,
        };
        for t in m.triangles() {
            let n = normal(&t);
            let c = f(t[0]);
            // Outward from the centre circle.
            let rl = (c[0] * c[0] + c[2] * c[2]).sqrt();
            let cc = [c[0] - 2.0 * c[0] / rl, c[1], c[2] - 2.0 * c[2] / rl];
            assert!(n[0] * cc[0] + n[1] * cc[1] + n[2] * cc[2] > 0.0);
        }
        let p = Mesh::Plane {
            half_size: 100 * UNIT,
            rings: 3,
        };
        assert!(p.triangles().all(|t| normal(&t)[1] > 0.0));
        // The teapot's body faces away from its axis.
        let tp = Mesh::Teapot { level: 3 };
        for t in tp.triangles().skip(3 * 3 * 2 * 4).take(3 * 3 * 2 * 8) {
            let n = normal(&t);
            let c = f(t[0]);
            assert!(n[0] * c[0] + n[1] * c[1] > 0.0);
        }
    }

    #[test]
    fn sphere_accuracy() {
        let m = Mesh::Sphere {
            radius: 3 * UNIT,
            stacks: 9,
            slices: 17,
        };
        for t in m.triangles() {
            for p in t {
                let r = f(p).iter().map(|c| c * c).sum::<f64>().sqrt();
                assert!((r - 3.0).abs() < 1e-4, "{r}");
            }
        }
    }

    #[test]
    fn walked_quads_are_quads() {
        // Every grid kind, the odd sizes too: given its predecessor's right edge, each quad is
        // exactly `quad(q)` (including the first of each row, computed whole).
        let meshes = [
            Mesh::Teapot { level: 1 },
            Mesh::Teapot { level: 3 },
            Mesh::Sphere {
                radius: 3 << 15,
                stacks: 5,
                slices: 7,
            },
            Mesh::Torus {
                major: 2 << 16,
                minor: 1 << 15,
                major_segments: 9,
                minor_segments: 4,
            },
            Mesh::Cube {
                half: 1 << 16,
                divisions: 3,
            },
            Mesh::Plane {
                half_size: 5 << 16,
                rings: 3,
            },
            Mesh::Quad {
                corners: [
                    Vec3::ZERO,
                    Vec3::new(1, 0, 0),
                    Vec3::new(1, 1, 0),
                    Vec3::new(0, 1, 0),
                ],
            },
        ];
        for m in &meshes {
            let mut left = [Vec3::ZERO; 2];
            for q in 0..m.quad_count() + 1 {
                let whole = m.quad(q);
                assert_eq!(m.quad_after(q, left), whole, "{m:?} quad {q}");
                if let Some(c) = whole {
                    left = [c[1], c[2]];
                }
            }
            // A walk keeping its cursor, over every quad, over every third one and every
            // fifth (rows entered anywhere, quads skipped), and backwards (no row taken over):
            // every quad as `quad`, `false` past the end.
            for order in [
                (0..=m.quad_count()).collect::<Vec<_>>(),
                (0..=m.quad_count()).step_by(3).collect(),
                (0..=m.quad_count()).step_by(5).collect(),
                (0..=m.quad_count()).rev().collect(),
            ] {
                let mut cursor = QuadCursor::default();
                for q in order {
                    let mut got = [Vec3::new(7, 7, 7); 4];
                    let found = m.quad_walked_into(q, &mut cursor, &mut got);
                    assert_eq!(found.then_some(got), m.quad(q), "{m:?} quad {q}");
                }
            }
        }
    }

    #[test]
    fn plane_lines() {
        let h = 4095 * UNIT;
        let v: Vec<i32> = (0..=24).map(|k| plane_line(h, 12, k)).collect();
        assert_eq!(v[12], 0);
        assert_eq!(v[13], UNIT);
        assert_eq!(v[11], -UNIT);
        assert_eq!(v[24], h);
        assert_eq!(v[0], -h);
        assert!(v.windows(2).all(|w| w[0] < w[1]));
        let b = Mesh::Plane {
            half_size: h,
            rings: 12,
        }
        .bounds();
        assert_eq!(b, [Vec3::new(-h, 0, -h), Vec3::new(h, 0, h)]);
    }

    #[test]
    fn teapot_bounds() {
        let b = Mesh::Teapot { level: 4 }.bounds();
        let lo = f(b[0]);
        let hi = f(b[1]);
        assert!(
            (lo[0] + 3.0).abs() < 0.01 && (hi[0] - 3.43).abs() < 0.05,
            "{lo:?} {hi:?}"
        );
        assert!(lo[2].abs() < 1e-4 && (hi[2] - 3.15).abs() < 1e-4);
        assert!((lo[1] + 2.0).abs() < 1e-3 && (hi[1] - 2.0).abs() < 1e-3);
    }
}
