//! The renderer's filter widths from differences against a reference made from the rasterizer's
//! segments, and the same colours streamed and in bands.

extern crate std;
use std::collections::BTreeMap;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::filter::{Antialias, WidthStream};
use crate::format::{TexPoint, TexValue};
use crate::raster::Perspective;
use crate::span::FaceCache;
use crate::texture::{DifferenceMemory, TILE_ROWS};

use super::tests::Quads;

/// A corner at pixel `(x, y)` (1/16 pixel units) with `1/w = q` and texture point `s`.
fn corner(x: i32, y: i32, z: u16, q: u32, s: [f64; 3]) -> ScreenVertex {
    ScreenVertex::from_bits(x, y, z, q, TexPoint::from_f64(s[0], s[1], s[2]))
}

fn object(texture: usize, perspective: Perspective, depth: bool) -> DrawObject {
    DrawObject {
        texture,
        depth,
        raster: TriangleOptions {
            perspective,
            ..TriangleOptions::default()
        },
        ..DrawObject::default()
    }
}

/// The scenes: a full affine quad, a receding perspective quad, small and sliver quads
/// off the pixel grid, and one that leaves the image.
fn scenes() -> Vec<Quads> {
    let aff = Perspective::Affine;
    let per = Perspective::Every16;
    vec![
        Quads {
            size: 64,
            objects: vec![(
                object(0, aff, false),
                [
                    corner(0, 0, 0, 1 << 30, [0.0, 0.5, 0.25]),
                    corner(1024, 0, 0, 1 << 30, [4.0, 0.5, 0.25]),
                    corner(1024, 1024, 0, 1 << 30, [4.0, 3.5, 0.25]),
                    corner(0, 1024, 0, 1 << 30, [0.0, 3.5, 0.25]),
                ],
            )],
        },
        Quads {
            size: 48,
            objects: vec![
                (
                    object(0, per, false),
                    [
                        corner(-37, 21, 0, 1 << 30, [-3.0, 0.2, -5.0]),
                        corner(811, 45, 0, 1 << 28, [9.0, 0.2, -5.0]),
                        corner(760, 700, 0, 1 << 28, [9.0, 6.7, -5.0]),
                        corner(3, 771, 0, 1 << 30, [-3.0, 6.7, -5.0]),
                    ],
                ),
                (
                    object(1, aff, false),
                    [
                        corner(100, 90, 0, 1 << 30, [1.0, 2.0, 3.0]),
                        corner(230, 130, 0, 1 << 30, [1.5, 2.0, 3.0]),
                        corner(240, 141, 0, 1 << 30, [1.5, 2.2, 3.0]),
                        corner(101, 103, 0, 1 << 30, [1.0, 2.2, 3.0]),
                    ],
                ),
                // Flat: its rows reach past the row above by more than a 16-pixel
                // piece.
                (
                    object(0, per, false),
                    [
                        corner(750, 320, 0, 1 << 30, [0.0, 1.0, 0.0]),
                        corner(765, 320, 0, 1 << 28, [5.0, 1.0, 0.0]),
                        corner(765, 370, 0, 1 << 28, [5.0, 1.5, 0.5]),
                        corner(0, 355, 0, 1 << 30, [0.0, 1.5, 0.5]),
                    ],
                ),
                (
                    object(0, per, false),
                    [
                        corner(500, 400, 0, 1 << 29, [0.0, 0.0, 0.0]),
                        corner(900, 420, 0, 1 << 30, [2.0, 0.0, 0.0]),
                        corner(880, 900, 0, 1 << 30, [2.0, 2.0, 1.0]),
                        corner(520, 880, 0, 1 << 29, [0.0, 2.0, 1.0]),
                    ],
                ),
            ],
        },
    ]
}

fn textures() -> Vec<Texture<8, 256>> {
    use crate::ready::{Material, PresetName};
    vec![
        Material::preset(PresetName::Marble)
            .texture(Antialias::Csat)
            .unwrap(),
        Material::preset(PresetName::Wood)
            .texture(Antialias::Mip)
            .unwrap(),
    ]
}

