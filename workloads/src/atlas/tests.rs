//! The atlas layout, bake and frame against hand-made cases and the scans they replace.

extern crate std;
use super::frame::*;
use super::*;

/// Every quad half's corners from [`HalfCorners`] against its `AtlasTriangle`'s, for layouts
/// of one quad up to the most the atlas holds.
#[test]
fn half_corners_are_the_triangles() {
    let mut tried = 0;
    for quads in [1u32, 2, 3, 7, 64, 515, 516, 1000, 2047, 4096] {
        let Some(layout) = UniformLayout::new(quads) else {
            continue;
        };
        let table = HalfCorners::new(&layout).expect("corners of quad 0");
        for q in 0..quads {
            for (k, ((half, idx), tri)) in HALF_CORNERS.iter().zip(HALF_TRIANGLES).enumerate() {
                let uv = layout
                    .triangle(q, *half, [TexPoint::ZERO; 3])
                    .expect("a quad of the layout")
                    .inset_corners();
                let want = tri.map(|ci| uv[idx.iter().position(|&i| i == ci).unwrap()]);
                assert_eq!(
                    table.get(q, k),
                    Some(want),
                    "quads {quads}, quad {q}, half {k}"
                );
            }
        }
        assert_eq!(table.get(quads, 0), None);
        tried += 1;
    }
    assert!(tried >= 8, "layouts tried: {tried}");
}

/// The band index against a scan of the list, for random band ranges (empty ones
/// included), and its refusals.
#[test]
fn band_index_is_the_scan() {
    let mut seed = 0x2545_f491_u32;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    };
    for round in 0..200 {
        let bands = 1 + (next() % MAX_BANDS as u32) as usize;
        let list: std::vec::Vec<FrameQuad> = (0..next() % 300)
            .map(|_| {
                let b0 = (next() % (bands as u32 + 2)) as u8;
                let b1 = if next() % 8 == 0 {
                    0
                } else {
                    b0 + (next() % 4) as u8
                };
                FrameQuad {
                    bands: if next() % 16 == 0 {
                        [u8::MAX, 0]
                    } else {
                        [b0, b1]
                    },
                    ..FrameQuad::EMPTY
                }
            })
            .collect();
        let mut refs = std::vec![0u16; 4 * list.len()];
        let index = BandIndex::new(&list, bands, &mut refs).expect("refs enough");
        let mut total = 0;
        for b in 0..bands {
            let scan: std::vec::Vec<u16> = (0..list.len() as u16)
                .filter(|&i| {
                    let q = &list[usize::from(i)];
                    usize::from(q.bands[0]) <= b && b <= usize::from(q.bands[1])
                })
                .collect();
            assert_eq!(index.band(b), &scan[..], "round {round}, band {b}");
            total += scan.len();
        }
        assert!(index.band(bands).is_empty());
        if total > 0 {
            let mut short = std::vec![0u16; total - 1];
            assert!(
                BandIndex::new(&list, bands, &mut short).is_none(),
                "round {round}"
            );
        }
    }
    assert!(BandIndex::new(&[], MAX_BANDS + 1, &mut []).is_none());
}

/// The band fill sets exactly the pixels `fill_u16` sets, at every alignment and length of the
/// band (odd starts leave a head pixel, odd ends a tail pixel, short bands no word at all).
#[test]
fn band_fill_is_the_pixel_fill() {
    let mut a = [0x1234u16; 80];
    let mut b = [0x1234u16; 80];
    for start in 0..4 {
        for len in 0..70 {
            a.fill(0x1234);
            b.fill(0x1234);
            let v = 0xA55A ^ (start as u16 * 7 + len as u16);
            fill_rgb565(&mut a[start..start + len], v);
            texcore::raster::fill_u16(&mut b[start..start + len], v);
            assert_eq!(a, b, "start {start} len {len}");
        }
    }
}
