//! A scene drawn from atlases (`texsim render --via-atlas N`, or the objects of a scene file
//! with `shading = "atlas"`, [`super::shading`]; the others are shaded procedurally): every
//! atlas-shaded object's mesh is laid out in an `N x N` uniform atlas (gutter 1), its texture slot baked into it once with texcore's
//! bake kernel (solid coordinates exactly the object's texture mapping), and the frame drawn
//! by walking the scene as the procedural renderer does (same cameras, clipping and screen
//! triangles), texcore's rasterizer interpolating atlas coordinates perspective-correctly and
//! every pixel sampling the object's atlas.
//!
//! Atlases hold opaque colour (a texel's alpha marks whether a triangle owns it), so objects
//! drawn with `blend = "over"` are shaded procedurally (`--via-atlas`; a scene file may not ask
//! for their atlas) and composited over what is behind them with the texture's alpha
//! ([`texcore::color::over`], as the renderer does).
//!
//! A screen triangle carries solid coordinates; inside one mesh triangle the atlas coordinates
//! are an affine function of them (both are affine in the triangle's points), so each screen
//! vertex, clipped or not, gets its atlas coordinates from its solid ones (barycentric
//! coordinates in the mesh triangle's solid-space plane).

use texcore::atlas::sample::{AtlasImage, MipAtlas};
use texcore::color::Rgba8888;
use texcore::format::TexPoint;
use texcore::hash::HashKind;
use texcore::raster::{DepthBuffer, Rasterizer, Rect, ScreenVertex, Segment};
use texcore::render::Blend;
use texcore::scene::Mesh;
use texcore::span::Span;

use super::layout::{AtlasKind, Layout};
use super::shading::AtlasShading;
use super::view::Sampling;
use crate::mesh::TriMesh;
use crate::output::Frame;
use crate::scenes::HostScene;
use crate::unit::UnitConfig;

/// One object's atlas.
struct ObjectAtlas {
    layout: Layout,
    /// Mesh triangle of each (quad, half): `tri[2 q + half]`.
    tri: Vec<Option<u32>>,
    /// Solid coordinates (raw) of each mesh triangle's corners.
    solid: Vec<[[f64; 3]; 3]>,
    /// Level 0, then the coarser levels (power-of-two sizes).
    texels: Vec<Rgba8888>,
    first_group: usize,
    /// Side and look-up.
    size: u32,
    sampling: Sampling,
}

/// A frame drawn from atlases, and what it cost.
#[derive(Clone, Debug)]
pub struct AtlasRendered {
    /// The image.
    pub frame: Frame,
    /// Atlas texels baked (all objects).
    pub baked_texels: u64,
    /// Pixels shaded (with overdraw).
    pub shaded: u64,
    /// Seconds spent laying out and baking the atlases (and building MIP pyramids): the part
    /// of the call a frame drawn from existing atlases does not pay.
    pub bake_seconds: f64,
}

/// A procedural mesh as indexed triangles: raw positions, triangles, and the triangle of each
/// (quad, half) (`None` for a skipped degenerate half).
type IndexedMesh = (Vec<[i32; 3]>, Vec<[u32; 3]>, Vec<Option<u32>>);

fn object_mesh(mesh: &Mesh) -> IndexedMesh {
    let mut positions = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut tris = Vec::new();
    let mut map = Vec::new();
    for q in 0..mesh.quad_count() {
        let Some(c) = mesh.quad(q) else { break };
        for half in [[0usize, 1, 2], [0, 2, 3]] {
            let p = half.map(|k| c[k]);
            if p[0] == p[1] || p[1] == p[2] || p[0] == p[2] {
                map.push(None);
                continue;
            }
            let t = p.map(|v| {
                *index.entry((v.x, v.y, v.z)).or_insert_with(|| {
                    positions.push([v.x, v.y, v.z]);
                    positions.len() as u32 - 1
                })
            });
            map.push(Some(tris.len() as u32));
            tris.push(t);
        }
    }
    (positions, tris, map)
}

/// Renders frame `frame` of `host` with every opaque object from a `size x size` atlas of
/// layout `kind` sampled with `sampling` (`--via-atlas`); blended objects procedurally.
pub fn render_via_atlas(
    host: &HostScene,
    frame: u32,
    (size, kind): (u32, AtlasKind),
    sampling: Sampling,
    cfg: &UnitConfig,
    hash: HashKind,
) -> Result<AtlasRendered, String> {
    if sampling == Sampling::Mip && !size.is_power_of_two() {
        return Err(format!(
            "--via-atlas {size}: MIP look-ups need a power-of-two size"
        ));
    }
    // Atlases hold opaque colour (a texel's alpha marks ownership): blended objects stay
    // procedural.
    let plan: Vec<Option<AtlasShading>> = host
        .scene
        .objects
        .iter()
        .map(|o| {
            (o.blend != Blend::Over).then_some(AtlasShading {
                size,
                sampling,
                kind,
            })
        })
        .collect();
    render_planned(host, frame, &plan, cfg, hash)
}

