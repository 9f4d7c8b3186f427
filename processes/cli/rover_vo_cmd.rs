//! `hopnav eval rover-vo` and `hopnav bench rover-vo`: the rover's stereo VO on a rendered
//! traverse of the default terrain, without IPC.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::setup;

#[derive(Debug, Args)]
pub struct RoverVoEvalArgs {
    /// Folder for truth.tum, estimate.tum and trajectory.png (top view, truth vs estimate).
    #[arg(long, default_value = "runs/eval-rover-vo")]
    out: PathBuf,
    /// World, pixel-noise and IMU-noise seed.
    #[arg(long)]
    seed: Option<u64>,
    /// Estimate all six degrees of freedom without the IMU's roll and pitch prior.
    #[arg(long)]
    six_dof: bool,
}

#[derive(Debug, Args)]
pub struct RoverVoBenchArgs {
    /// Passes over the 400-frame traverse.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100))]
    repeats: u64,
}

pub fn eval(args: RoverVoEvalArgs) -> ExitCode {
    let mut options = hopnav_eval::rover_vo::EvalOptions {
        out_dir: Some(args.out.clone()),
        ..Default::default()
    };
    options.vo.use_imu_tilt = !args.six_dof;
    if let Some(seed) = args.seed {
        options.traverse.world.seed = seed;
        options.traverse.seed = seed;
    }
    eprintln!("rendering and tracking the traverse (about a thousand stereo frames)...");
    setup::report_outcome(hopnav_eval::rover_vo::run(&options), |report| {
        println!("{report}");
        println!("files: {}", args.out.display());
    })
}

pub fn bench(args: RoverVoBenchArgs) -> ExitCode {
    let options = hopnav_rover_vo::bench::BenchOptions {
        repeats: args.repeats as usize,
        ..Default::default()
    };
    setup::report_outcome(hopnav_rover_vo::bench::run(&options), |report| {
        println!("{report}")
    })
}
