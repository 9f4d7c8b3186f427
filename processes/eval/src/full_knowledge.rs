//! The path the planner would drive if every rock were known from the start (evaluation
//! only): the lower bound on what any scout can save the rover. It answers "how much longer
//! than necessary was the path" without guessing: rover-only missions that already drive
//! close to this length leave a jumper little to shorten.
//!
//! The known map is built as the mapper would build it from perfect clouds of the rocks the
//! rover cannot climb: every cell such a rock reaches is an obstacle, inflated with the
//! mapper's kernel. Lethal margins are obstacles too, unless they alone cut A off B: then,
//! as the navigator does, they are planned through at its doubtful-obstacle cost. A* plans
//! on it with the planner's costs; the length is that of the cell path pulled taut (a
//! straight segment wherever every cell it crosses is traversable), as pure pursuit drives.
//!
//! [`plan_on_known_map`] is that planning step on any map known in full; the mission report
//! also runs it on the map the robots built (see `MissionReport::built_map_path_m`).

use hopnav_mapper::inflation::KernelEntry;
use hopnav_planner::astar::astar;
use hopnav_planner::mission::{DOUBTFUL_OBSTACLE_COST, MapGeometry};
use hopnav_planner::{Cell, CellState, Grid};
use hopnav_robot::SlopeClass;

use crate::map_accuracy::{RockFootprint, distance_to_square_m};

/// The full-knowledge plan of one mission.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FullKnowledgePath {
    /// Length from A to B along the taut path, metres.
    pub length_m: f64,
    /// Obstacle cells of the known map (lethal margins included).
    pub obstacle_cells: usize,
}

/// Plans from `start_m` to `goal_m` on the map of `rocks` taller than
/// `min_obstacle_height_m` and of the ground's true `slopes` (row-major over the grid; empty:
/// level everywhere): too steep a cell is an obstacle, a steep one costs the kernel's band
/// cost, as the mapper costs them. `None` when A or B lies outside the grid or no path
/// exists.
pub fn full_knowledge_path(
    rocks: &[RockFootprint],
    min_obstacle_height_m: f64,
    slopes: &[SlopeClass],
    geometry: &MapGeometry,
    kernel: &[KernelEntry],
    start_m: [f64; 2],
    goal_m: [f64; 2],
) -> Option<FullKnowledgePath> {
    let grid = Grid::new(
        geometry.width_cells(),
        geometry.height_cells(),
        CellState::Free,
    )
    .ok()?;
    let mut rock = vec![false; grid.cell_count()];
    let mut lethal = vec![false; grid.cell_count()];
    let mut extra_cost = vec![0u32; grid.cell_count()];
    for cell in rock_cells(rocks, min_obstacle_height_m, geometry, &grid) {
        if let Some(index) = grid.index_of(cell) {
            rock[index] = true;
        }
        for entry in kernel {
            let Some(index) = grid
                .offset(cell, entry.dx, entry.dy)
                .and_then(|near| grid.index_of(near))
            else {
                continue;
            };
            lethal[index] |= entry.lethal;
            extra_cost[index] = extra_cost[index].max(entry.cost);
        }
    }
    let band_cost = kernel.iter().map(|entry| entry.cost).max().unwrap_or(0);
    for (index, slope) in slopes.iter().enumerate().take(grid.cell_count()) {
        match slope {
            SlopeClass::TooSteep => rock[index] = true,
            SlopeClass::Steep => extra_cost[index] = extra_cost[index].max(band_cost),
            SlopeClass::Level => {}
        }
    }
    let known: Vec<KnownCell> = (0..grid.cell_count())
        .map(|index| {
            if rock[index] {
                KnownCell::Obstacle
            } else if lethal[index] {
                KnownCell::Doubtful
            } else {
                KnownCell::Free {
                    extra_cost: extra_cost[index],
                }
            }
        })
        .collect();
    plan_on_known_map(&known, geometry, start_m, goal_m)
}

/// One cell of a map known in full, for [`plan_on_known_map`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KnownCell {
    /// Never driven through.
    Obstacle,
    /// An obstacle unless such cells alone cut A off B: then, as the navigator does, planned
    /// through at its doubtful-obstacle cost (a lethal margin, a rock the rover never saw).
    Doubtful,
    /// Traversable at this extra cost per move into it (planner units).
    Free {
        /// See [`KnownCell::Free`].
        extra_cost: u32,
    },
}

