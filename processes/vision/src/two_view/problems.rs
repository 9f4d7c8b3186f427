//! The two RANSAC problems of the two-view estimator: the essential matrix (Sampson
//! residual, local optimisation by LM) and the homography (symmetric transfer residual).

use crate::essential::eight_point::essential_eight_point;
use crate::essential::five_point::essential_five_point;
use crate::essential::refine::refine_pose_sampson;
use crate::essential::{essential_from_pose, recover_pose, sampson_error_sq};
use crate::homography::{has_collinear_triple, homography_dlt, transfer_errors_sq};
use crate::ransac::RansacProblem;
use nalgebra::{Matrix3, Vector2};

use super::EssentialSolver;

/// Inliers used by the LM step of local optimisation.
const LO_MAX_POINTS: usize = 256;

/// Essential-matrix RANSAC problem (normalized coordinates, Sampson residual).
#[derive(Debug, Clone, Copy)]
pub struct EssentialProblem<'a> {
    /// View-1 points.
    pub x1: &'a [Vector2<f64>],
    /// View-2 points.
    pub x2: &'a [Vector2<f64>],
    /// Minimal solver.
    pub solver: EssentialSolver,
    /// LM iterations in local optimisation (0: 8-point refit only).
    pub refine_iterations: usize,
    /// Cauchy scale of the LM refit (expected Sampson error, normalized units).
    pub cauchy_scale: f64,
}

impl RansacProblem for EssentialProblem<'_> {
    type Model = Matrix3<f64>;

    fn num_data(&self) -> usize {
        self.x1.len().min(self.x2.len())
    }

    fn sample_size(&self) -> usize {
        match self.solver {
            EssentialSolver::FivePoint => 5,
            EssentialSolver::EightPoint => 8,
        }
    }

    fn fit_minimal(&self, sample: &[usize], models: &mut Vec<Matrix3<f64>>) {
        match self.solver {
            EssentialSolver::FivePoint => essential_five_point(self.x1, self.x2, sample, models),
            EssentialSolver::EightPoint => {
                if let Ok(e) = essential_eight_point(self.x1, self.x2, sample) {
                    models.push(e);
                }
            }
        }
    }

    fn fit_refine(&self, model: &Matrix3<f64>, inliers: &[usize], models: &mut Vec<Matrix3<f64>>) {
        if let Ok(e) = essential_eight_point(self.x1, self.x2, inliers) {
            models.push(e);
        }
        // Robust Sampson LM from the current model: algebraic refits alone can slide along the
        // rotation/translation ambiguity valley when a few accidental inliers are present.
        // A strided subset of at most LO_MAX_POINTS inliers is enough to find the basin; the
        // final refinement uses all of them.
        let stride = inliers.len().div_ceil(LO_MAX_POINTS).max(1);
        let mut subset = [0usize; LO_MAX_POINTS];
        let mut count = 0;
        for &i in inliers.iter().step_by(stride).take(LO_MAX_POINTS) {
            subset[count] = i;
            count += 1;
        }
        let subset = &subset[..count];
        if self.refine_iterations > 0
            && let Ok(pose) = recover_pose(model, self.x1, self.x2, subset)
        {
            let refined = refine_pose_sampson(
                &pose.cam2_from_cam1,
                self.x1,
                self.x2,
                subset,
                self.refine_iterations,
                Some(self.cauchy_scale),
            );
            models.push(essential_from_pose(&refined));
        }
    }

    fn residual_sq(&self, e: &Matrix3<f64>, i: usize) -> f64 {
        sampson_error_sq(e, &self.x1[i], &self.x2[i])
    }
}

/// A homography with its inverse (for the symmetric residual).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomographyModel {
    /// `x2 ~ H x1`.
    pub h: Matrix3<f64>,
    /// `H⁻¹`.
    pub h_inv: Matrix3<f64>,
}

impl HomographyModel {
    fn new(h: Matrix3<f64>) -> Option<Self> {
        let h_inv = h.try_inverse()?;
        h_inv
            .iter()
            .all(|v| v.is_finite())
            .then_some(Self { h, h_inv })
    }
}

/// Homography RANSAC problem; residual = `(fwd² + bwd²) / 2` so the threshold matches one
/// image's transfer error.
#[derive(Debug, Clone, Copy)]
pub struct HomographyProblem<'a> {
    /// View-1 points.
    pub x1: &'a [Vector2<f64>],
    /// View-2 points.
    pub x2: &'a [Vector2<f64>],
}

impl RansacProblem for HomographyProblem<'_> {
    type Model = HomographyModel;

    fn num_data(&self) -> usize {
        self.x1.len().min(self.x2.len())
    }

    fn sample_size(&self) -> usize {
        4
    }

    fn is_degenerate_sample(&self, s: &[usize]) -> bool {
        s.len() < 4
            || has_collinear_triple([
                &self.x1[s[0]],
                &self.x1[s[1]],
                &self.x1[s[2]],
                &self.x1[s[3]],
            ])
            || has_collinear_triple([
                &self.x2[s[0]],
                &self.x2[s[1]],
                &self.x2[s[2]],
                &self.x2[s[3]],
            ])
    }

    fn fit_minimal(&self, sample: &[usize], models: &mut Vec<HomographyModel>) {
        if let Some(m) = homography_dlt(self.x1, self.x2, sample)
            .ok()
            .and_then(HomographyModel::new)
        {
            models.push(m);
        }
    }

    fn fit_refine(
        &self,
        _model: &HomographyModel,
        inliers: &[usize],
        models: &mut Vec<HomographyModel>,
    ) {
        self.fit_minimal(inliers, models);
    }

    fn residual_sq(&self, m: &HomographyModel, i: usize) -> f64 {
        let (f, b) = transfer_errors_sq(&m.h, &m.h_inv, &self.x1[i], &self.x2[i]);
        0.5 * (f + b)
    }
}
