//! Relative pose between two views: essential and homography RANSAC, model selection,
//! decomposition with a gravity-normal prior, cheirality, pure-rotation detection.
//!
//! [`TwoViewEstimator::estimate`] runs, on normalized correspondences:
//!
//! 1. essential-matrix RANSAC (5-point by default, 8-point selectable; Sampson residual; MSAC;
//!    LO refit with the 8-point algorithm on all inliers);
//! 2. homography RANSAC (4-point normalized DLT; symmetric transfer residual; LO refit);
//! 3. pure-rotation test: if the rotation nearest to `H` explains ≥ 90 % of the homography
//!    inliers, the translation is unobservable and [`MotionModel::PureRotation`] is returned;
//! 4. model selection by the score ratio of [`crate::model_select`];
//! 5. for `H`: decomposition, the candidate whose normal best matches the prior (gravity in
//!    camera 1) — or, without a prior, the one with the most points in front; for `E`: the
//!    cheirality test over the four candidates.
//!
//! The returned translation has unit norm (scale comes from elsewhere: altimeter, stereo). For
//! the homography branch, `t/d` is also returned: with a known plane distance `d` (height above
//! ground) it gives metric translation.

use crate::camera::PinholeCamera;
use crate::essential::recover_pose;
use crate::essential::refine::refine_pose_sampson;
use crate::homography::{
    HomographyDecomposition, decompose_homography, nearest_rotation, transfer_errors_sq,
};
use crate::model_select::{
    CHI2_1DOF_95, CHI2_2DOF_95, ModelChoice, choose_model, homography_ratio, inv_sigma_sq,
    score_essential, score_homography,
};
use crate::ransac::{Ransac, RansacConfig, RansacError};
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, UnitVector3, Vector2, Vector3};

mod problems;

pub use problems::{EssentialProblem, HomographyModel, HomographyProblem};

/// Minimal solver used for the essential matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EssentialSolver {
    /// Nistér's five-point solver (default).
    FivePoint,
    /// Normalized eight-point algorithm.
    EightPoint,
}

/// Settings of [`TwoViewEstimator`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoViewConfig {
    /// Focal length used to convert pixel thresholds to normalized units.
    pub focal_px: f64,
    /// Assumed per-image keypoint noise σ, in pixels. RANSAC thresholds are the 95 % χ²
    /// quantiles for noise in both images: `√(3.84 · 2) σ` for the (1-DOF) Sampson error,
    /// `√(5.99 · 2) σ` for the (2-DOF) transfer error; model selection uses the same σ.
    pub sigma_px: f64,
    /// RANSAC confidence `p`.
    pub confidence: f64,
    /// Essential RANSAC iteration cap.
    pub max_iterations: usize,
    /// Homography RANSAC iteration cap. Lower than the essential one: in a general 3-D scene
    /// the homography has few inliers, the adaptive count would run to the cap, and only its
    /// score is needed there.
    pub homography_max_iterations: usize,
    /// LO refits per improvement.
    pub local_optimization_steps: usize,
    /// Levenberg–Marquardt iterations polishing the essential-branch pose on the Sampson error
    /// of its inliers (0 disables).
    pub refine_iterations: usize,
    /// Essential minimal solver.
    pub solver: EssentialSolver,
    /// `R_H` above which the homography is used.
    pub homography_ratio_threshold: f64,
    /// Fraction of homography inliers a pure rotation must explain to declare `t` unobservable.
    pub pure_rotation_inlier_fraction: f64,
    /// Fewer inliers than this is a failure.
    pub min_inliers: usize,
    /// RANSAC seed.
    pub seed: u64,
}

impl TwoViewConfig {
    /// Defaults for a camera (thresholds converted with its mean focal length).
    pub fn for_camera(camera: &PinholeCamera) -> Self {
        Self {
            focal_px: camera.mean_focal_px(),
            sigma_px: 0.5,
            confidence: 0.999,
            max_iterations: 500,
            homography_max_iterations: 100,
            local_optimization_steps: 3,
            refine_iterations: 10,
            solver: EssentialSolver::FivePoint,
            homography_ratio_threshold: 0.40,
            pure_rotation_inlier_fraction: 0.9,
            min_inliers: 15,
            seed: 0x5EED,
        }
    }

    /// Essential RANSAC threshold on the Sampson error, in pixels.
    pub fn essential_threshold_px(&self) -> f64 {
        (CHI2_1DOF_95 * 2.0).sqrt() * self.sigma_px
    }

    /// Homography RANSAC threshold on the transfer error, in pixels.
    pub fn homography_threshold_px(&self) -> f64 {
        (CHI2_2DOF_95 * 2.0).sqrt() * self.sigma_px
    }

