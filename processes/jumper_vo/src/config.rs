//! Configuration of the jumper VO (`[jumper_vo]` table): serde with defaults,
//! `deny_unknown_fields`, and [`JumperVoConfig::validate`] naming the offending key.
//!
//! ```
//! use hopnav_jumper_vo::config::JumperVoConfig;
//! let mut cfg = JumperVoConfig::default();
//! assert!(cfg.validate().is_ok());
//! cfg.keyframe_min_parallax_deg = -1.0;
//! let err = cfg.validate().unwrap_err().to_string();
//! assert!(err.contains("jumper_vo.keyframe_min_parallax_deg"));
//! ```

use hopnav_config::range::{OutOfRange, Table};
use serde::{Deserialize, Serialize};

/// How the metric scale of the monocular translation is obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ScaleMethod {
    /// Paper eq. (4)–(5): `λ = Δz_alt / t_z^w` over the current keyframe pair. Singular near
    /// the apex and noisy with σ = 1 m; kept as the baseline.
    PaperEq4,
    /// Default: a least-squares fit of the launch velocity with the known-g ballistic model, fed
    /// by every altimeter sample and by every VO translation direction (gravity makes the
    /// length of a direction observable); the VO translation is scaled by the fitted
    /// displacement along it.
    #[default]
    Ballistic,
}

/// Essential-matrix minimal solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SolverChoice {
    /// Nistér's 5-point (default).
    #[default]
    FivePoint,
    /// Normalized 8-point.
    EightPoint,
}

/// Most keyframes a cloud track may reach back ([`JumperVoConfig::cloud_track_keyframes`]):
/// the VO keeps this many keyframe poses.
pub const MAX_CLOUD_TRACK_KEYFRAMES: u32 = 32;

