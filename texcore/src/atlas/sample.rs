//! Sampling a baked atlas: nearest, bilinear, and MIP with blending between levels.
//!
//! Atlas coordinates are `Q16.16` texels of level 0 (texel `(i, j)` covers `[i, i+1) x [j, j+1)`).
//! A texel with alpha 0 is **unused** (the bake writes opaque texels only); the MIP pyramid
//! averages the used texels under each coarser texel (a coarser texel is used when any texel
//! under it is) and fills a coarser texel with nothing under it from the level above it, so
//! every texel of levels 1 and up is used while level 0 keeps exactly what was baked.
//!
//! Guarantees: every constructor checks its sizes once; no look-up can panic or read out of
//! bounds for any coordinates (they are clamped to the image); the arithmetic is integer, so
//! every target returns the same colours. Nothing allocates.

use crate::color::Rgba8888;

/// Why an image or pyramid cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SampleError {
    /// A zero side, or the buffer's length is not what the sides call for.
    Size,
    /// A MIP pyramid needs a square power-of-two level 0.
    NotPowerOfTwo,
}

impl core::fmt::Display for SampleError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SampleError::Size => write!(f, "atlas buffer length does not match its size"),
            SampleError::NotPowerOfTwo => write!(f, "MIP atlas side is not a power of two"),
        }
    }
}

/// A borrowed `width x height` atlas level, row-major.
#[derive(Clone, Copy, Debug)]
pub struct AtlasImage<'a> {
    texels: &'a [Rgba8888],
    width: u16,
    height: u16,
}

/// Blends `a` and `b` with weight `f / 256` on `b` (rounded, every channel including alpha).
fn lerp(a: Rgba8888, b: Rgba8888, f: u32) -> Rgba8888 {
    let m = |x: u8, y: u8| ((x as u32 * (256 - f) + y as u32 * f + 128) >> 8) as u8;
    Rgba8888::new(m(a.r, b.r), m(a.g, b.g), m(a.b, b.b), m(a.a, b.a))
}

impl<'a> AtlasImage<'a> {
    /// Checks `texels.len() == width * height`, both non-zero.
    pub fn new(texels: &'a [Rgba8888], width: u16, height: u16) -> Result<Self, SampleError> {
        if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
            return Err(SampleError::Size);
        }
        Ok(AtlasImage {
            texels,
            width,
            height,
        })
    }

    /// `(width, height)`.
    pub fn size(&self) -> (u16, u16) {
        (self.width, self.height)
    }

    /// Texel `(x, y)`, clamped to the image.
    pub fn texel(&self, x: i32, y: i32) -> Rgba8888 {
        let x = x.clamp(0, self.width as i32 - 1) as usize;
        let y = y.clamp(0, self.height as i32 - 1) as usize;
        self.texels
            .get(y * self.width as usize + x)
            .copied()
            .unwrap_or_default()
    }

    /// The texel containing `(u, v)` (`Q16.16` texels).
    pub fn nearest(&self, u: i32, v: i32) -> Rgba8888 {
        self.texel(u >> 16, v >> 16)
    }

    /// Bilinear interpolation of the four texel centres around `(u, v)`, 8-bit weights.
    pub fn bilinear(&self, u: i32, v: i32) -> Rgba8888 {
        let u = u.saturating_sub(1 << 15);
        let v = v.saturating_sub(1 << 15);
        let (x, y) = (u >> 16, v >> 16);
        let (fx, fy) = (((u >> 8) & 255) as u32, ((v >> 8) & 255) as u32);
        let top = lerp(self.texel(x, y), self.texel(x + 1, y), fx);
        let bottom = lerp(self.texel(x, y + 1), self.texel(x + 1, y + 1), fx);
        lerp(top, bottom, fy)
    }
}

/// Number of levels of a pyramid over a `size x size` level 0 (`lg size + 1`).
pub const fn mip_levels(size: u16) -> u8 {
    (u16::BITS - size.leading_zeros()) as u8
}

/// Texels of a whole pyramid over a `size x size` level 0 (levels one after the other).
pub const fn mip_len(size: u16) -> usize {
    let mut n = 0usize;
    let mut s = size as usize;
    while s > 0 {
        n += s * s;
        s /= 2;
    }
    n
}

/// Fills levels 1 and up of the pyramid in `buf` (level 0 = its first `size^2` texels) from
/// level 0, as described in the module documentation.
pub fn build_mip(buf: &mut [Rgba8888], size: u16) -> Result<(), SampleError> {
    if size == 0 || !size.is_power_of_two() {
        return Err(SampleError::NotPowerOfTwo);
    }
    if buf.len() != mip_len(size) {
        return Err(SampleError::Size);
    }
    // Down: average the used texels.
    let mut start = 0usize;
    let mut s = size as usize;
    while s > 1 {
        let (fine, coarse) = buf.split_at_mut(start + s * s);
        let fine = &fine[start..];
        let h = s / 2;
        for y in 0..h {
            for x in 0..h {
                let mut sum = [0u32; 3];
                let mut n = 0u32;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let c = fine[(2 * y + dy) * s + 2 * x + dx];
                    if c.a != 0 {
                        sum[0] += c.r as u32;
                        sum[1] += c.g as u32;
                        sum[2] += c.b as u32;
                        n += 1;
                    }
                }
                coarse[y * h + x] = if n == 0 {
                    Rgba8888::TRANSPARENT
                } else {
                    let avg = |v: u32| ((v + n / 2) / n) as u8;
                    Rgba8888::new(avg(sum[0]), avg(sum[1]), avg(sum[2]), 255)
                };
            }
        }
        start += s * s;
        s = h;
    }
    // Up: fill the unused texels of levels 1.. from the level above.
    let mut level_start = [0usize; 17];
    let mut s = size as usize;
    let mut l = 0usize;
    let mut o = 0usize;
    while s > 0 && l < 17 {
        level_start[l] = o;
        o += s * s;
        s /= 2;
        l += 1;
    }
    let levels = l;
    for l in (1..levels.saturating_sub(1)).rev() {
        let s = size as usize >> l;
        let (a, b) = buf.split_at_mut(level_start[l + 1]);
        let fine = &mut a[level_start[l]..];
        for y in 0..s {
            for x in 0..s {
                if fine[y * s + x].a == 0 {
                    fine[y * s + x] = b[(y / 2) * (s / 2) + x / 2];
                }
            }
        }
    }
    Ok(())
}

