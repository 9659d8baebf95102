//! Host measurements of the accuracy report: images, references, errors, flicker and time.

use std::collections::HashMap;
use std::time::Instant;

use texcore::color::Rgba8888;
use texcore::filter::Antialias;
use texcore::hash::HashKind;
use texcore::presets::CheckPlane;
use texcore::raster::Perspective;
use texcore::render::{Output, Renderer};
use texcore::scene::Scene;
use texcore::sink::RgbaBuffer;
use texcore::table::{TableLookup, TableWrap};

use super::device_jobs::{self as fw, Config};
use crate::bridge;
use crate::metrics::{compare_to_reference, Metrics};
use crate::reference::model::Nyquist;
use crate::reference::table::{Lookup, RefTable};
use crate::scenes;
use crate::unit::{self, MaterialSpec, ShaderSpec, UnitConfig, UnitError};

/// The texture unit configuration (`host_sim::unit`) of a row's configuration.
pub fn unit_config(cfg: &Config) -> UnitConfig {
    UnitConfig {
        table_size: usize::from(cfg.table_size),
        lookup: cfg.lookup,
        aa: cfg.aa,
        norm: cfg.norm,
        mode: cfg.mode,
        cull: cfg.cull,
        band_limit: cfg.band_limit,
        precision: texcore::model::Precision::new(
            u32::from(cfg.coord_bits),
            u32::from(cfg.value_bits),
        )
        .unwrap_or_default(),
        widths: cfg.widths,
    }
}

/// The check plane whose first `size x size` pixels, as `unit` renders them (it scales a
/// preset's 256-pixel plane to the image size), are the first pixels of the 256-pixel plane at
/// its own scale: the device's window is the top-left corner of every error image.
pub fn plane_for(size: u32) -> CheckPlane {
    let p = fw::PLANE;
    let k = |v: i32| ((i64::from(v) * i64::from(size)) / 256) as i32;
    CheckPlane {
        origin: p.origin,
        step_x: p.step_x.map(k),
        step_y: p.step_y.map(k),
    }
}

/// The host material of a plane configuration (the model of [`fw::model`] with the marble keys).
pub fn plane_material(cfg: &Config, size: u32) -> Result<MaterialSpec, UnitError> {
    let model = fw::model(cfg).ok_or_else(|| UnitError::Render("no model".into()))?;
    Ok(MaterialSpec {
        name: "marble".into(),
        shader: ShaderSpec::Model(Box::new(model)),
        keys: texcore::presets::MARBLE_KEYS.to_vec(),
        squared_keys: false,
        wrap: TableWrap::Mod,
        plane: plane_for(size),
    })
}

/// What defines a configuration's f64 reference image (precision and evaluation mode never do:
/// the reference is exact).
fn reference_key(cfg: &Config) -> Config {
    Config {
        coord_bits: 16,
        value_bits: 16,
        mode: texcore::span::EvalMode::Auto,
        ..*cfg
    }
}

/// Whether a configuration renders the baseline's texture (same noise, hash and scene), so its
/// image can be compared with the baseline's reference and the supersampled truth.
pub fn same_texture(cfg: &Config) -> bool {
    cfg.perspective.is_none()
        && cfg.basis == fw::BASELINE.basis
        && cfg.fade == fw::BASELINE.fade
        && cfg.hash == fw::BASELINE.hash
}

/// FNV-1a over the colours of the top-left `side x side` pixels of a row-major image, each
/// folded as the device folds a colour of filter `aa` ([`fw::fold_colour`]).
pub fn window_checksum(pixels: &[[u8; 4]], width: u32, side: u32, aa: Antialias) -> u32 {
    let mut acc = fw::FNV_OFFSET;
    for y in 0..side {
        for x in 0..side {
            let p = pixels[(y * width + x) as usize];
            acc = fw::fold(acc, fw::fold_colour(aa, Rgba8888::from_array(p)));
        }
    }
    acc
}

/// Reference images, computed once per key.
#[derive(Default)]
pub struct References {
    plane: HashMap<String, Vec<[f64; 4]>>,
    scene: HashMap<String, Vec<[f64; 4]>>,
}

