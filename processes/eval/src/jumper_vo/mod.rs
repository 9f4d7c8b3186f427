//! Evaluation of the jumper VO against ground truth: ATE after Sim(3) and SE(3) alignment,
//! RPE, final position error, TUM files and a Fig.-5-style PNG.
//!
//! `hopnav_jumper_vo::run::run_hop` feeds a simulated hop frame by frame through the VO and
//! times `process_frame`; [`evaluate`] computes the metrics. [`cloud_heights`] judges the
//! keyframe clouds' heights against the world they were rendered from; [`dataset`] scores a
//! recorded launch.

pub mod cases;
pub mod cloud_heights;
pub mod dataset;
pub mod plot;
pub mod truth_surface;

pub use hopnav_metrics::trajectory::{align, errors as metrics, tum};

use hopnav_jumper_vo::output::{VoOutput, VoStatus};
use nalgebra::Isometry3;

/// Metrics of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoReport {
    /// Frames evaluated.
    pub frames: usize,
    /// Position RMSE with no alignment (the VO starts from the true launch pose), metres.
    pub rmse_unaligned_m: f64,
    /// ATE RMSE after Sim(3) Umeyama alignment, metres.
    pub ate_sim3_m: f64,
    /// ATE RMSE after SE(3) Umeyama alignment, metres.
    pub ate_se3_m: f64,
    /// Scale of the Sim(3) alignment (1 = perfect metric scale).
    pub sim3_scale: f64,
    /// RPE over one frame: translation RMSE, metres.
    pub rpe_frame_m: f64,
    /// RPE over one frame: rotation RMSE, radians.
    pub rpe_frame_rad: f64,
    /// RPE translation per metre travelled (over one frame).
    pub rpe_per_m: f64,
    /// Final position error, metres.
    pub final_error_m: f64,
    /// Largest attitude error over the run, radians.
    pub max_rotation_error_rad: f64,
    /// Frames not produced by a vision estimate (propagated, landed, rejected).
    pub non_tracking_frames: usize,
    /// Keyframes.
    pub keyframes: usize,
    /// Share of the frames with a position σ whose unaligned error is within 2 σ, percent
    /// (whether the σ the VO publishes is honest; NaN without any σ).
    pub within_two_sigma_percent: f64,
}

/// Computes the metrics of `outputs` against `truth` (matched by index).
pub fn evaluate(outputs: &[VoOutput], truth: &[Isometry3<f64>]) -> Option<VoReport> {
    let n = outputs.len().min(truth.len());
    let est: Vec<Isometry3<f64>> = outputs[..n].iter().map(|o| o.world_from_body).collect();
    let gt = &truth[..n];
    let sim3 = metrics::ate(&est, gt, true)?;
    let se3 = metrics::ate(&est, gt, false)?;
    let rpe = metrics::rpe(&est, gt, 1)?;
    Some(VoReport {
        frames: n,
        rmse_unaligned_m: metrics::unaligned_rmse_m(&est, gt),
        ate_sim3_m: sim3.rmse_m,
        ate_se3_m: se3.rmse_m,
        sim3_scale: sim3.alignment.scale,
        rpe_frame_m: rpe.translation_rmse_m,
        rpe_frame_rad: rpe.rotation_rmse_rad,
        rpe_per_m: rpe.translation_per_m,
        final_error_m: metrics::final_position_error_m(&est, gt)?,
        max_rotation_error_rad: est
            .iter()
            .zip(gt)
            .map(|(e, g)| e.rotation.angle_to(&g.rotation))
            .fold(0.0, f64::max),
        non_tracking_frames: outputs[..n]
            .iter()
            .filter(|o| !matches!(o.status, VoStatus::Tracking | VoStatus::Initializing))
            .count(),
        keyframes: outputs[..n].iter().filter(|o| o.is_keyframe).count(),
        within_two_sigma_percent: within_two_sigma_percent(&outputs[..n], gt),
    })
}

/// Share of the outputs with a finite position σ whose error is within twice it, percent.
fn within_two_sigma_percent(outputs: &[VoOutput], truth: &[Isometry3<f64>]) -> f64 {
    let judged: Vec<bool> = outputs
        .iter()
        .zip(truth)
        .filter(|(o, _)| o.position_sigma_m.is_finite())
        .map(|(o, g)| {
            let error = (o.world_from_body.translation.vector - g.translation.vector).norm();
            error <= 2.0 * o.position_sigma_m
        })
        .collect();
    if judged.is_empty() {
        return f64::NAN;
    }
    100.0 * judged.iter().filter(|&&inside| inside).count() as f64 / judged.len() as f64
}

impl std::fmt::Display for VoReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "frames {} | ATE sim3 {:.3} m (scale {:.3}) | ATE se3 {:.3} m | unaligned {:.3} m | \
             RPE {:.3} m/frame {:.2}°/frame {:.3} m/m | final {:.3} m | max rot err {:.2}° | \
             non-tracking {} | keyframes {} | within 2σ {:.0} %",
            self.frames,
            self.ate_sim3_m,
            self.sim3_scale,
            self.ate_se3_m,
            self.rmse_unaligned_m,
            self.rpe_frame_m,
            self.rpe_frame_rad.to_degrees(),
            self.rpe_per_m,
            self.final_error_m,
            self.max_rotation_error_rad.to_degrees(),
            self.non_tracking_frames,
            self.keyframes,
            self.within_two_sigma_percent
        )
    }
}
