//! A hop's jumper-only map changes, held until its keyframe clouds stop coming, so that one hop
//! changes the route once rather than at every keyframe.

use std::collections::BTreeMap;

use super::navigator::MapChange;
use crate::grid::{Cell, CellState};

/// A batch of cells only the jumper saw is taken once no more have come for this long, seconds
/// (keyframe clouds of a flying hop come a few frames apart).
pub const SCOUT_BATCH_QUIET_S: f64 = 1.0;

/// … or once the batch is this old, seconds (a hop flies for about 4.7 s).
pub const SCOUT_BATCH_MAX_AGE_S: f64 = 8.0;

/// A held cell that costs more than free ground this far along the path ahead of the rover,
/// metres, releases the batch at once: at cruise speed the rover would be into it before the
/// batch settles (0.5 m/s × up to 8 s).
pub const SCOUT_BATCH_URGENT_AHEAD_M: f64 = 4.0;

/// Jumper-only changes held back, the latest per cell.
#[derive(Debug, Default)]
pub(super) struct ScoutBatch {
    /// Keyed (row, column): taken in that order, so replays plan alike.
    held: BTreeMap<(u32, u32), MapChange>,
    /// When the held batch began, seconds (set by the first `take_if_settled` that sees it).
    since_s: Option<f64>,
    /// When it last grew, seconds.
    last_s: f64,
    /// It grew since the last `take_if_settled`.
    grew: bool,
}

impl ScoutBatch {
    /// Holds `change`, replacing what was held for its cell (the mapper sends a cell's whole
    /// state).
    pub(super) fn hold(&mut self, change: MapChange) {
        let cell = change.change.cell;
        self.held.insert((cell.y, cell.x), change);
        self.grew = true;
    }

    /// Drops what is held for `cell` (the rover's own word on it supersedes the jumper's).
    pub(super) fn forget(&mut self, cell: Cell) {
        self.held.remove(&(cell.y, cell.x));
    }

    /// At `time_s`: the whole batch, row by row, once no change has come for
    /// [`SCOUT_BATCH_QUIET_S`] or the batch is [`SCOUT_BATCH_MAX_AGE_S`] old, or at once when
    /// a held cell would close or raise the cost of `path_ahead` (the next
    /// [`SCOUT_BATCH_URGENT_AHEAD_M`] of the rover's path); else nothing.
    pub(super) fn take_if_settled(&mut self, time_s: f64, path_ahead: &[Cell]) -> Vec<MapChange> {
        if self.held.is_empty() {
            self.since_s = None;
            return Vec::new();
        }
        let since_s = *self.since_s.get_or_insert(time_s);
        if std::mem::take(&mut self.grew) {
            self.last_s = time_s;
        }
        let quiet = time_s - self.last_s >= SCOUT_BATCH_QUIET_S;
        let old = time_s - since_s >= SCOUT_BATCH_MAX_AGE_S;
        if !(quiet || old || self.blocks(path_ahead)) {
            return Vec::new();
        }
        self.since_s = None;
        std::mem::take(&mut self.held).into_values().collect()
    }

    /// A held cell on `path` is an obstacle or costs extra.
    fn blocks(&self, path: &[Cell]) -> bool {
        path.iter().any(|cell| {
            self.held.get(&(cell.y, cell.x)).is_some_and(|held| {
                held.change.state == CellState::Obstacle || held.change.extra_cost > 0
            })
        })
    }
}
