//! Own-harness benchmarks for the planner targets (no criterion).
//!
//! [`run_dynamic_benchmark`] generates seeded 257² rocky maps (clustered obstacles), runs the
//! unknown-terrain traverse of [`crate::dynamic`] with D* Lite and both repeated-A* policies,
//! and reports total expansions, their ratio, and replan time p50 / p99 / max. Run it in
//! release: `cargo run --release --example dynamic_bench`.

use std::fmt;
use std::time::Duration;

use crate::cost::Cost;
use crate::dijkstra::dijkstra_cost;
use crate::dynamic::{
    Algorithm, COMPARED_ALGORITHMS, DynamicConfig, DynamicError, TraverseResult, compare,
};
use crate::grid::Cell;
use crate::random_map::{RandomMapConfig, clustered_obstacles, inflate_obstacles};
use crate::rng::SplitMix64;

/// Benchmark parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicBenchConfig {
    /// Random map shape and obstacle density.
    pub map: RandomMapConfig,
    /// Number of maps (one traverse each).
    pub maps: usize,
    /// Sensing radius in cells.
    pub sensor_radius_cells: u32,
    /// Extra cost of free cells next to obstacles (0 for none).
    pub inflation_cost: u32,
    /// Seed of the first map.
    pub seed: u64,
    /// How often each traverse is repeated for timing; each replan's time is the minimum
    /// over the repeats (the traverse is deterministic), which filters out preemption by
    /// other processes. Expansions are identical across repeats.
    pub timing_repeats: usize,
}

impl Default for DynamicBenchConfig {
    fn default() -> Self {
        Self {
            map: RandomMapConfig::default(),
            maps: 20,
            sensor_radius_cells: 5,
            inflation_cost: 0,
            seed: 1,
            timing_repeats: 3,
        }
    }
}

/// Median, 99th percentile and maximum of a set of durations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Percentiles {
    /// Number of samples.
    pub count: usize,
    /// Median.
    pub p50: Duration,
    /// 99th percentile (nearest rank).
    pub p99: Duration,
    /// Maximum.
    pub max: Duration,
}

impl Percentiles {
    /// Percentiles of `samples` (sorted in place). All zero when empty.
    pub fn of(samples: &mut [Duration]) -> Self {
        if samples.is_empty() {
            return Self::default();
        }
        samples.sort_unstable();
        let rank = |fraction: f64| {
            let position = (fraction * samples.len() as f64).ceil() as usize;
            samples[position.clamp(1, samples.len()) - 1]
        };
        Self {
            count: samples.len(),
            p50: rank(0.50),
            p99: rank(0.99),
            max: samples[samples.len() - 1],
        }
    }
}

/// Totals of one planner over all benchmark maps.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlannerSummary {
    /// Planner name.
    pub name: String,
    /// Traverses run.
    pub runs: usize,
    /// Traverses that reached the goal.
    pub successes: usize,
    /// Expansions over all traverses.
    pub expansions: u64,
    /// Replans over all traverses.
    pub replans: u64,
    /// Executed path cost over all traverses.
    pub executed_cost: Cost,
    /// Total planning time (initial + replans).
    pub plan_time: Duration,
    /// Initial search times.
    pub initial: Percentiles,
    /// Replan times.
    pub replan: Percentiles,
    initial_samples: Vec<Duration>,
    replan_samples: Vec<Duration>,
}

impl PlannerSummary {
    fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            ..Self::default()
        }
    }

    fn add(&mut self, run: &TraverseResult) {
        self.runs += 1;
        self.successes += usize::from(run.reached_goal);
        self.expansions += run.expansions;
        self.replans += run.replans;
        self.executed_cost += run.executed_cost;
        self.plan_time += run.total_plan_time();
        self.initial_samples.push(run.initial_plan_time);
        self.replan_samples.extend_from_slice(&run.replan_times);
    }

    fn finish(&mut self) {
        self.initial = Percentiles::of(&mut self.initial_samples);
        self.replan = Percentiles::of(&mut self.replan_samples);
    }
}

/// Result of [`run_dynamic_benchmark`].
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicBenchReport {
    /// Parameters used.
    pub config: DynamicBenchConfig,
    /// Mean obstacle fraction of the generated maps.
    pub mean_obstacle_fraction: f64,
    /// Totals per planner, in the order of [`COMPARED_ALGORITHMS`].
    pub summaries: Vec<(Algorithm, PlannerSummary)>,
}

impl DynamicBenchReport {
    /// The totals of `algorithm`.
    pub fn summary(&self, algorithm: Algorithm) -> Option<&PlannerSummary> {
        self.summaries
            .iter()
            .find(|(candidate, _)| *candidate == algorithm)
            .map(|(_, summary)| summary)
    }

    /// `planner` total expansions / `baseline` total expansions (NaN if either is missing).
    pub fn expansion_ratio(&self, planner: Algorithm, baseline: Algorithm) -> f64 {
        match (self.summary(planner), self.summary(baseline)) {
            (Some(planner), Some(baseline)) => ratio(planner.expansions, baseline.expansions),
            _ => f64::NAN,
        }
    }
}

fn ratio(numerator: u64, denominator: u64) -> f64 {
    if denominator == 0 {
        return f64::NAN;
    }
    numerator as f64 / denominator as f64
}

