//! How well the mapper's obstacles match the world's rocks (evaluation only: the world is
//! regenerated from the config after the mission; nothing here reaches the robots).
//!
//! - An obstacle cell is **true** when a rock at least `min_rock_height_m` tall overlaps it
//!   (its footprint reaches within half a cell of the cell's square); otherwise it is a
//!   **false obstacle**, counted by who observed it. A false cell of the jumper's within
//!   [`MISPLACEMENT_REACH_M`] of a rock the rover cannot climb is counted again as
//!   **misplaced**: a real rock drawn off its place by the jumper's pose error, not invented.
//! - A rock the rover cannot climb (taller than `blocking_height_m`) near the rover's track
//!   is **found** when an obstacle cell lies within its footprint plus half a cell.
//!
//! ```
//! use hopnav_eval::map_accuracy::{ObstacleCell, RockFootprint, evaluate};
//! let rocks = [RockFootprint { center_m: [1.25, 1.25], radius_m: 0.3, height_m: 0.4 }];
//! let cells = [
//!     ObstacleCell { center_m: [1.25, 1.25], by_rover: true, by_jumper: false },
//!     ObstacleCell { center_m: [5.25, 5.25], by_rover: false, by_jumper: true },
//! ];
//! let accuracy = evaluate(&rocks, &cells, &[[0.0, 1.25], [3.0, 1.25]], 0.5, 0.1, 0.2);
//! assert_eq!((accuracy.true_obstacle_cells, accuracy.false_by_jumper), (1, 1));
//! assert_eq!((accuracy.blocking_rocks_near_track, accuracy.blocking_rocks_found), (1, 1));
//! ```

use serde::{Deserialize, Serialize};

/// Blocking rocks this close to the rover's true track count for recall, metres.
pub const TRACK_NEIGHBOURHOOD_M: f64 = 3.0;

/// A false jumper cell this close to an unclimbable rock's footprint counts as misplaced,
/// metres: about the jumper VO's world-frame error after a dozen hops (unaligned RMSE ≈ 2 m
/// in boulder fields), beyond which a rock is more likely invented than shifted.
pub const MISPLACEMENT_REACH_M: f64 = 2.5;

/// A rock as the evaluation needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockFootprint {
    /// Centre (x, y), world metres.
    pub center_m: [f64; 2],
    /// Horizontal bounding radius, metres.
    pub radius_m: f64,
    /// Height above its base, metres.
    pub height_m: f64,
}

#[cfg(test)]
impl RockFootprint {
    /// A rock centred on (`x_m`, `y_m`), for tests.
    pub(crate) fn at(x_m: f64, y_m: f64, radius_m: f64, height_m: f64) -> Self {
        Self {
            center_m: [x_m, y_m],
            radius_m,
            height_m,
        }
    }
}

/// An obstacle cell of the final map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObstacleCell {
    /// Cell centre (x, y), world metres.
    pub center_m: [f64; 2],
    /// The rover's cloud contributed to the cell.
    pub by_rover: bool,
    /// The jumper's cloud contributed to the cell.
    pub by_jumper: bool,
}

/// Obstacle precision and blocking-rock recall of one mission's map.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct MapAccuracy {
    /// Obstacle cells over a real rock.
    pub true_obstacle_cells: usize,
    /// Obstacle cells over no rock, seen by the rover only.
    pub false_by_rover: usize,
    /// … by the jumper only.
    pub false_by_jumper: usize,
    /// … by both.
    pub false_by_both: usize,
    /// Of `false_by_jumper`, cells within [`MISPLACEMENT_REACH_M`] of a rock the rover
    /// cannot climb: real rocks the jumper drew in the wrong place.
    #[serde(default)]
    pub false_by_jumper_misplaced: usize,
    /// Rocks the rover cannot climb within [`TRACK_NEIGHBOURHOOD_M`] of its true track.
    pub blocking_rocks_near_track: usize,
    /// Of them, covered by an obstacle cell.
    pub blocking_rocks_found: usize,
}

impl MapAccuracy {
    /// False obstacle cells, whoever saw them.
    pub fn false_obstacle_cells(&self) -> usize {
        self.false_by_rover + self.false_by_jumper + self.false_by_both
    }
}

/// Distance from `point_m` to the square of side `size_m` centred on `center_m` (0 inside),
/// metres.
pub(crate) fn distance_to_square_m(center_m: [f64; 2], size_m: f64, point_m: [f64; 2]) -> f64 {
    let half_m = 0.5 * size_m;
    let dx = ((point_m[0] - center_m[0]).abs() - half_m).max(0.0);
    let dy = ((point_m[1] - center_m[1]).abs() - half_m).max(0.0);
    dx.hypot(dy)
}

