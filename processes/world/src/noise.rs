//! Seeded 2-D lattice noise (value and gradient) and fractal sums of octaves.
//!
//! Pure functions of `(seed, x, y)`: no tables, no state, so evaluation order never changes a
//! result. Periodic variants wrap the lattice so tiles repeat seamlessly.
//!
//! ```
//! use hopnav_world::noise::{fbm, NoiseKind};
//! let a = fbm(NoiseKind::Gradient, 9, 1.25, -3.5, 5, 0.5);
//! assert_eq!(a, fbm(NoiseKind::Gradient, 9, 1.25, -3.5, 5, 0.5));
//! assert!(a.abs() < 2.0);
//! ```

use crate::rng::{derive_seed, hash2, unit_f64};

/// Which lattice noise an octave uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseKind {
    /// Random values at lattice points, smoothly interpolated (cheap, blobby).
    Value,
    /// Random gradients at lattice points (Perlin style, less grid-aligned).
    Gradient,
}

/// `floor` without a libm call (exact for |x| < 2^52; NaN maps to 0).
#[inline(always)]
fn floor_f64(x: f64) -> f64 {
    let t = x as i64 as f64;
    if x < t { t - 1.0 } else { t }
}

#[inline]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lattice_value(seed: u64, ix: i64, iy: i64) -> f64 {
    unit_f64(hash2(seed, ix, iy)) * 2.0 - 1.0
}

#[inline]
fn lattice_gradient(seed: u64, ix: i64, iy: i64, dx: f64, dy: f64) -> f64 {
    // 8 gradient directions of unit length.
    const G: [(f64, f64); 8] = [
        (1.0, 0.0),
        (-1.0, 0.0),
        (0.0, 1.0),
        (0.0, -1.0),
        (
            std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::FRAC_1_SQRT_2,
        ),
        (
            -std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::FRAC_1_SQRT_2,
        ),
        (
            std::f64::consts::FRAC_1_SQRT_2,
            -std::f64::consts::FRAC_1_SQRT_2,
        ),
        (
            -std::f64::consts::FRAC_1_SQRT_2,
            -std::f64::consts::FRAC_1_SQRT_2,
        ),
    ];
    let (gx, gy) = G[(hash2(seed, ix, iy) >> 61) as usize];
    gx * dx + gy * dy
}

/// One octave of noise at `(x, y)` in lattice units, roughly in `[-1, 1]`.
/// With `period = Some(p)` the lattice wraps every `p` cells (seamless tiles).
#[inline]
pub fn noise2(kind: NoiseKind, seed: u64, x: f64, y: f64, period: Option<i64>) -> f64 {
    let fx = floor_f64(x);
    let fy = floor_f64(y);
    let tx = x - fx;
    let ty = y - fy;
    let (mut x0, mut y0) = (fx as i64, fy as i64);
    let (mut x1, mut y1) = (x0 + 1, y0 + 1);
    if let Some(p) = period.filter(|p| *p > 0) {
        x0 = x0.rem_euclid(p);
        y0 = y0.rem_euclid(p);
        x1 = x1.rem_euclid(p);
        y1 = y1.rem_euclid(p);
    }
    let (n00, n10, n01, n11) = match kind {
        NoiseKind::Value => (
            lattice_value(seed, x0, y0),
            lattice_value(seed, x1, y0),
            lattice_value(seed, x0, y1),
            lattice_value(seed, x1, y1),
        ),
        NoiseKind::Gradient => (
            lattice_gradient(seed, x0, y0, tx, ty) * 1.4,
            lattice_gradient(seed, x1, y0, tx - 1.0, ty) * 1.4,
            lattice_gradient(seed, x0, y1, tx, ty - 1.0) * 1.4,
            lattice_gradient(seed, x1, y1, tx - 1.0, ty - 1.0) * 1.4,
        ),
    };
    let u = fade(tx);
    let v = fade(ty);
    let a = n00 + (n10 - n00) * u;
    let b = n01 + (n11 - n01) * u;
    a + (b - a) * v
}

/// Fractal sum of `octaves` octaves: frequency doubles and amplitude scales by `gain` per
/// octave; the first octave has amplitude 1 and lattice spacing 1.
pub fn fbm(kind: NoiseKind, seed: u64, x: f64, y: f64, octaves: u32, gain: f64) -> f64 {
    fbm_range(kind, seed, x, y, 0..octaves, gain)
}