/// The objects of a scene file drawn from atlases (`shading = "atlas"`), `None` when there
/// are none (every object procedural).
pub fn atlas_plan(host: &HostScene) -> Option<Vec<Option<AtlasShading>>> {
    let plan = host.hook.as_ref()?.atlas_shading();
    plan.iter().any(Option::is_some).then_some(plan)
}

/// Renders frame `frame` of `host`, object `i` from its atlas when `plan[i]` says so and
/// procedurally otherwise (the span evaluator over each segment, as the renderer shades).
pub fn render_planned(
    host: &HostScene,
    frame: u32,
    plan: &[Option<AtlasShading>],
    cfg: &UnitConfig,
    hash: HashKind,
) -> Result<AtlasRendered, String> {
    if cfg.table_size != 256 {
        return Err("atlas bakes use 256-entry colour tables (--table-size 256)".into());
    }
    let (s, materials) = host.frame(frame, hash).map_err(|e| e.to_string())?;
    let textures = materials
        .iter()
        .map(|m| crate::unit::texture::<256>(m, cfg))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let mut atlases = Vec::new();
    let mut baked_texels = 0u64;
    let mut first_group = 0usize;
    let bake_start = std::time::Instant::now();
    for (i, o) in s.objects.iter().enumerate() {
        let Some(AtlasShading {
            size,
            sampling,
            kind,
        }) = plan.get(i).copied().flatten()
        else {
            atlases.push(None);
            first_group += o.mesh.quad_count() as usize;
            continue;
        };
        let (raw, tris, tri) = object_mesh(&o.mesh);
        let f = |v: [i32; 3]| v.map(|c| c as f64 / 65536.0);
        let mesh = TriMesh::from_parts(
            &format!("object {i}"),
            raw.iter().map(|&v| f(v)).collect(),
            tris.clone(),
        )
        .map_err(|e| format!("object {i}: mesh cannot be laid out: {e}"))?;
        let solid_of = |p: [f64; 3]| {
            let q = p.map(|c| (c * 65536.0).round() as i32);
            let s = o.tex_map.apply_point(TexPoint::from_bits(q[0], q[1], q[2]));
            TexPoint::from_bits(s[0], s[1], s[2])
        };
        let layout = Layout::with_solid(&mesh, kind, size, 1, &solid_of)
            .map_err(|e| format!("object {i}: {e}"))?;
        let tex = textures
            .get(o.slot as usize)
            .ok_or_else(|| format!("object {i}: no texture slot {}", o.slot))?;
        let baked = super::bake(&layout, tex);
        baked_texels += baked.written as u64;
        let texels = if sampling == Sampling::Mip {
            super::pyramid(&baked).ok_or("MIP pyramid")?
        } else {
            baked.texels
        };
        let solid = (0..mesh.triangles().len())
            .map(|t| {
                mesh.corners(t)
                    .map(|p| solid_of(p).to_bits().map(|c| c as f64))
            })
            .collect();
        atlases.push(Some(ObjectAtlas {
            layout,
            tri,
            solid,
            texels,
            first_group,
            size,
            sampling,
        }));
        first_group += o.mesh.quad_count() as usize;
    }
    let bake_seconds = bake_start.elapsed().as_secs_f64();
    let (w, h) = s.size();
    let n = w as usize * h as usize;
    let bg = s.background;
    let mut pixels = vec![Rgba8888::new(bg[0], bg[1], bg[2], bg[3]); n];
    let mut depth = vec![u16::MAX; n];
    let rect = Rect::from_size(w, h);
    let mut db = DepthBuffer::new(&mut depth, rect).ok_or("depth buffer")?;
    let mut rast = Rasterizer::new(rect);
    let mut shaded = 0u64;
    s.for_each_triangle_by_quad(
        &mut |_| true,
        &mut |group, object, tri: &[ScreenVertex; 3]| {
            let (Some(a), Some(o)) = (atlases.get(object), s.objects.get(object)) else {
                return;
            };
            // Opaque objects replace the pixel, `blend = "over"` ones are composited over it.
            let over = o.blend == Blend::Over;
            let put = |c: Rgba8888, behind: Rgba8888| {
                if over {
                    texcore::color::over(c, behind)
                } else {
                    c.with_alpha(255)
                }
            };
            let Some(a) = a else {
                // Procedural: the object's texture over each segment.
                let Some(tex) = textures.get(o.slot as usize) else {
                    return;
                };
                let mut ev = tex.evaluator();
                rast.draw_depth(tri, &o.options(), &mut db, &mut |seg: &Segment| {
                    let span = Span {
                        s0: seg.s0,
                        ds: seg.ds,
                        dsdy: seg.dsdy,
                        len: seg.len,
                    };
                    let mut x = seg.x0 as usize;
                    ev.shade(&span, |c| {
                        if let Some(px) = pixels.get_mut(seg.y as usize * w as usize + x) {
                            *px = put(c, *px);
                        }
                        x += 1;
                    });
                    shaded += seg.len as u64;
                });
                return;
            };
            let (size, sampling) = (a.size, a.sampling);
            let size16 = size as u16;
            let q = group.saturating_sub(a.first_group);
            // The mesh triangle: the live half whose solid plane holds the screen triangle best.
            let sv = tri.map(|v| v.tex.to_bits().map(|c| c as f64));
            let centroid = [0, 1, 2].map(|k| (sv[0][k] + sv[1][k] + sv[2][k]) / 3.0);
            let mut best: Option<(f64, u32)> = None;
            for half in 0..2 {
                if let Some(Some(t)) = a.tri.get(2 * q + half) {
                    let (b, g) = bary(&a.solid[*t as usize], centroid);
                    let out = (-b).max(0.0) + (-g).max(0.0) + (b + g - 1.0).max(0.0);
                    if best.is_none_or(|(o, _)| out < o) {
                        best = Some((out, *t));
                    }
                }
            }
            let Some((_, t)) = best else { return };
            let uv = a.layout.uv(t as usize);
            let st = &a.solid[t as usize];
            let mut v = *tri;
            for (k, vert) in v.iter_mut().enumerate() {
                let (b, g) = bary(st, sv[k]);
                let u = uv[0][0] + b * (uv[1][0] - uv[0][0]) + g * (uv[2][0] - uv[0][0]);
                let w = uv[0][1] + b * (uv[1][1] - uv[0][1]) + g * (uv[2][1] - uv[0][1]);
                vert.tex = TexPoint::from_bits(
                    (u * 65536.0).round() as i32,
                    (w * 65536.0).round() as i32,
                    0,
                );
            }
            let img = AtlasImage::new(&a.texels[..(size * size) as usize], size16, size16);
            let mip = MipAtlas::new(&a.texels, size16);
            rast.draw_depth(&v, &o.options(), &mut db, &mut |seg: &Segment| {
                let d = seg.ds.to_bits();
                let dy = seg.dsdy.to_bits();
                let footprint = [d[0], d[1], dy[0], dy[1]]
                    .iter()
                    .map(|x| x.unsigned_abs())
                    .max()
                    .unwrap_or(0);
                for i in 0..seg.len {
                    let p = seg.s_at(i);
                    let (u, v) = (p[0] as i32, p[1] as i32);
                    let c = match (sampling, &img, &mip) {
                        (Sampling::Mip, _, Ok(m)) => m.trilinear(u, v, footprint, u8::MAX),
                        (Sampling::Nearest, Ok(img), _) => img.nearest(u, v),
                        (_, Ok(img), _) => img.bilinear(u, v),
                        _ => Rgba8888::TRANSPARENT,
                    };
                    let idx = seg.y as usize * w as usize + (seg.x0 + i) as usize;
                    if let Some(px) = pixels.get_mut(idx) {
                        *px = put(c, *px);
                    }
                    shaded += 1;
                }
            });
        },
    );
    Ok(AtlasRendered {
        frame: Frame {
            width: w as u32,
            height: h as u32,
            pixels: pixels.iter().map(|c| c.to_array()).collect(),
        },
        baked_texels,
        shaded,
        bake_seconds,
    })
}

