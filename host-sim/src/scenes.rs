//! Rendering scenes on the host: textures for a scene's slots, frames through texcore's renderer,
//! the f64 reference render of the same geometry, and render statistics.

use serde::Serialize;
use texcore::color::Rgba8888;
use texcore::filter::WidthSource;
use texcore::format::Amplitude;
use texcore::gouraud::TriangleLight;
use texcore::hash::HashKind;
use texcore::raster::{DepthBuffer, Rasterizer, Rect, Segment};
use texcore::render::{Blend, Output, RenderStats, Renderer, TriangleSource};
use texcore::scene::{Scene, TextureSlot};
use texcore::sink::{ChecksumSink, PixelSink, RgbaBuffer};
use texcore::span::FaceCache;
use texcore::texture::{DifferenceMemory, Texture};

use crate::bridge;
use crate::metrics::{compare_to_reference, Metrics};
use crate::output::Frame;
use crate::reference::model::{Footprint, Nyquist};
use crate::reference::perturbed::RefPerturbed;
use crate::reference::table::RefTable;
use crate::unit::{self, MaterialSpec, ShaderSpec, UnitConfig, UnitError, DIFFERENCES_MAX_WIDTH};

/// Face-cache entries of a scene rendered with filter widths from differences
/// (`texcore::span::FaceCache`; the values are the same with any number).
pub const DIFFERENCES_FACES: usize = 128;

/// The material of a texture slot: its preset with the slot's amplitude factor, phase and keys.
pub fn slot_material(slot: &TextureSlot, hash: HashKind) -> Result<MaterialSpec, UnitError> {
    let mut m = unit::preset_material(slot.material, hash)?;
    if let Some(keys) = slot.keys {
        m.keys = keys.to_vec();
    }
    let factor = i64::from(slot.amplitude);
    let scale = |a: Amplitude| -> Amplitude {
        Amplitude::from_bits(
            ((i64::from(a.to_bits()) * factor) >> 16).clamp(i32::MIN.into(), i32::MAX.into())
                as i32,
        )
    };
    match &mut m.shader {
        ShaderSpec::Model(model) => {
            if factor != 1 << 16 {
                for k in 0..model.terms().len() {
                    let a = scale(model.terms()[k].amplitude);
                    model.set_amplitude(k, a).map_err(UnitError::Model)?;
                }
            }
            if slot.phase != 0 && slot.material == "fire" {
                texcore::presets::set_fire_phase(model, slot.phase);
            }
        }
        ShaderSpec::Perturbed(p) => {
            for a in &mut p.alpha {
                *a = scale(*a);
            }
        }
    }
    Ok(m)
}

/// The materials of every slot of `scene`.
pub fn scene_materials(scene: &Scene, hash: HashKind) -> Result<Vec<MaterialSpec>, UnitError> {
    scene.slots.iter().map(|s| slot_material(s, hash)).collect()
}

/// A rendered frame and what it cost.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image.
    pub frame: Frame,
    /// Stage counters.
    pub stats: RenderStats,
}

pub(crate) fn render_n<const N: usize>(
    scene: &Scene,
    materials: &[MaterialSpec],
    cfg: &UnitConfig,
    output: Output,
) -> Result<Rendered, UnitError> {
    let textures: Vec<Texture<{ texcore::presets::PRESET_TERMS }, N>> = materials
        .iter()
        .map(|m| unit::texture::<N>(m, cfg))
        .collect::<Result<_, _>>()?;
    let (w, h) = scene.size();
    // The memory of the filter widths from differences, only when the render takes them.
    let mut memory = match cfg.widths {
        WidthSource::Gradients => None,
        WidthSource::Differences => {
            if usize::from(w) > DIFFERENCES_MAX_WIDTH {
                return Err(UnitError::TooWide {
                    width: u32::from(w),
                    max: DIFFERENCES_MAX_WIDTH,
                });
            }
            Some((
                Box::new(DifferenceMemory::<DIFFERENCES_MAX_WIDTH>::new()),
                Box::new(FaceCache::<
                    DIFFERENCES_FACES,
                    { texcore::presets::PRESET_TERMS },
                >::new()),
            ))
        }
    };
    let renderer = match memory.as_mut() {
        None => Renderer::new(&textures),
        Some((mem, faces)) => Renderer::new(&textures).with_differences(&mut **mem, &mut **faces),
    }
    .with_output(output);
    let n = usize::from(w) * usize::from(h);
    let mut img = vec![Rgba8888::BLACK; n];
    let mut sink = RgbaBuffer::new(&mut img, w, 0, h).ok_or(UnitError::TableSize(0))?;
    let stats = match renderer.needs_bands(scene) {
        Ok(false) => renderer.render_streamed(scene, &mut sink),
        _ => {
            let mut band = vec![Rgba8888::BLACK; n];
            let mut depth = vec![0u16; n];
            renderer.render_banded(scene, &mut band, &mut depth, h, &mut sink)
        }
    }
    .map_err(|e| UnitError::Render(e.to_string()))?;
    Ok(Rendered {
        frame: Frame {
            width: u32::from(w),
            height: u32::from(h),
            pixels: img.iter().map(|c| c.to_array()).collect(),
        },
        stats,
    })
}

