//! Pinhole camera model, camera configuration, look-at and stereo helpers.
//!
//! # Convention
//! Camera frame is OpenCV's: **x right, y down, z forward** (optical axis). A pose is
//! `world_from_camera` (`p_world = world_from_camera * p_camera`). Pixel coordinates are
//! OpenCV's too: pixel `(u, v)` (column, row) has its centre at integer `(u, v)`, so the image
//! centre is `((w−1)/2, (h−1)/2)`. A camera point projects to
//! `u = fx·x/z + cx`, `v = fy·y/z + cy`.
//!
//! The focal length is derived from the field of view: `fx = (w/2) / tan(hfov/2)`
//! (45° over 320 px gives 386.27 px; the paper's 521.78 px does not match its own FOV).
//!
//! ```
//! use hopnav_world::camera::{CameraConfig, PinholeCamera};
//! let cam = PinholeCamera::from_config(&CameraConfig::default(), "camera").unwrap();
//! assert!((cam.fx_px - 386.2742).abs() < 1e-3);
//! assert_eq!(cam.cx_px, 159.5);
//! ```

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::config::{Interval, check_int};
use crate::error::ConfigError;

/// Camera image size, field of view and near-plane distance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraConfig {
    /// Image width, pixels.
    pub width_px: u32,
    /// Image height, pixels.
    pub height_px: u32,
    /// Horizontal field of view, radians.
    pub hfov_rad: f64,
    /// Vertical field of view, radians; `None` means square pixels (`fy = fx`).
    pub vfov_rad: Option<f64>,
    /// Near clipping plane distance, metres.
    pub near_m: f64,
}

impl Default for CameraConfig {
    fn default() -> Self {
        Self {
            width_px: 320,
            height_px: 320,
            hfov_rad: std::f64::consts::FRAC_PI_4,
            vfov_rad: None,
            near_m: 0.05,
        }
    }
}

impl CameraConfig {
    /// Checks the values; errors name `prefix.field`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        check_int(prefix, "width_px", u64::from(self.width_px), 1, 8192)?;
        check_int(prefix, "height_px", u64::from(self.height_px), 1, 8192)?;
        Interval::left_open(0.0, 3.0).check(prefix, "hfov_rad", self.hfov_rad)?;
        if let Some(v) = self.vfov_rad {
            Interval::left_open(0.0, 3.0).check(prefix, "vfov_rad", v)?;
        }
        Interval::closed(0.001, 10.0).check(prefix, "near_m", self.near_m)?;
        Ok(())
    }
}

/// Pinhole intrinsics (no distortion) plus image size and near plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinholeCamera {
    /// Image width, pixels.
    pub width_px: u32,
    /// Image height, pixels.
    pub height_px: u32,
    /// Focal length along x, pixels.
    pub fx_px: f64,
    /// Focal length along y, pixels.
    pub fy_px: f64,
    /// Principal point x, pixels (centre of pixel 0 is 0).
    pub cx_px: f64,
    /// Principal point y, pixels.
    pub cy_px: f64,
    /// Near clipping plane, metres.
    pub near_m: f64,
}

impl PinholeCamera {
    /// Validates `cfg` (errors name `prefix.field`) and derives the intrinsics.
    pub fn from_config(cfg: &CameraConfig, prefix: &str) -> Result<Self, ConfigError> {
        cfg.validate(prefix)?;
        let w = f64::from(cfg.width_px);
        let h = f64::from(cfg.height_px);
        let fx = (w / 2.0) / (cfg.hfov_rad / 2.0).tan();
        let fy = match cfg.vfov_rad {
            Some(v) => (h / 2.0) / (v / 2.0).tan(),
            None => fx,
        };
        Ok(Self {
            width_px: cfg.width_px,
            height_px: cfg.height_px,
            fx_px: fx,
            fy_px: fy,
            cx_px: (w - 1.0) / 2.0,
            cy_px: (h - 1.0) / 2.0,
            near_m: cfg.near_m,
        })
    }

