//! Colours: [`Rgba8888`] (colour-table entries and pixels) and [`Rgb565`] (display output).
//!
//! Guarantees:
//! - Every conversion and blend is pure integer arithmetic, `const fn` where possible, and never
//!   panics or overflows for any input.
//! - Channel-depth conversions round to nearest: [`Rgba8888::to_rgb565`] gives
//!   `round(c * 31 / 255)` (`round(c * 63 / 255)` for green), and [`Rgb565::to_rgba8888`] gives
//!   `round(c5 * 255 / 31)` (`round(c6 * 255 / 63)`), computed exactly (there are no ties because
//!   the divisors are odd). Expanding then reducing is the identity on every `Rgb565`. These are the
//!   same numbers `embedded-graphics` produces for its `Rgb888` <-> `Rgb565` conversions.
//! - [`over`] is Porter-Duff source-over on straight (non-premultiplied) alpha, rounded to nearest
//!   from the exact rational result (formula in its docs). An opaque source (`a = 255`) returns the
//!   source exactly, a transparent source (`a = 0`) returns the destination exactly.
//!
//! `u32` packing is `0xRRGGBBAA` (red in the most significant byte).

/// An 8-bit-per-channel colour with straight (non-premultiplied) alpha: a colour-table entry or a
/// pixel. `a = 255` is opaque.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(C, align(4))]
pub struct Rgba8888 {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
    /// Alpha (coverage / opacity), 255 = opaque.
    pub a: u8,
}

impl Rgba8888 {
    /// Opaque black.
    pub const BLACK: Rgba8888 = Rgba8888::rgb(0, 0, 0);
    /// Opaque white.
    pub const WHITE: Rgba8888 = Rgba8888::rgb(255, 255, 255);
    /// Fully transparent black.
    pub const TRANSPARENT: Rgba8888 = Rgba8888::new(0, 0, 0, 0);

    /// Builds a colour from its four channels.
    pub const fn new(r: u8, g: u8, b: u8, a: u8) -> Self {
        Rgba8888 { r, g, b, a }
    }

    /// Builds an opaque colour (`a = 255`).
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Rgba8888 { r, g, b, a: 255 }
    }

    /// Unpacks `0xRRGGBBAA`.
    pub const fn from_u32(v: u32) -> Self {
        Rgba8888 {
            r: (v >> 24) as u8,
            g: (v >> 16) as u8,
            b: (v >> 8) as u8,
            a: v as u8,
        }
    }

    /// Packs as `0xRRGGBBAA`.
    pub const fn to_u32(self) -> u32 {
        ((self.r as u32) << 24) | ((self.g as u32) << 16) | ((self.b as u32) << 8) | self.a as u32
    }

    /// The channels as `[r, g, b, a]` (the lane order of the filters).
    pub const fn to_array(self) -> [u8; 4] {
        [self.r, self.g, self.b, self.a]
    }

    /// Builds a colour from `[r, g, b, a]`.
    pub const fn from_array(c: [u8; 4]) -> Self {
        Rgba8888::new(c[0], c[1], c[2], c[3])
    }

    /// The same colour with alpha replaced.
    pub const fn with_alpha(self, a: u8) -> Self {
        Rgba8888 { a, ..self }
    }

    /// Reduces to RGB565, rounding each channel to nearest (`(c * 31 + 127) / 255`, exact; green
    /// `(c * 63 + 127) / 255`). Alpha is dropped (composite with [`over`] first if needed).
    ///
    /// Each quotient is taken as a multiply-add and a shift, `(c * 249 + 1014) >> 11` and
    /// `(c * 253 + 505) >> 10`: equal to the divisions for every 8-bit `c` (a unit test checks
    /// all 256), without the divisions' reciprocal multiplications.
    pub const fn to_rgb565(self) -> Rgb565 {
        let r = (self.r as u32 * 249 + 1014) >> 11;
        let g = (self.g as u32 * 253 + 505) >> 10;
        let b = (self.b as u32 * 249 + 1014) >> 11;
        Rgb565::new(r as u8, g as u8, b as u8)
    }
}

