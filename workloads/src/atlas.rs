//! Drawing a built-in scene from meshed texture atlases on the device (Carr & Hart 2002): every
//! mesh quad of the scene gets a block of a [`SIDE`] x [`SIDE`] RGB565 atlas in RAM (a uniform
//! layout, [`UniformLayout`]), the object's texture is baked into it once with texcore's bake
//! kernel (`texcore::atlas::bake`: row spans of the span evaluator, the filter width from the
//! texel's footprint on the surface), then the frame is drawn in bands of
//! [`DRAW_ROWS`] rows with texcore's textured-triangle path (`Rasterizer::draw_textured`:
//! the rasterizer's coverage and depth test, atlas coordinates interpolated
//! perspective-correctly at every pixel, the nearest atlas texel written into the band).
//!
//! The frame is walked once: the scene's walk projects every quad, and the quads drawn are kept
//! in a *frame list* ([`FrameQuad`]: projected corners, 46 bytes a quad) from which every band
//! draws the quads that touch it (found through a band index, `BandIndex`), so no band walks
//! the scene, generates a mesh quad or projects a corner again (a frame the list cannot hold
//! exactly takes the general way: every band walks the quads its bins name, as the procedural
//! renderer does).
//!
//! Memory: the atlas is caller-owned frame memory like the band buffers (32 KB for 128 x 128
//! RGB565, on the job's stack), not texture-unit state; the RGB565 band and its depth band
//! ([`DRAW_PIXELS`] x 2 bytes each, taller bands than the procedural renderer's: a triangle is
//! set up once per band it touches), the frame list ([`FRAME_QUADS`] entries, 23.7 KB) and its
//! band index ([`FRAME_REFS`] entries, 1.6 KB) are on the stack too, the quad bins are the
//! suite's. On the Cortex-M4F the draw job peaks at about 102 KB of the 109 KB stack (the scene
//! walk's corner store included): bands of 24 rows with the list would not fit.
//!
//! Atlas coordinates of a screen vertex: the scene's walk hands over screen triangles whose
//! vertices carry solid coordinates. A vertex of an unclipped triangle carries exactly the solid
//! coordinates of one of its quad's corners, whose atlas position is known; a vertex made by
//! clipping gets its atlas position from its barycentric coordinates in the quad half's solid
//! triangle (integer, `Q16` fractions). The half of a screen triangle is the one whose corners
//! its vertices are, or (clipped) the one whose solid triangle holds its centroid.
//!
//! Exactness: integer arithmetic only, the same code on the host and both devices, so the
//! device's checksums equal the host's (`tests/tests/firmware_qemu.rs`). Atlas drawing is an
//! approximation of procedural shading (a *named* mode); its error against the procedural frame
//! is measured on the host (`texsim render --via-atlas`, `docs/atlas.md`). Every object is drawn
//! opaque. Nothing allocates; nothing panics.

use texcore::atlas::{bake, AtlasTriangle, Half};
use texcore::color::Rgba8888;
use texcore::format::TexPoint;
use texcore::hash::HashKind;
use texcore::raster::{
    fill_u16, DepthBuffer, DepthFunc, InvW, Rasterizer, Rect, ScreenCoord, ScreenVertex,
    Texture565, TriangleSetup,
};
use texcore::render::{GroupRows, TriangleSource};
use texcore::scene::{Object, Scene};
use texcore::sink::ChecksumSink;

use crate::scenes::{builtin_frame, slot_texture, FRAME_START, WIDTH};

/// Side of the device atlas in texels.
pub const SIDE: u16 = 128;
/// Texels of the device atlas (`SIDE * SIDE`, 32 KB of RGB565).
pub const TEXELS: usize = SIDE as usize * SIDE as usize;
/// Gutter of the device layout: 0, the paper's atlas for nearest look-ups.
pub const GUTTER: u8 = 0;
/// Rows of a band of the atlas draw.
pub const DRAW_ROWS: u16 = 16;
/// Pixels of a band of the atlas draw (and entries of its depth band): the widest scene's.
pub const DRAW_PIXELS: usize = WIDTH as usize * DRAW_ROWS as usize;
/// The built-in scene the atlas jobs draw.
pub const SCENE: &str = "marble";

