//! Packed triangle meshes: the compact device form of a mesh file, generated on the host
//! (`texsim mesh pack bunny.obj -o bunny.mesh`), linked with `include_bytes!` and read in place.
//!
//! Layout (all little-endian, no alignment needed):
//!
//! | bytes | contents |
//! |---|---|
//! | 4 | magic `TXM1` |
//! | 2 | vertex count `V` (`3..=MAX_VERTICES`) |
//! | 2 | triangle count `T` (`1..=MAX_TRIANGLES`) |
//! | `12 V` | positions, three `i32` `Q16.16` each |
//! | `6 T` | triangles, three `u16` vertex indices each |
//! | 4 | FNV-1a checksum of everything before it |
//!
//! Guarantees: [`PackedMesh::new`] checks everything once (length, magic, counts, checksum, every
//! index in range, no triangle with a repeated index or zero area in exact integer arithmetic);
//! afterwards no accessor can fail or panic for an index in range, and nothing allocates.

use crate::scene::math::Vec3;

/// The file magic.
pub const MAGIC: [u8; 4] = *b"TXM1";
/// Most vertices of a packed mesh.
pub const MAX_VERTICES: usize = u16::MAX as usize;
/// Most triangles of a packed mesh.
pub const MAX_TRIANGLES: usize = u16::MAX as usize;

const HEADER: usize = 8;

/// Why bytes are not a packed mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PackedMeshError {
    /// Shorter than a header, or not the length the counts call for.
    Length,
    /// Not starting with [`MAGIC`].
    Magic,
    /// Fewer than three vertices or no triangle.
    Empty,
    /// The checksum does not match.
    Checksum,
    /// Triangle `0` has a vertex index past the vertex count.
    Index(u16),
    /// Triangle `0` has a repeated index or zero area.
    Degenerate(u16),
}

impl core::fmt::Display for PackedMeshError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PackedMeshError::Length => write!(f, "wrong length for its counts"),
            PackedMeshError::Magic => write!(f, "not a packed mesh (bad magic)"),
            PackedMeshError::Empty => write!(f, "fewer than 3 vertices or no triangle"),
            PackedMeshError::Checksum => write!(f, "checksum mismatch"),
            PackedMeshError::Index(t) => write!(f, "triangle {t}: vertex index out of range"),
            PackedMeshError::Degenerate(t) => write!(f, "triangle {t}: degenerate"),
        }
    }
}

/// FNV-1a over `bytes` (the packed format's checksum).
pub fn checksum(bytes: &[u8]) -> u32 {
    let mut h: u32 = 0x811C_9DC5;
    for &b in bytes {
        h = (h ^ b as u32).wrapping_mul(0x0100_0193);
    }
    h
}

/// A validated packed mesh borrowed from its bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PackedMesh<'a> {
    vertices: &'a [u8],
    triangles: &'a [u8],
}

fn u16_at(b: &[u8], i: usize) -> u16 {
    match b.get(i..i + 2) {
        Some(s) => u16::from_le_bytes([s[0], s[1]]),
        None => 0,
    }
}

fn i32_at(b: &[u8], i: usize) -> i32 {
    match b.get(i..i + 4) {
        Some(s) => i32::from_le_bytes([s[0], s[1], s[2], s[3]]),
        None => 0,
    }
}

