//! [`Rng`]: random states, inputs and parameters for checks at many points, the same on
//! every run and every platform.

/// A small deterministic generator (xorshift64*), uniform in [lo, hi). The seed must not be
/// zero.
pub struct Rng(pub u64);

impl Rng {
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let u = (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}
