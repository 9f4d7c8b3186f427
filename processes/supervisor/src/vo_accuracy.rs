//! Live VO accuracy: each robot's published pose estimate against physics' ground truth of
//! the same frame (evaluation only; nothing here reaches the robots).
//!
//! ```
//! use hopnav_supervisor::vo_accuracy::VoTrack;
//! use nalgebra::{Isometry3, Vector3};
//! let mut track = VoTrack::default();
//! for frame in 0..20u64 {
//!     let x = frame as f64 * 0.1;
//!     let t_ns = frame * 100_000_000;
//!     track.add_truth(t_ns, Isometry3::translation(x, 0.0, 0.0));
//!     track.add_estimate(t_ns, Isometry3::translation(1.01 * x, 0.0, 0.0));
//! }
//! let accuracy = track.accuracy("rover").unwrap();
//! assert_eq!(accuracy.poses, 20);
//! assert!(accuracy.ate_sim3_m < 1e-9 && accuracy.final_error_m > 0.01);
//! ```

use std::collections::BTreeMap;

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use hopnav_metrics::trajectory::errors::{ate, final_position_error_m, unaligned_rmse_m};

/// Stamped poses for a TUM file: (sim time s, `world_from_body`).
pub type TumPoses = Vec<(f64, Isometry3<f64>)>;

/// Truth poses kept while waiting for their estimate (a mission of ten minutes at 10 fps).
const MAX_PENDING_TRUTH: usize = 8192;

/// One robot's estimates paired with the truth of the same sim time.
#[derive(Debug, Clone, Default)]
pub struct VoTrack {
    truth_by_time: BTreeMap<u64, Isometry3<f64>>,
    /// (sim time ns, estimate, truth), in time order.
    pairs: Vec<(u64, Isometry3<f64>, Isometry3<f64>)>,
}

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

impl VoTrack {
    /// Ground truth at `sim_time_ns`.
    pub fn add_truth(&mut self, sim_time_ns: u64, world_from_body: Isometry3<f64>) {
        if self.truth_by_time.len() >= MAX_PENDING_TRUTH
            && let Some((&oldest, _)) = self.truth_by_time.iter().next()
        {
            self.truth_by_time.remove(&oldest);
        }
        self.truth_by_time.insert(sim_time_ns, world_from_body);
    }

    /// An estimate for `sim_time_ns`; kept when the truth of that time is known.
    pub fn add_estimate(&mut self, sim_time_ns: u64, world_from_body: Isometry3<f64>) {
        if let Some(truth) = self.truth_by_time.remove(&sim_time_ns) {
            self.pairs.push((sim_time_ns, world_from_body, truth));
        }
        // Truth older than this estimate will never be matched.
        self.truth_by_time = self.truth_by_time.split_off(&sim_time_ns);
    }

    /// The matched `(sim time s, pose)` pairs, estimate and truth, for TUM files.
    pub fn tum_poses(&self) -> (TumPoses, TumPoses) {
        let at = |t_ns: u64| t_ns as f64 * 1e-9;
        (
            self.pairs.iter().map(|(t, e, _)| (at(*t), *e)).collect(),
            self.pairs.iter().map(|(t, _, g)| (at(*t), *g)).collect(),
        )
    }

    /// The accuracy so far; `None` with fewer than three matched poses.
    pub fn accuracy(&self, robot: &str) -> Option<VoAccuracy> {
        if self.pairs.len() < 3 {
            return None;
        }
        let estimate: Vec<Isometry3<f64>> = self.pairs.iter().map(|(_, e, _)| *e).collect();
        let truth: Vec<Isometry3<f64>> = self.pairs.iter().map(|(_, _, g)| *g).collect();
        let travelled_m: f64 = truth
            .windows(2)
            .map(|pair| (pair[1].translation.vector - pair[0].translation.vector).norm())
            .sum();
        let final_error_m = final_position_error_m(&estimate, &truth)?;
        // A robot that never moved cannot be aligned with scale: report 0 error then.
        let ate_of = |with_scale| ate(&estimate, &truth, with_scale).map_or(0.0, |a| a.rmse_m);
        Some(VoAccuracy {
            robot: robot.to_owned(),
            poses: self.pairs.len(),
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_pair_with_the_truth_of_their_own_time_only() {
        let mut track = VoTrack::default();
        track.add_truth(100, Isometry3::translation(1.0, 0.0, 0.0));
        track.add_truth(200, Isometry3::translation(2.0, 0.0, 0.0));
        // An estimate with no truth of its time is dropped, and so is older truth.
        track.add_estimate(150, Isometry3::translation(9.0, 0.0, 0.0));
        track.add_estimate(200, Isometry3::translation(2.5, 0.0, 0.0));
        track.add_truth(300, Isometry3::translation(3.0, 0.0, 0.0));
        track.add_estimate(300, Isometry3::translation(3.5, 0.0, 0.0));
        track.add_truth(400, Isometry3::translation(4.0, 0.0, 0.0));
        track.add_estimate(400, Isometry3::translation(4.5, 0.0, 0.0));
        let accuracy = track.accuracy("rover").unwrap();
        assert_eq!(accuracy.poses, 3);
        assert!((accuracy.unaligned_rmse_m - 0.5).abs() < 1e-12);
        assert!(accuracy.ate_se3_m < 1e-9, "a constant offset aligns away");
        assert!((accuracy.travelled_m - 2.0).abs() < 1e-12);
        assert!((accuracy.drift_percent - 25.0).abs() < 1e-9);
        let (estimate, truth) = track.tum_poses();
        assert_eq!((estimate.len(), truth.len()), (3, 3));
    }

    #[test]
    fn too_few_poses_give_no_accuracy() {
        let mut track = VoTrack::default();
        track.add_truth(1, Isometry3::identity());
        track.add_estimate(1, Isometry3::identity());
        assert!(track.accuracy("jumper").is_none());
    }
}
