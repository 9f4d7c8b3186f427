//! Runs the rover VO evaluation on the default 56 m traverse and prints the report.
//! `cargo run --release -p hopnav-rover-vo --example rover_vo_eval -- [out_dir]`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let options = hopnav_rover_vo::eval::EvalOptions {
        out_dir: std::env::args().nth(1).map(Into::into),
        ..Default::default()
    };
    let report = hopnav_rover_vo::eval::run(&options)?;
    println!("{report}");
    Ok(())
}