/// The streamed frame of `scene` with widths from differences, by hand: each triangle of at
/// least `DIFFERENCE_MIN_ROWS` rows' segments from the rasterizer (a shorter one's colours
/// those of the gradients' widths), each pixel's value from the span evaluator, the pixel
/// above from the same triangle's row above unless the pixel is on a tile's first row; a
/// pixel the row above does not have takes the vertical difference of the nearest one that
/// has it, and a segment none of whose pixels has it is evaluated one row up; the colour
/// is the stage's at the width of the differences.
fn reference(scene: &Quads, tex: &[Texture<8, 256>]) -> Vec<Rgba8888> {
    let n = usize::from(scene.size);
    let mut img = vec![scene.background(); n * n];
    let mut raster = Rasterizer::new(Rect::from_size(scene.size, scene.size));
    scene.for_each_triangle(|obj, tri| {
        let o = scene.object(obj).unwrap();
        let t = &tex[o.texture];
        let Shader::Model(m) = t.shader() else {
            unreachable!()
        };
        let mut ev = SpanEvaluator::new(m, t.options());
        let mut values = |span: &Span| {
            let mut out = vec![TexValue::ZERO; usize::from(span.len)];
            let extra = ev.eval_values(span, &mut out).extra_width48;
            (out, extra)
        };
        let mut segs = Vec::new();
        raster.draw(tri, &o.raster, &mut |s: &Segment| segs.push(*s));
        // A triangle of fewer than `DIFFERENCE_MIN_ROWS` rows: the gradients' widths.
        let [_, _, y0, y1] = crate::raster::bounding_box(tri);
        let short = y1 - y0 < 16 * i32::from(segment::DIFFERENCE_MIN_ROWS);
        let mut held: BTreeMap<(u16, u16), TexValue> = BTreeMap::new();
        for seg in segs {
            let span = Span {
                s0: seg.s0,
                ds: seg.ds,
                dsdy: seg.dsdy,
                len: seg.len,
            };
            if short {
                let at = usize::from(seg.y) * n + usize::from(seg.x0);
                let mut i = 0;
                t.evaluator().shade(&span, |c| {
                    img[at + i] = c;
                    i += 1;
                });
                continue;
            }
            let (f, extra) = values(&span);
            let bits = |v: TexValue| v.to_bits();
            // The same triangle's values of the row above, unless on a tile's first row.
            let kept: Vec<Option<TexValue>> = (0..seg.len)
                .map(|i| {
                    let x = seg.x0 + i;
                    (seg.y % TILE_ROWS != 0)
                        .then(|| held.get(&(x, seg.y - 1)).copied())
                        .flatten()
                })
                .collect();
            let first = kept.iter().position(Option::is_some);
            let last = kept.iter().rposition(Option::is_some);
            let above: Vec<TexValue> = match (first, last) {
                // None kept: the segment one row up.
                (None, _) | (_, None) => values(&span.prev_row()).0,
                // The others take the vertical difference of the nearest kept one.
                (Some(a), Some(b)) => {
                    let dy = |k: usize| bits(f[k]).wrapping_sub(bits(kept[k].unwrap()));
                    (0..f.len())
                        .map(|i| match kept[i] {
                            Some(v) => v,
                            None => {
                                let d = if i < a { dy(a) } else { dy(b) };
                                TexValue::from_bits(bits(f[i]).wrapping_sub(d))
                            }
                        })
                        .collect()
                }
            };
            for (i, &v) in f.iter().enumerate() {
                held.insert((seg.x0 + i as u16, seg.y), v);
            }
            for i in 0..f.len() {
                let dx = match (f.get(i + 1), i.checked_sub(1)) {
                    (Some(&r), _) => bits(r).wrapping_sub(bits(f[i])),
                    (None, Some(l)) => bits(f[i]).wrapping_sub(bits(f[l])),
                    (None, None) => 0,
                };
                let dy = bits(f[i]).wrapping_sub(bits(above[i]));
                let w = WidthStream::new(t.norm(), 8).width_with(
                    i64::from(dx) << 32,
                    i64::from(dy) << 32,
                    extra,
                );
                let at = usize::from(seg.y) * n + usize::from(seg.x0) + i;
                img[at] = t.stage().shade(f[i], w);
            }
        }
    });
    img
}

/// The frame of `scene` streamed (`rows` 0) or in bands of `rows` rows.
fn render(r: &Renderer<'_, 8, 256>, scene: &Quads, rows: u16) -> Vec<Rgba8888> {
    super::tests::render_full(r, scene, rows).0
}

#[test]
fn differences_are_the_reference_streamed_and_in_bands() {
    let tex = textures();
    let mut mem = DifferenceMemory::<64>::new();
    let mut faces = FaceCache::<64, 8>::new();
    let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
    for (k, scene) in scenes().iter().enumerate() {
        let want = reference(scene, &tex);
        assert_eq!(render(&r, scene, 0), want, "scene {k} streamed");
        for rows in [8, 16, 24, 64] {
            assert_eq!(render(&r, scene, rows), want, "scene {k}, bands of {rows}");
        }
        // The frame differs from the gradients' (the mode is on).
        let plain = Renderer::new(&tex);
        assert_ne!(render(&plain, scene, 0), want, "scene {k}");
    }
}

#[test]
fn depth_tested_scenes_agree_in_bands() {
    let tex = textures();
    let mut mem = DifferenceMemory::<48>::new();
    let mut faces = FaceCache::<1, 0>::new();
    let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
    let mut scene = scenes().remove(1);
    for (i, (o, v)) in scene.objects.iter_mut().enumerate() {
        o.depth = true;
        for c in v.iter_mut() {
            *c = ScreenVertex::from_bits(
                c.x.to_bits(),
                c.y.to_bits(),
                1000 - 100 * i as u16,
                c.inv_w.to_bits(),
                c.tex,
            );
        }
    }
    let want = render(&r, &scene, 48);
    for rows in [8, 16, 24] {
        assert_eq!(render(&r, &scene, rows), want, "bands of {rows}");
    }
}

#[test]
fn a_narrow_memory_is_refused_and_kept() {
    let tex = textures();
    let mut mem = DifferenceMemory::<32>::new();
    let mut faces = FaceCache::<16, 8>::new();
    let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
    let wide = scenes().remove(0);
    let mut img = vec![Rgba8888::BLACK; 64 * 64];
    let mut sink = RgbaBuffer::new(&mut img, 64, 0, 64).unwrap();
    let e = r.render_streamed(&wide, &mut sink).unwrap_err();
    assert_eq!(
        e,
        RenderError::MemoryTooNarrow {
            width: 64,
            memory: 32
        }
    );
    assert!(e.to_string().contains("32 pixels"));
    // The memory is still the renderer's: a narrow enough scene renders as the reference.
    let mut narrow = scenes().remove(1);
    narrow.size = 32;
    assert_eq!(render(&r, &narrow, 0), reference(&narrow, &tex));
    assert_eq!(render(&r, &narrow, 8), reference(&narrow, &tex));
}
