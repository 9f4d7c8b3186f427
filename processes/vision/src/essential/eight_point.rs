//! Normalized 8-point algorithm for the essential matrix (Hartley normalisation, least squares
//! over any number ≥ 8 of correspondences, projection onto the essential manifold).
//!
//! Used as the selectable minimal solver (8 points) and as the local-optimisation refit on all
//! inliers in RANSAC. Degenerate on planar scenes (that is what the homography branch is for).
//!
//! ```
//! use hopnav_vision::essential::{eight_point::essential_eight_point, sampson_error_sq};
//! use nalgebra::{Isometry3, Point3, Vector2, Vector3};
//! let pose = Isometry3::new(Vector3::new(1.0, 0.2, 0.1), Vector3::new(0.0, 0.05, 0.02));
//! let pts: Vec<_> = (0..12).map(|i| Point3::new((i % 4) as f64 - 1.5, (i / 4) as f64 - 1.0, 4.0 + (i % 5) as f64)).collect();
//! let x1: Vec<_> = pts.iter().map(|p| Vector2::new(p.x / p.z, p.y / p.z)).collect();
//! let x2: Vec<_> = pts.iter().map(|p| { let q = pose * p; Vector2::new(q.x / q.z, q.y / q.z) }).collect();
//! let idx: Vec<usize> = (0..12).collect();
//! let e = essential_eight_point(&x1, &x2, &idx).unwrap();
//! assert!(sampson_error_sq(&e, &x1[0], &x2[0]) < 1e-18);
//! ```

use super::{
    epipolar_row, finite_correspondences, hartley_normalization, normalized_pairs,
    project_to_essential,
};
use nalgebra::{Matrix3, SMatrix, SVector, Vector2};

/// Error of the 8-point solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum EightPointError {
    /// Fewer than 8 correspondences.
    #[error("8-point needs at least 8 correspondences, got {got}")]
    TooFewPoints {
        /// Correspondences given.
        got: usize,
    },
    /// An index is out of range or a coordinate is not finite.
    #[error("bad input: index out of range or non-finite coordinate")]
    BadInput,
    /// The configuration is degenerate (coincident points, rank-deficient system).
    #[error("degenerate configuration")]
    Degenerate,
}

/// Least-squares essential matrix from the correspondences `indices` of `x1 ↔ x2`
/// (normalized image coordinates), unit Frobenius norm.
pub fn essential_eight_point(
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> Result<Matrix3<f64>, EightPointError> {
    if indices.len() < 8 {
        return Err(EightPointError::TooFewPoints { got: indices.len() });
    }
    if !finite_correspondences(x1, x2, indices) {
        return Err(EightPointError::BadInput);
    }
    let t1 = hartley_normalization(x1, indices).ok_or(EightPointError::Degenerate)?;
    let t2 = hartley_normalization(x2, indices).ok_or(EightPointError::Degenerate)?;
    let mut ata = SMatrix::<f64, 9, 9>::zeros();
    for (a, b) in normalized_pairs(x1, x2, indices, &t1, &t2) {
        let row = SVector::<f64, 9>::from(epipolar_row([a.x, a.y], [b.x, b.y]));
        ata += row * row.transpose();
    }
    let f = smallest_eigenvector(ata).ok_or(EightPointError::Degenerate)?;
    let f_norm = Matrix3::new(f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8]);
    let e = t2.transpose() * f_norm * t1;
    project_to_essential(&e).ok_or(EightPointError::Degenerate)
}

/// Unit eigenvector of the smallest eigenvalue of a symmetric 9×9 matrix.
pub(crate) fn smallest_eigenvector(m: SMatrix<f64, 9, 9>) -> Option<SVector<f64, 9>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let eig = m.try_symmetric_eigen(1e-15, 500)?;
    let (i_min, _) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))?;
    Some(eig.eigenvectors.column(i_min).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::essential::{essential_from_pose, recover_pose};
    use nalgebra::{Isometry3, Vector3};

    #[test]
    fn rejects_too_few_and_bad_input() {
        let x = vec![Vector2::new(0.1, 0.2); 8];
        let idx: Vec<usize> = (0..7).collect();
        assert!(matches!(
            essential_eight_point(&x, &x, &idx),
            Err(EightPointError::TooFewPoints { got: 7 })
        ));
        let idx: Vec<usize> = (0..8).collect();
        assert!(essential_eight_point(&x, &x, &idx).is_err());
        let idx = [0, 1, 2, 3, 4, 5, 6, 99];
        assert_eq!(
            essential_eight_point(&x, &x, &idx),
            Err(EightPointError::BadInput)
        );
    }

    #[test]
    fn exact_recovery() {
        let pose = Isometry3::new(Vector3::new(-0.3, 0.1, 1.0), Vector3::new(0.1, -0.05, 0.2));
        let pts = crate::synthetic::random_points_in_box(30, 3.0, 3.0, 9.0, 4);
        let (x1, x2) = crate::synthetic::exact_views(&pose, &pts);
        let idx: Vec<usize> = (0..30).collect();
        let e = essential_eight_point(&x1, &x2, &idx).unwrap();
        let truth = essential_from_pose(&pose).normalize();
        assert!((e - truth).norm().min((e + truth).norm()) < 1e-8);
        let rec = recover_pose(&e, &x1, &x2, &idx).unwrap();
        assert_eq!(rec.num_in_front, 30);
        assert!(rec.cam2_from_cam1.rotation.angle_to(&pose.rotation) < 1e-8);
    }
}
