//! The frame drawn from the atlas: the frame list of projected quads, its band index, and the
//! bands drawn with the textured-triangle path.

use super::*;

/// Sets every pixel of `band` to `v`: the pixels before and after the band's 4-byte-aligned
/// middle one at a time, the middle as words of two pixels each (`[v, v]` in memory order:
/// the same pixels as `fill_u16`, in about a third of its stores on the Cortex-M4F, whose
/// compiler cannot pair the stores of a slice of unknown alignment).
pub(super) fn fill_rgb565(band: &mut [u16], v: u16) {
    let (head, words, tail) = bytemuck::pod_align_to_mut::<u16, u32>(band);
    head.fill(v);
    tail.fill(v);
    let w: u32 = bytemuck::cast([v, v]);
    // Eight words a turn, as `fill_u16` takes eight pixels: a plain `fill` of the words
    // measured 0.4 instructions a frame pixel dearer (`atlas:marble`, Cortex-M4F).
    let mut chunks = words.chunks_exact_mut(8);
    for c in &mut chunks {
        if let Ok(c) = <&mut [u32; 8]>::try_from(c) {
            *c = [w; 8];
        }
    }
    chunks.into_remainder().fill(w);
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
pub fn draw_scene(scene: &Scene, atlas: &AtlasTexels, bins: &mut [GroupRows]) -> u32 {
    let mut band = [0u16; DRAW_PIXELS];
    draw_scene_in(scene, atlas, bins, &mut band)
}

/// [`draw_scene`] into the caller's RGB565 band `band` (at least [`DRAW_PIXELS`] entries; 0
/// otherwise): the frame list and its index on the stack. (The device passes memory that the
/// atlas jobs do not otherwise use, so that the band does not take stack.)
#[inline(never)]
pub fn draw_scene_in(
    scene: &Scene,
    atlas: &AtlasTexels,
    bins: &mut [GroupRows],
    band: &mut [u16],
) -> u32 {
    let mut sink = ChecksumSink::resume(FRAME_START);
    let mut list = [FrameQuad::EMPTY; FRAME_QUADS];
    let mut refs = [0u16; FRAME_REFS];
    let drawn = draw_scene_rows_with(scene, atlas, bins, &mut list, &mut refs, band, |row| {
        sink.add_rgb565_row(row)
    });
    if drawn {
        sink.checksum()
    } else {
        0
    }
}

/// Quads of the frame list ([`FrameQuad`]) that [`draw_scene_rows`] keeps (48 bytes each,
/// 24.8 KB on the stack): the marble frame lists 516 (515 drawn quads, one of them in two
/// entries). A frame that lists more is drawn the general way.
pub const FRAME_QUADS: usize = 528;

/// Entries of the band index (`BandIndex`) that [`draw_scene_rows`] keeps (2 bytes each):
/// a listed quad takes one in every band its rows touch (the marble frame: about 720). A frame
/// that needs more scans the whole list in every band instead.
pub const FRAME_REFS: usize = 800;

/// Bands the band index can hold (frames up to `MAX_BANDS * DRAW_ROWS` rows; taller ones scan
/// the list in every band).
pub(super) const MAX_BANDS: usize = 32;

/// The listed quads of every band, in list order: `refs[start[b]..start[b + 1]]` are the
/// indices of band `b`'s quads (a counting sort of the list by band, built once a frame), so a
/// band visits only the quads that touch it instead of testing every listed quad.
pub(super) struct BandIndex<'a> {
    refs: &'a [u16],
    start: [u16; MAX_BANDS + 1],
}

