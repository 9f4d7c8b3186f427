//! Normalized DLT homography and its decomposition into `(R, t/d, n)` candidates.
//!
//! Conventions: `H` maps view 1 to view 2 in normalized coordinates, `x2 ~ H x1`. For a plane
//! `nᵀ X₁ = d` (unit `n` in camera 1 pointing from the camera towards the plane, `d > 0`) and
//! `(R, t) = cam2_from_cam1`: `H = R + (t / d) nᵀ`. On the ground seen from above, `n` is the
//! gravity direction (down) expressed in camera 1.
//!
//! Decomposition follows Ma, Soatto, Košecká & Sastry (*An Invitation to 3-D Vision*, §5.3):
//! after scaling `H` so its middle singular value is 1 and fixing its sign so that
//! `x2ᵀ H x1 > 0`, the eigen-decomposition of `HᵀH` yields four `(R, t/d, n)` solutions; the
//! requirement that the observed points lie in front of camera 1 (`nᵀ x1 > 0`) leaves two, and
//! a normal prior (gravity) picks one. If all singular values are equal the motion is a pure
//! rotation (`t = 0`, `n` undefined).
//!
//! ```
//! use hopnav_vision::homography::{homography_from_plane, decompose_homography};
//! use nalgebra::{Isometry3, Vector2, Vector3, Unit};
//! let pose = Isometry3::new(Vector3::new(0.3, 0.0, 0.1), Vector3::new(0.0, 0.1, 0.0));
//! let n = Unit::new_normalize(Vector3::new(0.0, 1.0, 0.3));
//! let h = homography_from_plane(&pose, &n, 4.0);
//! let x1 = [Vector2::new(0.0, 0.1)];
//! let x2 = [{ let p = h * Vector3::new(0.0, 0.1, 1.0); Vector2::new(p.x / p.z, p.y / p.z) }];
//! let d = decompose_homography(&h, &x1, &x2, &[0]).unwrap();
//! assert!(d.candidates().iter().any(|c| c.normal_cam1.dot(&n) > 0.999999));
//! ```

use crate::essential::eight_point::smallest_eigenvector;
use crate::essential::{
    count_in_front, finite_correspondences, hartley_normalization, normalized_pairs,
};
use nalgebra::{
    Isometry3, Matrix3, Rotation3, SMatrix, SVector, Translation3, Unit, UnitQuaternion,
    UnitVector3, Vector2, Vector3,
};

/// Error estimating or decomposing a homography.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum HomographyError {
    /// Fewer than four correspondences.
    #[error("homography needs at least 4 correspondences, got {got}")]
    TooFewPoints {
        /// Correspondences given.
        got: usize,
    },
    /// An index is out of range or a coordinate is not finite.
    #[error("bad input: index out of range or non-finite value")]
    BadInput,
    /// Degenerate configuration (collinear points, singular matrix).
    #[error("degenerate configuration")]
    Degenerate,
}

/// `H = R + (t / d) nᵀ` for a known plane (`nᵀ X₁ = d`).
pub fn homography_from_plane(
    cam2_from_cam1: &Isometry3<f64>,
    normal_cam1: &UnitVector3<f64>,
    distance: f64,
) -> Matrix3<f64> {
    cam2_from_cam1.rotation.to_rotation_matrix().into_inner()
        + cam2_from_cam1.translation.vector * normal_cam1.transpose() / distance
}

/// Normalized DLT estimate of `H` (`x2 ~ H x1`) from the correspondences `indices`, scaled to
/// unit Frobenius norm.
pub fn homography_dlt(
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> Result<Matrix3<f64>, HomographyError> {
    if indices.len() < 4 {
        return Err(HomographyError::TooFewPoints { got: indices.len() });
    }
    if !finite_correspondences(x1, x2, indices) {
        return Err(HomographyError::BadInput);
    }
    let t1 = hartley_normalization(x1, indices).ok_or(HomographyError::Degenerate)?;
    let t2 = hartley_normalization(x2, indices).ok_or(HomographyError::Degenerate)?;
    let h_norm = if indices.len() == 4 {
        minimal_four_point(normalized_pairs(x1, x2, indices, &t1, &t2))?
    } else {
        least_squares_dlt(normalized_pairs(x1, x2, indices, &t1, &t2))?
    };
    let t2_inv = t2.try_inverse().ok_or(HomographyError::Degenerate)?;
    let h = t2_inv * h_norm * t1;
    let norm = h.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(HomographyError::Degenerate);
    }
    Ok(h / norm)
}

