//! Bump marks: the cells the navigator marks as obstacles where the rover stalled against
//! something the map does not show, and how those marks are forgotten again.

use super::super::bumper::RoverPose;
use super::super::scout::distance_m;
use super::{BumpedCell, NavigationError, Navigator};
use crate::grid::{Cell, CellChange, CellState};

/// Bumped cells remembered (a bounded list: a mission bumps a handful of times, up to about
/// thirty cells each on a fine grid).
const MAX_BUMPED_CELLS: usize = 4096;

impl Navigator {
    /// The rover, facing `rover.yaw_rad` (its heading, or the way it reversed), is stuck
    /// against something at `obstacle_m` that way: marks that cell, or, when it is already
    /// marked (the rover stalled again facing the same way: the rock or slope is wider than a
    /// cell), the next unmarked cell to the left or right of it.
    pub(super) fn mark_bumped_ahead(
        &mut self,
        rover: RoverPose,
        obstacle_m: [f64; 2],
        rover_cell: Cell,
    ) {
        let reach_m = distance_m(rover.xy_m, obstacle_m);
        let candidates = [0.0, 0.6, -0.6, 1.1, -1.1].map(|turn_rad| {
            RoverPose {
                xy_m: rover.xy_m,
                yaw_rad: rover.yaw_rad + turn_rad,
            }
            .ahead_m(reach_m)
        });
        for candidate_m in candidates {
            if self.mark_bumped(candidate_m, rover_cell) {
                return;
            }
        }
    }

    /// The rover is stuck against something at `obstacle_m` the map does not show: mark its
    /// cell as an obstacle, and the ring of cells around it, so the next search keeps the
    /// rover's body clear of it as the mapper's lethal margin would (a path one cell over
    /// brushed the same rock again: the rover is 0.7 m wide). Never the goal or the rover's
    /// own cell. True when the centre cell was newly marked.
    pub(super) fn mark_bumped(&mut self, obstacle_m: [f64; 2], rover_cell: Cell) -> bool {
        let Some(centre) = self.geometry.cell_of(obstacle_m) else {
            return false;
        };
        if !self.mark_bumped_cell(centre, rover_cell) {
            return false;
        }
        let cell_size_m = self.geometry.cell_size_m();
        let reach = (self.config.bump_ring_m / cell_size_m).ceil() as i64;
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let within =
                    (dx as f64).hypot(dy as f64) * cell_size_m <= self.config.bump_ring_m + 1e-9;
                let (x, y) = (i64::from(centre.x) + dx, i64::from(centre.y) + dy);
                if (dx, dy) == (0, 0) || !within || x < 0 || y < 0 {
                    continue;
                }
                let cell = Cell::new(x as u32, y as u32);
                if self.planner.grid().index_of(cell).is_some() {
                    self.mark_bumped_cell(cell, rover_cell);
                }
            }
        }
        self.counters.blocked_marks += 1;
        true
    }

    /// Marks one cell as bumped (remembering the mapper's view of it, so that the mark can
    /// be forgotten); false for the goal, the rover's cell, a cell already marked, or when the
    /// list of bumped cells is full.
    pub(super) fn mark_bumped_cell(&mut self, cell: Cell, rover_cell: Cell) -> bool {
        if cell == self.planner.goal()
            || cell == rover_cell
            || self.bumped.len() >= MAX_BUMPED_CELLS
            || self.is_bumped_cell(cell)
        {
            return false;
        }
        let Some(index) = self.cell_index(cell) else {
            return false;
        };
        let grid = self.planner.grid();
        let mapper = CellChange::new(
            cell,
            grid.state(cell).unwrap_or(CellState::Unknown),
            grid.extra_cost(cell).unwrap_or(0),
        );
        self.pending
            .push(CellChange::new(cell, CellState::Obstacle, 0));
        self.bumped.push(BumpedCell { cell, mapper });
        self.is_bumped[index] = true;
        true
    }

    /// The cell carries a bump mark.
    pub(super) fn is_bumped_cell(&self, cell: Cell) -> bool {
        self.cell_index(cell)
            .is_some_and(|index| self.is_bumped[index])
    }

    /// When the goal is unreachable and bump marks exist, they may be what cuts the rover
    /// off (bumps are guesses from a stall): restore the mapper's view of those cells.
    /// True when marks were forgotten and the search is worth repeating.
    pub(super) fn forget_bump_marks(&mut self) -> Result<bool, NavigationError> {
        if self.bumped.is_empty() {
            return Ok(false);
        }
        let restore: Vec<CellChange> = self.bumped.drain(..).map(|bumped| bumped.mapper).collect();
        self.is_bumped.fill(false);
        self.planner
            .update_cells(&restore)
            .map_err(NavigationError::Plan)?;
        self.counters.bump_marks_forgotten += 1;
        Ok(true)
    }
}
