//! Pinhole camera intrinsics and pixel ↔ normalized-coordinate conversions.
//!
//! Pixel convention: the centre of the top-left pixel is at `(0, 0)` (OpenCV convention), `u`
//! grows to the right and `v` downwards. Normalized coordinates are `((u - cx) / fx, (v - cy) / fy)`,
//! i.e. the point on the `z = 1` plane of the camera frame (x right, y down, z forward).
//!
//! The jumper camera is specified by its field of view: 45° over 320 px gives
//! `f = 160 / tan(22.5°) ≈ 386.3 px` (the paper's 521.78 px does not match its own FOV; see
//! DESIGN.md §5), so [`PinholeCamera::from_fov`] derives `f` from the FOV.
//!
//! ```
//! use hopnav_vision::camera::PinholeCamera;
//! let cam = PinholeCamera::from_fov(320, 320, 45f64.to_radians(), 45f64.to_radians()).unwrap();
//! assert!((cam.fx_px - 386.27).abs() < 0.01);
//! let n = cam.pixel_to_normalized(nalgebra::Point2::new(200.0, 100.0));
//! let p = cam.normalized_to_pixel(&n);
//! assert!((p.x - 200.0).abs() < 1e-12 && (p.y - 100.0).abs() < 1e-12);
//! ```

use nalgebra::{Matrix3, Point2, Point3, Vector2, Vector3};

/// Error building a [`PinholeCamera`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// Width or height is zero.
    #[error("image size must be non-zero, got {width_px}x{height_px}")]
    ZeroSize {
        /// Requested width.
        width_px: u32,
        /// Requested height.
        height_px: u32,
    },
    /// A focal length is not finite and positive.
    #[error("focal lengths must be finite and > 0, got fx={fx_px}, fy={fy_px}")]
    BadFocal {
        /// Horizontal focal length.
        fx_px: f64,
        /// Vertical focal length.
        fy_px: f64,
    },
    /// The principal point is not finite.
    #[error("principal point must be finite, got ({cx_px}, {cy_px})")]
    BadPrincipalPoint {
        /// Principal point u.
        cx_px: f64,
        /// Principal point v.
        cy_px: f64,
    },
    /// A field of view is outside `(0, π)`.
    #[error("field of view must be in (0, pi) rad, got {fov_rad}")]
    BadFov {
        /// Offending field of view.
        fov_rad: f64,
    },
}

/// Pinhole intrinsics without distortion (the simulated cameras have none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinholeCamera {
    /// Image width.
    pub width_px: u32,
    /// Image height.
    pub height_px: u32,
    /// Horizontal focal length.
    pub fx_px: f64,
    /// Vertical focal length.
    pub fy_px: f64,
    /// Principal point, horizontal.
    pub cx_px: f64,
    /// Principal point, vertical.
    pub cy_px: f64,
}

impl PinholeCamera {
    /// Builds intrinsics after validating them.
    pub fn new(
        width_px: u32,
        height_px: u32,
        fx_px: f64,
        fy_px: f64,
        cx_px: f64,
        cy_px: f64,
    ) -> Result<Self, CameraError> {
        if width_px == 0 || height_px == 0 {
            return Err(CameraError::ZeroSize {
                width_px,
                height_px,
            });
        }
        if !(fx_px.is_finite() && fy_px.is_finite() && fx_px > 0.0 && fy_px > 0.0) {
            return Err(CameraError::BadFocal { fx_px, fy_px });
        }
        if !(cx_px.is_finite() && cy_px.is_finite()) {
            return Err(CameraError::BadPrincipalPoint { cx_px, cy_px });
        }
        Ok(Self {
            width_px,
            height_px,
            fx_px,
            fy_px,
            cx_px,
            cy_px,
        })
    }

