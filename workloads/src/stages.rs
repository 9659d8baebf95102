//! Per-stage workloads: each stage of the pixel path alone, so its instructions per pixel (per
//! triangle for set-up) can be read off on its own (shared with the host, like `planes`).
//!
//! Every workload `f(hash, work)` first builds its inputs; with `work == false` it stops there
//! (keeping the inputs alive with `black_box`) and returns a checksum of them. The device measures
//! both, and the host takes the difference as the stage's cost, so set-up (colour tables, sums,
//! models) never pollutes a per-pixel figure. The consumer of each stage's output is one FNV-1a
//! fold per pixel (`fold`: an xor and a multiply), included in the figure.
//!
//! | stage | what runs per unit | units |
//! |---|---|---|
//! | `noise-octave` | one trilinear value-noise octave, forward-differenced (`EvalMode::Fd`), no gradients, zero quadric | 64 x 64 pixels, 16 pixels per cell, spans of 16 |
//! | `noise-octave-grad` | the same with the filter-width gradients | same |
//! | `quadric` | the quadric `50 s^2 + 50 t^2` alone (forward differenced) | 64 x 64 pixels, spans of 16 |
//! | `color-lookup` | `ColorTable::shade` (mod, nearest) of a sweep of `f` | 4096 look-ups |
//! | `csat` | `ColorStage::shade` with the summed-area box filter, sweeps of `f` and `w` | 4096 look-ups |
//! | `raster-setup` | `TriangleSetup::new` of a perspective (`Every16`) triangle | 64 triangles |
//! | `perspective-every16` | rasterizing a full-screen perspective quad into segments, divides every 16 pixels | 128 x 128 pixels |
//! | `perspective-affine` | the same quad, affine (no divides) | 128 x 128 pixels |

use texcore::filter::{Antialias, ColorStage};
use texcore::format::{Amplitude, FilterWidth, MatrixEntry, QuadricCoeff, TexPoint, TexValue};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, TextureModel};
use texcore::noise::NoiseBasis;
use texcore::presets::{CheckPlane, MARBLE_KEYS};
use texcore::quadric::Quadric;
use texcore::raster::{
    Perspective, Rasterizer, Rect, ScreenVertex, Segment, TriangleOptions, TriangleSetup,
};
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::table::{KeySpacing, TableLookup, TableWrap};
use texcore::transform::Affine3;

use crate::planes::{plane_span, SEGMENT, TABLE, TERMS};

/// FNV-1a 32-bit offset basis.
pub const FNV_OFFSET: u32 = 0x811C_9DC5;

/// One FNV-1a step over a 32-bit word.
#[inline(always)]
pub fn fold(acc: u32, word: u32) -> u32 {
    (acc ^ word).wrapping_mul(0x0100_0193)
}

/// Side of the square pixel workloads.
pub const STAGE_SIZE: u32 = 64;
/// Look-ups of the colour-stage workloads.
pub const LOOKUPS: u32 = 4096;
/// Triangles of the set-up workload.
pub const SETUP_TRIANGLES: usize = 64;
/// Side of the rasterized quad.
pub const QUAD_SIZE: u16 = 128;

/// One stage workload.
#[derive(Clone, Copy)]
pub struct Stage {
    /// Name (the job is `stage:<name>`).
    pub name: &'static str,
    /// What one unit is (`pixel`, `lookup`, `triangle`).
    pub unit: &'static str,
    /// Units of work.
    pub units: u32,
    /// The workload.
    pub run: fn(HashKind, bool) -> u32,
}

/// Every stage workload, in job order.
pub const STAGES: [Stage; 8] = [
    Stage {
        name: "noise-octave",
        unit: "pixel",
        units: STAGE_SIZE * STAGE_SIZE,
        run: noise_octave,
    },
    Stage {
        name: "noise-octave-grad",
        unit: "pixel",
        units: STAGE_SIZE * STAGE_SIZE,
        run: noise_octave_grad,
    },
    Stage {
        name: "quadric",
        unit: "pixel",
        units: STAGE_SIZE * STAGE_SIZE,
        run: quadric,
    },
    Stage {
        name: "color-lookup",
        unit: "lookup",
        units: LOOKUPS,
        run: color_lookup,
    },
    Stage {
        name: "csat",
        unit: "lookup",
        units: LOOKUPS,
        run: csat,
    },
    Stage {
        name: "raster-setup",
        unit: "triangle",
        units: SETUP_TRIANGLES as u32,
        run: raster_setup,
    },
    Stage {
        name: "perspective-every16",
        unit: "pixel",
        units: QUAD_SIZE as u32 * QUAD_SIZE as u32,
        run: perspective_every16,
    },
    Stage {
        name: "perspective-affine",
        unit: "pixel",
        units: QUAD_SIZE as u32 * QUAD_SIZE as u32,
        run: perspective_affine,
    },
];

