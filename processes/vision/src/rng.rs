//! A tiny deterministic pseudo-random generator (SplitMix64-seeded xorshift64*).
//!
//! RANSAC and the synthetic scene generators must be reproducible run to run, so every random
//! choice in this crate goes through [`XorShiftRng`] with an explicit seed. It is not
//! cryptographic and needs no dependency.
//!
//! ```
//! use hopnav_vision::rng::XorShiftRng;
//! let mut a = XorShiftRng::new(7);
//! let mut b = XorShiftRng::new(7);
//! assert_eq!(a.next_u64(), b.next_u64());
//! assert!(a.below(10) < 10);
//! ```

/// Deterministic xorshift64* generator.
#[derive(Debug, Clone)]
pub struct XorShiftRng {
    state: u64,
}

impl XorShiftRng {
    /// Creates a generator from any seed (zero included); the seed is scrambled with SplitMix64.
    pub fn new(seed: u64) -> Self {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // xorshift must never hold zero.
        Self {
            state: if z == 0 { 0x2545_F491_4F6C_DD1D } else { z },
        }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform integer in `0..bound`; returns 0 when `bound` is 0.
    pub fn below(&mut self, bound: usize) -> usize {
        if bound == 0 {
            return 0;
        }
        // Multiply-shift: bias is < bound / 2^64, irrelevant here.
        ((u128::from(self.next_u64()) * bound as u128) >> 64) as usize
    }

    /// Uniform `f64` in `[0, 1)`.
    pub fn unit_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform `f64` in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit_f64()
    }

    /// A vector whose components are uniform in `[lo, hi)`, drawn in the order x, y, z.
    pub fn uniform_vector3(&mut self, lo: f64, hi: f64) -> nalgebra::Vector3<f64> {
        let x = self.uniform(lo, hi);
        let y = self.uniform(lo, hi);
        let z = self.uniform(lo, hi);
        nalgebra::Vector3::new(x, y, z)
    }

    /// Standard normal sample (Box–Muller).
    pub fn gaussian(&mut self) -> f64 {
        let u1 = self.unit_f64().max(f64::MIN_POSITIVE);
        let u2 = self.unit_f64();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// Fills `out` with distinct indices drawn uniformly from `0..n`.
    ///
    /// Returns `false` (leaving `out` unspecified) when `out.len() > n`. Rejection sampling: meant
    /// for the small sample sizes (≤ 8) of minimal solvers.
    pub fn sample_distinct(&mut self, n: usize, out: &mut [usize]) -> bool {
        if out.len() > n {
            return false;
        }
        let mut filled = 0;
        while filled < out.len() {
            let candidate = self.below(n);
            if !out[..filled].contains(&candidate) {
                out[filled] = candidate;
                filled += 1;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_and_in_range() {
        let mut a = XorShiftRng::new(0);
        let mut b = XorShiftRng::new(0);
        for _ in 0..1000 {
            let x = a.unit_f64();
            assert_eq!(x.to_bits(), b.unit_f64().to_bits());
            assert!((0.0..1.0).contains(&x));
        }
        let mut idx = [0usize; 5];
        assert!(a.sample_distinct(5, &mut idx));
        let mut sorted = idx;
        sorted.sort_unstable();
        assert_eq!(sorted, [0, 1, 2, 3, 4]);
        assert!(!a.sample_distinct(3, &mut idx));
    }
}