impl From<u32> for Rgba8888 {
    fn from(v: u32) -> Self {
        Rgba8888::from_u32(v)
    }
}

impl From<Rgba8888> for u32 {
    fn from(c: Rgba8888) -> Self {
        c.to_u32()
    }
}

impl From<Rgb565> for Rgba8888 {
    fn from(c: Rgb565) -> Self {
        c.to_rgba8888()
    }
}

impl From<Rgba8888> for Rgb565 {
    fn from(c: Rgba8888) -> Self {
        c.to_rgb565()
    }
}

/// A 16-bit display pixel, `rrrrrggg gggbbbbb` (red in the most significant bits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(transparent)]
pub struct Rgb565(pub u16);

impl Rgb565 {
    /// Black.
    pub const BLACK: Rgb565 = Rgb565(0);
    /// White.
    pub const WHITE: Rgb565 = Rgb565(0xFFFF);

    /// Builds a pixel from raw channels: `r` and `b` in 0..=31, `g` in 0..=63 (excess high bits are
    /// masked off).
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Rgb565((((r & 31) as u16) << 11) | (((g & 63) as u16) << 5) | ((b & 31) as u16))
    }

    /// The raw 16-bit value.
    pub const fn to_bits(self) -> u16 {
        self.0
    }

    /// Raw red, 0..=31.
    pub const fn r(self) -> u8 {
        (self.0 >> 11) as u8
    }

    /// Raw green, 0..=63.
    pub const fn g(self) -> u8 {
        ((self.0 >> 5) & 63) as u8
    }

    /// Raw blue, 0..=31.
    pub const fn b(self) -> u8 {
        (self.0 & 31) as u8
    }

    /// Red expanded to 8 bits, `round(r * 255 / 31)` = `(r * 255 + 15) / 31` (exact).
    pub const fn r8(self) -> u8 {
        ((self.r() as u16 * 255 + 15) / 31) as u8
    }

    /// Green expanded to 8 bits, `round(g * 255 / 63)` = `(g * 255 + 31) / 63` (exact).
    pub const fn g8(self) -> u8 {
        ((self.g() as u16 * 255 + 31) / 63) as u8
    }

    /// Blue expanded to 8 bits, `round(b * 255 / 31)` = `(b * 255 + 15) / 31` (exact).
    pub const fn b8(self) -> u8 {
        ((self.b() as u16 * 255 + 15) / 31) as u8
    }

    /// Expands to an opaque [`Rgba8888`] (channels rounded to nearest; see the module docs):
    /// [`Rgb565::r8`], [`Rgb565::g8`] and [`Rgb565::b8`], read from their tables (128 bytes)
    /// instead of computed (the ramp's colours, `crate::filter::Ramp565`, take this once a
    /// pixel).
    pub const fn to_rgba8888(self) -> Rgba8888 {
        Rgba8888::rgb(
            EXPAND5[(self.0 >> 11) as usize & 31],
            EXPAND6[(self.0 >> 5) as usize & 63],
            EXPAND5[self.0 as usize & 31],
        )
    }
}

/// `round(v * 255 / 31)` for every 5-bit `v` ([`Rgb565::r8`], [`Rgb565::b8`]).
const EXPAND5: [u8; 32] = {
    let mut t = [0u8; 32];
    let mut v = 0;
    while v < 32 {
        t[v] = Rgb565::new(v as u8, 0, 0).r8();
        v += 1;
    }
    t
};

/// `round(v * 255 / 63)` for every 6-bit `v` ([`Rgb565::g8`]).
const EXPAND6: [u8; 64] = {
    let mut t = [0u8; 64];
    let mut v = 0;
    while v < 64 {
        t[v] = Rgb565::new(0, v as u8, 0).g8();
        v += 1;
    }
    t
};

impl From<u16> for Rgb565 {
    fn from(v: u16) -> Self {
        Rgb565(v)
    }
}

