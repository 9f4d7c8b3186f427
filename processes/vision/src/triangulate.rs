//! Two-view triangulation (linear DLT and midpoint) with depth, parallax and reprojection checks.
//!
//! Camera 1 is the reference: `P1 = [I | 0]`, `P2 = [R | t]` with
//! `(R, t) = cam2_from_cam1`; inputs are normalized image coordinates; outputs are in camera-1
//! coordinates (metres if `t` is metric, else in units of `|t|`).
//!
//! ```
//! use hopnav_vision::triangulate::{triangulate_checked, TriangulationConfig, Method};
//! use nalgebra::{Isometry3, Point3, Vector2, Vector3};
//! let cam2_from_cam1 = Isometry3::new(Vector3::new(-1.0, 0.0, 0.0), Vector3::zeros());
//! let p = Point3::new(0.5, 0.2, 5.0);
//! let q = cam2_from_cam1 * p;
//! let x1 = Vector2::new(p.x / p.z, p.y / p.z);
//! let x2 = Vector2::new(q.x / q.z, q.y / q.z);
//! let t = triangulate_checked(&cam2_from_cam1, &x1, &x2, &TriangulationConfig::default(), Method::Dlt).unwrap();
//! assert!((t.point_cam1 - p).norm() < 1e-9);
//! ```

use nalgebra::{Isometry3, Matrix4, Point3, RowVector4, Vector2, Vector3};

/// Which linear method to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Homogeneous DLT (smallest singular vector of the 4×4 system).
    Dlt,
    /// Midpoint of the shortest segment between the two rays.
    Midpoint,
}

/// Acceptance thresholds for [`triangulate_checked`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangulationConfig {
    /// Minimum angle between the two viewing rays at the point.
    pub min_parallax_rad: f64,
    /// Maximum squared reprojection error in each view, normalized units² (px² / f²).
    pub max_reprojection_error_sq: f64,
    /// Minimum depth in both cameras (same unit as `t`).
    pub min_depth: f64,
    /// Maximum depth in camera 1 (same unit as `t`).
    pub max_depth: f64,
}

impl Default for TriangulationConfig {
    fn default() -> Self {
        Self {
            min_parallax_rad: 0.5f64.to_radians(),
            max_reprojection_error_sq: (2.0f64 / 400.0).powi(2),
            min_depth: 1e-6,
            max_depth: f64::INFINITY,
        }
    }
}

/// Why a correspondence was not triangulated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TriangulationError {
    /// Rays are parallel, inputs non-finite, or the homogeneous solution is at infinity.
    #[error("degenerate ray geometry")]
    Degenerate,
    /// The point is behind (or too close to) camera 1.
    #[error("point behind camera 1 (depth {depth})")]
    BehindCamera1 {
        /// Depth in camera 1.
        depth: f64,
    },
    /// The point is behind (or too close to) camera 2.
    #[error("point behind camera 2 (depth {depth})")]
    BehindCamera2 {
        /// Depth in camera 2.
        depth: f64,
    },
    /// The rays are too close to parallel for a useful depth.
    #[error("parallax {parallax_rad} rad below the minimum")]
    LowParallax {
        /// Measured parallax.
        parallax_rad: f64,
    },
    /// The point is farther than `max_depth`.
    #[error("depth {depth} beyond the maximum")]
    TooFar {
        /// Depth in camera 1.
        depth: f64,
    },
    /// The point does not reproject onto its observations.
    #[error("reprojection error² {error_sq} above the maximum")]
    LargeReprojectionError {
        /// Larger of the two squared errors (normalized units²).
        error_sq: f64,
    },
}

/// An accepted triangulated point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangulatedPoint {
    /// Position in camera-1 coordinates.
    pub point_cam1: Point3<f64>,
    /// Depth along camera 1's optical axis.
    pub depth_cam1: f64,
    /// Depth along camera 2's optical axis.
    pub depth_cam2: f64,
    /// Angle between the two viewing rays at the point.
    pub parallax_rad: f64,
    /// Larger of the two squared reprojection errors (normalized units²).
    pub reprojection_error_sq: f64,
}