/// Scores `cells` against `rocks`. Rocks lower than `min_rock_height_m` do not make a cell
/// true; rocks taller than `blocking_height_m` are the ones recall counts.
pub fn evaluate(
    rocks: &[RockFootprint],
    cells: &[ObstacleCell],
    track_m: &[[f64; 2]],
    cell_size_m: f64,
    min_rock_height_m: f64,
    blocking_height_m: f64,
) -> MapAccuracy {
    let half_cell_m = 0.5 * cell_size_m;
    let to_square = |cell: &ObstacleCell, point: [f64; 2]| {
        distance_to_square_m(cell.center_m, cell_size_m, point)
    };
    let mut accuracy = MapAccuracy::default();
    for cell in cells {
        let over_rock = rocks.iter().any(|rock| {
            rock.height_m >= min_rock_height_m
                && to_square(cell, rock.center_m) <= rock.radius_m + half_cell_m
        });
        match (over_rock, cell.by_rover, cell.by_jumper) {
            (true, _, _) => accuracy.true_obstacle_cells += 1,
            (false, true, true) => accuracy.false_by_both += 1,
            (false, false, true) => {
                accuracy.false_by_jumper += 1;
                let beside_rock = rocks.iter().any(|rock| {
                    rock.height_m > blocking_height_m
                        && to_square(cell, rock.center_m) <= rock.radius_m + MISPLACEMENT_REACH_M
                });
                if beside_rock {
                    accuracy.false_by_jumper_misplaced += 1;
                }
            }
            (false, _, false) => accuracy.false_by_rover += 1,
        }
    }
    for rock in rocks
        .iter()
        .filter(|rock| rock.height_m > blocking_height_m)
    {
        let near_track = track_m.iter().any(|point| {
            (point[0] - rock.center_m[0]).hypot(point[1] - rock.center_m[1])
                <= TRACK_NEIGHBOURHOOD_M
        });
        if !near_track {
            continue;
        }
        accuracy.blocking_rocks_near_track += 1;
        if cells
            .iter()
            .any(|cell| to_square(cell, rock.center_m) <= rock.radius_m + half_cell_m)
        {
            accuracy.blocking_rocks_found += 1;
        }
    }
    accuracy
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(x_m: f64, y_m: f64, by_rover: bool, by_jumper: bool) -> ObstacleCell {
        ObstacleCell {
            center_m: [x_m, y_m],
            by_rover,
            by_jumper,
        }
    }

    #[test]
    fn cells_over_rocks_are_true_and_others_false_by_observer() {
        let rocks = [
            RockFootprint::at(2.0, 2.0, 0.4, 0.3),
            // Too low to make a cell true.
            RockFootprint::at(6.0, 6.0, 0.2, 0.05),
        ];
        let cells = [
            cell(2.25, 2.25, true, false),
            cell(2.75, 2.25, false, true),
            cell(6.25, 6.25, true, false),
            cell(9.25, 9.25, false, true),
            cell(9.75, 9.25, true, true),
        ];
        let accuracy = evaluate(&rocks, &cells, &[[2.0, 0.0]], 0.5, 0.1, 0.2);
        assert_eq!(accuracy.true_obstacle_cells, 2);
        assert_eq!(
            (
                accuracy.false_by_rover,
                accuracy.false_by_jumper,
                accuracy.false_by_both
            ),
            (1, 1, 1)
        );
        assert_eq!(accuracy.false_obstacle_cells(), 3);
        assert_eq!(accuracy.blocking_rocks_near_track, 1);
        assert_eq!(accuracy.blocking_rocks_found, 1);
    }

    #[test]
    fn a_false_jumper_cell_beside_an_unclimbable_rock_counts_as_misplaced() {
        let rocks = [
            RockFootprint::at(2.0, 2.0, 0.5, 0.8),
            // Climbable: a false cell beside it is not a shifted obstacle.
            RockFootprint::at(20.0, 2.0, 0.3, 0.15),
        ];
        let cells = [
            // 2 m beyond the rock's edge: shifted.
            cell(4.75, 2.25, false, true),
            // 6 m away: invented.
            cell(8.75, 2.25, false, true),
            cell(21.25, 2.25, false, true),
            // The rover's false cells are not the jumper's pose error.
            cell(4.75, 2.75, true, false),
        ];
        let accuracy = evaluate(&rocks, &cells, &[], 0.5, 0.1, 0.2);
        assert_eq!(accuracy.false_by_jumper, 3);
        assert_eq!(accuracy.false_by_jumper_misplaced, 1);
        assert_eq!(accuracy.false_by_rover, 1);
    }

    #[test]
    fn a_blocking_rock_far_from_the_track_does_not_count_and_a_missed_one_does() {
        let rocks = [
            RockFootprint::at(2.0, 2.0, 0.3, 0.3),
            RockFootprint::at(20.0, 20.0, 0.3, 0.3),
        ];
        let accuracy = evaluate(&rocks, &[], &[[2.0, 1.0]], 0.5, 0.1, 0.2);
        assert_eq!(accuracy.blocking_rocks_near_track, 1);
        assert_eq!(accuracy.blocking_rocks_found, 0);
    }
}