/// Renders frame `frame` of `scene` with the given knobs.
pub fn render_frame(
    scene: &Scene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
    output: Output,
) -> Result<Rendered, UnitError> {
    let s = scene.at_frame(frame);
    let materials = scene_materials(&s, hash)?;
    crate::dispatch_table_size!(cfg.table_size, render_n(&s, &materials, cfg, output))
}

/// A host-side per-frame hook: the scene and the materials of its slots at each frame. Scene
/// files use it for what texcore's [`Scene`] cannot carry (materials that are not presets,
/// animations of parameters that a plain `fn` pointer cannot capture).
pub trait FrameHook: Send + Sync {
    /// The scene and one material per slot at `frame` (already taken modulo the frame count).
    fn frame(&self, frame: u32, hash: HashKind) -> Result<(Scene, Vec<MaterialSpec>), UnitError>;
    /// Per object, whether it is drawn from a baked atlas (`shading = "atlas"` in scene files,
    /// [`crate::atlas::shading`]); empty: every object procedural.
    fn atlas_shading(&self) -> Vec<Option<crate::atlas::shading::AtlasShading>> {
        Vec::new()
    }
}

/// A scene as the host renders it: texcore's [`Scene`] and, for scene files, a [`FrameHook`]
/// that supplies each frame's scene and materials. Built-in scenes have no hook: their frames
/// come from [`Scene::at_frame`] and their materials from the slots' presets
/// ([`scene_materials`]).
#[derive(Clone)]
pub struct HostScene {
    /// The scene at frame 0: name, camera (image size), frame count, still frame, objects.
    pub scene: Scene,
    /// Per-frame scenes and materials (`None`: a built-in scene).
    pub hook: Option<std::sync::Arc<dyn FrameHook>>,
}

impl std::fmt::Debug for HostScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HostScene")
            .field("scene", &self.scene)
            .field("hook", &self.hook.is_some())
            .finish()
    }
}

impl HostScene {
    /// A built-in (or any texcore) scene, its slots naming presets.
    pub fn builtin(scene: Scene) -> HostScene {
        HostScene { scene, hook: None }
    }

    /// The scene and its slot materials at `frame` (taken modulo the frame count), at the image
    /// size of [`HostScene::scene`]'s camera.
    pub fn frame(
        &self,
        frame: u32,
        hash: HashKind,
    ) -> Result<(Scene, Vec<MaterialSpec>), UnitError> {
        match &self.hook {
            Some(h) => {
                let (mut s, m) = h.frame(frame % self.scene.frames().max(1), hash)?;
                // The image size of `self.scene` is authoritative (it may have been changed,
                // e.g. to render a scene file small).
                s.camera.width = self.scene.camera.width;
                s.camera.height = self.scene.camera.height;
                Ok((s, m))
            }
            None => {
                let s = self.scene.at_frame(frame);
                let m = scene_materials(&s, hash)?;
                Ok((s, m))
            }
        }
    }
}

/// Renders frame `frame` of a host scene (built-in or from a file) with the given knobs.
pub fn render_host_frame(
    scene: &HostScene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
    output: Output,
) -> Result<Rendered, UnitError> {
    let (s, materials) = scene.frame(frame, hash)?;
    crate::dispatch_table_size!(cfg.table_size, render_n(&s, &materials, cfg, output))
}

/// The checksum of an image as the device computes it: FNV-1a over its RGB565 pixels, row-major.
pub fn checksum(frame: &Frame) -> u32 {
    let mut c = ChecksumSink::new();
    for row in frame.pixels.chunks(frame.width.max(1) as usize) {
        let colors: Vec<Rgba8888> = row.iter().map(|p| Rgba8888::from_array(*p)).collect();
        c.write_span(0, 0, &colors);
    }
    c.checksum()
}