/// The octaves `range` of [`fbm`] only (`fbm(.., n, g) == fbm_range(.., 0..k, g) +
/// fbm_range(.., k..n, g)` up to rounding), so coarse octaves can be evaluated on a coarser grid.
pub fn fbm_range(
    kind: NoiseKind,
    seed: u64,
    x: f64,
    y: f64,
    range: std::ops::Range<u32>,
    gain: f64,
) -> f64 {
    let mut sum = 0.0;
    let mut amp = gain.powi(range.start as i32);
    let mut freq = f64::from(1u32 << range.start.min(31));
    for o in range {
        let s = derive_seed(seed, u64::from(o));
        // Offset each octave so lattice points of different octaves do not line up.
        let off = 0.317 * f64::from(o);
        sum += amp * noise2(kind, s, x * freq + off, y * freq - off, None);
        amp *= gain;
        freq *= 2.0;
    }
    sum
}

/// Adds the value-noise octaves `range` of [`fbm`] (kind [`NoiseKind::Value`]) along one row:
/// `out[i] += scale · fbm_range(Value, seed, x0 + i·dx, y, range, gain)` up to rounding. Lattice
/// values are reused while consecutive samples stay in one cell, which makes baking textures
/// several times faster than calling [`fbm`] per sample.
#[allow(clippy::too_many_arguments)]
pub fn fbm_row_add(
    seed: u64,
    x0: f64,
    dx: f64,
    y: f64,
    range: std::ops::Range<u32>,
    gain: f64,
    scale: f64,
    out: &mut [f64],
) {
    let mut amp = scale * gain.powi(range.start as i32);
    let mut freq = f64::from(1u32 << range.start.min(31));
    for o in range {
        let s = derive_seed(seed, u64::from(o));
        let off = 0.317 * f64::from(o);
        let yy = y * freq - off;
        let fy = floor_f64(yy);
        let iy = fy as i64;
        let v = fade(yy - fy);
        let mut cached = i64::MIN;
        let (mut c0, mut c1) = (0.0, 0.0);
        for (i, acc) in out.iter_mut().enumerate() {
            let xx = (x0 + i as f64 * dx) * freq + off;
            let fx = floor_f64(xx);
            let ix = fx as i64;
            if ix != cached {
                cached = ix;
                let n00 = lattice_value(s, ix, iy);
                let n10 = lattice_value(s, ix + 1, iy);
                let n01 = lattice_value(s, ix, iy + 1);
                let n11 = lattice_value(s, ix + 1, iy + 1);
                c0 = n00 + (n01 - n00) * v;
                c1 = n10 + (n11 - n10) * v;
            }
            *acc += amp * (c0 + (c1 - c0) * fade(xx - fx));
        }
        amp *= gain;
        freq *= 2.0;
    }
}

/// Periodic fractal sum: the first octave wraps every `period` lattice cells, octave `o`
/// every `period · 2^o` cells, so the whole sum tiles with period `period` (in input units).
pub fn fbm_periodic(seed: u64, x: f64, y: f64, octaves: u32, gain: f64, period: i64) -> f64 {
    let mut sum = 0.0;
    let mut amp = 1.0;
    let mut freq = 1.0;
    let mut p = period.max(1);
    for o in 0..octaves {
        let s = derive_seed(seed, u64::from(o));
        sum += amp * noise2(NoiseKind::Value, s, x * freq, y * freq, Some(p));
        amp *= gain;
        freq *= 2.0;
        p *= 2;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuous_across_lattice_lines() {
        for kind in [NoiseKind::Value, NoiseKind::Gradient] {
            let a = noise2(kind, 5, 2.0 - 1e-9, 0.3, None);
            let b = noise2(kind, 5, 2.0 + 1e-9, 0.3, None);
            assert!((a - b).abs() < 1e-6);
        }
    }

    #[test]
    fn periodic_tiles() {
        let a = fbm_periodic(3, 0.25, 0.75, 4, 0.5, 8);
        let b = fbm_periodic(3, 8.25, 16.75, 4, 0.5, 8);
        assert!((a - b).abs() < 1e-12);
    }

    #[test]
    fn row_evaluation_matches_pointwise() {
        let mut row = vec![0.0; 50];
        fbm_row_add(4, -1.3, 0.07, 2.2, 1..5, 0.6, 2.0, &mut row);
        for (i, v) in row.iter().enumerate() {
            let p = 2.0 * fbm_range(NoiseKind::Value, 4, -1.3 + i as f64 * 0.07, 2.2, 1..5, 0.6);
            assert!((v - p).abs() < 1e-12, "{v} vs {p}");
        }
    }

    #[test]
    fn seed_changes_output() {
        let a = fbm(NoiseKind::Value, 1, 0.4, 0.6, 3, 0.5);
        let b = fbm(NoiseKind::Value, 2, 0.4, 0.6, 3, 0.5);
        assert_ne!(a, b);
    }
}
