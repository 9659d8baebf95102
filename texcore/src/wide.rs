//! Wide-integer helpers shared by the set-up code (triangle set-up, Hermite segments).
//!
//! 32-bit targets have no i128 division instruction or library routine: the compiler expands
//! every i128 division site inline (about 1 KB of code each on the Cortex-M4F). The set-up code
//! divides in i128 in several places, none of them per pixel, so they share the one out-of-line
//! division here.

/// `(n.div_euclid(d), n.rem_euclid(d))` with a single division; `(0, 0)` where those would panic
/// (`d == 0`, or `i128::MIN / -1`), which no caller reaches.
#[inline(never)]
pub(crate) fn div_rem_euclid_i128(n: i128, d: i128) -> (i128, i128) {
    let Some(q) = n.checked_div(d) else {
        return (0, 0);
    };
    let r = n.wrapping_sub(q.wrapping_mul(d));
    if r < 0 {
        if d > 0 {
            (q.wrapping_sub(1), r.wrapping_add(d))
        } else {
            (q.wrapping_add(1), r.wrapping_sub(d))
        }
    } else {
        (q, r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_div_euclid_and_rem_euclid() {
        let vals: [i128; 14] = [
            0,
            1,
            -1,
            2,
            -2,
            7,
            -7,
            15,
            -16,
            3375,
            i128::from(i64::MAX) * 5 + 3,
            -(i128::from(i64::MAX) * 7) - 11,
            i128::MAX,
            i128::MIN + 1,
        ];
        for &n in &vals {
            for &d in &vals {
                if d == 0 {
                    assert_eq!(div_rem_euclid_i128(n, d), (0, 0));
                    continue;
                }
                assert_eq!(
                    div_rem_euclid_i128(n, d),
                    (n.div_euclid(d), n.rem_euclid(d)),
                    "{n} / {d}"
                );
            }
        }
        assert_eq!(div_rem_euclid_i128(i128::MIN, -1), (0, 0));
        assert_eq!(
            div_rem_euclid_i128(i128::MIN, 3),
            (i128::MIN.div_euclid(3), i128::MIN.rem_euclid(3))
        );
    }
}
