//! Trajectory error metrics: ATE (after Sim(3) or SE(3) alignment), RPE per frame and per
//! metre travelled, final position error, rotation errors.

use super::align::{Similarity, umeyama};
use nalgebra::{Isometry3, Point3};

/// Absolute trajectory error after an alignment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ate {
    /// RMSE of the aligned positions, metres.
    pub rmse_m: f64,
    /// Largest aligned position error, metres.
    pub max_m: f64,
    /// The alignment used.
    pub alignment: Similarity,
}

/// ATE of `estimate` against `truth` (same length, matched by index).
pub fn ate(estimate: &[Isometry3<f64>], truth: &[Isometry3<f64>], with_scale: bool) -> Option<Ate> {
    let est: Vec<Point3<f64>> = estimate
        .iter()
        .map(|p| p.translation.vector.into())
        .collect();
    let gt: Vec<Point3<f64>> = truth.iter().map(|p| p.translation.vector.into()).collect();
    let alignment = umeyama(&est, &gt, with_scale)?;
    let errors: Vec<f64> = est
        .iter()
        .zip(&gt)
        .map(|(e, g)| (alignment.apply(e) - g).norm())
        .collect();
    Some(Ate {
        rmse_m: rms(&errors),
        max_m: errors.iter().copied().fold(0.0, f64::max),
        alignment,
    })
}

/// RMSE of positions without any alignment (the estimate is already in the world frame).
pub fn unaligned_rmse_m(estimate: &[Isometry3<f64>], truth: &[Isometry3<f64>]) -> f64 {
    let errors: Vec<f64> = estimate
        .iter()
        .zip(truth)
        .map(|(e, g)| (e.translation.vector - g.translation.vector).norm())
        .collect();
    rms(&errors)
}

/// Relative pose error over a fixed frame offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rpe {
    /// Translation RMSE per `delta` frames, metres.
    pub translation_rmse_m: f64,
    /// Rotation RMSE per `delta` frames, radians.
    pub rotation_rmse_rad: f64,
    /// Translation RMSE divided by the mean true distance travelled over `delta` frames
    /// (metres of error per metre travelled).
    pub translation_per_m: f64,
    /// Pairs used.
    pub pairs: usize,
}

/// RPE over `delta` frames: `(T_i⁻¹ T_{i+δ})_est` vs truth.
pub fn rpe(estimate: &[Isometry3<f64>], truth: &[Isometry3<f64>], delta: usize) -> Option<Rpe> {
    let n = estimate.len().min(truth.len());
    if delta == 0 || n <= delta {
        return None;
    }
    let (mut t_err, mut r_err, mut dist) = (Vec::new(), Vec::new(), 0.0);
    for i in 0..n - delta {
        let rel_e = estimate[i].inverse() * estimate[i + delta];
        let rel_g = truth[i].inverse() * truth[i + delta];
        let err = rel_g.inverse() * rel_e;
        t_err.push(err.translation.vector.norm());
        r_err.push(err.rotation.angle());
        dist += rel_g.translation.vector.norm();
    }
    let pairs = t_err.len();
    let mean_dist = dist / pairs as f64;
    let translation_rmse_m = rms(&t_err);
    Some(Rpe {
        translation_rmse_m,
        rotation_rmse_rad: rms(&r_err),
        translation_per_m: if mean_dist > 0.0 {
            translation_rmse_m / mean_dist
        } else {
            f64::NAN
        },
        pairs,
    })
}

/// Distance between the last estimated and true positions, metres.
pub fn final_position_error_m(
    estimate: &[Isometry3<f64>],
    truth: &[Isometry3<f64>],
) -> Option<f64> {
    let (e, g) = (estimate.last()?, truth.get(estimate.len().checked_sub(1)?)?);
    Some((e.translation.vector - g.translation.vector).norm())
}

/// Root mean square; NaN for an empty slice.
pub fn rms(values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    fn traj() -> Vec<Isometry3<f64>> {
        (0..40)
            .map(|i| {
                let t = i as f64 * 0.1;
                Isometry3::from_parts(
                    Translation3::new(5.0 * t, 0.2 * t, 8.66 * t - 1.85 * t * t),
                    UnitQuaternion::from_euler_angles(0.0, -0.1 * t, 0.0),
                )
            })
            .collect()
    }

    #[test]
    fn ate_is_zero_for_a_similar_copy() {
        let gt = traj();
        let s = 0.6;
        let moved = Isometry3::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.1, 0.2, 0.3));
        let est: Vec<Isometry3<f64>> = gt
            .iter()
            .map(|p| {
                let q = moved * Point3::from(p.translation.vector * s);
                Isometry3::from_parts(q.coords.into(), moved.rotation * p.rotation)
            })
            .collect();
        let sim = ate(&est, &gt, true).unwrap();
        assert!(sim.rmse_m < 1e-9, "{sim:?}");
        assert!((sim.alignment.scale - 1.0 / s).abs() < 1e-9);
        // Without scale the error cannot vanish.
        assert!(ate(&est, &gt, false).unwrap().rmse_m > 0.1);
        let r = rpe(&gt, &gt, 1).unwrap();
        assert!(r.translation_rmse_m < 1e-12 && r.rotation_rmse_rad < 1e-12);
        assert_eq!(final_position_error_m(&gt, &gt), Some(0.0));
    }
}
