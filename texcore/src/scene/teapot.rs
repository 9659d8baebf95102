//! The Utah teapot (Martin Newell, 1975): its 32 bicubic Bezier patches over 306 control points,
//! and exact fixed-point evaluation for tessellation.
//!
//! The data are the classic patch set (rim, body, handle, spout, lid, and the four bottom patches
//! added later), as distributed in the public "teaset" archive (zero-based indices here). Object
//! space is the data's own: **z up**, the base at `z = 0`, the spout towards `+x`, the handle
//! towards `-x`; extent `x` in `[-3, 3.525]`, `y` in `[-2, 2]`, `z` in `[0, 3.15]`. Every patch
//! is oriented so that `dP/du x dP/dv` points out of the teapot.
//!
//! # Exact evaluation
//!
//! The teapot is tessellated at a level `n` (parameters `u = k/n`, `v = l/n`). The Bernstein
//! weights at `k/n` are the integers `b_i(k) = C(3, i) k^i (n - k)^(3 - i)` over `n^3`, so
//! `P(k, l) = sum_ij b_j(l) b_i(k) P_ji / n^6` has an **exact integer numerator** (`i64`,
//! at most `n^6 * 2^18 <= 2^42` for `n <= 16`) and is rounded once (half up) to `Q16.16`.
//! Hence a point depends only on the exact rational value of the surface at that parameter:
//! patches that share a boundary curve (the same four control points, in either direction)
//! produce **bit-identical vertices** along it, and the tessellated teapot has no cracks
//! between patches.

use super::math::{div_round, sat_i32, sat_i64, Vec3};

/// Number of patches.
pub const TEAPOT_PATCH_COUNT: usize = 32;
/// Number of control points.
pub const TEAPOT_POINT_COUNT: usize = 306;
/// Largest tessellation level accepted (higher levels are clamped to it).
pub const MAX_TEAPOT_LEVEL: u8 = 16;

