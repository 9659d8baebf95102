//! Cubic stepping: the exact polynomial of a trilinear term inside one cell (symbolic
//! expansion of the lerp levels) and its forward-difference states: exact in 64 bits (`Cubic`,
//! wrapping: the true values fit `i64`), their top 32 bits (`Cubic32`, the approximate
//! [`EvalMode::Fd32`]) and the cubic Hermite segments of the approximate
//! [`EvalMode::Reanchored`] (`hermite_setup`).

use super::*;

/// A trilinear term inside one cell as exact polynomials in the local pixel index `j` (pixel 0
/// is where the set-up was made): the value `P(j) = g0 + g1 j + g2 j^2 + g3 j^3` and the
/// directional derivative across the span `Gy(j) = h0 + h1 j + h2 j^2`. The derivative along the
/// span is `P'(j)`. All coefficients are exact integers taken modulo 2^64 (wrapping), which is all
/// forward differencing needs: every value derived from them is an integer polynomial of the
/// coefficients, and the true values fit in i64.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct CubicPoly {
    pub(super) g: [i64; 4],
    pub(super) h: [i64; 3],
}

#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn wmul(a: i64, b: i64) -> i64 {
    a.wrapping_mul(b)
}

#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn wadd(a: i64, b: i64) -> i64 {
    a.wrapping_add(b)
}

#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn wsub(a: i64, b: i64) -> i64 {
    a.wrapping_sub(b)
}

/// The exact polynomials of a trilinear term (corner values `v`, fractions `frac` at pixel 0,
/// lattice steps `du` along and `dy` across the span), by symbolic expansion of the three lerp
/// levels of `docs/model.md` 4.2 (`lerp(p, q, w) = p 2^16 + (q - p) w` with `w = f + j d`):
/// x-lerps are linear in `j`, y-lerps quadratic, the z-lerp cubic. The derivative across the span
/// is carried along as the dual part of every lerp (`d lerp = dp 2^16 + (dq - dp) w + (q - p) e`).
/// This is the same integer polynomial as [`crate::noise::value::interpolate`] and
/// [`crate::noise::value::directional`] at `w = f + j d`, so the forward differences are
/// bit-identical to direct evaluation. 22 multiplications (41 with the derivative across), the
/// x level as exact 32 x 32 -> 64-bit products.
#[inline]
pub(super) fn cubic_poly(
    v: &[i32; 8],
    frac: [u32; 3],
    du: [i32; 3],
    dy: [i32; 3],
    grads: bool,
) -> CubicPoly {
    let grads = GRADIENTS && grads;
    // Fractions are below 2^16: zero-extended, their products with 64-bit values need one
    // multiplication less on a 32-bit core.
    let f = [i64::from(frac[0]), i64::from(frac[1]), i64::from(frac[2])];
    // x level: e(j) = e0 + e1 j, derivative across de (constant). v' fits 26 bits (model 4.4),
    // so dv fits i32 and every product here is an exact 32 x 32 -> 64-bit one.
    let xl = |a: usize| -> (i64, i64, i64) {
        let v0 = v[a];
        let dv = i64::from(v[a + 1].wrapping_sub(v0));
        (
            wadd(i64::from(v0) << 16, dv * f[0]),
            wmul(dv, i64::from(du[0])),
            wmul(dv, i64::from(dy[0])),
        )
    };
    // y level: F(j) = F0 + F1 j + F2 j^2, dF(j) = dF0 + dF1 j.
    let (fy, sy, ey) = (f[1], i64::from(du[1]), i64::from(dy[1]));
    let yl = |a: (i64, i64, i64), b: (i64, i64, i64)| -> ([i64; 3], [i64; 2]) {
        let d0 = wsub(b.0, a.0);
        let d1 = wsub(b.1, a.1);
        let ff = [
            wadd(a.0 << 16, wmul(d0, fy)),
            wadd(wadd(a.1 << 16, wmul(d1, fy)), wmul(d0, sy)),
            wmul(d1, sy),
        ];
        if !grads {
            return (ff, [0, 0]);
        }
        let dd = wsub(b.2, a.2);
        (
            ff,
            [
                wadd(wadd(a.2 << 16, wmul(dd, fy)), wmul(d0, ey)),
                wadd(wmul(dd, sy), wmul(d1, ey)),
            ],
        )
    };
    let (fa, dfa) = yl(xl(0), xl(2));
    let (fb, dfb) = yl(xl(4), xl(6));
    // z level: P(j) cubic, Gy(j) quadratic.
    let (fz, sz, ez) = (f[2], i64::from(du[2]), i64::from(dy[2]));
    let e = [wsub(fb[0], fa[0]), wsub(fb[1], fa[1]), wsub(fb[2], fa[2])];
    let g = [
        wadd(fa[0] << 16, wmul(e[0], fz)),
        wadd(wadd(fa[1] << 16, wmul(e[1], fz)), wmul(e[0], sz)),
        wadd(wadd(fa[2] << 16, wmul(e[2], fz)), wmul(e[1], sz)),
        wmul(e[2], sz),
    ];
    if !grads {
        return CubicPoly { g, h: [0; 3] };
    }
    let k = [wsub(dfb[0], dfa[0]), wsub(dfb[1], dfa[1])];
    let h = [
        wadd(wadd(dfa[0] << 16, wmul(k[0], fz)), wmul(e[0], ez)),
        wadd(
            wadd(wadd(dfa[1] << 16, wmul(k[1], fz)), wmul(k[0], sz)),
            wmul(e[1], ez),
        ),
        wadd(wmul(k[1], sz), wmul(e[2], ez)),
    ];
    CubicPoly { g, h }
}

