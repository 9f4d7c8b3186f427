//! Follows the D* Lite path to the goal: applies the mapper's changes, moves the search start
//! with the rover, replans, picks a waypoint, and asks the jumper to scout.

use super::bumper::{Bumper, BumperEvent, RoverPose};
use super::config::NavigatorConfig;
use super::geometry::MapGeometry;
use super::route_change::route_moved;
use super::scout::{self, ScoutDecision, distance_m};
use super::scout_batch::{SCOUT_BATCH_URGENT_AHEAD_M, ScoutBatch};
use crate::cost::{Cost, path_cost};
use crate::grid::{Cell, CellChange, CellState, Grid};
use crate::{DStarLite, PlanError};

#[path = "navigator_bumps.rs"]
mod bumps;
#[path = "navigator_changes.rs"]
mod changes;
#[path = "navigator_doubts.rs"]
mod doubts;
#[path = "navigator_pursuit.rs"]
mod pursuit;

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
    /// Back up rear first toward the waypoint (getting away from something the rover hit;
    /// false for the nose-first escape after failed back-offs).
    pub reverse: bool,
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
    /// Replans after which the rover follows a different way (see [`route_moved`]), not
    /// only a re-priced one.
    pub route_changes: u64,
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
    /// Times the bump marks were forgotten because they alone cut the rover off the goal.
    pub bump_marks_forgotten: u32,
    /// Times the rover tilted beyond `max_safe_tilt_rad` and backed off.
    pub tilt_stops: u32,
    /// Doubtful obstacles (see [`MapChange`]) cut the rover off the goal once, and are planned
    /// through at a high cost since.
    pub doubts_relaxed: bool,
}

/// A map change as the mapper reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapChange {
    /// The cell's new state.
    pub change: CellChange,
    /// An obstacle the rover has not confirmed: a rock seen only from the jumper's distant
    /// viewpoint, or the lethal margin around a rock. When such cells alone cut the rover off
    /// the goal, the navigator plans through them at a high cost and lets the rover look.
    pub doubtful: bool,
    /// The cell's state comes from the jumper alone. A hop's clouds arrive keyframe by
    /// keyframe over its flight; the navigator takes them as one batch once they stop coming
    /// (see [`ScoutBatch`]), so one hop changes the route once, not at every keyframe.
    pub scouted: bool,
    /// The mapper calls the cell a rock (not a lethal margin): the rover's body must not
    /// touch it (see `NavigatorConfig::footprint_check`).
    pub rock: bool,
}

impl From<CellChange> for MapChange {
    fn from(change: CellChange) -> Self {
        Self {
            change,
            doubtful: false,
            scouted: false,
            rock: change.state == CellState::Obstacle,
        }
    }
}

/// A cell the rover bumped into, and what the mapper says of it meanwhile.
#[derive(Debug, Clone, Copy, PartialEq)]
struct BumpedCell {
    cell: Cell,
    mapper: CellChange,
}

/// Extra cost of a goal cell the map calls an obstacle (see `keep_goal_open`), planner units.
const GOAL_IN_OBSTACLE_EXTRA_COST: u32 = 5000;

/// Cost of moving into a doubtful obstacle cell once the goal is unreachable without them,
/// planner units (1000 = one cell): the rover detours up to 100 cells (50 m) to avoid one, so
/// relaxed cells elsewhere on the map are used only where nothing else leads on (at 8 cells,
/// routes squeezed through lethal margins between rocks and hit them).
pub const DOUBTFUL_OBSTACLE_COST: u32 = 100_000;

/// On steep ground, the rover stops again only once this much steeper, radians (2°).
const TILT_STOP_MARGIN_RAD: f64 = 0.035;