impl References {
    /// The f64 reference of a plane configuration (its own table, filter, norm and culling; ideal
    /// precision, exact evaluation).
    pub fn plane(&mut self, cfg: &Config, size: u32) -> Result<&Vec<[f64; 4]>, UnitError> {
        let key = format!("{:?}/{size}", reference_key(cfg));
        if !self.plane.contains_key(&key) {
            let m = plane_material(cfg, size)?;
            let r = unit::reference_plane(&m, &unit_config(&reference_key(cfg)), size)?;
            self.plane.insert(key.clone(), r);
        }
        Ok(&self.plane[&key])
    }

    /// Computes the plane references of `cfgs` that are not cached yet, in parallel (rayon),
    /// each distinct one once.
    pub fn fill_planes(&mut self, cfgs: &[&Config], size: u32) -> Result<(), UnitError> {
        use rayon::prelude::*;
        let mut todo: Vec<(String, &Config)> = Vec::new();
        for cfg in cfgs {
            let key = format!("{:?}/{size}", reference_key(cfg));
            if !self.plane.contains_key(&key) && todo.iter().all(|(k, _)| *k != key) {
                todo.push((key, cfg));
            }
        }
        let made = todo
            .into_par_iter()
            .map(|(key, cfg)| {
                let m = plane_material(cfg, size)?;
                let r = unit::reference_plane(&m, &unit_config(&reference_key(cfg)), size)?;
                Ok((key, r))
            })
            .collect::<Result<Vec<_>, UnitError>>()?;
        self.plane.extend(made);
        Ok(())
    }

    /// A plane reference computed before ([`References::plane`], [`References::fill_planes`]).
    pub fn cached_plane(&self, cfg: &Config, size: u32) -> Option<&Vec<[f64; 4]>> {
        self.plane.get(&format!("{:?}/{size}", reference_key(cfg)))
    }

    /// A scene's f64 reference (cached by `key`).
    pub fn scene(
        &mut self,
        key: &str,
        make: impl FnOnce() -> Result<Vec<[f64; 4]>, UnitError>,
    ) -> Result<&Vec<[f64; 4]>, UnitError> {
        if !self.scene.contains_key(key) {
            let r = make()?;
            self.scene.insert(key.to_string(), r);
        }
        Ok(&self.scene[key])
    }
}

/// Renders the first `size x size` pixels of the check plane with texcore (through
/// `host_sim::unit`, the host's own pixel path).
pub fn plane_image(cfg: &Config, size: u32) -> Result<Vec<[u8; 4]>, UnitError> {
    let m = plane_material(cfg, size)?;
    Ok(unit::render_plane(&m, &unit_config(cfg), size)?.0.pixels)
}

/// The checksum the device computes for a plane configuration, computed here with the same code
/// (`device_jobs::plane_texture` and `plane_checksum` over the device's window).
pub fn plane_device_checksum(cfg: &Config) -> Option<u32> {
    fn go<const N: usize>(cfg: &Config) -> Option<u32> {
        Some(fw::plane_checksum(
            &fw::plane_texture::<N>(cfg)?,
            cfg.widths,
            fw::SIDE,
        ))
    }
    match cfg.table_size {
        16 => go::<16>(cfg),
        32 => go::<32>(cfg),
        64 => go::<64>(cfg),
        128 => go::<128>(cfg),
        256 => go::<256>(cfg),
        512 => go::<512>(cfg),
        1024 => go::<1024>(cfg),
        _ => None,
    }
}

/// The checksum the device computes for a scene configuration, computed here with the same code.
pub fn scene_device_checksum(cfg: &Config, mode: Perspective) -> Option<u32> {
    let s = fw::scene(mode)?;
    let t = fw::scene_textures(cfg, &s)?;
    Some(fw::scene_checksum(&s, &t))
}

