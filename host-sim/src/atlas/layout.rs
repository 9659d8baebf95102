//! Atlas layouts (Carr & Hart 2002, sections 3 and 4): where each mesh triangle goes in an
//! `H x H` atlas, as texcore [`AtlasTriangle`]s, and the paper's two quality measures.
//!
//! Every triangle becomes an isosceles right triangle of integer leg `L`; two consecutive
//! triangles share a block of `(L + 2g + 1) x (L + 2g)` texels (texcore's geometry, gutter
//! `g`: 0 for nearest look-ups, 1 for bilinear and MIP). The kinds:
//!
//! - **uniform**: every leg equal, blocks in rows. For `M` triangles (`P = ceil(M/2)` pairs) the
//!   leg is the largest `L` with `floor(H / (L + 2g + 1)) * floor(H / (L + 2g)) >= P`;
//!   without gutter and over-scan this is the paper's `a = floor(H / ceil(sqrt(M/2)))` (pairs of
//!   side `a` in `sqrt(M/2)` rows and columns, the paper's equation 3 as restored);
//! - **area**-weighted: triangles by non-increasing area, legs `max(1, floor(k sqrt(area)))`
//!   packed in shelves (each shelf as high as its first block), `k` the largest that fits;
//! - **length**-weighted: the same with the longest edge for `sqrt(area)`;
//! - **mip**: square power-of-two blocks of side `S = H / 2^levels` in Z order, pairs ordered
//!   by the balanced quadtree partition ([`super::partition`]), so each quadtree node is one
//!   square of the atlas and its MIP texels average neighbouring faces.
//!
//! The measures (section 3.3, 3.4) with the atlas as the unit square: coverage
//! `C = sum A(u_j)` and relative scale `S^2 = (sum A(x_j)) (1/M) sum A(u_j) / A(x_j)`.

use texcore::atlas::{AtlasTriangle, Half};
use texcore::format::TexPoint;

use super::partition::Partition;
use crate::mesh::{longest_edge, triangle_area, TriMesh};

/// How far inside its atlas triangle a mesh triangle's atlas coordinates lie, in texels
/// ([`Layout::uv`]).
pub const INSET: f64 = texcore::atlas::INSET as f64 / 65536.0;

/// The layout kinds (`--kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AtlasKind {
    /// Every triangle the same size.
    Uniform,
    /// Legs proportional to the square root of the triangle's area.
    Area,
    /// Legs proportional to the triangle's longest edge.
    Length,
    /// Power-of-two blocks in a balanced quadtree (MIP-mappable).
    Mip,
}

/// The kind as spelled on the command line (`--kind`).
impl core::fmt::Display for AtlasKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            AtlasKind::Uniform => "uniform",
            AtlasKind::Area => "area",
            AtlasKind::Length => "length",
            AtlasKind::Mip => "mip",
        })
    }
}

/// Why a layout cannot be made.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LayoutError {
    /// The atlas is too small for the mesh at the smallest leg.
    #[error("{triangles} triangles do not fit a {size}x{size} atlas ({why})")]
    TooSmall {
        /// Triangles of the mesh.
        triangles: usize,
        /// Atlas side.
        size: u32,
        /// The limit met.
        why: String,
    },
    /// Size out of range.
    #[error("atlas size {0} out of range (8..=4096{1})")]
    Size(u32, &'static str),
}

/// A mesh's atlas.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Side in texels.
    pub size: u32,
    /// Kind.
    pub kind: AtlasKind,
    /// Gutter (0 or 1).
    pub gutter: u8,
    /// One atlas triangle per mesh triangle, in mesh order.
    pub triangles: Vec<AtlasTriangle>,
    /// For each mesh triangle, the mesh corner (0..3) at the atlas triangle's right angle,
    /// along-`u` and along-`v` corners.
    pub corners: Vec<[u8; 3]>,
}

/// Solid texture coordinates of a mesh point: the mesh's bounding box mapped to `[-1, 1]`
/// on its longest axis (centred), `Q16.16`.
pub fn solid_map(mesh: &TriMesh) -> impl Fn([f64; 3]) -> TexPoint {
    let [lo, hi] = mesh.bounds();
    let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let half = (0..3).map(|k| 0.5 * (hi[k] - lo[k])).fold(1e-9, f64::max);
    move |p| {
        let q = |k: usize| ((p[k] - c[k]) / half * 65536.0).round() as i32;
        TexPoint::from_bits(q(0), q(1), q(2))
    }
}

