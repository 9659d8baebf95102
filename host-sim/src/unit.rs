//! Host-side configuration of a texture unit: a material (preset or scene texture) plus the
//! accuracy knobs, dispatched to texcore's const-generic types, and rendering of check planes with
//! texcore and with the f64 reference.

use serde::Serialize;
use texcore::bandlimit::BandLimit;
use texcore::filter::{Antialias, GradientNorm, WidthSource};
use texcore::format::TexPoint;
use texcore::hash::HashKind;
use texcore::material::PerturbedParams;
use texcore::model::{Precision, TextureModel};
use texcore::presets::{self, CheckPlane, Key, PRESET_TERMS};
use texcore::ready::{Material, MaterialError, TextureOptions};
use texcore::span::{EvalMode, RowCache, Span};
use texcore::table::{ColorTable, KeySpacing, TableError, TableLookup, TableWrap};
use texcore::texture::{DifferenceMemory, ShadeStats, Shader, Texture};

use crate::bridge;
use crate::metrics::{compare_to_reference, Metrics};
use crate::reference::model::{Norm, Nyquist};
use crate::reference::perturbed::RefPerturbed;
use crate::reference::plane::Plane;
use crate::reference::table::{Filter, Lookup, RefTable};

/// What computes `f`, on the host.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShaderSpec {
    /// A quadric-plus-noise model (boxed: it is much larger than the perturbed parameters).
    Model(Box<TextureModel<PRESET_TERMS>>),
    /// A perturbed material.
    Perturbed(PerturbedParams),
}

/// A material: shader, colour keys and table wrap.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MaterialSpec {
    /// Name for messages and reports.
    pub name: String,
    /// The shader.
    pub shader: ShaderSpec,
    /// Key colours (U0F16 positions).
    pub keys: Vec<Key>,
    /// Keys placed at `c^2`.
    pub squared_keys: bool,
    /// Table wrap.
    pub wrap: TableWrap,
    /// The plane `check` samples.
    pub plane: CheckPlane,
}

/// The accuracy knobs of a texture unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct UnitConfig {
    /// Colour-table entries (power of two, 2..=1024).
    pub table_size: usize,
    /// Nearest or linear look-up.
    #[serde(serialize_with = "ser_display")]
    pub lookup: TableLookup,
    /// Antialiasing filter.
    #[serde(serialize_with = "ser_display")]
    pub aa: Antialias,
    /// Gradient norm of the filter width.
    #[serde(serialize_with = "ser_display")]
    pub norm: GradientNorm,
    /// Span evaluation mode.
    #[serde(serialize_with = "ser_mode")]
    pub mode: EvalMode,
    /// Cull octaves past Nyquist.
    pub cull: bool,
    /// How culling fades and spreads the octaves past Nyquist (`texcore::bandlimit`).
    #[serde(serialize_with = "ser_display")]
    pub band_limit: BandLimit,
    /// Arithmetic precision of the noise terms (`docs/model.md` 3.2; default 16/16, native).
    #[serde(serialize_with = "ser_precision")]
    pub precision: Precision,
    /// Where the filter widths come from: the analytic gradients (exact, the default) or the
    /// differences of neighbouring values (approximate: check planes through
    /// `texcore::texture::DifferenceSpans`, scenes through `Renderer::with_differences`).
    #[serde(serialize_with = "ser_display")]
    pub widths: WidthSource,
}

fn ser_precision<S: serde::Serializer>(p: &Precision, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let mut st = s.serialize_struct("Precision", 2)?;
    st.serialize_field("coord_bits", &p.coord_bits())?;
    st.serialize_field("value_bits", &p.value_bits())?;
    st.end()
}

fn ser_mode<S: serde::Serializer>(m: &EvalMode, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&crate::multipass::mode_name(*m))
}

fn ser_display<T: core::fmt::Display, S: serde::Serializer>(
    v: &T,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.serialize_str(&v.to_string())
}

impl Default for UnitConfig {
    fn default() -> Self {
        UnitConfig {
            table_size: 256,
            lookup: TableLookup::Nearest,
            aa: Antialias::Csat,
            norm: GradientNorm::L2,
            mode: EvalMode::Auto,
            cull: true,
            band_limit: BandLimit::DEFAULT,
            precision: Precision::NATIVE,
            widths: WidthSource::Gradients,
        }
    }
}

