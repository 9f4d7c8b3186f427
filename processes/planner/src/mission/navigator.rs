//! Follows the D* Lite path to the goal: applies the mapper's changes, moves the search start
//! with the rover, replans, picks a waypoint, and asks the jumper to scout.

use super::config::NavigatorConfig;
use super::geometry::MapGeometry;
use super::scout::{self, ScoutDecision, distance_m, line_of_sight};
use crate::cost::{Cost, path_cost};
use crate::grid::{Cell, CellChange, CellState, Grid};
use crate::{DStarLite, PlanError};

/// Why navigation could not go on.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NavigationError {
    /// The start or goal is outside the map or not finite.
    #[error("{what} ({x_m}, {y_m}) m lies outside the map")]
    OutsideMap {
        /// "start", "goal" or "rover position".
        what: &'static str,
        /// x, metres.
        x_m: f64,
        /// y, metres.
        y_m: f64,
    },
    /// The planner failed (not "unreachable", which is a mission status).
    #[error("planner: {0}")]
    Plan(PlanError),
}

/// Where the mission stands after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MissionStatus {
    /// A path is known; the rover follows it.
    Driving,
    /// The rover is within the goal tolerance.
    GoalReached,
    /// No path to the goal on the known map: the rover holds.
    Unreachable,
}

/// What the rover should do this frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Decision {
    /// Drive toward this point, world metres.
    pub waypoint_m: [f64; 2],
    /// Commanded speed, m/s (0 when holding).
    pub speed_mps: f64,
    /// Hold still.
    pub hold: bool,
    /// A hop to request from the jumper, if the cooperative rule fired.
    pub scout: Option<ScoutDecision>,
    /// Mission status.
    pub status: MissionStatus,
    /// True when map changes invalidated the current path and the planner replanned.
    pub replanned: bool,
}

/// Lifetime counters for the report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NavigatorCounters {
    /// Searches forced by map changes that altered the cost of the path being followed.
    pub replans: u64,
    /// Node expansions over all searches (the first plan included).
    pub total_expansions: u64,
    /// Node expansions of the last search.
    pub last_expansions: u64,
    /// Cost of the current path (planner units, 1000 per straight cell; 0 when none).
    pub path_cost: Cost,
    /// Hops requested from the jumper.
    pub scout_requests: u32,
    /// Times the rover was found blocked and the cell ahead marked as an obstacle.
    pub blocked_marks: u32,
}

/// Bumped cells remembered (a bounded list: a mission bumps a handful).
const MAX_BUMPED_CELLS: usize = 256;

/// The rover's navigator.
pub struct Navigator {
    geometry: MapGeometry,
    config: NavigatorConfig,
    goal_m: [f64; 2],
    planner: DStarLite,
    path: Vec<Cell>,
    pending: Vec<CellChange>,
    counters: NavigatorCounters,
    last_request_s: f64,
    /// Where and when the rover last made progress (stall detection).
    progress_anchor: Option<([f64; 2], f64)>,
    /// Cells the rover bumped into: obstacles whatever the mapper says later.
    bumped: Vec<Cell>,
}

impl Navigator {
    /// A navigator on an all-unknown map (planned through as free) from `start_m` to `goal_m`.
    pub fn new(
        geometry: MapGeometry,
        start_m: [f64; 2],
        goal_m: [f64; 2],
        config: NavigatorConfig,
    ) -> Result<Self, NavigationError> {
        let cell = |what, xy_m: [f64; 2]| {
            geometry.cell_of(xy_m).ok_or(NavigationError::OutsideMap {
                what,
                x_m: xy_m[0],
                y_m: xy_m[1],
            })
        };
        let start = cell("start", start_m)?;
        let goal = cell("goal", goal_m)?;
        let grid = Grid::new(
            geometry.width_cells(),
            geometry.height_cells(),
            CellState::Unknown,
        )
        .map_err(|error| NavigationError::Plan(PlanError::OutOfBounds(error)))?;
        let planner = DStarLite::new(grid, start, goal).map_err(NavigationError::Plan)?;
        let cell_count = geometry.width_cells() as usize * geometry.height_cells() as usize;
        Ok(Self {
            geometry,
            config,
            goal_m,
            planner,
            path: Vec::with_capacity(cell_count.min(1 << 16)),
            pending: Vec::with_capacity(1024),
            counters: NavigatorCounters::default(),
            last_request_s: 0.0,
            progress_anchor: None,
            bumped: Vec::new(),
        })
    }

