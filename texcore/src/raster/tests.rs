//! Whole-rasterizer tests: shared edges and meshes, clipping, bands, perspective accuracy against
//! an f64 reference, Jacobians and activity counters.

// Per-component loops index several parallel `[_; 3]` arrays.
#![allow(clippy::needless_range_loop)]

extern crate std;

use super::*;
use crate::format::TexPoint;
use proptest::prelude::*;
use std::vec::Vec;

// ---------------------------------------------------------------------------------------------
// Helpers and references.

/// Independent coverage reference: edge functions in i128 with the top-left rule (after
/// normalising to clockwise on screen, the interior has E > 0; a top edge has dy == 0 and
/// dx > 0, a left edge dy < 0).
pub(crate) fn reference_covered(p: [[i64; 2]; 3], cx: i64, cy: i64) -> bool {
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

fn raw_xy(v: &[ScreenVertex; 3]) -> [[i64; 2]; 3] {
    v.map(|p| [p.x.to_bits() as i64, p.y.to_bits() as i64])
}

/// A vertex at raw 28.4 position with `1/w` raw and texture raw.
fn vert(x: i32, y: i32, inv_w: u32, tex: [i32; 3]) -> ScreenVertex {
    ScreenVertex::from_bits(x, y, 0, inv_w, TexPoint::from_bits(tex[0], tex[1], tex[2]))
}

/// Draws triangles and returns their segments in emission order.
fn segments(clip: Rect, tris: &[[ScreenVertex; 3]], opts: &TriangleOptions) -> Vec<Segment> {
    let mut r = Rasterizer::new(clip);
    let mut out = Vec::new();
    for t in tris {
        r.draw(t, opts, &mut |s: &Segment| out.push(*s));
    }
    out
}

/// Per-pixel coverage counts of a set of segments on a `w` x `h` target.
fn counts(segs: &[Segment], w: usize, h: usize) -> Vec<u32> {
    let mut c = std::vec![0u32; w * h];
    for s in segs {
        assert!(s.len >= 1);
        for i in 0..s.len as usize {
            c[s.y as usize * w + s.x0 as usize + i] += 1;
        }
    }
    c
}

/// The perspective term used by setup (1/w to 30 significant bits) for the f64 reference.
fn quantised_q(v: &[ScreenVertex; 3]) -> [f64; 3] {
    let qmax = v.iter().map(|p| p.inv_w.to_bits()).max().unwrap();
    let b = 32 - qmax.leading_zeros();
    v.map(|p| {
        let w = p.inv_w.to_bits() as i64;
        (if b <= 30 {
            w << (30 - b)
        } else {
            (w + (1 << (b - 31))) >> (b - 30)
        }) as f64
    })
}

/// f64 reference: texture coordinates (raw units) at screen point (x, y) in pixels,
/// perspective-correct (or screen-linear with `persp == false`).
fn reference_tex(v: &[ScreenVertex; 3], x: f64, y: f64, persp: bool) -> [f64; 3] {
    let q = if persp { quantised_q(v) } else { [1.0; 3] };
    let p = v.map(|p| [p.x.to_bits() as f64 / 16.0, p.y.to_bits() as f64 / 16.0]);
    let mut w = [0.0f64; 3];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let e = (p[j][0] - x) * (p[k][1] - y) - (p[k][0] - x) * (p[j][1] - y);
        w[i] = e * q[i];
    }
    let sum: f64 = w.iter().sum();
    let mut out = [0.0; 3];
    for (c, o) in out.iter_mut().enumerate() {
        *o = (0..3)
            .map(|i| w[i] * v[i].tex.to_bits()[c] as f64)
            .sum::<f64>()
            / sum;
    }
    out
}

/// f64 reference: `d ln(1/w) / dx` (or `/ dy`) at a screen point, per pixel.
fn reference_dlnq(v: &[ScreenVertex; 3], x: f64, y: f64, dy: bool) -> f64 {
    let q = quantised_q(v);
    let p = v.map(|p| [p.x.to_bits() as f64 / 16.0, p.y.to_bits() as f64 / 16.0]);
    let (mut val, mut der) = (0.0, 0.0);
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        val += q[i] * ((p[j][0] - x) * (p[k][1] - y) - (p[k][0] - x) * (p[j][1] - y));
        der += q[i]
            * if dy {
                p[k][0] - p[j][0]
            } else {
                p[j][1] - p[k][1]
            };
    }
    der / val
}