    /// Pixel `[u, v]` of a point in the camera frame, `None` behind the near plane.
    pub fn project(&self, p_camera: &Point3<f64>) -> Option<[f64; 2]> {
        if p_camera.z < self.near_m || !p_camera.z.is_finite() {
            return None;
        }
        Some([
            self.fx_px * p_camera.x / p_camera.z + self.cx_px,
            self.fy_px * p_camera.y / p_camera.z + self.cy_px,
        ])
    }

    /// Pixel of a world point seen from `world_from_camera`.
    pub fn project_world(
        &self,
        world_from_camera: &Isometry3<f64>,
        p_world: &Point3<f64>,
    ) -> Option<[f64; 2]> {
        self.project(&world_from_camera.inverse_transform_point(p_world))
    }

    /// Ray direction (camera frame, z = 1) through pixel `(u, v)`.
    pub fn ray(&self, u_px: f64, v_px: f64) -> Vector3<f64> {
        Vector3::new(
            (u_px - self.cx_px) / self.fx_px,
            (v_px - self.cy_px) / self.fy_px,
            1.0,
        )
    }
}

/// `world_from_camera` of a camera at `eye` looking at `target`, image "up" towards `up`
/// (OpenCV frame: z along the view, y down). Falls back to another up vector when the view
/// is parallel to `up`.
pub fn look_at(eye: &Point3<f64>, target: &Point3<f64>, up: &Vector3<f64>) -> Isometry3<f64> {
    let forward = (target - eye)
        .try_normalize(1e-12)
        .unwrap_or_else(Vector3::z);
    let right = forward
        .cross(up)
        .try_normalize(1e-9)
        .or_else(|| forward.cross(&Vector3::x()).try_normalize(1e-9))
        .unwrap_or_else(Vector3::y);
    let down = forward.cross(&right);
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[right, down, forward]));
    Isometry3::from_parts(
        Translation3::from(eye.coords),
        UnitQuaternion::from_rotation_matrix(&rot),
    )
}

/// `world_from_right` of a stereo pair: the right camera sits `baseline_m` along the left
/// camera's +x axis with the same orientation.
pub fn stereo_right(world_from_left: &Isometry3<f64>, baseline_m: f64) -> Isometry3<f64> {
    world_from_left * Translation3::new(baseline_m, 0.0, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_frames_target_at_principal_point() {
        let cam = PinholeCamera::from_config(&CameraConfig::default(), "c").unwrap();
        let pose = look_at(
            &Point3::new(1.0, 2.0, 5.0),
            &Point3::new(3.0, -1.0, 0.0),
            &Vector3::z(),
        );
        let px = cam
            .project_world(&pose, &Point3::new(3.0, -1.0, 0.0))
            .unwrap();
        assert!((px[0] - cam.cx_px).abs() < 1e-9 && (px[1] - cam.cy_px).abs() < 1e-9);
        // A point above the target appears higher in the image (smaller v).
        let up = cam
            .project_world(&pose, &Point3::new(3.0, -1.0, 0.5))
            .unwrap();
        assert!(up[1] < px[1]);
    }

    #[test]
    fn bad_fov_names_key() {
        let cfg = CameraConfig {
            hfov_rad: -0.5,
            ..CameraConfig::default()
        };
        let e = PinholeCamera::from_config(&cfg, "camera.jumper").unwrap_err();
        assert_eq!(
            e.to_string(),
            "camera.jumper.hfov_rad must be in (0, 3], got -0.5"
        );
        let cfg = CameraConfig {
            width_px: 0,
            ..CameraConfig::default()
        };
        let e = cfg.validate("camera.rover").unwrap_err();
        assert_eq!(
            e.to_string(),
            "camera.rover.width_px must be in [1, 8192], got 0"
        );
    }
}