/// The corner order putting the largest angle at the right angle (least distortion), keeping
/// the winding: `[right, along u, along v]`.
fn corner_order(p: [[f64; 3]; 3]) -> [u8; 3] {
    let mut best = 0usize;
    let mut best_cos = f64::INFINITY;
    for k in 0..3 {
        let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let dot = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
        let n =
            (e1.iter().map(|x| x * x).sum::<f64>() * e2.iter().map(|x| x * x).sum::<f64>()).sqrt();
        let cos = dot / n.max(1e-300);
        if cos < best_cos {
            best_cos = cos;
            best = k;
        }
    }
    [best as u8, ((best + 1) % 3) as u8, ((best + 2) % 3) as u8]
}

/// A placed block: origin, size, leg.
#[derive(Clone, Copy, Debug)]
struct Block {
    x: u32,
    y: u32,
    w: u32,
    h: u32,
    leg: u32,
}

/// Shelf packing of blocks with the given legs (in order): `None` if they do not fit.
fn shelves(legs: &[u32], size: u32, g: u32) -> Option<Vec<Block>> {
    let mut out = Vec::with_capacity(legs.len());
    let (mut x, mut y, mut row_h) = (0u32, 0u32, 0u32);
    for &leg in legs {
        let (w, h) = (leg + 2 * g + 1, leg + 2 * g);
        if w > size {
            return None;
        }
        if x + w > size {
            y += row_h;
            x = 0;
            row_h = 0;
        }
        if row_h == 0 {
            row_h = h;
        }
        if y + h > size || h > row_h {
            return None;
        }
        out.push(Block { x, y, w, h, leg });
        x += w;
    }
    Some(out)
}

impl Layout {
    /// Lays out `mesh` in a `size x size` atlas of `kind` with gutter `gutter` (0 or 1), solid
    /// coordinates from [`solid_map`].
    pub fn new(
        mesh: &TriMesh,
        kind: AtlasKind,
        size: u32,
        gutter: u8,
    ) -> Result<Layout, LayoutError> {
        Layout::with_solid(mesh, kind, size, gutter, &solid_map(mesh))
    }

