//! The plane of solid texture coordinates sampled by `texsim check PRESET`, and f64 renders of it.
//!
//! A [`Plane`] maps continuous pixel coordinates `(x, y)` (pixel `(i, j)` covers `[i, i + 1) x
//! [j, j + 1)`, its centre is `(i + 1/2, j + 1/2)`) to
//!
//! ```text
//! s(x, y) = origin + (x / width) * x_axis + (y / height) * y_axis
//! ```
//!
//! so the screen Jacobian is constant: `ds/dx = x_axis / width`, `ds/dy = y_axis / height`.
//! The default is the paper's zone-plate set-up (Hart et al. 1999, 3.4): the unit square in `s, t`
//! at `r = 1/2`, 256 x 256 pixels, i.e. pixel `(i, j)` has `s = (i + 0.5) / 256`,
//! `t = (j + 0.5) / 256`, `r = 0.5` and `ds/dx = dt/dy = 1/256`.

use super::model::{Footprint, Norm, Nyquist, RefModel};
use super::table::{Filter, Lookup, RefTable, Rgba};

/// A rectangle of solid texture coordinates rendered as `width x height` pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// `s` at the image corner `(x, y) = (0, 0)` (the top-left corner of pixel (0, 0)).
    pub origin: [f64; 3],
    /// Texture-space vector spanned by the full image width.
    pub x_axis: [f64; 3],
    /// Texture-space vector spanned by the full image height.
    pub y_axis: [f64; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Default for Plane {
    /// The unit square in `s, t` at `r = 0.5`, 256 x 256 pixels.
    fn default() -> Self {
        Plane {
            origin: [0.0, 0.0, 0.5],
            x_axis: [1.0, 0.0, 0.0],
            y_axis: [0.0, 1.0, 0.0],
            width: 256,
            height: 256,
        }
    }
}

impl Plane {
    /// `s` at continuous pixel coordinates `(x, y)`.
    pub fn point(&self, x: f64, y: f64) -> [f64; 3] {
        let fx = x / f64::from(self.width);
        let fy = y / f64::from(self.height);
        [0, 1, 2].map(|i| self.origin[i] + fx * self.x_axis[i] + fy * self.y_axis[i])
    }

    /// `s` at the centre of pixel `(i, j)`.
    pub fn pixel_center(&self, i: u32, j: u32) -> [f64; 3] {
        self.point(f64::from(i) + 0.5, f64::from(j) + 0.5)
    }

    /// `ds/dx`, one pixel to the right.
    pub fn dsdx(&self) -> [f64; 3] {
        self.x_axis.map(|c| c / f64::from(self.width))
    }

    /// `ds/dy`, one pixel down.
    pub fn dsdy(&self) -> [f64; 3] {
        self.y_axis.map(|c| c / f64::from(self.height))
    }

    /// The footprint (centre and Jacobian) of pixel `(i, j)`.
    pub fn footprint(&self, i: u32, j: u32) -> Footprint {
        Footprint {
            s: self.pixel_center(i, j),
            dsdx: self.dsdx(),
            dsdy: self.dsdy(),
        }
    }

    /// Render with the analytic filter: each pixel is [`RefModel::pixel_color`] at its footprint.
    pub fn render(
        &self,
        model: &RefModel,
        table: &RefTable,
        filter: Filter,
        norm: Norm,
        nyquist: Nyquist,
    ) -> RefImage {
        self.map_pixels(|i, j| {
            model.pixel_color(&self.footprint(i, j), table, filter, norm, nyquist)
        })
    }

    /// Ground truth for antialiasing: each pixel is the mean of `n x n` stratified point samples
    /// (sub-pixel centres `(i + (a + 1/2)/n, j + (b + 1/2)/n)`), each a point look-up at `f`.
    pub fn supersample(
        &self,
        model: &RefModel,
        table: &RefTable,
        lookup: Lookup,
        n: u32,
    ) -> RefImage {
        let n = n.max(1);
        let inv = 1.0 / f64::from(n * n);
        self.map_pixels(|i, j| {
            let mut acc = [0.0; 4];
            for b in 0..n {
                for a in 0..n {
                    let x = f64::from(i) + (f64::from(a) + 0.5) / f64::from(n);
                    let y = f64::from(j) + (f64::from(b) + 0.5) / f64::from(n);
                    let c = model.point_color(self.point(x, y), table, lookup);
                    for k in 0..4 {
                        acc[k] += c[k];
                    }
                }
            }
            acc.map(|c| c * inv)
        })
    }

    /// `f` at every pixel centre (row-major), no culling.
    pub fn f_values(&self, model: &RefModel) -> Vec<f64> {
        let mut v = Vec::with_capacity(self.width as usize * self.height as usize);
        for j in 0..self.height {
            for i in 0..self.width {
                v.push(model.f(self.pixel_center(i, j)));
            }
        }
        v
    }

    fn map_pixels(&self, mut f: impl FnMut(u32, u32) -> Rgba) -> RefImage {
        let mut pixels = Vec::with_capacity(self.width as usize * self.height as usize);
        for j in 0..self.height {
            for i in 0..self.width {
                pixels.push(f(i, j));
            }
        }
        RefImage {
            width: self.width,
            height: self.height,
            pixels,
        }
    }
}

/// An f64 RGBA image (0..255 units), row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct RefImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row-major.
    pub pixels: Vec<Rgba>,
}

