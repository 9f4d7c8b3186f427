//! Unknown-terrain traverse benchmark: D* Lite vs repeated A* on random rocky 257² maps.
//!
//! `cargo run --release --example dynamic_bench -- [--maps N] [--radius R] [--density F]
//!  [--size S] [--inflation C] [--seed K] [--repeats T] [--cluster R]`

use hopnav_planner::bench::{DynamicBenchConfig, run_dynamic_benchmark};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut config = DynamicBenchConfig::default();
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().ok_or(format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--maps" => config.maps = value.parse()?,
            "--radius" => config.sensor_radius_cells = value.parse()?,
            "--density" => config.map.obstacle_fraction = value.parse()?,
            "--size" => {
                config.map.width = value.parse()?;
                config.map.height = config.map.width;
            }
            "--inflation" => config.inflation_cost = value.parse()?,
            "--seed" => config.seed = value.parse()?,
            "--repeats" => config.timing_repeats = value.parse()?,
            "--cluster" => config.map.max_cluster_radius = value.parse()?,
            other => return Err(format!("unknown flag {other}").into()),
        }
    }
    let report = run_dynamic_benchmark(&config)?;
    println!("{report}");
    Ok(())
}