/// The 32 bicubic Bezier patches of the teapot: 16 control-point indices each, row-major
/// (`index = 4 v + u`, `u` and `v` the patch parameters), zero-based.
pub const TEAPOT_PATCHES: [[u16; 16]; 32] = [
    [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
    [3, 16, 17, 18, 7, 19, 20, 21, 11, 22, 23, 24, 15, 25, 26, 27],
    [
        18, 28, 29, 30, 21, 31, 32, 33, 24, 34, 35, 36, 27, 37, 38, 39,
    ],
    [30, 40, 41, 0, 33, 42, 43, 4, 36, 44, 45, 8, 39, 46, 47, 12],
    [
        12, 13, 14, 15, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59,
    ],
    [
        15, 25, 26, 27, 51, 60, 61, 62, 55, 63, 64, 65, 59, 66, 67, 68,
    ],
    [
        27, 37, 38, 39, 62, 69, 70, 71, 65, 72, 73, 74, 68, 75, 76, 77,
    ],
    [
        39, 46, 47, 12, 71, 78, 79, 48, 74, 80, 81, 52, 77, 82, 83, 56,
    ],
    [
        56, 57, 58, 59, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95,
    ],
    [
        59, 66, 67, 68, 87, 96, 97, 98, 91, 99, 100, 101, 95, 102, 103, 104,
    ],
    [
        68, 75, 76, 77, 98, 105, 106, 107, 101, 108, 109, 110, 104, 111, 112, 113,
    ],
    [
        77, 82, 83, 56, 107, 114, 115, 84, 110, 116, 117, 88, 113, 118, 119, 92,
    ],
    [
        120, 121, 122, 123, 124, 125, 126, 127, 128, 129, 130, 131, 132, 133, 134, 135,
    ],
    [
        123, 136, 137, 120, 127, 138, 139, 124, 131, 140, 141, 128, 135, 142, 143, 132,
    ],
    [
        132, 133, 134, 135, 144, 145, 146, 147, 148, 149, 150, 151, 68, 152, 153, 154,
    ],
    [
        135, 142, 143, 132, 147, 155, 156, 144, 151, 157, 158, 148, 154, 159, 160, 68,
    ],
    [
        161, 162, 163, 164, 165, 166, 167, 168, 169, 170, 171, 172, 173, 174, 175, 176,
    ],
    [
        164, 177, 178, 161, 168, 179, 180, 165, 172, 181, 182, 169, 176, 183, 184, 173,
    ],
    [
        173, 174, 175, 176, 185, 186, 187, 188, 189, 190, 191, 192, 193, 194, 195, 196,
    ],
    [
        176, 183, 184, 173, 188, 197, 198, 185, 192, 199, 200, 189, 196, 201, 202, 193,
    ],
    [
        203, 203, 203, 203, 206, 207, 208, 209, 210, 210, 210, 210, 211, 212, 213, 214,
    ],
    [
        203, 203, 203, 203, 209, 216, 217, 218, 210, 210, 210, 210, 214, 219, 220, 221,
    ],
    [
        203, 203, 203, 203, 218, 223, 224, 225, 210, 210, 210, 210, 221, 226, 227, 228,
    ],
    [
        203, 203, 203, 203, 225, 229, 230, 206, 210, 210, 210, 210, 228, 231, 232, 211,
    ],
    [
        211, 212, 213, 214, 233, 234, 235, 236, 237, 238, 239, 240, 241, 242, 243, 244,
    ],
    [
        214, 219, 220, 221, 236, 245, 246, 247, 240, 248, 249, 250, 244, 251, 252, 253,
    ],
    [
        221, 226, 227, 228, 247, 254, 255, 256, 250, 257, 258, 259, 253, 260, 261, 262,
    ],
    [
        228, 231, 232, 211, 256, 263, 264, 233, 259, 265, 266, 237, 262, 267, 268, 241,
    ],
    [
        269, 269, 269, 269, 278, 279, 280, 281, 274, 275, 276, 277, 270, 271, 272, 273,
    ],
    [
        269, 269, 269, 269, 281, 288, 289, 290, 277, 285, 286, 287, 273, 282, 283, 284,
    ],
    [
        269, 269, 269, 269, 290, 297, 298, 299, 287, 294, 295, 296, 284, 291, 292, 293,
    ],
    [
        269, 269, 269, 269, 299, 304, 305, 278, 296, 302, 303, 274, 293, 300, 301, 270,
    ],
];

/// The 306 control points `(x, y, z)` in units of `10^-5` (z up, the base at `z = 0`).
pub const TEAPOT_POINTS: [[i32; 3]; 306] = [
    [140000, 0, 240000],
    [140000, -78400, 240000],
    [78400, -140000, 240000],
    [0, -140000, 240000],
    [133750, 0, 253125],
    [133750, -74900, 253125],
    [74900, -133750, 253125],
    [0, -133750, 253125],
    [143750, 0, 253125],
    [143750, -80500, 253125],
    [80500, -143750, 253125],
    [0, -143750, 253125],
    [150000, 0, 240000],
    [150000, -84000, 240000],
    [84000, -150000, 240000],
    [0, -150000, 240000],
    [-78400, -140000, 240000],
    [-140000, -78400, 240000],
    [-140000, 0, 240000],
    [-74900, -133750, 253125],
    [-133750, -74900, 253125],
    [-133750, 0, 253125],
    [-80500, -143750, 253125],
    [-143750, -80500, 253125],
    [-143750, 0, 253125],
    [-84000, -150000, 240000],
    [-150000, -84000, 240000],
    [-150000, 0, 240000],
    [-140000, 78400, 240000],
    [-78400, 140000, 240000],
    [0, 140000, 240000],
    [-133750, 74900, 253125],
    [-74900, 133750, 253125],
    [0, 133750, 253125],
    [-143750, 80500, 253125],
    [-80500, 143750, 253125],
    [0, 143750, 253125],
    [-150000, 84000, 240000],
    [-84000, 150000, 240000],
    [0, 150000, 240000],
    [78400, 140000, 240000],
    [140000, 78400, 240000],
    [74900, 133750, 253125],
    [133750, 74900, 253125],
    [80500, 143750, 253125],
    [143750, 80500, 253125],
    [84000, 150000, 240000],
    [150000, 84000, 240000],
    [175000, 0, 187500],
    [175000, -98000, 187500],
    [98000, -175000, 187500],
    [0, -175000, 187500],
    [200000, 0, 135000],
    [200000, -112000, 135000],
    [112000, -200000, 135000],
    [0, -200000, 135000],
    [200000, 0, 90000],
    [200000, -112000, 90000],
    [112000, -200000, 90000],
    [0, -200000, 90000],
    [-98000, -175000, 187500],
    [-175000, -98000, 187500],
    [-175000, 0, 187500],
    [-112000, -200000, 135000],
    [-200000, -112000, 135000],
    [-200000, 0, 135000],
    [-112000, -200000, 90000],
    [-200000, -112000, 90000],
    [-200000, 0, 90000],
    [-175000, 98000, 187500],
    [-98000, 175000, 187500],
    [0, 175000, 187500],
    [-200000, 112000, 135000],
    [-112000, 200000, 135000],
    [0, 200000, 135000],
    [-200000, 112000, 90000],
    [-112000, 200000, 90000],
    [0, 200000, 90000],
    [98000, 175000, 187500],
    [175000, 98000, 187500],
    [112000, 200000, 135000],
    [200000, 112000, 135000],
    [112000, 200000, 90000],
    [200000, 112000, 90000],
    [200000, 0, 45000],
    [200000, -112000, 45000],
    [112000, -200000, 45000],
    [0, -200000, 45000],
    [150000, 0, 22500],
    [150000, -84000, 22500],
    [84000, -150000, 22500],
    [0, -150000, 22500],
    [150000, 0, 15000],
    [150000, -84000, 15000],
    [84000, -150000, 15000],
    [0, -150000, 15000],
    [-112000, -200000, 45000],
    [-200000, -112000, 45000],
    [-200000, 0, 45000],
    [-84000, -150000, 22500],
    [-150000, -84000, 22500],
    [-150000, 0, 22500],
    [-84000, -150000, 15000],
    [-150000, -84000, 15000],
    [-150000, 0, 15000],
    [-200000, 112000, 45000],
    [-112000, 200000, 45000],
    [0, 200000, 45000],
    [-150000, 84000, 22500],
    [-84000, 150000, 22500],
    [0, 150000, 22500],
    [-150000, 84000, 15000],
    [-84000, 150000, 15000],
    [0, 150000, 15000],
    [112000, 200000, 45000],
    [200000, 112000, 45000],
    [84000, 150000, 22500],
    [150000, 84000, 22500],
    [84000, 150000, 15000],
    [150000, 84000, 15000],
    [-160000, 0, 202500],
    [-160000, -30000, 202500],
    [-150000, -30000, 225000],
    [-150000, 0, 225000],
    [-230000, 0, 202500],
    [-230000, -30000, 202500],
    [-250000, -30000, 225000],
    [-250000, 0, 225000],
    [-270000, 0, 202500],
    [-270000, -30000, 202500],
    [-300000, -30000, 225000],
    [-300000, 0, 225000],
    [-270000, 0, 180000],
    [-270000, -30000, 180000],
    [-300000, -30000, 180000],
    [-300000, 0, 180000],
    [-150000, 30000, 225000],
    [-160000, 30000, 202500],
    [-250000, 30000, 225000],
    [-230000, 30000, 202500],
    [-300000, 30000, 225000],
    [-270000, 30000, 202500],
    [-300000, 30000, 180000],
    [-270000, 30000, 180000],
    [-270000, 0, 157500],
    [-270000, -30000, 157500],
    [-300000, -30000, 135000],
    [-300000, 0, 135000],
    [-250000, 0, 112500],
    [-250000, -30000, 112500],
    [-265000, -30000, 93750],
    [-265000, 0, 93750],
    [-200000, -30000, 90000],
    [-190000, -30000, 60000],
    [-190000, 0, 60000],
    [-300000, 30000, 135000],
    [-270000, 30000, 157500],
    [-265000, 30000, 93750],
    [-250000, 30000, 112500],
    [-190000, 30000, 60000],
    [-200000, 30000, 90000],
    [170000, 0, 142500],
    [170000, -66000, 142500],
    [170000, -66000, 60000],
    [170000, 0, 60000],
    [260000, 0, 142500],
    [260000, -66000, 142500],
    [310000, -66000, 82500],
    [310000, 0, 82500],
    [230000, 0, 210000],
    [230000, -25000, 210000],
    [240000, -25000, 202500],
    [240000, 0, 202500],
    [270000, 0, 240000],
    [270000, -25000, 240000],
    [330000, -25000, 240000],
    [330000, 0, 240000],
    [170000, 66000, 60000],
    [170000, 66000, 142500],
    [310000, 66000, 82500],
    [260000, 66000, 142500],
    [240000, 25000, 202500],
    [230000, 25000, 210000],
    [330000, 25000, 240000],
    [270000, 25000, 240000],
    [280000, 0, 247500],
    [280000, -25000, 247500],
    [352500, -25000, 249375],
    [352500, 0, 249375],
    [290000, 0, 247500],
    [290000, -15000, 247500],
    [345000, -15000, 251250],
    [345000, 0, 251250],
    [280000, 0, 240000],
    [280000, -15000, 240000],
    [320000, -15000, 240000],
    [320000, 0, 240000],
    [352500, 25000, 249375],
    [280000, 25000, 247500],
    [345000, 15000, 251250],
    [290000, 15000, 247500],
    [320000, 15000, 240000],
    [280000, 15000, 240000],
    [0, 0, 315000],
    [0, -200, 315000],
    [200, 0, 315000],
    [80000, 0, 315000],
    [80000, -45000, 315000],
    [45000, -80000, 315000],
    [0, -80000, 315000],
    [0, 0, 285000],
    [20000, 0, 270000],
    [20000, -11200, 270000],
    [11200, -20000, 270000],
    [0, -20000, 270000],
    [-200, 0, 315000],
    [-45000, -80000, 315000],
    [-80000, -45000, 315000],
    [-80000, 0, 315000],
    [-11200, -20000, 270000],
    [-20000, -11200, 270000],
    [-20000, 0, 270000],
    [0, 200, 315000],
    [-80000, 45000, 315000],
    [-45000, 80000, 315000],
    [0, 80000, 315000],
    [-20000, 11200, 270000],
    [-11200, 20000, 270000],
    [0, 20000, 270000],
    [45000, 80000, 315000],
    [80000, 45000, 315000],
    [11200, 20000, 270000],
    [20000, 11200, 270000],
    [40000, 0, 255000],
    [40000, -22400, 255000],
    [22400, -40000, 255000],
    [0, -40000, 255000],
    [130000, 0, 255000],
    [130000, -72800, 255000],
    [72800, -130000, 255000],
    [0, -130000, 255000],
    [130000, 0, 240000],
    [130000, -72800, 240000],
    [72800, -130000, 240000],
    [0, -130000, 240000],
    [-22400, -40000, 255000],
    [-40000, -22400, 255000],
    [-40000, 0, 255000],
    [-72800, -130000, 255000],
    [-130000, -72800, 255000],
    [-130000, 0, 255000],
    [-72800, -130000, 240000],
    [-130000, -72800, 240000],
    [-130000, 0, 240000],
    [-40000, 22400, 255000],
    [-22400, 40000, 255000],
    [0, 40000, 255000],
    [-130000, 72800, 255000],
    [-72800, 130000, 255000],
    [0, 130000, 255000],
    [-130000, 72800, 240000],
    [-72800, 130000, 240000],
    [0, 130000, 240000],
    [22400, 40000, 255000],
    [40000, 22400, 255000],
    [72800, 130000, 255000],
    [130000, 72800, 255000],
    [72800, 130000, 240000],
    [130000, 72800, 240000],
    [0, 0, 0],
    [150000, 0, 15000],
    [150000, 84000, 15000],
    [84000, 150000, 15000],
    [0, 150000, 15000],
    [150000, 0, 7500],
    [150000, 84000, 7500],
    [84000, 150000, 7500],
    [0, 150000, 7500],
    [142500, 0, 0],
    [142500, 79800, 0],
    [79800, 142500, 0],
    [0, 142500, 0],
    [-84000, 150000, 15000],
    [-150000, 84000, 15000],
    [-150000, 0, 15000],
    [-84000, 150000, 7500],
    [-150000, 84000, 7500],
    [-150000, 0, 7500],
    [-79800, 142500, 0],
    [-142500, 79800, 0],
    [-142500, 0, 0],
    [-150000, -84000, 15000],
    [-84000, -150000, 15000],
    [0, -150000, 15000],
    [-150000, -84000, 7500],
    [-84000, -150000, 7500],
    [0, -150000, 7500],
    [-142500, -79800, 0],
    [-79800, -142500, 0],
    [0, -142500, 0],
    [84000, -150000, 15000],
    [150000, -84000, 15000],
    [84000, -150000, 7500],
    [150000, -84000, 7500],
    [79800, -142500, 0],
    [142500, -79800, 0],
];

/// The control points in `Q16.16` (each rounded to nearest from the `10^-5` table).
pub const TEAPOT_POINTS_Q16: [Vec3; TEAPOT_POINT_COUNT] = {
    let mut out = [Vec3::ZERO; TEAPOT_POINT_COUNT];
    let mut i = 0;
    while i < TEAPOT_POINT_COUNT {
        let p = TEAPOT_POINTS[i];
        out[i] = Vec3::new(to_q16(p[0]), to_q16(p[1]), to_q16(p[2]));
        i += 1;
    }
    out
};

const fn to_q16(v: i32) -> i32 {
    div_round(v as i64 * 65536, 100_000) as i32
}

/// The Bernstein numerators `C(3, i) k^i (n - k)^(3 - i)`, `i = 0..4` (they sum to `n^3`).
const fn bernstein(n: i64, k: i64) -> [i64; 4] {
    let j = n - k;
    [j * j * j, 3 * k * j * j, 3 * k * k * j, k * k * k]
}

/// Every control point coordinate is below `2^18` in magnitude (checked at compile time), so a
/// row numerator `sum_i b_i P_ji` (`sum_i b_i = n^3 <= 2^12`) is below `2^30`: exact in i32.
const POINT_BOUND_BITS: u32 = 18;
const _: () = {
    let mut i = 0;
    while i < TEAPOT_POINT_COUNT {
        let p = TEAPOT_POINTS_Q16[i];
        assert!(p.x.unsigned_abs() < 1 << POINT_BOUND_BITS);
        assert!(p.y.unsigned_abs() < 1 << POINT_BOUND_BITS);
        assert!(p.z.unsigned_abs() < 1 << POINT_BOUND_BITS);
        i += 1;
    }
    let n = MAX_TEAPOT_LEVEL as u32;
    assert!(n * n * n <= 1 << (30 - POINT_BOUND_BITS));
};

/// Exact numerators of the four curves of patch `idx` along one parameter, for the Bernstein
/// numerators `w` of one of its steps (at most `n^3 <= 2^12`, summing to `n^3`): without
/// `COLUMNS` the row curves at `u = k / n`, `sum_i b_i(k) P_ji` for each row `j`; with
/// `COLUMNS` the column curves at `v = l / n`, `sum_j b_j(l) P_ji` for each column `i`. Either
/// is below `n^3 2^18 <= 2^30` in magnitude, so 32-bit products and sums are exact. [`combine`]
/// of the column curves with the weights of a step `k` is the point at `(k, l)` bit for bit: its
/// exact numerator `sum_i b_i(k) sum_j b_j(l) P_ji` is the same integer as that of the row
/// curves at `k` combined with the weights of `l`, summed in the other order (no partial sum
/// wraps).
fn curves_at<const COLUMNS: bool>(idx: &[u16; 16], w: &[i64; 4]) -> [[i32; 3]; 4] {
    let w = w.map(|b| b as i32);
    let mut out = [[0i32; 3]; 4];
    // Masked indices: provably in bounds (no panic path in any code shape).
    for j in 0..4usize {
        for i in 0..4usize {
            // Control point `P_ji` (row `j`, column `i`) into its row's or its column's curve.
            let (o, wk) = if COLUMNS { (i, j) } else { (j, i) };
            let (o, wk) = (&mut out[o & 3], w[wk & 3]);
            let p = TEAPOT_POINTS_Q16
                .get(idx[(4 * j + i) & 15] as usize)
                .copied()
                .unwrap_or(Vec3::ZERO);
            o[0] = o[0].wrapping_add(wk.wrapping_mul(p.x));
            o[1] = o[1].wrapping_add(wk.wrapping_mul(p.y));
            o[2] = o[2].wrapping_add(wk.wrapping_mul(p.z));
        }
    }
    out
}

/// `round(sum_j b_j(l) rows_j / n^6)` per coordinate: the exact numerator (`|acc| < 2^42`) times
/// `recip = round(2^62 / n^6)`, rounded half up from 62 fraction bits. A function of the exact
/// numerator only (so shared boundaries agree bit for bit), within `2^-20` LSB of the exactly
/// rounded quotient before the final rounding (exact at control points).
fn combine(rows: &[[i32; 3]; 4], bv: &[i64; 4], recip: Recip6) -> Vec3 {
    // 32 x 32 -> 64-bit products (`|b_j| <= 2^12`, `|rows| < 2^30`): one multiply-accumulate.
    let mut acc = [0i64; 3];
    for (r, &wv) in rows.iter().zip(bv.iter()) {
        let wv = i64::from(wv as i32);
        acc[0] += wv * i64::from(r[0]);
        acc[1] += wv * i64::from(r[1]);
        acc[2] += wv * i64::from(r[2]);
    }
    // A signed 64 x 64 -> 128-bit product (|acc| < 2^42, recip <= 2^62), rounded half up by
    // one addition and shift: round_shift_128 of the same product. When recip = 2^k with
    // k < 62 (levels 2, 4 and 8), (a 2^k + 2^61) >> 62 = (a + 2^(61 - k)) >> (62 - k) exactly:
    // one 64-bit addition and shift, no 128-bit product (|a| + 2^30 < 2^63).
    let s = recip.shift;
    if s != 0 {
        // 0 < s < 32 (asserted with `RECIP6`): masked, the compiler knows the shift of each
        // 64-bit sum stays within a word (three instructions, no test of `s >= 32`).
        let s = s & 31;
        let half = i64::from(1u32 << (s - 1));
        let f = |a: i64| sat_i32((a + half) >> s);
        return Vec3::new(f(acc[0]), f(acc[1]), f(acc[2]));
    }
    let r = recip.recip;
    let f = |a: i64| sat_i32(sat_i64((a as i128 * r as i128 + (1 << 61)) >> 62));
    Vec3::new(f(acc[0]), f(acc[1]), f(acc[2]))
}

/// `round(2^62 / n^6)` for a level `n`, and the shift `62 - k` that divides by it when it is
/// `2^k` with `k < 62` (0 otherwise): found once at compile time, not at every point.
#[derive(Clone, Copy, Debug)]
struct Recip6 {
    recip: i64,
    shift: u32,
}

impl Recip6 {
    /// No level (outside `1..=MAX_TEAPOT_LEVEL`).
    const NONE: Recip6 = Recip6 { recip: 0, shift: 0 };
}

/// [`Recip6`] for every level `n` (index `n`; index 0 unused), computed at compile time: no
/// 64-bit division a quad.
const RECIP6: [Recip6; MAX_TEAPOT_LEVEL as usize + 1] = {
    let mut t = [Recip6::NONE; MAX_TEAPOT_LEVEL as usize + 1];
    let mut n = 1;
    while n <= MAX_TEAPOT_LEVEL as i64 {
        let recip = div_round(1 << 62, n * n * n * n * n * n);
        let k = recip.trailing_zeros();
        let shift = if recip == 1 << k && k < 62 { 62 - k } else { 0 };
        t[n as usize] = Recip6 { recip, shift };
        n += 1;
    }
    t
};

// `combine`'s shifts stay within a word.
const _: () = {
    let mut n = 0;
    while n < RECIP6.len() {
        assert!(RECIP6[n].shift < 32);
        n += 1;
    }
};

/// [`Recip6`] of a clamped level `n` (`1..=MAX_TEAPOT_LEVEL`; zero outside).
fn recip6(n: i64) -> Recip6 {
    RECIP6.get(n as usize).copied().unwrap_or(Recip6::NONE)
}

/// The point of patch `patch` at `u = k / n`, `v = l / n` (`k, l <= n`), rounded to `Q16.16`.
/// `n` is clamped to `1..=MAX_TEAPOT_LEVEL`, `k` and `l` to `0..=n`; an out-of-range patch gives
/// the origin.
pub fn teapot_point(patch: usize, n: u32, k: u32, l: u32) -> Vec3 {
    let Some(idx) = TEAPOT_PATCHES.get(patch) else {
        return Vec3::ZERO;
    };
    let n = n.clamp(1, MAX_TEAPOT_LEVEL as u32);
    let (k, l) = (k.min(n) as i64, l.min(n) as i64);
    let n = n as i64;
    combine(
        &curves_at::<false>(idx, &bernstein(n, k)),
        &bernstein(n, l),
        recip6(n),
    )
}

/// Where quad `(k, l)` of patch `patch` at level `n` lies: the patch's control points, the
/// level (clamped to `1..=MAX_TEAPOT_LEVEL`), its parameter steps `k, k + 1` and `l, l + 1`
/// (clamped to the level) and `recip6` of the level. `None` past the last patch.
struct QuadAt {
    idx: &'static [u16; 16],
    n: i64,
    k: [i64; 2],
    l: [i64; 2],
    recip: Recip6,
}

impl QuadAt {
    fn new(patch: usize, n: u32, k: u32, l: u32) -> Option<QuadAt> {
        let idx = TEAPOT_PATCHES.get(patch)?;
        let n = n.clamp(1, MAX_TEAPOT_LEVEL as u32);
        let (k0, l0) = (k.min(n) as i64, l.min(n) as i64);
        let n = n as i64;
        Some(QuadAt {
            idx,
            n,
            k: [k0, (k0 + 1).min(n)],
            l: [l0, (l0 + 1).min(n)],
            recip: recip6(n),
        })
    }

    /// The patch's row curves at parameter step `k` ([`curves_at`]).
    fn rows(&self, k: i64) -> [[i32; 3]; 4] {
        curves_at::<false>(self.idx, &bernstein(self.n, k))
    }

    /// The Bernstein weights of parameter step `l` ([`bernstein`]).
    fn weights(&self, l: i64) -> [i64; 4] {
        bernstein(self.n, l)
    }

    /// The point of the row curves `rows` with the weights `w` of a step ([`combine`]).
    fn point(&self, rows: &[[i32; 3]; 4], w: &[i64; 4]) -> Vec3 {
        combine(rows, w, self.recip)
    }
}

/// The corners `[P(k, l), P(k+1, l), P(k+1, l+1), P(k, l+1)]` of quad `(k, l)` of patch
/// `patch` at level `n` (`k, l < n`), identical to four calls of [`teapot_point`] but sharing
/// the row curves (about half the work).
pub fn teapot_quad(patch: usize, n: u32, k: u32, l: u32) -> [Vec3; 4] {
    let Some(at) = QuadAt::new(patch, n, k, l) else {
        return [Vec3::ZERO; 4];
    };
    let ([k0, k1], [l0, l1]) = (at.k, at.l);
    let (r0, r1) = (at.rows(k0), at.rows(k1));
    let (b0, b1) = (at.weights(l0), at.weights(l1));
    [
        at.point(&r0, &b0),
        at.point(&r1, &b0),
        at.point(&r1, &b1),
        at.point(&r0, &b1),
    ]
}

/// Corners 1 and 2 of [`teapot_quad`]`(patch, n, k, l)` (its edge at `k + 1`), computed as
/// that function computes them: when `k >= 1`, its corners 0 and 3 are exactly corners 1 and 2
/// of `teapot_quad(patch, n, k - 1, l)`, so a walk along `k` needs only this edge.
#[inline(never)]
pub fn teapot_right_edge(patch: usize, n: u32, k: u32, l: u32) -> [Vec3; 2] {
    let Some(at) = QuadAt::new(patch, n, k, l) else {
        return [Vec3::ZERO; 2];
    };
    let r1 = at.rows(at.k[1]);
    let [l0, l1] = at.l;
    [
        at.point(&r1, &at.weights(l0)),
        at.point(&r1, &at.weights(l1)),
    ]
}

/// One row of quads of a patch, `(k, l)` for every `k` at one `l`: the column curves at `l` and
/// `l + 1` ([`curves_at`]), so that each vertical edge of the row, `[P(k, l), P(k, l + 1)]`, is two
/// [`combine`]s (a walk along the row computes one edge a quad). Every point is exactly
/// [`teapot_point`]'s (and [`teapot_quad`]'s): the curves give the same exact numerators.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TeapotRow {
    patch: u32,
    n: u32,
    l: u32,
    cols: [[[i32; 3]; 4]; 2],
    recip: Recip6,
}