impl<'a> PackedMesh<'a> {
    /// Checks `bytes` completely (see the module guarantees).
    pub fn new(bytes: &'a [u8]) -> Result<PackedMesh<'a>, PackedMeshError> {
        if bytes.len() < HEADER + 4 {
            return Err(PackedMeshError::Length);
        }
        if bytes[..4] != MAGIC {
            return Err(PackedMeshError::Magic);
        }
        let v = u16_at(bytes, 4) as usize;
        let t = u16_at(bytes, 6) as usize;
        if bytes.len() != HEADER + 12 * v + 6 * t + 4 {
            return Err(PackedMeshError::Length);
        }
        if v < 3 || t == 0 {
            return Err(PackedMeshError::Empty);
        }
        let body = bytes.len() - 4;
        if checksum(&bytes[..body]) != i32_at(bytes, body) as u32 {
            return Err(PackedMeshError::Checksum);
        }
        let m = PackedMesh {
            vertices: &bytes[HEADER..HEADER + 12 * v],
            triangles: &bytes[HEADER + 12 * v..body],
        };
        for k in 0..t {
            let idx = m.indices(k as u16);
            if idx.iter().any(|&i| i as usize >= v) {
                return Err(PackedMeshError::Index(k as u16));
            }
            if idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2] {
                return Err(PackedMeshError::Degenerate(k as u16));
            }
            let [a, b, c] = idx.map(|i| m.vertex(i));
            // Widened before subtracting: corners at opposite ends of the `i32` range differ by
            // up to 2^32.
            let d = |p: Vec3, q: Vec3| {
                [
                    p.x as i64 - q.x as i64,
                    p.y as i64 - q.y as i64,
                    p.z as i64 - q.z as i64,
                ]
            };
            let (e, f) = (d(b, a), d(c, a));
            let cx = e[1] as i128 * f[2] as i128 - e[2] as i128 * f[1] as i128;
            let cy = e[2] as i128 * f[0] as i128 - e[0] as i128 * f[2] as i128;
            let cz = e[0] as i128 * f[1] as i128 - e[1] as i128 * f[0] as i128;
            if cx == 0 && cy == 0 && cz == 0 {
                return Err(PackedMeshError::Degenerate(k as u16));
            }
        }
        Ok(m)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> u16 {
        (self.vertices.len() / 12) as u16
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> u16 {
        (self.triangles.len() / 6) as u16
    }

    /// Vertex `i` (`Q16.16`; zero past the end).
    pub fn vertex(&self, i: u16) -> Vec3 {
        let o = 12 * i as usize;
        Vec3::new(
            i32_at(self.vertices, o),
            i32_at(self.vertices, o + 4),
            i32_at(self.vertices, o + 8),
        )
    }

    /// The vertex indices of triangle `t` (zeros past the end).
    pub fn indices(&self, t: u16) -> [u16; 3] {
        let o = 6 * t as usize;
        [
            u16_at(self.triangles, o),
            u16_at(self.triangles, o + 2),
            u16_at(self.triangles, o + 4),
        ]
    }

    /// The corners of triangle `t`.
    pub fn triangle(&self, t: u16) -> [Vec3; 3] {
        self.indices(t).map(|i| self.vertex(i))
    }

    /// Every triangle in order.
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        (0..self.triangle_count()).map(move |t| self.triangle(t))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    fn pack(p: &[[i32; 3]], t: &[[u16; 3]]) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&(p.len() as u16).to_le_bytes());
        out.extend_from_slice(&(t.len() as u16).to_le_bytes());
        for v in p.iter().flatten() {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for i in t.iter().flatten() {
            out.extend_from_slice(&i.to_le_bytes());
        }
        let h = checksum(&out);
        out.extend_from_slice(&h.to_le_bytes());
        out
    }

    const P: [[i32; 3]; 4] = [[0, 0, 0], [65536, 0, 0], [0, 65536, 0], [0, 0, 65536]];

    #[test]
    fn round_trip() {
        let b = pack(&P, &[[0, 2, 1], [0, 1, 3]]);
        let m = PackedMesh::new(&b).unwrap();
        assert_eq!((m.vertex_count(), m.triangle_count()), (4, 2));
        assert_eq!(
            m.triangle(1),
            [
                Vec3::new(0, 0, 0),
                Vec3::new(65536, 0, 0),
                Vec3::new(0, 0, 65536)
            ]
        );
        assert_eq!(m.triangles().count(), 2);
    }

    #[test]
    fn every_defect_is_caught() {
        let good = pack(&P, &[[0, 2, 1]]);
        assert_eq!(PackedMesh::new(&good[..10]), Err(PackedMeshError::Length));
        assert_eq!(
            PackedMesh::new(&good[..good.len() - 1]),
            Err(PackedMeshError::Length)
        );
        let mut b = good.clone();
        b[0] = b'X';
        assert_eq!(PackedMesh::new(&b), Err(PackedMeshError::Magic));
        let mut b = good.clone();
        b[9] ^= 1;
        assert_eq!(PackedMesh::new(&b), Err(PackedMeshError::Checksum));
        assert_eq!(
            PackedMesh::new(&pack(&P, &[[0, 2, 4]])),
            Err(PackedMeshError::Index(0))
        );
        assert_eq!(
            PackedMesh::new(&pack(&P, &[[0, 1, 2], [0, 2, 2]])),
            Err(PackedMeshError::Degenerate(1))
        );
        let line = [[0, 0, 0], [1, 1, 1], [2, 2, 2]];
        assert_eq!(
            PackedMesh::new(&pack(&line, &[[0, 1, 2]])),
            Err(PackedMeshError::Degenerate(0))
        );
        assert_eq!(PackedMesh::new(&pack(&P, &[])), Err(PackedMeshError::Empty));
    }

    /// Found by the `mesh` fuzz target: corners at opposite ends of the `i32` range overflowed
    /// the area check's differences (a panic with debug assertions, a wrong verdict without).
    #[test]
    fn corners_at_the_ends_of_the_range() {
        let (lo, hi) = (i32::MIN, i32::MAX);
        let wide = [[lo, lo, lo], [hi, lo, lo], [lo, hi, hi]];
        assert!(PackedMesh::new(&pack(&wide, &[[0, 1, 2]])).is_ok());
        // Collinear across the whole range: (lo,lo,lo), (0,0,0) and (hi-1 .. ) on one line.
        let line = [[lo, lo, lo], [0, 0, 0], [-(lo / 2), -(lo / 2), -(lo / 2)]];
        assert_eq!(
            PackedMesh::new(&pack(&line, &[[0, 1, 2]])),
            Err(PackedMeshError::Degenerate(0))
        );
    }
}
