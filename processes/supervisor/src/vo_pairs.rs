//! Each robot's published pose estimate paired with physics' ground truth of the same frame,
//! recorded for the evaluation (nothing here reaches the robots; `hopnav-eval` scores it).
//!
//! ```
//! use hopnav_supervisor::vo_pairs::VoTrack;
//! use nalgebra::{Isometry3, Vector3};
//! let mut track = VoTrack::default();
//! for frame in 0..20u64 {
//!     let x = frame as f64 * 0.1;
//!     let t_ns = frame * 100_000_000;
//!     track.add_truth(t_ns, Isometry3::translation(x, 0.0, 0.0));
//!     track.add_estimate(t_ns, Isometry3::translation(1.01 * x, 0.0, 0.0));
//! }
//! assert_eq!(track.pairs().len(), 20);
//! ```

use std::collections::BTreeMap;

use nalgebra::Isometry3;

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

    /// The matched `(sim time ns, estimate, truth)` triples, in time order.
    pub fn pairs(&self) -> &[(u64, Isometry3<f64>, Isometry3<f64>)] {
        &self.pairs
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
        let times: Vec<u64> = track.pairs().iter().map(|(t, _, _)| *t).collect();
        assert_eq!(times, [200, 300]);
        let (estimate, truth) = track.tum_poses();
        assert_eq!((estimate.len(), truth.len()), (2, 2));
        assert!((estimate[0].1.translation.vector.x - 2.5).abs() < 1e-12);
        assert!((truth[0].1.translation.vector.x - 2.0).abs() < 1e-12);
    }
}
