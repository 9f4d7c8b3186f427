//! The `planner` process: turns the mapper's changed cells and the rover's VO pose into drive
//! commands, the current path, and, in cooperative missions, jump requests for the jumper.
//!
//! The grid geometry comes from the map header (the mapper owns it); the goal from the world
//! scenario (`world.scenario.goal_m`); the start is the rover's first pose estimate. It never
//! reads ground truth.

use hopnav_config::{ConfigError, HopnavConfig, MissionMode, parse_section};
use hopnav_ipc::messages::{
    CellClass, CellUpdate, DriveCommand, DriveDirection, FrameTick, JumpRequest, MapHeader,
    MissionState, PathHeader, PathPoint, PoseEstimate, Robot,
};
use hopnav_ipc::node_error::NodeError;
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{Publisher, SlicePublisher, SliceSubscriber, Subscriber};

use hopnav_planner::grid::{Cell, CellChange, CellState};
use hopnav_planner::mission::{
    Decision, MapChange, MapGeometry, MissionStatus, NavigationError, Navigator, NavigatorConfig,
    RoverPose,
};

/// Why the planner process failed: the shared node plumbing, or navigation failed for a
/// reason other than an unreachable goal.
pub type PlannerProcessError = NodeError<NavigationError>;

/// What the planner needs from the config.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannerSection {
    /// `[planner]`.
    pub navigator: NavigatorConfig,
    /// `world.scenario.goal_m`.
    pub goal_m: [f64; 2],
}

/// Parses and validates `[planner]` and the goal; errors name the key. Rover-only missions
/// switch the cooperative rule off.
pub fn planner_section(config: &HopnavConfig) -> Result<PlannerSection, ConfigError> {
    let mut navigator: NavigatorConfig = parse_section(config, "planner")?;
    navigator.validate()?;
    if config.mission.mode == MissionMode::RoverOnly {
        navigator.scout.enabled = false;
    }
    navigator.rover_body = hopnav_robot::RoverBody::from_config(config)?;
    let world: hopnav_world::WorldConfig = parse_section(config, "world")?;
    let goal_m = world.scenario.goal_m.ok_or_else(|| ConfigError::Schema {
        key: "world.scenario.goal_m".into(),
        message: "the planner needs the mission goal B (set [world.scenario] goal_m)".into(),
    })?;
    Ok(PlannerSection { navigator, goal_m })
}

/// Runs one planning cycle per frame.
pub struct PlannerProcess {
    section: PlannerSection,
    navigator: Option<Navigator>,
    geometry: Option<MapGeometry>,
    /// Changes that arrived before the navigator existed (no rover pose yet).
    early_changes: Vec<MapChange>,
    map_updates: SliceSubscriber<MapHeader>,
    map_snapshots: SliceSubscriber<MapHeader>,
    rover_poses: Subscriber<PoseEstimate>,
    jumper_poses: Subscriber<PoseEstimate>,
    paths: SlicePublisher<PathHeader>,
    drive_commands: Publisher<DriveCommand>,
    jump_requests: Publisher<JumpRequest>,
    last_rover_pose: Option<PoseEstimate>,
    last_jumper_xy_m: Option<[f64; 2]>,
    refused_changes: u64,
}

/// The longest path the PATH topic carries; longer paths are sent truncated (the report only
/// needs its head).
const MAX_PATH_POINTS: usize = 4096;

/// The planner's view of a mapper cell. A rock the rover never saw, and the lethal margin
/// around any rock, are doubtful obstacles (see [`MapChange`]).
fn cell_change(update: &CellUpdate) -> Option<MapChange> {
    let class = CellClass::from_code(update.class)?;
    let state = match class {
        CellClass::Unknown => CellState::Unknown,
        CellClass::Free | CellClass::Inflated | CellClass::Uncertain => CellState::Free,
        CellClass::Obstacle | CellClass::Lethal => CellState::Obstacle,
    };
    let seen_by_rover = update.observed_by & (1 << Robot::Rover.code()) != 0;
    let seen_by_jumper = update.observed_by & (1 << Robot::Jumper.code()) != 0;
    let doubtful = class == CellClass::Lethal || (class == CellClass::Obstacle && !seen_by_rover);
    Some(MapChange {
        change: CellChange::new(Cell::new(update.x, update.y), state, update.extra_cost),
        doubtful,
        rock: class == CellClass::Obstacle,
        scouted: seen_by_jumper && !seen_by_rover,
    })
}

