//! Measurement helpers shared by the supervisor's report and the benchmarks: latency
//! summaries and plots that build with no system library.
#![warn(missing_docs)]

pub mod map_plot;
pub mod plot;
mod summary;
pub mod trajectory;

pub use summary::LatencySummary;
