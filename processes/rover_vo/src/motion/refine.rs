//! Gauss–Newton refinement of a pose on the reprojection error of its inliers, one step at a
//! time: normal equations with Huber weights, an optional gravity-direction prior, a 4- or
//! 6-DOF solve, and the update `R ← exp(δω)·R`, `t ← t + δt`.

use super::{Correspondence, Intrinsics, Tilt};
use nalgebra::{
    Isometry3, Matrix3, Matrix6, Point3, SMatrix, SVector, Translation3, UnitQuaternion, Vector3,
    Vector6,
};
use std::ops::AddAssign;

/// Residuals above this many pixels are down-weighted (Huber).
const HUBER_PX: f64 = 1.0;

/// Gauss–Newton with Huber weights (1 px) on the reprojection error of `inliers`.
/// With a [`Tilt`] without prior σ only yaw about world z and translation change; with a σ the
/// refinement is 6-DOF with a gravity-direction prior; without a tilt it is 6-DOF.
/// Returns the pose and the RMS reprojection error.
pub fn refine(
    data: &[Correspondence],
    inliers: &[usize],
    mut pose: Isometry3<f64>,
    body_from_camera: &Isometry3<f64>,
    intrinsics: &Intrinsics,
    tilt: Option<Tilt>,
    iterations: usize,
) -> (Isometry3<f64>, f64) {
    let four_dof = matches!(
        tilt,
        Some(Tilt {
            prior_sigma_rad: None,
            ..
        })
    );
    let prior = gravity_prior(tilt);
    let camera_from_body = body_from_camera.inverse();
    let mut rms = f64::NAN;
    for _ in 0..iterations {
        let r_t = pose.rotation.inverse().to_rotation_matrix().into_inner();
        let Some(mut normal) =
            NormalEquations::of_reprojection(data, inliers, &pose, &camera_from_body, intrinsics)
        else {
            break;
        };
        rms = normal.rms_px;
        if let Some((weight, gravity_body)) = prior {
            normal.add_gravity_prior(&r_t, weight, &gravity_body);
        }
        let Some(step) = normal.solve(four_dof) else {
            break;
        };
        let converged;
        (pose, converged) = apply_step(&pose, &step);
        if converged {
            break;
        }
    }
    (pose, rms)
}

/// The prior's weight and the IMU's gravity direction in the body frame, if `tilt` has a
/// usable σ.
fn gravity_prior(tilt: Option<Tilt>) -> Option<(f64, Vector3<f64>)> {
    tilt.and_then(|t| {
        t.prior_sigma_rad
            .filter(|s| s.is_finite() && *s > 0.0)
            .map(|s| ((0.5 / s).powi(2), t.leveling.inverse() * Vector3::z()))
    })
}

/// `H δ = −g` of one Gauss–Newton step, in `(δω, δt)`.
struct NormalEquations {
    h: Matrix6<f64>,
    g: Vector6<f64>,
    rms_px: f64,
}

impl NormalEquations {
    /// The Huber-weighted reprojection terms of `inliers` at `pose` (`None` if fewer than three
    /// points are in front of the camera).
    fn of_reprojection(
        data: &[Correspondence],
        inliers: &[usize],
        pose: &Isometry3<f64>,
        camera_from_body: &Isometry3<f64>,
        intrinsics: &Intrinsics,
    ) -> Option<Self> {
        let mut h = Matrix6::<f64>::zeros();
        let mut g = Vector6::<f64>::zeros();
        let mut sum_sq = 0.0;
        let mut n = 0usize;
        let r_t = pose.rotation.inverse().to_rotation_matrix().into_inner();
        let c = camera_from_body.rotation.to_rotation_matrix().into_inner();
        for &i in inliers {
            let d = &data[i];
            let x_minus_t = d.point_world_m.coords - pose.translation.vector;
            let Some((e, j)) =
                reprojection_jacobian(d, &x_minus_t, &r_t, &c, camera_from_body, intrinsics)
            else {
                continue;
            };
            let norm = e.norm();
            let w = if norm <= HUBER_PX {
                1.0
            } else {
                HUBER_PX / norm
            };
            h += w * j.transpose() * j;
            g += w * j.transpose() * e;
            sum_sq += norm * norm;
            n += 1;
        }
        (n >= 3).then(|| Self {
            h,
            g,
            rms_px: (sum_sq / n as f64).sqrt(),
        })
    }