impl TeapotRow {
    /// The row `l` of patch `patch` at level `n` (`n` in `1..=MAX_TEAPOT_LEVEL`, `l < n`; `None`
    /// otherwise or past the last patch). When `prev` is the row `l - 1` of the same patch and
    /// level, its curves at `l` are taken over (one [`curves_at`] instead of two).
    pub(crate) fn new(patch: u32, n: u32, l: u32, prev: Option<&TeapotRow>) -> Option<TeapotRow> {
        let idx = TEAPOT_PATCHES.get(patch as usize)?;
        if n == 0 || n > MAX_TEAPOT_LEVEL as u32 || l >= n {
            return None;
        }
        let (ni, li) = (i64::from(n), i64::from(l));
        let at_l = match prev {
            Some(r) if r.patch == patch && r.n == n && r.l.wrapping_add(1) == l => r.cols[1],
            _ => curves_at::<true>(idx, &bernstein(ni, li)),
        };
        Some(TeapotRow {
            patch,
            n,
            l,
            cols: [at_l, curves_at::<true>(idx, &bernstein(ni, li + 1))],
            recip: recip6(ni),
        })
    }

    /// Whether this is the row `l` of patch `patch` at level `n`.
    pub(crate) fn is(&self, patch: u32, n: u32, l: u32) -> bool {
        self.patch == patch && self.n == n && self.l == l
    }