    /// Intrinsics from the full horizontal/vertical field of view, principal point at the image
    /// centre `((w - 1) / 2, (h - 1) / 2)` and `f = (w / 2) / tan(fov / 2)`.
    pub fn from_fov(
        width_px: u32,
        height_px: u32,
        hfov_rad: f64,
        vfov_rad: f64,
    ) -> Result<Self, CameraError> {
        for fov_rad in [hfov_rad, vfov_rad] {
            if !(fov_rad.is_finite() && fov_rad > 0.0 && fov_rad < std::f64::consts::PI) {
                return Err(CameraError::BadFov { fov_rad });
            }
        }
        let fx_px = 0.5 * f64::from(width_px) / (0.5 * hfov_rad).tan();
        let fy_px = 0.5 * f64::from(height_px) / (0.5 * vfov_rad).tan();
        Self::new(
            width_px,
            height_px,
            fx_px,
            fy_px,
            0.5 * (f64::from(width_px) - 1.0),
            0.5 * (f64::from(height_px) - 1.0),
        )
    }

    /// The calibration matrix `K`.
    pub fn k_matrix(&self) -> Matrix3<f64> {
        Matrix3::new(
            self.fx_px, 0.0, self.cx_px, 0.0, self.fy_px, self.cy_px, 0.0, 0.0, 1.0,
        )
    }

    /// Geometric mean focal length; converts pixel thresholds to normalized units.
    pub fn mean_focal_px(&self) -> f64 {
        (self.fx_px * self.fy_px).sqrt()
    }

    /// Pixel → normalized image coordinates.
    pub fn pixel_to_normalized(&self, pixel: Point2<f64>) -> Vector2<f64> {
        Vector2::new(
            (pixel.x - self.cx_px) / self.fx_px,
            (pixel.y - self.cy_px) / self.fy_px,
        )
    }

    /// `f32` pixel (as produced by the tracker) → normalized image coordinates.
    pub fn pixel_f32_to_normalized(&self, pixel: Point2<f32>) -> Vector2<f64> {
        self.pixel_to_normalized(Point2::new(f64::from(pixel.x), f64::from(pixel.y)))
    }

    /// Normalized image coordinates → pixel.
    pub fn normalized_to_pixel(&self, normalized: &Vector2<f64>) -> Point2<f64> {
        Point2::new(
            normalized.x * self.fx_px + self.cx_px,
            normalized.y * self.fy_px + self.cy_px,
        )
    }

    /// Unit bearing vector in the camera frame through a pixel.
    pub fn pixel_to_bearing(&self, pixel: Point2<f64>) -> Vector3<f64> {
        let n = self.pixel_to_normalized(pixel);
        Vector3::new(n.x, n.y, 1.0).normalize()
    }

    /// Projects a camera-frame point; `None` behind (or on) the camera plane.
    pub fn project(&self, point_cam: &Point3<f64>) -> Option<Point2<f64>> {
        if point_cam.z <= f64::EPSILON || !point_cam.coords.iter().all(|v| v.is_finite()) {
            return None;
        }
        Some(self.normalized_to_pixel(&Vector2::new(
            point_cam.x / point_cam.z,
            point_cam.y / point_cam.z,
        )))
    }

    /// Whether a pixel position lies inside the image (pixel centres span `0..=w-1`).
    pub fn contains_pixel(&self, pixel: Point2<f64>) -> bool {
        pixel.x >= 0.0
            && pixel.y >= 0.0
            && pixel.x <= f64::from(self.width_px) - 1.0
            && pixel.y <= f64::from(self.height_px) - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_intrinsics() {
        assert!(PinholeCamera::new(0, 10, 1.0, 1.0, 0.0, 0.0).is_err());
        assert!(PinholeCamera::new(10, 10, -1.0, 1.0, 0.0, 0.0).is_err());
        assert!(PinholeCamera::new(10, 10, 1.0, 1.0, f64::NAN, 0.0).is_err());
        assert!(PinholeCamera::from_fov(10, 10, 0.0, 1.0).is_err());
    }

    #[test]
    fn projection_roundtrip() {
        let cam = PinholeCamera::from_fov(320, 320, 0.785, 0.785).unwrap();
        let p = Point3::new(0.3, -0.2, 4.0);
        let px = cam.project(&p).unwrap();
        let b = cam.pixel_to_bearing(px);
        assert!((b - p.coords.normalize()).norm() < 1e-12);
        assert!(cam.project(&Point3::new(0.0, 0.0, -1.0)).is_none());
    }
}