/// Forward-difference state of `c` at local pixel 0 (gradient parts zero unless `grads`).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn fd_start(c: &CubicPoly, grads: bool) -> Cubic {
    let grads = GRADIENTS && grads;
    let [g0, g1, g2, g3] = c.g;
    let [h0, h1, h2] = c.h;
    let d3 = wmul(g3, 6);
    let p = [g0, wadd(wadd(g1, g2), g3), wadd(wmul(g2, 2), d3), d3];
    if !grads {
        return Cubic {
            p,
            ..Cubic::default()
        };
    }
    Cubic {
        p,
        gx: [g1, wadd(wmul(g2, 2), wmul(g3, 3)), d3],
        gy: [h0, wadd(h1, h2), wmul(h2, 2)],
    }
}

/// Forward-difference state of `c` at local pixel `l <= 65535` (12 multiplications; gradient
/// parts zero unless `grads`).
#[inline]
pub(super) fn fd_at(c: &CubicPoly, l: u32, grads: bool) -> Cubic {
    let grads = GRADIENTS && grads;
    let [g0, g1, g2, g3] = c.g;
    let [h0, h1, h2] = c.h;
    let l = i64::from(l.min(1 << 16));
    // A linear cell polynomial (single-axis terms, `axis`): the same values, two products.
    if g2 == 0 && g3 == 0 && h2 == 0 {
        let p = [wadd(g0, wmul(g1, l)), g1, 0, 0];
        return Cubic {
            p,
            gx: if grads { [g1, 0, 0] } else { [0; 3] },
            gy: if grads {
                [wadd(h0, wmul(h1, l)), h1, 0]
            } else {
                [0; 3]
            },
        };
    }
    let l2 = l * l; // l <= 2^16: exact
    let t = 2 * l + 1;
    let d3 = wmul(g3, 6);
    let p = [
        wadd(g0, wmul(l, wadd(g1, wmul(l, wadd(g2, wmul(l, g3)))))),
        wadd(wadd(g1, wmul(g2, t)), wmul(g3, 3 * l2 + 3 * l + 1)),
        wadd(wmul(g2, 2), wmul(g3, 6 * l + 6)),
        d3,
    ];
    if !grads {
        return Cubic {
            p,
            ..Cubic::default()
        };
    }
    Cubic {
        p,
        gx: [
            wadd(g1, wmul(l, wadd(wmul(g2, 2), wmul(wmul(g3, 3), l)))),
            wadd(wmul(g2, 2), wmul(wmul(g3, 3), t)),
            d3,
        ],
        gy: [
            wadd(h0, wmul(l, wadd(h1, wmul(l, h2)))),
            wadd(h1, wmul(h2, t)),
            wmul(h2, 2),
        ],
    }
}

impl Cubic {
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn add(&mut self, o: &Cubic) {
        for (a, b) in self.p.iter_mut().zip(o.p) {
            *a = a.wrapping_add(b);
        }
        // Without the feature the gradient parts stay zero.
        if !GRADIENTS {
            return;
        }
        for (a, b) in self.gx.iter_mut().zip(o.gx) {
            *a = a.wrapping_add(b);
        }
        for (a, b) in self.gy.iter_mut().zip(o.gy) {
            *a = a.wrapping_add(b);
        }
    }

    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn sub(&mut self, o: &Cubic) {
        for (a, b) in self.p.iter_mut().zip(o.p) {
            *a = a.wrapping_sub(b);
        }
        // Without the feature the gradient parts stay zero.
        if !GRADIENTS {
            return;
        }
        for (a, b) in self.gx.iter_mut().zip(o.gx) {
            *a = a.wrapping_sub(b);
        }
        for (a, b) in self.gy.iter_mut().zip(o.gy) {
            *a = a.wrapping_sub(b);
        }
    }
}

/// Forward-difference start values of a trilinear term in a new cell (see [`cubic_poly`]).
#[cfg(any(feature = "turbulence-fd", feature = "fd32"))]
#[inline]
pub(super) fn cubic_setup(v: &[i32; 8], frac: [u32; 3], ts: &TermSetup, grads: bool) -> Cubic {
    fd_start(&cubic_poly(v, frac, ts.du, ts.dy, grads), grads)
}

