//! Where the rover drives next: the pure-pursuit waypoint its body reaches clear of rocks,
//! and the traversable cell it plans from when mapping noise puts it in an obstacle cell.

use super::super::scout::distance_m;
use super::Navigator;
use crate::grid::Cell;

impl Navigator {
    /// Pure pursuit: the first path point at least `lookahead_m` from the rover, or a nearer
    /// one, such that the straight drive from the rover's actual position to it crosses no
    /// obstacle cell (a segment from the cell centre could cut a corner the rover then hits)
    /// and, with `footprint_check`, sweeps the body past no rock; the goal itself at the end
    /// of the path.
    pub(super) fn waypoint(&self, rover_m: [f64; 2]) -> [f64; 2] {
        let ahead = self.path.iter().position(|&cell| {
            distance_m(self.geometry.center_of(cell), rover_m) >= self.config.lookahead_m
        });
        let Some(index) = ahead else {
            return self.goal_m;
        };
        let candidates = || {
            (1..=index)
                .rev()
                .map(|candidate| self.geometry.center_of(self.path[candidate]))
                .filter(|&target_m| {
                    self.geometry
                        .segment_is_clear(self.planner.grid(), rover_m, target_m)
                })
        };
        // The farthest waypoint the body reaches clear of every rock; when none (the rover
        // already brushes one, or the path squeezes past it), the farthest the centre reaches,
        // as without the sweep: a rover that waited for a clear footprint would never move.
        candidates()
            .find(|&target_m| self.footprint_fits(rover_m, target_m))
            .or_else(|| candidates().next())
            .unwrap_or_else(|| self.geometry.center_of(self.path[0]))
    }

    /// The rover's body, driven straight from `from_m` to `to_m`, touches no rock cell (always
    /// true with `footprint_check` off).
    pub(super) fn footprint_fits(&self, from_m: [f64; 2], to_m: [f64; 2]) -> bool {
        if !self.config.footprint_check {
            return true;
        }
        let body = &self.config.rover_body;
        let half_extents_m = [
            0.5 * body.footprint_length_m(),
            0.5 * body.footprint_width_m(),
        ];
        self.geometry
            .footprint_is_clear(from_m, to_m, half_extents_m, |cell| {
                self.cell_index(cell)
                    .is_some_and(|index| self.rock[index] || self.is_bumped[index])
            })
    }

    /// How many cells of the path, from its start, lie within `range_m` of the rover.
    pub(super) fn path_cells_within(&self, rover_m: [f64; 2], range_m: f64) -> usize {
        self.path
            .iter()
            .position(|&cell| distance_m(self.geometry.center_of(cell), rover_m) > range_m)
            .unwrap_or(self.path.len())
    }

    /// `cell` if traversable, else the traversable cell within three rings whose centre is
    /// nearest the rover's actual position.
    pub(super) fn nearest_traversable(&self, cell: Cell, rover_m: [f64; 2]) -> Option<Cell> {
        let grid = self.planner.grid();
        if grid.is_traversable(cell) {
            return Some(cell);
        }
        const MAX_RING: i64 = 3;
        for ring in 1..=MAX_RING {
            let mut best: Option<(f64, Cell)> = None;
            for dy in -ring..=ring {
                for dx in -ring..=ring {
                    if dx.abs().max(dy.abs()) != ring {
                        continue;
                    }
                    let (x, y) = (i64::from(cell.x) + dx, i64::from(cell.y) + dy);
                    if x < 0 || y < 0 || x > i64::from(u32::MAX) || y > i64::from(u32::MAX) {
                        continue;
                    }
                    let candidate = Cell::new(x as u32, y as u32);
                    if !(grid.contains(candidate) && grid.is_traversable(candidate)) {
                        continue;
                    }
                    let distance = distance_m(self.geometry.center_of(candidate), rover_m);
                    if best.is_none_or(|(best_m, _)| distance < best_m) {
                        best = Some((distance, candidate));
                    }
                }
            }
            if let Some((_, found)) = best {
                return Some(found);
            }
        }
        None
    }
}