    /// The essential-matrix RANSAC's settings (thresholds in normalized coordinates).
    pub fn essential_ransac(&self) -> RansacConfig {
        RansacConfig {
            threshold: self.essential_threshold_px() / self.focal_px,
            confidence: self.confidence,
            max_iterations: self.max_iterations,
            min_iterations: 10,
            local_optimization_steps: self.local_optimization_steps,
            seed: self.seed,
        }
    }

    /// The homography RANSAC's settings: the essential one's with its own threshold and
    /// iteration cap.
    pub fn homography_ransac(&self) -> RansacConfig {
        RansacConfig {
            threshold: self.homography_threshold_px() / self.focal_px,
            max_iterations: self.homography_max_iterations,
            ..self.essential_ransac()
        }
    }
}

/// Which model produced the pose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionModel {
    /// Essential matrix + cheirality.
    Essential,
    /// Homography decomposition (planar scene).
    Homography,
    /// Rotation only: the translation is zero or unobservable.
    PureRotation,
}

/// Result of [`TwoViewEstimator::estimate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoViewEstimate {
    /// Relative pose, unit translation (zero for [`MotionModel::PureRotation`]).
    pub cam2_from_cam1: Isometry3<f64>,
    /// Model used.
    pub model: MotionModel,
    /// Inliers of the model used ([`TwoViewEstimator::inliers`]).
    pub num_inliers: usize,
    /// Essential RANSAC inliers (0 if it failed).
    pub essential_inliers: usize,
    /// Homography RANSAC inliers (0 if it failed).
    pub homography_inliers: usize,
    /// `R_H = S_H / (S_H + S_E)`.
    pub homography_ratio: f64,
    /// Plane normal in camera 1 (homography branch).
    pub plane_normal_cam1: Option<UnitVector3<f64>>,
    /// `t / d` with `d` the distance of camera 1 to the plane (homography branch).
    pub translation_over_plane_distance: Option<Vector3<f64>>,
    /// Inliers in front of both cameras for the chosen candidate.
    pub num_in_front: usize,
}

impl TwoViewEstimate {
    /// Angle between the estimated and a reference rotation.
    pub fn rotation_error_rad(&self, truth: &Isometry3<f64>) -> f64 {
        self.cam2_from_cam1.rotation.angle_to(&truth.rotation)
    }

    /// Angle between the estimated and a reference translation direction; `None` if either is
    /// (near) zero.
    pub fn translation_direction_error_rad(&self, truth: &Isometry3<f64>) -> Option<f64> {
        let a = self.cam2_from_cam1.translation.vector;
        let b = truth.translation.vector;
        if a.norm() < 1e-12 || b.norm() < 1e-12 {
            return None;
        }
        Some(a.angle(&b))
    }
}