/// Settings of [`crate::pipeline::JumperVo`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JumperVoConfig {
    /// Maximum number of tracked features.
    pub max_features: usize,
    /// Fewer tracked features (or RANSAC inliers) than this: starvation, ballistic propagation.
    pub min_tracked_features: usize,
    /// A vision estimate with a smaller inlier fraction of the tracks is rejected (propagated).
    pub min_inlier_ratio: f64,
    /// Camera pitch below body −x, radians.
    pub mount_pitch_down_rad: f64,
    /// Camera centre in the body frame, metres.
    pub camera_offset_body_m: [f64; 3],
    /// Essential-matrix solver.
    pub essential_solver: SolverChoice,
    /// Scale method.
    pub scale_method: ScaleMethod,
    /// Below this median rotation-compensated parallax (vs the keyframe) the translation
    /// direction is not used.
    pub keyframe_min_parallax_deg: f64,
    /// Median parallax above which the current frame becomes the next keyframe.
    pub keyframe_max_parallax_deg: f64,
    /// New keyframe when fewer than this fraction of the keyframe's features are still tracked.
    pub keyframe_min_track_fraction: f64,
    /// New keyframe when fewer features than this are still tracked.
    pub keyframe_min_tracks: usize,
    /// Gravity, m/s².
    pub gravity_mps2: f64,
    /// Altimeter noise σ, metres.
    pub altimeter_sigma_m: f64,
    /// Assumed σ of a VO translation direction, radians (weights it against the altimeter).
    pub direction_sigma_rad: f64,
    /// Commanded launch speed, m/s (a weak prior until tracking starts; ≤ 0 disables it).
    pub launch_speed_mps: f64,
    /// Commanded launch elevation, radians.
    pub launch_elevation_rad: f64,
    /// σ of the launch-velocity prior per axis, m/s.
    pub launch_velocity_sigma_mps: f64,
    /// Largest plausible speed, m/s: bounds the eq. (4) scale and the propagated velocity.
    pub max_speed_mps: f64,
    /// KLT pixel noise σ assumed by the RANSAC thresholds.
    pub pixel_sigma_px: f64,
    /// Triangulate and publish a world-frame cloud at keyframes.
    pub publish_cloud: bool,
    /// A cloud triangulates each track between the current keyframe and the keyframe it was
    /// born in (its corner detected then and tracked since), if that spans at most this many
    /// keyframe intervals and the birth view reprojects; otherwise over the last interval.
    /// The parallax, and with it the depth precision, grows with the track's age. 1
    /// triangulates over the last interval only. At most [`MAX_CLOUD_TRACK_KEYFRAMES`].
    pub cloud_track_keyframes: u32,
    /// Largest plausible body angular rate in flight, rad/s (torque-free flight keeps the
    /// launch rate, 0.1 rad/s in Table 1). A vision rotation implying more is rejected
    /// (propagated): a wrong homography/essential solution, or the tumble of an impact.
    pub max_angular_rate_radps: f64,
    /// Touchdown is declared at the first vision breakdown (no estimate, or a rejected
    /// rotation) while descending with the fitted body altitude less than this above the
    /// launch altitude, metres (the landing terrain need not be at the launch altitude).
    pub touchdown_margin_m: f64,
    /// Without a vision breakdown, touchdown is declared when the fit has descended this far
    /// below the launch altitude, metres (or, with a static image, at the launch altitude).
    pub touchdown_max_drop_m: f64,
    /// Commanded launch spin, body frame (x forward, y left, z up), rad/s (Table 1: 0.1 rad/s
    /// about the pitch axis, positive y pitching the nose down). Torque-free flight keeps it:
    /// it carries the launch attitude to the first image and propagates the attitude until
    /// vision measures the rate.
    pub launch_angular_velocity_body_radps: [f64; 3],
    /// In flight, take the attitude from a constant-rate fit anchored at the launch attitude
    /// (see [`crate::spin`]) instead of chaining the keyframe rotations, whose error grows as
    /// a random walk (about 1° over a hop, 5–10 % of its length). The commanded spin is its
    /// prior until the measured rates' median disagrees (a launch a rock turned). On by
    /// default: over the 20 missions of each terrain it cut the jumper's median unaligned
    /// RMSE on the default terrain from 3.16 to 1.38 m, and cooperative missions reached B
    /// more often on both (docs/experiments/2026-12-03-jumper-spin-fit-attitude.md). Off
    /// restores the chained rotations.
    pub attitude_from_spin_fit: bool,
    /// σ per axis of the commanded launch spin as a prior of that fit, rad/s (≤ 0: none).
    pub launch_angular_velocity_sigma_radps: f64,
    /// σ of one keyframe-to-keyframe vision rotation in that fit, radians.
    pub keyframe_rotation_sigma_rad: f64,
    /// After touchdown the landing cage soaks up the horizontal velocity at this rate, 1/s:
    /// the body slides `v_h / k · (1 − e^(−k t))` along the touchdown velocity (the hardware's
    /// linear damping while landing). 0 holds the touchdown point.
    pub landing_slide_decay_per_s: f64,
    /// Local bundle adjustment ([`crate::flight_ba`]) at every flight keyframe: the flight's
    /// launch velocity, spin and resting-attitude correction refined jointly with the ground
    /// points the window's keyframes saw. `false` keeps the fits alone.
    pub bundle_adjustment: bool,
    /// Keyframes the adjustment's window holds (the hop's latest).
    pub ba_window_keyframes: usize,
    /// σ of the resting attitude the hop starts from, per axis, radians (its correction's
    /// prior in the adjustment).
    pub ba_launch_attitude_sigma_rad: f64,
    /// Cauchy scale of the adjustment's reprojection residuals, in pixel σs.
    pub ba_robust_scale_sigmas: f64,
    /// σ per horizontal axis of where the body comes to rest against the slide model, metres
    /// (widens the published position σ after a landing). Default from 20 cooperative
    /// missions of `docs/experiments/2026-12-07-jumper-local-bundle-adjustment.md`: the
    /// landing error's p10–p90 is about ±0.3 m along and across the travel.
    pub landing_slide_sigma_m: f64,
}

