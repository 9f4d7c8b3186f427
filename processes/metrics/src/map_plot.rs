//! The paper's Fig. 6 as a PNG: the mission grid with each mapped cell coloured by what it is
//! (obstacle or inflated) and who saw it (rover, jumper or both), the start and goal, any
//! number of trajectories drawn over it (both modes' rover paths, the jumper's hops) and, for
//! evaluation, the outlines of the world's true rocks the rover cannot climb.

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::plot::{PlotError, draw_legend, finite_points, register_font};

/// Who observed a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Observer {
    /// Only the rover's stereo camera.
    Rover,
    /// Only the jumper's camera.
    Jumper,
    /// Both robots.
    Both,
    /// Nobody: an unseen cell inside an obstacle's inflation.
    Nobody,
}

/// What a mapped cell is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MappedClass {
    /// Observed, traversable.
    Free,
    /// Obstacle.
    Obstacle,
    /// Traversable at extra cost near an obstacle.
    Inflated,
    /// Maybe too tall to climb, or the body would touch such a rock: traversable at a cost
    /// until a closer look settles it.
    Uncertain,
}

/// One mapped cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MappedCell {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// Class.
    pub class: MappedClass,
    /// Observer.
    pub observer: Observer,
}

/// A line drawn over the map.
#[derive(Debug, Clone)]
pub struct Track {
    /// Legend label.
    pub label: String,
    /// Points in world metres.
    pub points_m: Vec<(f64, f64)>,
    /// Colour (r, g, b).
    pub rgb: (u8, u8, u8),
    /// Dashed-looking markers instead of a line (for hops).
    pub markers_only: bool,
}

/// A true rock's footprint, drawn as an outline over the cells (evaluation only).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockOutline {
    /// Centre (x, y), world metres.
    pub center_m: (f64, f64),
    /// Horizontal radius, metres.
    pub radius_m: f64,
}

/// Everything on the figure.
#[derive(Debug, Clone)]
pub struct MapFigure {
    /// Title.
    pub title: String,
    /// World x, y of the corner of cell (0, 0), metres.
    pub origin_m: (f64, f64),
    /// Cell edge, metres.
    pub cell_size_m: f64,
    /// Mapped cells (unmapped cells stay white).
    pub cells: Vec<MappedCell>,
    /// Start A and goal B, world metres.
    pub start_m: (f64, f64),
    /// Goal B.
    pub goal_m: (f64, f64),
    /// Lines over the map.
    pub tracks: Vec<Track>,
    /// True rocks to outline (empty: none drawn, no legend entry).
    pub rocks: Vec<RockOutline>,
    /// World rectangle to show: (x min, x max, y min, y max), metres.
    pub view_m: (f64, f64, f64, f64),
}

fn cell_colour(class: MappedClass, observer: Observer) -> RGBColor {
    match (class, observer) {
        (MappedClass::Free, _) => RGBColor(235, 235, 235),
        (MappedClass::Obstacle, Observer::Rover) => RGBColor(31, 78, 160),
        (MappedClass::Obstacle, Observer::Jumper) => RGBColor(190, 40, 30),
        (MappedClass::Obstacle, Observer::Both) => RGBColor(110, 40, 130),
        (MappedClass::Inflated, Observer::Rover) => RGBColor(150, 185, 235),
        (MappedClass::Inflated, Observer::Jumper) => RGBColor(245, 170, 160),
        (MappedClass::Inflated, Observer::Both) => RGBColor(205, 170, 220),
        (MappedClass::Obstacle, Observer::Nobody) => RGBColor(90, 90, 90),
        (MappedClass::Inflated, Observer::Nobody) => RGBColor(225, 215, 190),
        (MappedClass::Uncertain, _) => RGBColor(240, 190, 40),
    }
}

const LEGEND: [(&str, MappedClass, Observer); 8] = [
    ("rover obstacle", MappedClass::Obstacle, Observer::Rover),
    ("rover inflated", MappedClass::Inflated, Observer::Rover),
    ("jumper obstacle", MappedClass::Obstacle, Observer::Jumper),
    ("jumper inflated", MappedClass::Inflated, Observer::Jumper),
    ("both obstacle", MappedClass::Obstacle, Observer::Both),
    ("both inflated", MappedClass::Inflated, Observer::Both),
    ("inflated, unseen", MappedClass::Inflated, Observer::Nobody),
    ("maybe too tall", MappedClass::Uncertain, Observer::Both),
];

/// Draws `figure` into a PNG at `path`.
pub fn write_map_png(path: &Path, figure: &MapFigure) -> Result<(), PlotError> {
    let error = PlotError::writing(path);
    register_font().map_err(error)?;
    let (x0, x1, y0, y1) = figure.view_m;
    if !(x1 > x0 && y1 > y0 && figure.cell_size_m > 0.0) {
        return Err(error(format!("empty view {:?}", figure.view_m)));
    }
    let width_px = 1100u32;
    let height_px =
        ((f64::from(width_px - 200) * (y1 - y0) / (x1 - x0)) as u32 + 140).clamp(300, 1400);
    let root = BitMapBackend::new(path, (width_px, height_px)).into_drawing_area();
    draw_map(&root, figure).map_err(error)?;
    root.present().map_err(|e| error(e.to_string()))
}

