//! Exact edge walking and the top-left fill rule.
//!
//! A triangle's vertices are sorted by `y` into `top`, `mid`, `bot`. The long edge `top -> bot`
//! bounds every row on one side, the short edges `top -> mid` then `mid -> bot` on the other. For
//! a row whose pixel centres lie at `cy` (raw, 1/16 pixel: `cy = 16 py + 8`), an edge `a -> b` with
//! `a.y <= cy < b.y` crosses the row at `x(cy) = a.x + (cy - a.y) (b.x - a.x) / (b.y - a.y)`, and
//! the first pixel whose centre is at or right of it is
//!
//! ```text
//! X(cy) = ceil((x(cy) - 8) / 16) = ceil(((a.x - 8) dy + (cy - a.y) dx) / (16 dy)).
//! ```
//!
//! The covered pixels of a row are `[X_left(cy), X_right(cy))`: centres on a left edge are
//! included and centres on a right edge excluded; rows are `[ceil((top.y - 8)/16),
//! ceil((bot.y - 8)/16))`, so centres on a horizontal top edge are included and on a horizontal
//! bottom edge excluded. This is exactly the top-left rule of the edge-function formulation.
//! An edge is always walked from its upper to its lower end, so two triangles sharing it compute
//! bit-identical `X(cy)`.
//!
//! `X(cy)` is kept as an exact quotient and remainder: one `i128` division per edge per draw
//! (at the first row inside the clip), then only `i64` additions per row.

use super::Rect;
#[cfg(not(texcore_lean))]
use crate::wide::div_rem_euclid_i64;
#[cfg(texcore_lean)]
use crate::wide::{div_rem_euclid_i128, mul_wide};

/// Sub-pixel units per pixel.
pub(crate) const SUB: i64 = 16;
/// Half a pixel in sub-pixel units (pixel centres are at `16 p + 8`).
pub(crate) const HALF: i64 = 8;

/// `ceil((v - 8) / 16)`: the first pixel row (or column) whose centre is at or after `v`.
#[inline]
pub(crate) fn first_centre_at_or_after(v: i64) -> i64 {
    (v - HALF + SUB - 1).div_euclid(SUB)
}

/// The coverage part of a triangle setup: vertices sorted by `y` (raw 28.4 in `i64`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Coverage {
    pub(crate) top: [i64; 2],
    pub(crate) mid: [i64; 2],
    pub(crate) bot: [i64; 2],
    /// The middle vertex is right of the long edge (so the long edge is the left boundary).
    pub(crate) mid_right: bool,
    /// First row with a centre at or below `top.y`.
    pub(crate) py_first: i64,
    /// First row with a centre at or below `mid.y` (where the short edge changes).
    pub(crate) py_mid: i64,
    /// First row with a centre at or below `bot.y` (exclusive end).
    pub(crate) py_end: i64,
}

/// The vertices `p` (raw `[x, y]`) sorted by `y`, ties kept in their order: the top, middle
/// and bottom vertex of a coverage (the small path's `i32` one too, so both walk the same
/// edges).
#[inline(always)]
pub(crate) fn sorted_by_y<T: PartialOrd + Copy>(p: [[T; 2]; 3]) -> [[T; 2]; 3] {
    let [mut a, mut b, mut c] = p;
    if b[1] < a[1] {
        core::mem::swap(&mut a, &mut b);
    }
    if c[1] < b[1] {
        core::mem::swap(&mut b, &mut c);
    }
    if b[1] < a[1] {
        core::mem::swap(&mut a, &mut b);
    }
    [a, b, c]
}

impl Coverage {
    /// Sorts the vertices (given as raw `[x, y]`) by `y`. The caller guarantees a non-zero area
    /// and the guard band.
    pub(crate) fn new(p: [[i64; 2]; 3]) -> Coverage {
        let [top, mid, bot] = sorted_by_y(p);
        // Guard band: |coordinate differences| < 2^31, so the cross product is exact in i64.
        let cross = (mid[0] - top[0]) * (bot[1] - top[1]) - (mid[1] - top[1]) * (bot[0] - top[0]);
        Coverage {
            top,
            mid,
            bot,
            mid_right: cross > 0,
            py_first: first_centre_at_or_after(top[1]),
            py_mid: first_centre_at_or_after(mid[1]),
            py_end: first_centre_at_or_after(bot[1]),
        }
    }
}

