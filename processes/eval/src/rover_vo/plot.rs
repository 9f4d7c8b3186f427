//! Top view (x–y) of the truth and estimated trajectories, drawn with `hopnav_metrics::plot`.

use hopnav_metrics::plot::{LinePlot, Scale, Series, write_png};
use nalgebra::Isometry3;
use std::path::Path;

pub use hopnav_metrics::plot::PlotError;

/// Writes the top-view PNG.
pub fn write_top_view_png(
    path: &Path,
    truth: &[Isometry3<f64>],
    estimate: &[Isometry3<f64>],
) -> Result<(), PlotError> {
    let xy = |label: &str, poses: &[Isometry3<f64>]| Series {
        label: label.to_owned(),
        points: poses
            .iter()
            .map(|p| (p.translation.x, p.translation.y))
            .collect(),
    };
    let series = [xy("truth", truth), xy("estimate", estimate)];
    write_png(
        path,
        &LinePlot {
            title: "rover VO, top view",
            x_label: "x [m]",
            y_label: "y [m]",
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: &series,
        },
    )
}