/// The stage called `name`.
pub fn stage(name: &str) -> Option<&'static Stage> {
    STAGES.iter().find(|s| s.name == name)
}

/// The unit square at `r = 1/2` in `STAGE_SIZE` pixels.
const UNIT_PLANE: CheckPlane = CheckPlane {
    origin: [0, 0, 32768],
    step_x: [65536 / STAGE_SIZE as i32, 0, 0],
    step_y: [0, 65536 / STAGE_SIZE as i32, 0],
};

/// Evaluates `model` over the unit plane (spans of 16) folding `f` (and the gradients' high words
/// when they are on).
fn eval_plane(model: &TextureModel<TERMS>, opts: EvalOptions, work: bool) -> u32 {
    let model = core::hint::black_box(model);
    if !work {
        return fold(FNV_OFFSET, model.terms().len() as u32);
    }
    let mut ev = SpanEvaluator::new(model, opts);
    let mut acc = FNV_OFFSET;
    for y in 0..STAGE_SIZE {
        let mut x0 = 0;
        while x0 < STAGE_SIZE {
            let span = plane_span(&UNIT_PLANE, x0, y, SEGMENT);
            ev.eval(&span, |s| {
                acc = fold(acc, s.f.to_bits() as u32);
                if opts.gradients {
                    acc = fold(acc, (s.gx >> 32) as u32 ^ (s.gy >> 32) as u32);
                }
            });
            x0 += SEGMENT;
        }
    }
    acc
}

fn octave_model(hash: HashKind) -> TextureModel<TERMS> {
    // 4 cells across the 64-pixel plane: 16 pixels per cell, forward differencing pays.
    let four = MatrixEntry::from_bits(4 << 16);
    TextureModel::new(Quadric::ZERO, TableWrap::Mod)
        .with(NoiseTerm::new(
            Amplitude::from_bits(1 << 16),
            Affine3::scale(four),
            NoiseBasis::trilinear(hash),
        ))
        .unwrap_or_else(|_| TextureModel::new(Quadric::ZERO, TableWrap::Mod))
}

/// One value-noise octave, forward differenced, no gradients.
pub fn noise_octave(hash: HashKind, work: bool) -> u32 {
    let opts = EvalOptions {
        mode: EvalMode::Fd,
        gradients: false,
        cull: true,
        ..Default::default()
    };
    eval_plane(&octave_model(hash), opts, work)
}

/// One value-noise octave, forward differenced, with the filter-width gradients.
pub fn noise_octave_grad(hash: HashKind, work: bool) -> u32 {
    let opts = EvalOptions {
        mode: EvalMode::Fd,
        gradients: true,
        cull: true,
        ..Default::default()
    };
    eval_plane(&octave_model(hash), opts, work)
}

/// The zone-plate quadric alone.
pub fn quadric(_hash: HashKind, work: bool) -> u32 {
    let fifty = QuadricCoeff::from_bits(50 << 16);
    let z = QuadricCoeff::ZERO;
    let q = Quadric::from_coefficients([fifty, z, z, z, fifty, z, z, z, z, z]);
    let model = TextureModel::new(q, TableWrap::Mod);
    let opts = EvalOptions {
        mode: EvalMode::Fd,
        gradients: false,
        cull: true,
        ..Default::default()
    };
    eval_plane(&model, opts, work)
}

/// The `f` of look-up `i`: a sweep over several table periods with an odd step.
#[inline(always)]
fn sweep_f(i: u32) -> TexValue {
    TexValue::from_bits((i.wrapping_mul(0x0001_3579) & 0x3_FFFF) as i32)
}

/// Nearest look-up of the marble colour table (mod).
pub fn color_lookup(_hash: HashKind, work: bool) -> u32 {
    let Some(t) = texcore::ready::key_table::<TABLE>(&MARBLE_KEYS, KeySpacing::Linear).ok() else {
        return 0;
    };
    let t = core::hint::black_box(&t);
    if !work {
        return fold(FNV_OFFSET, t.entries()[0].to_u32());
    }
    let mut acc = FNV_OFFSET;
    for i in 0..LOOKUPS {
        acc = fold(
            acc,
            t.shade(sweep_f(i), TableWrap::Mod, TableLookup::Nearest)
                .to_u32(),
        );
    }
    acc
}

