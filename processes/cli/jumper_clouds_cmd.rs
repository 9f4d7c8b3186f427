//! `hopnav eval jumper-clouds`: the jumper's keyframe-cloud heights against the rendered world.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use hopnav_eval::jumper_vo::cloud_heights::{CloudHeightStats, HEIGHT_CLASS_EDGES_M, HighRule};
use hopnav_jumper_vo::config::JumperVoConfig;
use hopnav_jumper_vo::run::run_hop;
use hopnav_jumper_vo::simulate::{SimConfig, simulate_hop};
use hopnav_mapper::config::MapperConfig;
use hopnav_world::World;

#[derive(Debug, Args)]
pub struct JumperCloudsArgs {
    /// Hops to run, one seeded world each (more hops: more points on the rare tall rocks).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=1000))]
    seeds: u64,
    /// Golombek rock abundance k of the worlds (0.07 moderate, 0.16 rocky).
    #[arg(long, default_value_t = 0.12, value_parser = parse_k)]
    k: f64,
    /// Median parallax at which the VO takes a new keyframe, degrees (default: the VO's):
    /// the clouds are triangulated between keyframes, so this sets their baseline.
    #[arg(long, value_name = "DEG")]
    keyframe_max_parallax_deg: Option<f64>,
    /// Keyframe intervals a cloud may triangulate a track over, from the keyframe it was born
    /// in (default: the VO's `cloud_track_keyframes`; 1: the last interval only).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=32))]
    cloud_track_keyframes: Option<u32>,
    /// Height sigmas of margin a point needs above the traversable height to be called high
    /// (default: the mapper's `jumper_height_sigma_factor`, 2).
    #[arg(long, value_name = "SIGMAS", value_parser = parse_sigma_factor)]
    jumper_height_sigma_factor: Option<f64>,
    /// Folder for eval_jumper_clouds.json.
    #[arg(long, default_value = "runs/eval-jumper-clouds")]
    out: PathBuf,
}

fn parse_k(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(k) if (0.0..=0.5).contains(&k) => Ok(k),
        Ok(k) => Err(format!("{k} is out of range: allowed [0, 0.5]")),
        Err(error) => Err(error.to_string()),
    }
}

fn parse_sigma_factor(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(factor) if (0.0..=10.0).contains(&factor) => Ok(factor),
        Ok(factor) => Err(format!("{factor} is out of range: allowed [0, 10]")),
        Err(error) => Err(error.to_string()),
    }
}

pub fn run(args: JumperCloudsArgs) -> ExitCode {
    match evaluate(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("\nerror: {error}");
            ExitCode::FAILURE
        }
    }
}

fn evaluate(args: &JumperCloudsArgs) -> Result<(), String> {
    let mut vo_config = JumperVoConfig::default();
    if let Some(deg) = args.keyframe_max_parallax_deg {
        vo_config.keyframe_max_parallax_deg = deg;
    }
    if let Some(intervals) = args.cloud_track_keyframes {
        vo_config.cloud_track_keyframes = intervals;
    }
    let mut rule = mapper_rule(&MapperConfig::default());
    if let Some(factor) = args.jumper_height_sigma_factor {
        rule.sigma_factor = factor;
    }
    let mut stats = CloudHeightStats::default();
    for seed in 1..=args.seeds {
        eprint!("\rhop {seed}/{}: rendering and tracking …   ", args.seeds);
        let mut sim = SimConfig {
            seed,
            ..SimConfig::default()
        };
        sim.world.seed = seed;
        sim.world.rocks.golombek_k = args.k;
        let hop = simulate_hop(&sim).map_err(|e| format!("simulating seed {seed}: {e}"))?;
        let world = World::generate(&sim.world).map_err(|e| format!("world {seed}: {e}"))?;
        let run = run_hop(&hop, &vo_config).map_err(|e| format!("VO on seed {seed}: {e}"))?;
        stats.add_hop(&world, &hop, &run, &rule);
    }
    eprintln!();
    print(args, &vo_config, &rule, &stats);
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let json_path = args.out.join("eval_jumper_clouds.json");
    let json = serde_json::json!({
        "seeds": args.seeds,
        "golombek_k": args.k,
        "keyframe_max_parallax_deg": vo_config.keyframe_max_parallax_deg,
        "cloud_track_keyframes": vo_config.cloud_track_keyframes,
        "jumper_height_sigma_factor": rule.sigma_factor,
        "ground_rms_m": stats.ground_rms_m(),
        "ground_z_rms": stats.ground_z_rms(),
        "stats": stats,
    });
    let text =
        serde_json::to_string_pretty(&json).map_err(|e| format!("{}: {e}", json_path.display()))?;
    std::fs::write(&json_path, text).map_err(|e| format!("{}: {e}", json_path.display()))?;
    println!("wrote {}", json_path.display());
    Ok(())
}