impl Default for JumperVoConfig {
    fn default() -> Self {
        Self {
            max_features: 1000,
            min_tracked_features: 60,
            min_inlier_ratio: 0.3,
            mount_pitch_down_rad: std::f64::consts::FRAC_PI_6,
            camera_offset_body_m: [-0.1, 0.0, 0.0],
            essential_solver: SolverChoice::FivePoint,
            scale_method: ScaleMethod::Ballistic,
            keyframe_min_parallax_deg: 0.3,
            keyframe_max_parallax_deg: 4.0,
            keyframe_min_track_fraction: 0.5,
            keyframe_min_tracks: 120,
            gravity_mps2: crate::trajectory::MARS_G_MPS2,
            altimeter_sigma_m: 1.0,
            direction_sigma_rad: 0.01,
            launch_speed_mps: 10.0,
            launch_elevation_rad: 60f64.to_radians(),
            launch_velocity_sigma_mps: 1.0,
            max_speed_mps: 20.0,
            pixel_sigma_px: 0.5,
            publish_cloud: true,
            cloud_track_keyframes: 8,
            max_angular_rate_radps: 1.0,
            touchdown_margin_m: 0.5,
            touchdown_max_drop_m: 3.0,
            launch_angular_velocity_body_radps: [0.0, 0.1, 0.0],
            attitude_from_spin_fit: true,
            launch_angular_velocity_sigma_radps: 0.003,
            keyframe_rotation_sigma_rad: 0.005,
            landing_slide_decay_per_s: 8.0,
            bundle_adjustment: true,
            ba_window_keyframes: 12,
            ba_launch_attitude_sigma_rad: 0.01,
            ba_robust_scale_sigmas: 3.0,
            landing_slide_sigma_m: 0.25,
        }
    }
}

/// A configuration value out of range: it names `jumper_vo.<key>`, the value and the allowed
/// range.
pub type ConfigError = OutOfRange;

/// The `[jumper_vo]` keys, for their range checks.
const KEYS: Table = Table::new("jumper_vo");