    /// Adds the gravity-direction prior: e = Rᵀẑ − g_imu; ∂e/∂δω = Rᵀ[ẑ]ₓ.
    fn add_gravity_prior(&mut self, r_t: &Matrix3<f64>, weight: f64, gravity_body: &Vector3<f64>) {
        let e = r_t * Vector3::z() - gravity_body;
        let j = r_t * Vector3::z().cross_matrix();
        self.h
            .fixed_view_mut::<3, 3>(0, 0)
            .add_assign(&(weight * j.transpose() * j));
        let gr = weight * j.transpose() * e;
        for k in 0..3 {
            self.g[k] += gr[k];
        }
    }

    /// The step, 6-DOF or (`four_dof`) yaw and translation only; `None` if singular or not
    /// finite.
    fn solve(&self, four_dof: bool) -> Option<Vector6<f64>> {
        let (h, g) = (&self.h, &self.g);
        let step: Vector6<f64> = if four_dof {
            let idx = [2usize, 3, 4, 5];
            let mut h4 = SMatrix::<f64, 4, 4>::zeros();
            let mut g4 = SVector::<f64, 4>::zeros();
            for (a, &ia) in idx.iter().enumerate() {
                g4[a] = g[ia];
                for (b, &ib) in idx.iter().enumerate() {
                    h4[(a, b)] = h[(ia, ib)];
                }
            }
            let s4 = h4.cholesky().map(|ch| ch.solve(&(-g4)))?;
            Vector6::new(0.0, 0.0, s4[0], s4[1], s4[2], s4[3])
        } else {
            h.cholesky().map(|ch| ch.solve(&(-g)))?
        };
        step.iter().all(|v| v.is_finite()).then_some(step)
    }
}

/// Reprojection error of `d` and its Jacobian in `(δω, δt)` (`None` behind or too near the
/// camera).
fn reprojection_jacobian(
    d: &Correspondence,
    x_minus_t: &Vector3<f64>,
    r_t: &Matrix3<f64>,
    c: &Matrix3<f64>,
    camera_from_body: &Isometry3<f64>,
    intrinsics: &Intrinsics,
) -> Option<(nalgebra::Vector2<f64>, SMatrix<f64, 2, 6>)> {
    let q = r_t * x_minus_t;
    let p = camera_from_body * Point3::from(q);
    if p.z <= 0.05 {
        return None;
    }
    let (iz, iz2) = (1.0 / p.z, 1.0 / (p.z * p.z));
    let u = intrinsics.fx_px * p.x * iz + intrinsics.cx_px;
    let v = intrinsics.fy_px * p.y * iz + intrinsics.cy_px;
    let e = nalgebra::Vector2::new(u - d.pixel.x, v - d.pixel.y);
    let j_proj = SMatrix::<f64, 2, 3>::new(
        intrinsics.fx_px * iz,
        0.0,
        -intrinsics.fx_px * p.x * iz2,
        0.0,
        intrinsics.fy_px * iz,
        -intrinsics.fy_px * p.y * iz2,
    );
    let jq = j_proj * c;
    let j_omega = jq * r_t * x_minus_t.cross_matrix();
    let j_t = -(jq * r_t);
    let mut j = SMatrix::<f64, 2, 6>::zeros();
    j.fixed_view_mut::<2, 3>(0, 0).copy_from(&j_omega);
    j.fixed_view_mut::<2, 3>(0, 3).copy_from(&j_t);
    Some((e, j))
}

/// `pose` moved by `step`, and whether the step was small enough to stop.
fn apply_step(pose: &Isometry3<f64>, step: &Vector6<f64>) -> (Isometry3<f64>, bool) {
    let omega = Vector3::new(step[0], step[1], step[2]);
    let rotation = UnitQuaternion::from_scaled_axis(omega) * pose.rotation;
    let translation = pose.translation.vector + Vector3::new(step[3], step[4], step[5]);
    let moved = Isometry3::from_parts(Translation3::from(translation), rotation);
    let converged = omega.norm() < 1e-8 && step.fixed_rows::<3>(3).norm() < 1e-7;
    (moved, converged)
}
