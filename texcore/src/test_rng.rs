//! Repeatable pseudo-random cases for the unit tests: Marsaglia's xorshift generators (the
//! 64-bit one with shifts 13, 7, 17 and the 32-bit one with 13, 17, 5), the one place every
//! test module draws its random cases from. A seed gives the same sequence on every host.

/// The 64-bit xorshift generator (shifts 13, 7, 17); the seed must not be zero.
pub(crate) struct XorShift64(u64);

impl XorShift64 {
    /// The generator from `seed` (non-zero).
    pub(crate) const fn new(seed: u64) -> XorShift64 {
        XorShift64(seed)
    }

    /// The next state: every non-zero bit pattern, once a period.
    pub(crate) fn next_u64(&mut self) -> u64 {
        xorshift64(&mut self.0)
    }

    /// The next state modulo `m` (non-zero).
    pub(crate) fn below(&mut self, m: u64) -> u64 {
        self.next_u64() % m
    }

    /// The next state shifted right by its own low six bits: magnitudes spread over every
    /// bit length, not only the largest.
    pub(crate) fn spread(&mut self) -> u64 {
        let x = self.next_u64();
        x >> (x % 64)
    }
}

/// One step of [`XorShift64`] on a state kept by the caller: the next state.
pub(crate) fn xorshift64(x: &mut u64) -> u64 {
    *x ^= *x << 13;
    *x ^= *x >> 7;
    *x ^= *x << 17;
    *x
}

/// One step of Knuth's 64-bit linear congruential generator (MMIX's multiplier and
/// increment) on a state kept by the caller: the next state (its high bits are the good ones).
pub(crate) fn lcg64(state: &mut u64) -> u64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    *state
}

/// A colour table of `N` entries from [`lcg64`]'s states from `seed` (each entry the high
/// word of a state): the filter tests' arbitrary tables.
#[cfg(any(feature = "csat", feature = "mip"))]
pub(crate) fn lcg_table<const N: usize>(seed: u64) -> crate::table::ColorTable<N> {
    let mut s = seed;
    let e =
        core::array::from_fn(|_| crate::color::Rgba8888::from_u32((lcg64(&mut s) >> 32) as u32));
    match crate::table::ColorTable::from_entries(e) {
        Ok(t) => t,
        Err(_) => unreachable!("every table size the tests take is valid"),
    }
}

/// The 32-bit xorshift generator (shifts 13, 17, 5); the seed must not be zero.
pub(crate) struct XorShift32(u32);

impl XorShift32 {
    /// The generator from `seed` (non-zero).
    pub(crate) const fn new(seed: u32) -> XorShift32 {
        XorShift32(seed)
    }

    /// The next state: every non-zero bit pattern, once a period.
    pub(crate) fn next_u32(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }

    /// The next state modulo `m` (non-zero).
    pub(crate) fn below(&mut self, m: u32) -> u32 {
        self.next_u32() % m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generators are the published xorshift recurrences (the first states from seed 1,
    /// worked by hand), never reach zero, and `below` and `spread` are their stated functions
    /// of the next state.
    #[test]
    fn sequences_are_the_xorshift_recurrences() {
        assert_eq!(XorShift64::new(1).next_u64(), 1_082_269_761);
        assert_eq!(XorShift32::new(1).next_u32(), 270_369);
        let (mut a, mut a2) = (XorShift64::new(7), XorShift64::new(7));
        let (mut b, mut b2) = (XorShift32::new(7), XorShift32::new(7));
        for _ in 0..10_000 {
            let x = a2.next_u64();
            assert_eq!(a.spread(), x >> (x % 64));
            let x = a2.next_u64();
            assert_eq!(a.below(10), x % 10);
            let y = b2.next_u32();
            assert_eq!(b.below(7), y % 7);
            assert!(x != 0 && y != 0);
        }
    }
}
