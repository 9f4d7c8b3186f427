//! How far a rock's lowest foot lies below the ground at its centre.
//!
//! Why: the step a rover meets at a rock is its top above the ground where the wheel
//! stands, and the worst approach is from the downhill side. Stereo heights are measured
//! above the local ground under each point, which on a slope is the ground at the rock's
//! middle: a rock resting on a 5° slope reads a few centimetres lower than the step it makes
//! from below (the world rests each rock on the lowest ground under its footprint, and the
//! physics blocks a rock by that full step). Every point seen on a rock also says where the
//! ground under it is (its z minus its height), so the points give the ground's slope under
//! the rock, and the slope times the base radius is how much lower the downhill foot stands.
//!
//! ```
//! use hopnav_mapper::dome::RockPoint;
//! use hopnav_mapper::foot::foot_drop_m;
//! // Points on a rock on ground that rises 0.1 m per metre along x.
//! let points: Vec<RockPoint> = [(0.0, 0.0), (0.2, 0.0), (0.0, 0.2), (0.2, 0.2), (0.1, 0.1)]
//!     .iter()
//!     .map(|&(x, y)| RockPoint {
//!         xy_m: [x, y],
//!         height_m: 0.2,
//!         sigma_m: 0.01,
//!         ground_z_m: 0.1 * x,
//!     })
//!     .collect();
//! assert!((foot_drop_m(&points, 0.3) - 0.03).abs() < 1e-4);
//! ```

use crate::dome::RockPoint;

/// Fewer points than this give no slope.
const MIN_POINTS: usize = 4;
/// Points spread less than this across their narrower direction (one-sigma, metres) give
/// the slope only along the wider one: a plane through points on a line is not fixed
/// across it.
const MIN_SPREAD_M: f64 = 0.03;
/// The steepest ground slope believed under a rock (rise over run, about 17°): the rover
/// does not drive steeper ground, and a steeper fit is noise of the ground under the
/// points.
const MAX_SLOPE: f64 = 0.3;

/// How far below the ground at the centre of a rock of `base_radius_m` its downhill foot
/// stands, metres (0 when the points cannot fix the slope), from the ground under the
/// rock's `points`.
pub fn foot_drop_m(points: &[RockPoint], base_radius_m: f64) -> f64 {
    if !(base_radius_m.is_finite() && base_radius_m > 0.0) {
        return 0.0;
    }
    slope(points).min(MAX_SLOPE) * base_radius_m
}

/// A point's (x, y, ground z), when all three are finite.
fn ground_sample(point: &RockPoint) -> Option<[f64; 3]> {
    let sample = [
        f64::from(point.xy_m[0]),
        f64::from(point.xy_m[1]),
        f64::from(point.ground_z_m),
    ];
    sample.iter().all(|v| v.is_finite()).then_some(sample)
}

/// The magnitude of the least-squares ground gradient under `points` (their finite ground
/// samples; 0 with fewer than [`MIN_POINTS`]): the full gradient when the points spread in
/// both directions, its component along the wider one otherwise.
fn slope(points: &[RockPoint]) -> f64 {
    let samples = || points.iter().filter_map(ground_sample);
    let count = samples().count();
    if count < MIN_POINTS {
        return 0.0;
    }
    let n = count as f64;
    let mut mean = [0.0; 3];
    for sample in samples() {
        for axis in 0..3 {
            mean[axis] += sample[axis];
        }
    }
    let [mx, my, mz] = mean.map(|sum| sum / n);
    let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for p in samples() {
        let (dx, dy, dz) = (p[0] - mx, p[1] - my, p[2] - mz);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
        sxz += dx * dz;
        syz += dy * dz;
    }
    // Eigenvalues of the points' horizontal covariance (times n).
    let half_trace = 0.5 * (sxx + syy);
    let root = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
    let (wide, narrow) = (half_trace + root, half_trace - root);
    if wide / n < MIN_SPREAD_M * MIN_SPREAD_M {
        return 0.0;
    }
    if narrow / n >= MIN_SPREAD_M * MIN_SPREAD_M {
        let det = sxx * syy - sxy * sxy;
        let gx = (syy * sxz - sxy * syz) / det;
        let gy = (sxx * syz - sxy * sxz) / det;
        return gx.hypot(gy);
    }
    // Along the wider direction only: its unit vector is the eigenvector of `wide`.
    let (ux, uy) = if sxy.abs() > 1e-12 {
        (wide - syy, sxy)
    } else if sxx >= syy {
        (1.0, 0.0)
    } else {
        (0.0, 1.0)
    };
    let norm = ux.hypot(uy);
    let (ux, uy) = (ux / norm, uy / norm);
    ((ux * sxz + uy * syz) / wide).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f32, y: f32, ground_z_m: f32) -> RockPoint {
        RockPoint {
            xy_m: [x, y],
            height_m: 0.2,
            sigma_m: 0.01,
            ground_z_m,
        }
    }

    #[test]
    fn flat_ground_drops_nothing() {
        let points: Vec<RockPoint> = (0..9)
            .map(|i| point(0.1 * (i % 3) as f32, 0.1 * (i / 3) as f32, 1.5))
            .collect();
        assert!(foot_drop_m(&points, 0.3).abs() < 1e-6);
    }

    #[test]
    fn a_slope_in_any_direction_drops_the_foot_by_slope_times_radius() {
        for angle in [0.0f32, 0.7, 2.0, 4.0] {
            let (s, c) = angle.sin_cos();
            let points: Vec<RockPoint> = (0..9)
                .map(|i| {
                    let (x, y) = (0.1 * (i % 3) as f32, 0.1 * (i / 3) as f32);
                    point(x, y, 0.087 * (c * x + s * y))
                })
                .collect();
            let drop_m = foot_drop_m(&points, 0.4);
            assert!((drop_m - 0.087 * 0.4).abs() < 1e-4, "{angle}: {drop_m}");
        }
    }

    #[test]
    fn points_along_a_line_give_the_slope_along_it() {
        let points: Vec<RockPoint> = (0..6)
            .map(|i| {
                let t = 0.05 * i as f32;
                point(t * 0.6, t * 0.8, 0.2 * t)
            })
            .collect();
        assert!((foot_drop_m(&points, 0.5) - 0.1).abs() < 1e-4);
    }

    #[test]
    fn steep_noise_is_capped_and_bad_input_gives_nothing() {
        let steep: Vec<RockPoint> = (0..9)
            .map(|i| {
                let x = 0.1 * (i % 3) as f32;
                point(x, 0.1 * (i / 3) as f32, 2.0 * x)
            })
            .collect();
        assert!((foot_drop_m(&steep, 0.3) - MAX_SLOPE * 0.3).abs() < 1e-6);
        assert_eq!(foot_drop_m(&steep[..3], 0.3), 0.0, "too few points");
        assert_eq!(foot_drop_m(&steep, f64::NAN), 0.0);
        let mut bad = steep.clone();
        bad.iter_mut().for_each(|p| p.ground_z_m = f32::NAN);
        assert_eq!(foot_drop_m(&bad, 0.3), 0.0, "no finite point");
        let same: Vec<RockPoint> = (0..5).map(|_| point(1.0, 1.0, 0.0)).collect();
        assert_eq!(foot_drop_m(&same, 0.3), 0.0, "no spread");
    }
}
