//! Meshed texture atlases on the host (Carr & Hart 2002): layouts and their measures
//! ([`layout`]), the balanced face partition of the MIP-mappable atlas ([`partition`]), the bake
//! (texcore's [`texcore::atlas::bake`] kernel, the same code the device runs) and drawing a mesh
//! from its atlas ([`view`]).
//!
//! Baked atlases mark unused texels with alpha 0 ([`UNUSED`], a loud magenta): every texel a
//! triangle owns is written opaque, so a look-up that touches an unused texel shows as a pixel
//! with alpha below 255 (the seam test, `tests/atlas.rs`).

pub mod cli;
pub mod layout;
pub mod partition;
pub mod scene;
pub mod shading;
pub mod view;

use texcore::color::Rgba8888;
use texcore::texture::Texture;

pub use layout::{AtlasKind, Layout, LayoutError};
pub use view::Sampling;

/// The colour of texels no triangle owns: loud magenta, alpha 0.
pub const UNUSED: Rgba8888 = Rgba8888::new(255, 0, 255, 0);

/// A baked atlas.
#[derive(Clone, Debug)]
pub struct Baked {
    /// Side in texels.
    pub size: u32,
    /// Row-major texels; [`UNUSED`] where no triangle owns the texel.
    pub texels: Vec<Rgba8888>,
    /// Texels written by the bake.
    pub written: u32,
}

/// Bakes `texture` into `layout` with texcore's bake kernel.
pub fn bake<const T: usize, const N: usize>(layout: &Layout, texture: &Texture<T, N>) -> Baked {
    let size = layout.size as usize;
    let mut texels = vec![UNUSED; size * size];
    let mut ev = texture.evaluator();
    let written = texcore::atlas::bake(&layout.triangles, &mut ev, |x, y, c| {
        if let Some(t) = texels.get_mut(y as usize * size + x as usize) {
            *t = c.with_alpha(255);
        }
    });
    Baked {
        size: layout.size,
        texels,
        written,
    }
}

/// The mask of a layout: owned texels opaque white, the rest [`UNUSED`].
pub fn mask(layout: &Layout) -> Baked {
    let size = layout.size as usize;
    let mut texels = vec![UNUSED; size * size];
    let mut written = 0;
    for t in &layout.triangles {
        let (_, y, _, h) = t.block();
        for j in y..y + h {
            if let Some((x0, n)) = t.row(j) {
                for i in x0..x0 + n {
                    texels[j as usize * size + i as usize] = Rgba8888::WHITE;
                    written += 1;
                }
            }
        }
    }
    Baked {
        size: layout.size,
        texels,
        written,
    }
}

/// The MIP pyramid of a baked atlas (level 0 first), or `None` if its side is not a power of
/// two.
pub fn pyramid(baked: &Baked) -> Option<Vec<Rgba8888>> {
    let size = u16::try_from(baked.size).ok()?;
    let mut buf = vec![Rgba8888::TRANSPARENT; texcore::atlas::sample::mip_len(size)];
    buf[..baked.texels.len()].copy_from_slice(&baked.texels);
    texcore::atlas::sample::build_mip(&mut buf, size).ok()?;
    Some(buf)
}
