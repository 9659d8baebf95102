//! The scene walk's corner cache: quad corners already transformed, classified and projected,
//! found again by their object-space position.
//!
//! A grid mesh's quads share corners with the quad before them in the row (the walk keeps that
//! edge itself) and with the quads of the row above. [`CornerCache`] keeps the bottom corners of
//! the quads walked last, so a quad whose top corners were some earlier quad's bottom corners
//! takes them from here instead of transforming them again.
//!
//! # Guarantees
//!
//! - **Exact.** An entry is used only for a corner at the same object-space position of the
//!   same object (the cache is emptied per object), and the camera vertex, outcodes and
//!   projection of a corner are functions of its position and the object alone: a hit gives
//!   exactly what recomputing would.
//! - **Bounded.** [`CACHE_CORNERS`] entries in the walk's frame, direct-mapped by a hash of the
//!   position: a miss (an empty slot, another position) only costs the computation it would
//!   have cost anyway. No allocation, no panic path.

use super::camera::CamVertex;
use super::math::Vec3;
use crate::raster::ScreenVertex;

/// Entries of a [`CornerCache`]: a power of two, enough for the bottom edge of a row of the
/// built-in meshes' patches and grids.
pub(crate) const CACHE_CORNERS: usize = 16;

/// One walked corner: what the walk computed for an object-space position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct WalkedCorner {
    /// The camera vertex.
    pub(crate) cam: CamVertex,
    /// The view and guard outcodes of `cam`.
    pub(crate) oc: (u8, u8),
    /// The projection of `cam`, once a triangle asked for it.
    pub(crate) projected: Option<(ScreenVertex, u64)>,
}

/// A direct-mapped cache of walked corners, by object-space position (see the module
/// documentation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CornerCache {
    slots: [Option<(Vec3, WalkedCorner)>; CACHE_CORNERS],
}

impl CornerCache {
    /// An empty cache.
    pub(crate) const fn new() -> CornerCache {
        CornerCache {
            slots: [None; CACHE_CORNERS],
        }
    }

    /// Forgets every entry (a new object: another transform).
    pub(crate) fn clear(&mut self) {
        self.slots = [None; CACHE_CORNERS];
    }

    /// The slot of position `p`: the top bits of a multiplicative hash of its coordinates.
    #[inline(always)]
    fn slot(p: &Vec3) -> usize {
        let (x, y, z) = (p.x as u32, p.y as u32, p.z as u32);
        let h = (x ^ y.rotate_left(11) ^ z.rotate_left(22)).wrapping_mul(0x9E37_79B1);
        (h >> (32 - CACHE_CORNERS.trailing_zeros())) as usize & (CACHE_CORNERS - 1)
    }

    /// The corner walked at position `p`, if it is still cached.
    #[inline]
    pub(crate) fn get(&self, p: &Vec3) -> Option<WalkedCorner> {
        match self.slots.get(Self::slot(p)) {
            Some(Some((q, w))) if q == p => Some(*w),
            _ => None,
        }
    }

    /// Keeps a quad's bottom edge: the corners walked at positions `p` with their camera
    /// vertices, outcodes and projections. Out of line: one copy for every walk.
    #[inline(never)]
    pub(crate) fn put_edge(
        &mut self,
        p: [Vec3; 2],
        cam: [CamVertex; 2],
        oc: [(u8, u8); 2],
        projected: [Option<(ScreenVertex, u64)>; 2],
    ) {
        for (((p, cam), oc), projected) in p.into_iter().zip(cam).zip(oc).zip(projected) {
            self.put(p, WalkedCorner { cam, oc, projected });
        }
    }

    /// Keeps the corner walked at position `p` (replacing what its slot held).
    #[inline]
    pub(crate) fn put(&mut self, p: Vec3, w: WalkedCorner) {
        if let Some(s) = self.slots.get_mut(Self::slot(&p)) {
            *s = Some((p, w));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corner(k: i64) -> WalkedCorner {
        WalkedCorner {
            cam: CamVertex {
                p: [k, -k, k * 3],
                tex: [1, 2, 3],
            },
            oc: (k as u8, 0),
            projected: None,
        }
    }

    #[test]
    fn hits_only_the_same_position() {
        let mut c = CornerCache::new();
        let p = Vec3::new(65536, -7, 1 << 20);
        assert_eq!(c.get(&p), None);
        c.put(p, corner(5));
        assert_eq!(c.get(&p), Some(corner(5)));
        // Every other position that maps to the same slot misses.
        let mut others = 0;
        for x in -2000..2000 {
            let q = Vec3::new(x, -7, 1 << 20);
            if q != p && CornerCache::slot(&q) == CornerCache::slot(&p) {
                others += 1;
                assert_eq!(c.get(&q), None, "{q:?}");
            }
        }
        assert!(others > 0);
        c.clear();
        assert_eq!(c.get(&p), None);
    }

    #[test]
    fn a_row_of_grid_corners_stays() {
        // The bottom edge of a row of a 4 x 4 patch (5 corners) and of an 8-quad row: the
        // slots spread them (a few may collide, never more than half).
        for n in [5, 9] {
            let mut c = CornerCache::new();
            let row: std::vec::Vec<Vec3> = (0..n)
                .map(|i| Vec3::new(i * 9000, 4321, -i * 777))
                .collect();
            for (i, p) in row.iter().enumerate() {
                c.put(*p, corner(i as i64));
            }
            let kept = row.iter().filter(|p| c.get(p).is_some()).count();
            assert!(2 * kept >= n as usize, "{kept} of {n}");
        }
    }
}
