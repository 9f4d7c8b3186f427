//! Generic RANSAC with MSAC scoring, adaptive iteration count and local optimisation.
//!
//! - **Adaptive iterations** (paper eq. 6): `N = log(1 − p) / log(1 − (1 − e)^s)` where `e` is the
//!   outlier ratio of the best model so far, `s` the sample size and `p` the confidence.
//! - **MSAC**: a model's cost is `Σ min(r², T²)`; lower is better (inliers are weighted by how
//!   well they fit, unlike plain inlier counting). Scoring stops early once a hypothesis is
//!   worse than the best so far, or 1.5× worse pro rata after 128 points (bail-out).
//! - **LO-RANSAC**: each time a new best model is found it is refit on all of its inliers
//!   ([`RansacProblem::fit_refine`]), repeated while the cost drops (at most
//!   `local_optimization_steps` times).
//! - **Deterministic**: the sampler is seeded from [`RansacConfig::seed`].
//!
//! Buffers live in [`Ransac`] and are reused between calls.
//!
//! ```
//! use hopnav_vision::ransac::{Ransac, RansacConfig, RansacProblem, adaptive_iterations};
//! // Fit y = a·x to points, with one outlier.
//! struct Line<'a>(&'a [(f64, f64)]);
//! impl RansacProblem for Line<'_> {
//!     type Model = f64;
//!     fn num_data(&self) -> usize { self.0.len() }
//!     fn sample_size(&self) -> usize { 1 }
//!     fn fit_minimal(&self, s: &[usize], out: &mut Vec<f64>) {
//!         let (x, y) = self.0[s[0]];
//!         if x != 0.0 { out.push(y / x) }
//!     }
//!     fn residual_sq(&self, a: &f64, i: usize) -> f64 { let (x, y) = self.0[i]; (y - a * x).powi(2) }
//! }
//! let pts = [(1.0, 2.0), (2.0, 4.0), (3.0, 6.0), (4.0, -9.0)];
//! let mut ransac = Ransac::new(RansacConfig { threshold: 0.1, ..RansacConfig::default() }, 4);
//! let fit = ransac.run(&Line(&pts)).unwrap();
//! assert!((fit.model - 2.0).abs() < 1e-12 && fit.num_inliers == 3);
//! assert!(adaptive_iterations(0.99, 0.5, 5) > 100);
//! ```

use crate::rng::XorShiftRng;

/// A model-fitting problem RANSAC can solve.
pub trait RansacProblem {
    /// The fitted model.
    type Model: Clone;
    /// Number of data points.
    fn num_data(&self) -> usize;
    /// Minimal sample size `s`.
    fn sample_size(&self) -> usize;
    /// Fits the minimal sample; pushes zero or more models (e.g. up to 10 for five-point).
    fn fit_minimal(&self, sample: &[usize], models: &mut Vec<Self::Model>);
    /// Non-minimal refit of `model` on its inliers for local optimisation; pushes candidates
    /// (the best by MSAC cost is kept if it beats `model`). Default: none.
    fn fit_refine(&self, _model: &Self::Model, _inliers: &[usize], _models: &mut Vec<Self::Model>) {
    }
    /// Squared residual of data point `index` (same unit as `threshold²`).
    fn residual_sq(&self, model: &Self::Model, index: usize) -> f64;
    /// Whether a sample is degenerate and should be skipped without fitting.
    fn is_degenerate_sample(&self, _sample: &[usize]) -> bool {
        false
    }
}

/// RANSAC settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RansacConfig {
    /// Inlier threshold `T` on the residual (not squared), in the problem's unit.
    pub threshold: f64,
    /// Probability `p` of drawing at least one all-inlier sample.
    pub confidence: f64,
    /// Iteration cap.
    pub max_iterations: usize,
    /// Iterations always performed (guards against a lucky early estimate).
    pub min_iterations: usize,
    /// Refits per improvement in local optimisation (0 disables LO).
    pub local_optimization_steps: usize,
    /// Sampler seed.
    pub seed: u64,
}

impl Default for RansacConfig {
    fn default() -> Self {
        Self {
            threshold: 1.0,
            confidence: 0.999,
            max_iterations: 1000,
            min_iterations: 10,
            local_optimization_steps: 3,
            seed: 0x5EED,
        }
    }
}

/// Error of a RANSAC run.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum RansacError {
    /// Fewer data points than the minimal sample.
    #[error("need at least {needed} data points, got {got}")]
    TooFewData {
        /// Minimal sample size.
        needed: usize,
        /// Data points given.
        got: usize,
    },
    /// A configuration value is out of range.
    #[error("invalid RANSAC config: threshold {threshold} (> 0), confidence {confidence} ((0, 1))")]
    BadConfig {
        /// Configured threshold.
        threshold: f64,
        /// Configured confidence.
        confidence: f64,
    },
    /// No sample produced a model with at least `sample_size` inliers.
    #[error("no model found")]
    NoModel,
}

