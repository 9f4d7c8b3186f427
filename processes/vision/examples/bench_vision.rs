//! Per-frame vision benchmark: `cargo run --release --example bench_vision [iterations]`.

use hopnav_vision::bench::{BenchConfig, run_frame_benchmark};

fn main() {
    let iterations = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let config = BenchConfig {
        iterations,
        ..BenchConfig::default()
    };
    match run_frame_benchmark(&config) {
        Ok(report) => print!("{report}"),
        Err(e) => {
            eprintln!("benchmark failed: {e}");
            std::process::exit(1);
        }
    }
}
