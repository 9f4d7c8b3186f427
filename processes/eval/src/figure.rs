//! The mission's Fig.-6 figure: the final map's cells coloured by who saw them, both robots'
//! true tracks and the outlines of the world's rocks the rover cannot climb.

use hopnav_ipc::messages::{CellClass, Robot};
use hopnav_metrics::map_plot::{MapFigure, MappedCell, MappedClass, Observer, RockOutline, Track};
use hopnav_supervisor::mission_record::{MissionRecord, RecordedMap};

use crate::mission::MissionTruth;

/// The figure of `record`, titled `title`; `None` without a map, A or B.
pub fn mission_figure(
    title: &str,
    truth: &MissionTruth,
    record: &MissionRecord,
) -> Option<MapFigure> {
    let map = record.map.as_ref()?;
    let (start, goal) = (truth.start_m?, truth.goal_m?);
    let rover_label = format!("rover ({})", record.mode.name());
    let rocks = truth
        .rocks
        .as_deref()
        .unwrap_or_default()
        .iter()
        .filter(|rock| rock.height_m > truth.climbable_height_m)
        .map(|rock| RockOutline {
            center_m: (rock.center_m[0], rock.center_m[1]),
            radius_m: rock.radius_m,
        })
        .collect();
    Some(map_figure(
        title,
        map.origin_m,
        map.cell_size_m,
        mapped_cells(map),
        (start[0], start[1]),
        (goal[0], goal[1]),
        vec![
            Track {
                label: rover_label,
                points_m: record.rover_track_m.clone(),
                rgb: (0, 150, 60),
                markers_only: false,
            },
            Track {
                label: "jumper".into(),
                points_m: record.jumper_track_m.clone(),
                rgb: (230, 130, 0),
                markers_only: true,
            },
        ],
        rocks,
    ))
}

fn mapped_cells(map: &RecordedMap) -> Vec<MappedCell> {
    let rover_bit = 1u32 << Robot::Rover.code();
    let jumper_bit = 1u32 << Robot::Jumper.code();
    map.cells
        .iter()
        .filter_map(|cell| {
            let class = match cell.class {
                CellClass::Unknown => return None,
                CellClass::Free => MappedClass::Free,
                CellClass::Obstacle => MappedClass::Obstacle,
                CellClass::Inflated | CellClass::Lethal => MappedClass::Inflated,
                CellClass::Uncertain => MappedClass::Uncertain,
            };
            let observer = match (
                cell.observed_by & rover_bit != 0,
                cell.observed_by & jumper_bit != 0,
            ) {
                (true, true) => Observer::Both,
                (false, true) => Observer::Jumper,
                (true, false) => Observer::Rover,
                (false, false) => Observer::Nobody,
            };
            Some(MappedCell {
                x: cell.x,
                y: cell.y,
                class,
                observer,
            })
        })
        .collect()
}

/// A figure around start, goal and every track, with `cells` under them and the `rocks`
/// within view outlined.
#[allow(clippy::too_many_arguments)]
pub fn map_figure(
    title: &str,
    origin_m: (f64, f64),
    cell_size_m: f64,
    cells: Vec<MappedCell>,
    start_m: (f64, f64),
    goal_m: (f64, f64),
    tracks: Vec<Track>,
    rocks: Vec<RockOutline>,
) -> MapFigure {
    let points = tracks
        .iter()
        .flat_map(|track| track.points_m.iter().copied())
        .chain([start_m, goal_m])
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in points {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let margin_m = 4.0;
    let half_height_m = ((y1 - y0) / 2.0 + margin_m).max((x1 - x0) / 6.0);
    let centre_y = (y0 + y1) / 2.0;
    // Room on the right for the legend, so it never hides the goal or a track.
    let legend_m = 0.3 * (x1 - x0 + 2.0 * margin_m);
    let view_m = (
        x0 - margin_m,
        x1 + margin_m + legend_m,
        centre_y - half_height_m,
        centre_y + half_height_m,
    );
    let in_view = |rock: &RockOutline| {
        let (x, y, r) = (rock.center_m.0, rock.center_m.1, rock.radius_m);
        x + r > view_m.0 && x - r < view_m.1 && y + r > view_m.2 && y - r < view_m.3
    };
    MapFigure {
        title: title.to_owned(),
        origin_m,
        cell_size_m,
        cells,
        start_m,
        goal_m,
        tracks,
        rocks: rocks.into_iter().filter(in_view).collect(),
        view_m,
    }
}