    /// [`Layout::new`] with the solid coordinates of each mesh point given by `solid`.
    pub fn with_solid(
        mesh: &TriMesh,
        kind: AtlasKind,
        size: u32,
        gutter: u8,
        solid: &dyn Fn([f64; 3]) -> TexPoint,
    ) -> Result<Layout, LayoutError> {
        if !(8..=4096).contains(&size) {
            return Err(LayoutError::Size(size, ""));
        }
        if kind == AtlasKind::Mip && !size.is_power_of_two() {
            return Err(LayoutError::Size(size, ", a power of two for mip"));
        }
        let g = gutter.min(1) as u32;
        let m = mesh.triangles().len();
        let too_small = |why: String| LayoutError::TooSmall {
            triangles: m,
            size,
            why,
        };
        // Pairs: lists of one or two mesh triangles, and their blocks.
        let (pairs, blocks): (Vec<[Option<usize>; 2]>, Vec<Block>) = match kind {
            AtlasKind::Uniform => {
                let pairs: Vec<_> = (0..m)
                    .step_by(2)
                    .map(|i| [Some(i), (i + 1 < m).then_some(i + 1)])
                    .collect();
                let fits = |l: u32| {
                    (size / (l + 2 * g + 1)) as usize * (size / (l + 2 * g)) as usize >= pairs.len()
                };
                let leg = (1..size)
                    .rev()
                    .find(|&l| fits(l))
                    .ok_or_else(|| too_small(format!("{} pairs even at leg 1", pairs.len())))?;
                let blocks = shelves(&vec![leg; pairs.len()], size, g)
                    .ok_or_else(|| too_small("shelves".into()))?;
                (pairs, blocks)
            }
            AtlasKind::Area | AtlasKind::Length => {
                let weight = |t: usize| {
                    let [a, b, c] = mesh.corners(t);
                    if kind == AtlasKind::Area {
                        triangle_area(a, b, c).sqrt()
                    } else {
                        longest_edge(a, b, c)
                    }
                };
                let mut order: Vec<usize> = (0..m).collect();
                let w: Vec<f64> = (0..m).map(weight).collect();
                order.sort_by(|&a, &b| w[b].total_cmp(&w[a]).then(a.cmp(&b)));
                let pairs: Vec<_> = order
                    .chunks(2)
                    .map(|c| [Some(c[0]), c.get(1).copied()])
                    .collect();
                let legs_for = |k: f64| -> Vec<u32> {
                    pairs
                        .iter()
                        .map(|p| ((k * w[p[0].unwrap_or(0)]).floor() as u32).clamp(1, size))
                        .collect()
                };
                let mut lo = 0.0f64;
                let mut hi = 1.0f64;
                // Grow hi until it does not fit (or the cap).
                let max_w = w.iter().copied().fold(1e-300, f64::max);
                hi = hi.max(size as f64 / max_w);
                if shelves(&legs_for(lo), size, g).is_none() {
                    return Err(too_small(format!("{} pairs even at leg 1", pairs.len())));
                }
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if shelves(&legs_for(mid), size, g).is_some() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let blocks =
                    shelves(&legs_for(lo), size, g).ok_or_else(|| too_small("k".into()))?;
                (pairs, blocks)
            }
            AtlasKind::Mip => {
                let p = Partition::new(mesh.triangles());
                let side = size >> p.levels;
                if side < 2 * g + 2 {
                    return Err(too_small(format!(
                        "a {}-level quadtree leaves {side}-texel squares, below {}",
                        p.levels,
                        2 * g + 2
                    )));
                }
                let leg = side - 2 * g - 1;
                let mut pairs = Vec::new();
                let mut blocks = Vec::new();
                for (leaf, pair) in p.order.chunks(2).enumerate() {
                    let get = |k: usize| pair.get(k).copied().filter(|&f| f != u32::MAX);
                    let (a, b) = (get(0), get(1));
                    let pr = match (a, b) {
                        (Some(a), b) => [Some(a as usize), b.map(|b| b as usize)],
                        (None, Some(b)) => [Some(b as usize), None],
                        (None, None) => continue,
                    };
                    let (zx, zy) = morton(leaf as u32);
                    pairs.push(pr);
                    blocks.push(Block {
                        x: zx * side,
                        y: zy * side,
                        w: side,
                        h: side,
                        leg,
                    });
                }
                (pairs, blocks)
            }
        };
        let mut triangles = vec![None; m];
        let mut corners = vec![[0u8, 1, 2]; m];
        for (pair, b) in pairs.iter().zip(&blocks) {
            for (slot, half) in pair.iter().zip([Half::Upper, Half::Lower]) {
                let Some(t) = *slot else { continue };
                let p = mesh.corners(t);
                let order = corner_order(p);
                let s = order.map(|k| solid(p[k as usize]));
                let at = AtlasTriangle::new(
                    b.x as u16,
                    b.y as u16,
                    b.w as u16,
                    b.h as u16,
                    b.leg as u16,
                    g as u8,
                    half,
                    s,
                )
                .map_err(|e| too_small(e.to_string()))?;
                triangles[t] = Some(at);
                corners[t] = order;
            }
        }
        let triangles = triangles
            .into_iter()
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| too_small("a triangle was not placed".into()))?;
        Ok(Layout {
            size,
            kind,
            gutter: g as u8,
            triangles,
            corners,
        })
    }

    /// The atlas coordinates (texels, `f64`, exact multiples of `2^-16`) of mesh triangle
    /// `t`'s corners in mesh corner order: texcore's
    /// [`AtlasTriangle::inset_corners`], [`INSET`] texels inside the legs and the hypotenuse,
    /// the same points the device draws with and texcore's ownership test samples. A
    /// renderer's rounding (a few `2^-16` texel) then never carries a look-up across an edge.
    pub fn uv(&self, t: usize) -> [[f64; 2]; 3] {
        let p = self.triangles[t]
            .inset_corners()
            .map(|q| q.map(|v| f64::from(v) / 65536.0));
        let mut out = [[0.0; 2]; 3];
        for (q, &corner) in p.iter().zip(&self.corners[t]) {
            out[corner as usize] = *q;
        }
        out
    }

    /// Coverage `C` (section 3.3): the atlas triangles' area over the atlas's.
    pub fn coverage(&self) -> f64 {
        let a: f64 = self
            .triangles
            .iter()
            .map(|t| 0.5 * (t.leg() as f64).powi(2))
            .sum();
        a / (self.size as f64).powi(2)
    }

    /// Relative scale `S` (section 3.4).
    pub fn relative_scale(&self, mesh: &TriMesh) -> f64 {
        let m = self.triangles.len() as f64;
        let mut surface = 0.0;
        let mut ratio = 0.0;
        for (t, at) in self.triangles.iter().enumerate() {
            let [a, b, c] = mesh.corners(t);
            let ax = triangle_area(a, b, c);
            let au = 0.5 * (at.leg() as f64 / self.size as f64).powi(2);
            surface += ax;
            ratio += au / ax;
        }
        (surface * ratio / m).sqrt()
    }
}