/// Walks one edge row by row: `x` is `X(cy)` of the current row, `r` the remainder of the exact
/// quotient (`0 <= r < m`).
#[derive(Clone, Copy, Debug)]
struct EdgeWalker {
    x: i64,
    r: i64,
    m: i64,
    step_q: i64,
    step_r: i64,
}

impl EdgeWalker {
    /// The edge `a -> b` (`a.y < b.y`) at row `py` (whose centre must satisfy
    /// `a.y <= cy < b.y`, which keeps `x` within the edge's horizontal extent).
    fn new(a: [i64; 2], b: [i64; 2], py: i64) -> EdgeWalker {
        // Guard band: |dx|, |dy| < 2^31.
        let dx = b[0] - a[0];
        let dy = b[1] - a[1];
        if dy <= 0 {
            // Never walked (horizontal edges cover no row); a harmless placeholder.
            return EdgeWalker {
                x: a[0].div_euclid(SUB),
                r: 0,
                m: 1,
                step_q: 0,
                step_r: 0,
            };
        }
        let m = SUB * dy;
        // 0 <= py < 2^16 (a row of the clip): cy - a.y is below 2^31 in magnitude.
        let cy = py * SUB + HALF;
        // ceil(N / m) = floor((N + m - 1) / m).
        #[cfg(texcore_lean)]
        let (x, r, step_q, step_r) = {
            let n = mul_wide(a[0] - HALF, dy) + mul_wide(cy - a[1], dx) + i128::from(m - 1);
            // m > 0; one shared out-of-line i128 division (code size on 32-bit targets).
            let (x, r) = div_rem_euclid_i128(n, i128::from(m));
            let (q, sr) = div_rem_euclid_i128(i128::from(SUB * dx), i128::from(m));
            (x as i64, r as i64, q as i64, sr as i64)
        };
        // |a.x - HALF| < 2^30 + 8 and 0 < dy < 2^31 (guard band): the first product is below
        // 2^61 + 2^34 in magnitude; |cy - a.y| < 2^31 and |dx| < 2^31: the second below 2^62;
        // 0 <= m - 1 < 2^35. The sum is below 2^63 in magnitude: exact in i64, and the same
        // N as the 128-bit form above.
        #[cfg(not(texcore_lean))]
        let (x, r, step_q, step_r) = {
            let n = (a[0] - HALF) * dy + (cy - a[1]) * dx + (m - 1);
            let (x, r) = div_rem_euclid_i64(n, m);
            let (q, sr) = div_rem_euclid_i64(SUB * dx, m);
            (x, r, q, sr)
        };
        EdgeWalker {
            x,
            r,
            m,
            step_q,
            step_r,
        }
    }

    /// Moves to the next row (out of line in the size-lean shape: two walkers per row loop).
    #[cfg_attr(texcore_lean, inline(never))]
    #[cfg_attr(not(texcore_lean), inline)]
    fn advance(&mut self) {
        self.x = self.x.wrapping_add(self.step_q);
        self.r += self.step_r;
        if self.r >= self.m {
            self.r -= self.m;
            self.x = self.x.wrapping_add(1);
        }
    }
}

/// [`for_each_run`] for the rasterizer's draw calls: in the size-lean shape
/// (`cfg(texcore_lean)`) through one out-of-line copy taking `f` as a trait object (an indirect
/// call per row) instead of one inlined copy per caller.
#[inline(always)]
pub(crate) fn walk_runs(cov: &Coverage, clip: Rect, mut f: impl FnMut(u16, u16, u16)) {
    #[cfg(texcore_lean)]
    for_each_run_dyn(cov, clip, &mut f);
    #[cfg(not(texcore_lean))]
    for_each_run(cov, clip, &mut f);
}

/// [`for_each_run`] for every caller (size-lean shape).
#[cfg(texcore_lean)]
#[inline(never)]
fn for_each_run_dyn(cov: &Coverage, clip: Rect, f: &mut dyn FnMut(u16, u16, u16)) {
    for_each_run(cov, clip, f);
}

