//! Rasterizer: random triangles (coordinates in and around a small target, anywhere in the guard
//! band, or any `i32` bit pattern: degenerate, huge, outside the guard band), any `1/w`, depth
//! and texture coordinates, every perspective and cull mode, any clip rectangle. Checks: no
//! panic; every segment lies inside the clip and is at most the mode's longest; no pixel is
//! drawn twice; without culling the covered pixels are exactly those of an independent top-left
//! rule reference (none outside the guard band); culling drops a triangle whole; drawing in
//! bands gives the whole clip's segments; a depth-tested draw covers a subset; two triangles on
//! either side of a shared edge never draw a pixel twice.
#![no_main]

use libfuzzer_sys::fuzz_target;
use texcore::format::TexPoint;
use texcore::raster::{
    CullMode, DepthBuffer, DepthFunc, Perspective, Rasterizer, Rect, ScreenVertex, Segment,
    TriangleOptions, GUARD_BAND,
};
use texcore_fuzz::Bytes;

/// Target side, in pixels (the clip lies inside).
const SIDE: u16 = 48;

/// A raw 28.4 coordinate: near the target, anywhere, or any bit pattern.
fn coord(b: &mut Bytes) -> i32 {
    match b.below(4) {
        0 => b.i32(),
        1 => b.i32_scaled(),
        _ => i32::from(b.u16() % (16 * (SIDE + 16))) - 16 * 8,
    }
}

fn vertex(b: &mut Bytes) -> ScreenVertex {
    let (x, y) = (coord(b), coord(b));
    let z = b.u16();
    let inv_w = b.u32();
    let tex = TexPoint::from_bits(b.i32_scaled(), b.i32_scaled(), b.i32_scaled());
    ScreenVertex::from_bits(x, y, z, inv_w, tex)
}

/// The top-left rule with exact edge functions (as `texcore::raster`'s own test reference):
/// pixel centre `(cx, cy)` (raw 28.4) strictly inside, or on a top or left edge.
fn reference_covered(p: [[i64; 2]; 3], cx: i64, cy: i64) -> bool {
    let a = (p[1][0] - p[0][0]) as i128 * (p[2][1] - p[0][1]) as i128
        - (p[2][0] - p[0][0]) as i128 * (p[1][1] - p[0][1]) as i128;
    if a == 0 {
        return false;
    }
    let p = if a > 0 { p } else { [p[0], p[2], p[1]] };
    (0..3).all(|i| {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        let (dx, dy) = ((b[0] - a[0]) as i128, (b[1] - a[1]) as i128);
        let e = dx * (cy - a[1]) as i128 - dy * (cx - a[0]) as i128;
        e > 0 || (e == 0 && (dy < 0 || (dy == 0 && dx > 0)))
    })
}

fn raw(v: &[ScreenVertex; 3]) -> [[i64; 2]; 3] {
    v.map(|p| [i64::from(p.x.to_bits()), i64::from(p.y.to_bits())])
}

/// Twice the signed area (clockwise on screen > 0).
fn orient(p: [[i64; 2]; 3]) -> i128 {
    (p[1][0] - p[0][0]) as i128 * (p[2][1] - p[0][1]) as i128
        - (p[2][0] - p[0][0]) as i128 * (p[1][1] - p[0][1]) as i128
}

fn in_guard_band(v: &[ScreenVertex; 3]) -> bool {
    v.iter().all(|p| {
        p.x.to_bits().unsigned_abs() < GUARD_BAND && p.y.to_bits().unsigned_abs() < GUARD_BAND
    })
}

/// Per-pixel counts over the target; checks each segment against the clip and the mode.
/// `persp` is `None` when the triangle is interpolated affinely whatever the mode (all `1/w`
/// zero, as the module documents): whole runs.
fn count(segs: &[Segment], clip: Rect, persp: Option<Perspective>, counts: &mut [u8]) {
    for s in segs {
        assert!(s.len >= 1, "empty segment {s:?}");
        if let Some(max) = persp.and_then(|p| p.max_len()) {
            assert!(s.len <= max, "{persp:?} segment of {} pixels", s.len);
        }
        assert!(
            s.y >= clip.y0
                && s.y < clip.y1
                && s.x0 >= clip.x0
                && u32::from(s.x0) + u32::from(s.len) <= u32::from(clip.x1),
            "segment {s:?} outside the clip {clip:?}"
        );
        for x in s.x0..s.x0 + s.len {
            let c = &mut counts[usize::from(s.y) * usize::from(SIDE) + usize::from(x)];
            *c += 1;
        }
    }
}

