//! Essential matrix: construction, error measures, decomposition and cheirality.
//!
//! `E = [t]ₓ R` for `(R, t) = cam2_from_cam1`, so `x2ᵀ E x1 = 0` for normalized homogeneous
//! image points. Solvers live in [`eight_point`] and [`five_point`].
//!
//! ```
//! use hopnav_vision::essential::{essential_from_pose, decompose_essential, recover_pose};
//! use nalgebra::{Isometry3, Point3, Vector2, Vector3};
//! let pose = Isometry3::new(Vector3::new(0.6, 0.0, 0.8), Vector3::new(0.0, 0.1, 0.0));
//! let e = essential_from_pose(&pose);
//! assert_eq!(decompose_essential(&e).unwrap().len(), 4);
//! let pts: Vec<Point3<f64>> = (0..20).map(|i| Point3::new(i as f64 * 0.1 - 1.0, 0.3, 5.0 + i as f64 * 0.2)).collect();
//! let x1: Vec<_> = pts.iter().map(|p| Vector2::new(p.x / p.z, p.y / p.z)).collect();
//! let x2: Vec<_> = pts.iter().map(|p| { let q = pose * p; Vector2::new(q.x / q.z, q.y / q.z) }).collect();
//! let idx: Vec<usize> = (0..20).collect();
//! let rec = recover_pose(&e, &x1, &x2, &idx).unwrap();
//! assert!((rec.cam2_from_cam1.rotation.angle_to(&pose.rotation)) < 1e-9);
//! ```

pub mod eight_point;
pub mod five_point;
pub mod refine;

use crate::triangulate::two_view_depths;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector2, Vector3};

/// Skew-symmetric cross-product matrix `[v]ₓ`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// `E = [t]ₓ R` of a relative pose (not normalized).
pub fn essential_from_pose(cam2_from_cam1: &Isometry3<f64>) -> Matrix3<f64> {
    skew(&cam2_from_cam1.translation.vector) * cam2_from_cam1.rotation.to_rotation_matrix().matrix()
}

/// Squared Sampson distance of a correspondence to `E` (normalized units²): first-order
/// geometric error, the RANSAC residual.
pub fn sampson_error_sq(e: &Matrix3<f64>, x1: &Vector2<f64>, x2: &Vector2<f64>) -> f64 {
    let x1h = Vector3::new(x1.x, x1.y, 1.0);
    let x2h = Vector3::new(x2.x, x2.y, 1.0);
    let ex1 = e * x1h;
    let etx2 = e.transpose() * x2h;
    let num = x2h.dot(&ex1);
    let denom = ex1.x * ex1.x + ex1.y * ex1.y + etx2.x * etx2.x + etx2.y * etx2.y;
    if denom <= f64::MIN_POSITIVE {
        return f64::INFINITY;
    }
    num * num / denom
}

/// Squared distances `(d1², d2²)` of `x1` to the epipolar line `Eᵀx2` and of `x2` to `E x1`
/// (normalized units²); used for model-selection scores.
pub fn epipolar_distances_sq(e: &Matrix3<f64>, x1: &Vector2<f64>, x2: &Vector2<f64>) -> (f64, f64) {
    let x1h = Vector3::new(x1.x, x1.y, 1.0);
    let x2h = Vector3::new(x2.x, x2.y, 1.0);
    let l2 = e * x1h;
    let l1 = e.transpose() * x2h;
    let num = x2h.dot(&l2);
    let n2 = l2.x * l2.x + l2.y * l2.y;
    let n1 = l1.x * l1.x + l1.y * l1.y;
    let d = |n: f64| {
        if n <= f64::MIN_POSITIVE {
            f64::INFINITY
        } else {
            num * num / n
        }
    };
    (d(n1), d(n2))
}

