//! Configuration of the rover VO (`[rover_vo]` table): serde with defaults,
//! `deny_unknown_fields`, and [`RoverVoConfig::validate`] naming the offending key and range.
//!
//! ```
//! use hopnav_rover_vo::config::RoverVoConfig;
//! let mut cfg = RoverVoConfig::default();
//! assert!(cfg.validate().is_ok());
//! cfg.max_depth_m = -1.0;
//! let err = cfg.validate().unwrap_err().to_string();
//! assert!(err.contains("rover_vo.max_depth_m"));
//! ```

use hopnav_config::range::{OutOfRange, Table};
use serde::{Deserialize, Serialize};

/// Settings of [`crate::pipeline::RoverVo`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RoverVoConfig {
    /// Maximum number of tracked features.
    pub max_features: usize,
    /// New keyframe (new corners, refreshed points, a cloud) when fewer tracks survive.
    pub keyframe_min_tracks: usize,
    /// New keyframe after this much translation since the last one, metres.
    pub keyframe_max_translation_m: f64,
    /// New keyframe after this much rotation since the last one, radians.
    pub keyframe_max_rotation_rad: f64,
    /// Fewer RANSAC inliers than this: the frame is not trusted (pose propagated).
    pub min_inliers: usize,
    /// Smaller inlier fraction of the usable tracks than this: the frame is not trusted.
    pub min_inlier_ratio: f64,
    /// Largest disparity searched, pixels.
    pub max_disparity_px: f64,
    /// Smallest disparity accepted (far points), pixels.
    pub min_disparity_px: f64,
    /// Stereo patch half size, pixels (patch is `2r+1` square).
    pub stereo_patch_radius_px: usize,
    /// Minimum zero-mean normalized cross-correlation of a stereo match.
    pub min_zncc: f64,
    /// Left–right consistency limit, pixels.
    pub left_right_max_px: f64,
    /// Largest disparity gap between the halves of a stereo patch matched on their own,
    /// pixels: a wider gap is a depth edge inside the patch (ground behind a rock's silhouette
    /// read a few per cent too near) and the match is refused; 0 turns the check off.
    pub stereo_max_half_disagreement_px: f64,
    /// Assumed disparity noise σ, pixels (gives each point's depth σ).
    pub disparity_sigma_px: f64,
    /// Points farther than this are not used, metres.
    pub max_depth_m: f64,
    /// RANSAC inlier threshold on the reprojection error, pixels.
    pub reprojection_threshold_px: f64,
    /// Use the IMU roll and pitch: 2-point stereo RANSAC hypotheses (yaw and translation) and
    /// a roll/pitch prior in the refinement. Otherwise 3-point hypotheses and a free 6-DOF fit.
    pub use_imu_tilt: bool,
    /// σ of the IMU roll/pitch prior in the 6-DOF refinement, radians; 0 fixes roll and pitch
    /// to the IMU's (4-DOF refinement).
    pub imu_tilt_sigma_rad: f64,
    /// Radius of the neighbourhood that defines a point's local ground, metres.
    pub ground_radius_m: f64,
    /// Share of the lowest residuals kept by the robust ground-plane fits (rocks stand above).
    pub ground_keep_fraction: f64,
    /// World z of the ground under the rover at the start, metres (the VO measures its height
    /// above the ground from the first stereo frame).
    pub start_ground_z_m: f64,
    /// Start position override (x, y), metres; absent: `physics.rover.start_xy_m`, the
    /// scenario's start point, or the physics default, in that order.
    pub start_xy_m: Option<[f64; 2]>,
    /// Publish a world-frame cloud at keyframes.
    pub publish_cloud: bool,
}

