//! Render benchmark: `cargo run --release --example bench_render [frames] [best-of]`.
//!
//! `best-of` > 1 renders each pose that many times and counts the fastest, which filters out
//! preemption when other processes share the cores.

use hopnav_world::bench::{RenderBenchOptions, render_bench};

fn main() {
    let mut opts = RenderBenchOptions::default();
    let mut args = std::env::args().skip(1);
    if let Some(n) = args.next().and_then(|a| a.parse().ok()) {
        opts.frames = n;
    }
    if let Some(n) = args.next().and_then(|a| a.parse().ok()) {
        opts.repeats_per_pose = n;
    }
    match render_bench(&opts) {
        Ok(report) => println!("{report}"),
        Err(e) => {
            eprintln!("bench failed: {e}");
            std::process::exit(1);
        }
    }
}