/// Errors building a texture unit.
#[derive(Debug, thiserror::Error)]
pub enum UnitError {
    /// Unknown preset name.
    #[error("unknown preset `{0}` (known: {known})", known = presets::NAMES.join(", "))]
    UnknownPreset(String),
    /// Colour table problem.
    #[error("colour table: {0}")]
    Table(TableError),
    /// The material could not become a texture (its colour table, filter or shader).
    #[error("{0}")]
    Material(MaterialError),
    /// Model problem.
    #[error("texture model: {0}")]
    Model(texcore::model::ModelError),
    /// Unsupported table size.
    #[error("table size {0} is not a power of two in 2..=1024")]
    TableSize(usize),
    /// The renderer refused the scene.
    #[error("render: {0}")]
    Render(String),
    /// A plane too wide for the memory of the filter widths from differences.
    #[error(
        "filter widths from differences take planes up to {max} pixels wide, not {width} \
         (use --widths gradients)"
    )]
    TooWide {
        /// The plane's width.
        width: u32,
        /// The widest plane taken.
        max: usize,
    },
}

/// The widest plane [`render_plane`] shades with filter widths from differences.
pub const DIFFERENCES_MAX_WIDTH: usize = 8192;

/// The preset `name` as a material.
pub fn preset_material(name: &str, hash: HashKind) -> Result<MaterialSpec, UnitError> {
    if let Some(p) = presets::by_name(name, hash) {
        return Ok(MaterialSpec {
            name: p.name.to_string(),
            wrap: p.model.wrap(),
            shader: ShaderSpec::Model(Box::new(p.model)),
            keys: p.keys.to_vec(),
            squared_keys: p.squared_keys,
            plane: p.plane,
        });
    }
    let p = presets::perturbed_by_name(name, hash)
        .ok_or_else(|| UnitError::UnknownPreset(name.to_string()))?;
    Ok(MaterialSpec {
        name: name.to_string(),
        shader: ShaderSpec::Perturbed(p.params),
        keys: p.keys.to_vec(),
        squared_keys: p.squared_keys,
        wrap: p.wrap,
        plane: p.plane,
    })
}

/// The key spacing of a material.
fn spacing(m: &MaterialSpec) -> KeySpacing {
    if m.squared_keys {
        KeySpacing::Squared
    } else {
        KeySpacing::Linear
    }
}

/// The colour table of a material at size `N`.
pub fn table<const N: usize>(m: &MaterialSpec) -> Result<ColorTable<N>, UnitError> {
    texcore::ready::key_table(&m.keys, spacing(m)).map_err(UnitError::Material)
}

/// A texcore texture for a material and configuration.
pub fn texture<const N: usize>(
    m: &MaterialSpec,
    cfg: &UnitConfig,
) -> Result<Texture<PRESET_TERMS, N>, UnitError> {
    let shader = match &m.shader {
        ShaderSpec::Model(model) => {
            let mut model = (**model).clone();
            if !cfg.precision.is_native() {
                model.set_precision(cfg.precision);
            }
            Shader::Model(model)
        }
        ShaderSpec::Perturbed(p) => Shader::Perturbed(
            texcore::material::PerturbedMaterial::new(p, m.wrap)
                .map_err(UnitError::Model)?
                .with_precision(cfg.precision),
        ),
    };
    let opts = TextureOptions {
        lookup: cfg.lookup,
        norm: cfg.norm,
        mode: cfg.mode,
        cull: cfg.cull,
        band_limit: cfg.band_limit,
    };
    Material::new(shader, m.wrap, &m.keys)
        .with_spacing(spacing(m))
        .texture_with(cfg.aa, opts)
        .map_err(UnitError::Material)
}

/// An RGBA8 image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels.
    pub pixels: Vec<[u8; 4]>,
}

/// Pixels per span when a check plane is rendered: the segment length the rasterizer's default
/// perspective mode (`Every16`) delivers, which bounds the drift of the rounded lattice step
/// (`docs/model.md` section 3) to 8 raw units per term.
pub const PLANE_SEGMENT: u32 = 16;

/// The span of pixels `x0 .. x0 + len` of row `y` of a check plane.
pub fn plane_span(p: &CheckPlane, x0: u32, y: u32, len: u32) -> Span {
    let s0 = [0, 1, 2].map(|i| {
        let v = i64::from(p.origin[i])
            + (i64::from(p.step_x[i]) * (2 * i64::from(x0) + 1)) / 2
            + (i64::from(p.step_y[i]) * (2 * i64::from(y) + 1)) / 2;
        v as i32
    });
    Span {
        s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
        ds: TexPoint::from_bits(p.step_x[0], p.step_x[1], p.step_x[2]),
        dsdy: TexPoint::from_bits(p.step_y[0], p.step_y[1], p.step_y[2]),
        len: len.min(u32::from(u16::MAX)) as u16,
    }
}

