//! The quadric `q(s) = [s t r 1] Q [s t r 1]^T` in f64 (`docs/model.md` section 5).
//!
//! Coefficients `[A, B, C, D, E, F, G, H, I, J]`:
//! `q = A s^2 + 2B st + 2C sr + 2D s + E t^2 + 2F tr + 2G t + H r^2 + 2I r + J`, i.e. the symmetric
//!
//! ```text
//!     | A B C D |
//! Q = | B E F G |
//!     | C F H I |
//!     | D G I J |
//! ```
//!
//! with gradient `dq/ds = 2 Q [s t r 1]^T` (first three rows).

/// The symmetric 4x4 matrix `Q` of the ten coefficients `A..J`.
pub fn matrix(c: &[f64; 10]) -> [[f64; 4]; 4] {
    let [a, b, cc, d, e, f, g, h, i, j] = *c;
    [[a, b, cc, d], [b, e, f, g], [cc, f, h, i], [d, g, i, j]]
}

/// `q(s)`, evaluated as the expanded polynomial of the contract.
pub fn value(c: &[f64; 10], p: [f64; 3]) -> f64 {
    let [a, b, cc, d, e, f, g, h, i, j] = *c;
    let [s, t, r] = p;
    a * s * s
        + 2.0 * b * s * t
        + 2.0 * cc * s * r
        + 2.0 * d * s
        + e * t * t
        + 2.0 * f * t * r
        + 2.0 * g * t
        + h * r * r
        + 2.0 * i * r
        + j
}

/// `dq/ds = 2 Q [s t r 1]^T` (the first three rows).
pub fn gradient(c: &[f64; 10], p: [f64; 3]) -> [f64; 3] {
    let q = matrix(c);
    let v = [p[0], p[1], p[2], 1.0];
    let mut g = [0.0; 3];
    for (row, gi) in q.iter().zip(g.iter_mut()) {
        *gi = 2.0 * (row[0] * v[0] + row[1] * v[1] + row[2] * v[2] + row[3] * v[3]);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn known_quadrics() {
        // Zone plate 50 s^2 + 50 t^2.
        let zone = [50.0, 0.0, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(value(&zone, [0.5, 0.25, 9.0]), 50.0 * 0.25 + 50.0 * 0.0625);
        assert_eq!(gradient(&zone, [0.5, 0.25, 9.0]), [50.0, 25.0, 0.0]);
        // The plane f = r is I = 1/2.
        let plane = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0];
        assert_eq!(value(&plane, [3.0, 4.0, 0.75]), 0.75);
        assert_eq!(gradient(&plane, [3.0, 4.0, 0.75]), [0.0, 0.0, 1.0]);
        // J is the constant; B couples s and t.
        let mixed = [0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -2.0];
        assert_eq!(value(&mixed, [2.0, 3.0, 1.0]), 2.0 * 1.5 * 6.0 - 2.0);
        assert_eq!(gradient(&mixed, [2.0, 3.0, 1.0]), [9.0, 6.0, 0.0]);
    }

    proptest! {
        #[test]
        fn value_is_the_quadratic_form(
            c in prop::array::uniform10(-100.0f64..100.0),
            p in prop::array::uniform3(-50.0f64..50.0),
        ) {
            let q = matrix(&c);
            let v = [p[0], p[1], p[2], 1.0];
            let mut form = 0.0;
            for i in 0..4 {
                for j in 0..4 {
                    form += v[i] * q[i][j] * v[j];
                }
            }
            let x = value(&c, p);
            prop_assert!((x - form).abs() <= 1e-9 * (1.0 + form.abs()), "{} vs {}", x, form);
        }

        #[test]
        fn gradient_matches_finite_differences(
            c in prop::array::uniform10(-100.0f64..100.0),
            p in prop::array::uniform3(-50.0f64..50.0),
        ) {
            let g = gradient(&c, p);
            let h = 1e-3; // exact for a quadratic up to rounding
            for i in 0..3 {
                let mut a = p;
                let mut b = p;
                a[i] += h;
                b[i] -= h;
                let fd = (value(&c, a) - value(&c, b)) / (2.0 * h);
                prop_assert!((fd - g[i]).abs() <= 1e-6 * (1.0 + g[i].abs()), "{} {} {}", i, fd, g[i]);
            }
        }
    }
}