/// The RGB565 texels of a device atlas, row-major.
pub type AtlasTexels = [u16; TEXELS];

/// A uniform atlas layout of `quads` mesh quads: quad `q`'s two triangles share the block
/// `q % cols, q / cols` of `(leg + 2g + 1) x (leg + 2g)` texels (`texcore::atlas`), the
/// largest leg that fits. Built by [`UniformLayout::new`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UniformLayout {
    leg: u16,
    cols: u16,
    quads: u32,
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
    fn block(&self) -> (u16, u16) {
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
const HALF_CORNERS: [(Half, [usize; 3]); 2] = [(Half::Upper, [1, 2, 0]), (Half::Lower, [3, 0, 2])];

/// One quad as the draw needs it: its corners' solid coordinates and, per half, whether it is a
/// triangle and its corners' atlas positions (raw `Q16.16` texels, inset:
/// `AtlasTriangle::inset_corners`).
#[derive(Clone, Copy, Default)]
struct QuadAtlas {
    solid: [[i32; 3]; 4],
    live: [bool; 2],
    uv: [[[i32; 2]; 3]; 2],
}

/// The solid coordinates of quad `q` of object `o` and whether each half is a triangle.
fn quad_solid(o: &Object, q: u32) -> Option<([[i32; 3]; 4], [bool; 2])> {
    let c = o.mesh.quad(q)?;
    let distinct = |a: usize, b: usize, d: usize| c[a] != c[b] && c[b] != c[d] && c[d] != c[a];
    let solid = c.map(|p| o.tex_map.apply_point(TexPoint::from_bits(p.x, p.y, p.z)));
    Some((solid, [distinct(0, 1, 2), distinct(0, 2, 3)]))
}

fn tex(s: [i32; 3]) -> TexPoint {
    TexPoint::from_bits(s[0], s[1], s[2])
}

impl QuadAtlas {
    fn new(layout: &UniformLayout, o: &Object, group: u32, q: u32) -> Option<QuadAtlas> {
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
    fn atlas_of(&self, k: usize, p: [i32; 3]) -> [i32; 2] {
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
    fn half_of(&self, v: &[[i32; 3]; 3]) -> usize {
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

/// The layout of `scene`'s quads (every object's, in the scene's group order).
pub fn scene_layout(scene: &Scene) -> Option<UniformLayout> {
    UniformLayout::new(u32::try_from(scene.quad_count()).ok()?)
}

/// Texels the bake writes for `scene` (every live half's owned texels).
pub fn owned_texels(scene: &Scene) -> u32 {
    let Some(layout) = scene_layout(scene) else {
        return 0;
    };
    let mut n = 0u32;
    let mut group = 0u32;
    for o in &scene.objects {
        for q in 0..o.mesh.quad_count() {
            if let Some((solid, live)) = quad_solid(o, q) {
                for ((half, idx), live) in HALF_CORNERS.iter().zip(live) {
                    let t = layout.triangle(group, *half, idx.map(|i| tex(solid[i & 3])));
                    if let (true, Some(t)) = (live, t) {
                        let (_, y, _, h) = t.block();
                        n += (y..y + h)
                            .filter_map(|j| t.row(j))
                            .map(|r| u32::from(r.1))
                            .sum::<u32>();
                    }
                }
            }
            group += 1;
        }
    }
    n
}

/// Bakes every object of `scene` into `atlas` (texels no triangle owns stay 0): per object its
/// slot's texture is built, then (with `work`) each live quad half baked. Returns the texels
/// written (`work`) or the objects whose texture was built (not `work`); 0 if the layout or a
/// texture cannot be built.
#[inline(never)]
pub fn bake_scene(scene: &Scene, hash: HashKind, atlas: &mut AtlasTexels, work: bool) -> u32 {
    let Some(layout) = scene_layout(scene) else {
        return 0;
    };
    let mut written = 0u32;
    let mut group = 0u32;
    for o in &scene.objects {
        let Some(t) = scene
            .slots
            .get(usize::from(o.slot))
            .and_then(|s| slot_texture(s, hash))
        else {
            return 0;
        };
        let t = core::hint::black_box(t);
        if !work {
            written += 1;
            group += o.mesh.quad_count();
            continue;
        }
        let mut ev = t.evaluator();
        for q in 0..o.mesh.quad_count() {
            if let Some((solid, live)) = quad_solid(o, q) {
                for ((half, idx), live) in HALF_CORNERS.iter().zip(live) {
                    let tri = layout.triangle(group, *half, idx.map(|i| tex(solid[i & 3])));
                    if let (true, Some(tri)) = (live, tri) {
                        written += bake(core::slice::from_ref(&tri), &mut ev, |x, y, c| {
                            let i = usize::from(y) * usize::from(SIDE) + usize::from(x);
                            if let Some(texel) = atlas.get_mut(i) {
                                *texel = c.to_rgb565().to_bits();
                            }
                        });
                    }
                }
            }
            group += 1;
        }
    }
    written
}

/// The checksum of an atlas: FNV-1a over its RGB565 texels, row-major.
pub fn atlas_checksum(atlas: &AtlasTexels) -> u32 {
    let mut sink = ChecksumSink::new();
    for t in atlas {
        sink.add_rgb565(*t);
    }
    sink.checksum()
}

/// The rows a screen triangle can cover in an image `h` rows high (a superset).
fn triangle_rows(tri: &[ScreenVertex; 3], h: u16) -> Option<(u16, u16)> {
    let ys = tri.map(|v| v.y.to_bits());
    let (lo, hi) = (
        ys.iter().min()?.div_euclid(16),
        ys.iter().max()?.div_euclid(16),
    );
    if hi < 0 || lo >= i32::from(h) {
        return None;
    }
    Some((lo.max(0) as u16, hi.min(i32::from(h) - 1) as u16))
}

/// Draws `scene` from `atlas` (laid out by [`scene_layout`]) in bands of [`DRAW_ROWS`] rows and
/// returns the frame's checksum (FNV-1a over its RGB565 pixels, row-major, as `ChecksumSink`);
/// 0 if the scene has no layout or the buffers are too small. See [`draw_scene_rows`].
#[inline(never)]
pub fn draw_scene(scene: &Scene, atlas: &AtlasTexels, bins: &mut [GroupRows]) -> u32 {
    let mut sink = ChecksumSink::resume(FRAME_START);
    let drawn = draw_scene_rows(scene, atlas, bins, |row| sink.add_rgb565_row(row));
    if drawn {
        sink.checksum()
    } else {
        0
    }
}

/// Quads of the frame list ([`FrameQuad`]) that [`draw_scene_rows`] keeps (46 bytes each,
/// 23.7 KB on the stack): the marble frame lists 516 (515 drawn quads, one of them in two
/// entries). A frame that lists more is drawn the general way.
pub const FRAME_QUADS: usize = 528;

/// Entries of the band index (`BandIndex`) that [`draw_scene_rows`] keeps (2 bytes each):
/// a listed quad takes one in every band its rows touch (the marble frame: about 720). A frame
/// that needs more scans the whole list in every band instead.
pub const FRAME_REFS: usize = 800;

/// Bands the band index can hold (frames up to `MAX_BANDS * DRAW_ROWS` rows; taller ones scan
/// the list in every band).
const MAX_BANDS: usize = 32;

/// The listed quads of every band, in list order: `refs[start[b]..start[b + 1]]` are the
/// indices of band `b`'s quads (a counting sort of the list by band, built once a frame), so a
/// band visits only the quads that touch it instead of testing every listed quad.
struct BandIndex<'a> {
    refs: &'a [u16],
    start: [u16; MAX_BANDS + 1],
}

impl<'a> BandIndex<'a> {
    /// The index of `list` over `bands` bands in `refs`; `None` when the bands or the entries
    /// do not fit (`refs` too short, more than [`MAX_BANDS`] bands or `u16::MAX` quads).
    fn new(list: &[FrameQuad], bands: usize, refs: &'a mut [u16]) -> Option<BandIndex<'a>> {
        if bands > MAX_BANDS || list.len() > usize::from(u16::MAX) {
            return None;
        }
        let span = |q: &FrameQuad| {
            let s = q.band_span();
            s.start..s.end.min(bands)
        };
        // Counts, shifted by one band, then their prefix sums: the first entry of each band.
        let mut start = [0u16; MAX_BANDS + 1];
        let mut total = 0usize;
        for q in list {
            for b in span(q) {
                let c = start.get_mut(b + 1)?;
                *c += 1;
                total += 1;
            }
        }
        if total > refs.len() {
            return None;
        }
        for b in 1..start.len() {
            let before = *start.get(b - 1)?;
            *start.get_mut(b)? += before;
        }
        let mut next = start;
        for (i, q) in list.iter().enumerate() {
            for b in span(q) {
                let n = next.get_mut(b)?;
                *refs.get_mut(usize::from(*n))? = i as u16;
                *n += 1;
            }
        }
        Some(BandIndex { refs, start })
    }

    /// The indices of the quads of band `b`, in list order.
    fn band(&self, b: usize) -> &[u16] {
        let (Some(&s), Some(&e)) = (self.start.get(b), self.start.get(b + 1)) else {
            return &[];
        };
        self.refs.get(usize::from(s)..usize::from(e)).unwrap_or(&[])
    }
}

/// A screen vertex of the frame list, exactly as the scene's walk made it (the atlas position is
/// the quad corner's, from the layout): sub-pixel position (`i16`: every vertex of a listed quad
/// lies within 2048 pixels of the origin), depth and `1/w` (as two halves, so that the vertex
/// packs into 10 bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct ListedVertex {
    x: i16,
    y: i16,
    z: u16,
    inv_w: [u16; 2],
}

impl ListedVertex {
    fn new(v: &ScreenVertex) -> Option<ListedVertex> {
        let w = v.inv_w.to_bits();
        Some(ListedVertex {
            x: i16::try_from(v.x.to_bits()).ok()?,
            y: i16::try_from(v.y.to_bits()).ok()?,
            z: v.z,
            inv_w: [w as u16, (w >> 16) as u16],
        })
    }

    fn vertex(&self, uv: [i32; 2]) -> ScreenVertex {
        let w = u32::from(self.inv_w[0]) | (u32::from(self.inv_w[1]) << 16);
        ScreenVertex::new(
            ScreenCoord::from_bits(i32::from(self.x)),
            ScreenCoord::from_bits(i32::from(self.y)),
            self.z,
            InvW::from_bits(w),
            TexPoint::from_bits(uv[0], uv[1], 0),
        )
    }
}

/// One quad of the frame list: the screen corners the scene's walk projected for it, and which
/// of its halves (`[0, 1, 2]`, `[0, 2, 3]`) are drawn (emitted unclipped and not culled).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameQuad {
    group: u16,
    object: u8,
    /// Bit `k`: half `k` is drawn; bit `4 + i`: corner `i` is set.
    flags: u8,
    /// First and last band (of [`DRAW_ROWS`] rows) the drawn halves can cover.
    bands: [u8; 2],
    corners: [ListedVertex; 4],
}

impl FrameQuad {
    /// An unused entry.
    pub const EMPTY: FrameQuad = FrameQuad {
        group: 0,
        object: 0,
        flags: 0,
        bands: [0, 0],
        corners: [ListedVertex {
            x: 0,
            y: 0,
            z: 0,
            inv_w: [0, 0],
        }; 4],
    };

    /// The bands the entry's drawn halves can cover (empty for an entry whose triangles cover
    /// no row: its bands stay `[u8::MAX, 0]`).
    #[inline(always)]
    fn band_span(&self) -> core::ops::Range<usize> {
        usize::from(self.bands[0])..usize::from(self.bands[1]) + 1
    }
}

/// The quad corners of each half, in the walk's triangle order.
const HALF_TRIANGLES: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// The inset atlas corners (`AtlasTriangle::inset_corners`) of every quad half of a
/// [`UniformLayout`], in the frame list's triangle order ([`HALF_TRIANGLES`]): quad 0's, moved
/// by each quad's block (the blocks of a uniform layout differ by whole texels, so the corners
/// move by whole texels too). The draw finds a listed half's corners with a division and two
/// additions instead of building its `AtlasTriangle` in every band. Exactly
/// `layout.triangle(q, half, _).inset_corners()` for every quad of the layout
/// (`half_corners_are_the_triangles`).
#[derive(Clone, Copy, Debug)]
struct HalfCorners {
    base: [[[i32; 2]; 3]; 2],
    w: u32,
    h: u32,
    cols: u32,
    quads: u32,
}

impl HalfCorners {
    fn new(layout: &UniformLayout) -> Option<HalfCorners> {
        let mut base = [[[0i32; 2]; 3]; 2];
        for ((half, idx), (b, tri)) in HALF_CORNERS.iter().zip(base.iter_mut().zip(HALF_TRIANGLES))
        {
            let uv = layout
                .triangle(0, *half, [TexPoint::ZERO; 3])?
                .inset_corners();
            for (corner, ci) in b.iter_mut().zip(tri) {
                let j = idx.iter().position(|&i| i == ci)?;
                *corner = *uv.get(j)?;
            }
        }
        let (w, h) = layout.block();
        Some(HalfCorners {
            base,
            w: u32::from(w),
            h: u32::from(h),
            cols: u32::from(layout.cols),
            quads: layout.quads,
        })
    }

    /// The corners of half `k` of quad `q` (`None` past the layout's quads).
    #[inline(always)]
    fn get(&self, q: u32, k: usize) -> Option<[[i32; 2]; 3]> {
        if q >= self.quads {
            return None;
        }
        let bx = q.checked_rem(self.cols)? * self.w;
        let by = q.checked_div(self.cols)? * self.h;
        let d = [(bx as i32).wrapping_shl(16), (by as i32).wrapping_shl(16)];
        let base = self.base.get(k)?;
        Some(base.map(|p| [p[0].wrapping_add(d[0]), p[1].wrapping_add(d[1])]))
    }
}

/// Adds the walk's triangle `t` (quad corners `corners` of group `g`, object `obj`, rows `rows`
/// as [`triangle_rows`]) to the frame list: to the last entry when that is the same quad and
/// holds the same values at the corners they share, otherwise as a new entry (the walk
/// normalises `1/w` per triangle, so a quad's two halves can disagree at their shared corners;
/// such a quad takes two entries). `false` when the triangle cannot be listed exactly (clipped,
/// a vertex past `i16`, an object or group past the entry's fields, or the list full). The
/// frame has at most 4096 rows (its bands fit a byte).
fn list_triangle(
    list: &mut [FrameQuad],
    n: &mut usize,
    g: usize,
    obj: usize,
    t: &[ScreenVertex; 3],
    corners: Option<[u8; 3]>,
    rows: Option<(u16, u16)>,
) -> bool {
    let Some(c) = corners else {
        return false;
    };
    // The bands of the rows (below 256: the caller lists frames of at most 4096 rows only).
    let bands = rows.map(|(r0, r1)| ((r0 / DRAW_ROWS) as u8, (r1 / DRAW_ROWS) as u8));
    let Some(half) = HALF_TRIANGLES.iter().position(|h| h.map(|i| i as u8) == c) else {
        return false;
    };
    let (Ok(group), Ok(object)) = (u16::try_from(g), u8::try_from(obj)) else {
        return false;
    };
    let mut lv = [ListedVertex::default(); 3];
    for (l, v) in lv.iter_mut().zip(t) {
        let Some(x) = ListedVertex::new(v) else {
            return false;
        };
        *l = x;
    }
    let fits = |q: &FrameQuad| {
        q.group == group
            && q.object == object
            && c.iter().zip(&lv).all(|(&ci, l)| {
                let i = usize::from(ci & 3);
                q.flags & (1 << (4 + i)) == 0 || q.corners[i] == *l
            })
    };
    let last = n.checked_sub(1);
    let i = match last.and_then(|i| list.get(i)) {
        Some(q) if fits(q) => last.unwrap_or(0),
        _ => {
            let Some(q) = list.get_mut(*n) else {
                return false;
            };
            // A fresh entry: no corner set (corners are read only where their bit is set, so
            // the old values need no clearing).
            q.group = group;
            q.object = object;
            q.flags = 0;
            q.bands = [u8::MAX, 0];
            *n += 1;
            *n - 1
        }
    };
    let Some(q) = list.get_mut(i) else {
        return false;
    };
    for (&ci, l) in c.iter().zip(lv) {
        let i = usize::from(ci & 3);
        q.corners[i] = l;
        q.flags |= 1 << (4 + i);
    }
    q.flags |= 1 << half;
    if let Some((b0, b1)) = bands {
        q.bands = [q.bands[0].min(b0), q.bands[1].max(b1)];
    }
    true
}

/// Draws `scene` from `atlas` (laid out by [`scene_layout`]) in bands of [`DRAW_ROWS`] rows,
/// handing every RGB565 row to `out`, top to bottom: [`draw_scene_rows_with`] with a frame list
/// of [`FRAME_QUADS`] quads and a band index of [`FRAME_REFS`] entries on the stack.
pub fn draw_scene_rows<O: FnMut(&[u16])>(
    scene: &Scene,
    atlas: &AtlasTexels,
    bins: &mut [GroupRows],
    out: O,
) -> bool {
    let mut list = [FrameQuad::EMPTY; FRAME_QUADS];
    let mut refs = [0u16; FRAME_REFS];
    draw_scene_rows_with(scene, atlas, bins, &mut list, &mut refs, out)
}

/// Draws `scene` from `atlas` (laid out by [`scene_layout`]) in bands of [`DRAW_ROWS`] rows,
/// handing every RGB565 row to `out`, top to bottom. `false` (and no row) if the scene has no
/// layout or is wider than [`WIDTH`].
///
/// One walk over the scene lists every drawn quad with its projected corners in `list` (a
/// *frame list*: the quad's atlas positions come from the layout, so nothing of the walk is
/// repeated), then every band draws the listed quads that touch it, in the walk's order: those
/// the band index in `refs` names (`BandIndex`), or, when `refs` cannot hold the index, every
/// listed quad whose bands include the band. A frame
/// the list cannot hold exactly (a clipped triangle, a vertex past 2048 pixels, more quads than
/// `list`) is drawn the general way instead: the walk bins its quads into `bins` (one per quad;
/// quads past the bins are walked in every band), and every band walks the quads that touch it
/// again. Both ways draw the same triangles in the same order, so the pixels are the same
/// (`tests/tests/atlas_device.rs`).
pub fn draw_scene_rows_with<O: FnMut(&[u16])>(
    scene: &Scene,
    atlas: &AtlasTexels,
    bins: &mut [GroupRows],
    list: &mut [FrameQuad],
    refs: &mut [u16],
    mut out: O,
) -> bool {
    let Some(layout) = scene_layout(scene) else {
        return false;
    };
    let (w, h) = scene.size();
    let wu = usize::from(w);
    if wu * usize::from(DRAW_ROWS) > DRAW_PIXELS {
        return false;
    }
    let mut depth = [0u16; DRAW_PIXELS];
    let Some(depth) = depth.get_mut(..wu * usize::from(DRAW_ROWS)) else {
        return false;
    };
    let Some(mut db) = DepthBuffer::new(depth, Rect::new(0, 0, w, DRAW_ROWS)) else {
        return false;
    };
    for b in bins.iter_mut() {
        *b = GroupRows::EMPTY;
    }
    let mut listed = 0usize;
    // A frame is listed only if its bands' numbers fit the entries' bytes.
    let bands = usize::from(h.div_ceil(DRAW_ROWS));
    let mut exact = bands <= usize::from(u8::MAX);
    scene.for_each_screen_triangle_with_corners(&mut |_| true, &mut |g, obj, tri, corners| {
        let rows = triangle_rows(tri, h);
        if let (Some(b), Some((r0, r1))) = (bins.get_mut(g), rows) {
            *b = match b.rows() {
                Some((a0, a1)) => GroupRows::new(a0.min(r0), a1.max(r1)),
                None => GroupRows::new(r0, r1),
            };
        }
        if exact {
            // A triangle the rasterizer rejects (zero area, culled) is not listed.
            let opts = scene.object(obj).map(|d| d.raster).unwrap_or_default();
            if TriangleSetup::check(tri, &opts).is_ok() {
                exact = list_triangle(list, &mut listed, g, obj, tri, corners, rows);
            }
        }
    });
    let bg = {
        let c = scene.background;
        Rgba8888::new(c[0], c[1], c[2], c[3]).to_rgb565().to_bits()
    };
    // Start group of each object (the scene's group numbering).
    let mut starts = [0u32; texcore::scene::MAX_OBJECTS];
    let mut at = 0u32;
    for (s, o) in starts.iter_mut().zip(&scene.objects) {
        *s = at;
        at += o.mesh.quad_count();
    }
    let Some(texture) = Texture565::new(atlas, SIDE) else {
        return false;
    };
    let Some(half_corners) = HalfCorners::new(&layout) else {
        return false;
    };
    let list = list.get(..listed).unwrap_or(&[]);
    let index = if exact {
        BandIndex::new(list, bands, refs)
    } else {
        None
    };
    let mut band = [0u16; DRAW_PIXELS];
    let mut raster = Rasterizer::new(Rect::from_size(w, h));
    let mut cache: Option<(usize, QuadAtlas)> = None;
    let mut y0 = 0u16;
    while y0 < h {
        let y1 = y0.saturating_add(DRAW_ROWS).min(h);
        let rect = Rect::new(0, y0, w, y1);
        raster.set_clip(rect);
        db.set_rect(rect);
        db.clear(u16::MAX);
        fill_u16(&mut band, bg);
        let mut draw = |obj: usize, v: &[ScreenVertex; 3]| {
            let Some(d) = scene.object(obj) else {
                return;
            };
            if d.depth {
                raster.draw_textured(v, &d.raster, &mut db, &texture, &mut band);
            } else {
                let mut opts = d.raster;
                opts.depth_func = DepthFunc::Always;
                opts.depth_write = false;
                raster.draw_textured(v, &opts, &mut db, &texture, &mut band);
            }
        };
        if exact {
            let mut draw_quad = |q: &FrameQuad| {
                for (k, [a, b, c]) in HALF_TRIANGLES.iter().copied().enumerate() {
                    if q.flags & (1 << k) == 0 {
                        continue;
                    }
                    // The atlas position of each corner of the half (its solid coordinates
                    // do not move it).
                    let Some([ua, ub, uc]) = half_corners.get(u32::from(q.group), k) else {
                        continue;
                    };
                    let corner = |ci: usize, uv: [i32; 2]| q.corners[ci & 3].vertex(uv);
                    draw(
                        usize::from(q.object),
                        &[corner(a, ua), corner(b, ub), corner(c, uc)],
                    );
                }
            };
            // The band's quads from the index, or (no index) every listed quad tested: one
            // loop, one call site of the quad's draw (inlined).
            let b = usize::from(y0 / DRAW_ROWS);
            let band_refs = index.as_ref().map(|ix| ix.band(b));
            let n = band_refs.map_or(list.len(), <[u16]>::len);
            for j in 0..n {
                let i = band_refs.map_or(Some(j), |r| r.get(j).map(|&i| usize::from(i)));
                let Some(q) = i.and_then(|i| list.get(i)) else {
                    continue;
                };
                if band_refs.is_none() && !q.band_span().contains(&b) {
                    continue;
                }
                draw_quad(q);
            }
        } else {
            let mut keep = |g: usize| bins.get(g).is_none_or(|b| b.touches(y0, y1));
            scene.for_each_triangle_by_quad(&mut keep, &mut |g, obj, tri| {
                let Some(o) = scene.objects.get(obj) else {
                    return;
                };
                let start = starts.get(obj).copied().unwrap_or(0);
                if cache.as_ref().is_none_or(|c| c.0 != g) {
                    let q = (g as u32).wrapping_sub(start);
                    cache = QuadAtlas::new(&layout, o, g as u32, q).map(|a| (g, a));
                }
                let Some((_, qa)) = cache.as_ref() else {
                    return;
                };
                let solid = tri.map(|v| v.tex.to_bits());
                let k = qa.half_of(&solid);
                let mut v = *tri;
                for (vert, s) in v.iter_mut().zip(solid) {
                    let [u, t] = qa.atlas_of(k, s);
                    vert.tex = TexPoint::from_bits(u, t, 0);
                }
                draw(obj, &v);
            });
        }
        for row in band.chunks(wu.max(1)).take(usize::from(y1 - y0)) {
            out(row);
        }
        y0 = y1;
    }
    true
}

/// `atlas:<SCENE>-bake` (with `work`) and its set-up: the scene's frame and its textures built,
/// the atlas zeroed; with `work` the bake, and the checksum of the whole atlas.
#[inline(never)]
pub fn bake_job(hash: HashKind, work: bool) -> u32 {
    let Some(scene) = builtin_frame(SCENE) else {
        return 0;
    };
    let scene = core::hint::black_box(scene);
    let mut atlas = [0u16; TEXELS];
    let n = bake_scene(&scene, hash, &mut atlas, work);
    if !work {
        return n;
    }
    n ^ atlas_checksum(core::hint::black_box(&atlas))
}

/// `atlas:<SCENE>` (with `work`) and its set-up: the scene's frame, textures and atlas baked;
/// with `work` the frame drawn from the atlas, returning the frame's checksum (the set-up
/// returns the texels baked).
#[inline(never)]
pub fn draw_job(hash: HashKind, work: bool, bins: &mut [GroupRows]) -> u32 {
    let Some(scene) = builtin_frame(SCENE) else {
        return 0;
    };
    let scene = core::hint::black_box(scene);
    let mut atlas = [0u16; TEXELS];
    let n = bake_scene(&scene, hash, &mut atlas, true);
    let atlas = core::hint::black_box(&atlas);
    if !work {
        return n;
    }
    draw_scene(&scene, atlas, bins)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// Every quad half's corners from [`HalfCorners`] against its `AtlasTriangle`'s, for layouts
    /// of one quad up to the most the atlas holds.
    #[test]
    fn half_corners_are_the_triangles() {
        let mut tried = 0;
        for quads in [1u32, 2, 3, 7, 64, 515, 516, 1000, 2047, 4096] {
            let Some(layout) = UniformLayout::new(quads) else {
                continue;
            };
            let table = HalfCorners::new(&layout).expect("corners of quad 0");
            for q in 0..quads {
                for (k, ((half, idx), tri)) in HALF_CORNERS.iter().zip(HALF_TRIANGLES).enumerate() {
                    let uv = layout
                        .triangle(q, *half, [TexPoint::ZERO; 3])
                        .expect("a quad of the layout")
                        .inset_corners();
                    let want = tri.map(|ci| uv[idx.iter().position(|&i| i == ci).unwrap()]);
                    assert_eq!(
                        table.get(q, k),
                        Some(want),
                        "quads {quads}, quad {q}, half {k}"
                    );
                }
            }
            assert_eq!(table.get(quads, 0), None);
            tried += 1;
        }
        assert!(tried >= 8, "layouts tried: {tried}");
    }

    /// The band index against a scan of the list, for random band ranges (empty ones
    /// included), and its refusals.
    #[test]
    fn band_index_is_the_scan() {
        let mut seed = 0x2545_f491_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        for round in 0..200 {
            let bands = 1 + (next() % MAX_BANDS as u32) as usize;
            let list: std::vec::Vec<FrameQuad> = (0..next() % 300)
                .map(|_| {
                    let b0 = (next() % (bands as u32 + 2)) as u8;
                    let b1 = if next() % 8 == 0 {
                        0
                    } else {
                        b0 + (next() % 4) as u8
                    };
                    FrameQuad {
                        bands: if next() % 16 == 0 {
                            [u8::MAX, 0]
                        } else {
                            [b0, b1]
                        },
                        ..FrameQuad::EMPTY
                    }
                })
                .collect();
            let mut refs = std::vec![0u16; 4 * list.len()];
            let index = BandIndex::new(&list, bands, &mut refs).expect("refs enough");
            let mut total = 0;
            for b in 0..bands {
                let scan: std::vec::Vec<u16> = (0..list.len() as u16)
                    .filter(|&i| {
                        let q = &list[usize::from(i)];
                        usize::from(q.bands[0]) <= b && b <= usize::from(q.bands[1])
                    })
                    .collect();
                assert_eq!(index.band(b), &scan[..], "round {round}, band {b}");
                total += scan.len();
            }
            assert!(index.band(bands).is_empty());
            if total > 0 {
                let mut short = std::vec![0u16; total - 1];
                assert!(
                    BandIndex::new(&list, bands, &mut short).is_none(),
                    "round {round}"
                );
            }
        }
        assert!(BandIndex::new(&[], MAX_BANDS + 1, &mut []).is_none());
    }
}
