//! The scene walk's corner store: quad corners already transformed, classified and projected,
//! found again by their object-space position.
//!
//! A grid mesh's quads share corners with the quad before them in the row (the walk keeps that
//! edge's slots itself) and with the quads of the row above. [`CornerStore`] holds the walk's
//! corners in place and finds the recent ones by position, so a quad whose top corners were
//! some earlier quad's bottom corners takes them from there instead of transforming them again.
//!
//! # Guarantees
//!
//! - **Exact.** A slot is found only for a corner at the same object-space position of the
//!   same object (the positions are forgotten per object), and the camera vertex, outcodes and
//!   projection of a corner are functions of its position and the object alone: a hit gives
//!   exactly what recomputing would.
//! - **Bounded.** `S - 4` cached positions and four scratch slots in the walk's frame,
//!   direct-mapped by a hash of the position: a miss (an empty slot, another position) only
//!   costs the computation it would have cost anyway. No allocation, no panic path.

use super::camera::CamVertex;
use super::math::Vec3;
use crate::raster::ScreenVertex;

/// Slots of the store of a walk that runs once per band (the renderer's): 28 cached corners,
/// enough for the bottom edge of a row of the built-in meshes' patches and, often, the edge a
/// teapot patch shares with the one walked before it. Every slot costs about 96 bytes of the
/// walk's frame, in every band.
pub(crate) const BAND_WALK_SLOTS: usize = 32;

/// Slots of the store of a walk that runs once a frame (`Scene::for_each_screen_triangle_with_corners`,
/// the atlas draw's frame list): 60 cached corners. The marble frame's walk computes 983 corners
/// with 12 cached, 835 with 28 and 709 with 60.
pub(crate) const FRAME_WALK_SLOTS: usize = 64;

/// A corner's projection ([`super::View::project`]) without its texture coordinates, which the
/// camera vertex holds: 24 bytes, so that it moves through registers rather than a `memcpy`
/// call on 32-bit cores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Projected {
    /// The unnormalised `1/w`.
    q: u64,
    x: i32,
    y: i32,
    z: u16,
}

impl Projected {
    /// The projection `p` of a camera vertex, less its texture coordinates.
    #[inline(always)]
    pub(crate) fn new(p: (ScreenVertex, u64)) -> Projected {
        let (v, q) = p;
        Projected {
            q,
            x: v.x.to_bits(),
            y: v.y.to_bits(),
            z: v.z,
        }
    }

    /// The projection again, with the camera vertex's texture coordinates `tex` (what
    /// [`super::View::project`] returned: its `1/w` field is 0, the texture coordinates are the
    /// camera vertex's).
    #[inline(always)]
    pub(crate) fn vertex(&self, tex: &[i32; 3]) -> (ScreenVertex, u64) {
        let t = crate::format::TexPoint::from_bits(tex[0], tex[1], tex[2]);
        (
            ScreenVertex::from_bits(self.x, self.y, self.z, 0, t),
            self.q,
        )
    }
}

/// One walked corner: what the walk computed for an object-space position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct WalkedCorner {
    /// The camera vertex.
    pub(crate) cam: CamVertex,
    /// The view and guard outcodes of `cam`.
    pub(crate) oc: (u8, u8),
    /// The projection of `cam`, once a triangle asked for it.
    pub(crate) projected: Option<Projected>,
}

impl WalkedCorner {
    /// An empty slot (every field zero: a store's slots start as one fill of zeros).
    const EMPTY: WalkedCorner = WalkedCorner {
        cam: CamVertex {
            p: [0; 3],
            tex: [0; 3],
        },
        oc: (0, 0),
        projected: None,
    };
}

/// The walk's corners, in place: the current quad's corners are slot numbers, and the
/// `S - 4` cached slots are direct-mapped by a hash of the position, so a corner
/// computed once is found again by its position while its slot is not reused (see the module
/// documentation). Nothing is copied in or out.
///
/// `S` slots: `S - 4` cached ones and four scratch slots (a quad has four corners, so a free one
/// always exists); a power of two, so a slot number is masked into range.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CornerStore<const S: usize> {
    /// The position each cached slot holds (`None`: empty; scratch slots, the last four, are
    /// never found).
    pos: [Option<Vec3>; S],
    corner: [WalkedCorner; S],
}

impl<const S: usize> CornerStore<S> {
    /// The cached slots (checked at compile time: `S` a power of two above 4).
    const CACHE: usize = {
        assert!(S.is_power_of_two() && S > 4);
        S - 4
    };

    /// An empty store. Inlined, from constant empty slots (all zero): the caller's store is
    /// filled in place (from `Default` slots, or out of line, the store was built beside it
    /// and copied: a second store's worth of the walk's stack).
    #[inline(always)]
    pub(crate) fn new() -> CornerStore<S> {
        CornerStore {
            pos: [None; S],
            corner: [WalkedCorner::EMPTY; S],
        }
    }

    /// Forgets every cached position (a new object: another transform).
    pub(crate) fn clear(&mut self) {
        self.pos = [None; S];
    }

    /// The cached slot of position `p`: a multiplicative hash of its coordinates scaled to
    /// `0..S - 4` by its top bits (one multiplication, no division).
    #[inline(always)]
    fn slot(p: &Vec3) -> usize {
        let (x, y, z) = (p.x as u32, p.y as u32, p.z as u32);
        let h = (x ^ y.rotate_left(11) ^ z.rotate_left(22)).wrapping_mul(0x9E37_79B1);
        ((u64::from(h) * Self::CACHE as u64) >> 32) as usize
    }