/// Calls `f(py, xa, xb)` for every row `py` of the triangle inside `clip` whose covered pixels
/// `[xa, xb)` (clipped) are not empty, top to bottom.
pub(crate) fn for_each_run(cov: &Coverage, clip: Rect, mut f: impl FnMut(u16, u16, u16)) {
    let y0 = cov.py_first.max(clip.y0 as i64);
    let y1 = cov.py_end.min(clip.y1 as i64);
    if y0 >= y1 || clip.x0 >= clip.x1 {
        return;
    }
    let (cx0, cx1) = (clip.x0 as i64, clip.x1 as i64);
    let mut long = EdgeWalker::new(cov.top, cov.bot, y0);
    let mut short = if y0 < cov.py_mid {
        EdgeWalker::new(cov.top, cov.mid, y0)
    } else {
        EdgeWalker::new(cov.mid, cov.bot, y0)
    };
    for py in y0..y1 {
        if py == cov.py_mid && py != y0 {
            short = EdgeWalker::new(cov.mid, cov.bot, py);
        }
        let (l, r) = if cov.mid_right {
            (long.x, short.x)
        } else {
            (short.x, long.x)
        };
        let xa = l.max(cx0);
        let xb = r.min(cx1);
        if xa < xb {
            // 0 <= clip.x0 <= xa < xb <= clip.x1 <= 65535 and 0 <= py < clip.y1.
            f(py as u16, xa as u16, xb as u16);
        }
        long.advance();
        short.advance();
    }
}

#[cfg(test)]
mod tests {
    //! Fill-rule pattern tests on a 16x16 grid, against hand-written expected patterns, and
    //! against an independent edge-function reference.
    extern crate std;
    use super::super::tests::reference_covered;
    use super::*;
    use std::string::String;
    use std::vec::Vec;

    /// Raw 28.4 from pixels.
    fn px(v: f64) -> i64 {
        (v * 16.0) as i64
    }

    /// Renders the coverage of a triangle (pixel coordinates) on a 16x16 grid as text.
    fn pattern(p: [[f64; 2]; 3]) -> String {
        let raw = p.map(|v| [px(v[0]), px(v[1])]);
        let mut grid = [[0u8; 16]; 16];
        if area2(raw) != 0 {
            for_each_run(&Coverage::new(raw), Rect::from_size(16, 16), |y, a, b| {
                for x in a..b {
                    grid[y as usize][x as usize] += 1;
                }
            });
        }
        to_text(&grid)
    }

    fn area2(p: [[i64; 2]; 3]) -> i128 {
        (p[1][0] - p[0][0]) as i128 * (p[2][1] - p[0][1]) as i128
            - (p[2][0] - p[0][0]) as i128 * (p[1][1] - p[0][1]) as i128
    }

    fn to_text(grid: &[[u8; 16]; 16]) -> String {
        let mut s = String::new();
        for row in grid {
            for &c in row {
                s.push(match c {
                    0 => '.',
                    1 => '#',
                    _ => '2',
                });
            }
            s.push('\n');
        }
        s
    }

    /// Expected patterns are written as 16 rows; trailing all-dot rows may be omitted.
    fn expect(rows: &[&str]) -> String {
        let mut s = String::new();
        for i in 0..16 {
            s.push_str(rows.get(i).copied().unwrap_or("................"));
            s.push('\n');
        }
        s
    }