impl fmt::Display for DynamicBenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let config = &self.config;
        writeln!(
            f,
            "dynamic reveal: {} maps {}x{}, obstacles {:.1} % (clustered, r<={}), sensor radius {} cells, inflation {}, seed {}, times = min of {} repeats",
            config.maps,
            config.map.width,
            config.map.height,
            100.0 * self.mean_obstacle_fraction,
            config.map.max_cluster_radius,
            config.sensor_radius_cells,
            config.inflation_cost,
            config.seed,
            config.timing_repeats,
        )?;
        writeln!(
            f,
            "{:<34} {:>7} {:>12} {:>8} {:>12} {:>10} {:>10} {:>10} {:>10} {:>11}",
            "planner",
            "success",
            "expansions",
            "replans",
            "path cost",
            "init µs",
            "p50 µs",
            "p99 µs",
            "max µs",
            "total ms"
        )?;
        for (_, summary) in &self.summaries {
            writeln!(
                f,
                "{:<34} {:>3}/{:<3} {:>12} {:>8} {:>12} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>11.2}",
                summary.name,
                summary.successes,
                summary.runs,
                summary.expansions,
                summary.replans,
                summary.executed_cost,
                micros(summary.initial.p50),
                micros(summary.replan.p50),
                micros(summary.replan.p99),
                micros(summary.replan.max),
                summary.plan_time.as_secs_f64() * 1e3,
            )?;
        }
        let is_dstar = |algorithm: &Algorithm| matches!(algorithm, Algorithm::DStarLite { .. });
        for (planner, summary) in self.summaries.iter().filter(|(a, _)| is_dstar(a)) {
            for (baseline, _) in self.summaries.iter().filter(|(a, _)| !is_dstar(a)) {
                writeln!(
                    f,
                    "expansion ratio {planner} / {baseline} = {:.3}   (target <= 0.2)",
                    self.expansion_ratio(*planner, *baseline)
                )?;
            }
            writeln!(
                f,
                "{planner} replan p50 {:.1} µs, p99 {:.1} µs, max {:.1} µs over {} replans   (target <= 1000 µs)",
                micros(summary.replan.p50),
                micros(summary.replan.p99),
                micros(summary.replan.max),
                summary.replan.count
            )?;
        }
        Ok(())
    }
}

fn micros(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1e6
}

/// Runs the unknown-terrain traverse benchmark. Maps whose goal is unreachable on the true
/// map are skipped (regenerated with the next seed).
pub fn run_dynamic_benchmark(
    config: &DynamicBenchConfig,
) -> Result<DynamicBenchReport, DynamicError> {
    let mut summaries: Vec<(Algorithm, PlannerSummary)> = COMPARED_ALGORITHMS
        .iter()
        .map(|&algorithm| (algorithm, PlannerSummary::new(&algorithm.to_string())))
        .collect();
    let mut fraction_sum = 0.0;
    let dynamic = DynamicConfig {
        sensor_radius_cells: config.sensor_radius_cells,
        max_steps: None,
    };
    let mut seed = config.seed;
    let mut done = 0;
    while done < config.maps {
        let (start, goal) = endpoints(config, done);
        let mut rng = SplitMix64::new(seed);
        seed = seed.wrapping_add(1);
        let mut truth = clustered_obstacles(&config.map, &[start, goal], &mut rng)?;
        if config.inflation_cost > 0 {
            inflate_obstacles(&mut truth, config.inflation_cost)?;
        }
        if dijkstra_cost(&truth, start, goal).is_none() {
            continue;
        }
        fraction_sum += truth.obstacle_fraction();
        let mut comparison = compare(&truth, start, goal, &dynamic)?;
        for _ in 1..config.timing_repeats {
            let repeat = compare(&truth, start, goal, &dynamic)?;
            keep_fastest_times(&mut comparison.runs, &repeat.runs);
        }
        for (algorithm, summary) in &mut summaries {
            if let Some(run) = comparison.run(*algorithm) {
                summary.add(run);
            }
        }
        done += 1;
    }
    for (_, summary) in &mut summaries {
        summary.finish();
    }
    Ok(DynamicBenchReport {
        config: *config,
        mean_obstacle_fraction: fraction_sum / config.maps.max(1) as f64,
        summaries,
    })
}

/// Keeps, per replan, the smaller of the two measured times of identical traverses.
fn keep_fastest_times(best: &mut [TraverseResult], repeat: &[TraverseResult]) {
    for (best, repeat) in best.iter_mut().zip(repeat) {
        if best.replan_times.len() != repeat.replan_times.len() {
            continue;
        }
        best.initial_plan_time = best.initial_plan_time.min(repeat.initial_plan_time);
        for (time, other) in best.replan_times.iter_mut().zip(&repeat.replan_times) {
            *time = (*time).min(*other);
        }
    }
}

/// Corner-to-corner traverses, alternating between the two diagonals.
fn endpoints(config: &DynamicBenchConfig, run: usize) -> (Cell, Cell) {
    let margin = 3.min(config.map.width / 4).min(config.map.height / 4);
    let right = config.map.width.saturating_sub(1 + margin);
    let bottom = config.map.height.saturating_sub(1 + margin);
    if run.is_multiple_of(2) {
        (Cell::new(margin, margin), Cell::new(right, bottom))
    } else {
        (Cell::new(margin, bottom), Cell::new(right, margin))
    }
}
