//! The uniform layout of a scene's quads in the atlas ([`UniformLayout`]) and the atlas
//! position of a solid point of a quad half ([`QuadAtlas`]).

use super::*;

/// A uniform atlas layout of `quads` mesh quads: quad `q`'s two triangles share the block
/// `q % cols, q / cols` of `(leg + 2g + 1) x (leg + 2g)` texels (`texcore::atlas`), the
/// largest leg that fits. Built by [`UniformLayout::new`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UniformLayout {
    leg: u16,
    pub(super) cols: u16,
    pub(super) quads: u32,
}

impl UniformLayout {
    /// The layout of `quads` quads in a [`SIDE`] x [`SIDE`] atlas with [`GUTTER`]; `None` when
    /// not even a leg of 1 fits.
    pub fn new(quads: u32) -> Option<UniformLayout> {
        let g = u32::from(GUTTER);
        let mut best = None;
        for leg in 1..u32::from(SIDE) {
            let (w, h) = (leg + 2 * g + 1, leg + 2 * g);
            let (cols, rows) = (u32::from(SIDE) / w, u32::from(SIDE) / h);
            if cols * rows < quads {
                break;
            }
            best = Some(UniformLayout {
                leg: leg as u16,
                cols: cols as u16,
                quads,
            });
        }
        best
    }

    /// The leg of every triangle, in texels.
    pub fn leg(&self) -> u16 {
        self.leg
    }

    /// Block width and height.
    pub(super) fn block(&self) -> (u16, u16) {
        let g = u16::from(GUTTER);
        (self.leg + 2 * g + 1, self.leg + 2 * g)
    }

    /// The atlas triangle of half `half` of quad `q` with solid corners `solid` (right angle,
    /// along `u`, along `v`).
    pub fn triangle(&self, q: u32, half: Half, solid: [TexPoint; 3]) -> Option<AtlasTriangle> {
        if q >= self.quads {
            return None;
        }
        let (w, h) = self.block();
        let cols = u32::from(self.cols);
        let x = q.checked_rem(cols)? as u16 * w;
        let y = q.checked_div(cols)? as u16 * h;
        AtlasTriangle::new(x, y, w, h, self.leg, GUTTER, half, solid).ok()
    }
}

/// The corners of a quad's halves in atlas order (right angle, along `u`, along `v`): the upper
/// half is the quad's first triangle `(c0, c1, c2)` with its right angle at `c1`, the lower half
/// the second `(c0, c2, c3)` with its right angle at `c3`; both hypotenuses are `c0 c2`.
pub(super) const HALF_CORNERS: [(Half, [usize; 3]); 2] =
    [(Half::Upper, [1, 2, 0]), (Half::Lower, [3, 0, 2])];

/// One quad as the draw needs it: its corners' solid coordinates and, per half, whether it is a
/// triangle and its corners' atlas positions (raw `Q16.16` texels, inset:
/// `AtlasTriangle::inset_corners`).
#[derive(Clone, Copy, Default)]
pub(super) struct QuadAtlas {
    solid: [[i32; 3]; 4],
    live: [bool; 2],
    uv: [[[i32; 2]; 3]; 2],
}

/// The solid coordinates of quad `q` of object `o` and whether each half is a triangle.
pub(super) fn quad_solid(o: &Object, q: u32) -> Option<([[i32; 3]; 4], [bool; 2])> {
    let c = o.mesh.quad(q)?;
    let distinct = |a: usize, b: usize, d: usize| c[a] != c[b] && c[b] != c[d] && c[d] != c[a];
    let solid = c.map(|p| o.tex_map.apply_point(TexPoint::from_bits(p.x, p.y, p.z)));
    Some((solid, [distinct(0, 1, 2), distinct(0, 2, 3)]))
}

pub(super) fn tex(s: [i32; 3]) -> TexPoint {
    TexPoint::from_bits(s[0], s[1], s[2])
}

impl QuadAtlas {
    pub(super) fn new(layout: &UniformLayout, o: &Object, group: u32, q: u32) -> Option<QuadAtlas> {
        let (solid, live) = quad_solid(o, q)?;
        let mut uv = [[[0i32; 2]; 3]; 2];
        for (k, (half, idx)) in HALF_CORNERS.iter().enumerate() {
            let t = layout.triangle(group, *half, idx.map(|i| tex(solid[i & 3])))?;
            uv[k] = t.inset_corners();
        }
        Some(QuadAtlas { solid, live, uv })
    }