/// Closest essential matrix (two equal singular values, one zero) to `m`, scaled to unit
/// Frobenius norm. `None` for non-finite input or rank < 2.
pub fn project_to_essential(m: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = m.try_svd(true, true, 1e-15, 200)?;
    let (u, v_t) = (svd.u?, svd.v_t?);
    let s = svd.singular_values;
    if s[1] <= 1e-12 * s[0].max(f64::MIN_POSITIVE) {
        return None;
    }
    let d = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0));
    Some(u * d * v_t / 2f64.sqrt())
}

/// The four `cam2_from_cam1` candidates `(R₁, t), (R₁, −t), (R₂, t), (R₂, −t)` of an essential
/// matrix, with unit translation. `None` if `e` is not (close to) rank 2.
pub fn decompose_essential(e: &Matrix3<f64>) -> Option<[Isometry3<f64>; 4]> {
    if !e.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = e.try_svd(true, true, 1e-15, 200)?;
    let (mut u, mut v_t) = (svd.u?, svd.v_t?);
    let s = svd.singular_values;
    if s[1] <= 1e-9 * s[0].max(f64::MIN_POSITIVE) {
        return None;
    }
    if u.determinant() < 0.0 {
        u = -u;
    }
    if v_t.determinant() < 0.0 {
        v_t = -v_t;
    }
    let w = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let r1 = Rotation3::from_matrix_unchecked(u * w * v_t);
    let r2 = Rotation3::from_matrix_unchecked(u * w.transpose() * v_t);
    let t = u.column(2).into_owned();
    let make = |r: &Rotation3<f64>, t: Vector3<f64>| {
        Isometry3::from_parts(
            Translation3::from(t),
            UnitQuaternion::from_rotation_matrix(r),
        )
    };
    Some([make(&r1, t), make(&r1, -t), make(&r2, t), make(&r2, -t)])
}

/// The pose chosen by the cheirality test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecoveredPose {
    /// Relative pose with unit-norm translation.
    pub cam2_from_cam1: Isometry3<f64>,
    /// Correspondences in front of both cameras for the chosen candidate.
    pub num_in_front: usize,
    /// Same count for the runner-up candidate (a close second means an unreliable choice).
    pub num_in_front_runner_up: usize,
}

/// Error recovering a pose from an essential matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum PoseRecoveryError {
    /// `E` is not a valid essential matrix (rank, non-finite).
    #[error("matrix is not a valid essential matrix")]
    InvalidEssential,
    /// No correspondence lies in front of both cameras for any candidate.
    #[error("no candidate puts any point in front of both cameras")]
    NoPointInFront,
}

