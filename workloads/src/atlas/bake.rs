//! The bake: every quad half's texels written once with texcore's bake kernel, and the
//! atlas's checksum.

use super::*;

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
