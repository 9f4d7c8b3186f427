//! Watches the mission from outside: the planner's state and counters, the mapper's cells, and
//! ground truth of both robots (for the report and the evaluation only; never fed back).

use std::collections::HashMap;

use hopnav_config::HopnavConfig;
use hopnav_ipc::IpcService;
use hopnav_ipc::messages::{
    BodyStates, CellClass, MapHeader, MissionState, PathHeader, PoseEstimate,
};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SliceSubscriber, Subscriber};
use iceoryx2::node::Node;

use crate::contact_log::{CELLS_AROUND_M, ContactLog};
use crate::hop_counter::HopCounter;
use crate::mission_record::{MissionRecord, RecordedCell, RecordedMap, RecordedVo};
use crate::mission_report::MissionReport;
use crate::rover_motion::{MotionTimes, motion_of};
use crate::vo_pairs::VoTrack;

/// The planner holding "unreachable" this long ends the mission as failed, seconds.
const UNREACHABLE_GIVE_UP_S: f64 = 5.0;
/// Truth positions closer than this to the previous one are not stored again, metres.
const TRACK_STEP_M: f64 = 0.05;

/// A cell as the mapper last published it.
#[derive(Debug, Clone, Copy)]
struct CellView {
    class: CellClass,
    observed_by: u32,
    extra_cost: u32,
}

/// Grid placement from the map header.
#[derive(Debug, Clone, Copy)]
struct Geometry {
    origin_m: (f64, f64),
    cell_size_m: f64,
}

/// Mission bookkeeping of one launch.
pub struct MissionObserver {
    mode: hopnav_config::MissionMode,
    truth: Subscriber<BodyStates>,
    jumper_poses: Subscriber<PoseEstimate>,
    rover_poses: Subscriber<PoseEstimate>,
    jumper_vo: VoTrack,
    rover_vo: VoTrack,
    paths: SliceSubscriber<PathHeader>,
    maps: SliceSubscriber<MapHeader>,
    last_path: Option<PathHeader>,
    planned_path_m: Vec<(f64, f64)>,
    geometry: Option<Geometry>,
    cells: HashMap<(u32, u32), CellView>,
    rover_track_m: Vec<(f64, f64)>,
    jumper_track_m: Vec<(f64, f64)>,
    rover_path_m: f64,
    last_rover_m: Option<[f64; 2]>,
    collisions: u32,
    contacts: ContactLog,
    rover_times: MotionTimes,
    hops: HopCounter,
    last_sim_time_s: f64,
    reached_at_s: Option<f64>,
    unreachable_since_s: Option<f64>,
}

impl MissionObserver {
    /// Subscribes on the supervisor's node. `None` when a mission topic cannot be opened.
    pub fn open(node: &Node<IpcService>, config: &HopnavConfig) -> Option<Self> {
        Some(Self {
            mode: config.mission.mode,
            truth: Subscriber::open(node, &topics::BODY_STATES).ok()?,
            jumper_poses: Subscriber::open(node, &topics::JUMPER_POSE).ok()?,
            rover_poses: Subscriber::open(node, &topics::ROVER_POSE).ok()?,
            jumper_vo: VoTrack::default(),
            rover_vo: VoTrack::default(),
            paths: SliceSubscriber::open(node, &topics::PATH).ok()?,
            maps: SliceSubscriber::open(node, &topics::MAP_UPDATES).ok()?,
            last_path: None,
            planned_path_m: Vec::new(),
            geometry: None,
            cells: HashMap::new(),
            rover_track_m: Vec::new(),
            jumper_track_m: Vec::new(),
            rover_path_m: 0.0,
            last_rover_m: None,
            collisions: 0,
            contacts: ContactLog::default(),
            rover_times: MotionTimes::default(),
            hops: HopCounter::default(),
            last_sim_time_s: 0.0,
            reached_at_s: None,
            unreachable_since_s: None,
        })
    }