/// A borrowed MIP pyramid built by [`build_mip`].
#[derive(Clone, Copy, Debug)]
pub struct MipAtlas<'a> {
    buf: &'a [Rgba8888],
    size: u16,
}

/// `floor(log2(x)) * 256 + ` a linear fraction (8 bits) for `x > 0`.
fn log2_q8(x: u32) -> i32 {
    let e = 31 - x.leading_zeros() as i32;
    let frac = if e >= 8 {
        (x >> (e - 8)) & 255
    } else {
        (x << (8 - e)) & 255
    };
    e * 256 + frac as i32
}

impl<'a> MipAtlas<'a> {
    /// Checks the buffer's length for a `size x size` level 0 (a power of two).
    pub fn new(buf: &'a [Rgba8888], size: u16) -> Result<Self, SampleError> {
        if size == 0 || !size.is_power_of_two() {
            return Err(SampleError::NotPowerOfTwo);
        }
        if buf.len() != mip_len(size) {
            return Err(SampleError::Size);
        }
        Ok(MipAtlas { buf, size })
    }

    /// Number of levels.
    pub fn levels(&self) -> u8 {
        mip_levels(self.size)
    }

    /// Level `l` (clamped to the last).
    pub fn level(&self, l: u8) -> AtlasImage<'a> {
        let l = l.min(self.levels() - 1);
        let mut start = 0usize;
        for k in 0..l {
            let s = (self.size >> k) as usize;
            start += s * s;
        }
        let s = self.size >> l;
        let texels = self
            .buf
            .get(start..start + s as usize * s as usize)
            .unwrap_or(&[]);
        AtlasImage {
            texels,
            width: s,
            height: s,
        }
    }

    /// The level-of-detail of a footprint (`Q16.16` texels of level 0 per pixel), `Q8`:
    /// `lg footprint`, at least 0.
    pub fn lod(footprint: u32) -> i32 {
        if footprint <= 1 << 16 {
            0
        } else {
            log2_q8(footprint) - 16 * 256
        }
    }

    /// Bilinear samples of the two levels around the footprint's level of detail, blended
    /// linearly by its fraction (at most level `max_level`).
    pub fn trilinear(&self, u: i32, v: i32, footprint: u32, max_level: u8) -> Rgba8888 {
        let top = max_level.min(self.levels() - 1) as i32;
        let lod = Self::lod(footprint).min(top * 256);
        let l = (lod >> 8) as u8;
        let f = (lod & 255) as u32;
        let at = |l: u8| self.level(l).bilinear(u >> l, v >> l);
        let a = at(l);
        if f == 0 || l as i32 >= top {
            return a;
        }
        lerp(a, at(l + 1), f)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec;

    const RED: Rgba8888 = Rgba8888::rgb(255, 0, 0);
    const BLUE: Rgba8888 = Rgba8888::rgb(0, 0, 255);

    #[test]
    fn nearest_and_bilinear() {
        let t = [RED, BLUE, BLUE, RED];
        let img = AtlasImage::new(&t, 2, 2).unwrap();
        assert_eq!(img.nearest(65536 + 100, 100), BLUE);
        // At a texel centre bilinear is the texel.
        assert_eq!(img.bilinear(1 << 15, 1 << 15), RED);
        // Half way between (0,0) and (1,0) centres.
        let m = img.bilinear(65536, 1 << 15);
        assert_eq!((m.r, m.b), (128, 128));
        // Out of range coordinates clamp.
        assert_eq!(img.nearest(-5 << 16, 99 << 16), BLUE);
        assert!(AtlasImage::new(&t, 3, 1).is_err());
    }

    #[test]
    fn pyramid_averages_used_texels_and_fills_coarse_levels() {
        let size = 4u16;
        let mut buf = vec![Rgba8888::TRANSPARENT; mip_len(size)];
        assert_eq!(buf.len(), 16 + 4 + 1);
        // Used: the top-left 2x2 block, half red half blue.
        buf[0] = RED;
        buf[1] = BLUE;
        buf[4] = RED;
        buf[5] = BLUE;
        build_mip(&mut buf, size).unwrap();
        let m = MipAtlas::new(&buf, size).unwrap();
        assert_eq!(m.levels(), 3);
        let l1 = m.level(1);
        assert_eq!(l1.texel(0, 0), Rgba8888::rgb(128, 0, 128));
        // Unused level-1 texels filled from level 2 (the same average).
        assert_eq!(l1.texel(1, 1), Rgba8888::rgb(128, 0, 128));
        // Level 0 untouched.
        assert_eq!(m.level(0).texel(3, 3).a, 0);
        assert_eq!(MipAtlas::lod(1 << 16), 0);
        assert_eq!(MipAtlas::lod(2 << 16), 256);
        assert_eq!(MipAtlas::lod(3 << 16), 256 + 128);
        assert!(build_mip(&mut buf[..20], size).is_err());
        assert!(MipAtlas::new(&buf, 3).is_err());
    }
}
