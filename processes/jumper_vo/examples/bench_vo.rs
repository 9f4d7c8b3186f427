//! Per-frame cost of the jumper VO on the default rendered hop (320², ≤ 1000 features).
//! `cargo run --release --example bench_vo -- [repeats]`.
use hopnav_jumper_vo::bench::bench_hop;
use hopnav_jumper_vo::config::JumperVoConfig;
use hopnav_jumper_vo::simulate::{SimConfig, simulate_hop};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let repeats = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let hop = simulate_hop(&SimConfig::default())?;
    let cost = bench_hop(&hop, &JumperVoConfig::default(), repeats)?;
    println!("{cost}");
    Ok(())
}
