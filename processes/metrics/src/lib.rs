//! Measurement helpers shared by the evaluation and the benchmarks: trajectory metrics and
//! plots that build with no system library. (Latency summaries are the runtime's:
//! `hopnav_ipc::latency`.)
#![warn(missing_docs)]

pub mod map_plot;
pub mod plot;
pub mod trajectory;