/// Host nanoseconds per pixel of a plane configuration: the device's job (same code) over
/// `size x size` pixels, `runs` timed runs (the texture is built once, outside the timing).
pub fn plane_time(cfg: &Config, size: u16, runs: usize) -> Option<Timing> {
    fn go<const N: usize>(cfg: &Config, size: u16, runs: usize) -> Option<Timing> {
        let tex = fw::plane_texture::<N>(cfg)?;
        let px = f64::from(size) * f64::from(size);
        Some(Timing::measure(runs, px, || {
            std::hint::black_box(fw::plane_checksum(&tex, cfg.widths, size));
        }))
    }
    match cfg.table_size {
        16 => go::<16>(cfg, size, runs),
        32 => go::<32>(cfg, size, runs),
        64 => go::<64>(cfg, size, runs),
        128 => go::<128>(cfg, size, runs),
        256 => go::<256>(cfg, size, runs),
        512 => go::<512>(cfg, size, runs),
        1024 => go::<1024>(cfg, size, runs),
        _ => None,
    }
}

/// Repeated timings of one workload.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Median ns per pixel.
    pub median: f64,
    /// Fastest run, ns per pixel.
    pub min: f64,
    /// Slowest run, ns per pixel.
    pub max: f64,
    /// Timed runs.
    pub runs: usize,
}

impl Timing {
    /// Times `runs` calls of `f` (after one untimed warm-up), each over `pixels` pixels.
    pub fn measure(runs: usize, pixels: f64, mut f: impl FnMut()) -> Timing {
        f();
        let mut t: Vec<f64> = (0..runs.max(1))
            .map(|_| {
                let start = Instant::now();
                f();
                start.elapsed().as_secs_f64() * 1e9 / pixels
            })
            .collect();
        t.sort_by(f64::total_cmp);
        let n = t.len();
        let median = if n % 2 == 1 {
            t[n / 2]
        } else {
            (t[n / 2 - 1] + t[n / 2]) / 2.0
        };
        Timing {
            median,
            min: t[0],
            max: t[n - 1],
            runs: n,
        }
    }
}

/// The seascape of the perspective rows ([`fw::scene`]) without its animation hook (it is
/// already at its still frame), so `host_sim::scenes` can render and reference it as is.
pub fn static_scene(mode: Perspective) -> Option<Scene> {
    let mut s = fw::scene(mode)?;
    s.animate = None;
    Some(s)
}

/// Renders a scene with the device's textures ([`fw::scene_textures`]) into an RGBA image.
pub fn scene_image(cfg: &Config, scene: &Scene) -> Option<Vec<[u8; 4]>> {
    let tex = fw::scene_textures(cfg, scene)?;
    let r = Renderer::new(&tex[..]).with_output(Output::Color);
    let (w, h) = scene.size();
    let mut img = vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
    let mut sink = RgbaBuffer::new(&mut img, w, 0, h)?;
    match r.needs_bands(scene) {
        Ok(false) => r.render_streamed(scene, &mut sink).ok()?,
        _ => return None,
    };
    Some(img.iter().map(|c| c.to_array()).collect())
}

/// Host nanoseconds per frame pixel of a scene configuration ([`fw::scene_checksum`]).
pub fn scene_time(cfg: &Config, scene: &Scene, runs: usize) -> Option<Timing> {
    let tex = fw::scene_textures(cfg, scene)?;
    let (w, h) = scene.size();
    let px = f64::from(w) * f64::from(h);
    Some(Timing::measure(runs, px, || {
        std::hint::black_box(fw::scene_checksum(scene, &tex));
    }))
}

/// The f64 reference of a scene frame: [`scenes::reference_frame`] with the configuration's
/// knobs.
pub fn scene_reference(
    scene: &Scene,
    frame: u32,
    cfg: &Config,
) -> Result<Vec<[f64; 4]>, UnitError> {
    scenes::reference_frame(scene, frame, &unit_config(cfg), cfg.hash)
}

/// A scene with every object drawn in perspective mode `mode`.
pub fn with_perspective(scene: &Scene, mode: Perspective) -> Scene {
    let mut s = scene.clone();
    for o in s.objects.iter_mut() {
        o.perspective = mode;
    }
    s
}

/// A scene at another image size (same view).
pub fn resized(scene: &Scene, w: u16, h: u16) -> Scene {
    let mut s = scene.clone();
    s.camera.width = w;
    s.camera.height = h;
    s
}