/// Forward-difference state of a cubic term inside one cell (exact, 64-bit).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Cubic {
    pub(super) p: [i64; 4],
    pub(super) gx: [i64; 3],
    pub(super) gy: [i64; 3],
}

impl Cubic {
    /// The zero state.
    #[cfg_attr(not(texcore_fd_state), allow(dead_code))]
    pub(super) const ZERO: Cubic = Cubic {
        p: [0; 4],
        gx: [0; 3],
        gy: [0; 3],
    };
}

/// Forward-difference state with 32-bit accumulators (the exact state's top 32 bits at the anchor).
#[cfg(feature = "fd32")]
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Cubic32 {
    pub(super) p: [i32; 4],
    pub(super) gx: [i32; 3],
    pub(super) gy: [i32; 3],
}

#[cfg(feature = "fd32")]
impl Cubic32 {
    /// The zero state.
    pub(super) const ZERO: Cubic32 = Cubic32 {
        p: [0; 4],
        gx: [0; 3],
        gy: [0; 3],
    };
}

/// The top 32 bits (floor) of an exact forward-difference state.
#[cfg(feature = "fd32")]
pub(super) fn narrow(c: &Cubic) -> Cubic32 {
    let h = |x: i64| (x >> 32) as i32;
    Cubic32 {
        p: [h(c.p[0]), h(c.p[1]), h(c.p[2]), h(c.p[3])],
        gx: [h(c.gx[0]), h(c.gx[1]), h(c.gx[2])],
        gy: [h(c.gy[0]), h(c.gy[1]), h(c.gy[2])],
    }
}

/// Division of an i128 by a positive divisor, rounded to nearest (ties away from zero), saturated.
#[cfg(texcore_hermite)]
pub(super) fn div_round(x: i128, d: i128) -> i64 {
    // `(x + d/2) / d` for x >= 0 and `(x - d/2) / d` (truncating) for x < 0, i.e. the rounded
    // magnitude with x's sign; the division is the crate's shared one (code size).
    let (q, _) = crate::wide::div_rem_euclid_i128(x.unsigned_abs() as i128 + d / 2, d);
    sat_i64(if x < 0 { q.wrapping_neg() } else { q })
}

/// Cubic Hermite segment over pixels `0..l` through the exact values and derivatives at pixels
/// `0` and `l - 1` (both inside the current cell), as a forward-difference state: the value is
/// cubic, the x-gradient its derivative, the y-gradient linear between the anchors (`gy[2] = 0`).
#[cfg(texcore_hermite)]
#[allow(clippy::too_many_arguments)]
pub(super) fn hermite_setup(
    term: &NoiseTerm,
    data: &CellData,
    u: [i32; 3],
    ts: &TermSetup,
    l: u32,
    amp: i32,
    fv: u32,
    grads: bool,
) -> Cubic {
    let (_, f0) = split(u);
    let b = &term.basis;
    let p0 = b.sample(data, f0, amp, fv);
    let g0 = b.derivative(data, f0, ts.du, amp, fv);
    let y0 = if grads {
        b.derivative(data, f0, ts.dy, amp, fv)
    } else {
        0
    };
    if l <= 1 {
        return Cubic {
            p: [p0, 0, 0, 0],
            gx: [g0, 0, 0],
            gy: [y0, 0, 0],
        };
    }
    let mm = l - 1;
    let (_, fm) = split([
        u[0].wrapping_add(ts.du[0].wrapping_mul(mm as i32)),
        u[1].wrapping_add(ts.du[1].wrapping_mul(mm as i32)),
        u[2].wrapping_add(ts.du[2].wrapping_mul(mm as i32)),
    ]);
    let pm = b.sample(data, fm, amp, fv);
    let gm = b.derivative(data, fm, ts.du, amp, fv);
    let ym = if grads {
        b.derivative(data, fm, ts.dy, amp, fv)
    } else {
        0
    };
    let m = i128::from(mm);
    let (p0w, pmw, g0w, gmw) = (
        i128::from(p0),
        i128::from(pm),
        i128::from(g0),
        i128::from(gm),
    );
    let c2 = div_round(3 * (pmw - p0w) - (2 * g0w + gmw) * m, m * m);
    let c3 = div_round(2 * (p0w - pmw) + (g0w + gmw) * m, m * m * m);
    let c1 = g0;
    Cubic {
        p: [
            p0,
            c1.wrapping_add(c2).wrapping_add(c3),
            c2.wrapping_mul(2).wrapping_add(c3.wrapping_mul(6)),
            c3.wrapping_mul(6),
        ],
        gx: [
            g0,
            c2.wrapping_mul(2).wrapping_add(c3.wrapping_mul(3)),
            c3.wrapping_mul(6),
        ],
        gy: [y0, div_round(i128::from(ym) - i128::from(y0), m), 0],
    }
}
