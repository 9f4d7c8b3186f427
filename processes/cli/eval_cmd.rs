//! `hopnav eval …`: accuracy evaluations against ground truth.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};
use hopnav_eval::jumper_vo::{VoReport, evaluate, plot::write_fig5_png, tum::write_tum};
use hopnav_jumper_vo::config::{JumperVoConfig, ScaleMethod};
use hopnav_jumper_vo::run::{HopRun, run_hop};
use hopnav_jumper_vo::simulate::{SimConfig, SimulatedHop, simulate_hop};

#[derive(Debug, Subcommand)]
pub enum EvalCommand {
    /// Jumper VO on the Table 1 hop (10 m/s at 60°, σ = 1 m altimeter): renders the hop with
    /// the world renderer along the analytic trajectory for each seed, runs the default VO,
    /// the same without its local bundle adjustment, and the paper's eq. (4), and reports ATE
    /// (Sim(3) and SE(3)), RPE and final error; then a tumbling launch (a rock-turned hop
    /// spinning at 10–30 rad/s) and hops in a row (error growth hop by hop). Writes TUM files,
    /// a Fig. 5-style PNG and eval_vo.json.
    Vo(VoArgs),
    /// Rover stereo VO on a rendered ~56 m traverse of the default terrain (IMU roll/pitch
    /// prior): drift in % of distance, ATE (Sim(3), SE(3)), RPE; TUM files and a top-view PNG.
    RoverVo(crate::rover_vo_cmd::RoverVoEvalArgs),
    /// Jumper keyframe clouds on Table 1 hops over seeded rocky worlds: each point's viewing
    /// ray is cast from the true camera to find the surface it came from; prints the height
    /// noise on bare ground (and whether the clouds' sigmas are honest) and, per true rock
    /// height, how many rock points the mapper's rule calls high. Writes
    /// eval_jumper_clouds.json.
    JumperClouds(crate::jumper_clouds_cmd::JumperCloudsArgs),
    /// Rover-only missions at k = 0.07, 0.10, 0.13, 0.16: over the ground the rover's camera
    /// had in sight within 5 m (the true world rendered from its true poses, so ground hidden
    /// behind a rock is left out), the final map's ground lethal for the rover's centre against
    /// the rocks' (blocked-area ratio), truly lethal cells mapped traversable (missed) or
    /// uncertain (maybe too tall, at a cost), the open share (both) and false lethal cells,
    /// median and worst per k; the missed share over the field of view (hidden ground too) and
    /// in the map's frame beside them; the missed cells by cause; a map PNG per k with the
    /// map's classes and the true unclimbable rocks' outlines.
    Traversability(crate::eval_traversability_cmd::TraversabilityArgs),
}

#[derive(Debug, Args)]
pub struct VoArgs {
    /// Seeds to run (world, altimeter noise and pixel noise differ per seed).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=1000))]
    seeds: u64,
    /// Folder for TUM files, the PNGs and eval_vo.json.
    #[arg(long, default_value = "runs/eval-vo")]
    out: PathBuf,
    /// Hops of the hops-in-a-row case (each starts where the VO believed the last one
    /// landed); 0 skips it.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(0..=100))]
    hops: u64,
    /// Skip the tumbling-launch case.
    #[arg(long)]
    no_tumbling: bool,
    /// Evaluate a recorded launch instead (a folder written by `hopnav launch
    /// --export-dataset DIR`): the live jumper_vo estimate against the physics ground truth.
    #[arg(long, value_name = "DIR")]
    dataset: Option<PathBuf>,
}

pub fn run(command: EvalCommand) -> ExitCode {
    match command {
        EvalCommand::RoverVo(args) => crate::rover_vo_cmd::eval(args),
        EvalCommand::JumperClouds(args) => crate::jumper_clouds_cmd::run(args),
        EvalCommand::Traversability(args) => crate::eval_traversability_cmd::run(args),
        EvalCommand::Vo(args) => match match &args.dataset {
            Some(dataset) => vo_dataset(dataset, &args.out),
            None => vo(&args),
        } {
            Ok(()) => ExitCode::SUCCESS,
            Err(error) => {
                eprintln!("\nerror: {error}");
                ExitCode::FAILURE
            }
        },
    }
}

fn hop_for_seed(seed: u64) -> Result<SimulatedHop, String> {
    let mut config = SimConfig {
        seed,
        ..SimConfig::default()
    };
    config.world.seed = seed;
    simulate_hop(&config).map_err(|error| format!("simulating seed {seed}: {error}"))
}

