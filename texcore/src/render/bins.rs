//! Frame bins: the image rows each triangle group can cover ([`GroupRows`]), recorded once a
//! frame in caller-owned [`FrameBins`] so that each band walks only the groups that can touch
//! it. A group's recorded rows hold every pixel centre its triangles can cover in the rendered
//! columns (the rasterizer's own bounding-box test), so a band never leaves out a group that
//! draws in it.

use super::*;

/// The image rows a group of triangles (see [`TriangleSource::for_each_triangle_grouped`]) can
/// cover, as recorded by [`Renderer::render_banded_rows_binned`]: an inclusive row range, or
/// empty. Four bytes.
///
/// Invariant: either [`GroupRows::EMPTY`] (the only empty value), or `first <= last`. As
/// recorded by the renderer, every pixel centre of the rendered rows and columns that the
/// group's triangles can cover lies on a row in `first..=last`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GroupRows {
    first: u16,
    last: u16,
}

impl GroupRows {
    /// No rows: the group covers no pixel centre.
    pub const EMPTY: GroupRows = GroupRows {
        first: u16::MAX,
        last: 0,
    };

    /// The rows `first..=last` (empty if `first > last`).
    pub const fn new(first: u16, last: u16) -> GroupRows {
        if first > last {
            GroupRows::EMPTY
        } else {
            GroupRows { first, last }
        }
    }

    /// Whether no row is covered.
    pub const fn is_empty(&self) -> bool {
        self.first > self.last
    }

    /// The first and last row covered (`None` when empty).
    pub const fn rows(&self) -> Option<(u16, u16)> {
        if self.is_empty() {
            None
        } else {
            Some((self.first, self.last))
        }
    }

    /// Whether a row of `y0..y1` is covered.
    #[inline]
    pub const fn touches(&self, y0: u16, y1: u16) -> bool {
        // Empty is `first == u16::MAX >= y1`.
        self.first < y1 && self.last >= y0 && y0 < y1
    }

    /// The smallest range covering both `self` and `first..=last` (`first <= last`).
    #[inline]
    pub(super) fn include(&mut self, first: u16, last: u16) {
        if self.is_empty() {
            *self = GroupRows { first, last };
        } else {
            self.first = self.first.min(first);
            self.last = self.last.max(last);
        }
    }
}

impl Default for GroupRows {
    /// [`GroupRows::EMPTY`].
    fn default() -> Self {
        GroupRows::EMPTY
    }
}

/// The bins of one frame: a caller-owned table of [`GroupRows`] (one per triangle group, 4
/// bytes each) and whether a walk over the whole scene has filled it, and for which image size.
///
/// A frame rendered in several calls (horizontal strips, e.g. to bound the work of one call or
/// to stream a display in parts) walks the whole scene only once: the first
/// [`Renderer::render_banded_rows_binned`] call (or [`Renderer::bin`]) fills the bins with the
/// rows each group can cover anywhere in the image, and every later call with the same bins
/// takes each band's groups from them from its first band on.
///
/// Guarantees: bins are filled only by a walk over every group of a scene, recording the
/// rows of the whole image (never only of the rows that call rendered), so filled bins are
/// valid for any rows of that scene's frame. Contract: the bins describe the triangles of the
/// walk that filled them. Call [`FrameBins::reset`] before rendering another scene of the same
/// size, or the same scene after its triangles changed (a new camera or animation time): with
/// stale bins a band may leave out a group that covers it. A scene of another size is binned
/// again without a reset.
#[derive(Debug)]
pub struct FrameBins<'b> {
    pub(super) rows: &'b mut [GroupRows],
    /// The image size of the scene whose walk filled `rows`; `None`: not filled.
    pub(super) filled: Option<(u16, u16)>,
}

impl<'b> FrameBins<'b> {
    /// Bins in `rows`, not filled (any contents: the first walk overwrites every entry).
    /// Groups past `rows.len()` are walked in every band (too few bins cost speed, never
    /// pixels); [`crate::scene::Scene::quad_count`] is the number a scene needs. An empty table
    /// bins nothing: every band walks the whole scene.
    pub fn new(rows: &'b mut [GroupRows]) -> Self {
        FrameBins { rows, filled: None }
    }

    /// Forgets the filling: the next render (or [`Renderer::bin`]) walks the whole scene again.
    pub fn reset(&mut self) {
        self.filled = None;
    }

    /// Whether a walk has filled the bins (for a scene of image size `size`).
    pub fn is_filled_for(&self, size: (u16, u16)) -> bool {
        self.filled == Some(size)
    }

    /// The bins: entry `g` holds the rows group `g` can cover once filled.
    pub fn rows(&self) -> &[GroupRows] {
        self.rows
    }
}

