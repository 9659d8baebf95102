//! Drawing a mesh from its atlas: the mesh is projected by a simple orbit camera, texcore's
//! rasterizer interpolates each triangle's atlas coordinates perspective-correctly (as the
//! texture coordinates of its vertices, `Perspective::Every16`), and every pixel samples the
//! baked atlas ([`texcore::atlas::sample`]): nearest, bilinear, or MIP with blending between
//! levels (footprint from the segment's screen derivatives).

use texcore::atlas::sample::{AtlasImage, MipAtlas};
use texcore::color::Rgba8888;
use texcore::format::TexPoint;
use texcore::raster::{
    CullMode, DepthBuffer, DepthFunc, InvW, Perspective, Rasterizer, Rect, ScreenCoord,
    ScreenVertex, Segment, TriangleOptions,
};

use super::layout::Layout;
use crate::mesh::TriMesh;

/// Texture look-up of the atlas (`--sampling`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// The texel containing the point.
    Nearest,
    /// Bilinear between the four nearest texel centres.
    Bilinear,
    /// Bilinear in the two MIP levels around the footprint, blended.
    Mip,
}

/// The look-up as spelled on the command line (`--sampling`).
impl core::fmt::Display for Sampling {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Sampling::Nearest => "nearest",
            Sampling::Bilinear => "bilinear",
            Sampling::Mip => "mip",
        })
    }
}

/// An orbit camera around the mesh's bounding-box centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Turn about the vertical axis, degrees.
    pub yaw: f64,
    /// Elevation, degrees.
    pub pitch: f64,
    /// Distance from the centre in bounding radii (more than 1).
    pub distance: f64,
    /// Image side in pixels.
    pub size: u16,
}

/// A drawn frame.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Side in pixels.
    pub size: u16,
    /// Row-major RGBA pixels (background transparent black).
    pub pixels: Vec<Rgba8888>,
    /// Pixels shaded (including overdraw).
    pub shaded: u64,
    /// Shaded pixels whose look-up gave alpha below 255, i.e. read an unused texel
    /// ([`super::UNUSED`]) with a non-zero weight.
    pub loud: u64,
}

/// The baked atlas in the form a look-up needs.
pub enum Source<'a> {
    /// Level 0 only.
    Flat(AtlasImage<'a>),
    /// A MIP pyramid (levels up to the second number).
    Mip(MipAtlas<'a>, u8),
}

/// Screen triangles of `mesh` seen by `cam`, with atlas coordinates (`Q16.16` texels) as
/// their texture coordinates; triangles behind the near plane are left out.
pub fn screen_triangles(mesh: &TriMesh, layout: &Layout, cam: &Orbit) -> Vec<[ScreenVertex; 3]> {
    let [lo, hi] = mesh.bounds();
    let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let r = (0..3)
        .map(|k| (0.5 * (hi[k] - lo[k])).powi(2))
        .sum::<f64>()
        .sqrt()
        .max(1e-9);
    let (yaw, pitch) = (cam.yaw.to_radians(), cam.pitch.to_radians());
    let dir = [
        pitch.cos() * yaw.sin(),
        pitch.sin(),
        pitch.cos() * yaw.cos(),
    ];
    let eye = [0, 1, 2].map(|k| c[k] + cam.distance * r * dir[k]);
    let f = dir.map(|d| -d);
    let up = [0.0, 1.0, 0.0];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let mut right = cross(f, up);
    let n = right.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n < 1e-9 {
        right = [1.0, 0.0, 0.0];
    } else {
        right = right.map(|x| x / n);
    }
    let upv = cross(right, f);
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let near = 0.01 * r;
    let (zmin, zmax) = ((cam.distance - 1.0).max(0.0) * r, (cam.distance + 1.0) * r);
    let half = cam.size as f64 / 2.0;
    let focal = half / (22.5f64).to_radians().tan();
    let mut out = Vec::with_capacity(mesh.triangles().len());
    for t in 0..mesh.triangles().len() {
        let p = mesh.corners(t);
        let uv = layout.uv(t);
        let mut v = [ScreenVertex::default(); 3];
        let mut ok = true;
        for k in 0..3 {
            let q = [0, 1, 2].map(|i| p[k][i] - eye[i]);
            let (x, y, z) = (dot(q, right), dot(q, upv), dot(q, f));
            if z < near {
                ok = false;
                break;
            }
            let sx = half + focal * x / z;
            let sy = half - focal * y / z;
            let depth = (((z - zmin) / (zmax - zmin)).clamp(0.0, 1.0) * 65535.0) as u16;
            let inv_w = ((near / z) * 2f64.powi(31)).clamp(1.0, 2f64.powi(31)) as u32;
            v[k] = ScreenVertex::new(
                ScreenCoord::from_bits((sx * 16.0).round() as i32),
                ScreenCoord::from_bits((sy * 16.0).round() as i32),
                depth,
                InvW::from_bits(inv_w),
                TexPoint::from_bits((uv[k][0] * 65536.0) as i32, (uv[k][1] * 65536.0) as i32, 0),
            );
        }
        if ok {
            out.push(v);
        }
    }
    out
}

/// Draws `mesh` from its atlas, depth tested, no culling.
pub fn draw(
    mesh: &TriMesh,
    layout: &Layout,
    source: &Source<'_>,
    sampling: Sampling,
    cam: &Orbit,
) -> Frame {
    let size = cam.size;
    let rect = Rect::from_size(size, size);
    let n = size as usize * size as usize;
    let mut pixels = vec![Rgba8888::TRANSPARENT; n];
    let mut depth = vec![u16::MAX; n];
    let mut db = DepthBuffer::new(&mut depth, rect).expect("depth buffer sized to its rect");
    let mut rast = Rasterizer::new(rect);
    let opts = TriangleOptions {
        perspective: Perspective::Every16,
        cull: CullMode::None,
        depth_func: DepthFunc::Less,
        depth_write: true,
    };
    let mut shaded = 0u64;
    let mut loud = 0u64;
    for tri in screen_triangles(mesh, layout, cam) {
        rast.draw_depth(&tri, &opts, &mut db, &mut |seg: &Segment| {
            let d = seg.ds.to_bits();
            let dy = seg.dsdy.to_bits();
            let footprint = [d[0], d[1], dy[0], dy[1]]
                .iter()
                .map(|x| x.unsigned_abs())
                .max()
                .unwrap_or(0);
            for i in 0..seg.len {
                let s = seg.s_at(i);
                let (u, v) = (s[0] as i32, s[1] as i32);
                let c = match (source, sampling) {
                    (Source::Flat(img), Sampling::Nearest) => img.nearest(u, v),
                    (Source::Flat(img), _) => img.bilinear(u, v),
                    (Source::Mip(m, _), Sampling::Nearest) => m.level(0).nearest(u, v),
                    (Source::Mip(m, _), Sampling::Bilinear) => m.level(0).bilinear(u, v),
                    (Source::Mip(m, top), Sampling::Mip) => m.trilinear(u, v, footprint, *top),
                };
                let idx = seg.y as usize * size as usize + (seg.x0 + i) as usize;
                if let Some(p) = pixels.get_mut(idx) {
                    *p = c;
                }
                shaded += 1;
                loud += u64::from(c.a < 255);
            }
        });
    }
    Frame {
        size,
        pixels,
        shaded,
        loud,
    }
}