/// Render statistics as `--stats --json` prints them.
#[derive(Clone, Debug, Serialize)]
pub struct StatsReport {
    /// Pixels shaded.
    pub pixels: u64,
    /// Spans evaluated.
    pub spans: u64,
    /// Lattice cell set-ups.
    pub cell_setups: u64,
    /// Noise term samples.
    pub noise_evaluations: u64,
    /// Octaves culled past the Nyquist limit (per term per span).
    pub culled_octaves: u64,
    /// Gradient samples (quadric and terms, per pixel).
    pub gradient_evaluations: u64,
    /// Pixels produced by forward differencing.
    pub fd_pixels: u64,
    /// Filtered colour-table look-ups.
    pub filter_lookups: u64,
    /// Plain colour-table look-ups.
    pub plain_lookups: u64,
    /// Pixels alpha-blended.
    pub blended_pixels: u64,
    /// Triangles set up by the rasterizer.
    pub triangles: u64,
    /// Triangles whose texture planes were set up (those with a visible pixel in a band,
    /// once per band).
    pub texture_setups: u64,
    /// Segments produced by the rasterizer.
    pub segments: u64,
    /// Perspective divides.
    pub perspective_divides: u64,
    /// Pixels hidden by the depth test.
    pub depth_failed: u64,
    /// Bands rendered (0: streamed without a frame buffer).
    pub bands: u32,
    /// Pixels multiplied by their light (0 for a scene without lights).
    pub lit_pixels: u64,
}

impl From<&RenderStats> for StatsReport {
    fn from(s: &RenderStats) -> Self {
        let sp = &s.shade.span;
        StatsReport {
            pixels: sp.pixels,
            spans: sp.spans,
            cell_setups: sp.cell_setups,
            noise_evaluations: sp.noise_evaluations,
            culled_octaves: sp.culled_octaves,
            gradient_evaluations: sp.gradient_evaluations,
            fd_pixels: sp.fd_pixels,
            filter_lookups: s.shade.filter_lookups,
            plain_lookups: s.shade.plain_lookups,
            blended_pixels: s.blended_pixels,
            triangles: u64::from(s.raster.triangles),
            texture_setups: u64::from(s.raster.texture_setups),
            segments: s.raster.segments,
            perspective_divides: s.raster.divides,
            depth_failed: s.raster.depth_failed,
            bands: s.bands,
            lit_pixels: s.lit_pixels,
        }
    }
}

fn over_f64(src: [f64; 4], dst: [f64; 4]) -> [f64; 4] {
    let a = src[3] / 255.0;
    let da = dst[3] / 255.0;
    let oa = a + da * (1.0 - a);
    if oa <= 0.0 {
        return [0.0; 4];
    }
    let mut out = [0.0; 4];
    for k in 0..3 {
        out[k] = (src[k] * a + dst[k] * da * (1.0 - a)) / oa;
    }
    out[3] = oa * 255.0;
    out
}