/// Exactly four normalized correspondences (the first four of `pairs`, from [`normalized_pairs`]): `h₃₃ = 1` and an 8×8 linear solve (much cheaper than
/// the eigen-decomposition; `h₃₃ = 0` would need the centroid to map to infinity, which no
/// valid sample does).
fn minimal_four_point(
    pairs: impl Iterator<Item = (Vector3<f64>, Vector3<f64>)>,
) -> Result<Matrix3<f64>, HomographyError> {
    let mut a = SMatrix::<f64, 8, 8>::zeros();
    let mut b = SVector::<f64, 8>::zeros();
    for (k, (p, q)) in pairs.take(4).enumerate() {
        let (u, v) = (q.x, q.y);
        let r = 2 * k;
        // u (h31 x + h32 y + 1) = h11 x + h12 y + h13, likewise for v.
        a.set_row(
            r,
            &nalgebra::RowSVector::<f64, 8>::from_row_slice(&[
                p.x,
                p.y,
                1.0,
                0.0,
                0.0,
                0.0,
                -u * p.x,
                -u * p.y,
            ]),
        );
        b[r] = u;
        a.set_row(
            r + 1,
            &nalgebra::RowSVector::<f64, 8>::from_row_slice(&[
                0.0,
                0.0,
                0.0,
                p.x,
                p.y,
                1.0,
                -v * p.x,
                -v * p.y,
            ]),
        );
        b[r + 1] = v;
    }
    let h = a.lu().solve(&b).ok_or(HomographyError::Degenerate)?;
    if !h.iter().all(|v| v.is_finite()) {
        return Err(HomographyError::Degenerate);
    }
    Ok(Matrix3::new(
        h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], 1.0,
    ))
}

/// Least-squares DLT on normalized correspondences `pairs` (smallest eigenvector of `AᵀA`).
fn least_squares_dlt(
    pairs: impl Iterator<Item = (Vector3<f64>, Vector3<f64>)>,
) -> Result<Matrix3<f64>, HomographyError> {
    let mut ata = SMatrix::<f64, 9, 9>::zeros();
    for (a, b) in pairs {
        let (u, v) = (b.x, b.y);
        let r1 = SVector::<f64, 9>::from_column_slice(&[
            0.0,
            0.0,
            0.0,
            -a.x,
            -a.y,
            -1.0,
            v * a.x,
            v * a.y,
            v,
        ]);
        let r2 = SVector::<f64, 9>::from_column_slice(&[
            a.x,
            a.y,
            1.0,
            0.0,
            0.0,
            0.0,
            -u * a.x,
            -u * a.y,
            -u,
        ]);
        ata += r1 * r1.transpose() + r2 * r2.transpose();
    }
    let h = smallest_eigenvector(ata).ok_or(HomographyError::Degenerate)?;
    Ok(Matrix3::from_row_slice(h.as_slice()))
}

/// `π(H x)`: applies a homography to a normalized point; `None` at infinity.
pub fn transfer(h: &Matrix3<f64>, x: &Vector2<f64>) -> Option<Vector2<f64>> {
    let p = h * x.push(1.0);
    if p.z.abs() < 1e-12 {
        return None;
    }
    Some(Vector2::new(p.x / p.z, p.y / p.z))
}

/// Squared transfer errors `(|x2 − π(H x1)|², |x1 − π(H⁻¹ x2)|²)` (normalized units²).
pub fn transfer_errors_sq(
    h: &Matrix3<f64>,
    h_inv: &Matrix3<f64>,
    x1: &Vector2<f64>,
    x2: &Vector2<f64>,
) -> (f64, f64) {
    let fwd = transfer(h, x1).map_or(f64::INFINITY, |p| (p - x2).norm_squared());
    let bwd = transfer(h_inv, x2).map_or(f64::INFINITY, |p| (p - x1).norm_squared());
    (fwd, bwd)
}