/// Barycentric coordinates `(beta, gamma)` of `p` in the plane of triangle `t` (least squares:
/// `p - t0 ~ beta (t1 - t0) + gamma (t2 - t0)`).
fn bary(t: &[[f64; 3]; 3], p: [f64; 3]) -> (f64, f64) {
    let e1 = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
    let e2 = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
    let d = [0, 1, 2].map(|k| p[k] - t[0][k]);
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (a11, a12, a22) = (dot(e1, e1), dot(e1, e2), dot(e2, e2));
    let (b1, b2) = (dot(d, e1), dot(d, e2));
    let det = a11 * a22 - a12 * a12;
    if det.abs() < 1e-30 {
        return (0.0, 0.0);
    }
    ((b1 * a22 - b2 * a12) / det, (a11 * b2 - a12 * b1) / det)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accuracy::measure::resized;

    /// `moonrise` has blended objects (the moon's glow on the water, the clouds): drawn from
    /// atlases, the opaque objects come from their atlases and the blended ones are composited
    /// procedurally, so the frame stays close to the procedural one (drawn opaque, they hid the
    /// moon: 9.8 dB).
    #[test]
    fn blended_objects_are_composited_not_baked() {
        let scene = resized(&texcore::scene::by_name("moonrise").unwrap(), 96, 72);
        let blended = scene
            .objects
            .iter()
            .filter(|o| o.blend == Blend::Over)
            .count();
        assert!(blended > 0 && blended < scene.objects.len());
        let host = HostScene::builtin(scene.clone());
        let cfg = UnitConfig::default();
        let hash = HashKind::Integer;
        let frame = scene.still();
        let r = render_via_atlas(
            &host,
            frame,
            (256, AtlasKind::Uniform),
            Sampling::Bilinear,
            &cfg,
            hash,
        )
        .unwrap();
        let p = crate::scenes::render_frame(
            &scene,
            frame,
            &cfg,
            hash,
            texcore::render::Output::Color,
        )
        .unwrap();
        let m = crate::metrics::compare_rgba8(&r.frame.pixels, &p.frame.pixels).unwrap();
        assert!(m.psnr > 30.0, "{}", m.psnr);
        assert!(r.baked_texels > 0);
    }
}
