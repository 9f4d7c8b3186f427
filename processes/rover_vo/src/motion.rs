//! Robust stereo motion: RANSAC hypotheses from 3D–3D correspondences (map point in the world,
//! stereo point in the current camera), scored by the reprojection error of the map point in
//! the current left image, then Gauss–Newton refinement of that error over all inliers.
//!
//! - With the IMU's roll and pitch ([`Tilt`]), a hypothesis needs **two** points (the 2-point
//!   stereo algorithm): the leveled body-frame points give yaw from the direction of their
//!   horizontal difference, and translation from the centroid. Refinement keeps roll and pitch
//!   fixed (4 DOF: yaw about world z and translation).
//! - Without it, **three** points and Kabsch/Umeyama give a 6-DOF hypothesis; refinement is 6-DOF.
//!
//! Transforms: `world_from_body`, `body_from_camera`; the pose is perturbed as
//! `R ← exp(δω)·R`, `t ← t + δt` (a perturbation about world z keeps roll and pitch).

use hopnav_vision::ransac::{Ransac, RansacConfig, RansacProblem};
use nalgebra::{
    Isometry3, Matrix3, Point2, Point3, Rotation3, Translation3, UnitQuaternion, Vector3,
};

mod refine;
pub use refine::refine;

/// Intrinsics used for reprojection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intrinsics {
    /// Focal length x, pixels.
    pub fx_px: f64,
    /// Focal length y, pixels.
    pub fy_px: f64,
    /// Principal point x, pixels.
    pub cx_px: f64,
    /// Principal point y, pixels.
    pub cy_px: f64,
}

impl Intrinsics {
    /// Projects a camera-frame point; `None` behind or too close to the camera.
    pub fn project(&self, p: &Point3<f64>) -> Option<Point2<f64>> {
        if p.z > 0.05 {
            Some(Point2::new(
                self.fx_px * p.x / p.z + self.cx_px,
                self.fy_px * p.y / p.z + self.cy_px,
            ))
        } else {
            None
        }
    }
}

/// Roll and pitch of the body from the IMU: `world_from_body = Rz(yaw) · leveling`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tilt {
    /// `Ry(pitch) · Rx(roll)`.
    pub leveling: UnitQuaternion<f64>,
    /// How refinement uses it: `None` keeps roll and pitch fixed (4 DOF); `Some(σ)` refines
    /// 6 DOF with a prior of σ radians on the gravity direction in the body frame, in units
    /// of the pixel error scale `σ_px = 0.5 px`.
    pub prior_sigma_rad: Option<f64>,
}

impl Tilt {
    /// The roll and pitch of an attitude (its yaw is dropped).
    pub fn from_attitude(world_from_body: &UnitQuaternion<f64>) -> Self {
        let (roll, pitch, _) = world_from_body.euler_angles();
        Self {
            leveling: UnitQuaternion::from_euler_angles(roll, pitch, 0.0),
            prior_sigma_rad: None,
        }
    }

    /// `Rz(yaw) · leveling`.
    pub fn with_yaw(&self, yaw_rad: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_rad) * self.leveling
    }
}

/// One map-point observation in the current frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Correspondence {
    /// Map point, world frame, metres.
    pub point_world_m: Point3<f64>,
    /// Tracked position in the current left image, pixels.
    pub pixel: Point2<f64>,
    /// The same feature triangulated by the current stereo pair, left camera frame (if matched).
    pub point_camera_m: Option<Point3<f64>>,
}

/// Result of [`MotionEstimator::estimate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionEstimate {
    /// Refined pose.
    pub world_from_body: Isometry3<f64>,
    /// Inliers after refinement.
    pub inliers: usize,
    /// Correspondences with a current stereo point (hypothesis candidates).
    pub stereo_candidates: usize,
    /// RMS reprojection error of the inliers, pixels.
    pub rms_px: f64,
}

