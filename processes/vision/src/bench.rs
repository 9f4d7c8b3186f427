//! Own-harness per-frame benchmark (no criterion): pyramid, corners, KLT with the
//! forward–backward check, and two-view estimation, reported as p50/p99/max.
//!
//! The image stages run on two synthetic 320×320 textured frames (the second rotated and
//! shifted); the geometry stage runs on a synthetic 3-D scene with the same number of
//! correspondences and 10 % outliers, because an image warp is a homography and would make the
//! essential-matrix RANSAC degenerate. Target (issue 4): ≤ 5 ms per frame at 320² with 1000
//! features. Run with `cargo run --release --example bench_vision`.
//!
//! ```
//! use hopnav_vision::bench::{BenchConfig, run_frame_benchmark};
//! let report = run_frame_benchmark(&BenchConfig { width: 96, height: 96, features: 60, iterations: 2 }).unwrap();
//! assert!(report.stage("klt").is_some());
//! println!("{report}");
//! ```

use crate::camera::PinholeCamera;
use crate::corners::{Corner, CornerConfig, CornerDetector};
use crate::image::ImageView;
use crate::klt::{KltConfig, KltTracker, TrackStatus};
use crate::pyramid::{Pyramid, PyramidConfig};
use crate::ransac::Ransac;
use crate::synthetic::{AffineWarp, BlobTexture, TwoViewScene, random_points_in_box};
use crate::two_view::{EssentialProblem, HomographyProblem, TwoViewConfig, TwoViewEstimator};
use nalgebra::{Isometry3, Point2, Vector3};
use std::fmt;
use std::time::Instant;

/// Benchmark shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BenchConfig {
    /// Frame width in pixels.
    pub width: usize,
    /// Frame height in pixels.
    pub height: usize,
    /// Features to detect, track and feed to the geometry stage.
    pub features: usize,
    /// Timed repetitions.
    pub iterations: usize,
}

impl Default for BenchConfig {
    fn default() -> Self {
        Self {
            width: 320,
            height: 320,
            features: 1000,
            iterations: 100,
        }
    }
}

/// Timing statistics of one stage.
#[derive(Debug, Clone, PartialEq)]
pub struct StageTiming {
    /// Stage name.
    pub name: &'static str,
    /// Median, microseconds.
    pub p50_us: f64,
    /// 99th percentile, microseconds.
    pub p99_us: f64,
    /// Maximum, microseconds.
    pub max_us: f64,
}

/// Result of [`run_frame_benchmark`].
#[derive(Debug, Clone, PartialEq)]
pub struct BenchReport {
    /// The configuration used.
    pub config: BenchConfig,
    /// Corners detected in the first frame.
    pub detected: usize,
    /// Of those, tracks that passed every check.
    pub tracked: usize,
    /// Correspondences given to the geometry stage.
    pub correspondences: usize,
    /// Per-stage statistics; `frame` is pyramid + KLT + corners + two-view;
    /// `essential_ransac` and `homography_ransac` time the two RANSAC runs inside two-view alone.
    pub stages: Vec<StageTiming>,
}

impl BenchReport {
    /// Statistics of a stage by name.
    pub fn stage(&self, name: &str) -> Option<&StageTiming> {
        self.stages.iter().find(|s| s.name == name)
    }
}

impl fmt::Display for BenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}x{} px, {} detected, {} tracked, {} correspondences, {} iterations",
            self.config.width,
            self.config.height,
            self.detected,
            self.tracked,
            self.correspondences,
            self.config.iterations
        )?;
        writeln!(
            f,
            "{:<22} {:>10} {:>10} {:>10}",
            "stage", "p50 ms", "p99 ms", "max ms"
        )?;
        for s in &self.stages {
            writeln!(
                f,
                "{:<22} {:>10.3} {:>10.3} {:>10.3}",
                s.name,
                s.p50_us / 1e3,
                s.p99_us / 1e3,
                s.max_us / 1e3
            )?;
        }
        Ok(())
    }
}

/// Error of the benchmark setup.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BenchError {
    /// A component rejected the configuration.
    #[error("benchmark setup failed: {0}")]
    Setup(String),
    /// `iterations` is zero.
    #[error("iterations must be >= 1")]
    NoIterations,
}

fn stats(name: &'static str, samples_us: &mut [f64]) -> StageTiming {
    samples_us.sort_by(f64::total_cmp);
    let pick = |q: f64| {
        if samples_us.is_empty() {
            return 0.0;
        }
        let i = ((samples_us.len() - 1) as f64 * q).round() as usize;
        samples_us[i.min(samples_us.len() - 1)]
    };
    StageTiming {
        name,
        p50_us: pick(0.5),
        p99_us: pick(0.99),
        max_us: samples_us.last().copied().unwrap_or(0.0),
    }
}

fn setup<E: fmt::Display>(e: E) -> BenchError {
    BenchError::Setup(e.to_string())
}

