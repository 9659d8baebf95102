//! Preset check planes through texcore's real pixel path (shared with the host).
//!
//! Every material of `texsim presets` (the eight model presets of `texcore::presets::by_name` and
//! Miné & Neyret's perturbed `mn-marble` / `mn-wood`) is built into a [`Texture`] with a 256-entry
//! colour table and the summed-area colour-table filter (csat), and its check plane is shaded,
//! [`SIZE`] x [`SIZE`] pixels in spans of 16 pixels exactly like `host_sim::unit::plane_row`, into
//! a [`ChecksumSink`] (FNV-1a over RGB565). `host_sim::unit::render_plane` computes the same image
//! on the host, so the checksums must be equal.
//!
//! This file has no firmware dependencies (only `texcore`): the host includes it verbatim
//! (`host_sim::report::shared`) to know the job list and the pixel counts. The lattice hash is a
//! parameter: the Cortex-M4F firmware uses the permutation hash, the rv32imc firmware the
//! table-free integer hash.

use texcore::color::Rgba8888;
use texcore::filter::Antialias;
use texcore::format::{TexPoint, TexValue};
use texcore::hash::HashKind;
use texcore::presets::{self, CheckPlane, PRESET_TERMS};
pub use texcore::ready::Material;
use texcore::sink::ChecksumSink;
use texcore::span::{Span, SpanPlane};
use texcore::texture::Texture;

/// Colour-table entries of every device texture.
pub const TABLE: usize = 256;
/// Noise-term capacity of every device texture.
pub const TERMS: usize = PRESET_TERMS;
/// The texture type the device jobs use.
pub type DeviceTexture = Texture<TERMS, TABLE>;

/// Check-plane image size in pixels (square).
pub const SIZE: u32 = 64;
/// Pixels per span (`host_sim::unit::PLANE_SEGMENT`).
pub const SEGMENT: u32 = 16;

/// Every material with a check plane, in `texsim presets` order.
pub const MATERIALS: [&str; 10] = presets::NAMES;

/// The check plane of the perturbed materials.
pub use texcore::presets::PERTURBED_PLANE;

/// The material `name` with lattice hash `hash` (as `host_sim::unit::preset_material`).
#[inline(never)]
pub fn material(name: &str, hash: HashKind) -> Option<Material<'static, TERMS>> {
    Material::by_name(name, hash)
}

/// The device texture of a material: nearest look-up, filter `aa`, L2 norm, `EvalMode::Auto`,
/// culling on (`host_sim::unit::UnitConfig::default()` with `aa`).
#[inline(never)]
pub fn texture(m: &Material<'_, TERMS>, aa: Antialias) -> Option<DeviceTexture> {
    m.texture(aa).ok()
}

/// A 256-pixel check plane scaled to `size` pixels (`host_sim::unit::scaled_plane`).
pub fn scaled_plane(p: &CheckPlane, size: u32) -> CheckPlane {
    let k = |v: i32| ((i64::from(v) * 256) / i64::from(size.max(1))) as i32;
    CheckPlane {
        origin: p.origin,
        step_x: p.step_x.map(k),
        step_y: p.step_y.map(k),
    }
}

/// Pixels `x0 .. x0 + len` of row `y` of a check plane (`host_sim::unit::plane_span`).
pub fn plane_span(p: &CheckPlane, x0: u32, y: u32, len: u32) -> Span {
    let c = |i: usize| -> i32 {
        let v = i64::from(p.origin[i])
            + (i64::from(p.step_x[i]) * (2 * i64::from(x0) + 1)) / 2
            + (i64::from(p.step_y[i]) * (2 * i64::from(y) + 1)) / 2;
        v as i32
    };
    Span {
        s0: TexPoint::from_bits(c(0), c(1), c(2)),
        ds: TexPoint::from_bits(p.step_x[0], p.step_x[1], p.step_x[2]),
        dsdy: TexPoint::from_bits(p.step_y[0], p.step_y[1], p.step_y[2]),
        len: len.min(u32::from(u16::MAX)) as u16,
    }
}

/// Shades the `size x size` image of `plane` with `tex`, rows top to bottom, spans of
/// [`SEGMENT`] pixels, into a checksum.
#[inline(never)]
///
/// A model's spans go through the plane's set-up ([`span_plane`], `TextureEvaluator::shade_plane`:
/// the terms set up once for the plane, the same colours); a perturbed material's are set up one
/// by one.
pub fn shade_plane(tex: &DeviceTexture, plane: &CheckPlane, size: u32) -> ChecksumSink {
    let mut sink = ChecksumSink::new();
    let mut ev = tex.evaluator();
    let setup = span_plane(plane, size).and_then(|p| ev.plane_setup(&p));
    for y in 0..size {
        let mut x0 = 0;
        while x0 < size {
            let len = SEGMENT.min(size - x0);
            let emit = |c: Rgba8888| sink.add_rgb565(c.to_rgb565().to_bits());
            match &setup {
                // x0 + len <= size <= u16::MAX (`span_plane`).
                Some(s) => ev.shade_plane(s, x0 as u16, y as u16, len as u16, emit),
                None => ev.shade(&plane_span(plane, x0, y, len), emit),
            }
            x0 += SEGMENT;
        }
    }
    sink
}

/// The spans of the `size x size` image of a check plane as a [`SpanPlane`]: span `(x0, y)` of
/// it is [`plane_span`]`(p, x0, y, len)` (for `x0, y >= 0` each start is the plane's origin plus
/// `x0` steps along and `y` steps down, the half-pixel offsets rounded once, in the origin); `None`
/// when the image is larger than `u16::MAX` or a start would leave the coordinate range.
pub fn span_plane(p: &CheckPlane, size: u32) -> Option<SpanPlane> {
    let size = u16::try_from(size).ok()?;
    let s = plane_span(p, 0, 0, 0);
    SpanPlane::new(s.s0, s.ds, s.dsdy, size, size).ok()
}

/// The set-up part of [`plane_checksum`] alone: builds the same texture (kept alive with
/// `black_box`) and folds a few filtered colours of its stage instead of shading the plane. The
/// device measures it as a separate job so that set-up can be subtracted from the plane's count.
#[inline(never)]
pub fn setup_checksum(name: &str, hash: HashKind) -> u32 {
    let Some(tex) = material(name, hash).and_then(|m| texture(&m, Antialias::Csat)) else {
        return 0;
    };
    let tex = core::hint::black_box(&tex);
    let mut sink = ChecksumSink::new();
    for f in [0, 0x4000, 0x8000, 0xC000] {
        let c = tex.stage().shade(
            TexValue::from_bits(f),
            texcore::format::FilterWidth::from_bits(3 << 16),
        );
        sink.add_rgb565(c.to_rgb565().to_bits());
    }
    sink.checksum()
}

/// Builds the csat texture of material `name` and shades its [`SIZE`] x [`SIZE`] check plane;
/// returns the image checksum (0 for an unknown name).
#[inline(never)]
pub fn plane_checksum(name: &str, hash: HashKind) -> u32 {
    let Some(m) = material(name, hash) else {
        return 0;
    };
    let plane = scaled_plane(&m.plane(), SIZE);
    match texture(&m, Antialias::Csat) {
        Some(tex) => shade_plane(&tex, &plane, SIZE).checksum(),
        None => 0,
    }
}