    /// The grid placement.
    pub fn geometry(&self) -> &MapGeometry {
        &self.geometry
    }

    /// The known map.
    pub fn grid(&self) -> &Grid {
        self.planner.grid()
    }

    /// The path last planned, start first.
    pub fn path(&self) -> &[Cell] {
        &self.path
    }

    /// Lifetime counters.
    pub fn counters(&self) -> NavigatorCounters {
        self.counters
    }

    /// Queues map changes for the next [`step`](Self::step). Cells outside the grid are
    /// refused (the count of refused changes is returned) and never reach the planner.
    pub fn queue_changes(&mut self, changes: impl IntoIterator<Item = CellChange>) -> usize {
        let mut refused = 0;
        for change in changes {
            if self.bumped.contains(&change.cell) {
                continue;
            }
            if self.planner.grid().contains(change.cell) {
                self.pending.push(change);
            } else {
                refused += 1;
            }
        }
        refused
    }

    /// One planning cycle at `time_s` with the rover at `rover_m` and, if known, the jumper at
    /// `jumper_m`.
    pub fn step(
        &mut self,
        rover_m: [f64; 2],
        jumper_m: Option<[f64; 2]>,
        time_s: f64,
    ) -> Result<Decision, NavigationError> {
        let rover_cell =
            self.geometry
                .nearest_cell(rover_m)
                .ok_or(NavigationError::OutsideMap {
                    what: "rover position",
                    x_m: rover_m[0],
                    y_m: rover_m[1],
                })?;
        self.check_progress(rover_m, time_s);
        let replanned = self.apply_pending()?;
        if distance_m(rover_m, self.goal_m) <= self.config.goal_tolerance_m {
            return Ok(self.hold(rover_m, MissionStatus::GoalReached, replanned));
        }
        // Mapping noise or a cut corner can put the rover in an obstacle cell: plan from the
        // nearest traversable cell instead (an obstacle start would have no way out).
        let Some(start_cell) = self.nearest_traversable(rover_cell) else {
            return Ok(self.hold(rover_m, MissionStatus::Unreachable, replanned));
        };
        if start_cell != self.planner.start() {
            self.planner
                .move_start(start_cell)
                .map_err(NavigationError::Plan)?;
        }
        match self.planner.compute_shortest_path() {
            Ok(stats) => {
                self.counters.total_expansions += stats.expansions;
                self.counters.last_expansions = stats.expansions;
                self.counters.path_cost = stats.cost;
            }
            Err(PlanError::Unreachable) => {
                self.path.clear();
                self.counters.path_cost = 0;
                return Ok(self.hold(rover_m, MissionStatus::Unreachable, replanned));
            }
            Err(error) => return Err(NavigationError::Plan(error)),
        }
        self.path.clear();
        if let Some(path) = self.planner.path() {
            self.path.extend(path);
        }
        let waypoint_m = self.waypoint(rover_m);
        let scout = self.scout(rover_m, jumper_m, time_s);
        Ok(Decision {
            waypoint_m,
            speed_mps: self.config.cruise_speed_mps,
            hold: false,
            scout,
            status: MissionStatus::Driving,
            replanned,
        })
    }

    /// A rover that stopped making progress while driving is against something the map does
    /// not show (a rock its camera missed): mark the cell ahead, toward the last waypoint, as an
    /// obstacle so the next search goes around it.
    fn check_progress(&mut self, rover_m: [f64; 2], time_s: f64) {
        let Some((anchor_m, since_s)) = self.progress_anchor else {
            self.progress_anchor = Some((rover_m, time_s));
            return;
        };
        if distance_m(anchor_m, rover_m) > self.config.stall_distance_m {
            self.progress_anchor = Some((rover_m, time_s));
            return;
        }
        if time_s - since_s < self.config.stall_time_s {
            return;
        }
        self.progress_anchor = Some((rover_m, time_s));
        let Some(&next) = self.path.get(1) else {
            return;
        };
        let toward_m = self.geometry.center_of(next);
        let (dx, dy) = (toward_m[0] - rover_m[0], toward_m[1] - rover_m[1]);
        let length_m = dx.hypot(dy);
        if length_m < 1e-6 {
            return;
        }
        let reach_m = 0.6 * self.geometry.cell_size_m().max(0.5) / 0.5;
        let ahead_m = [
            rover_m[0] + dx / length_m * reach_m,
            rover_m[1] + dy / length_m * reach_m,
        ];
        if let Some(cell) = self.geometry.cell_of(ahead_m)
            && cell != self.planner.goal()
        {
            self.pending
                .push(CellChange::new(cell, CellState::Obstacle, 0));
            if self.bumped.len() < MAX_BUMPED_CELLS {
                self.bumped.push(cell);
            }
            self.counters.blocked_marks += 1;
        }
    }