/// Error of [`TwoViewEstimator::estimate`].
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TwoViewError {
    /// `x1` and `x2` differ in length.
    #[error("x1 has {x1} points, x2 has {x2}")]
    LengthMismatch {
        /// `x1.len()`.
        x1: usize,
        /// `x2.len()`.
        x2: usize,
    },
    /// Too few correspondences (or inliers) for a reliable estimate.
    #[error("{got} correspondences/inliers, need {needed}")]
    TooFewPoints {
        /// What was available.
        got: usize,
        /// The configured minimum.
        needed: usize,
    },
    /// A configuration value is out of range.
    #[error("invalid two-view config: {0}")]
    BadConfig(&'static str),
    /// Neither model could be estimated.
    #[error("no model found (essential: {essential}, homography: {homography})")]
    NoModel {
        /// Why the essential RANSAC failed.
        essential: RansacError,
        /// Why the homography RANSAC failed.
        homography: RansacError,
    },
    /// The chosen model could not be turned into a pose.
    #[error("pose recovery failed")]
    PoseRecovery,
}

/// Two-view relative-pose estimator with reusable buffers.
#[derive(Debug, Clone)]
pub struct TwoViewEstimator {
    config: TwoViewConfig,
    essential_ransac: Ransac<Matrix3<f64>>,
    homography_ransac: Ransac<HomographyModel>,
    inliers: Vec<usize>,
}

impl TwoViewEstimator {
    /// An estimator for up to `max_points` correspondences per call (more still work, but may
    /// allocate).
    pub fn new(config: TwoViewConfig, max_points: usize) -> Self {
        Self {
            config,
            essential_ransac: Ransac::new(config.essential_ransac(), max_points),
            homography_ransac: Ransac::new(config.homography_ransac(), max_points),
            inliers: Vec::with_capacity(max_points),
        }
    }

    /// The configuration.
    pub fn config(&self) -> &TwoViewConfig {
        &self.config
    }

    /// Indices of the inliers of the model used by the last successful `estimate`.
    pub fn inliers(&self) -> &[usize] {
        &self.inliers
    }

    /// Estimates `cam2_from_cam1` from normalized correspondences `x1[i] ↔ x2[i]`.
    ///
    /// `plane_normal_prior_cam1`: expected normal of the dominant plane in camera 1, pointing
    /// from the camera to the plane (for ground: gravity "down" in camera 1). Used to pick the
    /// homography decomposition.
    pub fn estimate(
        &mut self,
        x1: &[Vector2<f64>],
        x2: &[Vector2<f64>],
        plane_normal_prior_cam1: Option<&UnitVector3<f64>>,
    ) -> Result<TwoViewEstimate, TwoViewError> {
        let cfg = self.config;
        self.check_input(x1, x2)?;
        self.inliers.clear();
        let cauchy_scale = 2f64.sqrt() * cfg.sigma_px / cfg.focal_px;
        let e_fit = self.essential_ransac.run(&EssentialProblem {
            x1,
            x2,
            solver: cfg.solver,
            refine_iterations: cfg.refine_iterations.min(5),
            cauchy_scale,
        });
        let h_fit = self.homography_ransac.run(&HomographyProblem { x1, x2 });
        let (e_inliers, h_inliers) = (
            e_fit.as_ref().map_or(0, |f| f.num_inliers),
            h_fit.as_ref().map_or(0, |f| f.num_inliers),
        );
        let inv_sigma = inv_sigma_sq(cfg.sigma_px / cfg.focal_px);
        let (choice, ratio) = match (&e_fit, &h_fit) {
            (Err(e), Err(h)) => {
                return Err(TwoViewError::NoModel {
                    essential: *e,
                    homography: *h,
                });
            }
            (Ok(_), Err(_)) => (ModelChoice::Essential, 0.0),
            (Err(_), Ok(_)) => (ModelChoice::Homography, 1.0),
            (Ok(e), Ok(h)) => {
                let r = homography_ratio(
                    score_homography(&h.model.h, &h.model.h_inv, x1, x2, inv_sigma),
                    score_essential(&e.model, x1, x2, inv_sigma),
                );
                (choose_model(r, cfg.homography_ratio_threshold), r)
            }
        };
        let mut estimate = TwoViewEstimate {
            cam2_from_cam1: Isometry3::identity(),
            model: MotionModel::Essential,
            num_inliers: 0,
            essential_inliers: e_inliers,
            homography_inliers: h_inliers,
            homography_ratio: ratio,
            plane_normal_cam1: None,
            translation_over_plane_distance: None,
            num_in_front: 0,
        };
        // Pure rotation: the nearest rotation to H explains (almost) all homography inliers.
        if let Ok(h) = &h_fit
            && let Some(rotation) = self.pure_rotation(&h.model.h, x1, x2)
        {
            estimate.model = MotionModel::PureRotation;
            estimate.cam2_from_cam1 = Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_rotation_matrix(&rotation),
            );
            self.inliers
                .extend_from_slice(self.homography_ransac.inliers());
            estimate.num_inliers = self.inliers.len();
            return self.check_inliers(estimate);
        }
        let use_h = choice == ModelChoice::Homography || e_fit.is_err();
        if use_h && let Ok(h) = &h_fit {
            self.take_homography_pose(&h.model.h, x1, x2, plane_normal_prior_cam1, &mut estimate)?;
        } else if let Ok(e) = &e_fit {
            self.take_essential_pose(&e.model, x1, x2, cauchy_scale, &mut estimate)?;
        }
        estimate.num_inliers = self.inliers.len();
        self.check_inliers(estimate)
    }

    /// Rejects a bad focal length or sigma, slices of different lengths, too few points and
    /// non-finite correspondences.
    fn check_input(&self, x1: &[Vector2<f64>], x2: &[Vector2<f64>]) -> Result<(), TwoViewError> {
        let cfg = &self.config;
        if !(cfg.focal_px.is_finite() && cfg.focal_px > 0.0) {
            return Err(TwoViewError::BadConfig("focal_px must be finite and > 0"));
        }
        if !(cfg.sigma_px.is_finite() && cfg.sigma_px > 0.0) {
            return Err(TwoViewError::BadConfig("sigma_px must be finite and > 0"));
        }
        if x1.len() != x2.len() {
            return Err(TwoViewError::LengthMismatch {
                x1: x1.len(),
                x2: x2.len(),
            });
        }
        let needed = cfg.min_inliers.max(8);
        if x1.len() < needed {
            return Err(TwoViewError::TooFewPoints {
                got: x1.len(),
                needed,
            });
        }
        if x1
            .iter()
            .chain(x2)
            .any(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(TwoViewError::BadConfig("correspondences must be finite"));
        }
        Ok(())
    }

    /// Fills `estimate` with the pose of the homography `h` (the decomposition the plane
    /// normal prior picks, or the first) and takes its inliers.
    fn take_homography_pose(
        &mut self,
        h: &Matrix3<f64>,
        x1: &[Vector2<f64>],
        x2: &[Vector2<f64>],
        plane_normal_prior_cam1: Option<&UnitVector3<f64>>,
        estimate: &mut TwoViewEstimate,
    ) -> Result<(), TwoViewError> {
        let h_inl = self.homography_ransac.inliers();
        let decomposition =
            decompose_homography(h, x1, x2, h_inl).map_err(|_| TwoViewError::PoseRecovery)?;
        let candidate = match (&decomposition, plane_normal_prior_cam1) {
            (HomographyDecomposition::Planar { .. }, Some(prior)) => {
                decomposition.select_by_normal(prior)
            }
            _ => decomposition.candidates().first().copied(),
        }
        .ok_or(TwoViewError::PoseRecovery)?;
        let t_over_d = candidate.cam2_from_cam1.translation.vector;
        let t_norm = t_over_d.norm();
        estimate.model = MotionModel::Homography;
        estimate.cam2_from_cam1 = Isometry3::from_parts(
            Translation3::from(if t_norm > 0.0 {
                t_over_d / t_norm
            } else {
                t_over_d
            }),
            candidate.cam2_from_cam1.rotation,
        );
        estimate.plane_normal_cam1 = Some(candidate.normal_cam1);
        estimate.translation_over_plane_distance = Some(t_over_d);
        estimate.num_in_front = candidate.num_in_front;
        self.inliers.extend_from_slice(h_inl);
        Ok(())
    }

    /// Fills `estimate` with the pose recovered from the essential matrix `e`, refined on its
    /// inliers, and takes those inliers.
    fn take_essential_pose(
        &mut self,
        e: &Matrix3<f64>,
        x1: &[Vector2<f64>],
        x2: &[Vector2<f64>],
        cauchy_scale: f64,
        estimate: &mut TwoViewEstimate,
    ) -> Result<(), TwoViewError> {
        let e_inl = self.essential_ransac.inliers();
        let pose = recover_pose(e, x1, x2, e_inl).map_err(|_| TwoViewError::PoseRecovery)?;
        estimate.cam2_from_cam1 = refine_pose_sampson(
            &pose.cam2_from_cam1,
            x1,
            x2,
            e_inl,
            self.config.refine_iterations,
            Some(cauchy_scale),
        );
        estimate.num_in_front = pose.num_in_front;
        self.inliers.extend_from_slice(e_inl);
        Ok(())
    }

    fn check_inliers(&self, estimate: TwoViewEstimate) -> Result<TwoViewEstimate, TwoViewError> {
        if estimate.num_inliers < self.config.min_inliers {
            return Err(TwoViewError::TooFewPoints {
                got: estimate.num_inliers,
                needed: self.config.min_inliers,
            });
        }
        Ok(estimate)
    }

    /// The rotation nearest to `h` if it explains enough of the homography inliers.
    fn pure_rotation(
        &self,
        h: &Matrix3<f64>,
        x1: &[Vector2<f64>],
        x2: &[Vector2<f64>],
    ) -> Option<nalgebra::Rotation3<f64>> {
        let h_inl = self.homography_ransac.inliers();
        if h_inl.is_empty() {
            return None;
        }
        let svd = h.try_svd(false, false, 1e-15, 200)?;
        let scale = svd.singular_values[1];
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        // Sign so that H x1 points along x2.
        let sign = h_inl
            .iter()
            .map(|&i| x2[i].push(1.0).dot(&(h * x1[i].push(1.0))))
            .sum::<f64>()
            .signum();
        let rotation = nearest_rotation(&(h * (sign / scale)))?;
        let r = rotation.into_inner();
        let t_sq = (self.config.homography_threshold_px() / self.config.focal_px).powi(2);
        let explained = h_inl
            .iter()
            .filter(|&&i| {
                let (f, b) = transfer_errors_sq(&r, &r.transpose(), &x1[i], &x2[i]);
                0.5 * (f + b) < t_sq
            })
            .count();
        (explained as f64 >= self.config.pure_rotation_inlier_fraction * h_inl.len() as f64)
            .then_some(rotation)
    }
}

#[cfg(test)]
mod tests;
