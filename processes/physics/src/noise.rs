//! Seeded, deterministic noise: xoshiro256** seeded through SplitMix64, Gaussian samples by
//! Box–Muller. No global state and no OS entropy, so the same seed gives the same samples.
//!
//! ```
//! use hopnav_physics::noise::NoiseRng;
//! let mut a = NoiseRng::new(7, 1);
//! let mut b = NoiseRng::new(7, 1);
//! assert_eq!(a.gaussian().to_bits(), b.gaussian().to_bits());
//! ```

// The seeding and the step are the world's generator's (hopnav_world::rng); what this one
// adds is the cached second Box–Muller sample and a state that can be saved and restored.
use hopnav_world::rng::{unit_f64, xoshiro_next, xoshiro_words};

/// A xoshiro256** generator with a cached second Box–Muller sample.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseRng {
    s: [u64; 4],
    spare: Option<f64>,
}

impl NoiseRng {
    /// A generator for `seed` and an independent `stream` number (one per sensor).
    pub fn new(seed: u64, stream: u64) -> Self {
        Self {
            s: xoshiro_words(seed, stream),
            spare: None,
        }
    }

    /// The generator's state: its words and the cached Box–Muller sample.
    pub fn state(&self) -> ([u64; 4], Option<f64>) {
        (self.s, self.spare)
    }

    /// A generator continuing from a [`state`](Self::state); `None` for all-zero words (a
    /// xoshiro generator never reaches them) or a non-finite cached sample.
    pub fn from_state(words: [u64; 4], spare: Option<f64>) -> Option<Self> {
        let valid = words != [0; 4] && spare.is_none_or(f64::is_finite);
        valid.then_some(Self { s: words, spare })
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        xoshiro_next(&mut self.s)
    }

    /// Uniform in `[0, 1)` with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        unit_f64(self.next_u64())
    }

    /// Standard normal sample (Box–Muller; the second value of each pair is cached).
    pub fn gaussian(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        // u1 in (0, 1] so ln(u1) is finite.
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
        self.spare = Some(r * s);
        r * c
    }

    /// Normal sample with standard deviation `sigma` (0 → exactly 0, no draw skipped).
    pub fn normal(&mut self, sigma: f64) -> f64 {
        sigma * self.gaussian()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_moments() {
        let mut rng = NoiseRng::new(3, 9);
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0, 0.0);
        for _ in 0..n {
            let z = rng.gaussian();
            sum += z;
            sum2 += z * z;
        }
        let mean = sum / n as f64;
        let var = sum2 / n as f64 - mean * mean;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.02, "var {var}");
    }

    #[test]
    fn a_generator_continues_from_its_state() {
        let mut a = NoiseRng::new(3, 9);
        a.gaussian();
        let (words, spare) = a.state();
        let mut b = NoiseRng::from_state(words, spare).unwrap();
        for _ in 0..5 {
            assert_eq!(a.gaussian().to_bits(), b.gaussian().to_bits());
        }
        assert!(NoiseRng::from_state([0; 4], None).is_none());
        assert!(NoiseRng::from_state([1, 0, 0, 0], Some(f64::NAN)).is_none());
    }

    #[test]
    fn streams_differ() {
        let mut a = NoiseRng::new(3, 1);
        let mut b = NoiseRng::new(3, 2);
        assert_ne!(a.next_u64(), b.next_u64());
    }
}
