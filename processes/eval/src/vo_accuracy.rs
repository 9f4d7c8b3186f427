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
    fn too_few_poses_give_no_accuracy() {
        let pose = Isometry3::identity();
        assert!(accuracy("jumper", &[(1, pose, pose)]).is_none());
    }
}