impl From<Rgb565> for u16 {
    fn from(c: Rgb565) -> Self {
        c.0
    }
}

/// Porter-Duff source-over on straight (non-premultiplied) alpha: `src` drawn over `dst`.
///
/// With `A = sa * 255 + da * (255 - sa)` (the output alpha times 255, 0..=65025):
///
/// ```text
/// out.a = round(A / 255)                                   = (A + 127) / 255
/// out.c = round((sc * sa * 255 + dc * da * (255 - sa)) / A) = (num + A / 2) / A   (ties up)
/// ```
///
/// all in `u32` (the numerator is at most 255 * 65025, no overflow). Special cases, all consistent
/// with the formula: `sa = 255` returns `src` exactly; `sa = 0` returns `dst` exactly (also when
/// `dst` is transparent, where the formula is 0/0); an opaque `dst` (`da = 255`) reduces to the
/// familiar `out.c = round((sc * sa + dc * (255 - sa)) / 255)`, `out.a = 255`, which is the path taken
/// for opaque framebuffers (one constant division per channel, no general division).
pub const fn over(src: Rgba8888, dst: Rgba8888) -> Rgba8888 {
    let sa = src.a as u32;
    if sa == 255 {
        return src;
    }
    if sa == 0 {
        return dst;
    }
    let da = dst.a as u32;
    let inv = 255 - sa;
    if da == 255 {
        // Exact: round((sc*sa + dc*inv) / 255), no ties since 255 is odd.
        return Rgba8888::new(
            mix255(src.r, dst.r, sa, inv),
            mix255(src.g, dst.g, sa, inv),
            mix255(src.b, dst.b, sa, inv),
            255,
        );
    }
    // General straight-alpha case; A >= 255 here because sa >= 1 (the `max` only lets the
    // compiler see that the divisions cannot trap).
    let big_a = sa * 255 + da * inv;
    let big_a = if big_a == 0 { 1 } else { big_a };
    let ws = sa * 255;
    let wd = da * inv;
    Rgba8888::new(
        mix_general(src.r, dst.r, ws, wd, big_a),
        mix_general(src.g, dst.g, ws, wd, big_a),
        mix_general(src.b, dst.b, ws, wd, big_a),
        ((big_a + 127) / 255) as u8,
    )
}

/// `round((s * ws + d * wd) / 255)` for `ws + wd = 255` (exact, no ties).
#[cfg_attr(not(texcore_lean), inline(always))]
const fn mix255(s: u8, d: u8, ws: u32, wd: u32) -> u8 {
    ((s as u32 * ws + d as u32 * wd + 127) / 255) as u8
}

/// `round((s * ws + d * wd) / a)`, ties up, for `a = ws + wd` in 255..=65025; the result is a
/// weighted mean of `s` and `d`, so it fits a `u8`.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn mix_general(s: u8, d: u8, ws: u32, wd: u32, a: u32) -> u8 {
    ((s as u32 * ws + d as u32 * wd + a / 2) / a) as u8
}

#[cfg(feature = "embedded-graphics")]
mod eg {
    use super::{Rgb565, Rgba8888};
    use embedded_graphics_core::pixelcolor::{self as pc, RgbColor};

    impl From<Rgb565> for pc::Rgb565 {
        fn from(c: Rgb565) -> Self {
            pc::Rgb565::new(c.r(), c.g(), c.b())
        }
    }

    impl From<pc::Rgb565> for Rgb565 {
        fn from(c: pc::Rgb565) -> Self {
            Rgb565::new(c.r(), c.g(), c.b())
        }
    }

    impl From<Rgb565> for pc::Rgb888 {
        fn from(c: Rgb565) -> Self {
            pc::Rgb888::new(c.r8(), c.g8(), c.b8())
        }
    }

    /// Drops alpha.
    impl From<Rgba8888> for pc::Rgb888 {
        fn from(c: Rgba8888) -> Self {
            pc::Rgb888::new(c.r, c.g, c.b)
        }
    }

