//! Runs the rover VO evaluation on the default 56 m traverse and prints the report.
//! `cargo run --release -p hopnav-rover-vo --example rover_vo_eval -- [out_dir] [--six-dof]
//! [--tilt-sigma=RAD] [--path=x,y;x,y;...] [--seed=N]`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut options = hopnav_rover_vo::eval::EvalOptions {
        out_dir: args.iter().find(|a| !a.starts_with("--")).map(Into::into),
        ..Default::default()
    };
    options.vo.use_imu_tilt = !args.iter().any(|a| a == "--six-dof");
    if let Some(s) = args.iter().find_map(|a| a.strip_prefix("--tilt-sigma=")) {
        options.vo.imu_tilt_sigma_rad = s.parse()?;
    }
    if let Some(path) = args.iter().find_map(|a| a.strip_prefix("--path=")) {
        options.traverse.waypoints_xy_m = path
            .split(';')
            .map(|p| {
                let v: Vec<f64> = p.split(',').filter_map(|x| x.trim().parse().ok()).collect();
                [
                    v.first().copied().unwrap_or(0.0),
                    v.get(1).copied().unwrap_or(0.0),
                ]
            })
            .collect();
    }
    if let Some(seed) = args.iter().find_map(|a| a.strip_prefix("--seed=")) {
        options.traverse.world.seed = seed.parse()?;
        options.traverse.seed = options.traverse.world.seed;
    }
    let report = hopnav_rover_vo::eval::run(&options)?;
    println!("{report}");
    Ok(())
}