/// Plans from `start_m` to `goal_m` with A* and the planner's costs on `cells` (row-major,
/// `geometry`'s size) and pulls the path taut. A and B stay open, as the navigator keeps
/// them. `None` when A or B lies outside the grid, the cell count does not match, or no path
/// exists even through the doubtful cells.
pub fn plan_on_known_map(
    cells: &[KnownCell],
    geometry: &MapGeometry,
    start_m: [f64; 2],
    goal_m: [f64; 2],
) -> Option<FullKnowledgePath> {
    let mut grid = Grid::new(
        geometry.width_cells(),
        geometry.height_cells(),
        CellState::Free,
    )
    .ok()?;
    if cells.len() != grid.cell_count() {
        return None;
    }
    let goal = geometry.cell_of(goal_m)?;
    let start = geometry.cell_of(start_m)?;
    let mut obstacle_cells = 0;
    let mut plan = None;
    for doubtful_is_obstacle in [true, false] {
        obstacle_cells = 0;
        for (index, known) in cells.iter().enumerate() {
            let cell = grid.cell_at(index)?;
            let (state, extra_cost) = match known {
                _ if cell == start || cell == goal => (CellState::Free, 0),
                KnownCell::Obstacle => (CellState::Obstacle, 0),
                KnownCell::Doubtful if doubtful_is_obstacle => (CellState::Obstacle, 0),
                KnownCell::Doubtful => (CellState::Free, DOUBTFUL_OBSTACLE_COST),
                KnownCell::Free { extra_cost } => (CellState::Free, *extra_cost),
            };
            obstacle_cells += usize::from(state == CellState::Obstacle);
            grid.set(cell, state, extra_cost).ok()?;
        }
        plan = astar(&grid, start, goal).ok();
        if plan.is_some() {
            break;
        }
    }
    Some(FullKnowledgePath {
        length_m: taut_length_m(&grid, geometry, &plan?.path, start_m, goal_m),
        obstacle_cells,
    })
}

/// Cells of `grid` whose square a rock taller than `min_height_m` reaches.
fn rock_cells(
    rocks: &[RockFootprint],
    min_height_m: f64,
    geometry: &MapGeometry,
    grid: &Grid,
) -> Vec<Cell> {
    let size_m = geometry.cell_size_m();
    let mut cells = Vec::new();
    for rock in rocks.iter().filter(|rock| rock.height_m > min_height_m) {
        let Some(centre) = geometry.cell_of(rock.center_m) else {
            continue;
        };
        let reach = (rock.radius_m / size_m).ceil() as i32 + 1;
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let Some(cell) = grid.offset(centre, dx, dy) else {
                    continue;
                };
                let gap_m = distance_to_square_m(geometry.center_of(cell), size_m, rock.center_m);
                if gap_m < rock.radius_m {
                    cells.push(cell);
                }
            }
        }
    }
    cells
}

/// Length of `path` pulled taut: from each point, straight to the farthest later path point
/// the segment to which stays on traversable cells; A and B are the real points.
fn taut_length_m(
    grid: &Grid,
    geometry: &MapGeometry,
    path: &[Cell],
    start_m: [f64; 2],
    goal_m: [f64; 2],
) -> f64 {
    let mut points: Vec<[f64; 2]> = path.iter().map(|&cell| geometry.center_of(cell)).collect();
    if let Some(first) = points.first_mut() {
        *first = start_m;
    }
    if let Some(last) = points.last_mut() {
        *last = goal_m;
    }
    let mut length_m = 0.0;
    let mut from = 0;
    while from + 1 < points.len() {
        let to = (from + 1..points.len())
            .rev()
            .find(|&to| geometry.segment_is_clear(grid, points[from], points[to]))
            .unwrap_or(from + 1);
        length_m += distance_m(points[from], points[to]);
        from = to;
    }
    length_m
}