    /// The row's edge at step `k` (`k <= n`): `[P(k, l), P(k, l + 1)]`.
    pub(crate) fn edge(&self, k: u32) -> [Vec3; 2] {
        let w = bernstein(i64::from(self.n), i64::from(k.min(self.n)));
        let [c0, c1] = &self.cols;
        [combine(c0, &w, self.recip), combine(c1, &w, self.recip)]
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    /// `combine` at every level (the power-of-two ones take the shift) equals the 128-bit
    /// product rounded half up, for random rows and weights up to their bounds.
    #[test]
    fn combine_is_the_wide_product() {
        let mut st = 99u64;
        let mut rnd = |bits: u32| {
            let st = crate::test_rng::lcg64(&mut st);
            let v = (st >> 33) as i64 & ((1 << bits) - 1);
            if st & 1 == 0 {
                v
            } else {
                -v
            }
        };
        for n in 1..=MAX_TEAPOT_LEVEL as i64 {
            let recip = recip6(n);
            for _ in 0..2000 {
                let rows = [[0i32; 3]; 4].map(|r| r.map(|_| rnd(30) as i32));
                let bv = [0i64; 4].map(|_| rnd(12));
                let got = combine(&rows, &bv, recip);
                let mut acc = [0i128; 3];
                for (r, &w) in rows.iter().zip(&bv) {
                    for c in 0..3 {
                        acc[c] += w as i128 * r[c] as i128;
                    }
                }
                let f = |a: i128| {
                    let q = crate::scene::math::round_shift_128(a * recip.recip as i128, 62);
                    q.clamp(i32::MIN as i128, i32::MAX as i128) as i32
                };
                assert_eq!(got, Vec3::new(f(acc[0]), f(acc[1]), f(acc[2])), "n = {n}");
            }
        }
    }

    #[test]
    fn patch_data_counts() {
        assert_eq!(TEAPOT_PATCHES.len(), 32);
        assert_eq!(TEAPOT_POINTS.len(), 306);
        let max = TEAPOT_PATCHES.iter().flatten().copied().max().unwrap();
        assert_eq!(max as usize, TEAPOT_POINT_COUNT - 1);
        // Four near-duplicate points of the lid's pole are in the data but unused.
        let mut used = [false; 306];
        for &i in TEAPOT_PATCHES.iter().flatten() {
            used[i as usize] = true;
        }
        let unused: std::vec::Vec<usize> = (0..306).filter(|&i| !used[i]).collect();
        assert_eq!(unused, [204, 205, 215, 222]);
    }

    /// The rim, body, lid and bottom are four copies of one quadrant turned by quarter turns,
    /// the handle and spout are mirror-symmetric in y: a transcription error would break this.
    #[test]
    fn patch_data_symmetry() {
        let p = |i: u16| TEAPOT_POINTS[i as usize];
        for (group, sense) in [(0, 1), (4, 1), (8, 1), (20, 1), (24, 1), (28, -1)] {
            for k in 0..4 {
                let a = TEAPOT_PATCHES[group + k];
                let b = TEAPOT_PATCHES[group + (k + 1) % 4];
                for (&i, &j) in a.iter().zip(b.iter()) {
                    let [x, y, z] = p(i);
                    let turned = if sense > 0 { [y, -x, z] } else { [-y, x, z] };
                    assert_eq!(
                        turned,
                        p(j),
                        "patches {} {}",
                        group + k,
                        group + (k + 1) % 4
                    );
                }
            }
        }
        for (a, b) in [(12, 13), (14, 15), (16, 17), (18, 19)] {
            for r in 0..4 {
                for c in 0..4 {
                    let [x, y, z] = p(TEAPOT_PATCHES[a][r * 4 + c]);
                    assert_eq!([x, -y, z], p(TEAPOT_PATCHES[b][r * 4 + 3 - c]));
                }
            }
        }
    }

    #[test]
    fn quads_equal_points() {
        for n in [1u32, 4, 5, 16] {
            for patch in 0..32 {
                for (k, l) in [(0, 0), (n - 1, 0), (n / 2, n - 1), (n - 1, n - 1)] {
                    assert_eq!(
                        teapot_quad(patch, n, k, l),
                        [
                            teapot_point(patch, n, k, l),
                            teapot_point(patch, n, k + 1, l),
                            teapot_point(patch, n, k + 1, l + 1),
                            teapot_point(patch, n, k, l + 1),
                        ]
                    );
                }
            }
        }
    }

    /// Every quad of every patch at every level from a walk of [`TeapotRow`]s (each row taking
    /// over the one before) equals [`teapot_quad`]: the column curves give the same points.
    #[test]
    fn rows_of_quads_are_the_quads() {
        for n in 1..=MAX_TEAPOT_LEVEL as u32 {
            for patch in 0..TEAPOT_PATCH_COUNT as u32 {
                let mut row: Option<TeapotRow> = None;
                for l in 0..n {
                    let r = TeapotRow::new(patch, n, l, row.as_ref()).unwrap();
                    assert!(r.is(patch, n, l));
                    // A row taken over equals a row computed afresh.
                    let fresh = TeapotRow::new(patch, n, l, None).unwrap();
                    assert_eq!(r.cols, fresh.cols);
                    for k in 0..n {
                        let [a, d] = r.edge(k);
                        let [b, c] = r.edge(k + 1);
                        let want = teapot_quad(patch as usize, n, k, l);
                        assert_eq!([a, b, c, d], want, "patch {patch} n {n} k {k} l {l}");
                        if k > 0 {
                            assert_eq!([b, c], teapot_right_edge(patch as usize, n, k, l));
                        }
                    }
                    row = Some(r);
                }
            }
        }
        assert!(TeapotRow::new(0, 0, 0, None).is_none());
        assert!(TeapotRow::new(0, 4, 4, None).is_none());
        assert!(TeapotRow::new(TEAPOT_PATCH_COUNT as u32, 4, 0, None).is_none());
        assert!(TeapotRow::new(0, MAX_TEAPOT_LEVEL as u32 + 1, 0, None).is_none());
    }

    #[test]
    fn corners_are_control_points() {
        for (pi, patch) in TEAPOT_PATCHES.iter().enumerate() {
            for n in [1, 3, 7, 16] {
                assert_eq!(
                    teapot_point(pi, n, 0, 0),
                    TEAPOT_POINTS_Q16[patch[0] as usize]
                );
                assert_eq!(
                    teapot_point(pi, n, n, 0),
                    TEAPOT_POINTS_Q16[patch[3] as usize]
                );
                assert_eq!(
                    teapot_point(pi, n, 0, n),
                    TEAPOT_POINTS_Q16[patch[12] as usize]
                );
                assert_eq!(
                    teapot_point(pi, n, n, n),
                    TEAPOT_POINTS_Q16[patch[15] as usize]
                );
            }
        }
        assert_eq!(teapot_point(99, 4, 1, 1), Vec3::ZERO);
    }

    #[test]
    fn matches_f64_bezier() {
        let b = |t: f64| {
            [
                (1. - t).powi(3),
                3. * t * (1. - t).powi(2),
                3. * t * t * (1. - t),
                t.powi(3),
            ]
        };
        for (pi, patch) in TEAPOT_PATCHES.iter().enumerate() {
            for (k, l) in [(1, 2), (3, 3), (0, 4), (5, 1)] {
                let n = 5;
                let (bu, bv) = (b(k as f64 / n as f64), b(l as f64 / n as f64));
                let mut e = [0f64; 3];
                for r in 0..4 {
                    for c in 0..4 {
                        let q = TEAPOT_POINTS[patch[r * 4 + c] as usize];
                        for d in 0..3 {
                            e[d] += bv[r] * bu[c] * q[d] as f64 * 1e-5;
                        }
                    }
                }
                let got = teapot_point(pi, n, k, l).to_array();
                for d in 0..3 {
                    assert!((got[d] as f64 / 65536.0 - e[d]).abs() < 2e-5, "patch {pi}");
                }
            }
        }
    }

    /// Patches sharing a boundary curve (four equal control points along an edge, in either
    /// order) give bit-identical points along it at every level.
    #[test]
    fn shared_boundaries_identical() {
        // Boundary curves as (patch, edge): edge 0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0.
        let edge_pts_ctl = |p: usize, e: usize| -> [[i32; 3]; 4] {
            let q = TEAPOT_PATCHES[p].map(|i| TEAPOT_POINTS[i as usize]);
            match e {
                0 => [q[0], q[1], q[2], q[3]],
                1 => [q[3], q[7], q[11], q[15]],
                2 => [q[12], q[13], q[14], q[15]],
                _ => [q[0], q[4], q[8], q[12]],
            }
        };
        let edge_pts = |p: usize, e: usize, n: u32| -> std::vec::Vec<Vec3> {
            (0..=n)
                .map(|i| match e {
                    0 => teapot_point(p, n, i, 0),
                    1 => teapot_point(p, n, n, i),
                    2 => teapot_point(p, n, i, n),
                    _ => teapot_point(p, n, 0, i),
                })
                .collect()
        };
        let mut shared = 0;
        for a in 0..32 {
            for ea in 0..4 {
                for b in 0..32 {
                    for eb in 0..4 {
                        if (a, ea) >= (b, eb) {
                            continue;
                        }
                        let (ia, ib) = (edge_pts_ctl(a, ea), edge_pts_ctl(b, eb));
                        let mut rb = ib;
                        rb.reverse();
                        if ia != ib && ia != rb {
                            continue;
                        }
                        if ia.iter().all(|&i| i == ia[0]) {
                            continue; // a pole, not a curve
                        }
                        shared += 1;
                        for n in [3, 4, 5, 8] {
                            let pa = edge_pts(a, ea, n);
                            let mut pb = edge_pts(b, eb, n);
                            if ia != ib {
                                pb.reverse();
                            }
                            assert_eq!(pa, pb, "patches {a}/{ea} and {b}/{eb} at level {n}");
                        }
                    }
                }
            }
        }
        // Rim and body: 4 around each of three rings and 4 between consecutive rings (20);
        // handle and spout: 2 around each of two segments and 2 between them (6 + 6); lid: 4
        // around each of two rings, 4 between them (12); bottom: 4 around and 4 to the body
        // (by equal coordinates, not indices).
        assert_eq!(shared, 52, "shared boundary curves");
    }
}