fn write_outputs(
    out: &std::path::Path,
    variant: VoVariant,
    hop: &SimulatedHop,
    run: &HopRun,
) -> Result<(), String> {
    let name = out.join(variant.name());
    let estimate: Vec<_> = hop.t_s.iter().copied().zip(run.poses()).collect();
    let truth: Vec<_> = hop
        .t_s
        .iter()
        .copied()
        .zip(hop.truth_world_from_body.iter().copied())
        .collect();
    let path = |suffix: &str| PathBuf::from(format!("{}{suffix}", name.display()));
    write_tum(&path("_estimate.tum"), &estimate).map_err(|e| e.to_string())?;
    write_tum(&path("_truth.tum"), &truth).map_err(|e| e.to_string())?;
    write_fig5_png(
        &path("_fig5.png"),
        &hop.t_s,
        &hop.truth_world_from_body,
        &run.poses(),
    )
    .map_err(|e| e.to_string())
}

/// The VO variants `eval vo` compares in one run: the default, the same without its local
/// bundle adjustment, and the paper's eq. (4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VoVariant {
    /// The default: ballistic scale with the local bundle adjustment.
    Default,
    /// Ballistic scale, the fits alone (`bundle_adjustment = false`).
    FitsOnly,
    /// The paper's eq. (4) scale (no adjustment).
    PaperEq4,
}

const VO_VARIANTS: [VoVariant; 3] = [VoVariant::Default, VoVariant::FitsOnly, VoVariant::PaperEq4];

impl VoVariant {
    pub fn name(self) -> &'static str {
        match self {
            Self::Default => "default",
            Self::FitsOnly => "fits-only",
            Self::PaperEq4 => "papereq4",
        }
    }

    pub fn config(self) -> JumperVoConfig {
        let base = JumperVoConfig::default();
        match self {
            Self::Default => base,
            Self::FitsOnly => JumperVoConfig {
                bundle_adjustment: false,
                ..base
            },
            Self::PaperEq4 => JumperVoConfig {
                scale_method: ScaleMethod::PaperEq4,
                bundle_adjustment: false,
                ..base
            },
        }
    }

    /// What the summary line says after the figures.
    fn verdict(self, worst_ate_m: f64) -> &'static str {
        match self {
            Self::Default if worst_ate_m <= 0.25 => "  (target <= 0.25 m: met)",
            Self::Default => "  (target <= 0.25 m: NOT met)",
            Self::FitsOnly => "  (the default without its bundle adjustment)",
            Self::PaperEq4 => "  (the paper's eq. 4 baseline)",
        }
    }
}

/// One VO run's report: its variant and seed.
type SeedReport = (VoVariant, u64, VoReport);

fn vo(args: &VoArgs) -> Result<(), String> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let reports = run_vo_seeds(args)?;
    print_seed_table(&reports);
    let mut summary = serde_json::Map::new();
    for variant in VO_VARIANTS {
        summary.insert(
            variant.name().to_string(),
            method_summary(variant, &reports),
        );
    }
    println!();
    if !args.no_tumbling {
        summary.insert(
            "tumbling".to_owned(),
            crate::eval_vo_cases_cmd::tumbling(args.seeds)?,
        );
    }
    if args.hops > 0 {
        summary.insert(
            "hops_in_a_row".to_owned(),
            crate::eval_vo_cases_cmd::in_a_row(args.seeds, args.hops as usize)?,
        );
    }
    let json_path = args.out.join("eval_vo.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )
    .map_err(|e| format!("{}: {e}", json_path.display()))?;
    println!(
        "wrote {}/{{default,fits-only,papereq4}}_{{estimate,truth}}.tum, *_fig5.png and eval_vo.json",
        args.out.display()
    );
    Ok(())
}

/// Renders each seed's hop and runs the VO on it with every scale method; the first seed's
/// runs also write their TUM files and figures.
fn run_vo_seeds(args: &VoArgs) -> Result<Vec<SeedReport>, String> {
    let mut reports = Vec::new();
    for seed in 1..=args.seeds {
        eprint!(
            "\rseed {seed}/{}: rendering the hop …            ",
            args.seeds
        );
        let hop = hop_for_seed(seed)?;
        for variant in VO_VARIANTS {
            eprint!(
                "\rseed {seed}/{}: VO {} …               ",
                args.seeds,
                variant.name()
            );
            let config = variant.config();
            let run = run_hop(&hop, &config).map_err(|e| e.to_string())?;
            let report = evaluate(&run.outputs, &hop.truth_world_from_body)
                .ok_or_else(|| format!("seed {seed}: too few frames to evaluate"))?;
            if seed == 1 {
                write_outputs(&args.out, variant, &hop, &run)?;
            }
            reports.push((variant, seed, report));
        }
    }
    eprintln!();
    Ok(reports)
}