/// Whether any three of the four points are (nearly) collinear: such a sample cannot define a
/// homography.
pub fn has_collinear_triple(points: [&Vector2<f64>; 4]) -> bool {
    const TRIPLES: [[usize; 3]; 4] = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]];
    TRIPLES.iter().any(|t| {
        let (a, b, c) = (points[t[0]], points[t[1]], points[t[2]]);
        let (u, v) = (b - a, c - a);
        let cross = u.x * v.y - u.y * v.x;
        cross.abs() <= 1e-6 * u.norm() * v.norm() + 1e-15
    })
}

/// One physically possible decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomographyCandidate {
    /// Relative pose with translation `t / d` (metric after multiplying by the plane distance).
    pub cam2_from_cam1: Isometry3<f64>,
    /// Plane normal in camera 1 (from the camera towards the plane).
    pub normal_cam1: UnitVector3<f64>,
    /// Correspondences with positive depths in both cameras under this candidate.
    pub num_in_front: usize,
}

/// Result of [`decompose_homography`].
#[derive(Debug, Clone, PartialEq)]
pub enum HomographyDecomposition {
    /// Singular values all equal: `H` is a rotation, the translation is zero (or unobservable).
    PureRotation {
        /// The rotation `R ≈ H`.
        cam2_from_cam1: Rotation3<f64>,
    },
    /// Up to two candidates satisfying the visibility constraint for camera 1.
    Planar {
        /// Candidates, best visibility first.
        candidates: Vec<HomographyCandidate>,
    },
}

impl HomographyDecomposition {
    /// The candidates (a pure rotation yields one with zero translation and an arbitrary normal).
    pub fn candidates(&self) -> Vec<HomographyCandidate> {
        match self {
            Self::PureRotation { cam2_from_cam1 } => vec![HomographyCandidate {
                cam2_from_cam1: Isometry3::from_parts(
                    Translation3::identity(),
                    UnitQuaternion::from_rotation_matrix(cam2_from_cam1),
                ),
                normal_cam1: Vector3::z_axis(),
                num_in_front: 0,
            }],
            Self::Planar { candidates } => candidates.clone(),
        }
    }

    /// The planar candidate whose normal is closest to `normal_prior_cam1`; `None` for a pure
    /// rotation or when no candidate survived.
    pub fn select_by_normal(
        &self,
        normal_prior_cam1: &UnitVector3<f64>,
    ) -> Option<HomographyCandidate> {
        match self {
            Self::PureRotation { .. } => None,
            Self::Planar { candidates } => candidates
                .iter()
                .max_by(|a, b| {
                    a.normal_cam1
                        .dot(normal_prior_cam1)
                        .total_cmp(&b.normal_cam1.dot(normal_prior_cam1))
                })
                .copied(),
        }
    }
}

/// Ratio `σ₁ / σ₃` (after normalisation) below which `H` is treated as a pure rotation.
const PURE_ROTATION_SPREAD: f64 = 1e-6;