/// The `(x, y)` of Z-order index `i`.
pub fn morton(i: u32) -> (u32, u32) {
    let mut x = 0;
    let mut y = 0;
    for b in 0..16 {
        x |= ((i >> (2 * b)) & 1) << b;
        y |= ((i >> (2 * b + 1)) & 1) << b;
    }
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_and_samplings_display_as_their_command_line_names() {
        use clap::ValueEnum;
        for k in AtlasKind::value_variants() {
            let name = k.to_possible_value().unwrap();
            assert_eq!(k.to_string(), name.get_name());
        }
        for k in crate::atlas::Sampling::value_variants() {
            let name = k.to_possible_value().unwrap();
            assert_eq!(k.to_string(), name.get_name());
        }
    }

    /// Two unit right triangles (a unit square) and a 2 x 1 rectangle.
    fn tiny() -> TriMesh {
        TriMesh::from_parts(
            "tiny",
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [3.0, 0.0, 0.0],
                [3.0, 1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]],
        )
        .unwrap()
    }

    /// Hand-computed: 4 triangles, 2 pairs, size 16, gutter 1: blocks (L + 3) x (L + 2),
    /// floor(16 / (L + 3)) * floor(16 / (L + 2)) >= 2 holds up to L = 6 (1 * 2). Coverage
    /// 4 * 18 / 256 = 0.28125. Areas 0.5, 0.5, 1, 1 (total 3); atlas areas 18/256 each:
    /// S^2 = 3 * (1/4) * (18/256) * (2/0.5 + 2/1) = 0.31640625, S = 0.5625.
    #[test]
    fn uniform_metrics_by_hand() {
        let l = Layout::new(&tiny(), AtlasKind::Uniform, 16, 1).unwrap();
        assert!(l.triangles.iter().all(|t| t.leg() == 6));
        assert!((l.coverage() - 0.28125).abs() < 1e-12);
        assert!((l.relative_scale(&tiny()) - 0.5625).abs() < 1e-12);
        // Nearest-only: blocks (L + 1) x L: L = 8 (1 * floor(16 / 8) = 2 blocks).
        let l = Layout::new(&tiny(), AtlasKind::Uniform, 16, 0).unwrap();
        assert!(l.triangles.iter().all(|t| t.leg() == 8));
    }

    /// Area weighting gives the larger triangles the longer legs.
    #[test]
    fn weighted_kinds_favour_large_triangles() {
        for kind in [AtlasKind::Area, AtlasKind::Length] {
            let l = Layout::new(&tiny(), kind, 32, 1).unwrap();
            assert!(l.triangles[2].leg() >= l.triangles[0].leg(), "{kind:?}");
            assert!(l.coverage() > 0.0 && l.coverage() <= 1.0);
        }
    }

    #[test]
    fn morton_order() {
        assert_eq!(
            (0..4).map(morton).collect::<Vec<_>>(),
            [(0, 0), (1, 0), (0, 1), (1, 1)]
        );
        assert_eq!(morton(4), (2, 0));
    }

    #[test]
    fn too_small_is_an_error() {
        let e = Layout::new(&tiny(), AtlasKind::Uniform, 8, 1);
        assert!(e.is_ok());
        assert!(Layout::new(&tiny(), AtlasKind::Mip, 12, 1).is_err());
        assert!(Layout::new(&tiny(), AtlasKind::Uniform, 4, 1).is_err());
    }
}