/// The documented bound (in LSB) of exact perspective values, beyond rounding (0.5):
/// `ratio * (2^(2b - 62) + 2^(b - 45))` with `b` the bits of the coordinate range.
fn persp_bound(v: &[ScreenVertex; 3], c: usize) -> f64 {
    let q = quantised_q(v);
    let ratio = q.iter().cloned().fold(0.0, f64::max) / q.iter().cloned().fold(f64::MAX, f64::min);
    let base = v[0].tex.to_bits()[c] as i64;
    let range = v
        .iter()
        .map(|p| (p.tex.to_bits()[c] as i64 - base).unsigned_abs())
        .max()
        .unwrap();
    let b = (64 - range.leading_zeros()) as i32;
    0.5 + ratio * (2f64.powi(2 * b - 62) + 2f64.powi(b - 45)) + 1e-6
}

// ---------------------------------------------------------------------------------------------
// Shared edges and meshes.

#[test]
fn two_triangles_sharing_an_edge() {
    // Quads split along diagonals of many slopes (some through pixel centres); both halves
    // together cover the quad's pixels exactly once.
    let quads: [[[i32; 2]; 4]; 5] = [
        [[0, 0], [256, 0], [256, 256], [0, 256]],
        [[8, 8], [200, 24], [232, 248], [24, 200]],
        [[3, 5], [251, 9], [247, 250], [11, 240]],
        [[40, 0], [255, 100], [180, 255], [0, 120]],
        [[8, 8], [248, 8], [248, 136], [8, 136]],
    ];
    let o = TriangleOptions::new(Perspective::Affine);
    for q in &quads {
        let v = q.map(|p| vert(p[0], p[1], 1 << 30, [0; 3]));
        for (a, b) in [((0, 1, 2), (0, 2, 3)), ((0, 1, 3), (1, 2, 3))] {
            let t1 = [v[a.0], v[a.1], v[a.2]];
            // The second triangle in the opposite winding.
            let t2 = [v[b.0], v[b.2], v[b.1]];
            let c = counts(&segments(Rect::from_size(16, 16), &[t1, t2], &o), 16, 16);
            for y in 0..16 {
                for x in 0..16 {
                    let (cx, cy) = (16 * x + 8, 16 * y + 8);
                    let r = reference_covered(raw_xy(&t1), cx, cy) as u32
                        + reference_covered(raw_xy(&t2), cx, cy) as u32;
                    assert!(r <= 1);
                    assert_eq!(c[(y * 16 + x) as usize], r, "{q:?} {x} {y}");
                }
            }
        }
    }
}

/// Draws a fan around `centre` with `ring` (raw positions) and returns the coverage counts
/// of a 48x48 target.
fn fan_counts(centre: [i32; 2], ring: &[[i32; 2]], flip: &[bool]) -> Vec<u32> {
    let c = vert(centre[0], centre[1], 1 << 30, [0; 3]);
    let mut tris = Vec::new();
    for i in 0..ring.len() {
        let a = vert(ring[i][0], ring[i][1], 1 << 30, [0; 3]);
        let b = vert(
            ring[(i + 1) % ring.len()][0],
            ring[(i + 1) % ring.len()][1],
            1 << 30,
            [0; 3],
        );
        tris.push(if flip[i % flip.len()] {
            [c, b, a]
        } else {
            [a, c, b]
        });
    }
    counts(
        &segments(Rect::from_size(48, 48), &tris, &TriangleOptions::default()),
        48,
        48,
    )
}

#[test]
fn fan_around_a_pixel_centre_covers_once() {
    // 24 triangles around the centre of pixel (20, 20), with ring vertices on pixel centres
    // and corners, so that many edges pass through pixel centres.
    let centre = [16 * 20 + 8, 16 * 20 + 8];
    let mut ring = Vec::new();
    for k in 0..24 {
        let a = k as f64 * core::f64::consts::TAU / 24.0;
        let r = 16.0 * 120.0;
        let x = (centre[0] as f64 + r * a.cos()) / 8.0;
        let y = (centre[1] as f64 + r * a.sin()) / 8.0;
        ring.push([x.round() as i32 * 8, y.round() as i32 * 8]);
    }
    let c = fan_counts(centre, &ring, &[false, true, true]);
    assert!(c.iter().all(|&n| n == 1), "{c:?}");
}