impl JumperVoConfig {
    /// Checks every value; the error names `jumper_vo.<key>` and the allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_tracking()?;
        self.validate_keyframes()?;
        self.validate_flight_model()?;
        self.validate_spin_and_landing()?;
        Ok(())
    }

    /// The tracker, the two-view gates and the camera mount.
    fn validate_tracking(&self) -> Result<(), ConfigError> {
        KEYS.count("max_features", self.max_features, 16, 4096)?;
        KEYS.count("min_tracked_features", self.min_tracked_features, 8, 1000)?;
        KEYS.real("min_inlier_ratio", self.min_inlier_ratio, 0.0, 1.0)?;
        KEYS.real("mount_pitch_down_rad", self.mount_pitch_down_rad, -1.5, 1.5)?;
        KEYS.per_axis(
            "camera_offset_body_m",
            &self.camera_offset_body_m,
            -5.0,
            5.0,
        )?;
        Ok(())
    }

    /// When a keyframe is taken and how long its tracks feed the cloud.
    fn validate_keyframes(&self) -> Result<(), ConfigError> {
        KEYS.real(
            "keyframe_min_parallax_deg",
            self.keyframe_min_parallax_deg,
            0.0,
            10.0,
        )?;
        KEYS.real(
            "keyframe_max_parallax_deg",
            self.keyframe_max_parallax_deg,
            self.keyframe_min_parallax_deg.max(0.1),
            45.0,
        )
        .map_err(|rejected| rejected.noted("from max(keyframe_min_parallax_deg, 0.1)"))?;
        KEYS.real(
            "keyframe_min_track_fraction",
            self.keyframe_min_track_fraction,
            0.0,
            1.0,
        )?;
        KEYS.count(
            "cloud_track_keyframes",
            self.cloud_track_keyframes as usize,
            1,
            MAX_CLOUD_TRACK_KEYFRAMES as usize,
        )?;
        KEYS.count("keyframe_min_tracks", self.keyframe_min_tracks, 0, 4096)?;
        Ok(())
    }

    /// The ballistic model, the launch prior and the measurement noise.
    fn validate_flight_model(&self) -> Result<(), ConfigError> {
        KEYS.real("gravity_mps2", self.gravity_mps2, 0.01, 100.0)?;
        KEYS.real("altimeter_sigma_m", self.altimeter_sigma_m, 1e-3, 1000.0)?;
        KEYS.real("direction_sigma_rad", self.direction_sigma_rad, 1e-5, 1.0)?;
        KEYS.real("launch_speed_mps", self.launch_speed_mps, 0.0, 100.0)
            .map_err(|rejected| rejected.noted("0 disables"))?;
        KEYS.real("launch_elevation_rad", self.launch_elevation_rad, -1.6, 1.6)?;
        KEYS.real(
            "launch_velocity_sigma_mps",
            self.launch_velocity_sigma_mps,
            1e-3,
            100.0,
        )?;
        KEYS.real("max_speed_mps", self.max_speed_mps, 0.1, 1000.0)?;
        KEYS.real("pixel_sigma_px", self.pixel_sigma_px, 0.05, 10.0)?;
        KEYS.real(
            "launch_angular_velocity_sigma_radps",
            self.launch_angular_velocity_sigma_radps,
            0.0,
            100.0,
        )
        .map_err(|rejected| rejected.noted("0: no prior"))?;
        KEYS.real(
            "keyframe_rotation_sigma_rad",
            self.keyframe_rotation_sigma_rad,
            1e-6,
            1.0,
        )?;
        Ok(())
    }

    /// The angular-rate gate, the touchdown test and the landing slide.
    fn validate_spin_and_landing(&self) -> Result<(), ConfigError> {
        KEYS.real(
            "max_angular_rate_radps",
            self.max_angular_rate_radps,
            0.01,
            100.0,
        )?;
        KEYS.real("touchdown_margin_m", self.touchdown_margin_m, 0.0, 100.0)?;
        KEYS.real(
            "touchdown_max_drop_m",
            self.touchdown_max_drop_m,
            0.0,
            1000.0,
        )?;
        KEYS.per_axis(
            "launch_angular_velocity_body_radps",
            &self.launch_angular_velocity_body_radps,
            -10.0,
            10.0,
        )?;
        KEYS.real(
            "landing_slide_decay_per_s",
            self.landing_slide_decay_per_s,
            0.0,
            1000.0,
        )
        .map_err(|rejected| rejected.noted("0 holds the touchdown point"))?;
        KEYS.count("ba_window_keyframes", self.ba_window_keyframes, 2, 64)?;
        KEYS.real(
            "ba_launch_attitude_sigma_rad",
            self.ba_launch_attitude_sigma_rad,
            1e-5,
            1.0,
        )?;
        KEYS.real(
            "landing_slide_sigma_m",
            self.landing_slide_sigma_m,
            0.0,
            100.0,
        )?;
        KEYS.real(
            "ba_robust_scale_sigmas",
            self.ba_robust_scale_sigmas,
            0.5,
            100.0,
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_name_their_key() {
        let cfg = JumperVoConfig {
            max_features: 3,
            ..JumperVoConfig::default()
        };
        assert_eq!(
            cfg.validate().unwrap_err().to_string(),
            "jumper_vo.max_features must be in [16, 4096], got 3"
        );
        let cfg = JumperVoConfig {
            altimeter_sigma_m: f64::NAN,
            ..JumperVoConfig::default()
        };
        assert_eq!(
            cfg.validate().unwrap_err().key,
            "jumper_vo.altimeter_sigma_m"
        );
    }
}
