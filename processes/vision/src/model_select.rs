//! Essential-vs-homography model selection (ORB-SLAM style score ratio).
//!
//! Each model is scored over all correspondences with a truncated, noise-normalised error:
//!
//! - essential: per image, squared distance to the epipolar line (1 DOF, threshold
//!   `T_E = 3.84`, the 95 % χ²₁ quantile);
//! - homography: per image, squared transfer error (2 DOF, threshold `T_H = 5.99`, χ²₂);
//!
//! and a point contributes `Γ − d²/σ²` per image while `d²/σ² < T` (with `Γ = T_H` for both so
//! the scores are comparable). `R_H = S_H / (S_H + S_E)`; above the threshold (ORB-SLAM uses
//! 0.40) the scene is treated as planar (or rotation-only) and the homography is decomposed.
//! The σ used is the per-image noise times √2, because both images contribute noise.
//!
//! DESIGN.md §5: on the jumper's near-planar ground the essential matrix picks the wrong twofold
//! solution; the homography with the gravity normal does not.
//!
//! ```
//! use hopnav_vision::model_select::{homography_ratio, choose_model, ModelChoice};
//! let r = homography_ratio(60.0, 40.0);
//! assert!((r - 0.6).abs() < 1e-12);
//! assert_eq!(choose_model(r, 0.40), ModelChoice::Homography);
//! ```

use crate::essential::epipolar_distances_sq;
use crate::homography::transfer_errors_sq;
use nalgebra::{Matrix3, Vector2};

/// χ² 95 % threshold, 1 degree of freedom.
pub const CHI2_1DOF_95: f64 = 3.841;
/// χ² 95 % threshold, 2 degrees of freedom.
pub const CHI2_2DOF_95: f64 = 5.991;

/// Which model describes the scene better.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelChoice {
    /// General 3-D scene: use the essential matrix.
    Essential,
    /// Planar scene or pure rotation: use the homography.
    Homography,
}

/// `inv_sigma_sq` for the scores: `1 / (2 σ²)` with σ the per-image noise in normalized units.
pub fn inv_sigma_sq(sigma_norm: f64) -> f64 {
    1.0 / (2.0 * sigma_norm * sigma_norm).max(f64::MIN_POSITIVE)
}

/// Score `S_E` of an essential matrix over all correspondences (higher is better).
pub fn score_essential(
    e: &Matrix3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    inv_sigma_sq: f64,
) -> f64 {
    two_way_score(x1, x2, inv_sigma_sq, CHI2_1DOF_95, |a, b| {
        epipolar_distances_sq(e, a, b)
    })
}

/// Score `S_H` of a homography (with its inverse) over all correspondences (higher is better).
pub fn score_homography(
    h: &Matrix3<f64>,
    h_inv: &Matrix3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    inv_sigma_sq: f64,
) -> f64 {
    two_way_score(x1, x2, inv_sigma_sq, CHI2_2DOF_95, |a, b| {
        transfer_errors_sq(h, h_inv, a, b)
    })
}

/// Sum over all correspondences of the truncated scores of both squared errors (one in each
/// image) that `errors_sq` gives for a correspondence; `threshold` is the χ² rejection bound.
fn two_way_score(
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    inv_sigma_sq: f64,
    threshold: f64,
    errors_sq: impl Fn(&Vector2<f64>, &Vector2<f64>) -> (f64, f64),
) -> f64 {
    x1.iter()
        .zip(x2)
        .map(|(a, b)| {
            let (first, second) = errors_sq(a, b);
            truncated(first * inv_sigma_sq, threshold) + truncated(second * inv_sigma_sq, threshold)
        })
        .sum()
}

fn truncated(chi2: f64, threshold: f64) -> f64 {
    if chi2 < threshold {
        CHI2_2DOF_95 - chi2
    } else {
        0.0
    }
}

/// `R_H = S_H / (S_H + S_E)`; 0 when both scores are zero.
pub fn homography_ratio(score_homography: f64, score_essential: f64) -> f64 {
    let total = score_homography + score_essential;
    if total > 0.0 && total.is_finite() {
        score_homography / total
    } else {
        0.0
    }
}

/// Homography if `ratio > threshold`.
pub fn choose_model(ratio: f64, threshold: f64) -> ModelChoice {
    if ratio > threshold {
        ModelChoice::Homography
    } else {
        ModelChoice::Essential
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::essential::essential_from_pose;
    use crate::homography::homography_from_plane;
    use nalgebra::{Isometry3, Point3, Unit, Vector3};

    #[test]
    fn general_scene_prefers_essential_plane_prefers_homography() {
        let pose = Isometry3::new(Vector3::new(0.5, 0.0, 0.1), Vector3::new(0.0, 0.05, 0.0));
        let e = essential_from_pose(&pose);
        let n = Unit::new_normalize(Vector3::new(0.0, 0.0, 1.0));
        let h = homography_from_plane(&pose, &n, 5.0);
        let h_inv = h.try_inverse().unwrap();
        let inv = inv_sigma_sq(1.0 / 400.0);
        let pts = crate::synthetic::random_points_in_box(100, 2.0, 3.0, 9.0, 1);
        let proj = |p: &Point3<f64>| Vector2::new(p.x / p.z, p.y / p.z);
        let x1: Vec<_> = pts.iter().map(proj).collect();
        let x2: Vec<_> = pts.iter().map(|p| proj(&(pose * p))).collect();
        let ratio = homography_ratio(
            score_homography(&h, &h_inv, &x1, &x2, inv),
            score_essential(&e, &x1, &x2, inv),
        );
        assert!(ratio < 0.2, "{ratio}");
        // Points on the plane z = 5: both fit, the ratio is 0.5 on exact data.
        let plane: Vec<_> = pts.iter().map(|p| Point3::new(p.x, p.y, 5.0)).collect();
        let x1: Vec<_> = plane.iter().map(proj).collect();
        let x2: Vec<_> = plane.iter().map(|p| proj(&(pose * p))).collect();
        let ratio = homography_ratio(
            score_homography(&h, &h_inv, &x1, &x2, inv),
            score_essential(&e, &x1, &x2, inv),
        );
        assert!((ratio - 0.5).abs() < 1e-6, "{ratio}");
        assert_eq!(homography_ratio(0.0, 0.0), 0.0);
    }
}