fn homogeneous(x: &Vector2<f64>) -> Vector3<f64> {
    Vector3::new(x.x, x.y, 1.0)
}

/// Depths `(z1, z2)` along both optical axes minimising `|z2 x2 − (z1 R x1 + t)|` (least squares
/// on the two rays). `None` for parallel rays or non-finite input. Cheap: used for cheirality.
pub fn two_view_depths(
    cam2_from_cam1: &Isometry3<f64>,
    x1: &Vector2<f64>,
    x2: &Vector2<f64>,
) -> Option<(f64, f64)> {
    let a = cam2_from_cam1.rotation * homogeneous(x1);
    let b = homogeneous(x2);
    let t = cam2_from_cam1.translation.vector;
    let (aa, ab, bb) = (a.dot(&a), a.dot(&b), b.dot(&b));
    let (at, bt) = (a.dot(&t), b.dot(&t));
    let det = aa * bb - ab * ab;
    if !(det.is_finite() && det > 1e-14 * aa * bb) {
        return None;
    }
    let z1 = (-at * bb + ab * bt) / det;
    let z2 = (aa * bt - ab * at) / det;
    Some((z1, z2))
}

/// Midpoint triangulation in camera-1 coordinates.
pub fn triangulate_midpoint(
    cam2_from_cam1: &Isometry3<f64>,
    x1: &Vector2<f64>,
    x2: &Vector2<f64>,
) -> Option<Point3<f64>> {
    let (z1, z2) = two_view_depths(cam2_from_cam1, x1, x2)?;
    let on_ray1 = homogeneous(x1) * z1;
    let on_ray2 = cam2_from_cam1.inverse_transform_point(&Point3::from(homogeneous(x2) * z2));
    Some(Point3::from((on_ray1 + on_ray2.coords) * 0.5))
}

/// Linear (DLT) triangulation in camera-1 coordinates.
pub fn triangulate_dlt(
    cam2_from_cam1: &Isometry3<f64>,
    x1: &Vector2<f64>,
    x2: &Vector2<f64>,
) -> Option<Point3<f64>> {
    let p2 = cam2_from_cam1.to_homogeneous();
    let row = |i: usize| RowVector4::new(p2[(i, 0)], p2[(i, 1)], p2[(i, 2)], p2[(i, 3)]);
    let a = Matrix4::from_rows(&[
        RowVector4::new(-1.0, 0.0, x1.x, 0.0),
        RowVector4::new(0.0, -1.0, x1.y, 0.0),
        row(2) * x2.x - row(0),
        row(2) * x2.y - row(1),
    ]);
    if !a.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = a.try_svd(false, true, 1e-15, 200)?;
    let v_t = svd.v_t?;
    let (i_min, _) = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))?;
    let h = v_t.row(i_min);
    if h[3].abs() < 1e-12 * h.norm() {
        return None;
    }
    Some(Point3::new(h[0] / h[3], h[1] / h[3], h[2] / h[3]))
}

/// Angle between the viewing rays from both camera centres to `point_cam1`.
pub fn parallax_rad(cam2_from_cam1: &Isometry3<f64>, point_cam1: &Point3<f64>) -> f64 {
    let center2_cam1 = cam2_from_cam1.inverse_transform_point(&Point3::origin());
    let r1 = point_cam1.coords;
    let r2 = point_cam1 - center2_cam1;
    let denom = r1.norm() * r2.norm();
    if denom <= 0.0 {
        return 0.0;
    }
    (r1.dot(&r2) / denom).clamp(-1.0, 1.0).acos()
}