    /// The slot holding the corner walked at position `p`, if it is still cached.
    #[inline]
    pub(crate) fn find(&self, p: &Vec3) -> Option<usize> {
        let i = Self::slot(p);
        match self.pos.get(i) {
            Some(Some(q)) if q == p => Some(i),
            _ => None,
        }
    }

    /// A slot for a new corner at position `p` that is none of `busy` (the slots the current
    /// quad still uses): its cached slot, which then holds `p`, or else a free scratch slot
    /// (never found again). The caller fills it.
    #[inline]
    pub(crate) fn claim(&mut self, p: Vec3, busy: &[usize; 4]) -> usize {
        let i = Self::slot(&p);
        if !busy.contains(&i) {
            if let Some(s) = self.pos.get_mut(i) {
                *s = Some(p);
            }
            return i;
        }
        (Self::CACHE..S)
            .find(|j| !busy.contains(j))
            .unwrap_or(Self::CACHE)
    }

    /// The corner in slot `i` (a slot of [`CornerStore::find`] or [`CornerStore::claim`]).
    #[inline]
    pub(crate) fn get(&self, i: usize) -> &WalkedCorner {
        // `i & (S - 1)`: in bounds, no panic path.
        &self.corner[i & (S - 1)]
    }

    /// The corner in slot `i`, to fill or to add its projection.
    #[inline]
    pub(crate) fn get_mut(&mut self, i: usize) -> &mut WalkedCorner {
        &mut self.corner[i & (S - 1)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Store = CornerStore<BAND_WALK_SLOTS>;
    const CACHE_CORNERS: usize = BAND_WALK_SLOTS - 4;
    const SLOTS: usize = BAND_WALK_SLOTS;

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

    const FREE: [usize; 4] = [usize::MAX; 4];

    /// A projection kept without its texture coordinates comes back as `View::project` gave
    /// it (its `1/w` field 0, the camera vertex's texture coordinates).
    #[test]
    fn a_projection_comes_back_whole() {
        let view = crate::scene::Camera::perspective(
            Vec3::units(1, 2, 5),
            Vec3::ZERO,
            Vec3::Y,
            crate::scene::focal_from_fov(crate::scene::Angle::from_degrees(60)),
            6554,
            1 << 26,
            320,
            240,
        )
        .view()
        .unwrap();
        for k in -50i64..50 {
            let cam = CamVertex {
                p: [k * 40_000, -k * 9_000, 300_000 + k * k * 700],
                tex: [k as i32, -7, (1 << 30) - k as i32],
            };
            let p = view.project(&cam);
            assert_eq!(Projected::new(p).vertex(&cam.tex), p, "{k}");
        }
    }

    #[test]
    fn finds_only_the_same_position() {
        let mut c = Store::new();
        let p = Vec3::new(65536, -7, 1 << 20);
        assert_eq!(c.find(&p), None);
        let i = c.claim(p, &FREE);
        *c.get_mut(i) = corner(5);
        assert_eq!(c.find(&p), Some(i));
        assert_eq!(*c.get(i), corner(5));
        // Every other position that maps to the same slot misses.
        let mut others = 0;
        for x in -2000..2000 {
            let q = Vec3::new(x, -7, 1 << 20);
            if q != p && Store::slot(&q) == Store::slot(&p) {
                others += 1;
                assert_eq!(c.find(&q), None, "{q:?}");
            }
        }
        assert!(others > 0);
        c.clear();
        assert_eq!(c.find(&p), None);
    }

    #[test]
    fn busy_slots_are_never_claimed() {
        let mut c = Store::new();
        let p = Vec3::new(3, 4, 5);
        let home = Store::slot(&p);
        // Its own slot busy: a scratch slot, none of the busy ones, and not found later.
        for busy in [
            [home, usize::MAX, usize::MAX, usize::MAX],
            [home, CACHE_CORNERS, CACHE_CORNERS + 1, CACHE_CORNERS + 2],
            [CACHE_CORNERS + 3, home, CACHE_CORNERS, CACHE_CORNERS + 1],
        ] {
            let i = c.claim(p, &busy);
            assert!(
                (CACHE_CORNERS..SLOTS).contains(&i) && !busy.contains(&i),
                "{i} {busy:?}"
            );
            assert_eq!(c.find(&p), None);
        }
        assert_eq!(c.claim(p, &FREE), home);
        assert_eq!(c.find(&p), Some(home));
    }

    #[test]
    fn a_row_of_grid_corners_stays() {
        // The bottom edge of a row of a 4 x 4 patch (5 corners) and of an 8-quad row: the
        // slots spread them (a few may collide, never more than half).
        for n in [5, 9] {
            let mut c = Store::new();
            let row: std::vec::Vec<Vec3> = (0..n)
                .map(|i| Vec3::new(i * 9000, 4321, -i * 777))
                .collect();
            for p in &row {
                c.claim(*p, &FREE);
            }
            let kept = row.iter().filter(|p| c.find(p).is_some()).count();
            assert!(2 * kept >= n as usize, "{kept} of {n}");
        }
    }
}
