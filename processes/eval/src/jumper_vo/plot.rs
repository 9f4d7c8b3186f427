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

/// One panel: title, y-axis label and its lines.
type Panel = (&'static str, &'static str, Vec<Series>);

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
    let panels = fig5_panels(t_s, truth, estimate);
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

/// x, y, z and pitch of truth and estimate, then the roll and yaw errors (wrapped to ±180°).
fn fig5_panels(t_s: &[f64], truth: &[Isometry3<f64>], estimate: &[Isometry3<f64>]) -> Vec<Panel> {
    let n = t_s.len().min(truth.len()).min(estimate.len());
    let series = |label: &str, f: &dyn Fn(usize) -> f64| Series {
        label: label.to_owned(),
        points: (0..n).map(|i| (t_s[i], f(i))).collect(),
    };
    let truth_and_estimate = |f: &dyn Fn(&[Isometry3<f64>], usize) -> f64| {
        vec![
            series("truth", &|i| f(truth, i)),
            series("estimate", &|i| f(estimate, i)),
        ]
    };
    let euler = |p: &[Isometry3<f64>], i: usize| euler_from_rotation(&p[i].rotation);
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
    };
    let mut panels: Vec<Panel> = [("(a) x", "x [m]"), ("(b) y", "y [m]"), ("(c) z", "z [m]")]
        .into_iter()
        .enumerate()
        .map(|(axis, (title, y_label))| {
            let lines = truth_and_estimate(&|p, i| p[i].translation.vector[axis]);
            (title, y_label, lines)
        })
        .collect();
    panels.push((
        "(d) pitch",
        "pitch [deg]",
        truth_and_estimate(&|p, i| euler(p, i).1.to_degrees()),
    ));
    panels.push((
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
    ));
    panels
}
