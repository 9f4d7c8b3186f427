//! Live VO accuracy: each robot's published pose estimate against physics' ground truth of
//! the same frame, as the supervisor paired them (evaluation only; nothing here reaches the
//! robots).
//!
//! ```
//! use hopnav_eval::vo_accuracy::accuracy;
//! use nalgebra::Isometry3;
//! let pairs: Vec<_> = (0..20u64)
//!     .map(|frame| {
//!         let x = frame as f64 * 0.1;
//!         let t_ns = frame * 100_000_000;
//!         (t_ns, Isometry3::translation(1.01 * x, 0.0, 0.0), Isometry3::translation(x, 0.0, 0.0))
//!     })
//!     .collect();
//! let accuracy = accuracy("rover", &pairs).unwrap();
//! assert_eq!(accuracy.poses, 20);
//! assert!(accuracy.ate_sim3_m < 1e-9 && accuracy.final_error_m > 0.01);
//! ```

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use hopnav_metrics::trajectory::errors::{ate, final_position_error_m, unaligned_rmse_m};

/// How well one robot's VO followed the truth over a launch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VoAccuracy {
    /// `jumper` or `rover`.
    pub robot: String,
    /// Estimates matched with truth.
    pub poses: usize,
    /// Position RMSE after a Sim(3) alignment, metres.
    pub ate_sim3_m: f64,
    /// Position RMSE after an SE(3) alignment, metres.
    pub ate_se3_m: f64,
    /// Position RMSE in the world frame, no alignment, metres.
    pub unaligned_rmse_m: f64,
    /// Distance between the last estimate and the truth, metres.
    pub final_error_m: f64,
    /// Distance the robot really travelled, metres.
    pub travelled_m: f64,
    /// `final_error_m` in % of `travelled_m` (NaN when it did not move).
    pub drift_percent: f64,
    /// Position error at the end of each rest after a move, in order: for the jumper, where
    /// each hop ended as the next one starts from it (its error growth hop by hop).
    #[serde(default)]
    pub rest_errors_m: Vec<f64>,
}

/// The truth moving less than this between two poses is at rest, metres.
const REST_STEP_M: f64 = 0.005;
/// Poses at rest in a row that make a rest.
const REST_POSES: usize = 5;

/// The error at the last pose of every rest (`REST_POSES` poses or more barely moving) that
/// follows a move, in order.
pub fn rest_errors_m(pairs: &[(u64, Isometry3<f64>, Isometry3<f64>)]) -> Vec<f64> {
    let mut errors = Vec::new();
    let mut moved = false;
    let mut still = 0;
    for (k, window) in pairs.windows(2).enumerate() {
        let step = (window[1].2.translation.vector - window[0].2.translation.vector).norm();
        if step >= REST_STEP_M {
            if moved && still >= REST_POSES {
                let (_, estimate, truth) = &pairs[k];
                errors.push((estimate.translation.vector - truth.translation.vector).norm());
            }
            moved = true;
            still = 0;
        } else {
            still += 1;
        }
    }
    if moved
        && still >= REST_POSES
        && let Some((_, estimate, truth)) = pairs.last()
    {
        errors.push((estimate.translation.vector - truth.translation.vector).norm());
    }
    errors
}

/// The accuracy of `(sim time ns, estimate, truth)` pairs; `None` with fewer than three.
pub fn accuracy(
    robot: &str,
    pairs: &[(u64, Isometry3<f64>, Isometry3<f64>)],
) -> Option<VoAccuracy> {
    if pairs.len() < 3 {
        return None;
    }
    let estimate: Vec<Isometry3<f64>> = pairs.iter().map(|(_, e, _)| *e).collect();
    let truth: Vec<Isometry3<f64>> = pairs.iter().map(|(_, _, g)| *g).collect();
    let travelled_m: f64 = truth
        .windows(2)
        .map(|pair| (pair[1].translation.vector - pair[0].translation.vector).norm())
        .sum();
    let final_error_m = final_position_error_m(&estimate, &truth)?;
    // A robot that never moved cannot be aligned with scale: report 0 error then.
    let ate_of = |with_scale| ate(&estimate, &truth, with_scale).map_or(0.0, |a| a.rmse_m);
    Some(VoAccuracy {
        robot: robot.to_owned(),
        poses: pairs.len(),
        ate_sim3_m: ate_of(true),
        ate_se3_m: ate_of(false),
        unaligned_rmse_m: unaligned_rmse_m(&estimate, &truth),
        final_error_m,
        travelled_m,
        drift_percent: if travelled_m > 0.0 {
            100.0 * final_error_m / travelled_m
        } else {
            f64::NAN
        },
        rest_errors_m: rest_errors_m(pairs),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_offset_aligns_away_and_drift_is_relative_to_the_distance() {
        let pairs: Vec<_> = (1..=3u64)
            .map(|i| {
                let x = i as f64;
                (
                    i * 100,
                    Isometry3::translation(x + 0.5, 0.0, 0.0),
                    Isometry3::translation(x, 0.0, 0.0),
                )
            })
            .collect();
        let accuracy = accuracy("rover", &pairs).unwrap();
        assert_eq!(accuracy.poses, 3);
        assert!((accuracy.unaligned_rmse_m - 0.5).abs() < 1e-12);
        assert!(accuracy.ate_se3_m < 1e-9, "a constant offset aligns away");
        assert!((accuracy.travelled_m - 2.0).abs() < 1e-12);
        assert!((accuracy.drift_percent - 25.0).abs() < 1e-9);
    }

    #[test]
    fn each_rest_after_a_move_gives_the_error_it_ends_with() {
        // At rest 10 poses, a hop of 5 poses, rest 10 poses with a 0.3 m error, another hop,
        // rest 6 poses with 0.5 m.
        let mut pairs = Vec::new();
        let mut x = 0.0;
        let push = |x: f64, error: f64, pairs: &mut Vec<_>| {
            let t = pairs.len() as u64;
            pairs.push((
                t,
                Isometry3::translation(x + error, 0.0, 0.0),
                Isometry3::translation(x, 0.0, 0.0),
            ));
        };
        for _ in 0..10 {
            push(x, 0.0, &mut pairs);
        }
        for (hop, (rest, error)) in [(10, 0.3), (6, 0.5)].into_iter().enumerate() {
            for _ in 0..5 {
                x += 1.0;
                push(x, 0.1 * hop as f64, &mut pairs);
            }
            for _ in 0..rest {
                push(x, error, &mut pairs);
            }
        }
        let errors = rest_errors_m(&pairs);
        assert_eq!(errors.len(), 2, "{errors:?}");
        assert!((errors[0] - 0.3).abs() < 1e-12 && (errors[1] - 0.5).abs() < 1e-12);
        assert_eq!(accuracy("jumper", &pairs).unwrap().rest_errors_m, errors);
    }

    #[test]
    fn too_few_poses_give_no_accuracy() {
        let pose = Isometry3::identity();
        assert!(accuracy("jumper", &[(1, pose, pose)]).is_none());
    }
}