/// Per-iteration timings of each stage, microseconds.
struct StageSamples {
    pyramid: Vec<f64>,
    klt: Vec<f64>,
    corners: Vec<f64>,
    two_view: Vec<f64>,
    frame: Vec<f64>,
    essential: Vec<f64>,
    homography: Vec<f64>,
}

impl StageSamples {
    fn with_capacity(n: usize) -> Self {
        Self {
            pyramid: Vec::with_capacity(n),
            klt: Vec::with_capacity(n),
            corners: Vec::with_capacity(n),
            two_view: Vec::with_capacity(n),
            frame: Vec::with_capacity(n),
            essential: Vec::with_capacity(n),
            homography: Vec::with_capacity(n),
        }
    }

    /// The report's stages, in the report's order.
    fn into_stages(mut self) -> Vec<StageTiming> {
        vec![
            stats("pyramid", &mut self.pyramid),
            stats("klt", &mut self.klt),
            stats("corners", &mut self.corners),
            stats("two_view", &mut self.two_view),
            stats("frame", &mut self.frame),
            stats("essential_ransac", &mut self.essential),
            stats("homography_ransac", &mut self.homography),
        ]
    }
}

/// The corners detected on the first frame's full-resolution level.
fn first_corners(
    detector: &mut CornerDetector,
    prev: &Pyramid,
    features: usize,
) -> Result<Vec<Point2<f32>>, BenchError> {
    let mut corners: Vec<Corner> = Vec::with_capacity(features);
    detector
        .detect(
            prev.level(0).ok_or_else(|| setup("no level"))?,
            &[],
            &mut corners,
        )
        .map_err(setup)?;
    Ok(corners.iter().map(|c| c.position_px).collect())
}

/// Two frames of a dense blob texture (about one blob per 25 px²), the second rotated by 1.5°
/// and shifted.
fn synthetic_frames(w: usize, h: usize) -> (Vec<u8>, Vec<u8>) {
    let texture = BlobTexture::random(w, h, (w * h / 25).max(50), 77);
    let warp = AffineWarp::rotation_about(
        1.5f64.to_radians(),
        w as f64 / 2.0,
        h as f64 / 2.0,
        2.3,
        -1.7,
    );
    let mut frame1 = vec![0u8; w * h];
    let mut frame2 = vec![0u8; w * h];
    texture.render(w, h, &AffineWarp::identity(), &mut frame1);
    texture.render(w, h, &warp, &mut frame2);
    (frame1, frame2)
}

/// Geometry input: a camera and a 3-D scene seen from two poses with as many
/// correspondences as `features`.
fn geometry_input(
    w: usize,
    h: usize,
    features: usize,
) -> Result<(PinholeCamera, TwoViewScene), BenchError> {
    let camera = PinholeCamera::from_fov(
        u32::try_from(w).map_err(setup)?,
        u32::try_from(h).map_err(setup)?,
        45f64.to_radians(),
        45f64.to_radians(),
    )
    .map_err(setup)?;
    let motion = Isometry3::new(Vector3::new(-0.5, 0.1, 0.3), Vector3::new(0.01, 0.03, 0.0));
    let points = random_points_in_box(features * 2, 6.0, 5.0, 20.0, 3);
    let mut scene = TwoViewScene::from_points(&camera, motion, &points, 0.5, 0.1, 4);
    scene.x1_norm.truncate(features);
    scene.x2_norm.truncate(features);
    Ok((camera, scene))
}

/// The image stages' state: both pyramids, the detector and the tracker, and their buffers.
struct ImageStages {
    prev: Pyramid,
    next: Pyramid,
    detector: CornerDetector,
    tracker: KltTracker,
    prev_px: Vec<Point2<f32>>,
    next_px: Vec<Point2<f32>>,
    status: Vec<TrackStatus>,
    survivors: Vec<Point2<f32>>,
    new_corners: Vec<Corner>,
}

impl ImageStages {
    /// Builds the first frame's pyramid and detects the corners the benchmark tracks.
    fn new(config: &BenchConfig, first: &ImageView<'_>) -> Result<Self, BenchError> {
        let (w, h) = (config.width, config.height);
        let mut prev = Pyramid::new(w, h, PyramidConfig::default()).map_err(setup)?;
        let next = Pyramid::new(w, h, PyramidConfig::default()).map_err(setup)?;
        // 1000 features in 320² need a tighter spacing than the default 6 px.
        let corner_config = CornerConfig {
            max_features: config.features,
            min_distance_px: 5.0,
            fill_leftover_budget: true,
            ..CornerConfig::default()
        };
        let mut detector = CornerDetector::new(w, h, corner_config).map_err(setup)?;
        let tracker = KltTracker::new(KltConfig::default(), config.features).map_err(setup)?;
        prev.build(first).map_err(setup)?;
        let prev_px = first_corners(&mut detector, &prev, config.features)?;
        Ok(Self {
            prev,
            next,
            detector,
            tracker,
            next_px: vec![Point2::origin(); prev_px.len()],
            status: vec![TrackStatus::Tracked; prev_px.len()],
            prev_px,
            survivors: Vec::with_capacity(config.features),
            new_corners: Vec::with_capacity(config.features),
        })
    }

