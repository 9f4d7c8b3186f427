//! The cooperative rule of the paper: the rover asks the jumper to hop when its path runs into
//! cells it cannot map itself, because they are beyond its stereo range or hidden behind an
//! obstacle. The jumper's rear camera maps the ground it flies over, so the hop target lies
//! past the region of interest, along the path.

use super::geometry::MapGeometry;
use crate::grid::{Cell, CellState, Grid};

/// A hop the rover wants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoutDecision {
    /// Index into the path of the first cell the rover cannot map itself.
    pub region_index: usize,
    /// Where the jumper should land, world metres.
    pub target_m: [f64; 2],
}

/// Index of the first path cell that is unknown and either farther than `sensing_range_m` from
/// the rover or hidden from it by an obstacle cell; `None` when the rover can map the whole
/// path itself.
pub fn find_region_of_interest(
    grid: &Grid,
    geometry: &MapGeometry,
    path: &[Cell],
    rover_m: [f64; 2],
    sensing_range_m: f64,
) -> Option<usize> {
    let rover_cell = geometry.nearest_cell(rover_m)?;
    path.iter().position(|&cell| {
        if grid.state(cell) != Some(CellState::Unknown) {
            return false;
        }
        let centre_m = geometry.center_of(cell);
        distance_m(centre_m, rover_m) > sensing_range_m || !line_of_sight(grid, rover_cell, cell)
    })
}

/// Picks a hop that flies over the region (the rear camera maps the ground between launch
/// and landing). A jumper short of the region along the path hops to the point farthest
/// along `path` (at or past `region_index`) within `hop_range_m`; a jumper already past it
/// (it scouted ahead earlier) hops back to the path point nearest the region on the rover's
/// side that lies [`BACK_HOP_MARGIN_M`] before it. Either way the hop is at least
/// `min_hop_m` long. When that point is beyond one hop (the route moved far from where the
/// jumper waits), the jumper hops to the path point nearest it within reach, if that gains
/// at least half a minimum hop: the next request can then reach the region.
pub(crate) fn choose_target(
    geometry: &MapGeometry,
    path: &[Cell],
    region_index: usize,
    jumper_m: [f64; 2],
    hop_range_m: f64,
    min_hop_m: f64,
) -> Option<ScoutDecision> {
    let jumper_index = path
        .iter()
        .enumerate()
        .min_by(|(_, a), (_, b)| {
            let (a_m, b_m) = (geometry.center_of(**a), geometry.center_of(**b));
            distance_m(a_m, jumper_m).total_cmp(&distance_m(b_m, jumper_m))
        })
        .map(|(index, _)| index)?;
    let reachable = |centre_m: &[f64; 2]| {
        let hop_m = distance_m(*centre_m, jumper_m);
        (min_hop_m..=hop_range_m).contains(&hop_m)
    };
    let region_m = geometry.center_of(*path.get(region_index)?);
    let ideal_m = if jumper_index <= region_index {
        path.iter()
            .skip(region_index)
            .map(|&cell| geometry.center_of(cell))
            .rfind(|centre_m| distance_m(*centre_m, jumper_m) <= hop_range_m)
            .unwrap_or(region_m)
    } else {
        path[..region_index]
            .iter()
            .rev()
            .map(|&cell| geometry.center_of(cell))
            .find(|centre_m| distance_m(*centre_m, region_m) >= BACK_HOP_MARGIN_M)?
    };
    let target_m = if distance_m(ideal_m, jumper_m) <= hop_range_m {
        Some(ideal_m).filter(reachable)?
    } else {
        let gap_m = |centre_m: &[f64; 2]| distance_m(*centre_m, ideal_m);
        path.iter()
            .map(|&cell| geometry.center_of(cell))
            .filter(reachable)
            .min_by(|a, b| gap_m(a).total_cmp(&gap_m(b)))
            .filter(|centre_m| gap_m(centre_m) <= gap_m(&jumper_m) - 0.5 * min_hop_m)?
    };
    Some(ScoutDecision {
        region_index,
        target_m,
    })
}

/// A hop back over a region lands this far before it, on the rover's side, metres.
const BACK_HOP_MARGIN_M: f64 = 3.0;

