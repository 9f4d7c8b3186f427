//! Line plots as SVG: plotters' SVG backend writes text as SVG elements, so no font or system
//! library is needed to build or to view them.

use std::path::Path;

use plotters::coord::CoordTranslate;
use plotters::prelude::*;

/// One line of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
}

/// Axis scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// Linear axis.
    Linear,
    /// Base-10 logarithmic axis (values must be positive).
    Log,
}

/// What a line plot shows.
#[derive(Debug, Clone)]
pub struct LinePlot<'a> {
    /// Title above the plot.
    pub title: &'a str,
    /// X axis label.
    pub x_label: &'a str,
    /// Y axis label.
    pub y_label: &'a str,
    /// X scaling.
    pub x_scale: Scale,
    /// Y scaling.
    pub y_scale: Scale,
    /// The lines.
    pub series: &'a [Series],
}

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw plot {path}: {message}")]
pub struct PlotError {
    /// Output path.
    pub path: String,
    /// What failed.
    pub message: String,
}

impl PlotError {
    /// The error of drawing into `path`, for `map_err`.
    pub fn writing(path: &Path) -> impl Fn(String) -> PlotError + Copy + '_ {
        move |message| PlotError {
            path: path.display().to_string(),
            message,
        }
    }
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn range(values: impl Iterator<Item = f64>, scale: Scale) -> (f64, f64) {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for value in values.filter(|v| v.is_finite() && (scale == Scale::Linear || *v > 0.0)) {
        low = low.min(value);
        high = high.max(value);
    }
    if !low.is_finite() {
        return (1.0, 10.0);
    }
    match scale {
        Scale::Linear if high > low => (low, high + (high - low) * 0.05),
        Scale::Linear => (low - 1.0, high + 1.0),
        Scale::Log => (low / 1.5, high * 1.5),
    }
}

/// The font of plot text, vendored so plots need no system font (DejaVu Sans, Bitstream Vera
/// licence in `assets/DejaVuSans-LICENSE`).
static FONT_TTF: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font with plotters; call it before drawing text on your own
/// drawing areas (`write_svg` and `write_png` call it themselves). Idempotent.
pub fn register_font() -> Result<(), String> {
    static REGISTERED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_TTF)
                .map_err(|_| "the embedded font is not a valid TrueType font".to_owned())
        })
        .clone()
}

/// Draws `plot` into an SVG file at `path`.
pub fn write_svg(path: &Path, plot: &LinePlot<'_>) -> Result<(), PlotError> {
    // Text is laid out with the embedded font's metrics even in SVG.
    draw_into(path, plot, || SVGBackend::new(path, (960, 600)))
}

/// Draws `plot` into a PNG file at `path`.
pub fn write_png(path: &Path, plot: &LinePlot<'_>) -> Result<(), PlotError> {
    draw_into(path, plot, || BitMapBackend::new(path, (1200, 750)))
}

/// Registers the font, then draws `plot` on the backend `open` makes for `path`.
fn draw_into<DB: DrawingBackend>(
    path: &Path,
    plot: &LinePlot<'_>,
    open: impl FnOnce() -> DB,
) -> Result<(), PlotError> {
    let error = PlotError::writing(path);
    register_font().map_err(error)?;
    draw(open().into_drawing_area(), plot).map_err(error)
}

/// The points of `points` with both coordinates finite (what a chart can place).
pub(crate) fn finite_points(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect()
}

/// Draws the legend of `chart`'s labelled series at `position`, framed in black on white of
/// `opacity` (0–1).
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    opacity: f64,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(opacity))
        .position(position)
        .draw()
        .map_err(|e| e.to_string())
}

/// Draws `plot` on any plotters drawing area (SVG, PNG, or a panel of a larger figure).
pub fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    plot: &LinePlot<'_>,
) -> Result<(), String> {
    let all_points = || plot.series.iter().flat_map(|series| series.points.iter());
    let x_range = range(all_points().map(|p| p.0), plot.x_scale);
    let y_range = range(all_points().map(|p| p.1), plot.y_scale);
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    macro_rules! draw {
        ($x:expr, $y:expr) => {{
            let mut chart = ChartBuilder::on(&root)
                .caption(plot.title, ("sans-serif", 22))
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(72)
                .build_cartesian_2d($x, $y)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc(plot.x_label)
                .y_desc(plot.y_label)
                .draw()
                .map_err(|e| e.to_string())?;
            for (index, series) in plot.series.iter().enumerate() {
                let color = PALETTE[index % PALETTE.len()];
                let points = finite_points(&series.points);
                chart
                    .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(series.label.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                if points.len() <= 64 {
                    chart
                        .draw_series(
                            points
                                .into_iter()
                                .map(|p| Circle::new(p, 3, color.filled())),
                        )
                        .map_err(|e| e.to_string())?;
                }
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft, 0.8)?;
        }};
    }
    match (plot.x_scale, plot.y_scale) {
        (Scale::Log, Scale::Log) => {
            draw!(
                (x_range.0..x_range.1).log_scale(),
                (y_range.0..y_range.1).log_scale()
            )
        }
        (Scale::Log, Scale::Linear) => {
            draw!((x_range.0..x_range.1).log_scale(), y_range.0..y_range.1)
        }
        (Scale::Linear, Scale::Log) => {
            draw!(x_range.0..x_range.1, (y_range.0..y_range.1).log_scale())
        }
        (Scale::Linear, Scale::Linear) => draw!(x_range.0..x_range.1, y_range.0..y_range.1),
    }
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_an_svg_with_title_and_labels() {
        let dir = std::env::temp_dir().join(format!("hopnav-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("plot.svg");
        let series = [Series {
            label: "transport".into(),
            points: vec![(64.0, 0.01), (4096.0, 0.011), (4.0e6, 0.012)],
        }];
        let plot = LinePlot {
            title: "latency",
            x_label: "payload bytes",
            y_label: "p50 ms",
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            series: &series,
        };
        write_svg(&path, &plot).expect("plot");
        let svg = std::fs::read_to_string(&path).expect("read");
        assert!(svg.contains("<svg") && svg.contains("latency") && svg.contains("transport"));
        let png_path = dir.join("plot.png");
        write_png(&png_path, &plot).expect("png");
        let png = std::fs::read(&png_path).expect("read png");
        assert_eq!(&png[1..4], b"PNG");
        std::fs::remove_dir_all(&dir).ok();
    }
}