fn distance_m(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod tests {
    use hopnav_mapper::inflation::inflation_kernel;

    use super::*;

    fn geometry() -> MapGeometry {
        MapGeometry::new(-10.0, -10.0, 0.5, 40, 40).unwrap()
    }

    /// The full-knowledge path on the test grid, with the first mapper's 0.5 m kernel.
    fn plan(
        rocks: &[RockFootprint],
        slopes: &[SlopeClass],
        start_m: [f64; 2],
        goal_m: [f64; 2],
    ) -> Option<FullKnowledgePath> {
        let kernel = inflation_kernel(0.5, 1.0, 0.75, 2000);
        full_knowledge_path(rocks, 0.15, slopes, &geometry(), &kernel, start_m, goal_m)
    }

    #[test]
    fn an_empty_field_is_crossed_in_a_straight_line() {
        let path = plan(&[], &[], [-8.0, 0.3], [8.0, 1.9]).unwrap();
        let straight_m = 16.0f64.hypot(1.6);
        assert!((path.length_m - straight_m).abs() < 1e-9, "{path:?}");
        assert_eq!(path.obstacle_cells, 0);
    }

    #[test]
    fn ground_too_steep_is_driven_around_and_steep_ground_costs() {
        // A too-steep band across y from -6 to 6 at x = 0 (one cell wide): the way round is
        // past y = ±6. The same band merely steep is driven across.
        let band = |class: SlopeClass| -> Vec<SlopeClass> {
            (0..40 * 40)
                .map(|index| {
                    let (x, y) = (index % 40, index / 40);
                    if x == 20 && (8..32).contains(&y) {
                        class
                    } else {
                        SlopeClass::Level
                    }
                })
                .collect()
        };
        let too_steep = band(SlopeClass::TooSteep);
        let path = plan(&[], &too_steep, [-8.0, 0.0], [8.0, 0.0]).unwrap();
        assert!(path.length_m > 2.0 * 8.0f64.hypot(6.0), "{path:?}");
        let steep = band(SlopeClass::Steep);
        let path = plan(&[], &steep, [-8.0, 0.0], [8.0, 0.0]).unwrap();
        assert!((path.length_m - 16.0).abs() < 1e-9, "{path:?}");
    }

    #[test]
    fn a_wall_of_tall_rocks_is_driven_around_and_low_rocks_are_ignored() {
        // A wall across y from -6 to 6 at x = 0; the way round is past y = ±6.
        let wall: Vec<RockFootprint> = (0..=24)
            .map(|i| RockFootprint::at(0.0, -6.0 + 0.5 * f64::from(i), 0.3, 0.4))
            .collect();
        let path = plan(&wall, &[], [-8.0, 0.0], [8.0, 0.0]).unwrap();
        assert!(path.length_m > 2.0 * 8.0f64.hypot(6.0), "{path:?}");
        assert!(path.obstacle_cells > 25);
        let low: Vec<RockFootprint> = wall
            .iter()
            .map(|r| RockFootprint::at(r.center_m[0], r.center_m[1], 0.3, 0.1))
            .collect();
        let flat = plan(&low, &[], [-8.0, 0.0], [8.0, 0.0]).unwrap();
        assert!((flat.length_m - 16.0).abs() < 1e-9, "{flat:?}");
    }

    #[test]
    fn a_gap_closed_only_by_lethal_margins_is_planned_through() {
        // A wall across the whole grid at x = 0 with a 1 m gap at y = 0: the rocks leave the
        // gap open, their lethal margins close it.
        let wall: Vec<RockFootprint> = (0..=40)
            .map(|i| -10.0 + 0.5 * f64::from(i))
            .filter(|y_m: &f64| y_m.abs() > 0.9)
            .map(|y_m| RockFootprint::at(0.25, y_m, 0.2, 0.4))
            .collect();
        let path = plan(&wall, &[], [-8.0, 0.25], [8.0, 0.25]).unwrap();
        assert!((path.length_m - 16.0).abs() < 1e-9, "{path:?}");
    }

    #[test]
    fn a_goal_walled_in_has_no_full_knowledge_path() {
        let ring: Vec<RockFootprint> = (0..64)
            .map(|i| {
                let angle = f64::from(i) * std::f64::consts::TAU / 64.0;
                RockFootprint::at(5.0 + 3.0 * angle.cos(), 3.0 * angle.sin(), 0.3, 0.5)
            })
            .collect();
        assert_eq!(plan(&ring, &[], [-8.0, 0.0], [5.0, 0.0]), None);
        assert_eq!(
            plan(&[], &[], [-80.0, 0.0], [5.0, 0.0]),
            None,
            "A outside the grid"
        );
    }
    #[test]
    fn a_built_map_is_planned_around_its_obstacles_and_through_doubts_only_when_it_must() {
        let geometry = geometry();
        let free = KnownCell::Free { extra_cost: 0 };
        let wall_at = |x_cell: u32, gap: KnownCell| -> Vec<KnownCell> {
            (0..40 * 40)
                .map(|index| match (index % 40, index / 40) {
                    (x, 20) if x == x_cell => gap,
                    (x, _) if x == x_cell => KnownCell::Obstacle,
                    _ => free,
                })
                .collect()
        };
        // A full-height wall at x = 0 m (column 20) with one free cell in row 20: through it.
        let open =
            plan_on_known_map(&wall_at(20, free), &geometry, [-8.0, 0.25], [8.0, 0.25]).unwrap();
        assert!((open.length_m - 16.0).abs() < 1e-9, "{open:?}");
        // The same gap as a doubtful cell is still the only way: planned through.
        let doubt = wall_at(20, KnownCell::Doubtful);
        let through = plan_on_known_map(&doubt, &geometry, [-8.0, 0.25], [8.0, 0.25]).unwrap();
        assert!((through.length_m - 16.0).abs() < 1e-9, "{through:?}");
        // A closed wall has no way; a map of the wrong size is refused.
        let closed = wall_at(20, KnownCell::Obstacle);
        assert_eq!(
            plan_on_known_map(&closed, &geometry, [-8.0, 0.25], [8.0, 0.25]),
            None
        );
        assert_eq!(
            plan_on_known_map(&closed[1..], &geometry, [-8.0, 0.25], [8.0, 0.25]),
            None
        );
    }

    #[test]
    fn a_doubtful_cell_is_avoided_while_a_way_round_exists() {
        let geometry = geometry();
        // A doubtful block across y from -3 to 3 m at x = 0 m: driven round, not through.
        let cells: Vec<KnownCell> = (0..40 * 40)
            .map(|index| match (index % 40, index / 40) {
                (20, y) if (14..26).contains(&y) => KnownCell::Doubtful,
                _ => KnownCell::Free { extra_cost: 0 },
            })
            .collect();
        let path = plan_on_known_map(&cells, &geometry, [-8.0, 0.25], [8.0, 0.25]).unwrap();
        assert!(path.length_m > 2.0 * 8.0f64.hypot(3.0) - 0.5, "{path:?}");
    }
}