impl<'a> BandIndex<'a> {
    /// The index of `list` over `bands` bands in `refs`; `None` when the bands or the entries
    /// do not fit (`refs` too short, more than [`MAX_BANDS`] bands or `u16::MAX` quads).
    pub(super) fn new(
        list: &[FrameQuad],
        bands: usize,
        refs: &'a mut [u16],
    ) -> Option<BandIndex<'a>> {
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
    pub(super) fn band(&self, b: usize) -> &[u16] {
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
pub(super) struct ListedVertex {
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
///
/// 46 bytes of fields, aligned to 4 (48 bytes): the list is then cleared as one block of words
/// and its entries read and written a word at a time where the fields allow (`atlas:marble`
/// measured 0.4 instructions a frame pixel cheaper on the Cortex-M4F than with 46-byte entries).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C, align(4))]
pub struct FrameQuad {
    pub(super) group: u16,
    pub(super) object: u8,
    /// Bit `k`: half `k` is drawn; bit `4 + i`: corner `i` is set.
    pub(super) flags: u8,
    /// First and last band (of [`DRAW_ROWS`] rows) the drawn halves can cover.
    pub(super) bands: [u8; 2],
    pub(super) corners: [ListedVertex; 4],
}

// The size the list's memory figures (`FRAME_QUADS`) are stated for.
const _: () = assert!(core::mem::size_of::<FrameQuad>() == 48);

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
pub(super) const HALF_TRIANGLES: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// The inset atlas corners (`AtlasTriangle::inset_corners`) of every quad half of a
/// [`UniformLayout`], in the frame list's triangle order ([`HALF_TRIANGLES`]): quad 0's, moved
/// by each quad's block (the blocks of a uniform layout differ by whole texels, so the corners
/// move by whole texels too). The draw finds a listed half's corners with a division and two
/// additions instead of building its `AtlasTriangle` in every band. Exactly
/// `layout.triangle(q, half, _).inset_corners()` for every quad of the layout
/// (`half_corners_are_the_triangles`).
#[derive(Clone, Copy, Debug)]
pub(super) struct HalfCorners {
    base: [[[i32; 2]; 3]; 2],
    w: u32,
    h: u32,
    cols: u32,
    quads: u32,
}

impl HalfCorners {
    pub(super) fn new(layout: &UniformLayout) -> Option<HalfCorners> {
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
    pub(super) fn get(&self, q: u32, k: usize) -> Option<[[i32; 2]; 3]> {
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

/// The general way's band `rows` of [`draw_scene_rows_with`]: walks the quads whose bins touch
/// the band (or that have no bin) again, gives each triangle its quad's atlas positions
/// (`QuadAtlas`, kept in `cache` from one triangle and band to the next) and hands it to
/// `draw`. Out of line: its walk's corners are in its own frame, not in the listed draw's.
#[inline(never)]
fn walk_band<D: FnMut(usize, &[ScreenVertex; 3])>(
    scene: &Scene,
    layout: &UniformLayout,
    bins: &[GroupRows],
    starts: &[u32; texcore::scene::MAX_OBJECTS],
    (y0, y1): (u16, u16),
    cache: &mut Option<(usize, QuadAtlas)>,
    draw: &mut D,
) {
    let mut keep = |g: usize| bins.get(g).is_none_or(|b| b.touches(y0, y1));
    scene.for_each_triangle_by_quad(&mut keep, &mut |g, obj, tri| {
        let Some(o) = scene.objects.get(obj) else {
            return;
        };
        let start = starts.get(obj).copied().unwrap_or(0);
        if cache.as_ref().is_none_or(|c| c.0 != g) {
            let q = (g as u32).wrapping_sub(start);
            *cache = QuadAtlas::new(layout, o, g as u32, q).map(|a| (g, a));
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

/// Draws `scene` from `atlas` (laid out by [`scene_layout`]) in bands of [`DRAW_ROWS`] rows,
/// handing every RGB565 row to `out`, top to bottom: [`draw_scene_rows_with`] with a frame list
/// of [`FRAME_QUADS`] quads, a band index of [`FRAME_REFS`] entries and the RGB565 band on the
/// stack.
pub fn draw_scene_rows<O: FnMut(&[u16])>(
    scene: &Scene,
    atlas: &AtlasTexels,
    bins: &mut [GroupRows],
    out: O,
) -> bool {
    let mut list = [FrameQuad::EMPTY; FRAME_QUADS];
    let mut refs = [0u16; FRAME_REFS];
    let mut band = [0u16; DRAW_PIXELS];
    draw_scene_rows_with(scene, atlas, bins, &mut list, &mut refs, &mut band, out)
}

/// Draws `scene` from `atlas` (laid out by [`scene_layout`]) in bands of [`DRAW_ROWS`] rows,
/// drawn into `band` (the caller's RGB565 band: at least [`DRAW_PIXELS`] entries), handing every
/// RGB565 row to `out`, top to bottom. `false` (and no row) if the scene has no layout, is wider
/// than [`WIDTH`] or `band` is too short.
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
    band: &mut [u16],
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
    let Some(texture) = Texture565::<{ SIDE as usize }>::new(atlas) else {
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
    // Each object's triangle options, once a frame (an object drawn without depth neither
    // tests nor writes it).
    let options: [Option<TriangleOptions>; texcore::scene::MAX_OBJECTS] =
        core::array::from_fn(|i| {
            let d = scene.object(i)?;
            let mut opts = d.raster;
            if !d.depth {
                opts.depth_func = DepthFunc::Always;
                opts.depth_write = false;
            }
            Some(opts)
        });
    let Some(band) = band.get_mut(..wu * usize::from(DRAW_ROWS)) else {
        return false;
    };
    let mut raster = Rasterizer::new(Rect::from_size(w, h));
    let mut cache: Option<(usize, QuadAtlas)> = None;
    let mut y0 = 0u16;
    while y0 < h {
        let y1 = y0.saturating_add(DRAW_ROWS).min(h);
        let rect = Rect::new(0, y0, w, y1);
        raster.set_clip(rect);
        db.set_rect(rect);
        db.clear(u16::MAX);
        fill_rgb565(band, bg);
        let mut draw = |obj: usize, v: &[ScreenVertex; 3]| {
            if let Some(Some(opts)) = options.get(obj) {
                raster.draw_textured(v, opts, &mut db, &texture, band);
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
            walk_band(
                scene,
                &layout,
                bins,
                &starts,
                (y0, y1),
                &mut cache,
                &mut draw,
            );
        }
        for row in band.chunks(wu.max(1)).take(usize::from(y1 - y0)) {
            out(row);
        }
        y0 = y1;
    }
    true
}