fn draw(clip: Rect, v: &[ScreenVertex; 3], opts: &TriangleOptions) -> Vec<Segment> {
    let mut r = Rasterizer::new(clip);
    let mut out = Vec::new();
    r.draw(v, opts, &mut |s: &Segment| out.push(*s));
    out
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes::new(data);
    let v = [vertex(&mut b), vertex(&mut b), vertex(&mut b)];
    let persp = b.pick(&[
        Perspective::Exact,
        Perspective::Every8,
        Perspective::Every16,
        Perspective::Affine,
    ]);
    let cull = b.pick(&[
        CullMode::None,
        CullMode::Clockwise,
        CullMode::CounterClockwise,
    ]);
    let (x0, y0) = (
        u16::from(b.below(SIDE as u8)),
        u16::from(b.below(SIDE as u8)),
    );
    let clip = Rect::new(
        x0,
        y0,
        x0 + 1 + u16::from(b.below((SIDE - x0) as u8)),
        y0 + 1 + u16::from(b.below((SIDE - y0) as u8)),
    );
    let band = 1 + u16::from(b.below(9));
    let fourth = vertex(&mut b);

    let opts = TriangleOptions {
        cull,
        ..TriangleOptions::new(persp)
    };
    let all = TriangleOptions::new(persp);
    // All `1/w` zero: interpolated affinely in every mode (whole-run segments).
    let persp = if v.iter().all(|p| p.inv_w.to_bits() == 0) {
        None
    } else {
        Some(persp)
    };
    let segs = draw(clip, &v, &all);
    let mut counts = vec![0u8; usize::from(SIDE) * usize::from(SIDE)];
    count(&segs, clip, persp, &mut counts);

    // Coverage: exactly the reference's pixels, each once.
    let p = raw(&v);
    let inside = in_guard_band(&v);
    for y in clip.y0..clip.y1 {
        for x in clip.x0..clip.x1 {
            let c = counts[usize::from(y) * usize::from(SIDE) + usize::from(x)];
            let want = inside && reference_covered(p, 16 * i64::from(x) + 8, 16 * i64::from(y) + 8);
            assert_eq!(
                c,
                u8::from(want),
                "pixel ({x}, {y}) drawn {c} times; triangle {p:?}"
            );
        }
    }

    // Culling drops the triangle whole or keeps it whole.
    let culled = draw(clip, &v, &opts);
    let dropped = match cull {
        CullMode::None => false,
        CullMode::Clockwise => orient(p) > 0,
        CullMode::CounterClockwise => orient(p) < 0,
    };
    if dropped {
        assert!(
            culled.is_empty(),
            "a culled triangle drew {} segments",
            culled.len()
        );
    } else {
        assert_eq!(culled, segs, "culling changed a kept triangle");
    }

    // Bands give the whole clip's segments, in the same order.
    let mut r = Rasterizer::new(clip);
    let mut banded = Vec::new();
    if let Ok(setup) = r.setup(&v, &all) {
        let mut y = clip.y0;
        while y < clip.y1 {
            let y1 = (y + band).min(clip.y1);
            r.set_clip(Rect::new(clip.x0, y, clip.x1, y1));
            r.draw_setup(&setup, &mut |s: &Segment| banded.push(*s));
            y = y1;
        }
    }
    assert_eq!(
        banded, segs,
        "bands of {band} rows differ from the whole clip"
    );

    // A depth-tested draw covers a subset of the pixels.
    let mut zbuf = vec![0u16; usize::from(clip.width()) * usize::from(clip.height())];
    let mut depth = DepthBuffer::new(&mut zbuf, clip).expect("buffer fits the clip");
    depth.clear(u16::MAX);
    let dopts = TriangleOptions {
        depth_func: DepthFunc::LessEqual,
        ..all
    };
    let mut r = Rasterizer::new(clip);
    let mut dsegs = Vec::new();
    r.draw_depth(&v, &dopts, &mut depth, &mut |s: &Segment| dsegs.push(*s));
    let mut dcounts = vec![0u8; counts.len()];
    count(&dsegs, clip, persp, &mut dcounts);
    assert!(
        dcounts.iter().zip(&counts).all(|(d, c)| d <= c),
        "depth test drew an uncovered pixel"
    );

    // A neighbour across the edge v0-v1 never draws a pixel of this triangle.
    let w = [v[1], v[0], fourth];
    let q = raw(&w);
    if inside && in_guard_band(&w) && orient(p).signum() * orient(q).signum() == 1 {
        // (v1, v0, x) has the orientation of (v0, v1, v2) when x lies on the other side of v0-v1.
        let mut both = counts.clone();
        let wp = if w.iter().all(|p| p.inv_w.to_bits() == 0) {
            None
        } else {
            Some(all.perspective)
        };
        count(&draw(clip, &w, &all), clip, wp, &mut both);
        assert!(
            both.iter().all(|&c| c <= 1),
            "triangles sharing an edge overlap: {p:?} {q:?}"
        );
    }
});