/// Angle between the rover's body z axis and the world vertical, radians.
fn tilt_rad(pose: &PoseEstimate) -> f64 {
    let (roll_rad, pitch_rad, _) = pose.world_from_body.to_isometry().rotation.euler_angles();
    // The body z axis's vertical component is cos(roll)·cos(pitch) whatever the yaw.
    (roll_rad.cos() * pitch_rad.cos()).clamp(-1.0, 1.0).acos()
}

fn mission_state(decision: Option<&Decision>) -> MissionState {
    match decision.map(|decision| decision.status) {
        None => MissionState::Waiting,
        Some(MissionStatus::Driving) => MissionState::Driving,
        Some(MissionStatus::GoalReached) => MissionState::GoalReached,
        Some(MissionStatus::Unreachable) => MissionState::Unreachable,
    }
}

impl PlannerProcess {
    /// Reads every map snapshot and update of this frame; the first header fixes the
    /// geometry. Snapshots come first: they carry the whole map (history gives a restarted
    /// planner the latest one), updates the changes since.
    fn drain_map_updates(&mut self) -> Result<(), PlannerProcessError> {
        while let Some(sample) = self.map_snapshots.receive()? {
            self.take_cells(sample.header(), sample.elements());
        }
        while let Some(sample) = self.map_updates.receive()? {
            self.take_cells(sample.header(), sample.elements());
        }
        Ok(())
    }

    fn take_cells(&mut self, header: &MapHeader, cells: &[CellUpdate]) {
        if self.geometry.is_none() {
            self.geometry = MapGeometry::new(
                header.origin_x_m,
                header.origin_y_m,
                header.cell_size_m,
                header.width_cells,
                header.height_cells,
            )
            .ok();
        }
        let changes = cells.iter().filter_map(cell_change);
        match self.navigator.as_mut() {
            Some(navigator) => {
                self.refused_changes += navigator.queue_changes(changes) as u64;
            }
            None => self.early_changes.extend(changes),
        }
    }

    fn ensure_navigator(&mut self) -> Result<(), PlannerProcessError> {
        if self.navigator.is_some() {
            return Ok(());
        }
        let (Some(geometry), Some(pose)) = (self.geometry, self.last_rover_pose) else {
            return Ok(());
        };
        let [x_m, y_m, _] = pose.world_from_body.position_m;
        let mut navigator = Navigator::new(
            geometry,
            [x_m, y_m],
            self.section.goal_m,
            self.section.navigator.clone(),
        )
        .map_err(NodeError::Own)?;
        self.refused_changes += navigator.queue_changes(self.early_changes.drain(..)) as u64;
        self.navigator = Some(navigator);
        Ok(())
    }

    fn publish(
        &mut self,
        tick: &FrameTick,
        decision: Option<&Decision>,
    ) -> Result<(), PlannerProcessError> {
        let mut stamp = tick.stamp;
        stamp.sequence = 0;
        if let Some(decision) = decision {
            self.drive_commands.send_with(|command| {
                command.stamp = stamp;
                command.waypoint_x_m = decision.waypoint_m[0];
                command.waypoint_y_m = decision.waypoint_m[1];
                command.speed_mps = decision.speed_mps;
                command.hold = u32::from(decision.hold);
                command.direction = if decision.reverse {
                    DriveDirection::Reverse
                } else {
                    DriveDirection::Forward
                }
                .code();
            })?;
        }
        let state = mission_state(decision);
        let Some(navigator) = self.navigator.as_ref() else {
            self.paths.send_from_fn(
                0,
                |header| {
                    header.stamp = stamp;
                    header.state = state.code();
                },
                |_| PathPoint::default(),
            )?;
            return Ok(());
        };
        let counters = navigator.counters();
        let geometry = *navigator.geometry();
        let path = navigator.path();
        let len = path.len().min(MAX_PATH_POINTS);
        self.paths.send_from_fn(
            len,
            |header| {
                header.stamp = stamp;
                header.cost = counters.path_cost;
                header.replan_count = counters.replans;
                header.route_change_count = counters.route_changes;
                header.expansions = counters.last_expansions;
                header.total_expansions = counters.total_expansions;
                header.point_count = len as u32;
                header.goal_reachable = u32::from(state != MissionState::Unreachable);
                header.state = state.code();
                header.jump_requests = counters.scout_requests;
            },
            |index| {
                let [x_m, y_m] = geometry.center_of(path[index]);
                PathPoint { x_m, y_m }
            },
        )?;
        Ok(())
    }
}