    /// Drops alpha and rounds to nearest ([`Rgba8888::to_rgb565`]).
    impl From<Rgba8888> for pc::Rgb565 {
        fn from(c: Rgba8888) -> Self {
            c.to_rgb565().into()
        }
    }

    /// Opaque.
    impl From<pc::Rgb888> for Rgba8888 {
        fn from(c: pc::Rgb888) -> Self {
            Rgba8888::rgb(c.r(), c.g(), c.b())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Round-half-up of `num / den` by exact integer arithmetic (u64).
    fn round_div(num: u64, den: u64) -> u64 {
        (2 * num + den) / (2 * den)
    }

    #[test]
    fn the_tables_expand_as_the_formulas() {
        for v in 0..=u16::MAX {
            let c = Rgb565(v);
            let want = |x: u64, max: u64| round_div(x * 255, max) as u8;
            let e = c.to_rgba8888();
            assert_eq!(e, Rgba8888::rgb(c.r8(), c.g8(), c.b8()), "{v:#06x}");
            assert_eq!(
                e.to_array()[..3],
                [
                    want(u64::from(c.r()), 31),
                    want(u64::from(c.g()), 63),
                    want(u64::from(c.b()), 31)
                ]
            );
        }
    }

    #[test]
    fn u32_round_trip() {
        let c = Rgba8888::new(0x12, 0x34, 0x56, 0x78);
        assert_eq!(c.to_u32(), 0x1234_5678);
        assert_eq!(Rgba8888::from_u32(0x1234_5678), c);
        for v in [0u32, 1, 0xFF, 0xFF00_0000, 0xDEAD_BEEF, u32::MAX] {
            assert_eq!(Rgba8888::from_u32(v).to_u32(), v);
            assert_eq!(u32::from(Rgba8888::from(v)), v);
        }
        assert_eq!(Rgba8888::from_array(c.to_array()), c);
        assert_eq!(c.to_array(), [0x12, 0x34, 0x56, 0x78]);
    }

    #[test]
    fn rgb565_reduction_rounds_to_nearest() {
        for c in 0..=255u32 {
            // The multiply-add-shift forms are the divisions.
            assert_eq!((c * 249 + 1014) >> 11, (c * 31 + 127) / 255, "{c}");
            assert_eq!((c * 253 + 505) >> 10, (c * 63 + 127) / 255, "{c}");
            let p = Rgba8888::rgb(c as u8, c as u8, c as u8).to_rgb565();
            assert_eq!(p.r() as u64, round_div(c as u64 * 31, 255), "r {c}");
            assert_eq!(p.g() as u64, round_div(c as u64 * 63, 255), "g {c}");
            assert_eq!(p.b() as u64, round_div(c as u64 * 31, 255), "b {c}");
            // It really is the nearest level.
            for q in 0..=31u32 {
                let d_best = (p.r() as i64 * 255 - c as i64 * 31).abs();
                assert!(d_best <= (q as i64 * 255 - c as i64 * 31).abs());
            }
        }
        assert_eq!(Rgba8888::WHITE.to_rgb565(), Rgb565::WHITE);
        assert_eq!(Rgba8888::BLACK.to_rgb565(), Rgb565::BLACK);
        assert_eq!(Rgba8888::rgb(255, 0, 0).to_rgb565(), Rgb565(0xF800));
        assert_eq!(Rgba8888::rgb(0, 255, 0).to_rgb565(), Rgb565(0x07E0));
        assert_eq!(Rgba8888::rgb(0, 0, 255).to_rgb565(), Rgb565(0x001F));
    }

    #[test]
    fn rgb565_exhaustive_expand_and_round_trip() {
        for v in 0..=u16::MAX {
            let p = Rgb565(v);
            assert_eq!(Rgb565::new(p.r(), p.g(), p.b()), p);
            let e = p.to_rgba8888();
            assert_eq!(e.r as u64, round_div(p.r() as u64 * 255, 31));
            assert_eq!(e.g as u64, round_div(p.g() as u64 * 255, 63));
            assert_eq!(e.b as u64, round_div(p.b() as u64 * 255, 31));
            assert_eq!(e.a, 255);
            assert_eq!(e.to_rgb565(), p, "{v:#06x}");
            assert_eq!(Rgb565::from(Rgba8888::from(p)), p);
        }
        // Excess bits are masked.
        assert_eq!(Rgb565::new(255, 255, 255), Rgb565::WHITE);
    }

    /// Independent reference of `over`: exact rationals in u64, round half up.
    fn over_ref(s: Rgba8888, d: Rgba8888) -> Rgba8888 {
        let (sa, da) = (s.a as u64, d.a as u64);
        let a255 = sa * 255 + da * (255 - sa);
        if a255 == 0 {
            return d;
        }
        let ch = |sc: u8, dc: u8| {
            round_div(sc as u64 * sa * 255 + dc as u64 * da * (255 - sa), a255) as u8
        };
        Rgba8888::new(
            ch(s.r, d.r),
            ch(s.g, d.g),
            ch(s.b, d.b),
            round_div(a255, 255) as u8,
        )
    }

    #[test]
    fn over_opaque_destination_exhaustive() {
        for sa in 0..=255u8 {
            for sc in 0..=255u8 {
                for dc in 0..=255u8 {
                    let s = Rgba8888::new(sc, 255 - sc, sc / 2, sa);
                    let d = Rgba8888::new(dc, dc / 3, 255 - dc, 255);
                    let o = over(s, d);
                    assert_eq!(o, over_ref(s, d), "{s:?} over {d:?}");
                }
            }
        }
    }

    #[test]
    fn over_all_alphas() {
        let levels = [0u8, 1, 2, 17, 64, 127, 128, 129, 200, 254, 255];
        for sa in 0..=255u8 {
            for da in 0..=255u8 {
                for &sc in &levels {
                    for &dc in &levels {
                        let s = Rgba8888::new(sc, dc, 255 - sc, sa);
                        let d = Rgba8888::new(dc, sc, 255 - dc, da);
                        let o = over(s, d);
                        if sa == 255 {
                            assert_eq!(o, s);
                        } else if sa == 0 {
                            assert_eq!(o, d);
                        } else {
                            assert_eq!(o, over_ref(s, d), "{s:?} over {d:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn over_identities() {
        let d = Rgba8888::new(10, 20, 30, 0);
        let s = Rgba8888::new(200, 100, 50, 77);
        // Over a transparent destination the source comes through unchanged.
        assert_eq!(over(s, d), s);
        // Over itself an opaque colour is unchanged.
        assert_eq!(over(Rgba8888::WHITE, Rgba8888::BLACK), Rgba8888::WHITE);
        assert_eq!(over(Rgba8888::TRANSPARENT, s), s);
        // Half-transparent white over black gives mid grey, rounded to nearest.
        assert_eq!(
            over(Rgba8888::new(255, 255, 255, 128), Rgba8888::BLACK),
            Rgba8888::rgb(128, 128, 128)
        );
    }

    #[cfg(feature = "embedded-graphics")]
    #[test]
    fn embedded_graphics_agrees() {
        use embedded_graphics_core::pixelcolor as pc;
        use embedded_graphics_core::pixelcolor::IntoStorage;
        for v in 0..=u16::MAX {
            let p = Rgb565(v);
            let e: pc::Rgb565 = p.into();
            assert_eq!(e.into_storage(), v);
            assert_eq!(Rgb565::from(e), p);
            let e8: pc::Rgb888 = p.into();
            assert_eq!(e8, pc::Rgb888::from(e));
        }
        for c in 0..=255u8 {
            let x = Rgba8888::rgb(c, 255 - c, c ^ 0x5A);
            let ours: pc::Rgb565 = x.into();
            let theirs: pc::Rgb565 = pc::Rgb888::from(x).into();
            assert_eq!(ours, theirs);
        }
    }
}