/// Decomposes `h` using the correspondences `indices` (typically the inliers) to fix the sign
/// of `H` and to apply the visibility and cheirality constraints.
pub fn decompose_homography(
    h: &Matrix3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> Result<HomographyDecomposition, HomographyError> {
    if !h.iter().all(|v| v.is_finite()) {
        return Err(HomographyError::BadInput);
    }
    if indices.iter().any(|&i| i >= x1.len() || i >= x2.len()) {
        return Err(HomographyError::BadInput);
    }
    let hn = normalized_homography(h, x1, x2, indices)?;
    let eig = (hn.transpose() * hn)
        .try_symmetric_eigen(1e-15, 500)
        .ok_or(HomographyError::Degenerate)?;
    let mut order = [0usize, 1, 2];
    order.sort_by(|a, b| eig.eigenvalues[*b].total_cmp(&eig.eigenvalues[*a]));
    let s1 = eig.eigenvalues[order[0]];
    let s3 = eig.eigenvalues[order[2]].max(0.0);
    let v1 = eig.eigenvectors.column(order[0]).into_owned();
    let v2 = eig.eigenvectors.column(order[1]).into_owned();
    let v3 = eig.eigenvectors.column(order[2]).into_owned();
    if s1 - s3 < PURE_ROTATION_SPREAD {
        return Ok(HomographyDecomposition::PureRotation {
            cam2_from_cam1: nearest_rotation(&hn).ok_or(HomographyError::Degenerate)?,
        });
    }
    let a = (1.0 - s3).max(0.0).sqrt();
    let b = (s1 - 1.0).max(0.0).sqrt();
    let c = (s1 - s3).sqrt();
    let u1 = (v1 * a + v3 * b) / c;
    let u2 = (v1 * a - v3 * b) / c;
    let mut candidates = Vec::with_capacity(4);
    for u in [u1, u2] {
        push_candidates(&hn, &v2, &u, (x1, x2), indices, &mut candidates);
    }
    candidates.sort_by_key(|c| std::cmp::Reverse(c.num_in_front));
    Ok(HomographyDecomposition::Planar { candidates })
}

/// `h` scaled so that its middle singular value is 1, with the sign that puts the
/// correspondences `indices` in front of both cameras (x2ᵀ H x1 > 0).
fn normalized_homography(
    h: &Matrix3<f64>,
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> Result<Matrix3<f64>, HomographyError> {
    let svd = h
        .try_svd(false, false, 1e-15, 200)
        .ok_or(HomographyError::Degenerate)?;
    let sigma2 = svd.singular_values[1];
    if !(sigma2.is_finite() && sigma2 > 1e-12) {
        return Err(HomographyError::Degenerate);
    }
    let hn = h / sigma2;
    let votes: f64 = indices
        .iter()
        .map(|&i| x2[i].push(1.0).dot(&(hn * x1[i].push(1.0))).signum())
        .sum();
    Ok(if votes < 0.0 { -hn } else { hn })
}

/// Adds the two candidates (plane normal ±n) of one solution `u` of the normalised
/// homography `hn`, keeping those that see most of the correspondences `indices`.
fn push_candidates(
    hn: &Matrix3<f64>,
    v2: &Vector3<f64>,
    u: &Vector3<f64>,
    (x1, x2): (&[Vector2<f64>], &[Vector2<f64>]),
    indices: &[usize],
    candidates: &mut Vec<HomographyCandidate>,
) {
    let big_u = Matrix3::from_columns(&[*v2, *u, v2.cross(u)]);
    let (hv2, hu) = (hn * v2, hn * u);
    let big_w = Matrix3::from_columns(&[hv2, hu, hv2.cross(&hu)]);
    let r = big_w * big_u.transpose();
    let n = v2.cross(u);
    let t = (hn - r) * n;
    for sign in [1.0, -1.0] {
        let (n_s, t_s) = (n * sign, t * sign);
        let visible = indices
            .iter()
            .filter(|&&i| n_s.dot(&x1[i].push(1.0)) > 0.0)
            .count();
        if 2 * visible < indices.len() || (indices.is_empty() && n_s.z <= 0.0) {
            continue;
        }
        let Some(rotation) = nearest_rotation(&r) else {
            continue;
        };
        let pose = Isometry3::from_parts(
            Translation3::from(t_s),
            UnitQuaternion::from_rotation_matrix(&rotation),
        );
        candidates.push(HomographyCandidate {
            cam2_from_cam1: pose,
            normal_cam1: Unit::new_normalize(n_s),
            num_in_front: count_in_front(&pose, x1, x2, indices),
        });
    }
}

/// Closest rotation (Frobenius) to `m`.
pub fn nearest_rotation(m: &Matrix3<f64>) -> Option<Rotation3<f64>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = m.try_svd(true, true, 1e-15, 200)?;
    let (u, v_t) = (svd.u?, svd.v_t?);
    let mut d = Matrix3::identity();
    if (u * v_t).determinant() < 0.0 {
        d[(2, 2)] = -1.0;
    }
    Some(Rotation3::from_matrix_unchecked(u * d * v_t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShiftRng;

    fn plane_scene(
        pose: &Isometry3<f64>,
        n: &UnitVector3<f64>,
        d: f64,
        count: usize,
        seed: u64,
    ) -> (Vec<Vector2<f64>>, Vec<Vector2<f64>>) {
        let mut rng = XorShiftRng::new(seed);
        let (mut x1, mut x2) = (Vec::new(), Vec::new());
        while x1.len() < count {
            let ray = Vector3::new(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), 1.0);
            let depth = d / n.dot(&ray);
            if depth.is_nan() || depth <= 0.0 {
                continue;
            }
            let p = nalgebra::Point3::from(ray * depth);
            let q = pose * p;
            if q.z <= 0.0 {
                continue;
            }
            x1.push(Vector2::new(ray.x, ray.y));
            x2.push(Vector2::new(q.x / q.z, q.y / q.z));
        }
        (x1, x2)
    }

    #[test]
    fn dlt_recovers_exact_homography() {
        let pose = Isometry3::new(Vector3::new(0.4, -0.1, 0.2), Vector3::new(0.05, 0.2, -0.1));
        let n = Unit::new_normalize(Vector3::new(0.1, 0.9, 0.4));
        let (x1, x2) = plane_scene(&pose, &n, 3.0, 30, 1);
        let idx: Vec<usize> = (0..30).collect();
        let h = homography_dlt(&x1, &x2, &idx).unwrap();
        let h_true = homography_from_plane(&pose, &n, 3.0).normalize();
        assert!((h - h_true).norm().min((h + h_true).norm()) < 1e-9);
        let h_inv = h.try_inverse().unwrap();
        let (a, b) = transfer_errors_sq(&h, &h_inv, &x1[3], &x2[3]);
        assert!(a < 1e-18 && b < 1e-18);
        // Minimal case.
        let h4 = homography_dlt(&x1, &x2, &[0, 1, 2, 3]).unwrap();
        assert!((h4 - h_true).norm().min((h4 + h_true).norm()) < 1e-7);
        assert!(homography_dlt(&x1, &x2, &[0, 1, 2]).is_err());
    }

    #[test]
    fn decomposition_recovers_pose_and_normal() {
        let mut rng = XorShiftRng::new(9);
        for trial in 0..20 {
            let pose = Isometry3::new(
                rng.uniform_vector3(-0.5, 0.5),
                rng.uniform_vector3(-0.2, 0.2),
            );
            let n = Unit::new_normalize(Vector3::new(
                rng.uniform(-0.5, 0.5),
                rng.uniform(-0.5, 0.5),
                1.0,
            ));
            let d = rng.uniform(2.0, 8.0);
            let (x1, x2) = plane_scene(&pose, &n, d, 40, trial);
            let idx: Vec<usize> = (0..x1.len()).collect();
            // Arbitrary scale and sign must not matter.
            let h = homography_from_plane(&pose, &n, d) * -2.7;
            let dec = decompose_homography(&h, &x1, &x2, &idx).unwrap();
            let cands = dec.candidates();
            assert!(cands.len() <= 2, "{}", cands.len());
            let best = dec.select_by_normal(&n).unwrap();
            assert!(best.normal_cam1.dot(&n) > 1.0 - 1e-9, "trial {trial}");
            assert!(best.cam2_from_cam1.rotation.angle_to(&pose.rotation) < 1e-7);
            let t_over_d = pose.translation.vector / d;
            assert!((best.cam2_from_cam1.translation.vector - t_over_d).norm() < 1e-7);
            assert_eq!(best.num_in_front, x1.len());
        }
    }

    #[test]
    fn pure_rotation_is_detected() {
        let pose = Isometry3::new(Vector3::zeros(), Vector3::new(0.1, -0.05, 0.2));
        let n = Vector3::z_axis();
        let (x1, x2) = plane_scene(&pose, &n, 5.0, 10, 3);
        let h = homography_from_plane(&pose, &n, 5.0);
        let idx: Vec<usize> = (0..10).collect();
        match decompose_homography(&h, &x1, &x2, &idx).unwrap() {
            HomographyDecomposition::PureRotation { cam2_from_cam1 } => {
                assert!(cam2_from_cam1.angle_to(&pose.rotation.to_rotation_matrix()) < 1e-9);
            }
            other => panic!("expected pure rotation, got {other:?}"),
        }
        assert!(decompose_homography(&Matrix3::zeros(), &x1, &x2, &idx).is_err());
    }

    #[test]
    fn collinear_detection() {
        let a = Vector2::new(0.0, 0.0);
        let b = Vector2::new(1.0, 1.0);
        let c = Vector2::new(2.0, 2.0);
        let d = Vector2::new(0.0, 1.0);
        assert!(has_collinear_triple([&a, &b, &c, &d]));
        let c2 = Vector2::new(1.0, 0.0);
        assert!(!has_collinear_triple([&a, &b, &c2, &d]));
    }
}