impl Process for PlannerProcess {
    type Error = PlannerProcessError;

    fn new(context: &ProcessContext) -> Result<Self, PlannerProcessError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        let section = planner_section(&config)?;
        let node = &context.node;
        Ok(Self {
            section,
            navigator: None,
            geometry: None,
            early_changes: Vec::with_capacity(4096),
            map_updates: SliceSubscriber::open(node, &topics::MAP_UPDATES)?,
            map_snapshots: SliceSubscriber::open(node, &topics::MAP_SNAPSHOT)?,
            rover_poses: Subscriber::open(node, &topics::ROVER_POSE)?,
            jumper_poses: Subscriber::open(node, &topics::JUMPER_POSE)?,
            paths: SlicePublisher::open(node, &topics::PATH, MAX_PATH_POINTS)?,
            drive_commands: Publisher::open(node, &topics::DRIVE_COMMAND)?,
            jump_requests: Publisher::open(node, &topics::JUMP_REQUEST)?,
            last_rover_pose: None,
            last_jumper_xy_m: None,
            refused_changes: 0,
        })
    }

    fn step(
        &mut self,
        _context: &ProcessContext,
        tick: &FrameTick,
    ) -> Result<(), PlannerProcessError> {
        if let Some(pose) = self.rover_poses.receive_latest()? {
            self.last_rover_pose = Some(pose);
        }
        if let Some(pose) = self.jumper_poses.receive_latest()? {
            let [x_m, y_m, _] = pose.world_from_body.position_m;
            self.last_jumper_xy_m = Some([x_m, y_m]);
        }
        self.drain_map_updates()?;
        self.ensure_navigator()?;
        let time_s = tick.stamp.sim_time_ns as f64 * 1e-9;
        let decision = match (self.navigator.as_mut(), self.last_rover_pose) {
            (Some(navigator), Some(pose)) => {
                let [x_m, y_m, _] = pose.world_from_body.position_m;
                let (_, _, yaw_rad) = pose.world_from_body.to_isometry().rotation.euler_angles();
                let rover = RoverPose {
                    xy_m: [x_m, y_m],
                    yaw_rad,
                };
                navigator.set_rover_tilt(tilt_rad(&pose));
                Some(
                    navigator
                        .step(rover, self.last_jumper_xy_m, time_s)
                        .map_err(NodeError::Own)?,
                )
            }
            _ => None,
        };
        if let Some(scout) = decision.as_ref().and_then(|decision| decision.scout) {
            let request_id = self.navigator.as_ref().map_or(0, |navigator| {
                u64::from(navigator.counters().scout_requests)
            });
            let mut stamp = tick.stamp;
            stamp.sequence = 0;
            self.jump_requests.send_with(|request| {
                request.stamp = stamp;
                request.target_m = [scout.target_m[0], scout.target_m[1], 0.0];
                request.request_id = request_id;
            })?;
        }
        self.publish(tick, decision.as_ref())
    }

    fn rejected_samples(&self) -> u64 {
        self.map_updates.rejected().total()
            + self.map_snapshots.rejected().total()
            + self.rover_poses.rejected().total()
            + self.jumper_poses.rejected().total()
            + self.refused_changes
    }
}