/// Triangulates and applies the depth, parallax and reprojection checks of `config`.
pub fn triangulate_checked(
    cam2_from_cam1: &Isometry3<f64>,
    x1: &Vector2<f64>,
    x2: &Vector2<f64>,
    config: &TriangulationConfig,
    method: Method,
) -> Result<TriangulatedPoint, TriangulationError> {
    let point_cam1 = match method {
        Method::Dlt => triangulate_dlt(cam2_from_cam1, x1, x2),
        Method::Midpoint => triangulate_midpoint(cam2_from_cam1, x1, x2),
    }
    .filter(|p| p.coords.iter().all(|v| v.is_finite()))
    .ok_or(TriangulationError::Degenerate)?;
    let point_cam2 = cam2_from_cam1 * point_cam1;
    let (depth_cam1, depth_cam2) = (point_cam1.z, point_cam2.z);
    if depth_cam1 < config.min_depth {
        return Err(TriangulationError::BehindCamera1 { depth: depth_cam1 });
    }
    if depth_cam2 < config.min_depth {
        return Err(TriangulationError::BehindCamera2 { depth: depth_cam2 });
    }
    if depth_cam1 > config.max_depth {
        return Err(TriangulationError::TooFar { depth: depth_cam1 });
    }
    let parallax = parallax_rad(cam2_from_cam1, &point_cam1);
    if parallax < config.min_parallax_rad {
        return Err(TriangulationError::LowParallax {
            parallax_rad: parallax,
        });
    }
    let e1 =
        (Vector2::new(point_cam1.x / depth_cam1, point_cam1.y / depth_cam1) - x1).norm_squared();
    let e2 =
        (Vector2::new(point_cam2.x / depth_cam2, point_cam2.y / depth_cam2) - x2).norm_squared();
    let error_sq = e1.max(e2);
    if error_sq > config.max_reprojection_error_sq {
        return Err(TriangulationError::LargeReprojectionError { error_sq });
    }
    Ok(TriangulatedPoint {
        point_cam1,
        depth_cam1,
        depth_cam2,
        parallax_rad: parallax,
        reprojection_error_sq: error_sq,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project(p: &Point3<f64>) -> Vector2<f64> {
        Vector2::new(p.x / p.z, p.y / p.z)
    }

    #[test]
    fn dlt_and_midpoint_agree_on_exact_data() {
        let pose = Isometry3::new(Vector3::new(-0.8, 0.1, 0.2), Vector3::new(0.05, -0.1, 0.02));
        for p in [Point3::new(0.3, -0.4, 6.0), Point3::new(-2.0, 1.0, 3.0)] {
            let (x1, x2) = (project(&p), project(&(pose * p)));
            let a = triangulate_dlt(&pose, &x1, &x2).unwrap();
            let b = triangulate_midpoint(&pose, &x1, &x2).unwrap();
            assert!((a - p).norm() < 1e-8 && (b - p).norm() < 1e-8);
            let (z1, z2) = two_view_depths(&pose, &x1, &x2).unwrap();
            assert!((z1 - p.z).abs() < 1e-8 && (z2 - (pose * p).z).abs() < 1e-8);
        }
    }

    #[test]
    fn checks_reject_bad_points() {
        let pose = Isometry3::new(Vector3::new(-1.0, 0.0, 0.0), Vector3::zeros());
        let cfg = TriangulationConfig::default();
        // Point behind both cameras: its projections are those of the mirrored point.
        let p = Point3::new(0.5, 0.2, -5.0);
        let (x1, x2) = (project(&p), project(&(pose * p)));
        assert!(matches!(
            triangulate_checked(&pose, &x1, &x2, &cfg, Method::Dlt),
            Err(TriangulationError::BehindCamera1 { .. })
        ));
        // Far point: tiny parallax.
        let far = Point3::new(0.0, 0.0, 1000.0);
        let (x1, x2) = (project(&far), project(&(pose * far)));
        assert!(matches!(
            triangulate_checked(&pose, &x1, &x2, &cfg, Method::Midpoint),
            Err(TriangulationError::LowParallax { .. })
        ));
        // Zero baseline: parallel rays.
        let still = Isometry3::identity();
        let x = Vector2::new(0.1, 0.1);
        assert!(two_view_depths(&still, &x, &x).is_none());
        assert!(triangulate_checked(&still, &x, &x, &cfg, Method::Midpoint).is_err());
        let nan = Vector2::new(f64::NAN, 0.0);
        assert!(triangulate_checked(&pose, &nan, &x, &cfg, Method::Dlt).is_err());
    }
}
