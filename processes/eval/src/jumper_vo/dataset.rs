//! ATE/RPE of the live `jumper_vo` estimate in a recorded launch (a folder written by
//! `hopnav launch --export-dataset DIR`: `estimate_jumper_vo.tum` and `groundtruth_jumper.tum`),
//! for `hopnav eval vo --dataset` and for a launch report's VO summary.
//!
//! ```no_run
//! use hopnav_eval::jumper_vo::dataset::evaluate_dataset;
//! let report = evaluate_dataset(std::path::Path::new("/tmp/d")).unwrap();
//! println!("ATE Sim(3) {:.3} m over {} frames", report.ate_sim3.rmse_m, report.frames());
//! ```

use super::metrics::{Ate, Rpe, ate, final_position_error_m, rpe, unaligned_rmse_m};
use super::tum::{TumError, read_tum};
use nalgebra::Isometry3;
use std::path::Path;

/// Estimate file the recorder writes for the jumper VO.
pub const ESTIMATE_FILE: &str = "estimate_jumper_vo.tum";
/// Ground-truth file the recorder writes for the jumper.
pub const TRUTH_FILE: &str = "groundtruth_jumper.tum";
/// Estimate and truth poses closer in time than this are paired, seconds.
const PAIR_TOLERANCE_S: f64 = 1e-4;

/// Error evaluating a dataset.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// A TUM file is missing or malformed.
    #[error(transparent)]
    Tum(#[from] TumError),
    /// Fewer than 3 estimate poses have a ground-truth pose at the same time.
    #[error("only {matched} estimate poses match ground-truth timestamps (need 3)")]
    TooFewMatches {
        /// Pairs found.
        matched: usize,
    },
    /// The Umeyama alignment is degenerate (e.g. all positions equal).
    #[error("trajectory alignment failed (degenerate positions)")]
    Alignment,
}

/// Metrics and the time-paired trajectories of one recorded launch.
#[derive(Debug, Clone, PartialEq)]
pub struct DatasetReport {
    /// Times of the paired poses, seconds.
    pub times_s: Vec<f64>,
    /// Estimated `world_from_body` per paired time.
    pub estimate: Vec<Isometry3<f64>>,
    /// True `world_from_body` per paired time.
    pub truth: Vec<Isometry3<f64>>,
    /// ATE after Sim(3) alignment.
    pub ate_sim3: Ate,
    /// ATE after SE(3) alignment.
    pub ate_se3: Ate,
    /// Position RMSE without alignment (the estimate is in the world frame), metres.
    pub unaligned_rmse_m: f64,
    /// Final position error, metres.
    pub final_error_m: Option<f64>,
    /// RPE over one frame.
    pub rpe_frame: Option<Rpe>,
}

impl DatasetReport {
    /// Paired frames evaluated.
    pub fn frames(&self) -> usize {
        self.times_s.len()
    }
}

/// Reads the jumper estimate and truth of the dataset in `dir`, pairs them by timestamp and
/// computes ATE (Sim(3), SE(3)), unaligned RMSE, final error and RPE per frame.
pub fn evaluate_dataset(dir: &Path) -> Result<DatasetReport, DatasetError> {
    let estimate = read_tum(&dir.join(ESTIMATE_FILE))?;
    let truth = read_tum(&dir.join(TRUTH_FILE))?;
    evaluate_pairs(&estimate, &truth)
}

/// [`evaluate_dataset`] on trajectories already read: `(t_s, world_from_body)` each.
pub fn evaluate_pairs(
    estimate: &[(f64, Isometry3<f64>)],
    truth: &[(f64, Isometry3<f64>)],
) -> Result<DatasetReport, DatasetError> {
    let mut times_s = Vec::with_capacity(estimate.len());
    let mut est = Vec::with_capacity(estimate.len());
    let mut gt = Vec::with_capacity(estimate.len());
    for (t_s, pose) in estimate {
        if let Some((_, true_pose)) = truth
            .iter()
            .find(|(truth_t_s, _)| (truth_t_s - t_s).abs() < PAIR_TOLERANCE_S)
        {
            times_s.push(*t_s);
            est.push(*pose);
            gt.push(*true_pose);
        }
    }
    if times_s.len() < 3 {
        return Err(DatasetError::TooFewMatches {
            matched: times_s.len(),
        });
    }
    let ate_sim3 = ate(&est, &gt, true).ok_or(DatasetError::Alignment)?;
    let ate_se3 = ate(&est, &gt, false).ok_or(DatasetError::Alignment)?;
    Ok(DatasetReport {
        unaligned_rmse_m: unaligned_rmse_m(&est, &gt),
        final_error_m: final_position_error_m(&est, &gt),
        rpe_frame: rpe(&est, &gt, 1),
        times_s,
        estimate: est,
        truth: gt,
        ate_sim3,
        ate_se3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    fn pose(x: f64, z: f64) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::new(x, 0.0, z), UnitQuaternion::identity())
    }

    #[test]
    fn pairs_by_time_and_scores_a_perfect_estimate_zero() {
        let truth: Vec<_> = (0..10)
            .map(|k| (0.1 * k as f64, pose(k as f64, (k * k) as f64 * 0.1)))
            .collect();
        // The estimate misses the first truth pose; the rest match exactly.
        let estimate = truth[1..].to_vec();
        let report = evaluate_pairs(&estimate, &truth).unwrap();
        assert_eq!(report.frames(), 9);
        assert!(report.ate_sim3.rmse_m < 1e-9 && report.ate_se3.rmse_m < 1e-9);
        assert!(report.final_error_m.unwrap() < 1e-9);
        assert!(matches!(
            evaluate_pairs(&estimate[..2], &truth),
            Err(DatasetError::TooFewMatches { matched: 2 })
        ));
    }
}