fn jittered_mesh(jitter: &[(i32, i32)], diag: &[bool], flip: &[u8]) -> Vec<[ScreenVertex; 3]> {
    // 7x7 vertices, 12-pixel cells from -12 px, covering a 48x48 target with margin.
    let n = 7;
    let mut pos = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (jx, jy) = jitter[(j * n + i) % jitter.len()];
            pos.push([(i as i32 - 1) * 192 + jx, (j as i32 - 1) * 192 + jy]);
        }
    }
    let v = |k: usize| vert(pos[k][0], pos[k][1], 1 << 30, [0; 3]);
    let mut tris = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (
                j * n + i,
                j * n + i + 1,
                (j + 1) * n + i + 1,
                (j + 1) * n + i,
            );
            let q = j * (n - 1) + i;
            let (t1, t2) = if diag[q % diag.len()] {
                ([v(a), v(b), v(c)], [v(a), v(c), v(d)])
            } else {
                ([v(a), v(b), v(d)], [v(b), v(c), v(d)])
            };
            for (k, t) in [t1, t2].into_iter().enumerate() {
                // Any of the six vertex orders (both windings).
                let f = flip[(2 * q + k) % flip.len()] % 6;
                let t = match f {
                    0 => t,
                    1 => [t[1], t[2], t[0]],
                    2 => [t[2], t[0], t[1]],
                    3 => [t[0], t[2], t[1]],
                    4 => [t[2], t[1], t[0]],
                    _ => [t[1], t[0], t[2]],
                };
                tris.push(t);
            }
        }
    }
    tris
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Jittered meshes (any sub-pixel jitter up to 2.5 px, random diagonals, random winding)
    /// cover every pixel of the target exactly once.
    #[test]
    fn random_meshes_cover_every_pixel_once(
        jitter in prop::collection::vec((-40i32..=40, -40i32..=40), 49),
        diag in prop::collection::vec(any::<bool>(), 36),
        flip in prop::collection::vec(any::<u8>(), 72),
    ) {
        let tris = jittered_mesh(&jitter, &diag, &flip);
        let c = counts(&segments(Rect::from_size(48, 48), &tris, &TriangleOptions::default()), 48, 48);
        prop_assert!(c.iter().all(|&n| n == 1), "{:?}", c);
    }

    /// Same with vertices on the half-pixel lattice (pixel centres and corners), where every
    /// tie of the fill rule occurs.
    #[test]
    fn lattice_meshes_cover_every_pixel_once(
        jitter in prop::collection::vec((-5i32..=5, -5i32..=5), 49),
        diag in prop::collection::vec(any::<bool>(), 36),
        flip in prop::collection::vec(any::<u8>(), 72),
    ) {
        let jitter: Vec<(i32, i32)> = jitter.iter().map(|&(x, y)| (8 * x, 8 * y)).collect();
        let tris = jittered_mesh(&jitter, &diag, &flip);
        let c = counts(&segments(Rect::from_size(48, 48), &tris, &TriangleOptions::default()), 48, 48);
        prop_assert!(c.iter().all(|&n| n == 1), "{:?}", c);
    }

    /// Fans of 4..40 triangles around any sub-pixel point cover every pixel exactly once.
    #[test]
    fn random_fans_cover_every_pixel_once(
        centre in (0i32..48 * 16, 0i32..48 * 16),
        n in 4usize..40,
        jit in prop::collection::vec(0.0f64..0.4, 40),
        flip in prop::collection::vec(any::<bool>(), 40),
    ) {
        let mut ring = Vec::new();
        for k in 0..n {
            let a = (k as f64 + jit[k]) * core::f64::consts::TAU / n as f64;
            let r = 16.0 * 100.0;
            ring.push([(384.0 + r * a.cos()).round() as i32, (384.0 + r * a.sin()).round() as i32]);
        }
        let c = fan_counts([centre.0, centre.1], &ring, &flip);
        prop_assert!(c.iter().all(|&n| n == 1), "{:?}", c);
    }

    /// Random triangles (either winding, any sub-pixel position, partly off-screen) cover
    /// exactly the pixels the edge-function reference covers.
    #[test]
    fn coverage_matches_reference(
        p in prop::array::uniform3((-200i32..600, -200i32..600)),
        clip in (0u16..16, 0u16..16, 16u16..33, 16u16..33),
    ) {
        let v = p.map(|(x, y)| vert(x, y, 1 << 30, [0; 3]));
        let clip = Rect::new(clip.0, clip.1, clip.2, clip.3);
        let c = counts(&segments(clip, &[v], &TriangleOptions::new(Perspective::Affine)), 32, 32);
        for y in 0..32u16 {
            for x in 0..32u16 {
                let r = clip.contains(x, y)
                    && reference_covered(raw_xy(&v), 16 * x as i64 + 8, 16 * y as i64 + 8);
                prop_assert_eq!(c[y as usize * 32 + x as usize], r as u32, "{} {}", x, y);
            }
        }
    }

    /// Any i32 coordinates: never panics; inside the guard band, coverage matches the
    /// reference; outside, the triangle is rejected.
    #[test]
    fn extreme_coordinates(
        p in prop::array::uniform3((any::<i32>(), any::<i32>())),
        scale in 0u32..32,
        tex in prop::array::uniform3(prop::array::uniform3(any::<i32>())),
        w in prop::array::uniform3(any::<u32>()),
        mode in 0usize..4,
    ) {
        let v: [ScreenVertex; 3] = core::array::from_fn(|i| {
            vert(p[i].0 >> scale, p[i].1 >> scale, w[i], tex[i])
        });
        let mode = [Perspective::Exact, Perspective::Every8, Perspective::Every16, Perspective::Affine][mode];
        let mut r = Rasterizer::new(Rect::from_size(32, 32));
        let mut segs = Vec::new();
        r.draw(&v, &TriangleOptions::new(mode), &mut |s: &Segment| segs.push(*s));
        let inside = v.iter().all(|q| {
            q.x.to_bits().unsigned_abs() < GUARD_BAND && q.y.to_bits().unsigned_abs() < GUARD_BAND
        });
        let c = counts(&segs, 32, 32);
        for y in 0..32 {
            for x in 0..32 {
                let e = inside && reference_covered(raw_xy(&v), 16 * x + 8, 16 * y + 8);
                prop_assert_eq!(c[(y * 32 + x) as usize], e as u32);
            }
        }
        // Values stay within the vertex range.
        for s in &segs {
            for c in 0..3 {
                let lo = v.iter().map(|q| q.tex.to_bits()[c]).min().unwrap();
                let hi = v.iter().map(|q| q.tex.to_bits()[c]).max().unwrap();
                let s0 = s.s0.to_bits()[c];
                prop_assert!(lo <= s0 && s0 <= hi);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Clipping and bands.

#[test]
fn fully_offscreen_and_huge_triangles() {
    let o = TriangleOptions::new(Perspective::Every16);
    let mut r = Rasterizer::new(Rect::from_size(32, 32));
    let mut n = 0usize;
    // Entirely left of, above, right of and below the target.
    for t in [
        [
            vert(-800, 0, 1 << 30, [0; 3]),
            vert(-8, 100, 1 << 30, [0; 3]),
            vert(-500, 400, 1 << 30, [0; 3]),
        ],
        [
            vert(0, -900, 1 << 30, [0; 3]),
            vert(500, -9, 1 << 30, [0; 3]),
            vert(100, -300, 1 << 30, [0; 3]),
        ],
        [
            vert(520, 0, 1 << 30, [0; 3]),
            vert(9000, 100, 1 << 30, [0; 3]),
            vert(700, 400, 1 << 30, [0; 3]),
        ],
        [
            vert(0, 505, 1 << 30, [0; 3]),
            vert(500, 600, 1 << 30, [0; 3]),
            vert(100, 9000, 1 << 30, [0; 3]),
        ],
    ] {
        r.draw(&t, &o, &mut |_: &Segment| n += 1);
    }
    assert_eq!(n, 0);
    assert_eq!(r.counters().offscreen, 4);
    assert_eq!(r.counters().setups, 0);

    // A triangle near the guard band covering the whole target: every pixel, one run per row.
    let g = (GUARD_BAND - 1) as i32;
    let big = [
        vert(-g, -g, 1 << 30, [-(1 << 30), 0, 5]),
        vert(g, -g, 1 << 29, [1 << 30, 1 << 20, 5]),
        vert(0, g, 1 << 28, [0, -(1 << 30), 5]),
    ];
    for mode in [Perspective::Affine, Perspective::Every8, Perspective::Exact] {
        let segs = segments(Rect::from_size(32, 32), &[big], &TriangleOptions::new(mode));
        assert!(counts(&segs, 32, 32).iter().all(|&c| c == 1));
        let persp = mode != Perspective::Affine;
        for s in &segs {
            let r = reference_tex(&big, s.x0 as f64 + 0.5, s.y as f64 + 0.5, persp);
            for c in 0..3 {
                let bound = if persp {
                    persp_bound(&big, c)
                } else {
                    0.5 + 1e-3
                };
                let err = (s.s0.to_bits()[c] as f64 - r[c]).abs();
                assert!(err <= bound, "{mode:?} {s:?} {r:?} {bound}");
            }
        }
    }
}

/// Random triangles, rendered whole and in bands (and with a setup reused across bands): the
/// segments are identical.
fn banded(
    tris: &[[ScreenVertex; 3]],
    opts: &TriangleOptions,
    cuts: &[u16],
) -> Vec<(usize, Segment)> {
    let mut out = Vec::new();
    let mut r = Rasterizer::new(Rect::from_size(40, 40));
    for (k, t) in tris.iter().enumerate() {
        let Ok(setup) = TriangleSetup::new(t, opts) else {
            continue;
        };
        let mut y0 = 0;
        for &c in cuts.iter().chain(core::iter::once(&40)) {
            let c = c.max(y0);
            r.set_clip(Rect::new(0, y0, 40, c));
            r.draw_setup(&setup, &mut |s: &Segment| out.push((k, *s)));
            y0 = c;
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn bands_equal_full_frame(
        tris in prop::collection::vec(
            prop::array::uniform3((-100i32..740, -100i32..740, 1u32..u32::MAX, prop::array::uniform3(-(1i32 << 24)..(1 << 24)))),
            1..6),
        mut cuts in prop::collection::vec(0u16..40, 0..6),
        mode in 0usize..4,
    ) {
        cuts.sort();
        let tris: Vec<[ScreenVertex; 3]> = tris.iter().map(|t| t.map(|(x, y, w, s)| vert(x, y, w, s))).collect();
        let opts = TriangleOptions::new([Perspective::Exact, Perspective::Every8, Perspective::Every16, Perspective::Affine][mode]);
        let whole = banded(&tris, &opts, &[]);
        let bands = banded(&tris, &opts, &cuts);
        prop_assert_eq!(&whole, &bands);
        // Through `draw` with per-band clips too.
        let mut r = Rasterizer::new(Rect::from_size(40, 40));
        let mut drawn = Vec::new();
        let mut y0 = 0;
        for &c in cuts.iter().chain(core::iter::once(&40)) {
            r.set_clip(Rect::new(0, y0, 40, c.max(y0)));
            for (k, t) in tris.iter().enumerate() {
                r.draw(t, &opts, &mut |s: &Segment| drawn.push((k, *s)));
            }
            y0 = c.max(y0);
        }
        drawn.sort_by_key(|(k, s)| (*k, s.y, s.x0));
        prop_assert_eq!(&whole, &drawn);
    }

    /// Clipping in x changes where segments start, but never a pixel's exact value.
    #[test]
    fn x_clipping_keeps_exact_values(
        t in prop::array::uniform3((-100i32..740, -100i32..740, 1u32..u32::MAX, prop::array::uniform3(any::<i32>()))),
        x0 in 0u16..40, x1 in 0u16..40,
    ) {
        let t = t.map(|(x, y, w, s)| vert(x, y, w, s));
        let o = TriangleOptions::new(Perspective::Exact);
        let full = segments(Rect::from_size(40, 40), &[t], &o);
        let clip = Rect::new(x0.min(x1), 0, x0.max(x1), 40);
        let clipped = segments(clip, &[t], &o);
        let expect: Vec<Segment> = full.into_iter().filter(|s| clip.contains(s.x0, s.y)).collect();
        prop_assert_eq!(expect, clipped);
    }
}

// ---------------------------------------------------------------------------------------------
// Perspective accuracy.

/// A random textured triangle with `1/w` ratios up to `max_ratio`, on a `size`-pixel target.
fn persp_triangle() -> impl Strategy<Value = [ScreenVertex; 3]> {
    let coord = prop_oneof![
        -(1i32 << 20)..(1i32 << 20),
        -(1i32 << 26)..(1i32 << 26),
        any::<i32>(),
    ];
    prop::array::uniform3((
        -200i32..1200,
        -200i32..1200,
        1.0f64..256.0,
        prop::array::uniform3(coord),
    ))
    .prop_map(|t| t.map(|(x, y, w, s)| vert(x, y, ((1u64 << 31) as f64 / w).round() as u32, s)))
}

fn mode_segments(t: &[ScreenVertex; 3], mode: Perspective) -> (Vec<Segment>, Counters) {
    let mut r = Rasterizer::new(Rect::from_size(64, 64));
    let mut v = Vec::new();
    r.draw(t, &TriangleOptions::new(mode), &mut |s: &Segment| {
        v.push(*s)
    });
    (v, r.counters())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Exact mode: every pixel within the documented bound of the f64 reference; the x and y
    /// Jacobian columns agree with f64 central finite differences.
    #[test]
    fn exact_matches_f64_reference(t in persp_triangle()) {
        let (segs, ctr) = mode_segments(&t, Perspective::Exact);
        prop_assert_eq!(ctr.persp_points, ctr.pixels);
        for s in &segs {
            prop_assert_eq!(s.len, 1);
            let (x, y) = (s.x0 as f64 + 0.5, s.y as f64 + 0.5);
            let r = reference_tex(&t, x, y, true);
            let h = 1.0 / 128.0;
            let (rxp, rxm) = (reference_tex(&t, x + h, y, true), reference_tex(&t, x - h, y, true));
            let (ryp, rym) = (reference_tex(&t, x, y + h, true), reference_tex(&t, x, y - h, true));
            let lq = [reference_dlnq(&t, x, y, false), reference_dlnq(&t, x, y, true)];
            for c in 0..3 {
                let bound = persp_bound(&t, c);
                let got = s.s0.to_bits()[c] as f64;
                prop_assert!((got - r[c]).abs() <= bound, "c{} {} vs {} (bound {}) {:?}", c, got, r[c], bound, s);
                // Jacobian (analytic derivative) vs central differences. Tolerance: rounding
                // (1/2 LSB), the value error propagated through the quotient rule
                // (bound * |d ln(1/w)|), relative 2^-20, and the O(h^2) truncation error of
                // the finite difference (about h^2 |f'| |d ln(1/w)|^2).
                let fdx = (rxp[c] - rxm[c]) / (2.0 * h);
                let fdy = (ryp[c] - rym[c]) / (2.0 * h);
                for (d, (got, fd)) in [(s.ds.to_bits()[c], fdx), (s.dsdy.to_bits()[c], fdy)].into_iter().enumerate() {
                    let fd = fd.clamp(i32::MIN as f64, i32::MAX as f64);
                    let tol = 1.0
                        + 1.5 * bound * lq[d].abs()
                        + fd.abs() * (2f64.powi(-20) + 2.0 * h * h * lq[d] * lq[d]);
                    prop_assert!((got as f64 - fd).abs() <= tol, "c{} d{} {} vs {} (tol {}) {:?}", c, d, got, fd, tol, s);
                }
            }
        }
    }

    /// Every8/Every16: segment starts are bit-identical to Exact; segments are screen-aligned
    /// and at most n long; every pixel is within the documented bound of the f64 reference.
    #[test]
    fn every_n_bounds(t in persp_triangle(), sixteen in any::<bool>()) {
        let (mode, n) = if sixteen { (Perspective::Every16, 16) } else { (Perspective::Every8, 8) };
        let (exact, _) = mode_segments(&t, Perspective::Exact);
        let (segs, ctr) = mode_segments(&t, mode);
        let mut exact_at = std::collections::HashMap::new();
        for s in &exact {
            exact_at.insert((s.x0, s.y), *s);
        }
        prop_assert_eq!(ctr.pixels, exact.len() as u64);
        for (k, s) in segs.iter().enumerate() {
            prop_assert!(s.len >= 1 && s.len <= n);
            // Ends on a multiple of n, or at the run end.
            let end = s.x0 + s.len;
            let next_in_run = segs.get(k + 1).is_some_and(|t| t.y == s.y && t.x0 == end);
            // (Single pixels may also come from the fallback for steps beyond I16F16.)
            prop_assert!(!next_in_run || end % n == 0 || s.len == 1);
            let e = exact_at[&(s.x0, s.y)];
            prop_assert_eq!(s.s0, e.s0);
            prop_assert_eq!(s.dsdy, e.dsdy);
            if s.len == 1 {
                prop_assert_eq!(s.ds, e.ds);
                continue;
            }
            // The exact end point: the next segment's start or the run's last pixel.
            let (end_x, steps) = if next_in_run { (end, s.len) } else { (end - 1, s.len - 1) };
            let y = s.y as f64 + 0.5;
            let r0 = reference_tex(&t, s.x0 as f64 + 0.5, y, true);
            let re = reference_tex(&t, end_x as f64 + 0.5, y, true);
            for c in 0..3 {
                let tol = persp_bound(&t, c);
                // The linear continuation reaches the exact end point within steps/2 LSB.
                let e_val = if next_in_run { segs[k + 1].s0 } else { exact_at[&(end_x, s.y)].s0 };
                let reach = s.s_at(steps)[c] - e_val.to_bits()[c] as i64;
                prop_assert!(reach.abs() <= steps as i64 / 2 + 1, "{:?} {}", s, reach);
                for i in 0..s.len {
                    let x = s.x0 as f64 + i as f64 + 0.5;
                    let f = reference_tex(&t, x, y, true)[c];
                    let chord = r0[c] + (re[c] - r0[c]) * i as f64 / steps as f64;
                    let bound = (chord - f).abs() + tol + i as f64 / 2.0 + 1e-6;
                    let got = s.s_at(i)[c] as f64;
                    prop_assert!((got - f).abs() <= bound, "c{} i{} {} vs {} (bound {}) {:?}", c, i, got, f, bound, s);
                }
            }
        }
    }

    /// Affine: one segment per run, no divides, values within 1/2 + i/2 LSB of the
    /// screen-linear plane, Jacobian = plane gradient within 1/2 LSB.
    #[test]
    fn affine_is_linear_without_divides(t in persp_triangle()) {
        let (segs, ctr) = mode_segments(&t, Perspective::Affine);
        prop_assert_eq!(ctr.divides, 0);
        prop_assert_eq!(ctr.persp_points, 0);
        let x = 20.5;
        let y = 20.5;
        let r = reference_tex(&t, x, y, false);
        let gx = reference_tex(&t, x + 1.0, y, false);
        let gy = reference_tex(&t, x, y + 1.0, false);
        let steep = (0..3).any(|c| (gx[c] - r[c]).abs() >= 2f64.powi(31) - 1.0);
        for (k, s) in segs.iter().enumerate() {
            // One segment per run: the next segment is on another row or not adjacent.
            prop_assert!(steep || segs.get(k + 1).is_none_or(|n| n.y != s.y || n.x0 > s.x0 + s.len));
            for c in 0..3 {
                let dx = gx[c] - r[c];
                let dy = gy[c] - r[c];
                if !steep {
                    prop_assert!((s.ds.to_bits()[c] as f64 - dx).abs() <= 0.5 + 1e-3);
                }
                if dy.abs() < 2f64.powi(31) {
                    prop_assert!((s.dsdy.to_bits()[c] as f64 - dy).abs() <= 0.5 + 1e-3);
                }
                for i in 0..s.len {
                    let f = reference_tex(&t, (s.x0 + i) as f64 + 0.5, s.y as f64 + 0.5, false)[c];
                    let got = s.s_at(i)[c] as f64;
                    prop_assert!((got - f).abs() <= 0.5 + i as f64 / 2.0 + 1e-3, "{} vs {} {:?}", got, f, s);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Far from the origin of the planes (pixel (0, 0)), near the 65535-pixel limit, the
    /// bounds still hold (Exact and Affine).
    #[test]
    fn far_from_the_origin(t in persp_triangle(), ox in 0u16..65400, oy in 0u16..65400) {
        let t = t.map(|mut v| {
            v.x += ScreenCoord::from_num(ox);
            v.y += ScreenCoord::from_num(oy);
            v
        });
        let clip = Rect::new(ox, oy, ox + 64, oy + 64);
        for persp in [true, false] {
            let mode = if persp { Perspective::Exact } else { Perspective::Affine };
            for s in segments(clip, &[t], &TriangleOptions::new(mode)) {
                for i in 0..s.len {
                    let r = reference_tex(&t, (s.x0 + i) as f64 + 0.5, s.y as f64 + 0.5, persp);
                    for c in 0..3 {
                        let b = if persp { persp_bound(&t, c) } else { 0.5 + i as f64 / 2.0 + 1e-3 };
                        let got = s.s_at(i)[c] as f64;
                        prop_assert!((got - r[c]).abs() <= b, "{} vs {} {:?}", got, r[c], s);
                    }
                }
            }
        }
    }
}

#[test]
fn typical_triangles_are_within_one_lsb() {
    // Texture ranges of a few hundred units and w ratios up to 64: the documented bound is
    // below 0.52 LSB; check the total error directly on a deterministic set.
    let mut rng = crate::test_rng::XorShift32::new(0x1234_5678);
    let mut rnd = |n: u32| rng.below(n);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let t: [ScreenVertex; 3] = core::array::from_fn(|_| {
            let w = 1 + rnd(64);
            vert(
                rnd(1024) as i32,
                rnd(1024) as i32,
                (1u32 << 31) / w,
                [0, 1, 2].map(|_| rnd(1 << 25) as i32 - (1 << 24)),
            )
        });
        let (segs, _) = mode_segments(&t, Perspective::Exact);
        for s in &segs {
            let r = reference_tex(&t, s.x0 as f64 + 0.5, s.y as f64 + 0.5, true);
            for c in 0..3 {
                worst = worst.max((s.s0.to_bits()[c] as f64 - r[c]).abs());
            }
        }
    }
    assert!(worst <= 0.52, "{worst}");
}

// ---------------------------------------------------------------------------------------------
// Counters.

#[test]
fn divide_counts_per_mode() {
    // A 64-pixel-wide rectangle from column 0: per row, Every8 evaluates 8 segment starts and
    // the last pixel (9 points), Every16 5, Exact 64.
    let v = [
        vert(0, 0, 1 << 31, [0, 0, 0]),
        vert(64 * 16, 0, 1 << 29, [1 << 22, 0, 0]),
        vert(64 * 16, 4 * 16, 1 << 29, [1 << 22, 1 << 20, 0]),
    ];
    let w = vert(0, 4 * 16, 1 << 31, [0, 1 << 20, 0]);
    let quad = [v, [v[0], v[2], w]];
    let rows = 4u64;
    let mut r = Rasterizer::new(Rect::from_size(64, 64));
    for (mode, points, segs) in [
        (Perspective::Exact, 64, 64),
        (Perspective::Every8, 9, 8),
        (Perspective::Every16, 5, 4),
        (Perspective::Affine, 0, 0),
    ] {
        r.reset_counters();
        let mut n = Vec::new();
        for t in &quad {
            r.draw(t, &TriangleOptions::new(mode), &mut |s: &Segment| {
                n.push(*s)
            });
        }
        let c = r.counters();
        assert_eq!(c.triangles, 2);
        assert_eq!(c.setups, 2);
        assert_eq!(c.pixels, 64 * rows);
        let row_segments: u64 = n.iter().filter(|s| s.y == 0).count() as u64;
        if mode == Perspective::Affine {
            assert_eq!(c.divides, 0);
            assert_eq!(c.persp_points, 0);
        } else {
            // The two triangles split each row in two runs: count per row over both.
            let per_row = c.persp_points / rows;
            assert!(
                per_row >= points && per_row <= points + 2,
                "{mode:?} {per_row}"
            );
            assert!(
                row_segments >= segs && row_segments <= segs + 2,
                "{mode:?} {row_segments}"
            );
            assert!(c.divides >= 3 * c.persp_points);
        }
    }
    // The same rectangle as one run per row (a single big triangle clipped to it).
    let big = [
        vert(0, 0, 1 << 31, [0; 3]),
        vert(128 * 16, 0, 1 << 30, [1 << 22, 0, 0]),
        vert(0, 128 * 16, 1 << 30, [0, 1 << 22, 0]),
    ];
    r.set_clip(Rect::new(0, 0, 64, 4));
    for (mode, points) in [
        (Perspective::Exact, 64),
        (Perspective::Every8, 9),
        (Perspective::Every16, 5),
    ] {
        r.reset_counters();
        r.draw(&big, &TriangleOptions::new(mode), &mut |_: &Segment| {});
        assert_eq!(r.counters().persp_points, points * rows, "{mode:?}");
    }
}

#[test]
fn degenerate_triangles_draw_nothing() {
    let mut r = Rasterizer::new(Rect::from_size(16, 16));
    let mut n = 0;
    let z = [0; 3];
    for t in [
        [vert(50, 50, 1, z), vert(50, 50, 1, z), vert(50, 50, 1, z)],
        [vert(0, 0, 1, z), vert(100, 100, 1, z), vert(200, 200, 1, z)],
        [vert(0, 40, 1, z), vert(250, 40, 1, z), vert(100, 40, 1, z)],
        [vert(40, 0, 1, z), vert(40, 250, 1, z), vert(40, 100, 1, z)],
        [vert(0, 0, 1, z), vert(0, 0, 1, z), vert(200, 30, 1, z)],
    ] {
        for mode in [Perspective::Exact, Perspective::Affine] {
            r.draw(&t, &TriangleOptions::new(mode), &mut |_: &Segment| n += 1);
        }
    }
    assert_eq!(n, 0);
    assert_eq!(r.counters().degenerate, 10);
    assert_eq!(r.counters().pixels, 0);
}

proptest! {
    /// `div_round_i64` (32-bit divisors on the hardware divide) is `round(n / d)`, ties up,
    /// computed in i128.
    #[test]
    fn div_round_i64_rounds_half_up(n in any::<i64>(), d in 1i64.., shift in 0u32..63) {
        for d in [d, (d >> shift).max(1), 1, i64::from(u32::MAX), i64::from(u32::MAX) + 1] {
            let (n128, d128) = (i128::from(n), i128::from(d));
            let want = (2 * n128 + d128).div_euclid(2 * d128);
            prop_assert_eq!(i128::from(div_round_i64(n, d)), want, "{} / {}", n, d);
        }
    }
}

#[test]
fn div_round_i64_edges() {
    for n in [i64::MIN, i64::MIN + 1, -3, -2, -1, 0, 1, 2, 3, i64::MAX] {
        for d in [1i64, 2, 3, 7, i64::from(u32::MAX), 1 << 32, i64::MAX] {
            let want = (2 * i128::from(n) + i128::from(d)).div_euclid(2 * i128::from(d));
            assert_eq!(i128::from(div_round_i64(n, d)), want, "{n} / {d}");
        }
        assert_eq!(div_round_i64(n, 0), n);
        assert_eq!(div_round_i64(n, -5), n);
    }
}

/// `TriangleSetup::check` rejects exactly what `TriangleSetup::new` rejects, for the same
/// reason: zero-area, culled (both windings, both modes) and outside-the-guard-band triangles,
/// and accepts the rest.
#[test]
fn check_rejects_what_setup_rejects() {
    let big = (GUARD_BAND as i32) - 1;
    let tri = |p: [[i32; 2]; 3]| p.map(|[x, y]| vert(x, y, 1 << 30, [0; 3]));
    let tris = [
        tri([[0, 0], [160, 0], [0, 160]]),
        tri([[0, 0], [0, 160], [160, 0]]),
        tri([[5, 5], [10, 10], [20, 20]]),
        tri([[5, 5], [5, 5], [9, 1]]),
        tri([[-big, 0], [big, 0], [0, big]]),
        tri([[big + 1, 0], [0, 16], [16, 16]]),
        tri([[0, -big - 1], [0, 16], [16, 16]]),
    ];
    let mut seen = std::collections::BTreeSet::new();
    for cull in [
        CullMode::None,
        CullMode::Clockwise,
        CullMode::CounterClockwise,
    ] {
        let opts = TriangleOptions {
            cull,
            ..TriangleOptions::new(Perspective::Every16)
        };
        for (k, t) in tris.iter().enumerate() {
            let want = TriangleSetup::new(t, &opts).map(|_| ());
            assert_eq!(
                TriangleSetup::check(t, &opts),
                want,
                "triangle {k}, {cull:?}"
            );
            seen.insert(format!("{want:?}"));
        }
    }
    // Every outcome occurs.
    assert_eq!(seen.len(), 4, "{seen:?}");
}
