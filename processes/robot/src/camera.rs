//! Where the robots' cameras sit and what they see, defined once: the jumper's rear mono
//! camera and the rover's stereo pair (intrinsics, mounts, baseline). The camera process renders
//! with them, the VO reads them from the image header it renders, the offline rover traverse
//! and the evaluation read them here.
//!
//! Their keys live in `[camera]` (the camera process renders them); [`CameraRig::from_config`]
//! reads them there for any other crate, with the defaults of [`CameraRig::default`], the
//! only place they are written.
//!
//! ```
//! use hopnav_robot::camera::CameraRig;
//! use nalgebra::Vector3;
//! let rig = CameraRig::default();
//! // The rover's stereo pair looks forward and down.
//! let left = rig.rover_body_from_left();
//! let axis = left.rotation * Vector3::z();
//! assert!(axis.x > 0.9 && axis.z < 0.0);
//! ```

use hopnav_config::{ConfigError, HopnavConfig, in_section, parse_section};
use hopnav_world::camera::CameraConfig;
use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use serde::{Deserialize, Serialize};

/// Where a camera sits on its robot (body frame: x forward, y left, z up).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraMount {
    /// Optical centre in the body frame, metres (for a stereo pair: midway between the two).
    pub position_m: [f64; 3],
    /// Viewing direction about body z: 0 = forward, π = backward, radians.
    pub yaw_rad: f64,
    /// Tilt below the body's x-y plane, radians.
    pub pitch_down_rad: f64,
}

impl CameraMount {
    /// `body_from_camera` of a camera at `position_m` looking along the body heading `yaw_rad`
    /// (0 = forward, π = backward) tilted `pitch_down_rad` below the body's x-y plane.
    /// Camera frame: OpenCV (x right, y down, z forward).
    pub fn body_from_camera(&self) -> Isometry3<f64> {
        let eye = Point3::from(Vector3::from(self.position_m));
        let (sin_pitch, cos_pitch) = self.pitch_down_rad.sin_cos();
        let (sin_yaw, cos_yaw) = self.yaw_rad.sin_cos();
        let view = Vector3::new(cos_pitch * cos_yaw, cos_pitch * sin_yaw, -sin_pitch);
        hopnav_world::camera::look_at(&eye, &(eye + view), &Vector3::z())
    }

    /// `body_from_camera` of the **left** camera of a stereo pair whose midpoint is this mount:
    /// half a baseline along camera −x.
    pub fn body_from_left_camera(&self, baseline_m: f64) -> Isometry3<f64> {
        self.body_from_camera() * Translation3::new(-baseline_m / 2.0, 0.0, 0.0)
    }

    /// Checks the mount's values; errors name `<section>.<name>.<key>`.
    pub fn check(&self, section: &str, name: &str) -> Result<(), ConfigError> {
        if !self
            .position_m
            .iter()
            .all(|v| v.is_finite() && v.abs() <= 10.0)
        {
            return Err(in_section(
                section,
                &format!("{name}.position_m"),
                format!("{:?}", self.position_m),
                "finite, each |v| <= 10",
            ));
        }
        if !(self.yaw_rad.is_finite() && self.yaw_rad.abs() <= 2.0 * std::f64::consts::PI) {
            return Err(in_section(
                section,
                &format!("{name}.yaw_rad"),
                self.yaw_rad,
                "[-2π, 2π]",
            ));
        }
        if !(self.pitch_down_rad.is_finite()
            && self.pitch_down_rad.abs() <= std::f64::consts::FRAC_PI_2)
        {
            return Err(in_section(
                section,
                &format!("{name}.pitch_down_rad"),
                self.pitch_down_rad,
                "[-π/2, π/2]",
            ));
        }
        Ok(())
    }
}

/// Both robots' cameras: what the `[camera]` table says besides its rendering options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CameraRig {
    /// Jumper camera intrinsics (paper: 320×320, FOV 45° → f = 386.3 px, not the paper's
    /// 521.78 px, which does not match its own FOV).
    pub jumper: CameraConfig,
    /// Jumper camera mount: at the rear, facing backward (along body −x).
    pub jumper_mount: CameraMount,
    /// Rover stereo intrinsics (both views).
    pub rover: CameraConfig,
    /// Rover stereo mount (midpoint of the pair).
    pub rover_mount: CameraMount,
    /// Rover stereo baseline along the camera x axis, metres.
    pub rover_baseline_m: f64,
}