/// The mapper's test for a jumper point, from its configuration.
fn mapper_rule(mapper: &MapperConfig) -> HighRule {
    HighRule {
        max_depth_sigma_m: mapper.max_depth_sigma_m,
        max_feature_height_m: mapper.max_feature_height_m,
        traversable_height_m: mapper.traversable_height_m,
        sigma_factor: mapper.jumper_height_sigma_factor,
    }
}

fn print(args: &JumperCloudsArgs, vo: &JumperVoConfig, rule: &HighRule, stats: &CloudHeightStats) {
    let percent = |part: usize, whole: usize| 100.0 * part as f64 / whole.max(1) as f64;
    println!(
        "\n{} hops, k {:.3}, keyframes every {:.1}° of parallax, tracks triangulated over up to {} keyframe intervals: {} clouds, {} points ({} rays met no surface)",
        args.seeds,
        args.k,
        vo.keyframe_max_parallax_deg,
        vo.cloud_track_keyframes,
        stats.clouds,
        stats.points,
        stats.unmatched
    );
    println!(
        "called high: above {:.2} m + {:.1} height sigmas (the mapper's rule for the jumper)",
        rule.traversable_height_m, rule.sigma_factor
    );
    let fmt = |value: Option<f64>| value.map_or("-".to_owned(), |v| format!("{v:.3}"));
    println!(
        "bare ground: {} points, height RMS {} m, RMS in own sigmas {} (1 = honest), called high {} ({:.1} %)",
        stats.ground_points,
        fmt(stats.ground_rms_m()),
        fmt(stats.ground_z_rms()),
        stats.ground_called_high,
        percent(stats.ground_called_high, stats.ground_points)
    );
    println!(
        "\n{:<16} {:>7} {:>12} {:>14} {:>11}",
        "rock surface", "points", "called high", "mean read m", "mean true m"
    );
    for (index, class) in stats.rock_classes.iter().enumerate() {
        let low = index
            .checked_sub(1)
            .and_then(|i| HEIGHT_CLASS_EDGES_M.get(i))
            .copied()
            .unwrap_or(0.0);
        let label = match HEIGHT_CLASS_EDGES_M.get(index) {
            Some(high) => format!("{low:.2}–{high:.2} m"),
            None => format!("≥ {low:.2} m"),
        };
        let mean =
            |sum: f64| (class.points > 0).then(|| format!("{:.3}", sum / class.points as f64));
        println!(
            "{:<16} {:>7} {:>6} ({:>4.1}%) {:>14} {:>11}",
            label,
            class.points,
            class.called_high,
            percent(class.called_high, class.points),
            mean(class.estimated_sum_m).unwrap_or_else(|| "-".to_owned()),
            mean(class.true_sum_m).unwrap_or_else(|| "-".to_owned())
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_evals_default_rule_is_the_mappers_default() {
        assert_eq!(HighRule::default(), mapper_rule(&MapperConfig::default()));
    }
}