/// One row per run.
fn print_seed_table(reports: &[SeedReport]) {
    println!(
        "\n{:<10} {:>5} {:>12} {:>12} {:>12} {:>11} {:>10} {:>9} {:>10}",
        "variant",
        "seed",
        "ATE Sim3 m",
        "ATE SE3 m",
        "unaligned m",
        "RPE m/frm",
        "final m",
        "max rot°",
        "in 2σ %"
    );
    for (variant, seed, report) in reports {
        println!(
            "{:<10} {:>5} {:>12.3} {:>12.3} {:>12.3} {:>11.3} {:>10.3} {:>9.2} {:>10.0}",
            variant.name(),
            seed,
            report.ate_sim3_m,
            report.ate_se3_m,
            report.rmse_unaligned_m,
            report.rpe_frame_m,
            report.final_error_m,
            report.max_rotation_error_rad.to_degrees(),
            report.within_two_sigma_percent
        );
    }
    println!();
}

/// Prints `variant`'s mean and worst ATE over the seeds (against the target for the default)
/// and returns them for eval_vo.json.
fn method_summary(variant: VoVariant, reports: &[SeedReport]) -> serde_json::Value {
    let of_method: Vec<&VoReport> = reports
        .iter()
        .filter(|(m, _, _)| *m == variant)
        .map(|(_, _, report)| report)
        .collect();
    let mean = |f: fn(&VoReport) -> f64| {
        of_method.iter().map(|r| f(r)).sum::<f64>() / of_method.len() as f64
    };
    let worst = |f: fn(&VoReport) -> f64| of_method.iter().map(|r| f(r)).fold(0.0, f64::max);
    println!(
        "{}: ATE Sim(3) mean {:.3} m, worst {:.3} m; SE(3) mean {:.3} m, worst {:.3} m; frames within 2 σ {:.0} %{}",
        variant.name(),
        mean(|r| r.ate_sim3_m),
        worst(|r| r.ate_sim3_m),
        mean(|r| r.ate_se3_m),
        worst(|r| r.ate_se3_m),
        mean(|r| r.within_two_sigma_percent),
        variant.verdict(worst(|r| r.ate_sim3_m))
    );
    serde_json::json!({
        "ate_sim3_mean_m": mean(|r| r.ate_sim3_m),
        "ate_sim3_worst_m": worst(|r| r.ate_sim3_m),
        "ate_se3_mean_m": mean(|r| r.ate_se3_m),
        "ate_se3_worst_m": worst(|r| r.ate_se3_m),
        "rpe_frame_mean_m": mean(|r| r.rpe_frame_m),
        "final_error_mean_m": mean(|r| r.final_error_m),
        "within_two_sigma_mean_percent": mean(|r| r.within_two_sigma_percent),
        "seeds": of_method.len(),
    })
}

/// Evaluates the live `jumper_vo` estimate of a recorded launch against its ground truth.
fn vo_dataset(dataset: &std::path::Path, out: &std::path::Path) -> Result<(), String> {
    let report = hopnav_eval::jumper_vo::dataset::evaluate_dataset(dataset)
        .map_err(|e| format!("{}: {e}", dataset.display()))?;
    let (sim3, se3) = (&report.ate_sim3, &report.ate_se3);
    let (times, est, gt) = (&report.times_s, &report.estimate, &report.truth);
    println!(
        "jumper_vo on {} ({} frames):",
        dataset.display(),
        report.frames()
    );
    println!(
        "  ATE Sim(3) {:.3} m (max {:.3} m)",
        sim3.rmse_m, sim3.max_m
    );
    println!("  ATE SE(3)  {:.3} m (max {:.3} m)", se3.rmse_m, se3.max_m);
    println!("  unaligned RMSE {:.3} m", report.unaligned_rmse_m);
    if let Some(final_m) = report.final_error_m {
        println!("  final position error {final_m:.3} m");
    }
    if let Some(relative) = &report.rpe_frame {
        println!(
            "  RPE per frame {:.3} m, {:.2} deg",
            relative.translation_rmse_m,
            relative.rotation_rmse_rad.to_degrees()
        );
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let png = out.join("dataset_fig5.png");
    write_fig5_png(&png, times, gt, est).map_err(|e| e.to_string())?;
    println!("wrote {}", png.display());
    Ok(())
}