impl RefImage {
    /// Pixel `(i, j)`.
    pub fn get(&self, i: u32, j: u32) -> Rgba {
        self.pixels[j as usize * self.width as usize + i as usize]
    }

    /// Rounded to RGBA8 (round half away from zero, clamped to 0..=255).
    pub fn to_rgba8(&self) -> Vec<[u8; 4]> {
        self.pixels
            .iter()
            .map(|p| p.map(|c| c.round().clamp(0.0, 255.0) as u8))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::table::Wrap;

    #[test]
    fn default_is_the_zone_plate_square() {
        let p = Plane::default();
        assert_eq!(p.pixel_center(0, 0), [0.5 / 256.0, 0.5 / 256.0, 0.5]);
        assert_eq!(p.pixel_center(255, 10), [255.5 / 256.0, 10.5 / 256.0, 0.5]);
        assert_eq!(p.dsdx(), [1.0 / 256.0, 0.0, 0.0]);
        assert_eq!(p.dsdy(), [0.0, 1.0 / 256.0, 0.0]);
        let fp = p.footprint(3, 4);
        assert_eq!(fp.s, [3.5 / 256.0, 4.5 / 256.0, 0.5]);
    }

    #[test]
    fn jacobian_matches_pixel_steps() {
        let p = Plane {
            origin: [1.0, -2.0, 3.0],
            x_axis: [0.5, 0.25, -1.0],
            y_axis: [-0.125, 2.0, 0.5],
            width: 64,
            height: 32,
        };
        let a = p.pixel_center(10, 7);
        let bx = p.pixel_center(11, 7);
        let by = p.pixel_center(10, 8);
        for k in 0..3 {
            assert!((bx[k] - a[k] - p.dsdx()[k]).abs() < 1e-15);
            assert!((by[k] - a[k] - p.dsdy()[k]).abs() < 1e-15);
        }
        assert_eq!(p.point(0.0, 0.0), p.origin);
        assert_eq!(
            p.point(64.0, 32.0),
            [1.0 + 0.5 - 0.125, -2.0 + 0.25 + 2.0, 3.0 - 1.0 + 0.5]
        );
    }

    #[test]
    fn box_filter_approaches_supersampling_on_a_ramp() {
        // f = s over the unit square (D = 1/2): each pixel spans exactly 1/256 of f, so the box of
        // width N/256 is the exact pixel average, which dense supersampling converges to.
        let model = RefModel::new(
            [0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            Vec::new(),
            Wrap::Mod,
        );
        let entries: Vec<[u8; 4]> = (0..64u32)
            .map(|i| [(i * 37 % 256) as u8, (i * 4) as u8, 0, 255])
            .collect();
        let table = RefTable::new(&entries).unwrap();
        let plane = Plane {
            width: 32,
            height: 2,
            ..Plane::default()
        };
        let boxed = plane.render(&model, &table, Filter::Box, Norm::L1, Nyquist::Evaluate);
        let ss = plane.supersample(&model, &table, Lookup::Nearest, 64);
        for (a, b) in boxed.pixels.iter().zip(ss.pixels.iter()) {
            for k in 0..4 {
                assert!((a[k] - b[k]).abs() < 1e-9, "{a:?} {b:?}");
            }
        }
        let rgba = boxed.to_rgba8();
        assert_eq!(rgba.len(), 64);
        assert_eq!(rgba[0][3], 255);
    }
}
