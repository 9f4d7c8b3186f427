//! World-frame feature cloud of a keyframe pair: triangulation of the RANSAC inliers with the
//! metric relative pose, and the height of each point above a robust local ground plane.

use hopnav_vision::triangulate::{Method, TriangulationConfig, parallax_rad, triangulate_checked};
use nalgebra::{Isometry3, Matrix3, Point3, Vector2, Vector3};

/// A triangulated feature in the world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldPoint {
    /// Position, world frame, metres.
    pub position_m: Point3<f64>,
    /// Height above the local ground plane fitted to the cloud, metres (`None` if no plane).
    pub height_above_ground_m: Option<f64>,
    /// One-sigma range uncertainty from a 1 px ray error at the pair's parallax, metres.
    pub depth_sigma_m: f64,
}

/// Triangulates `x1[i] ↔ x2[i]` for `i` in `indices` with the metric `cam2_from_cam1` and
/// appends the accepted points, in the world frame, to `out`.
pub fn triangulate_cloud(
    world_from_cam1: &Isometry3<f64>,
    cam2_from_cam1: &Isometry3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
    focal_px: f64,
    out: &mut Vec<WorldPoint>,
) {
    let cfg = TriangulationConfig {
        min_parallax_rad: 1f64.to_radians(),
        max_reprojection_error_sq: (2.0 / focal_px.max(1.0)).powi(2),
        min_depth: 0.05,
        max_depth: 500.0,
    };
    for &i in indices {
        let (Some(a), Some(b)) = (x1.get(i), x2.get(i)) else {
            continue;
        };
        if let Ok(p) = triangulate_checked(cam2_from_cam1, a, b, &cfg, Method::Midpoint) {
            // Range error ≈ range · ray error / parallax (small-angle triangulation).
            let parallax_rad = parallax_rad(cam2_from_cam1, &p.point_cam1).max(1e-6);
            let depth_sigma_m = p.point_cam1.coords.norm() / focal_px.max(1.0) / parallax_rad;
            out.push(WorldPoint {
                position_m: world_from_cam1 * p.point_cam1,
                height_above_ground_m: None,
                depth_sigma_m,
            });
        }
    }
}

/// Fits `z = a x + b y + c` to the lower part of the cloud (three passes of least squares that
/// drop points more than 2 robust σ above it: rocks) and fills `height_above_ground_m`.
/// Returns the plane coefficients, or `None` (heights left empty) with fewer than 10 points.
pub fn fill_heights_above_ground(points: &mut [WorldPoint]) -> Option<Vector3<f64>> {
    if points.len() < 10 {
        return None;
    }
    let mut use_point = vec![true; points.len()];
    let mut plane = None;
    let mut residuals = vec![0.0; points.len()];
    for _ in 0..3 {
        let mut n = Matrix3::zeros();
        let mut r = Vector3::zeros();
        for (p, _) in points.iter().zip(&use_point).filter(|(_, u)| **u) {
            let a = Vector3::new(p.position_m.x, p.position_m.y, 1.0);
            n += a * a.transpose();
            r += a * p.position_m.z;
        }
        let coeffs = n.try_inverse().map(|inv| inv * r)?;
        for (res, p) in residuals.iter_mut().zip(points.iter()) {
            *res =
                p.position_m.z - (coeffs.x * p.position_m.x + coeffs.y * p.position_m.y + coeffs.z);
        }
        let mut abs: Vec<f64> = residuals.iter().map(|v| v.abs()).collect();
        abs.sort_by(f64::total_cmp);
        let sigma = 1.4826 * abs[abs.len() / 2] + 1e-3;
        for (u, res) in use_point.iter_mut().zip(&residuals) {
            *u = *res < 2.0 * sigma;
        }
        plane = Some(coeffs);
    }
    let plane = plane?;
    // Rolling terrain bends away from one plane: measure each point against the low quartile
    // of its neighbours' residuals (same cloud, so the same pose and scale), which follows the
    // local ground and leaves rocks standing.
    let mut neighbour_residuals = Vec::with_capacity(points.len());
    let local_offsets: Vec<f64> = points
        .iter()
        .map(|p| {
            neighbour_residuals.clear();
            neighbour_residuals.extend(points.iter().zip(&residuals).filter_map(|(q, res)| {
                let dx = q.position_m.x - p.position_m.x;
                let dy = q.position_m.y - p.position_m.y;
                (dx * dx + dy * dy <= LOCAL_GROUND_RADIUS_M * LOCAL_GROUND_RADIUS_M).then_some(*res)
            }));
            if neighbour_residuals.len() < 8 {
                return 0.0;
            }
            neighbour_residuals.sort_by(f64::total_cmp);
            neighbour_residuals[neighbour_residuals.len() / 4]
        })
        .collect();
    for ((p, res), offset) in points.iter_mut().zip(&residuals).zip(&local_offsets) {
        p.height_above_ground_m = Some(res - offset);
    }
    Some(plane)
}

/// Neighbourhood of the local ground estimate, metres (about a rock's size, well below the
/// terrain's relief wavelength).
const LOCAL_GROUND_RADIUS_M: f64 = 2.5;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ground_plane_ignores_rocks() {
        let mut pts: Vec<WorldPoint> = (0..200)
            .map(|i| {
                let (x, y) = ((i % 20) as f64, (i / 20) as f64);
                let rock = if i % 17 == 0 { 0.8 } else { 0.0 };
                WorldPoint {
                    depth_sigma_m: 0.0,
                    position_m: Point3::new(x, y, 0.1 * x + 2.0 + rock),
                    height_above_ground_m: None,
                }
            })
            .collect();
        let plane = fill_heights_above_ground(&mut pts).unwrap();
        assert!((plane.x - 0.1).abs() < 1e-6 && (plane.z - 2.0).abs() < 1e-6);
        assert!((pts[17].height_above_ground_m.unwrap() - 0.8).abs() < 1e-6);
        assert!(pts[1].height_above_ground_m.unwrap().abs() < 1e-6);
    }
}