/// Cheirality test: the candidate of [`decompose_essential`] that puts the most of the
/// `indices` correspondences in front of both cameras.
pub fn recover_pose(
    e: &Matrix3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> Result<RecoveredPose, PoseRecoveryError> {
    let candidates = decompose_essential(e).ok_or(PoseRecoveryError::InvalidEssential)?;
    let mut counts = [0usize; 4];
    for (k, pose) in candidates.iter().enumerate() {
        counts[k] = count_in_front(pose, x1, x2, indices);
    }
    let mut order = [0usize, 1, 2, 3];
    order.sort_by(|a, b| counts[*b].cmp(&counts[*a]));
    if counts[order[0]] == 0 {
        return Err(PoseRecoveryError::NoPointInFront);
    }
    Ok(RecoveredPose {
        cam2_from_cam1: candidates[order[0]],
        num_in_front: counts[order[0]],
        num_in_front_runner_up: counts[order[1]],
    })
}

/// Number of `indices` correspondences with positive depth in both cameras under `pose`.
pub fn count_in_front(
    pose: &Isometry3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> usize {
    indices
        .iter()
        .filter(|&&i| match (x1.get(i), x2.get(i)) {
            (Some(a), Some(b)) => {
                matches!(two_view_depths(pose, a, b), Some((z1, z2)) if z1 > 0.0 && z2 > 0.0)
            }
            _ => false,
        })
        .count()
}

/// Coefficients of the epipolar constraint `x2ᵀ E x1 = 0` of one correspondence, in the
/// row-major order of `E`'s entries: `(x1, y1)` in view 1, `(x2, y2)` in view 2.
pub(crate) fn epipolar_row([x1, y1]: [f64; 2], [x2, y2]: [f64; 2]) -> [f64; 9] {
    [x2 * x1, x2 * y1, x2, y2 * x1, y2 * y1, y2, x1, y1, 1.0]
}

/// Whether every index in `indices` picks a correspondence of `x1 ↔ x2` with finite
/// coordinates in both views.
pub(crate) fn finite_correspondences(
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> bool {
    indices.iter().all(|&i| {
        i < x1.len() && i < x2.len() && x1[i].iter().chain(x2[i].iter()).all(|v| v.is_finite())
    })
}

/// The correspondences `indices` of `x1 ↔ x2` as homogeneous points, each mapped by its
/// view's normalization (`t1`, `t2`).
pub(crate) fn normalized_pairs<'a>(
    x1: &'a [Vector2<f64>],
    x2: &'a [Vector2<f64>],
    indices: &'a [usize],
    t1: &'a Matrix3<f64>,
    t2: &'a Matrix3<f64>,
) -> impl Iterator<Item = (Vector3<f64>, Vector3<f64>)> + 'a {
    indices
        .iter()
        .map(move |&i| (t1 * x1[i].push(1.0), t2 * x2[i].push(1.0)))
}

/// Hartley normalisation of the selected points: `T` maps them to zero mean and mean distance
/// `√2`. `None` if all points coincide or a value is non-finite.
pub(crate) fn hartley_normalization(
    points: &[Vector2<f64>],
    indices: &[usize],
) -> Option<Matrix3<f64>> {
    if indices.is_empty() {
        return None;
    }
    let mut centroid = Vector2::zeros();
    for &i in indices {
        centroid += points.get(i)?;
    }
    centroid /= indices.len() as f64;
    let mut mean_dist = 0.0;
    for &i in indices {
        mean_dist += (points.get(i)? - centroid).norm();
    }
    mean_dist /= indices.len() as f64;
    if !(mean_dist.is_finite() && mean_dist > 1e-12) {
        return None;
    }
    let s = 2f64.sqrt() / mean_dist;
    Some(Matrix3::new(
        s,
        0.0,
        -s * centroid.x,
        0.0,
        s,
        -s * centroid.y,
        0.0,
        0.0,
        1.0,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decomposition_contains_true_pose() {
        let pose = Isometry3::new(Vector3::new(0.2, -0.5, 0.3), Vector3::new(0.1, -0.2, 0.05));
        let e = essential_from_pose(&pose);
        let t_true = pose.translation.vector.normalize();
        let found = decompose_essential(&e).unwrap().iter().any(|c| {
            c.rotation.angle_to(&pose.rotation) < 1e-9
                && (c.translation.vector - t_true).norm() < 1e-9
        });
        assert!(found);
        assert!(decompose_essential(&Matrix3::zeros()).is_none());
        assert!(decompose_essential(&Matrix3::from_element(f64::NAN)).is_none());
        let p = project_to_essential(&(e * 3.0)).unwrap();
        assert!((p.norm() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn sampson_is_zero_on_exact_data() {
        let pose = Isometry3::new(Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 0.1, 0.0));
        let e = essential_from_pose(&pose);
        let p = nalgebra::Point3::new(0.3, 0.1, 4.0);
        let q = pose * p;
        let x1 = Vector2::new(p.x / p.z, p.y / p.z);
        let x2 = Vector2::new(q.x / q.z, q.y / q.z);
        assert!(sampson_error_sq(&e, &x1, &x2) < 1e-20);
        let (d1, d2) = epipolar_distances_sq(&e, &x1, &x2);
        assert!(d1 < 1e-20 && d2 < 1e-20);
        let off = x2 + Vector2::new(0.0, 0.01);
        assert!(sampson_error_sq(&e, &x1, &off) > 1e-6);
    }
}
