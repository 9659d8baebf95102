//! `texcore-probe`: the smallest program that links texcore's pixel path as a product would, for
//! the size report (`texsim report size`).
//!
//! It builds a texture (the marble preset: a quadric plus four octaves of value noise, a
//! 256-entry colour table from the preset's keys by `texcore::ready::key_table`), hides it from the optimiser (`black_box`, as if the material were
//! loaded at run time, so every code path the compiled-in features allow stays reachable: every
//! noise basis, every evaluation mode, every colour filter), shades a 64 x 64 check plane into a
//! `ChecksumSink`, and with feature `render` also renders a scene through the banded renderer
//! (perspective, depth test, alpha blending; with `render-differences` also with the filter widths
//! from differences, `Renderer::with_differences`), and with feature `atlas` bakes and samples a small
//! texture atlas (`texcore::atlas`, `texcore::packed_mesh`), and with feature `differences` shades
//! the plane once more with the filter widths from differences
//! (`texcore::texture::DifferenceSpans`). It exits through semihosting with status 0, so it also
//! runs under QEMU (`firmware/qemu-run.sh`).
//!
//! Which texcore features are compiled in is the size report's feature set (`--no-default-features
//! --features ...`): `minimal` is none of them (value noise, integer hash, mod/clamp colour table,
//! no antialiasing).
//!
//! The probe also exports `TEXCORE_PROBE_SIZES` (`.rodata`): `core::mem::size_of` of the parts of
//! a texture-unit instance on this target, read from the ELF by the size report.
#![cfg_attr(target_os = "none", no_std, no_main)]
#![deny(unsafe_code)]

#[cfg(not(target_os = "none"))]
fn main() {}

#[cfg(target_os = "none")]
mod probe {
    use core::hint::black_box;
    use core::mem::size_of;
    use texcore::filter::{Antialias, ColorStage, GradientNorm};
    use texcore::format::TexPoint;
    use texcore::hash::HashKind;
    use texcore::model::{NoiseTerm, TextureModel};
    use texcore::presets;
    use texcore::ready::key_table;
    use texcore::sink::ChecksumSink;
    use texcore::span::{EvalMode, Span, SpanEvaluator};
    use texcore::table::{ColorTable, KeySpacing, TableLookup, TableWrap};
    use texcore::texture::{Shader, Texture, TextureEvaluator};

    const N: usize = 256;
    const T: usize = presets::PRESET_TERMS;

    #[cfg(feature = "csat")]
    const CSAT: usize = size_of::<texcore::filter::Csat<N>>();
    #[cfg(not(feature = "csat"))]
    const CSAT: usize = 0;
    /// The filter data an instance without `csat` holds beyond its table: the ramp's samples
    /// (`ramp`), else the MIP levels above level 0 (`mip`), else 0 (0 with `csat`, whose sums are
    /// `CSAT`).
    #[cfg(feature = "csat")]
    const OTHER_FILTER: usize = 0;
    #[cfg(all(not(feature = "csat"), feature = "ramp"))]
    const OTHER_FILTER: usize = size_of::<texcore::filter::Ramp565<N>>();
    #[cfg(all(not(feature = "csat"), not(feature = "ramp"), feature = "mip"))]
    const OTHER_FILTER: usize = texcore::filter::ColorMip::<N>::BYTES - size_of::<ColorTable<N>>();
    #[cfg(not(any(feature = "csat", feature = "ramp", feature = "mip")))]
    const OTHER_FILTER: usize = 0;
    #[cfg(feature = "perturb")]
    const PERTURBED: usize = size_of::<texcore::material::PerturbedMaterial<T>>();
    #[cfg(not(feature = "perturb"))]
    const PERTURBED: usize = 0;

    /// Sizes in bytes on this target, in this order: colour table (256 entries), its csat
    /// (0 without `csat`), `ColorStage<256>`, `TextureModel<8>` (quadric and noise terms),
    /// `NoiseTerm`, `SpanEvaluator<8>`, `TextureEvaluator<8, 256>`, `Texture<8, 256>`,
    /// `PerturbedMaterial<8>` (0 without `perturb`), `Span`, the filter data beyond the table
    /// of an instance without csat (`OTHER_FILTER`).
    #[used]
    #[allow(unsafe_code)] // `no_mangle` (an exported symbol) counts as unsafe code.
    #[no_mangle]
    pub static TEXCORE_PROBE_SIZES: [u32; 11] = [
        size_of::<ColorTable<N>>() as u32,
        CSAT as u32,
        size_of::<ColorStage<N>>() as u32,
        size_of::<TextureModel<T>>() as u32,
        size_of::<NoiseTerm>() as u32,
        size_of::<SpanEvaluator<'static, T>>() as u32,
        size_of::<TextureEvaluator<'static, T, N>>() as u32,
        size_of::<Texture<T, N>>() as u32,
        PERTURBED as u32,
        size_of::<Span>() as u32,
        OTHER_FILTER as u32,
    ];