impl Default for CameraRig {
    fn default() -> Self {
        Self {
            jumper: CameraConfig::default(),
            // Physics sets the jumper to its launch attitude (body x along the launch
            // direction, 60° up), so a camera along body −x looks 60° below the horizon,
            // backward, at launch and tilts up as the body pitches nose-down in flight.
            jumper_mount: CameraMount {
                position_m: [-0.12, 0.0, 0.0],
                yaw_rad: std::f64::consts::PI,
                pitch_down_rad: 0.0,
            },
            rover: CameraConfig {
                width_px: 320,
                height_px: 240,
                hfov_rad: 60_f64.to_radians(),
                vfov_rad: None,
                near_m: 0.05,
            },
            rover_mount: CameraMount {
                position_m: [0.3, 0.0, 1.0],
                yaw_rad: 0.0,
                pitch_down_rad: 15_f64.to_radians(),
            },
            rover_baseline_m: 0.2,
        }
    }
}

impl CameraRig {
    /// Reads the cameras' keys of `[camera]` (absent keys take the defaults; other keys, such
    /// as `render`, are the camera process's business: it validates the whole table). This
    /// refuses what is not a camera.
    pub fn from_config(config: &HopnavConfig) -> Result<Self, ConfigError> {
        let rig: Self = parse_section(config, "camera")?;
        rig.check()?;
        Ok(rig)
    }

    /// Checks the mounts and the baseline (the intrinsics are the world crate's to check);
    /// errors name `camera.<key>`.
    pub fn check(&self) -> Result<(), ConfigError> {
        self.jumper_mount.check("camera", "jumper_mount")?;
        self.rover_mount.check("camera", "rover_mount")?;
        if !(self.rover_baseline_m.is_finite()
            && self.rover_baseline_m > 0.0
            && self.rover_baseline_m <= 2.0)
        {
            return Err(in_section(
                "camera",
                "rover_baseline_m",
                self.rover_baseline_m,
                "(0, 2]",
            ));
        }
        Ok(())
    }

    /// `body_from_camera` of the jumper's camera.
    pub fn jumper_body_from_camera(&self) -> Isometry3<f64> {
        self.jumper_mount.body_from_camera()
    }

    /// `body_from_camera` of the rover's left stereo camera.
    pub fn rover_body_from_left(&self) -> Isometry3<f64> {
        self.rover_mount
            .body_from_left_camera(self.rover_baseline_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mount(yaw_rad: f64, pitch_down_rad: f64) -> CameraMount {
        CameraMount {
            position_m: [-0.1, 0.0, 0.05],
            yaw_rad,
            pitch_down_rad,
        }
    }

    #[test]
    fn rear_camera_looks_backward_and_down_with_right_to_body_left() {
        let pose = mount(std::f64::consts::PI, 30_f64.to_radians()).body_from_camera();
        let optical_axis = pose.rotation * Vector3::z();
        assert!((optical_axis - Vector3::new(-30_f64.to_radians().cos(), 0.0, -0.5)).norm() < 1e-9);
        let image_right = pose.rotation * Vector3::x();
        assert!((image_right - Vector3::y()).norm() < 1e-9, "{image_right}");
        assert!((pose.translation.vector - Vector3::new(-0.1, 0.0, 0.05)).norm() < 1e-12);
    }

    #[test]
    fn forward_camera_image_down_points_down() {
        let pose = mount(0.0, 0.0).body_from_camera();
        assert!((pose.rotation * Vector3::z() - Vector3::x()).norm() < 1e-9);
        assert!((pose.rotation * Vector3::y() + Vector3::z()).norm() < 1e-9);
    }

    #[test]
    fn the_left_camera_sits_half_a_baseline_to_the_body_left() {
        let rig = CameraRig::default();
        let mid = rig.rover_mount.body_from_camera().translation.vector;
        let left = rig.rover_body_from_left().translation.vector;
        assert!(
            (left - mid - Vector3::new(0.0, 0.1, 0.0)).norm() < 1e-12,
            "{left}"
        );
    }

    #[test]
    fn the_rig_is_read_from_camera_and_render_is_left_to_the_camera() {
        let config = hopnav_config::load(Some(
            "[camera]\nrover_baseline_m = 0.3\n[camera.render]\nnoise_sigma_dn = 1.0\n",
        ))
        .expect("config");
        let rig = CameraRig::from_config(&config).expect("rig");
        assert_eq!(rig.rover_baseline_m, 0.3);
        assert_eq!(rig.rover_mount, CameraRig::default().rover_mount);
        let config =
            hopnav_config::load(Some("[camera]\nrover_baseline_m = 0.0\n")).expect("config");
        let error = CameraRig::from_config(&config)
            .expect_err("no baseline")
            .to_string();
        assert!(error.contains("camera.rover_baseline_m"), "{error}");
    }
}