fn reference_n<const N: usize>(
    scene: &Scene,
    materials: &[MaterialSpec],
    cfg: &UnitConfig,
) -> Result<Vec<[f64; 4]>, UnitError> {
    enum Shading {
        Model(crate::reference::model::RefModel),
        Perturbed(RefPerturbed),
    }
    let mut shaders = Vec::new();
    for m in materials {
        let t = unit::table::<N>(m)?;
        let entries: Vec<[u8; 4]> = t.entries().iter().map(|c| c.to_array()).collect();
        let table = RefTable::new(&entries).map_err(|_| UnitError::TableSize(N))?;
        let sh = match &m.shader {
            ShaderSpec::Model(model) => Shading::Model(bridge::ref_model(model)),
            ShaderSpec::Perturbed(p) => {
                Shading::Perturbed(RefPerturbed::new(p, bridge::wrap(m.wrap)))
            }
        };
        shaders.push((sh, table));
    }
    let filter = unit::ref_filter(cfg);
    let norm = unit::ref_norm(cfg.norm);
    let nyq = if cfg.cull {
        Nyquist::Cull
    } else {
        Nyquist::Widen
    };
    let (w, h) = scene.size();
    let bg = scene.background.map(f64::from);
    let mut img = vec![bg; usize::from(w) * usize::from(h)];
    let mut zbuf = vec![u16::MAX; usize::from(w) * usize::from(h)];
    let mut depth = DepthBuffer::new(&mut zbuf, Rect::from_size(w, h));
    let mut raster = Rasterizer::new(Rect::from_size(w, h));
    // Lit scenes: the texture's reference colour times the renderer's exact light (the light
    // is integer maths shared with the device; the reference is about the texture).
    let mut draw =
        |obj: usize, tri: &[texcore::raster::ScreenVertex; 3], light: Option<&TriangleLight>| {
            let Some(o) = TriangleSource::object(scene, obj) else {
                return;
            };
            let Some((sh, table)) = shaders.get(o.texture) else {
                return;
            };
            let mut seg_sink = |seg: &Segment| {
                let f = |p: texcore::format::TexPoint| p.to_bits().map(|v| f64::from(v) / 65536.0);
                let s0 = f(seg.s0);
                let ds = f(seg.ds);
                let dsdy = f(seg.dsdy);
                for i in 0..seg.len {
                    let s = [0, 1, 2].map(|k| s0[k] + f64::from(i) * ds[k]);
                    let fp = Footprint { s, dsdx: ds, dsdy };
                    let c = match sh {
                        Shading::Model(r) => r.pixel_color(&fp, table, filter, norm, nyq),
                        Shading::Perturbed(r) => r.pixel_color(&fp, table, filter, norm),
                    };
                    let c = match light {
                        Some(l) => {
                            let lv = l.at(seg.x0 + i, seg.y).map(|v| f64::from(v) / 65536.0);
                            [c[0] * lv[0], c[1] * lv[1], c[2] * lv[2], c[3]]
                        }
                        None => c,
                    };
                    let idx = usize::from(seg.y) * usize::from(w) + usize::from(seg.x0 + i);
                    if let Some(px) = img.get_mut(idx) {
                        *px = match o.blend {
                            Blend::Opaque => c,
                            Blend::Over => over_f64(c, *px),
                        };
                    }
                }
            };
            match (o.depth, depth.as_mut()) {
                (true, Some(d)) => raster.draw_depth(tri, &o.raster, d, &mut seg_sink),
                _ => raster.draw(tri, &o.raster, &mut seg_sink),
            }
        };
    if scene.is_lit() {
        scene.for_each_lit_triangle_by_quad(&mut |_| true, &mut |_, o, t, l| {
            draw(o, t, Some(&TriangleLight::new(t, &l())))
        });
    } else {
        scene.for_each_triangle_static(&mut |o, t| draw(o, t, None));
    }
    Ok(img)
}

/// The f64 reference image of frame `frame` of `scene`: the same geometry (texcore's rasterizer and
/// depth test), every pixel shaded by the reference model at the pixel's solid coordinate with the
/// segment's Jacobian, blending in f64.
pub fn reference_frame(
    scene: &Scene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
) -> Result<Vec<[f64; 4]>, UnitError> {
    reference_host_frame(&HostScene::builtin(scene.clone()), frame, cfg, hash)
}

/// The f64 reference image of an already framed scene with its slot materials (what
/// [`reference_host_frame`] computes after [`HostScene::frame`]).
pub fn reference_framed(
    scene: &Scene,
    materials: &[MaterialSpec],
    cfg: &UnitConfig,
) -> Result<Vec<[f64; 4]>, UnitError> {
    crate::dispatch_table_size!(cfg.table_size, reference_n(scene, materials, cfg))
}

/// [`reference_frame`] of a host scene (built-in or from a file).
pub fn reference_host_frame(
    scene: &HostScene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
) -> Result<Vec<[f64; 4]>, UnitError> {
    let (s, materials) = scene.frame(frame, hash)?;
    crate::dispatch_table_size!(cfg.table_size, reference_n(&s, &materials, cfg))
}

/// Renders a scene frame with texcore and with the reference and compares them.
pub fn check_scene(
    scene: &Scene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
) -> Result<Metrics, UnitError> {
    check_host_scene(&HostScene::builtin(scene.clone()), frame, cfg, hash)
}

/// [`check_scene`] of a host scene (built-in or from a file).
pub fn check_host_scene(
    scene: &HostScene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
) -> Result<Metrics, UnitError> {
    let r = render_host_frame(scene, frame, cfg, hash, Output::Color)?;
    let reference = reference_host_frame(scene, frame, cfg, hash)?;
    compare_to_reference(&r.frame.pixels, &reference).map_err(|e| UnitError::Render(e.to_string()))
}
