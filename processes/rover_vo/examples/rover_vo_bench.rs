//! Own-harness benchmark of the rover VO per stereo frame (320×240).
//! `cargo run --release -p hopnav-rover-vo --example rover_vo_bench`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let report = hopnav_rover_vo::bench::run(&hopnav_rover_vo::bench::BenchOptions::default())?;
    println!("{report}");
    Ok(())
}