/// Why no motion could be estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum MotionError {
    /// Too few correspondences with a stereo point to draw a hypothesis.
    #[error("too few stereo correspondences: {0}")]
    TooFewStereo(usize),
    /// RANSAC found no model.
    #[error("RANSAC found no model")]
    NoModel,
}

/// RANSAC + Gauss–Newton with buffers allocated once.
#[derive(Debug, Clone)]
pub struct MotionEstimator {
    ransac: Ransac<Isometry3<f64>>,
    candidates: Vec<usize>,
    inliers: Vec<usize>,
    inlier_flags: Vec<bool>,
    threshold_px: f64,
}

struct Problem<'a> {
    data: &'a [Correspondence],
    candidates: &'a [usize],
    body_from_camera: &'a Isometry3<f64>,
    intrinsics: &'a Intrinsics,
    tilt: Option<Tilt>,
}

/// Squared reprojection error of `c` under `world_from_body`, px² (large when behind).
pub fn reprojection_error_sq(
    c: &Correspondence,
    world_from_body: &Isometry3<f64>,
    body_from_camera: &Isometry3<f64>,
    intrinsics: &Intrinsics,
) -> f64 {
    let camera_from_world = (world_from_body * body_from_camera).inverse();
    match intrinsics.project(&(camera_from_world * c.point_world_m)) {
        Some(p) => (p - c.pixel).norm_squared(),
        None => 1e12,
    }
}

impl RansacProblem for Problem<'_> {
    type Model = Isometry3<f64>;

    fn num_data(&self) -> usize {
        self.candidates.len()
    }

    fn sample_size(&self) -> usize {
        if self.tilt.is_some() { 2 } else { 3 }
    }

    fn fit_minimal(&self, sample: &[usize], models: &mut Vec<Isometry3<f64>>) {
        let pair = |j: usize| {
            let c = &self.data[self.candidates[j]];
            c.point_camera_m
                .map(|q| (self.body_from_camera * q, c.point_world_m))
        };
        if let Some(tilt) = self.tilt {
            let (Some((b0, x0)), Some((b1, x1))) = (pair(sample[0]), pair(sample[1])) else {
                return;
            };
            let (a0, a1) = (tilt.leveling * b0, tilt.leveling * b1);
            let da = a1 - a0;
            let dx = x1 - x0;
            if da.xy().norm() < 0.1 || dx.xy().norm() < 0.1 {
                return;
            }
            // Lengths must agree (rigid motion) within a generous stereo tolerance.
            if (da.norm() - dx.norm()).abs() > 0.3 * da.norm().max(0.3) {
                return;
            }
            let yaw = dx.y.atan2(dx.x) - da.y.atan2(da.x);
            let rotation = tilt.with_yaw(yaw);
            let t = 0.5 * ((x0.coords - rotation * b0.coords) + (x1.coords - rotation * b1.coords));
            models.push(Isometry3::from_parts(Translation3::from(t), rotation));
        } else {
            let mut body = [Point3::origin(); 3];
            let mut world = [Point3::origin(); 3];
            for (k, &j) in sample.iter().enumerate() {
                let Some((b, x)) = pair(j) else { return };
                body[k] = b;
                world[k] = x;
            }
            if let Some(model) = kabsch(&body, &world) {
                models.push(model);
            }
        }
    }

    fn residual_sq(&self, model: &Isometry3<f64>, index: usize) -> f64 {
        reprojection_error_sq(
            &self.data[self.candidates[index]],
            model,
            self.body_from_camera,
            self.intrinsics,
        )
    }
}

