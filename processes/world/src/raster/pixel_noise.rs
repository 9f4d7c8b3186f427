//! Seeded Gaussian pixel noise, applied to ground pixels only (the sky stays plain).
//!
//! A table of 256 rounded `N(0, σ²)` quantiles is built once; each pixel picks an entry with
//! 8 bits of a per-row xorshift stream seeded from `(noise_seed, noise_key, row)` (one 32-bit
//! draw serves four pixels). Adding a rounded sample to
//! an 8-bit value is exactly `round(value + noise)`, so this is Gaussian noise quantised as a real
//! sensor would.

use crate::rng::{XorShift32, mix64};

/// Pre-built noise table.
#[derive(Debug, Clone)]
pub(crate) struct PixelNoise {
    table: [i8; 256],
    seed: u64,
    enabled: bool,
}

impl PixelNoise {
    pub fn new(sigma_dn: f64, seed: u64) -> Self {
        let mut table = [0i8; 256];
        for (i, t) in table.iter_mut().enumerate() {
            let q = inverse_normal_cdf((i as f64 + 0.5) / 256.0);
            *t = (sigma_dn * q).round().clamp(-127.0, 127.0) as i8;
        }
        Self {
            table,
            seed,
            enabled: sigma_dn > 0.0,
        }
    }

    /// Adds noise to every pixel whose depth is set (`zbuf > 0`).
    pub fn apply(&self, key: u64, zbuf: &[f32], out: &mut [u8], stride: usize, width: usize) {
        if !self.enabled || width == 0 {
            return;
        }
        let frame = mix64(self.seed ^ mix64(key));
        for (row, zrow) in zbuf.chunks_exact(width).enumerate() {
            let mut rng = XorShift32::new(frame ^ row as u64);
            let orow = &mut out[row * stride..row * stride + width];
            for (o4, z4) in orow.chunks_mut(4).zip(zrow.chunks(4)) {
                let bits = rng.next_u32().to_le_bytes();
                for ((o, &z), b) in o4.iter_mut().zip(z4).zip(bits) {
                    let n = if z > 0.0 {
                        self.table[usize::from(b)]
                    } else {
                        0
                    };
                    *o = o.saturating_add_signed(n);
                }
            }
        }
    }
}

/// Inverse of the standard normal CDF (Acklam's rational approximation, |error| < 1.2e-9).
fn inverse_normal_cdf(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let p = p.clamp(1e-12, 1.0 - 1e-12);
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_symmetric_and_scaled() {
        assert!(inverse_normal_cdf(0.5).abs() < 1e-9);
        assert!((inverse_normal_cdf(0.975) - 1.959_964).abs() < 1e-5);
        let n = PixelNoise::new(2.0, 0);
        let mean: f64 = n.table.iter().map(|&v| f64::from(v)).sum::<f64>() / 256.0;
        assert!(n.table.iter().any(|&v| v >= 5) && n.table.iter().any(|&v| v <= -5));
        let var: f64 = n.table.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>() / 256.0;
        assert!(mean.abs() < 1e-9);
        // Rounding to integers adds 1/12 DN² of variance.
        assert!((var - 4.0).abs() < 0.4, "{var}");
    }
}