    /// The filters compiled in, the strongest last.
    const FILTERS: &[Antialias] = &[
        Antialias::None,
        #[cfg(feature = "mip")]
        Antialias::Mip,
        #[cfg(feature = "ramp")]
        Antialias::Ramp,
        #[cfg(feature = "csat")]
        Antialias::Csat3,
        #[cfg(feature = "csat")]
        Antialias::Csat,
    ];

    /// The marble preset's texture: its colour table from the preset's keys by
    /// `texcore::ready::key_table` (the conversion `Material::table` makes), the wrap, look-up,
    /// norm, mode and filter hidden from the optimiser. Not `Material::texture_with` itself: its
    /// shader copy and error wrapping measured 384 bytes more `.text` in `minimal` on the
    /// Cortex-M4F (texcore's share 4190 bytes, past its 4 KB budget) and 364 more in `full`;
    /// `key_table` costs 20 bytes more than converting the keys by hand.
    fn texture() -> Option<Texture<T, N>> {
        let hash = black_box(HashKind::Integer);
        let p = presets::marble(hash);
        let table = key_table::<N>(p.keys, KeySpacing::Linear).ok()?;
        let aa = *FILTERS.last()?;
        let wrap = black_box(TableWrap::Mod);
        let lookup = black_box(TableLookup::Nearest);
        let stage = ColorStage::new(table, wrap, lookup, black_box(aa)).ok()?;
        let tex = Texture::new(
            Shader::Model(p.model),
            stage,
            black_box(GradientNorm::L2),
            black_box(EvalMode::Auto),
        );
        Some(tex)
    }

    fn shade(tex: &Texture<T, N>) -> u32 {
        let mut sink = ChecksumSink::new();
        let mut ev = tex.evaluator();
        for y in 0..64i32 {
            for x0 in (0..64i32).step_by(16) {
                let span = Span {
                    s0: TexPoint::from_bits(x0 * 2048 + 1024, 32768, y * 2048 + 1024),
                    ds: TexPoint::from_bits(2048, 0, 0),
                    dsdy: TexPoint::from_bits(0, 0, 2048),
                    len: 16,
                };
                // With the ramp, straight to RGB565 (its one-read path linked); otherwise each
                // colour reduced.
                #[cfg(feature = "ramp")]
                ev.shade565(&black_box(span), |c| sink.add_rgb565(c.to_bits()));
                #[cfg(not(feature = "ramp"))]
                ev.shade(&black_box(span), |c| {
                    sink.add_rgb565(c.to_rgb565().to_bits())
                });
            }
        }
        sink.checksum()
    }