/// The supersampled truth of a scene frame: the f64 reference at `n` times the size in each
/// direction with exact perspective and point sampling (nearest entry), averaged over each
/// `n x n` block (stratified samples at the sub-pixel centres).
pub fn scene_supersampled(
    scene: &Scene,
    frame: u32,
    cfg: &Config,
    n: u16,
) -> Result<Vec<[f64; 4]>, UnitError> {
    let (w, h) = scene.size();
    let big = with_perspective(&resized(scene, w * n, h * n), Perspective::Exact);
    let point = Config {
        aa: Antialias::None,
        lookup: TableLookup::Nearest,
        ..*cfg
    };
    let r = scenes::reference_frame(&big, frame, &unit_config(&point), cfg.hash)?;
    Ok(downsample(&r, u32::from(w), u32::from(h), u32::from(n)))
}

/// Box-averages `n x n` blocks of a `(w n) x (h n)` image.
pub fn downsample(img: &[[f64; 4]], w: u32, h: u32, n: u32) -> Vec<[f64; 4]> {
    let bw = w * n;
    let inv = 1.0 / f64::from(n * n);
    let mut out = vec![[0.0; 4]; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let mut acc = [0.0; 4];
            for b in 0..n {
                for a in 0..n {
                    let p = img[((y * n + b) * bw + x * n + a) as usize];
                    for k in 0..4 {
                        acc[k] += p[k];
                    }
                }
            }
            out[(y * w + x) as usize] = acc.map(|c| c * inv);
        }
    }
    out
}

/// The supersampled truth of the check plane for a configuration's texture: `n x n` stratified
/// point samples per pixel of the f64 model through the baseline's 256-entry table (nearest).
pub fn plane_supersampled(cfg: &Config, size: u32, n: u32) -> Result<Vec<[f64; 4]>, UnitError> {
    let truth = Config {
        table_size: 256,
        lookup: TableLookup::Nearest,
        ..*cfg
    };
    let m = plane_material(&truth, size)?;
    let t = unit::table::<256>(&m)?;
    let entries: Vec<[u8; 4]> = t.entries().iter().map(|c| c.to_array()).collect();
    let table = RefTable::new(&entries).map_err(|_| UnitError::TableSize(256))?;
    let ShaderSpec::Model(model) = &m.shader else {
        return Err(UnitError::Render("not a model".into()));
    };
    let r = bridge::ref_model(model);
    let plane = bridge::ref_plane(&fw::PLANE, size, size);
    Ok(plane.supersample(&r, &table, Lookup::Nearest, n).pixels)
}

/// Errors of an image against a reference.
pub fn errors(img: &[[u8; 4]], reference: &[[f64; 4]]) -> Result<Metrics, UnitError> {
    compare_to_reference(img, reference).map_err(|e| UnitError::Render(e.to_string()))
}

/// Mean absolute frame-to-frame difference (8-bit units, RGB) over rows `rows` of `width`-pixel
/// frames.
pub fn flicker(frames: &[Vec<[f64; 4]>], width: u32, rows: std::ops::Range<u32>) -> f64 {
    let mut sum = 0.0;
    let mut n = 0.0;
    for pair in frames.windows(2) {
        for y in rows.clone() {
            for x in 0..width {
                let i = (y * width + x) as usize;
                for (a, b) in pair[1][i].iter().zip(&pair[0][i]).take(3) {
                    sum += (a - b).abs();
                    n += 1.0;
                }
            }
        }
    }
    if n > 0.0 {
        sum / n
    } else {
        0.0
    }
}

/// An RGBA8 image as f64.
pub fn to_f64(img: &[[u8; 4]]) -> Vec<[f64; 4]> {
    img.iter().map(|p| p.map(f64::from)).collect()
}

/// `Nyquist` policy of a configuration (for documentation of the references).
pub fn nyquist(cfg: &Config) -> Nyquist {
    if cfg.cull {
        Nyquist::Cull
    } else {
        Nyquist::Widen
    }
}

/// The lattice hash's name.
pub fn hash_name(h: HashKind) -> &'static str {
    match h {
        HashKind::Permutation => "perm",
        HashKind::Integer => "int",
    }
}