pub(crate) fn distance_m(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// True when no obstacle cell lies strictly between `from` and `to` on the Bresenham line.
pub(crate) fn line_of_sight(grid: &Grid, from: Cell, to: Cell) -> bool {
    let (mut x, mut y) = (i64::from(from.x), i64::from(from.y));
    let (x1, y1) = (i64::from(to.x), i64::from(to.y));
    let dx = (x1 - x).abs();
    let dy = -(y1 - y).abs();
    let step_x = if x < x1 { 1 } else { -1 };
    let step_y = if y < y1 { 1 } else { -1 };
    let mut error = dx + dy;
    while (x, y) != (x1, y1) {
        let doubled = 2 * error;
        if doubled >= dy {
            error += dy;
            x += step_x;
        }
        if doubled <= dx {
            error += dx;
            y += step_y;
        }
        if (x, y) == (x1, y1) {
            break;
        }
        let cell = Cell::new(x as u32, y as u32);
        if grid.state(cell) == Some(CellState::Obstacle) {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::CellChange;

    fn straight_path(length: u32) -> Vec<Cell> {
        (0..length).map(|x| Cell::new(x, 10)).collect()
    }

    #[test]
    fn unknown_cells_beyond_range_are_interesting() {
        let geometry = MapGeometry::new(0.0, 0.0, 1.0, 40, 20).unwrap();
        let mut grid = Grid::new(40, 20, CellState::Unknown).unwrap();
        for x in 0..8 {
            grid.apply(&CellChange::new(Cell::new(x, 10), CellState::Free, 0))
                .unwrap();
        }
        let path = straight_path(40);
        // Cells 8..=10 are unknown but within 10 m: visible; 11.. are beyond range.
        let index = find_region_of_interest(&grid, &geometry, &path, [0.5, 10.5], 10.0);
        assert_eq!(index, Some(11));
    }

    #[test]
    fn unknown_cells_behind_an_obstacle_are_interesting() {
        let geometry = MapGeometry::new(0.0, 0.0, 1.0, 40, 20).unwrap();
        let mut grid = Grid::new(40, 20, CellState::Unknown).unwrap();
        // The path bends around an obstacle at (4, 12); the cell behind it is unknown.
        grid.apply(&CellChange::new(Cell::new(4, 12), CellState::Obstacle, 0))
            .unwrap();
        let path = vec![
            Cell::new(2, 10),
            Cell::new(3, 11),
            Cell::new(3, 12),
            Cell::new(3, 13),
            Cell::new(4, 13),
            Cell::new(5, 13),
            Cell::new(6, 13),
        ];
        for cell in &path[..4] {
            grid.apply(&CellChange::new(*cell, CellState::Free, 0))
                .unwrap();
        }
        // From (1,11) the line to (6,13) passes (4,12): hidden although only 5 m away.
        let index = find_region_of_interest(&grid, &geometry, &path, [1.5, 11.5], 30.0);
        assert_eq!(index, Some(6));
    }

    #[test]
    fn a_fully_visible_path_needs_no_hop() {
        let geometry = MapGeometry::new(0.0, 0.0, 1.0, 40, 20).unwrap();
        let grid = Grid::new(40, 20, CellState::Free).unwrap();
        let path = straight_path(40);
        assert_eq!(
            find_region_of_interest(&grid, &geometry, &path, [0.5, 10.5], 5.0),
            None
        );
    }

    #[test]
    fn target_is_the_farthest_path_point_in_hop_range() {
        let geometry = MapGeometry::new(0.0, 0.0, 1.0, 40, 20).unwrap();
        let path = straight_path(40);
        let decision = choose_target(&geometry, &path, 10, [0.5, 10.5], 20.0, 5.0).unwrap();
        assert_eq!(decision.target_m, [20.5, 10.5]);
        // The jumper is too close to the end of the path for a worthwhile hop.
        assert!(choose_target(&geometry, &path, 38, [37.5, 10.5], 20.0, 5.0).is_none());
        // The region is out of reach: one hop toward it, as far as the range allows.
        let decision = choose_target(&geometry, &path, 35, [0.5, 10.5], 20.0, 5.0).unwrap();
        assert_eq!(decision.target_m, [20.5, 10.5]);
    }

    #[test]
    fn a_jumper_past_the_region_hops_back_over_it() {
        let geometry = MapGeometry::new(0.0, 0.0, 1.0, 40, 20).unwrap();
        let path = straight_path(40);
        // The jumper waits at the end of the path; the region starts at cell 20.
        let decision = choose_target(&geometry, &path, 20, [38.5, 10.5], 25.0, 5.0).unwrap();
        assert_eq!(decision.target_m, [17.5, 10.5], "3 m short of the region");
        // Too far back for one hop: the jumper hops back as far as it can.
        let decision = choose_target(&geometry, &path, 20, [38.5, 10.5], 15.0, 5.0).unwrap();
        assert_eq!(decision.target_m, [23.5, 10.5]);
    }
}
