//! Helpers shared by the unit tests.

/// xorshift64* (S. Vigna, "An experimental exploration of Marsaglia's xorshift generators,
/// scrambled", ACM TOMS 42, 2016): a fixed, dependency-free sequence for randomised tests.
pub(crate) struct XorShift64Star(u64);

impl XorShift64Star {
    /// A generator from a non-zero seed.
    pub(crate) fn new(seed: u64) -> Self {
        XorShift64Star(seed)
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        let x = &mut self.0;
        *x ^= *x >> 12;
        *x ^= *x << 25;
        *x ^= *x >> 27;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A uniform number in `[0, 1)` from the top 53 bits.
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}