    /// Runs the image stages on `second` and `geometry` on the scene's correspondences, once,
    /// timing each into `t`; returns how many features were tracked.
    fn time_frame(
        &mut self,
        second: &ImageView<'_>,
        mut geometry: impl FnMut(),
        t: &mut StageSamples,
    ) -> Result<usize, BenchError> {
        let start = Instant::now();
        self.next.build(second).map_err(setup)?;
        let after_pyramid = Instant::now();
        let track_stats = self
            .tracker
            .track(
                &self.prev,
                &self.next,
                &self.prev_px,
                &mut self.next_px,
                &mut self.status,
                false,
            )
            .map_err(setup)?;
        let after_klt = Instant::now();
        self.survivors.clear();
        self.survivors.extend(
            self.next_px
                .iter()
                .zip(&self.status)
                .filter(|(_, s)| **s == TrackStatus::Tracked)
                .map(|(p, _)| *p),
        );
        self.detector
            .detect(
                self.next.level(0).ok_or_else(|| setup("no level"))?,
                &self.survivors,
                &mut self.new_corners,
            )
            .map_err(setup)?;
        let after_corners = Instant::now();
        geometry();
        let end = Instant::now();
        t.pyramid.push(micros(start, after_pyramid));
        t.klt.push(micros(after_pyramid, after_klt));
        t.corners.push(micros(after_klt, after_corners));
        t.two_view.push(micros(after_corners, end));
        t.frame.push(micros(start, end));
        Ok(track_stats.tracked)
    }
}

/// Microseconds from `a` to `b`.
fn micros(a: Instant, b: Instant) -> f64 {
    (b - a).as_secs_f64() * 1e6
}

/// Runs the per-frame pipeline `config.iterations` times and reports per-stage timings.
pub fn run_frame_benchmark(config: &BenchConfig) -> Result<BenchReport, BenchError> {
    if config.iterations == 0 {
        return Err(BenchError::NoIterations);
    }
    let (w, h) = (config.width, config.height);
    let (frame1, frame2) = synthetic_frames(w, h);
    let view1 = ImageView::packed(&frame1, w, h).map_err(setup)?;
    let view2 = ImageView::packed(&frame2, w, h).map_err(setup)?;
    let mut images = ImageStages::new(config, &view1)?;

    let (camera, scene) = geometry_input(w, h, config.features)?;
    let mut two_view = TwoViewEstimator::new(TwoViewConfig::for_camera(&camera), config.features);

    let n = config.iterations;
    let mut t = StageSamples::with_capacity(n);
    let tv = *two_view.config();
    let mut e_ransac = Ransac::new(tv.essential_ransac(), config.features);
    let mut h_ransac = Ransac::new(tv.homography_ransac(), config.features);
    let e_problem = EssentialProblem {
        x1: &scene.x1_norm,
        x2: &scene.x2_norm,
        solver: tv.solver,
        refine_iterations: tv.refine_iterations.min(5),
        cauchy_scale: 2f64.sqrt() * tv.sigma_px / tv.focal_px,
    };
    let h_problem = HomographyProblem {
        x1: &scene.x1_norm,
        x2: &scene.x2_norm,
    };
    let mut tracked = 0;
    for _ in 0..n {
        // A failed estimate is timed like a successful one.
        let geometry = || {
            let _ = two_view.estimate(&scene.x1_norm, &scene.x2_norm, None);
        };
        tracked = images.time_frame(&view2, geometry, &mut t)?;
        let a = Instant::now();
        let _ = e_ransac.run(&e_problem);
        let b = Instant::now();
        let _ = h_ransac.run(&h_problem);
        let c = Instant::now();
        t.essential.push(micros(a, b));
        t.homography.push(micros(b, c));
    }
    Ok(BenchReport {
        config: *config,
        detected: images.prev_px.len(),
        tracked,
        correspondences: scene.x1_norm.len(),
        stages: t.into_stages(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_benchmark_runs() {
        let report = run_frame_benchmark(&BenchConfig {
            width: 128,
            height: 128,
            features: 120,
            iterations: 2,
        })
        .unwrap();
        assert!(report.detected > 60, "{report}");
        assert!(
            report.tracked as f64 > 0.8 * report.detected as f64,
            "{report}"
        );
        assert_eq!(report.stages.len(), 7);
        assert!(
            run_frame_benchmark(&BenchConfig {
                iterations: 0,
                ..BenchConfig::default()
            })
            .is_err()
        );
    }
}