/// Rigid `world_from_body` aligning `body` onto `world` (least squares, no scale).
pub fn kabsch(body: &[Point3<f64>], world: &[Point3<f64>]) -> Option<Isometry3<f64>> {
    let n = body.len().min(world.len());
    if n < 3 {
        return None;
    }
    let cb = body[..n].iter().map(|p| p.coords).sum::<Vector3<f64>>() / n as f64;
    let cw = world[..n].iter().map(|p| p.coords).sum::<Vector3<f64>>() / n as f64;
    let mut h = Matrix3::zeros();
    for k in 0..n {
        h += (body[k].coords - cb) * (world[k].coords - cw).transpose();
    }
    let svd = h.svd(true, true);
    let (u, v_t) = (svd.u?, svd.v_t?);
    let mut d = Matrix3::identity();
    if (v_t.transpose() * u.transpose()).determinant() < 0.0 {
        d[(2, 2)] = -1.0;
    }
    let r = v_t.transpose() * d * u.transpose();
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    let t = cw - rotation * cb;
    (t.iter().all(|v| v.is_finite()))
        .then(|| Isometry3::from_parts(Translation3::from(t), rotation))
}

impl MotionEstimator {
    /// An estimator for up to `capacity` correspondences.
    pub fn new(threshold_px: f64, capacity: usize) -> Self {
        let config = RansacConfig {
            threshold: threshold_px,
            confidence: 0.999,
            max_iterations: 200,
            min_iterations: 20,
            local_optimization_steps: 0,
            seed: 7,
        };
        Self {
            ransac: Ransac::new(config, capacity),
            candidates: Vec::with_capacity(capacity),
            inliers: Vec::with_capacity(capacity),
            inlier_flags: Vec::with_capacity(capacity),
            threshold_px,
        }
    }

    /// Whether correspondence `i` was an inlier of the last successful estimate.
    pub fn is_inlier(&self, i: usize) -> bool {
        self.inlier_flags.get(i).copied().unwrap_or(false)
    }

    /// Estimates `world_from_body` from `data`.
    pub fn estimate(
        &mut self,
        data: &[Correspondence],
        body_from_camera: &Isometry3<f64>,
        intrinsics: &Intrinsics,
        tilt: Option<Tilt>,
    ) -> Result<MotionEstimate, MotionError> {
        self.inlier_flags.clear();
        self.inlier_flags.resize(data.len(), false);
        self.candidates.clear();
        self.candidates
            .extend((0..data.len()).filter(|&i| data[i].point_camera_m.is_some()));
        let needed = if tilt.is_some() { 2 } else { 3 };
        if self.candidates.len() < needed.max(4) {
            return Err(MotionError::TooFewStereo(self.candidates.len()));
        }
        let problem = Problem {
            data,
            candidates: &self.candidates,
            body_from_camera,
            intrinsics,
            tilt,
        };
        let fit = self
            .ransac
            .run(&problem)
            .map_err(|_| MotionError::NoModel)?;
        let mut pose = fit.model;
        let mut rms_px = f64::NAN;
        for round in 0..3 {
            let gate_px = if round == 0 {
                2.0 * self.threshold_px
            } else {
                self.threshold_px
            };
            self.collect_inliers(data, &pose, body_from_camera, intrinsics, gate_px);
            if self.inliers.len() < needed + 1 {
                return Err(MotionError::NoModel);
            }
            let (refined, rms) = refine(
                data,
                &self.inliers,
                pose,
                body_from_camera,
                intrinsics,
                tilt,
                6,
            );
            pose = refined;
            rms_px = rms;
        }
        self.collect_inliers(data, &pose, body_from_camera, intrinsics, self.threshold_px);
        for &i in &self.inliers {
            self.inlier_flags[i] = true;
        }
        Ok(MotionEstimate {
            world_from_body: pose,
            inliers: self.inliers.len(),
            stereo_candidates: self.candidates.len(),
            rms_px,
        })
    }

