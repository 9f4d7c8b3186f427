//! `hopnav eval vo`'s harder cases: the tumbling launch and hops in a row, each run with the
//! default VO and without its bundle adjustment in the same run.

use crate::compare_quality::{median_and_worst, spread};
use crate::eval_cmd::VoVariant;
use hopnav_eval::jumper_vo::cases::{
    MultiHopOutcome, TUMBLE_RADPS, TumblingOutcome, hops_in_a_row, tumbling_launch,
};

/// The VO variants the cases compare: the default and the fits alone (eq. 4 adds nothing
/// where the flight model is all there is).
const CASE_VARIANTS: [VoVariant; 2] = [VoVariant::Default, VoVariant::FitsOnly];

/// The finite ones of `values` (a run without an estimate gives NaN).
fn finite(values: &[f64]) -> Vec<f64> {
    values.iter().copied().filter(|v| v.is_finite()).collect()
}

/// The spread of the finite `values`, metres, naming how many had no estimate.
fn finite_spread(values: &[f64]) -> String {
    let mut finite = finite(values);
    let lost = values.len() - finite.len();
    let spread = spread(&mut finite, " m");
    if lost > 0 {
        format!("{spread}, {lost} without an estimate")
    } else {
        spread
    }
}

/// Runs the tumbling launch on each seed; prints a row per seed and the spread per setting.
pub fn tumbling(seeds: u64) -> Result<serde_json::Value, String> {
    let mut rows: Vec<(&str, TumblingOutcome)> = Vec::new();
    for seed in 1..=seeds {
        eprint!("\rtumbling launch, seed {seed}/{seeds} …          ");
        for variant in CASE_VARIANTS {
            rows.push((variant.name(), tumbling_launch(seed, &variant.config())?));
        }
    }
    eprintln!();
    println!(
        "tumbling launch (a rock turned it: {:.0}–{:.0} rad/s, heading ±0.3 rad, speed 0.8–1.1×, \
         elevation ±8°; the VO knows only the commanded hop):",
        TUMBLE_RADPS.0, TUMBLE_RADPS.1
    );
    println!(
        "{:<10} {:>5} {:>10} {:>12} {:>8} {:>10}",
        "variant", "seed", "spin r/s", "heading off", "speed", "final m"
    );
    for (name, row) in &rows {
        println!(
            "{:<10} {:>5} {:>10.1} {:>12.3} {:>8.2} {:>10.2}",
            name,
            row.seed,
            row.spin_radps,
            row.heading_error_rad,
            row.speed_ratio,
            row.final_error_m
        );
    }
    let mut summary = serde_json::Map::new();
    for name in CASE_VARIANTS.map(VoVariant::name) {
        let finals: Vec<f64> = rows
            .iter()
            .filter(|(n, _)| *n == name)
            .map(|(_, row)| row.final_error_m)
            .collect();
        println!(
            "{name}: tumbling final error {} (target <= 1 m)",
            finite_spread(&finals)
        );
        summary.insert(
            name.to_owned(),
            serde_json::json!({ "final_error_m": finals }),
        );
    }
    println!();
    Ok(serde_json::Value::Object(summary))
}

/// Runs `hops` hops in a row on each seed; prints the error after each hop (median and worst
/// over the seeds) per setting.
pub fn in_a_row(seeds: u64, hops: usize) -> Result<serde_json::Value, String> {
    let mut runs: Vec<(&str, MultiHopOutcome)> = Vec::new();
    for seed in 1..=seeds {
        eprint!("\r{hops} hops in a row, seed {seed}/{seeds} …          ");
        for variant in CASE_VARIANTS {
            runs.push((
                variant.name(),
                hops_in_a_row(seed, hops, &variant.config())?,
            ));
        }
    }
    eprintln!();
    println!(
        "{hops} Table 1 hops in a row (each VO hop starts where the last one believed it landed): \
         landing error after each hop, median / worst over {seeds} seeds, metres"
    );
    let mut summary = serde_json::Map::new();
    for name in CASE_VARIANTS.map(VoVariant::name) {
        let per_hop: Vec<Vec<f64>> = (0..hops)
            .map(|k| {
                runs.iter()
                    .filter(|(n, _)| *n == name)
                    .filter_map(|(_, run)| run.error_after_hop_m.get(k).copied())
                    .collect()
            })
            .collect();
        let cells: Vec<String> = per_hop
            .iter()
            .map(|errors| {
                median_and_worst(&mut finite(errors)).map_or("-".to_owned(), |(median, worst)| {
                    format!("{median:.2}/{worst:.2}")
                })
            })
            .collect();
        println!("{name:<10} {}", cells.join(" "));
        summary.insert(
            name.to_owned(),
            serde_json::json!({ "error_after_hop_m": per_hop }),
        );
    }
    println!();
    Ok(serde_json::Value::Object(summary))
}