/// The rows of `rows` (non-empty) that triangle `t` can cover a pixel centre of, as a range
/// that meets every band in which the rasterizer's bounding-box test
/// (`Rasterizer::misses`, pixel centres at `16 p + 8` in 28.4 fixed point) lets `t` through: the
/// rows from `ceil((y0 - 8) / 16)` to `floor((y1 - 8) / 16)` of its vertical extent `y0..=y1`,
/// or, when that extent holds no pixel centre, the two rows whose centres bracket it; clamped
/// to `rows`. `None` if the range misses `rows` or the horizontal extent misses every pixel
/// centre of the columns `0..width`: then that test rejects `t` in every band of `rows`.
pub(super) fn triangle_rows(
    t: &[ScreenVertex; 3],
    rows: &core::ops::Range<u16>,
    width: u16,
) -> Option<(u16, u16)> {
    let [x0, x1, y0, y1] = crate::raster::bounding_box(t).map(i64::from);
    if x1 < 8 || x0 > 16 * i64::from(width) - 8 {
        return None;
    }
    let (below, above) = ((y0 + 7) >> 4, (y1 - 8) >> 4);
    let first = below.min(above).max(i64::from(rows.start));
    let last = below.max(above).min(i64::from(rows.end) - 1);
    (first <= last).then_some((first as u16, last as u16))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::TexPoint;

    #[test]
    fn group_rows() {
        let e = GroupRows::EMPTY;
        assert!(e.is_empty() && e.rows().is_none());
        assert_eq!(GroupRows::default(), e);
        assert_eq!(GroupRows::new(5, 4), e);
        for (y0, y1) in [(0, 0), (0, 1), (0, u16::MAX), (u16::MAX - 1, u16::MAX)] {
            assert!(!e.touches(y0, y1));
        }
        let r = GroupRows::new(8, 15);
        assert_eq!(r.rows(), Some((8, 15)));
        assert!(!r.touches(0, 8) && r.touches(0, 9) && r.touches(15, 16) && !r.touches(16, 24));
        assert!(!r.touches(10, 10), "an empty band touches nothing");
        let mut x = e;
        x.include(3, 4);
        assert_eq!(x, GroupRows::new(3, 4));
        x.include(9, 9);
        assert_eq!(x, GroupRows::new(3, 9));
        x.include(0, 1);
        assert_eq!(x, GroupRows::new(0, 9));
        assert_eq!(core::mem::size_of::<GroupRows>(), 4);
    }

    /// `triangle_rows` follows the rasterizer's pixel-centre convention (centres at 16 p + 8).
    #[test]
    fn triangle_rows_pixel_centres() {
        let t = |y0: i32, y1: i32, x0: i32, x1: i32| {
            let v = |x, y| ScreenVertex::from_bits(x, y, 0, 1 << 30, TexPoint::ZERO);
            [v(x0, y0), v(x1, y0), v(x0, y1)]
        };
        let all = 0..100u16;
        // Exactly on a centre: included on both ends.
        assert_eq!(triangle_rows(&t(8, 24, 0, 64), &all, 10), Some((0, 1)));
        // Just past a centre: excluded.
        assert_eq!(triangle_rows(&t(9, 39, 0, 64), &all, 10), Some((1, 1)));
        assert_eq!(triangle_rows(&t(9, 40, 0, 64), &all, 10), Some((1, 2)));
        // No centre between: the two rows around (the rasterizer's box test lets it through
        // in a band holding both).
        assert_eq!(triangle_rows(&t(9, 23, 0, 64), &all, 10), Some((0, 1)));
        assert_eq!(triangle_rows(&t(9, 23, 0, 64), &(1..9), 10), Some((1, 1)));
        assert_eq!(triangle_rows(&t(9, 23, 0, 64), &(2..9), 10), None);
        // Negative coordinates round the right way; clamped to the rows.
        assert_eq!(triangle_rows(&t(-100, 40, 0, 64), &all, 10), Some((0, 2)));
        assert_eq!(
            triangle_rows(&t(-100, 40, 0, 64), &(1..2), 10),
            Some((1, 1))
        );
        assert_eq!(triangle_rows(&t(-100, 7, 0, 64), &all, 10), None);
        assert_eq!(
            triangle_rows(&t(0, 16 * 200, 0, 64), &(90..100), 10),
            Some((90, 99))
        );
        // Left or right of every column centre of a 10-pixel row.
        assert_eq!(triangle_rows(&t(0, 64, -50, 7), &all, 10), None);
        assert_eq!(triangle_rows(&t(0, 64, -50, 8), &all, 10), Some((0, 3)));
        assert_eq!(triangle_rows(&t(0, 64, 153, 400), &all, 10), None);
        assert_eq!(triangle_rows(&t(0, 64, 152, 400), &all, 10), Some((0, 3)));
        // Extremes do not overflow.
        assert_eq!(
            triangle_rows(&t(i32::MIN, i32::MAX, i32::MIN, i32::MAX), &all, u16::MAX),
            Some((0, 99))
        );
    }
}