/// The rover's navigator.
pub struct Navigator {
    geometry: MapGeometry,
    config: NavigatorConfig,
    goal_m: [f64; 2],
    planner: DStarLite,
    path: Vec<Cell>,
    pending: Vec<CellChange>,
    /// Jumper-only changes held back until the hop's clouds stop coming.
    scouted: ScoutBatch,
    counters: NavigatorCounters,
    last_request_s: f64,
    /// The last route followed before the current path (a reused buffer).
    previous_path: Vec<Cell>,
    /// Map changes invalidated the path since it was last extracted: compare the next one.
    route_check_pending: bool,
    /// Stall detection and backing off.
    bumper: Bumper,
    /// The last decision drove forward (the bumper only judges commanded motion).
    driving: bool,
    /// Cells the rover bumped into: obstacles whatever the mapper says later, unless they
    /// alone cut the rover off the goal.
    bumped: Vec<BumpedCell>,
    /// Per cell (row-major): the cell is in `bumped` (a lookup the footprint sweep makes for
    /// every cell it touches, every frame).
    is_bumped: Vec<bool>,
    /// Per cell (row-major): the mapper's obstacle there is doubtful (see [`MapChange`]).
    doubtful: Vec<bool>,
    /// Cells the mapper calls rocks (or the rover bumped into), for the footprint sweep.
    rock: Vec<bool>,
    /// Doubtful obstacles are planned through at [`DOUBTFUL_OBSTACLE_COST`]: set once they
    /// alone made the goal unreachable, for the rest of the mission.
    doubts_relaxed: bool,
    /// The rover's tilt from vertical, radians (see [`Navigator::set_rover_tilt`]).
    rover_tilt_rad: f64,
    /// Tilt beyond which the rover stops: `max_safe_tilt_rad`, or a little more than the
    /// tilt of the last stop (or of the start) while the rover stays on steeper ground.
    tilt_floor_rad: Option<f64>,
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
        let grid = Grid::filled(
            geometry.width_cells(),
            geometry.height_cells(),
            CellState::Unknown,
            config.unknown_extra_cost,
        )
        .map_err(|error| NavigationError::Plan(PlanError::OutOfBounds(error)))?;
        let planner = DStarLite::new(grid, start, goal).map_err(NavigationError::Plan)?;
        let bumper = Bumper::new(&config);
        let cell_count = geometry.width_cells() as usize * geometry.height_cells() as usize;
        Ok(Self {
            geometry,
            config,
            goal_m,
            planner,
            path: Vec::with_capacity(cell_count.min(1 << 16)),
            pending: Vec::with_capacity(1024),
            scouted: ScoutBatch::default(),
            counters: NavigatorCounters::default(),
            last_request_s: 0.0,
            previous_path: Vec::with_capacity(cell_count.min(1 << 16)),
            route_check_pending: false,
            bumper,
            driving: false,
            bumped: Vec::new(),
            is_bumped: vec![false; cell_count],
            doubtful: vec![false; cell_count],
            rock: vec![false; cell_count],
            doubts_relaxed: false,
            rover_tilt_rad: 0.0,
            tilt_floor_rad: None,
        })
    }

    /// The rover's tilt from vertical for the next [`step`](Self::step), radians (0 until
    /// set; non-finite values are ignored).
    pub fn set_rover_tilt(&mut self, tilt_rad: f64) {
        if tilt_rad.is_finite() {
            self.rover_tilt_rad = tilt_rad.abs();
        }
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

    /// One planning cycle at `time_s` with the rover at `rover` and, if known, the jumper at
    /// `jumper_m`.
    pub fn step(
        &mut self,
        rover: RoverPose,
        jumper_m: Option<[f64; 2]>,
        time_s: f64,
    ) -> Result<Decision, NavigationError> {
        let rover_m = rover.xy_m;
        let rover_cell =
            self.geometry
                .nearest_cell(rover_m)
                .ok_or(NavigationError::OutsideMap {
                    what: "rover position",
                    x_m: rover_m[0],
                    y_m: rover_m[1],
                })?;
        self.take_settled_scouting(rover_m, time_s);
        if distance_m(rover_m, self.goal_m) <= self.config.goal_tolerance_m {
            let replanned = self.apply_pending()?;
            return Ok(self.hold(rover_m, MissionStatus::GoalReached, replanned));
        }
        self.watch_tilt_and_bumper(rover, rover_cell, time_s);
        let replanned = self.apply_pending()?;
        self.route_check_pending |= replanned;
        if let Some(back_off) = self.back_off(replanned) {
            return Ok(back_off);
        }
        let Some(start_cell) = self.plan_start(rover_cell, rover_m)? else {
            return Ok(self.hold(rover_m, MissionStatus::Unreachable, replanned));
        };
        if !self.replan_from(start_cell)? {
            return Ok(self.hold(rover_m, MissionStatus::Unreachable, replanned));
        }
        self.follow_new_path();
        Ok(self.drive(rover_m, jumper_m, time_s, replanned))
    }

    /// Queues the scouted cells that have settled, those on the path just ahead first.
    fn take_settled_scouting(&mut self, rover_m: [f64; 2], time_s: f64) {
        let ahead_len = self.path_cells_within(rover_m, SCOUT_BATCH_URGENT_AHEAD_M);
        for change in self
            .scouted
            .take_if_settled(time_s, &self.path[..ahead_len])
        {
            self.take_change(change);
        }
    }

    /// Stops on a slope getting too steep, and feeds the bumper; a stuck rover marks the
    /// obstacle ahead.
    fn watch_tilt_and_bumper(&mut self, rover: RoverPose, rover_cell: Cell, time_s: f64) {
        let tilt_rad = self.rover_tilt_rad;
        let safe_rad = self.config.max_safe_tilt_rad;
        // Already on a slope steeper than safe (started there, or came back): only getting
        // steeper still stops the rover, else backing off could take it onto a steeper part.
        let floor_rad = *self
            .tilt_floor_rad
            .get_or_insert(safe_rad.max(tilt_rad + TILT_STOP_MARGIN_RAD));
        if tilt_rad < safe_rad {
            self.tilt_floor_rad = Some(safe_rad);
        }
        let too_steep =
            self.driving && tilt_rad > floor_rad && self.bumper.back_off_waypoint().is_none();
        let event = if too_steep {
            self.counters.tilt_stops += 1;
            self.tilt_floor_rad = Some(tilt_rad + TILT_STOP_MARGIN_RAD);
            self.bumper.tilted(rover, time_s)
        } else {
            self.bumper.observe(rover, time_s, self.driving)
        };
        if let BumperEvent::Stuck {
            obstacle_m,
            bearing_rad,
        } = event
        {
            let facing = RoverPose {
                xy_m: rover.xy_m,
                yaw_rad: bearing_rad,
            };
            self.mark_bumped_ahead(facing, obstacle_m, rover_cell);
        }
    }

    /// The bumper's back-off move, while it has one.
    fn back_off(&mut self, replanned: bool) -> Option<Decision> {
        let waypoint_m = self.bumper.back_off_waypoint()?;
        self.driving = false;
        Some(Decision {
            waypoint_m,
            speed_mps: 0.5 * self.config.cruise_speed_mps,
            hold: false,
            reverse: !self.bumper.backing_off_forward(),
            scout: None,
            status: MissionStatus::Driving,
            replanned,
        })
    }

    /// The cell to plan from (`None`: walled in even without the guesses).
    fn plan_start(
        &mut self,
        rover_cell: Cell,
        rover_m: [f64; 2],
    ) -> Result<Option<Cell>, NavigationError> {
        // Mapping noise or a cut corner can put the rover in an obstacle cell: plan from the
        // nearest traversable cell instead (an obstacle start would have no way out).
        let mut start = self.nearest_traversable(rover_cell, rover_m);
        // Walled in by marks and doubtful cells (a rover backing around in a crater): they
        // are guesses; drop them before giving up.
        if start.is_none() && (self.forget_bump_marks()? | self.relax_doubts()?) {
            start = self.nearest_traversable(rover_cell, rover_m);
        }
        Ok(start)
    }

    /// Plans from `start_cell`, dropping bump marks, then doubts, if the goal is unreachable
    /// with them; false if it stays unreachable (the path is then retired).
    fn replan_from(&mut self, start_cell: Cell) -> Result<bool, NavigationError> {
        if start_cell != self.planner.start() {
            self.planner
                .move_start(start_cell)
                .map_err(NavigationError::Plan)?;
        }
        let mut search = self.planner.compute_shortest_path();
        if search == Err(PlanError::Unreachable) && self.forget_bump_marks()? {
            search = self.planner.compute_shortest_path();
        }
        if search == Err(PlanError::Unreachable) && self.relax_doubts()? {
            search = self.planner.compute_shortest_path();
        }
        match search {
            Ok(stats) => {
                self.counters.total_expansions += stats.expansions;
                self.counters.last_expansions = stats.expansions;
                self.counters.path_cost = stats.cost;
                Ok(true)
            }
            Err(PlanError::Unreachable) => {
                self.retire_path();
                self.counters.path_cost = 0;
                Ok(false)
            }
            Err(error) => Err(NavigationError::Plan(error)),
        }
    }

    /// Takes the planner's path as the one to follow, counting a route change if a replan
    /// moved it.
    fn follow_new_path(&mut self) {
        self.retire_path();
        if let Some(path) = self.planner.path() {
            self.path.extend(path);
        }
        if std::mem::take(&mut self.route_check_pending)
            && route_moved(&self.previous_path, &self.path)
        {
            self.counters.route_changes += 1;
        }
    }

    /// Drives along the path at cruise speed, with the jumper's next scouting target.
    fn drive(
        &mut self,
        rover_m: [f64; 2],
        jumper_m: Option<[f64; 2]>,
        time_s: f64,
        replanned: bool,
    ) -> Decision {
        let waypoint_m = self.waypoint(rover_m);
        let scout = self.scout(rover_m, jumper_m, time_s);
        self.driving = true;
        Decision {
            waypoint_m,
            speed_mps: self.config.cruise_speed_mps,
            hold: false,
            reverse: false,
            scout,
            status: MissionStatus::Driving,
            replanned,
        }
    }

    /// Empties the path, keeping it as the last route followed unless it was empty already
    /// (an unreachable spell: the next route is compared with the one before it).
    fn retire_path(&mut self) {
        if !self.path.is_empty() {
            std::mem::swap(&mut self.path, &mut self.previous_path);
        }
        self.path.clear();
    }

    /// The cost of the rest of the path without the unknown premium: ground found free where
    /// the path expected free ground leaves the path as it was.
    fn remaining_path_cost(&self) -> Option<Cost> {
        let grid = self.planner.grid();
        if self.config.unknown_extra_cost == 0 {
            return path_cost(grid, &self.path);
        }
        let unknown_entered = self
            .path
            .iter()
            .skip(1)
            .filter(|&&cell| grid.state(cell) == Some(CellState::Unknown))
            .count() as Cost;
        path_cost(grid, &self.path).map(|cost| {
            cost.saturating_sub(unknown_entered * Cost::from(self.config.unknown_extra_cost))
        })
    }

    fn hold(&mut self, rover_m: [f64; 2], status: MissionStatus, replanned: bool) -> Decision {
        self.driving = false;
        Decision {
            waypoint_m: rover_m,
            speed_mps: 0.0,
            hold: true,
            reverse: false,
            scout: None,
            status,
            replanned,
        }
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
#[path = "navigator_tests.rs"]
mod tests;