impl Default for RoverVoConfig {
    fn default() -> Self {
        Self {
            max_features: 400,
            keyframe_min_tracks: 150,
            keyframe_max_translation_m: 1.0,
            keyframe_max_rotation_rad: 0.2,
            min_inliers: 20,
            min_inlier_ratio: 0.3,
            max_disparity_px: 64.0,
            min_disparity_px: 1.5,
            stereo_patch_radius_px: 3,
            min_zncc: 0.8,
            left_right_max_px: 1.0,
            stereo_max_half_disagreement_px: 0.0,
            disparity_sigma_px: 0.2,
            max_depth_m: 30.0,
            reprojection_threshold_px: 2.0,
            use_imu_tilt: true,
            imu_tilt_sigma_rad: 0.002,
            ground_radius_m: 2.0,
            ground_keep_fraction: 0.6,
            start_ground_z_m: 0.0,
            start_xy_m: None,
            publish_cloud: true,
        }
    }
}

/// A configuration value out of range: it names `rover_vo.<key>`, the value and the allowed
/// range.
pub type ConfigError = OutOfRange;

/// The `[rover_vo]` keys, for their range checks.
const KEYS: Table = Table::new("rover_vo");

impl RoverVoConfig {
    /// Checks every value; the error names `rover_vo.<key>` and the allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        KEYS.count("max_features", self.max_features, 16, 4000)?;
        KEYS.count(
            "keyframe_min_tracks",
            self.keyframe_min_tracks,
            8,
            self.max_features,
        )
        .map_err(|rejected| rejected.noted("up to max_features"))?;
        KEYS.real(
            "keyframe_max_translation_m",
            self.keyframe_max_translation_m,
            0.05,
            20.0,
        )?;
        KEYS.real(
            "keyframe_max_rotation_rad",
            self.keyframe_max_rotation_rad,
            0.01,
            1.5,
        )?;
        KEYS.count("min_inliers", self.min_inliers, 4, 1000)?;
        KEYS.real("min_inlier_ratio", self.min_inlier_ratio, 0.0, 1.0)?;
        KEYS.real("max_disparity_px", self.max_disparity_px, 2.0, 256.0)?;
        KEYS.real(
            "min_disparity_px",
            self.min_disparity_px,
            0.1,
            self.max_disparity_px - 1.0,
        )
        .map_err(|rejected| rejected.noted("up to max_disparity_px - 1"))?;
        KEYS.count("stereo_patch_radius_px", self.stereo_patch_radius_px, 1, 7)?;
        KEYS.real("min_zncc", self.min_zncc, 0.0, 1.0)?;
        KEYS.real("left_right_max_px", self.left_right_max_px, 0.1, 5.0)?;
        KEYS.real(
            "stereo_max_half_disagreement_px",
            self.stereo_max_half_disagreement_px,
            0.0,
            16.0,
        )?;
        KEYS.real("disparity_sigma_px", self.disparity_sigma_px, 0.01, 5.0)?;
        KEYS.real("max_depth_m", self.max_depth_m, 1.0, 1000.0)?;
        KEYS.real(
            "reprojection_threshold_px",
            self.reprojection_threshold_px,
            0.1,
            20.0,
        )?;
        KEYS.real("imu_tilt_sigma_rad", self.imu_tilt_sigma_rad, 0.0, 1.0)?;
        KEYS.real("ground_radius_m", self.ground_radius_m, 0.1, 50.0)?;
        KEYS.real("ground_keep_fraction", self.ground_keep_fraction, 0.2, 1.0)?;
        KEYS.real("start_ground_z_m", self.start_ground_z_m, -1e4, 1e4)?;
        if let Some(xy) = self.start_xy_m {
            KEYS.per_axis("start_xy_m", &xy, -1e5, 1e5)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_name_their_key() {
        assert!(RoverVoConfig::default().validate().is_ok());
        let cfg = RoverVoConfig {
            min_zncc: 2.0,
            ..RoverVoConfig::default()
        };
        let err = cfg.validate().unwrap_err();
        assert_eq!(err.key, "rover_vo.min_zncc");
        assert!(err.to_string().contains("[0, 1]"));
        let cfg = RoverVoConfig {
            start_xy_m: Some([f64::NAN, 0.0]),
            ..RoverVoConfig::default()
        };
        assert_eq!(cfg.validate().unwrap_err().key, "rover_vo.start_xy_m");
    }
}
