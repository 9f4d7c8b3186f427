//! The mapper's changes into the navigator: queued per cell (a scouted cell held until the
//! rover's look supersedes it), doubtful obstacles relaxed, the goal kept open, and applied to
//! D* Lite once per step.

use super::{GOAL_IN_OBSTACLE_EXTRA_COST, MapChange, NavigationError, Navigator};
use crate::grid::{Cell, CellChange, CellState};

impl Navigator {
    /// Queues map changes for the next [`step`](Self::step). Cells outside the grid are
    /// refused (the count of refused changes is returned) and never reach the planner.
    pub fn queue_changes(
        &mut self,
        changes: impl IntoIterator<Item = impl Into<MapChange>>,
    ) -> usize {
        let mut refused = 0;
        for change in changes {
            let change: MapChange = change.into();
            if self.cell_index(change.change.cell).is_none() {
                refused += 1;
                continue;
            }
            // The mapper sends a cell's whole state: the latest word on a cell wins, and a
            // rover observation supersedes a held jumper one.
            if change.scouted {
                self.scouted.hold(change);
            } else {
                self.scouted.forget(change.change.cell);
                self.take_change(change);
            }
        }
        refused
    }

    /// Queues one in-grid change for the planner.
    pub(super) fn take_change(&mut self, change: MapChange) {
        let MapChange {
            change,
            doubtful,
            rock,
            ..
        } = change;
        let Some(index) = self.cell_index(change.cell) else {
            return;
        };
        self.doubtful[index] = doubtful && change.state == CellState::Obstacle;
        self.rock[index] = rock && change.state == CellState::Obstacle;
        let change = self.relax_if_doubtful(change);
        let change = if change.state == CellState::Unknown {
            CellChange::new(
                change.cell,
                CellState::Unknown,
                self.config.unknown_extra_cost,
            )
        } else {
            change
        };
        if self.is_bumped[index]
            && let Some(bumped) = self.bumped.iter_mut().find(|b| b.cell == change.cell)
        {
            bumped.mapper = change;
            return;
        }
        self.pending.push(self.keep_goal_open(change));
    }

    pub(super) fn cell_index(&self, cell: Cell) -> Option<usize> {
        self.planner
            .grid()
            .contains(cell)
            .then(|| cell.y as usize * self.geometry.width_cells() as usize + cell.x as usize)
    }

    /// The goal cell stays traversable, at the highest cost, whatever the map says: a false
    /// obstacle next to the goal would otherwise make the whole mission unreachable, and the
    /// goal counts as reached within `goal_tolerance_m` (the bumper still stops the rover at a
    /// real rock).
    pub(super) fn keep_goal_open(&self, change: CellChange) -> CellChange {
        if change.cell == self.planner.goal() && change.state == CellState::Obstacle {
            CellChange::new(change.cell, CellState::Free, GOAL_IN_OBSTACLE_EXTRA_COST)
        } else {
            change
        }
    }

    /// Applies queued changes; true when they changed the cost of the path being followed.
    pub(super) fn apply_pending(&mut self) -> Result<bool, NavigationError> {
        if self.pending.is_empty() {
            return Ok(false);
        }
        let before = self.remaining_path_cost();
        let changed = self
            .planner
            .update_cells(&self.pending)
            .map_err(NavigationError::Plan)?;
        self.pending.clear();
        if changed == 0 || self.path.is_empty() {
            return Ok(false);
        }
        let invalidated = before != self.remaining_path_cost();
        if invalidated {
            self.counters.replans += 1;
        }
        Ok(invalidated)
    }
}
