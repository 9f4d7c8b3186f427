//! Doubtful obstacles: the mapper's obstacles it is unsure of, planned through at a high
//! cost once the goal is unreachable without them.

use super::{DOUBTFUL_OBSTACLE_COST, NavigationError, Navigator};
use crate::grid::{Cell, CellChange, CellState};

impl Navigator {
    /// A doubtful obstacle as a costly free cell, once doubts are relaxed.
    pub(super) fn relax_if_doubtful(&self, change: CellChange) -> CellChange {
        let doubtful = self
            .cell_index(change.cell)
            .is_some_and(|index| self.doubtful[index]);
        if self.doubts_relaxed && doubtful {
            CellChange::new(change.cell, CellState::Free, DOUBTFUL_OBSTACLE_COST)
        } else {
            change
        }
    }

    /// When the goal is unreachable, doubtful obstacles may be what cuts the rover off: plan
    /// through them at a high cost from now on (the rover's own stereo confirms real rocks as
    /// it comes near, and the bumper stops it at one the map missed). True when the search is
    /// worth repeating.
    pub(super) fn relax_doubts(&mut self) -> Result<bool, NavigationError> {
        if self.doubts_relaxed || !self.doubtful.contains(&true) {
            return Ok(false);
        }
        self.doubts_relaxed = true;
        let width = self.geometry.width_cells() as usize;
        let relaxed: Vec<CellChange> = self
            .doubtful
            .iter()
            .enumerate()
            .filter(|(_, doubtful)| **doubtful)
            .map(|(index, _)| {
                let cell = Cell::new((index % width) as u32, (index / width) as u32);
                self.keep_goal_open(self.relax_if_doubtful(CellChange::new(
                    cell,
                    CellState::Obstacle,
                    0,
                )))
            })
            .filter(|change| !self.is_bumped_cell(change.cell))
            .collect();
        self.planner
            .update_cells(&relaxed)
            .map_err(NavigationError::Plan)?;
        self.counters.doubts_relaxed = true;
        Ok(true)
    }
}