    #[test]
    fn square_split_on_the_diagonal() {
        // Upper-left half: the hypotenuse is a right edge, centres on it (x + y = 3) excluded.
        let a = pattern([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]);
        assert_eq!(
            a,
            expect(&["###.............", "##..............", "#..............."])
        );
        // Lower-right half: the hypotenuse is a left edge, centres on it included.
        let b = pattern([[4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]);
        assert_eq!(
            b,
            expect(&[
                "...#............",
                "..##............",
                ".###............",
                "####............",
            ])
        );
    }

    #[test]
    fn edges_through_pixel_centres() {
        // A right triangle whose legs run through pixel centres: the top edge (y = 1.5) and the
        // left edge (x = 1.5) are included, the hypotenuse x + y = 7 (a right edge) is not.
        let t = pattern([[1.5, 1.5], [5.5, 1.5], [1.5, 5.5]]);
        assert_eq!(
            t,
            expect(&[
                "................",
                ".####...........",
                ".###............",
                ".##.............",
                ".#..............",
            ])
        );
        // The same triangle mirrored: legs at y = 5.5 (bottom edge: excluded) and x = 5.5
        // (right edge: excluded); the hypotenuse x + y = 7 is now a left edge: included. Row 1
        // only holds the top vertex (5.5, 1.5), on the hypotenuse and the right leg: excluded.
        let m = pattern([[5.5, 1.5], [5.5, 5.5], [1.5, 5.5]]);
        assert_eq!(
            m,
            expect(&[
                "................",
                "................",
                "....#...........",
                "...##...........",
                "..###...........",
            ])
        );
    }

    #[test]
    fn thin_and_subpixel_triangles() {
        // No pixel centre inside: nothing is drawn.
        assert_eq!(pattern([[2.1, 2.1], [2.4, 2.1], [2.1, 2.4]]), expect(&[]));
        // A tiny triangle around the centre (3.5, 2.5): exactly one pixel.
        assert_eq!(
            pattern([[3.4, 2.4], [3.7, 2.4], [3.4, 2.7]]),
            expect(&["................", "................", "...#............"])
        );
        // A sliver along the column of centres x = 6.5, from y = 0 to y = 8: its left edge
        // (x = 6.5) passes through the centres, which are included.
        assert_eq!(
            pattern([[6.5, 0.0], [6.75, 8.0], [6.5, 8.0]]),
            expect(&[
                "......#.........",
                "......#.........",
                "......#.........",
                "......#.........",
                "......#.........",
                "......#.........",
                "......#.........",
                "......#.........",
            ])
        );
        // ... mirrored: the centres are on its right edge, so nothing is drawn.
        assert_eq!(pattern([[6.5, 0.0], [6.5, 8.0], [6.25, 8.0]]), expect(&[]));
    }

    #[test]
    fn pointy_vertices_on_centres() {
        // A diamond of four triangles around (8.5, 8.5), all vertices on pixel centres.
        let c = [8.5, 8.5];
        let ring = [[8.5, 4.5], [12.5, 8.5], [8.5, 12.5], [4.5, 8.5]];
        let mut grid = [[0u8; 16]; 16];
        for i in 0..4 {
            let tri = [c, ring[i], ring[(i + 1) % 4]].map(|v| [px(v[0]), px(v[1])]);
            for_each_run(&Coverage::new(tri), Rect::from_size(16, 16), |y, a, b| {
                for x in a..b {
                    grid[y as usize][x as usize] += 1;
                }
            });
        }
        // The diamond |x + 0.5 - 8.5| + |y + 0.5 - 8.5| <= 4 with the top-left rule: its two
        // left boundary edges are included, the two right ones excluded, so row 8 + dy covers
        // [8 - k, 8 + k) with k = 4 - |dy|. The top vertex (8, 4) is a pointy top (on a left
        // and a right edge: excluded), the bottom vertex row is excluded, the left vertex is
        // included and the right vertex excluded. Internal edges: every pixel exactly once.
        assert_eq!(
            to_text(&grid),
            expect(&[
                "................",
                "................",
                "................",
                "................",
                "................",
                ".......##.......",
                "......####......",
                ".....######.....",
                "....########....",
                ".....######.....",
                "......####......",
                ".......##.......",
                "................",
            ])
        );
    }

    #[test]
    fn matches_edge_function_reference_on_a_grid() {
        // Every triangle with vertices on a coarse half-pixel lattice of a 6x6 region.
        let coords: Vec<i64> = (0..7).map(|i| i * 8 + 16).collect();
        let pts: Vec<[i64; 2]> = coords
            .iter()
            .flat_map(|&x| coords.iter().map(move |&y| [x, y]))
            .collect();
        let mut checked = 0;
        for (i, &a) in pts.iter().enumerate().step_by(3) {
            for (j, &b) in pts.iter().enumerate().skip(1).step_by(2) {
                for &c in pts.iter().skip((i + j) % 5).step_by(5) {
                    let tri = [a, b, c];
                    let mut grid = [[0u8; 16]; 16];
                    if area2(tri) != 0 {
                        for_each_run(&Coverage::new(tri), Rect::from_size(16, 16), |y, xa, xb| {
                            for x in xa..xb {
                                grid[y as usize][x as usize] += 1;
                            }
                        });
                    }
                    for y in 0..16 {
                        for x in 0..16 {
                            let r = reference_covered(tri, 16 * x + 8, 16 * y + 8);
                            assert_eq!(grid[y as usize][x as usize], r as u8, "{tri:?} {x} {y}");
                        }
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000);
    }
}