    /// The solid triangle of half `k`.
    fn half_solid(&self, k: usize) -> [[i32; 3]; 3] {
        HALF_CORNERS[k & 1].1.map(|i| self.solid[i & 3])
    }

    /// Atlas position of solid point `p` in half `k`.
    pub(super) fn atlas_of(&self, k: usize, p: [i32; 3]) -> [i32; 2] {
        let s = self.half_solid(k);
        let uv = self.uv[k & 1];
        for (c, a) in s.iter().zip(uv) {
            if *c == p {
                return a;
            }
        }
        let (b, g) = bary(&s, p).unwrap_or((0, 0));
        let lerp = |j: usize| {
            let a0 = i64::from(uv[0][j]);
            let d1 = i64::from(uv[1][j]) - a0;
            let d2 = i64::from(uv[2][j]) - a0;
            (a0 + ((b * d1 + g * d2) >> 16)) as i32
        };
        [lerp(0), lerp(1)]
    }

    /// The half a screen triangle (its vertices' solid coordinates) belongs to.
    pub(super) fn half_of(&self, v: &[[i32; 3]; 3]) -> usize {
        match self.live {
            [true, false] => return 0,
            [false, true] => return 1,
            _ => {}
        }
        let all_in = |k: usize| {
            let s = self.half_solid(k);
            v.iter().all(|p| s.contains(p))
        };
        if all_in(0) {
            return 0;
        }
        if all_in(1) {
            return 1;
        }
        // Constant indices only (no bounds check survives at opt-level "z": panic-never).
        let m = |a: i32, b: i32, c: i32| ((i64::from(a) + i64::from(b) + i64::from(c)) / 3) as i32;
        let centroid = [
            m(v[0][0], v[1][0], v[2][0]),
            m(v[0][1], v[1][1], v[2][1]),
            m(v[0][2], v[1][2], v[2][2]),
        ];
        match bary(&self.half_solid(0), centroid) {
            // A small tolerance (1/256): a centroid on the shared diagonal belongs to either.
            Some((b, g)) if b >= -256 && g >= -256 && b + g <= (1 << 16) + 256 => 0,
            _ => 1,
        }
    }
}

/// Barycentric coordinates `(beta, gamma)` (`Q16`) of `p` in solid triangle `s`, in the plane
/// of the two axes the triangle's normal is least along; `None` for a degenerate triangle.
fn bary(s: &[[i32; 3]; 3], p: [i32; 3]) -> Option<(i64, i64)> {
    let sub = |a: [i32; 3], b: [i32; 3]| {
        [
            i64::from(a[0]) - i64::from(b[0]),
            i64::from(a[1]) - i64::from(b[1]),
            i64::from(a[2]) - i64::from(b[2]),
        ]
    };
    let (mut e1, mut e2, mut d) = (sub(s[1], s[0]), sub(s[2], s[0]), sub(p, s[0]));
    // A common shift so that every component is below 2^20 (products below 2^41, shifted
    // numerators below 2^57).
    let max = e1
        .iter()
        .chain(&e2)
        .chain(&d)
        .fold(0u64, |m, v| m | v.unsigned_abs());
    let shift = (64 - max.leading_zeros()).saturating_sub(20);
    for v in e1.iter_mut().chain(e2.iter_mut()).chain(d.iter_mut()) {
        *v >>= shift;
    }
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let k = if n[0].abs() >= n[1].abs() && n[0].abs() >= n[2].abs() {
        0
    } else if n[1].abs() >= n[2].abs() {
        1
    } else {
        2
    };
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let den = e1[i] * e2[j] - e1[j] * e2[i];
    if den == 0 {
        return None;
    }
    let bn = d[i] * e2[j] - d[j] * e2[i];
    let gn = e1[i] * d[j] - e1[j] * d[i];
    // (`checked_div`: no panic path; `den` is not 0 here and the quotients fit.)
    Some(((bn << 16).checked_div(den)?, (gn << 16).checked_div(den)?))
}
