//! Runs the rover VO evaluation on the default 56 m traverse and prints the report.
//! `cargo run --release -p hopnav-rover-vo --example rover_vo_eval -- [out_dir] [--six-dof]`
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
    let report = hopnav_rover_vo::eval::run(&options)?;
    println!("{report}");
    Ok(())
}
