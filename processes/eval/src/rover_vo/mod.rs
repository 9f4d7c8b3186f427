//! Evaluation of the rover VO on a rendered traverse: TUM files (truth and estimate), ATE after
//! Sim(3) and SE(3) alignment, RPE, drift in % of the distance travelled, and a top-view PNG.
//!
//! The VO starts as the process does: attitude from the first IMU sample, (x, y) from the
//! known start point, z from the ground height under the start (a config value) plus the body
//! height the first stereo pair measures. It never reads the truth after that.
//!
//! ```no_run
//! use hopnav_eval::rover_vo::{EvalOptions, run};
//! let report = run(&EvalOptions::default()).unwrap();
//! println!("{report}");
//! ```

pub mod plot;

pub use hopnav_metrics::trajectory::{errors as metrics, tum};

use hopnav_rover_vo::config::RoverVoConfig;
use hopnav_rover_vo::pipeline::VoStatus;
use hopnav_rover_vo::run::{RunError, TraverseRun, quantile, run_traverse};
use hopnav_rover_vo::simulate::{SimulatedTraverse, TraverseConfig, simulate_traverse};
use nalgebra::Isometry3;
use std::path::PathBuf;

/// Error of [`run`].
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// The traverse could not be simulated, the VO could not be run over it, or it gave too
    /// few frames to evaluate (the driver's own errors, as the benchmark reports them).
    #[error(transparent)]
    Run(#[from] RunError),
    /// A TUM file could not be written.
    #[error(transparent)]
    Tum(#[from] tum::TumError),
    /// The plot could not be written.
    #[error(transparent)]
    Plot(#[from] plot::PlotError),
    /// The output folder could not be created.
    #[error("cannot create {path}: {message}")]
    OutDir {
        /// Folder.
        path: String,
        /// OS reason.
        message: String,
    },
}

/// What to evaluate.
#[derive(Debug, Clone, Default)]
pub struct EvalOptions {
    /// The traverse.
    pub traverse: TraverseConfig,
    /// VO settings.
    pub vo: RoverVoConfig,
    /// Where to write `truth.tum`, `estimate.tum` and `trajectory.png` (`None`: nothing written).
    pub out_dir: Option<PathBuf>,
}

/// Metrics of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EvalReport {
    /// Frames evaluated.
    pub frames: usize,
    /// Truth path length, metres.
    pub distance_m: f64,
    /// Final position error, metres.
    pub final_error_m: f64,
    /// Final position error / distance, percent.
    pub drift_percent: f64,
    /// Position RMSE without alignment, metres.
    pub rmse_unaligned_m: f64,
    /// ATE RMSE after Sim(3) alignment, metres.
    pub ate_sim3_m: f64,
    /// Sim(3) scale.
    pub sim3_scale: f64,
    /// ATE RMSE after SE(3) alignment, metres.
    pub ate_se3_m: f64,
    /// RPE over one frame: translation RMSE, metres.
    pub rpe_frame_m: f64,
    /// RPE over one frame: rotation RMSE, radians.
    pub rpe_frame_rad: f64,
    /// RPE translation per metre travelled, percent (over 10 frames).
    pub rpe_percent_per_m: f64,
    /// Final yaw error, radians.
    pub final_yaw_error_rad: f64,
    /// Frames with a propagated pose.
    pub propagated_frames: usize,
    /// Keyframes.
    pub keyframes: usize,
    /// Cloud points checked against the terrain (depth ≤ 10 m).
    pub cloud_points_checked: usize,
    /// RMS of the estimated height above ground of points that lie on the terrain (true
    /// height < 0.05 m), metres.
    pub cloud_ground_rms_m: f64,
    /// Share of points truly ≥ 0.3 m above the terrain (rock tops) given a height > 0.15 m.
    pub cloud_rock_detected: f64,
    /// Share of points on the terrain given a height > 0.3 m (false obstacles).
    pub cloud_false_obstacles: f64,
    /// Frame time p50, milliseconds.
    pub p50_ms: f64,
    /// Frame time p99, milliseconds.
    pub p99_ms: f64,
    /// Frame time max, milliseconds.
    pub max_ms: f64,
}

/// Cloud height statistics: `(checked, ground RMS, rock detected share, false obstacle share)`.
/// A point's truth is its estimate moved by the keyframe's pose error.
fn cloud_heights(run: &TraverseRun, sim: &SimulatedTraverse) -> (usize, f64, f64, f64) {
    let (mut n, mut ground_sq, mut ground_n, mut rock_n, mut rock_hit, mut false_obst) =
        (0usize, 0.0, 0usize, 0usize, 0usize, 0usize);
    for (k, p) in &run.clouds {
        let (Some(est), Some(truth)) = (run.outputs.get(*k), sim.truth_world_from_body.get(*k))
        else {
            continue;
        };
        if !p.height_above_ground_m.is_finite()
            || (p.position_m.coords - est.world_from_body.translation.vector).norm() > 10.0
        {
            continue;
        }
        let true_point = truth * est.world_from_body.inverse() * p.position_m;
        let true_h = true_point.z - sim.world.ground_height_at(true_point.x, true_point.y);
        n += 1;
        if true_h < 0.05 {
            ground_n += 1;
            ground_sq += p.height_above_ground_m.powi(2);
            false_obst += usize::from(p.height_above_ground_m > 0.3);
        } else if true_h >= 0.3 {
            rock_n += 1;
            rock_hit += usize::from(p.height_above_ground_m > 0.15);
        }
    }
    let share = |a: usize, b: usize| {
        if b == 0 {
            f64::NAN
        } else {
            a as f64 / b as f64
        }
    };
    (
        n,
        (ground_sq / ground_n.max(1) as f64).sqrt(),
        share(rock_hit, rock_n),
        share(false_obst, ground_n),
    )
}

/// Metrics of `run` against the truth of `sim`.
pub fn evaluate_traverse(run: &TraverseRun, sim: &SimulatedTraverse) -> Option<EvalReport> {
    let mut report = evaluate(run, &sim.truth_world_from_body)?;
    let (n, rms, rock, false_obst) = cloud_heights(run, sim);
    report.cloud_points_checked = n;
    report.cloud_ground_rms_m = rms;
    report.cloud_rock_detected = rock;
    report.cloud_false_obstacles = false_obst;
    Some(report)
}

/// Trajectory metrics of `run` against `truth` (cloud fields NaN; see [`evaluate_traverse`]).
pub fn evaluate(run: &TraverseRun, truth: &[Isometry3<f64>]) -> Option<EvalReport> {
    let n = run.outputs.len().min(truth.len());
    if n < 12 {
        return None;
    }
    let est: Vec<Isometry3<f64>> = run.outputs[..n].iter().map(|o| o.world_from_body).collect();
    let gt = &truth[..n];
    let distance_m: f64 = gt
        .windows(2)
        .map(|w| (w[1].translation.vector - w[0].translation.vector).norm())
        .sum();
    let sim3 = metrics::ate(&est, gt, true)?;
    let se3 = metrics::ate(&est, gt, false)?;
    let rpe1 = metrics::rpe(&est, gt, 1)?;
    let rpe10 = metrics::rpe(&est, gt, 10)?;
    let final_error_m = metrics::final_position_error_m(&est, gt)?;
    let mut times = run.frame_time_us.clone();
    times.sort_by(f64::total_cmp);
    let yaw = |p: &Isometry3<f64>| p.rotation.euler_angles().2;
    let dyaw = yaw(&est[n - 1]) - yaw(&gt[n - 1]);
    let dyaw =
        (dyaw + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    Some(EvalReport {
        frames: n,
        distance_m,
        final_error_m,
        drift_percent: 100.0 * final_error_m / distance_m.max(1e-9),
        rmse_unaligned_m: metrics::unaligned_rmse_m(&est, gt),
        ate_sim3_m: sim3.rmse_m,
        sim3_scale: sim3.alignment.scale,
        ate_se3_m: se3.rmse_m,
        rpe_frame_m: rpe1.translation_rmse_m,
        rpe_frame_rad: rpe1.rotation_rmse_rad,
        rpe_percent_per_m: 100.0 * rpe10.translation_per_m,
        final_yaw_error_rad: dyaw,
        propagated_frames: run.outputs[..n]
            .iter()
            .filter(|o| o.status == VoStatus::Propagated)
            .count(),
        keyframes: run.outputs[..n].iter().filter(|o| o.is_keyframe).count(),
        cloud_points_checked: 0,
        cloud_ground_rms_m: f64::NAN,
        cloud_rock_detected: f64::NAN,
        cloud_false_obstacles: f64::NAN,
        p50_ms: quantile(&times, 0.5) / 1e3,
        p99_ms: quantile(&times, 0.99) / 1e3,
        max_ms: times.last().copied().unwrap_or(f64::NAN) / 1e3,
    })
}

impl std::fmt::Display for EvalReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "rover VO: {} frames, {:.1} m travelled, {} keyframes, {} propagated",
            self.frames, self.distance_m, self.keyframes, self.propagated_frames
        )?;
        writeln!(
            f,
            "  drift: final error {:.3} m = {:.2} % of distance | RPE {:.2} % per m (10 frames) | final yaw error {:.2}°",
            self.final_error_m,
            self.drift_percent,
            self.rpe_percent_per_m,
            self.final_yaw_error_rad.to_degrees()
        )?;
        writeln!(
            f,
            "  ATE: sim3 {:.3} m (scale {:.4}) | se3 {:.3} m | unaligned {:.3} m | RPE {:.4} m/frame {:.3}°/frame",
            self.ate_sim3_m,
            self.sim3_scale,
            self.ate_se3_m,
            self.rmse_unaligned_m,
            self.rpe_frame_m,
            self.rpe_frame_rad.to_degrees()
        )?;
        writeln!(
            f,
            "  cloud (≤ 10 m, {} points): ground height RMS {:.3} m | rock tops (≥ 0.3 m) seen > 0.15 m: {:.0} % | false obstacles (> 0.3 m): {:.1} %",
            self.cloud_points_checked,
            self.cloud_ground_rms_m,
            100.0 * self.cloud_rock_detected,
            100.0 * self.cloud_false_obstacles
        )?;
        write!(
            f,
            "  time per stereo frame: p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
            self.p50_ms, self.p99_ms, self.max_ms
        )
    }
}