    #[cfg(feature = "render")]
    fn render(tex: &Texture<T, N>) -> u32 {
        use texcore::color::Rgba8888;
        use texcore::raster::{Perspective, ScreenVertex, TriangleOptions};
        use texcore::render::{Blend, DrawObject, Renderer, TriangleSource};

        struct Scene([ScreenVertex; 4]);
        impl TriangleSource for Scene {
            fn size(&self) -> (u16, u16) {
                (64, 64)
            }
            fn background(&self) -> Rgba8888 {
                Rgba8888::BLACK
            }
            fn object_count(&self) -> usize {
                2
            }
            fn object(&self, i: usize) -> Option<DrawObject> {
                let (blend, perspective) = match i {
                    0 => (Blend::Opaque, Perspective::Every16),
                    1 => (Blend::Over, Perspective::Affine),
                    _ => return None,
                };
                Some(DrawObject {
                    texture: 0,
                    blend,
                    depth: true,
                    raster: TriangleOptions::new(perspective),
                })
            }
            fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, mut f: F) {
                let v = &self.0;
                for obj in 0..2 {
                    f(obj, &[v[0], v[1], v[2]]);
                    f(obj, &[v[0], v[2], v[3]]);
                }
            }
            /// With feature `lighting` the scene is lit (as far as the optimiser knows), so the
            /// renderer's lighting stage and `Lighting::shade` stay linked.
            #[cfg(feature = "lighting")]
            fn is_lit(&self) -> bool {
                black_box(true)
            }
            #[cfg(feature = "lighting")]
            fn for_each_lit_triangle_grouped<K, F>(&self, mut keep: K, mut f: F)
            where
                K: FnMut(usize) -> bool,
                F: FnMut(
                    usize,
                    usize,
                    &[ScreenVertex; 3],
                    &dyn Fn() -> [texcore::light::LightRgb; 3],
                ),
            {
                let lighting = black_box(lighting());
                let (p, n, eye) =
                    black_box((Vec3::ZERO, Vec3::new(0, 0, ONE), Vec3::new(0, 0, 4 * ONE)));
                let light = || {
                    let l = lighting.shade(p, n, eye);
                    [l, l, l]
                };
                let mut group = 0usize;
                self.for_each_triangle(|o, t| {
                    if keep(group) {
                        f(group, o, t, &light);
                    }
                    group = group.wrapping_add(1);
                });
            }
        }
        /// Ambient 1/8 and one white directional light (the lit scene job's set-up).
        #[cfg(feature = "lighting")]
        fn lighting() -> texcore::light::Lighting<1> {
            use texcore::light::{Light, Lighting};
            let Ok(mut l) = Lighting::new().with_ambient([ONE / 8; 3]) else {
                return Lighting::new();
            };
            if let Ok(sun) = Light::directional(Vec3::new(ONE, ONE, ONE), [ONE; 3], ONE) {
                let _ = l.try_add(sun);
            }
            l
        }
        #[cfg(feature = "lighting")]
        use texcore::scene::math::{Vec3, ONE};
        let c = |x: i32, y: i32, w: u32| {
            ScreenVertex::from_bits(
                x << 4,
                y << 4,
                100,
                w,
                TexPoint::from_bits(x << 12, y << 12, 0),
            )
        };
        let scene = black_box(Scene([
            c(0, 0, 1 << 29),
            c(64, 0, 1 << 29),
            c(64, 64, 1 << 30),
            c(0, 64, 1 << 30),
        ]));
        let mut band = [Rgba8888::BLACK; 64 * 8];
        let mut depth = [0u16; 64 * 8];
        let mut sink = ChecksumSink::new();
        let textures = core::slice::from_ref(tex);
        let renderer = Renderer::new(textures);
        // With `render-differences`, the widths from differences as far as the optimiser knows.
        #[cfg(feature = "render-differences")]
        let (mut mem, mut faces) = (
            texcore::texture::DifferenceMemory::<64>::new(),
            texcore::span::FaceCache::<64, T>::new(),
        );
        #[cfg(feature = "render-differences")]
        let renderer = if black_box(true) {
            renderer.with_differences(&mut mem, &mut faces)
        } else {
            renderer
        };
        match renderer.render_banded(&scene, &mut band, &mut depth, 8, &mut sink) {
            Ok(_) => sink.checksum(),
            Err(_) => 0,
        }
    }

    #[cfg(not(feature = "render"))]
    fn render(_: &Texture<T, N>) -> u32 {
        0
    }

    /// With feature `atlas`: a packed mesh validated and walked, a two-triangle atlas baked with
    /// the texture (`texcore::atlas::bake`), its MIP pyramid built and the 64 x 64 plane read
    /// back with nearest, bilinear and MIP look-ups (every atlas kernel a product would link).
    #[cfg(feature = "atlas")]
    fn atlas(tex: &Texture<T, N>) -> u32 {
        use texcore::atlas::sample::{build_mip, AtlasImage, MipAtlas};
        use texcore::atlas::{bake, AtlasTriangle, Half};
        use texcore::color::Rgba8888;
        use texcore::packed_mesh::PackedMesh;

        const SIDE: u16 = 32;
        const LEVELS: usize = 32 * 32 + 16 * 16 + 8 * 8 + 4 * 4 + 2 * 2 + 1;
        let mut acc = 0u32;
        let bytes = black_box([0u8; 64]);
        if let Ok(m) = PackedMesh::new(&bytes) {
            for t in m.triangles() {
                acc ^= t[0].x as u32 ^ t[1].y as u32 ^ t[2].z as u32;
            }
        }
        let solid = black_box([
            TexPoint::from_bits(0, 0, 0),
            TexPoint::from_bits(1 << 16, 0, 0),
            TexPoint::from_bits(0, 1 << 16, 0),
        ]);
        let mut buf = [Rgba8888::TRANSPARENT; LEVELS];
        for half in [Half::Upper, Half::Lower] {
            let leg = black_box(SIDE - 4);
            if let Ok(t) = AtlasTriangle::new(0, 0, SIDE, SIDE - 1, leg, 1, half, solid) {
                let mut ev = tex.evaluator();
                bake(core::slice::from_ref(&t), &mut ev, |x, y, c| {
                    if let Some(p) =
                        buf.get_mut(usize::from(y) * usize::from(SIDE) + usize::from(x))
                    {
                        *p = c;
                    }
                });
            }
        }
        if build_mip(&mut buf, SIDE).is_err() {
            return acc;
        }
        let mut sink = ChecksumSink::new();
        if let (Ok(img), Ok(mip)) = (
            AtlasImage::new(&buf[..usize::from(SIDE) * usize::from(SIDE)], SIDE, SIDE),
            MipAtlas::new(&buf, SIDE),
        ) {
            for y in 0..64i32 {
                for x in 0..64i32 {
                    let (u, v) = (black_box(x << 15), black_box(y << 15));
                    for c in [
                        img.nearest(u, v),
                        img.bilinear(u, v),
                        mip.trilinear(u, v, black_box(3 << 15), u8::MAX),
                    ] {
                        sink.add_rgb565(c.to_rgb565().to_bits());
                    }
                }
            }
        }
        acc ^ sink.checksum()
    }

    #[cfg(not(feature = "atlas"))]
    fn atlas(_: &Texture<T, N>) -> u32 {
        0
    }

    /// With feature `differences`: the 64 x 64 check plane shaded once more with the filter
    /// widths from the differences of neighbouring values (`texcore::texture::DifferenceSpans`,
    /// the values of two rows in a `DifferenceMemory<64>` of 528 bytes on the stack), in
    /// 16-pixel spans, straight to RGB565 with the ramp.
    #[cfg(feature = "differences")]
    fn differences(tex: &Texture<T, N>) -> u32 {
        use texcore::span::{RowCache, SpanPlane};
        use texcore::texture::DifferenceMemory;
        let plane = SpanPlane::new(
            TexPoint::from_bits(1024, 32768, 1024),
            TexPoint::from_bits(2048, 0, 0),
            TexPoint::from_bits(0, 0, 2048),
            64,
            64,
        );
        let mut ev = tex.evaluator();
        let Some(setup) = plane.ok().and_then(|p| ev.plane_setup(&black_box(p))) else {
            return 0;
        };
        let mut cache = RowCache::<128>::new();
        let mut mem = DifferenceMemory::<64>::new();
        let Some(mut spans) = ev.difference_spans(&setup, &mut cache, &mut mem) else {
            return 0;
        };
        let mut sink = ChecksumSink::new();
        for y in 0..64u16 {
            for x0 in (0..64u16).step_by(16) {
                #[cfg(feature = "ramp")]
                spans.shade565(x0, y, black_box(16), |c| sink.add_rgb565(c.to_bits()));
                #[cfg(not(feature = "ramp"))]
                spans.shade(x0, y, black_box(16), |c| {
                    sink.add_rgb565(c.to_rgb565().to_bits())
                });
            }
        }
        sink.checksum()
    }

    #[cfg(not(feature = "differences"))]
    fn differences(_: &Texture<T, N>) -> u32 {
        0
    }

    pub fn run() -> u32 {
        let Some(tex) = texture() else {
            return 0;
        };
        let tex = black_box(&tex);
        black_box(shade(tex))
            ^ black_box(render(tex))
            ^ black_box(atlas(tex))
            ^ black_box(differences(tex))
            ^ black_box(TEXCORE_PROBE_SIZES[0])
    }
}

#[cfg(target_os = "none")]
fn app() -> ! {
    let _ = core::hint::black_box(probe::run());
    semihosting::process::exit(0)
}

#[cfg(all(target_os = "none", target_arch = "arm"))]
mod entry {
    #![allow(unsafe_code)] // cortex-m-rt's entry trampoline
    #[cortex_m_rt::entry]
    fn main() -> ! {
        super::app()
    }
}

#[cfg(all(target_os = "none", target_arch = "riscv32"))]
mod entry {
    #![allow(unsafe_code)] // riscv-rt's entry trampoline
    #[riscv_rt::entry]
    fn main() -> ! {
        super::app()
    }
}

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    semihosting::process::exit(101)
}