/// Best model of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RansacFit<M> {
    /// The model.
    pub model: M,
    /// Inliers (`r² < T²`); their indices are in [`Ransac::inliers`].
    pub num_inliers: usize,
    /// MSAC cost `Σ min(r², T²)`.
    pub cost: f64,
    /// Hypothesis iterations performed.
    pub iterations: usize,
    /// Iterations the adaptive rule asked for at the end.
    pub required_iterations: usize,
}

/// `N = log(1 − p) / log(1 − (1 − e)^s)` (paper eq. 6), saturating at `usize::MAX` and at least 1.
pub fn adaptive_iterations(confidence: f64, outlier_ratio: f64, sample_size: usize) -> usize {
    let inlier_ratio = (1.0 - outlier_ratio).clamp(0.0, 1.0);
    let all_inlier = inlier_ratio.powi(sample_size.min(i32::MAX as usize) as i32);
    if all_inlier >= 1.0 {
        return 1;
    }
    if all_inlier <= f64::MIN_POSITIVE {
        return usize::MAX;
    }
    let n = (1.0 - confidence).ln() / (1.0 - all_inlier).ln();
    if !n.is_finite() || n >= usize::MAX as f64 {
        usize::MAX
    } else {
        (n.ceil() as usize).max(1)
    }
}

/// Reusable RANSAC driver for models of type `M`.
#[derive(Debug, Clone)]
pub struct Ransac<M> {
    config: RansacConfig,
    sample: Vec<usize>,
    models: Vec<M>,
    inliers: Vec<usize>,
    scratch_inliers: Vec<usize>,
}

impl<M: Clone> Ransac<M> {
    /// A driver with buffers for up to `capacity` data points.
    pub fn new(config: RansacConfig, capacity: usize) -> Self {
        Self {
            config,
            sample: Vec::with_capacity(16),
            models: Vec::with_capacity(16),
            inliers: Vec::with_capacity(capacity),
            scratch_inliers: Vec::with_capacity(capacity),
        }
    }

    /// The configuration.
    pub fn config(&self) -> &RansacConfig {
        &self.config
    }

    /// Mutable configuration (e.g. to change the threshold per frame).
    pub fn config_mut(&mut self) -> &mut RansacConfig {
        &mut self.config
    }

    /// Inlier indices of the last successful run, ascending.
    pub fn inliers(&self) -> &[usize] {
        &self.inliers
    }

    /// Runs RANSAC; the sampler is reseeded from the config so equal inputs give equal outputs.
    pub fn run<P: RansacProblem<Model = M>>(
        &mut self,
        problem: &P,
    ) -> Result<RansacFit<M>, RansacError> {
        let cfg = self.config;
        let threshold_ok = cfg.threshold.is_finite() && cfg.threshold > 0.0;
        let confidence_ok = cfg.confidence > 0.0 && cfg.confidence < 1.0;
        if !threshold_ok || !confidence_ok {
            return Err(RansacError::BadConfig {
                threshold: cfg.threshold,
                confidence: cfg.confidence,
            });
        }
        let n = problem.num_data();
        let s = problem.sample_size();
        if n < s || s == 0 {
            return Err(RansacError::TooFewData { needed: s, got: n });
        }
        let t_sq = cfg.threshold * cfg.threshold;
        let mut rng = XorShiftRng::new(cfg.seed);
        self.sample.clear();
        self.sample.resize(s, 0);
        let mut best: Option<(M, f64)> = None;
        let mut required = cfg.max_iterations;
        let mut iterations = 0;
        while iterations < required.max(cfg.min_iterations).min(cfg.max_iterations) {
            iterations += 1;
            if !rng.sample_distinct(n, &mut self.sample)
                || problem.is_degenerate_sample(&self.sample)
            {
                continue;
            }
            self.models.clear();
            problem.fit_minimal(&self.sample, &mut self.models);
            let mut improved = false;
            for k in 0..self.models.len() {
                let bound = best.as_ref().map_or(f64::INFINITY, |b| b.1);
                if let Some(cost) = msac_cost(problem, &self.models[k], t_sq, bound) {
                    best = Some((self.models[k].clone(), cost));
                    improved = true;
                }
            }
            if improved && let Some((model, cost)) = best.take() {
                let (model, cost) = self.local_optimization(problem, model, cost, t_sq);
                let inliers = count_inliers(problem, &model, t_sq);
                let outlier_ratio = 1.0 - inliers as f64 / n as f64;
                required = adaptive_iterations(cfg.confidence, outlier_ratio, s);
                best = Some((model, cost));
            }
        }
        let (model, cost) = best.ok_or(RansacError::NoModel)?;
        self.inliers.clear();
        for i in 0..n {
            if problem.residual_sq(&model, i) < t_sq {
                self.inliers.push(i);
            }
        }
        if self.inliers.len() < s {
            return Err(RansacError::NoModel);
        }
        Ok(RansacFit {
            model,
            num_inliers: self.inliers.len(),
            cost,
            iterations,
            required_iterations: required,
        })
    }