/// The summed-area box filter of the marble colour table (mod), widths from 0 to 2 N.
pub fn csat(_hash: HashKind, work: bool) -> u32 {
    let Some(t) = texcore::ready::key_table::<TABLE>(&MARBLE_KEYS, KeySpacing::Linear).ok() else {
        return 0;
    };
    let Ok(stage) =
        ColorStage::<TABLE>::new(t, TableWrap::Mod, TableLookup::Nearest, Antialias::Csat)
    else {
        return 0;
    };
    let stage = core::hint::black_box(&stage);
    if !work {
        return fold(FNV_OFFSET, stage.table().entries()[0].to_u32());
    }
    let mut acc = FNV_OFFSET;
    for i in 0..LOOKUPS {
        // Widths sweep 0 .. 512 entries (a quarter of them past N: the mean).
        let w = FilterWidth::from_bits(i.wrapping_mul(0x0002_0003) & 0x01FF_FFFF);
        acc = fold(acc, stage.shade(sweep_f(i), w).to_u32());
    }
    acc
}

/// A screen vertex at pixel `(x, y)` (sub-pixel raw), depth `z`, `1/w` raw `w`, texture `s`.
fn vertex(x: i32, y: i32, z: u16, w: u32, s: [i32; 3]) -> ScreenVertex {
    ScreenVertex::from_bits(x, y, z, w, TexPoint::from_bits(s[0], s[1], s[2]))
}

/// `SETUP_TRIANGLES` triangles of varied shape, size and perspective inside a 320 x 240 screen.
fn setup_triangles() -> [[ScreenVertex; 3]; SETUP_TRIANGLES] {
    let mut tris = [[ScreenVertex::default(); 3]; SETUP_TRIANGLES];
    let mut r: u32 = 0x1234_5678;
    let mut next = |m: u32| {
        r = r.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (r >> 8) % m
    };
    for tri in tris.iter_mut() {
        for v in tri.iter_mut() {
            let x = next(320 << 4) as i32;
            let y = next(240 << 4) as i32;
            let w = (1 << 28) + next(1 << 30);
            let s = [
                next(1 << 20) as i32,
                next(1 << 20) as i32,
                next(1 << 18) as i32,
            ];
            *v = vertex(x, y, next(65535) as u16, w, s);
        }
    }
    tris
}

/// `TriangleSetup::new` of perspective triangles.
pub fn raster_setup(_hash: HashKind, work: bool) -> u32 {
    let tris = setup_triangles();
    let tris = core::hint::black_box(&tris);
    if !work {
        return fold(FNV_OFFSET, tris[0][0].x.to_bits() as u32);
    }
    let opts = TriangleOptions::new(Perspective::Every16);
    let mut acc = FNV_OFFSET;
    for tri in tris.iter() {
        match TriangleSetup::new(tri, &opts) {
            Ok(s) => {
                let (y0, y1) = s.rows();
                acc = fold(acc, (s.area2() as u32) ^ (y0 as u32) ^ ((y1 as u32) << 16));
            }
            Err(_) => acc = fold(acc, 0xFFFF_FFFF),
        }
    }
    acc
}

/// A floor seen in perspective filling the `QUAD_SIZE` square: far edge at the top (`1/w` = 1/4),
/// near edge at the bottom (`1/w` = 1).
fn floor_quad() -> [ScreenVertex; 4] {
    let n = i32::from(QUAD_SIZE) << 4;
    let far = 1u32 << 29;
    let near = 1u32 << 31;
    [
        vertex(0, 0, 0, far, [0, 8 << 16, 32768]),
        vertex(n, 0, 0, far, [8 << 16, 8 << 16, 32768]),
        vertex(n, n, 0, near - 1, [8 << 16, 0, 32768]),
        vertex(0, n, 0, near - 1, [0, 0, 32768]),
    ]
}

fn rasterize_quad(mode: Perspective, work: bool) -> u32 {
    let quad = floor_quad();
    let quad = core::hint::black_box(&quad);
    if !work {
        return fold(FNV_OFFSET, quad[0].inv_w.to_bits());
    }
    let opts = TriangleOptions::new(mode);
    let mut raster = Rasterizer::new(Rect::from_size(QUAD_SIZE, QUAD_SIZE));
    let mut acc = FNV_OFFSET;
    let mut sink = |seg: &Segment| {
        let s0 = seg.s0.to_bits();
        let ds = seg.ds.to_bits();
        acc = fold(acc, u32::from(seg.len) ^ (u32::from(seg.x0) << 16));
        acc = fold(acc, (s0[0] ^ s0[1]) as u32);
        acc = fold(acc, (ds[0] ^ ds[1]) as u32);
    };
    raster.draw(&[quad[0], quad[1], quad[2]], &opts, &mut sink);
    raster.draw(&[quad[0], quad[2], quad[3]], &opts, &mut sink);
    acc
}

/// Rasterizing the perspective floor with exact divides every 16 pixels.
pub fn perspective_every16(_hash: HashKind, work: bool) -> u32 {
    rasterize_quad(Perspective::Every16, work)
}

/// Rasterizing the same floor affinely.
pub fn perspective_affine(_hash: HashKind, work: bool) -> u32 {
    rasterize_quad(Perspective::Affine, work)
}
