//! A PNG like the paper's Fig. 5: x, y, z and pitch against time (truth vs estimate) and the
//! roll/yaw errors, one panel each, drawn with `hopnav_metrics::plot::draw`.

use hopnav_jumper_vo::frames::euler_from_rotation;
use hopnav_metrics::plot::{LinePlot, Scale, Series, draw};
use nalgebra::Isometry3;
use plotters::prelude::*;
use std::path::Path;

/// Error writing the figure.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {message}")]
pub struct PlotError {
    /// Output file.
    pub path: String,
    /// What failed.
    pub message: String,
}

/// Writes the five-panel figure to `path` (PNG, 1500×900).
pub fn write_fig5_png(
    path: &Path,
    t_s: &[f64],
    truth: &[Isometry3<f64>],
    estimate: &[Isometry3<f64>],
) -> Result<(), PlotError> {
    let error = |message: String| PlotError {
        path: path.display().to_string(),
        message,
    };
    let n = t_s.len().min(truth.len()).min(estimate.len());
    let series = |label: &str, f: &dyn Fn(usize) -> f64| Series {
        label: label.to_owned(),
        points: (0..n).map(|i| (t_s[i], f(i))).collect(),
    };
    let pos = |p: &[Isometry3<f64>], i: usize, axis: usize| p[i].translation.vector[axis];
    let euler = |p: &[Isometry3<f64>], i: usize| euler_from_rotation(&p[i].rotation);
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
    };
    let panels: Vec<(&str, &str, Vec<Series>)> = vec![
        (
            "(a) x",
            "x [m]",
            vec![
                series("truth", &|i| pos(truth, i, 0)),
                series("estimate", &|i| pos(estimate, i, 0)),
            ],
        ),
        (
            "(b) y",
            "y [m]",
            vec![
                series("truth", &|i| pos(truth, i, 1)),
                series("estimate", &|i| pos(estimate, i, 1)),
            ],
        ),
        (
            "(c) z",
            "z [m]",
            vec![
                series("truth", &|i| pos(truth, i, 2)),
                series("estimate", &|i| pos(estimate, i, 2)),
            ],
        ),
        (
            "(d) pitch",
            "pitch [deg]",
            vec![
                series("truth", &|i| euler(truth, i).1.to_degrees()),
                series("estimate", &|i| euler(estimate, i).1.to_degrees()),
            ],
        ),
        (
            "(e) roll and yaw error",
            "error [deg]",
            vec![
                series("roll error", &|i| {
                    wrap(euler(estimate, i).0 - euler(truth, i).0).to_degrees()
                }),
                series("yaw error", &|i| {
                    wrap(euler(estimate, i).2 - euler(truth, i).2).to_degrees()
                }),
            ],
        ),
    ];
    hopnav_metrics::plot::register_font().map_err(error)?;
    let root = BitMapBackend::new(path, (1500, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
    let areas = root.split_evenly((2, 3));
    for ((title, y_label, series), area) in panels.iter().zip(areas) {
        let plot = LinePlot {
            title,
            x_label: "t [s]",
            y_label,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series,
        };
        draw(area, &plot).map_err(error)?;
    }
    root.present().map_err(|e| error(e.to_string()))
}