    /// Applies queued changes; true when they changed the cost of the path being followed.
    fn apply_pending(&mut self) -> Result<bool, NavigationError> {
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

    fn remaining_path_cost(&self) -> Option<Cost> {
        path_cost(self.planner.grid(), &self.path)
    }

    fn hold(&self, rover_m: [f64; 2], status: MissionStatus, replanned: bool) -> Decision {
        Decision {
            waypoint_m: rover_m,
            speed_mps: 0.0,
            hold: true,
            scout: None,
            status,
            replanned,
        }
    }

    /// The first path point at least `lookahead_m` from the rover if the rover sees it past
    /// no obstacle (else the next path cell), or the goal itself at the end.
    fn waypoint(&self, rover_m: [f64; 2]) -> [f64; 2] {
        let grid = self.planner.grid();
        let ahead = self.path.iter().position(|&cell| {
            distance_m(self.geometry.center_of(cell), rover_m) >= self.config.lookahead_m
        });
        let Some(index) = ahead else {
            return self.goal_m;
        };
        let start = self.planner.start();
        if line_of_sight(grid, start, self.path[index]) {
            return self.geometry.center_of(self.path[index]);
        }
        let next = self.path.get(1).copied().unwrap_or(self.path[index]);
        self.geometry.center_of(next)
    }

    /// `cell` if traversable, else the nearest traversable cell within three rings.
    fn nearest_traversable(&self, cell: Cell) -> Option<Cell> {
        let grid = self.planner.grid();
        if grid.is_traversable(cell) {
            return Some(cell);
        }
        const MAX_RING: i64 = 3;
        for ring in 1..=MAX_RING {
            let mut best: Option<(i64, Cell)> = None;
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
                    let distance_sq = dx * dx + dy * dy;
                    if grid.contains(candidate)
                        && grid.is_traversable(candidate)
                        && best.is_none_or(|(best_sq, _)| distance_sq < best_sq)
                    {
                        best = Some((distance_sq, candidate));
                    }
                }
            }
            if let Some((_, found)) = best {
                return Some(found);
            }
        }
        None
    }

    fn scout(
        &mut self,
        rover_m: [f64; 2],
        jumper_m: Option<[f64; 2]>,
        time_s: f64,
    ) -> Option<ScoutDecision> {
        let config = &self.config.scout;
        if !config.enabled
            || self.counters.scout_requests >= config.max_requests
            || time_s - self.last_request_s < config.min_interval_s
        {
            return None;
        }
        let region_index = scout::find_region_of_interest(
            self.planner.grid(),
            &self.geometry,
            &self.path,
            rover_m,
            self.config.sensing_range_m,
        )?;
        let decision = scout::choose_target(
            &self.geometry,
            &self.path,
            region_index,
            jumper_m.unwrap_or(rover_m),
            config.hop_range_m,
            config.min_hop_m,
        )?;
        self.counters.scout_requests += 1;
        self.last_request_s = time_s;
        Some(decision)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives a point rover along the decisions; cells within `reveal_m` are revealed from
    /// `truth` each frame. Returns the last decision and the frames used.
    fn drive(
        navigator: &mut Navigator,
        truth: &Grid,
        start_m: [f64; 2],
        reveal_m: f64,
        max_frames: usize,
    ) -> (Decision, usize) {
        let geometry = *navigator.geometry();
        let mut rover_m = start_m;
        let step_m: f64 = 0.25;
        for frame in 0..max_frames {
            let mut changes = Vec::new();
            for index in 0..truth.cell_count() {
                let cell = truth.cell_at(index).unwrap();
                let centre_m = geometry.center_of(cell);
                if distance_m(centre_m, rover_m) <= reveal_m
                    && navigator.grid().state(cell) == Some(CellState::Unknown)
                {
                    changes.push(CellChange::new(cell, truth.state(cell).unwrap(), 0));
                }
            }
            navigator.queue_changes(changes);
            let decision = navigator.step(rover_m, None, frame as f64 * 0.1).unwrap();
            if decision.hold {
                return (decision, frame);
            }
            let [dx, dy] = [
                decision.waypoint_m[0] - rover_m[0],
                decision.waypoint_m[1] - rover_m[1],
            ];
            let length = dx.hypot(dy).max(1e-9);
            let advance = step_m.min(length);
            rover_m = [
                rover_m[0] + dx / length * advance,
                rover_m[1] + dy / length * advance,
            ];
        }
        panic!("no terminal decision in {max_frames} frames");
    }

    fn walled_world() -> (MapGeometry, Grid) {
        let geometry = MapGeometry::new(0.0, 0.0, 0.5, 60, 40).unwrap();
        let mut truth = Grid::new(60, 40, CellState::Free).unwrap();
        // A wall one cell thick across x = 15 m, open above y = 17 m.
        for y in 0..34 {
            truth
                .apply(&CellChange::new(Cell::new(30, y), CellState::Obstacle, 0))
                .unwrap();
        }
        (geometry, truth)
    }

    #[test]
    fn reaches_the_goal_around_a_thin_wall_it_discovers() {
        let (geometry, truth) = walled_world();
        let mut config = NavigatorConfig::default();
        config.scout.enabled = false;
        let mut navigator = Navigator::new(geometry, [2.0, 5.0], [28.0, 5.0], config).unwrap();
        let (decision, _) = drive(&mut navigator, &truth, [2.0, 5.0], 4.0, 2000);
        assert_eq!(decision.status, MissionStatus::GoalReached);
        assert!(navigator.counters().replans >= 1);
        assert!(navigator.counters().total_expansions > 0);
    }

    #[test]
    fn an_unreachable_goal_is_a_clear_status_not_a_hang() {
        let (geometry, mut truth) = walled_world();
        for y in 34..40 {
            truth
                .apply(&CellChange::new(Cell::new(30, y), CellState::Obstacle, 0))
                .unwrap();
        }
        let mut config = NavigatorConfig::default();
        config.scout.enabled = false;
        let mut navigator = Navigator::new(geometry, [2.0, 5.0], [28.0, 5.0], config).unwrap();
        let (decision, _) = drive(&mut navigator, &truth, [2.0, 5.0], 40.0, 2000);
        assert_eq!(decision.status, MissionStatus::Unreachable);
        assert_eq!(decision.speed_mps, 0.0);
    }

    #[test]
    fn start_at_the_goal_holds_at_once() {
        let geometry = MapGeometry::new(0.0, 0.0, 0.5, 20, 20).unwrap();
        let mut navigator =
            Navigator::new(geometry, [5.0, 5.0], [5.2, 5.0], NavigatorConfig::default()).unwrap();
        let decision = navigator.step([5.0, 5.0], None, 0.0).unwrap();
        assert_eq!(decision.status, MissionStatus::GoalReached);
        assert!(decision.hold);
    }

    #[test]
    fn asks_the_jumper_to_scout_beyond_sensing_range_once_per_interval() {
        let geometry = MapGeometry::new(0.0, 0.0, 0.5, 100, 20).unwrap();
        let mut navigator = Navigator::new(
            geometry,
            [1.0, 5.0],
            [48.0, 5.0],
            NavigatorConfig::default(),
        )
        .unwrap();
        // Nothing before the first interval: the jumper's own first hop is in the air.
        assert!(
            navigator
                .step([1.0, 5.0], None, 1.0)
                .unwrap()
                .scout
                .is_none()
        );
        let decision = navigator.step([1.0, 5.0], None, 10.0).unwrap();
        let scout = decision.scout.expect("a hop request");
        assert!((scout.target_m[0] - 20.75).abs() < 0.5, "{scout:?}");
        assert!(
            navigator
                .step([1.0, 5.0], None, 12.0)
                .unwrap()
                .scout
                .is_none()
        );
        assert_eq!(navigator.counters().scout_requests, 1);
    }

    #[test]
    fn outside_positions_are_errors_not_panics() {
        let geometry = MapGeometry::new(0.0, 0.0, 0.5, 20, 20).unwrap();
        assert!(
            Navigator::new(
                geometry,
                [-5.0, 5.0],
                [5.0, 5.0],
                NavigatorConfig::default()
            )
            .is_err()
        );
        let mut navigator =
            Navigator::new(geometry, [1.0, 1.0], [8.0, 8.0], NavigatorConfig::default()).unwrap();
        assert!(navigator.step([f64::NAN, 1.0], None, 0.0).is_err());
        assert_eq!(
            navigator.queue_changes([CellChange::new(Cell::new(99, 0), CellState::Obstacle, 0)]),
            1
        );
    }
}