/// The spans of row `y` of a check plane `width` pixels wide, [`PLANE_SEGMENT`] pixels each.
pub fn plane_row(p: &CheckPlane, y: u32, width: u32) -> impl Iterator<Item = Span> + '_ {
    (0..width)
        .step_by(PLANE_SEGMENT as usize)
        .map(move |x0| plane_span(p, x0, y, PLANE_SEGMENT.min(width - x0)))
}

/// Scales a 256-pixel check plane to `size` pixels a side (same area of texture space).
pub fn scaled_plane(p: &CheckPlane, size: u32) -> CheckPlane {
    let k = |v: i32| ((i64::from(v) * 256) / i64::from(size.max(1))) as i32;
    CheckPlane {
        origin: p.origin,
        step_x: p.step_x.map(k),
        step_y: p.step_y.map(k),
    }
}

fn render_plane_n<const N: usize>(
    m: &MaterialSpec,
    cfg: &UnitConfig,
    plane: &CheckPlane,
    size: u32,
) -> Result<(Image, ShadeStats), UnitError> {
    let tex = texture::<N>(m, cfg)?;
    let mut ev = tex.evaluator();
    let mut pixels = Vec::with_capacity((size * size) as usize);
    // A model's spans through the plane's set-up (the device's path, `workloads::planes`; the
    // same colours as each span set up on its own).
    let setup = workloads::planes::span_plane(plane, size).and_then(|p| ev.plane_setup(&p));
    if cfg.widths == WidthSource::Differences {
        let too_wide = || UnitError::TooWide {
            width: size,
            max: DIFFERENCES_MAX_WIDTH,
        };
        if size as usize > DIFFERENCES_MAX_WIDTH {
            return Err(too_wide());
        }
        let mut mem = Box::new(DifferenceMemory::<DIFFERENCES_MAX_WIDTH>::new());
        let mut cache = RowCache::<{ texcore::texture::workload::peers::ROW_EVENTS }>::new();
        let mut emit = |c: texcore::color::Rgba8888| pixels.push(c.to_array());
        match &setup {
            // The spans of the plane, as the device's accuracy jobs shade them.
            Some(s) => {
                let mut spans = ev
                    .difference_spans(s, &mut cache, &mut mem)
                    .ok_or_else(too_wide)?;
                for y in 0..size {
                    for x0 in (0..size).step_by(PLANE_SEGMENT as usize) {
                        let len = PLANE_SEGMENT.min(size - x0);
                        spans.shade(x0 as u16, y as u16, len as u16, &mut emit);
                    }
                }
            }
            // A perturbed material (no plane set-up): whole rows.
            None => {
                let first = plane_span(plane, 0, 0, size);
                let mut rows = ev
                    .difference_rows(&first, &mut cache, &mut mem)
                    .ok_or_else(too_wide)?;
                for _ in 0..size {
                    rows.next_shade(&mut emit);
                }
            }
        }
    } else {
        for y in 0..size {
            for x0 in (0..size).step_by(PLANE_SEGMENT as usize) {
                let len = PLANE_SEGMENT.min(size - x0);
                let emit = |c: texcore::color::Rgba8888| pixels.push(c.to_array());
                match &setup {
                    // size <= u16::MAX (`workloads::planes::span_plane`).
                    Some(s) => ev.shade_plane(s, x0 as u16, y as u16, len as u16, emit),
                    None => ev.shade(&plane_span(plane, x0, y, len), emit),
                }
            }
        }
    }
    Ok((
        Image {
            width: size,
            height: size,
            pixels,
        },
        ev.stats(),
    ))
}

/// Calls `$f::<N>(args)` for the runtime table size.
#[macro_export]
macro_rules! dispatch_table_size {
    ($n:expr, $f:ident ( $($arg:expr),* )) => {
        match $n {
            2 => $f::<2>($($arg),*),
            4 => $f::<4>($($arg),*),
            8 => $f::<8>($($arg),*),
            16 => $f::<16>($($arg),*),
            32 => $f::<32>($($arg),*),
            64 => $f::<64>($($arg),*),
            128 => $f::<128>($($arg),*),
            256 => $f::<256>($($arg),*),
            512 => $f::<512>($($arg),*),
            1024 => $f::<1024>($($arg),*),
            other => Err($crate::unit::UnitError::TableSize(other)),
        }
    };
}

/// Renders a material's check plane (`size x size`) with texcore.
pub fn render_plane(
    m: &MaterialSpec,
    cfg: &UnitConfig,
    size: u32,
) -> Result<(Image, ShadeStats), UnitError> {
    let plane = scaled_plane(&m.plane, size);
    dispatch_table_size!(cfg.table_size, render_plane_n(m, cfg, &plane, size))
}