fn draw_map<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    figure: &MapFigure,
) -> Result<(), String> {
    let (x0, x1, y0, y1) = figure.view_m;
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut chart = ChartBuilder::on(root)
        .caption(&figure.title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x [m]")
        .y_desc("y [m]")
        .draw()
        .map_err(|e| e.to_string())?;
    draw_cells(&mut chart, figure)?;
    draw_rock_outlines(&mut chart, &figure.rocks)?;
    draw_tracks(&mut chart, &figure.tracks)?;
    for (label, point, colour) in [
        ("start A", figure.start_m, RGBColor(20, 140, 20)),
        ("goal B", figure.goal_m, RGBColor(0, 0, 0)),
    ] {
        chart
            .draw_series(std::iter::once(TriangleMarker::new(
                point,
                9,
                colour.filled(),
            )))
            .map_err(|e| e.to_string())?
            .label(label)
            .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 6, colour.filled()));
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperRight, 0.85)
}

/// The mapped cells, coloured by class and observer, with the legend of the colours.
fn draw_cells<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    figure: &MapFigure,
) -> Result<(), String> {
    let size_m = figure.cell_size_m;
    let (ox, oy) = figure.origin_m;
    chart
        .draw_series(figure.cells.iter().map(|cell| {
            let left = ox + f64::from(cell.x) * size_m;
            let bottom = oy + f64::from(cell.y) * size_m;
            Rectangle::new(
                [(left, bottom), (left + size_m, bottom + size_m)],
                cell_colour(cell.class, cell.observer).filled(),
            )
        }))
        .map_err(|e| e.to_string())?;
    for (label, class, observer) in LEGEND {
        let colour = cell_colour(class, observer);
        chart
            .draw_series(std::iter::empty::<Rectangle<(f64, f64)>>())
            .map_err(|e| e.to_string())?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
    }
    Ok(())
}

/// Each track as a line (or as dots), skipping points that are not finite.
fn draw_tracks<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    tracks: &[Track],
) -> Result<(), String> {
    for track in tracks {
        let colour = RGBColor(track.rgb.0, track.rgb.1, track.rgb.2);
        let points = finite_points(&track.points_m);
        let series = if track.markers_only {
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 2, colour.filled())))
                .map_err(|e| e.to_string())?
        } else {
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(3)))
                .map_err(|e| e.to_string())?
        };
        series.label(track.label.clone()).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
        });
    }
    Ok(())
}

/// Vertices of a rock outline: enough for a round look at the sizes a 0.5 m grid shows.
const OUTLINE_VERTICES: usize = 16;

fn draw_rock_outlines<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    rocks: &[RockOutline],
) -> Result<(), String> {
    if rocks.is_empty() {
        return Ok(());
    }
    let colour = RGBColor(20, 20, 20);
    let outline = |rock: &RockOutline| {
        let points: Vec<(f64, f64)> = (0..=OUTLINE_VERTICES)
            .map(|i| {
                let angle_rad = std::f64::consts::TAU * i as f64 / OUTLINE_VERTICES as f64;
                (
                    rock.center_m.0 + rock.radius_m * angle_rad.cos(),
                    rock.center_m.1 + rock.radius_m * angle_rad.sin(),
                )
            })
            .collect();
        PathElement::new(points, colour.stroke_width(1))
    };
    chart
        .draw_series(rocks.iter().map(outline))
        .map_err(|e| e.to_string())?
        .label("true rock, unclimbable")
        .legend(move |(x, y)| Circle::new((x + 8, y), 5, colour.stroke_width(1)));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_a_png_with_cells_and_tracks() {
        let dir = std::env::temp_dir().join(format!("hopnav-map-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("fig6.png");
        let figure = MapFigure {
            title: "test".into(),
            origin_m: (-10.0, -10.0),
            cell_size_m: 0.5,
            cells: vec![
                MappedCell {
                    x: 20,
                    y: 20,
                    class: MappedClass::Obstacle,
                    observer: Observer::Jumper,
                },
                MappedCell {
                    x: 21,
                    y: 20,
                    class: MappedClass::Inflated,
                    observer: Observer::Rover,
                },
            ],
            start_m: (-8.0, 0.0),
            goal_m: (8.0, 0.0),
            tracks: vec![Track {
                label: "rover".into(),
                points_m: vec![(-8.0, 0.0), (0.0, 3.0), (8.0, 0.0)],
                rgb: (0, 120, 0),
                markers_only: false,
            }],
            rocks: vec![RockOutline {
                center_m: (0.0, 0.0),
                radius_m: 0.6,
            }],
            view_m: (-10.0, 10.0, -10.0, 10.0),
        };
        write_map_png(&path, &figure).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let bad = MapFigure {
            view_m: (0.0, 0.0, 0.0, 1.0),
            ..figure
        };
        assert!(write_map_png(&path, &bad).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