/// Simulates the traverse, runs the VO, computes the metrics, and writes the TUM files and
/// the PNG if `options.out_dir` is set.
pub fn run(options: &EvalOptions) -> Result<EvalReport, EvalError> {
    let sim = simulate_traverse(&options.traverse).map_err(RunError::from)?;
    let run = run_traverse(&sim, &options.vo)?;
    let report = evaluate_traverse(&run, &sim).ok_or(RunError::TooFewFrames)?;
    if let Some(dir) = &options.out_dir {
        std::fs::create_dir_all(dir).map_err(|e| EvalError::OutDir {
            path: dir.display().to_string(),
            message: e.to_string(),
        })?;
        let stamped =
            |poses: &mut dyn Iterator<Item = Isometry3<f64>>| -> Vec<(f64, Isometry3<f64>)> {
                sim.t_s.iter().copied().zip(poses).collect()
            };
        let truth = stamped(&mut sim.truth_world_from_body.iter().copied());
        let estimate = stamped(&mut run.outputs.iter().map(|o| o.world_from_body));
        tum::write_tum(&dir.join("truth.tum"), &truth)?;
        tum::write_tum(&dir.join("estimate.tum"), &estimate)?;
        plot::write_top_view_png(
            &dir.join("trajectory.png"),
            &sim.truth_world_from_body,
            &run.poses(),
        )?;
    }
    Ok(report)
}