    /// Drains everything published since the last call.
    pub fn observe(&mut self) {
        while let Ok(Some(states)) = self.truth.receive() {
            self.on_truth(&states);
        }
        while let Ok(Some(pose)) = self.jumper_poses.receive() {
            let world_from_body = pose.world_from_body.to_isometry();
            self.jumper_vo
                .add_estimate(pose.stamp.sim_time_ns, world_from_body);
        }
        while let Ok(Some(pose)) = self.rover_poses.receive() {
            let world_from_body = pose.world_from_body.to_isometry();
            self.rover_vo
                .add_estimate(pose.stamp.sim_time_ns, world_from_body);
        }
        while let Ok(Some(sample)) = self.maps.receive() {
            let header = sample.header();
            self.geometry.get_or_insert(Geometry {
                origin_m: (header.origin_x_m, header.origin_y_m),
                cell_size_m: header.cell_size_m,
            });
            for update in sample.elements() {
                if let Some(class) = CellClass::from_code(update.class) {
                    self.cells.insert(
                        (update.x, update.y),
                        CellView {
                            class,
                            observed_by: update.observed_by,
                            extra_cost: update.extra_cost,
                        },
                    );
                }
            }
        }
        while let Ok(Some(sample)) = self.paths.receive() {
            let header = *sample.header();
            self.planned_path_m.clear();
            self.planned_path_m
                .extend(sample.elements().iter().map(|point| (point.x_m, point.y_m)));
            self.on_path(&header);
        }
    }

    fn on_truth(&mut self, states: &BodyStates) {
        let time_s = states.stamp.sim_time_ns as f64 * 1e-9;
        let motion = motion_of(&states.rover);
        // The frame's motion over the time since the last truth, until the rover is at B.
        if self.reached_at_s.is_none() && time_s > self.last_sim_time_s {
            self.rover_times
                .add(motion.0, time_s - self.last_sim_time_s);
        }
        self.last_sim_time_s = time_s;
        let time_ns = states.stamp.sim_time_ns;
        self.jumper_vo
            .add_truth(time_ns, states.jumper.world_from_body.to_isometry());
        self.rover_vo
            .add_truth(time_ns, states.rover.world_from_body.to_isometry());
        let [x_m, y_m, _] = states.rover.world_from_body.position_m;
        if let Some([last_x, last_y]) = self.last_rover_m {
            self.rover_path_m += (x_m - last_x).hypot(y_m - last_y);
        }
        self.last_rover_m = Some([x_m, y_m]);
        push_if_moved(&mut self.rover_track_m, (x_m, y_m));
        let [jx_m, jy_m, jz_m] = states.jumper.world_from_body.position_m;
        push_if_moved(&mut self.jumper_track_m, (jx_m, jy_m));
        self.hops.observe(states.jumper.in_contact != 0, jz_m);
        self.collisions = states.rover.collisions;
        let (geometry, cells) = (self.geometry, &self.cells);
        self.contacts
            .observe(self.last_sim_time_s, &states.rover, motion, |rover_m| {
                geometry.map_or_else(Vec::new, |geometry| {
                    cells_around(&geometry, cells, rover_m, CELLS_AROUND_M)
                })
            });
    }

    fn on_path(&mut self, header: &PathHeader) {
        let time_s = header.stamp.sim_time_ns as f64 * 1e-9;
        match MissionState::from_code(header.state) {
            Some(MissionState::GoalReached) => {
                self.reached_at_s.get_or_insert(time_s);
            }
            Some(MissionState::Unreachable) => {
                self.unreachable_since_s.get_or_insert(time_s);
            }
            _ => self.unreachable_since_s = None,
        }
        self.last_path = Some(*header);
    }

    /// Why the mission is over, if it is: the goal was reached, or it stayed unreachable.
    pub fn end_reason(&self) -> Option<String> {
        if let Some(at_s) = self.reached_at_s {
            return Some(format!("goal reached at {at_s:.1} s"));
        }
        let since_s = self.unreachable_since_s?;
        let now_s = self
            .last_path
            .map_or(since_s, |header| header.stamp.sim_time_ns as f64 * 1e-9);
        (now_s - since_s >= UNREACHABLE_GIVE_UP_S)
            .then(|| format!("goal unreachable on the known map since {since_s:.1} s"))
    }

