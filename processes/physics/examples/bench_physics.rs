//! Physics step-time benchmark on the default world.
//!
//! `cargo run --release --example bench_physics [frames]`

use hopnav_physics::bench::{PhysicsBenchConfig, run_physics_bench};

fn main() {
    let mut cfg = PhysicsBenchConfig::default();
    if let Some(frames) = std::env::args().nth(1).and_then(|a| a.parse().ok()) {
        cfg.frames = frames;
    }
    match run_physics_bench(&cfg) {
        Ok(report) => println!("{report}"),
        Err(e) => {
            eprintln!("bench failed: {e}");
            std::process::exit(1);
        }
    }
}