    fn local_optimization<P: RansacProblem<Model = M>>(
        &mut self,
        problem: &P,
        mut model: M,
        mut cost: f64,
        t_sq: f64,
    ) -> (M, f64) {
        for _ in 0..self.config.local_optimization_steps {
            self.scratch_inliers.clear();
            for i in 0..problem.num_data() {
                if problem.residual_sq(&model, i) < t_sq {
                    self.scratch_inliers.push(i);
                }
            }
            self.models.clear();
            problem.fit_refine(&model, &self.scratch_inliers, &mut self.models);
            let mut improved = false;
            for candidate in &self.models {
                if let Some(c) = msac_cost(problem, candidate, t_sq, cost) {
                    model = candidate.clone();
                    cost = c;
                    improved = true;
                }
            }
            if !improved {
                break;
            }
        }
        (model, cost)
    }
}

/// MSAC cost of `model`, or `None` as soon as it reaches `bound` (early exit).
fn msac_cost<P: RansacProblem>(
    problem: &P,
    model: &P::Model,
    t_sq: f64,
    bound: f64,
) -> Option<f64> {
    let mut cost = 0.0;
    for i in 0..problem.num_data() {
        let r = problem.residual_sq(model, i);
        cost += if r < t_sq { r } else { t_sq };
        if cost >= bound {
            return None;
        }
    }
    Some(cost)
}

fn count_inliers<P: RansacProblem>(problem: &P, model: &P::Model, t_sq: f64) -> usize {
    (0..problem.num_data())
        .filter(|&i| problem.residual_sq(model, i) < t_sq)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2-D line `a x + b y + c = 0` through two points.
    struct LineProblem {
        pts: Vec<(f64, f64)>,
    }

    impl RansacProblem for LineProblem {
        type Model = (f64, f64, f64);
        fn num_data(&self) -> usize {
            self.pts.len()
        }
        fn sample_size(&self) -> usize {
            2
        }
        fn fit_minimal(&self, s: &[usize], out: &mut Vec<Self::Model>) {
            let (p, q) = (self.pts[s[0]], self.pts[s[1]]);
            let (a, b) = (q.1 - p.1, p.0 - q.0);
            let norm = a.hypot(b);
            if norm > 0.0 {
                out.push((a / norm, b / norm, -(a * p.0 + b * p.1) / norm));
            }
        }
        fn residual_sq(&self, m: &Self::Model, i: usize) -> f64 {
            let (x, y) = self.pts[i];
            (m.0 * x + m.1 * y + m.2).powi(2)
        }
    }

    #[test]
    fn iteration_formula_matches_paper() {
        // e = 0.5, s = 5, p = 0.99: log(0.01) / log(1 - 1/32) = 145.06 -> 146.
        assert_eq!(adaptive_iterations(0.99, 0.5, 5), 146);
        assert_eq!(adaptive_iterations(0.99, 0.0, 5), 1);
        assert_eq!(adaptive_iterations(0.99, 1.0, 5), usize::MAX);
    }

    #[test]
    fn finds_line_with_half_outliers_deterministically() {
        let mut rng = XorShiftRng::new(3);
        let mut pts = Vec::new();
        for i in 0..100 {
            let x = i as f64 * 0.1;
            if i % 2 == 0 {
                pts.push((x, 0.5 * x + 1.0 + 0.01 * rng.gaussian()));
            } else {
                pts.push((rng.uniform(0.0, 10.0), rng.uniform(-5.0, 10.0)));
            }
        }
        let problem = LineProblem { pts };
        let cfg = RansacConfig {
            threshold: 0.05,
            ..RansacConfig::default()
        };
        let mut ransac = Ransac::new(cfg, 100);
        let fit = ransac.run(&problem).unwrap();
        assert!(fit.num_inliers >= 50 && fit.num_inliers <= 56);
        let slope = -fit.model.0 / fit.model.1;
        assert!((slope - 0.5).abs() < 0.01);
        assert!(fit.iterations < 100);
        let again = ransac.run(&problem).unwrap();
        assert_eq!(fit, again);
        assert!(ransac.inliers().iter().filter(|&&i| i % 2 == 0).count() >= 50);
    }

    #[test]
    fn errors() {
        let problem = LineProblem {
            pts: vec![(0.0, 0.0)],
        };
        let mut ransac = Ransac::new(RansacConfig::default(), 1);
        assert!(matches!(
            ransac.run(&problem),
            Err(RansacError::TooFewData { .. })
        ));
        let same = LineProblem {
            pts: vec![(1.0, 1.0); 5],
        };
        assert_eq!(ransac.run(&same), Err(RansacError::NoModel));
        ransac.config_mut().threshold = -1.0;
        assert!(matches!(
            ransac.run(&same),
            Err(RansacError::BadConfig { .. })
        ));
    }
}