    /// The report section: the planner's counters and what the truth says of the drive. An
    /// evaluator adds its fields later (see [`MissionReport::evaluation`]).
    pub fn report(&self) -> MissionReport {
        let header = self.last_path.unwrap_or_default();
        let state = MissionState::from_code(header.state).unwrap_or(MissionState::Waiting);
        let count = |class: CellClass| {
            self.cells
                .values()
                .filter(|cell| cell.class == class)
                .count()
        };
        MissionReport {
            mode: self.mode.name().to_owned(),
            goal_reached: self.reached_at_s.is_some(),
            final_state: format!("{state:?}"),
            mission_time_s: self.reached_at_s.unwrap_or(self.last_sim_time_s),
            executed_path_m: self.rover_path_m,
            replans: header.replan_count,
            route_changes: header.route_change_count,
            node_expansions: header.total_expansions,
            jump_requests: header.jump_requests,
            jumper_hops: self.hops.hops(),
            collisions: self.collisions,
            rover_motion_times: Some(self.rover_times),
            mapped_cells: self.cells.len(),
            obstacle_cells: count(CellClass::Obstacle),
            inflated_cells: count(CellClass::Inflated)
                + count(CellClass::Lethal)
                + count(CellClass::Uncertain),
            evaluation: serde_json::Map::new(),
        }
    }

    /// What the evaluation needs: the final map, the true tracks and the VO pairs.
    pub fn record(&self) -> MissionRecord {
        let map = self.geometry.map(|geometry| {
            let mut cells: Vec<RecordedCell> = self
                .cells
                .iter()
                .map(|(&(x, y), view)| RecordedCell {
                    x,
                    y,
                    class: view.class,
                    observed_by: view.observed_by,
                    extra_cost: view.extra_cost,
                })
                .collect();
            cells.sort_by_key(|cell| (cell.y, cell.x));
            RecordedMap {
                origin_m: geometry.origin_m,
                cell_size_m: geometry.cell_size_m,
                cells,
            }
        });
        MissionRecord {
            mode: self.mode,
            map,
            rover_track_m: self.rover_track_m.clone(),
            jumper_track_m: self.jumper_track_m.clone(),
            last_rover_m: self.last_rover_m,
            contacts: self.contacts.contacts().to_vec(),
            vo: vec![
                RecordedVo {
                    robot: "jumper",
                    track: self.jumper_vo.clone(),
                },
                RecordedVo {
                    robot: "rover",
                    track: self.rover_vo.clone(),
                },
            ],
        }
    }
}

/// The published cells whose centres lie within `radius_m` of `centre_m`, sorted by (y, x).
fn cells_around(
    geometry: &Geometry,
    cells: &HashMap<(u32, u32), CellView>,
    centre_m: [f64; 2],
    radius_m: f64,
) -> Vec<RecordedCell> {
    let size_m = geometry.cell_size_m;
    let reach = (radius_m / size_m).ceil() as i64 + 1;
    let column = ((centre_m[0] - geometry.origin_m.0) / size_m).floor() as i64;
    let row = ((centre_m[1] - geometry.origin_m.1) / size_m).floor() as i64;
    let mut around = Vec::new();
    for y in (row - reach).max(0)..=(row + reach) {
        for x in (column - reach).max(0)..=(column + reach) {
            let (Ok(x), Ok(y)) = (u32::try_from(x), u32::try_from(y)) else {
                continue;
            };
            let Some(view) = cells.get(&(x, y)) else {
                continue;
            };
            let dx_m = geometry.origin_m.0 + (f64::from(x) + 0.5) * size_m - centre_m[0];
            let dy_m = geometry.origin_m.1 + (f64::from(y) + 0.5) * size_m - centre_m[1];
            if dx_m.hypot(dy_m) <= radius_m {
                around.push(RecordedCell {
                    x,
                    y,
                    class: view.class,
                    observed_by: view.observed_by,
                    extra_cost: view.extra_cost,
                });
            }
        }
    }
    around
}

fn push_if_moved(track: &mut Vec<(f64, f64)>, point: (f64, f64)) {
    let moved = track
        .last()
        .is_none_or(|last| (point.0 - last.0).hypot(point.1 - last.1) >= TRACK_STEP_M);
    if moved && point.0.is_finite() && point.1.is_finite() {
        track.push(point);
    }
}