fn ref_table_n<const N: usize>(m: &MaterialSpec) -> Result<RefTable, UnitError> {
    let t = table::<N>(m)?;
    let entries: Vec<[u8; 4]> = t.entries().iter().map(|c| c.to_array()).collect();
    RefTable::new(&entries).map_err(|_| UnitError::TableSize(N))
}

/// The reference's filter for a configuration.
pub fn ref_filter(cfg: &UnitConfig) -> Filter {
    let lookup = match cfg.lookup {
        TableLookup::Nearest => Lookup::Nearest,
        TableLookup::Linear => Lookup::Linear,
    };
    match cfg.aa {
        Antialias::None => Filter::Point(lookup),
        Antialias::Mip => Filter::Mip(lookup),
        Antialias::Csat | Antialias::Csat3 => Filter::Box,
        Antialias::Ramp => Filter::Ramp,
    }
}

/// The reference's norm.
pub fn ref_norm(n: GradientNorm) -> Norm {
    match n {
        GradientNorm::L1 => Norm::L1,
        GradientNorm::L2 => Norm::L2,
        GradientNorm::Max => Norm::Max,
    }
}

/// The f64 reference image of a material's check plane.
pub fn reference_plane(
    m: &MaterialSpec,
    cfg: &UnitConfig,
    size: u32,
) -> Result<Vec<[f64; 4]>, UnitError> {
    let table = dispatch_table_size!(cfg.table_size, ref_table_n(m))?;
    let plane: Plane = bridge::ref_plane(&scaled_plane(&m.plane, size), size, size);
    let filter = ref_filter(cfg);
    let norm = ref_norm(cfg.norm);
    let mut out = Vec::with_capacity((size * size) as usize);
    match &m.shader {
        ShaderSpec::Model(model) => {
            let r = bridge::ref_model(model);
            let nyq = if cfg.cull {
                Nyquist::Cull
            } else {
                Nyquist::Widen
            };
            for y in 0..size {
                for x in 0..size {
                    out.push(r.pixel_color(&plane.footprint(x, y), &table, filter, norm, nyq));
                }
            }
        }
        ShaderSpec::Perturbed(p) => {
            let r = RefPerturbed::new(p, bridge::wrap(m.wrap));
            for y in 0..size {
                for x in 0..size {
                    out.push(r.pixel_color(&plane.footprint(x, y), &table, filter, norm));
                }
            }
        }
    }
    Ok(out)
}

/// `texsim check`'s result.
#[derive(Clone, Debug, Serialize)]
pub struct CheckReport {
    /// Preset or scene name.
    pub name: String,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Configuration.
    pub config: UnitConfig,
    /// Comparison with the reference.
    #[serde(flatten)]
    pub metrics: Metrics,
}

/// Renders a material's check plane with texcore and the reference and compares them.
pub fn check_material(
    m: &MaterialSpec,
    cfg: &UnitConfig,
    size: u32,
) -> Result<CheckReport, UnitError> {
    let (img, _) = render_plane(m, cfg, size)?;
    let reference = reference_plane(m, cfg, size)?;
    let metrics = compare_to_reference(&img.pixels, &reference)
        .map_err(|_| UnitError::TableSize(cfg.table_size))?;
    Ok(CheckReport {
        name: m.name.clone(),
        width: size,
        height: size,
        config: *cfg,
        metrics,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`render_plane`] (a model's spans through the plane's set-up) gives every preset's check
    /// plane exactly as its spans set up one by one ([`plane_row`]), in each evaluation mode,
    /// filter and precision, at sizes with a short last span.
    #[test]
    fn plane_renders_equal_their_spans() {
        let configs = [
            UnitConfig::default(),
            UnitConfig {
                mode: EvalMode::Direct,
                aa: Antialias::None,
                ..UnitConfig::default()
            },
            UnitConfig {
                mode: EvalMode::Fd,
                aa: Antialias::Mip,
                cull: false,
                precision: Precision::new(10, 12).unwrap(),
                ..UnitConfig::default()
            },
        ];
        for name in presets::NAMES {
            let m = preset_material(name, HashKind::Integer).unwrap();
            for cfg in &configs {
                for size in [24, 37] {
                    let (img, _) = render_plane(&m, cfg, size).unwrap();
                    let plane = scaled_plane(&m.plane, size);
                    let tex = texture::<256>(&m, cfg).unwrap();
                    let mut ev = tex.evaluator();
                    let mut want = Vec::new();
                    for y in 0..size {
                        for span in plane_row(&plane, y, size) {
                            ev.shade(&span, |c| want.push(c.to_array()));
                        }
                    }
                    assert_eq!(img.pixels, want, "{name} {cfg:?} {size}");
                }
            }
        }
    }
}