    fn collect_inliers(
        &mut self,
        data: &[Correspondence],
        pose: &Isometry3<f64>,
        body_from_camera: &Isometry3<f64>,
        intrinsics: &Intrinsics,
        gate_px: f64,
    ) {
        self.inliers.clear();
        let gate_sq = gate_px * gate_px;
        for (i, c) in data.iter().enumerate() {
            if reprojection_error_sq(c, pose, body_from_camera, intrinsics) < gate_sq {
                self.inliers.push(i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopnav_vision::rng::XorShiftRng;

    fn mount() -> Isometry3<f64> {
        // Camera 1 m up, looking forward (body x) and 15° down: z_cam = (cos, 0, −sin).
        let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[
            Vector3::new(0.0, -1.0, 0.0),
            Vector3::new(
                -(15f64.to_radians().sin()),
                0.0,
                -(15f64.to_radians().cos()),
            ),
            Vector3::new(15f64.to_radians().cos(), 0.0, -(15f64.to_radians().sin())),
        ]));
        Isometry3::from_parts(
            Translation3::new(0.3, 0.0, 1.0),
            UnitQuaternion::from_rotation_matrix(&rot),
        )
    }

    fn scene(
        outlier_fraction: f64,
        seed: u64,
    ) -> (Vec<Correspondence>, Isometry3<f64>, Intrinsics) {
        let k = Intrinsics {
            fx_px: 277.0,
            fy_px: 277.0,
            cx_px: 160.0,
            cy_px: 120.0,
        };
        let truth = Isometry3::from_parts(
            Translation3::new(3.0, -2.0, 0.4),
            UnitQuaternion::from_euler_angles(0.03, -0.05, 0.7),
        );
        let bfc = mount();
        let world_from_camera = truth * bfc;
        let mut rng = XorShiftRng::new(seed);
        let mut data = Vec::new();
        while data.len() < 200 {
            let p_cam = Point3::new(
                rng.uniform(-6.0, 6.0),
                rng.uniform(-1.0, 3.0),
                rng.uniform(2.0, 15.0),
            );
            let Some(px) = k.project(&p_cam) else {
                continue;
            };
            if !(0.0..320.0).contains(&px.x) || !(0.0..240.0).contains(&px.y) {
                continue;
            }
            let noisy_cam = p_cam + Vector3::new(0.0, 0.0, 0.01 * p_cam.z * rng.gaussian());
            let mut world = world_from_camera * p_cam;
            let mut pixel = px + nalgebra::Vector2::new(0.3 * rng.gaussian(), 0.3 * rng.gaussian());
            if rng.unit_f64() < outlier_fraction {
                world += Vector3::new(
                    rng.uniform(-2.0, 2.0),
                    rng.uniform(-2.0, 2.0),
                    rng.uniform(-1.0, 1.0),
                );
                pixel += nalgebra::Vector2::new(rng.uniform(-30.0, 30.0), rng.uniform(-30.0, 30.0));
            }
            data.push(Correspondence {
                point_world_m: world,
                pixel,
                point_camera_m: Some(noisy_cam),
            });
        }
        (data, truth, k)
    }

    #[test]
    fn recovers_pose_with_outliers_in_6dof_and_4dof() {
        let (data, truth, k) = scene(0.3, 3);
        let mut est = MotionEstimator::new(2.0, 256);
        let with_prior = Tilt {
            prior_sigma_rad: Some(0.002),
            ..Tilt::from_attitude(&truth.rotation)
        };
        for tilt in [
            None,
            Some(Tilt::from_attitude(&truth.rotation)),
            Some(with_prior),
        ] {
            let m = est.estimate(&data, &mount(), &k, tilt).unwrap();
            let dt = (m.world_from_body.translation.vector - truth.translation.vector).norm();
            let dr = m.world_from_body.rotation.angle_to(&truth.rotation);
            assert!(
                dt < 0.02 && dr < 0.002,
                "tilt {} dt {dt} dr {dr}",
                tilt.is_some()
            );
            assert!(m.inliers > 120 && m.inliers < 160, "inliers {}", m.inliers);
        }
    }

    #[test]
    fn too_few_points_is_an_error_not_a_panic() {
        let (data, _, k) = scene(0.0, 4);
        let mut est = MotionEstimator::new(2.0, 256);
        assert!(est.estimate(&data[..2], &mount(), &k, None).is_err());
        assert!(est.estimate(&[], &mount(), &k, None).is_err());
    }
}
