//! Watches the mission from outside: the planner's state and counters, the mapper's cells, and
//! ground truth of both robots (for the report and the figure only; never fed back).

use std::collections::HashMap;

use hopnav_config::HopnavConfig;
use hopnav_ipc::IpcService;
use hopnav_ipc::messages::{
    BodyStates, CellClass, MapHeader, MissionState, PathHeader, PoseEstimate, Robot,
};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SliceSubscriber, Subscriber};
use hopnav_metrics::map_plot::{MapFigure, MappedCell, MappedClass, Observer, RockOutline, Track};
use iceoryx2::node::Node;

use crate::full_knowledge::{FullKnowledgePath, KnownCell, full_knowledge_path, plan_on_known_map};
use crate::hop_counter::HopCounter;
use crate::map_accuracy::{self, MapAccuracy, ObstacleCell, RockFootprint};
use crate::mission_report::MissionReport;
use crate::vo_accuracy::VoTrack;

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

/// The mapper's default obstacle threshold (`mapper.traversable_height_m`), metres.
const DEFAULT_TRAVERSABLE_HEIGHT_M: f64 = 0.15;
/// Physics' default climbable height (`physics.rover.max_climbable_height_m`), metres.
const DEFAULT_CLIMBABLE_HEIGHT_M: f64 = 0.2;
/// Rocks this much lower than the obstacle threshold still make an obstacle cell true (the
/// clouds' height noise is a few centimetres), metres.
const HEIGHT_TOLERANCE_M: f64 = 0.05;

/// Mission bookkeeping of one launch.
pub struct MissionObserver {
    mode: hopnav_config::MissionMode,
    /// The world, regenerated at the end to score the map (evaluation only).
    world: hopnav_world::WorldConfig,
    traversable_height_m: f64,
    climbable_height_m: f64,
    /// The mapper's grid and inflation, for the full-knowledge path (`None` when invalid).
    mapper: Option<hopnav_mapper::config::MapperConfig>,
    start_m: Option<[f64; 2]>,
    goal_m: Option<[f64; 2]>,
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
    hops: HopCounter,
    last_sim_time_s: f64,
    reached_at_s: Option<f64>,
    unreachable_since_s: Option<f64>,
}

impl MissionObserver {
    /// Subscribes on the supervisor's node. `None` when the config has no mission goal.
    pub fn open(node: &Node<IpcService>, config: &HopnavConfig) -> Option<Self> {
        let world: hopnav_world::WorldConfig =
            hopnav_config::parse_section(config, "world").ok()?;
        let float_key = |table: &str, path: &[&str], default: f64| {
            hopnav_config::number_at(config, table, path).unwrap_or(default)
        };
        Some(Self {
            mode: config.mission.mode,
            start_m: world.scenario.start_m,
            goal_m: world.scenario.goal_m,
            traversable_height_m: float_key(
                "mapper",
                &["traversable_height_m"],
                DEFAULT_TRAVERSABLE_HEIGHT_M,
            ),
            climbable_height_m: float_key(
                "physics",
                &["rover", "max_climbable_height_m"],
                DEFAULT_CLIMBABLE_HEIGHT_M,
            ),
            mapper: hopnav_mapper::process::mapper_section(config).ok(),
            world,
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
        self.last_sim_time_s = states.stamp.sim_time_ns as f64 * 1e-9;
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

    /// The report section; `rocks` are the world's ([`Self::truth_rocks`]), for the map's
    /// accuracy and the full-knowledge path.
    pub fn report(&self, rocks: Option<&[RockFootprint]>) -> MissionReport {
        let header = self.last_path.unwrap_or_default();
        let distance_to_goal_m = match (self.goal_m, self.last_rover_m) {
            (Some(goal), Some(rover)) => Some((goal[0] - rover[0]).hypot(goal[1] - rover[1])),
            _ => None,
        };
        let straight_line_m = match (self.start_m, self.goal_m) {
            (Some(start), Some(goal)) => Some((goal[0] - start[0]).hypot(goal[1] - start[1])),
            _ => None,
        };
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
            straight_line_m,
            final_distance_to_goal_m: distance_to_goal_m,
            replans: header.replan_count,
            route_changes: header.route_change_count,
            node_expansions: header.total_expansions,
            jump_requests: header.jump_requests,
            jumper_hops: self.hops.hops(),
            collisions: self.collisions,
            mapped_cells: self.cells.len(),
            obstacle_cells: count(CellClass::Obstacle),
            inflated_cells: count(CellClass::Inflated) + count(CellClass::Lethal),
            built_map_path_m: self.built_map_path().map(|path| path.length_m),
            map_accuracy: rocks.and_then(|rocks| self.map_accuracy(rocks)),
            full_knowledge_path_m: rocks
                .and_then(|rocks| self.full_knowledge_path(rocks))
                .map(|path| path.length_m),
            vo: [
                self.jumper_vo.accuracy("jumper"),
                self.rover_vo.accuracy("rover"),
            ]
            .into_iter()
            .flatten()
            .collect(),
        }
    }

    /// Each robot's matched VO estimates and truths, for TUM files.
    pub fn vo_tracks(&self) -> [(&'static str, &VoTrack); 2] {
        [("jumper", &self.jumper_vo), ("rover", &self.rover_vo)]
    }

    /// The world's rocks, regenerated from the config (evaluation only); `None` when it
    /// cannot be.
    pub fn truth_rocks(&self) -> Option<Vec<RockFootprint>> {
        let world = hopnav_world::World::generate(&self.world).ok()?;
        Some(
            world
                .rocks()
                .iter()
                .map(|rock| RockFootprint {
                    center_m: [rock.center_m[0], rock.center_m[1]],
                    radius_m: rock.bounding_radius_m(),
                    height_m: rock.height_m,
                })
                .collect(),
        )
    }

    /// The planner's path from A to B had it known from the start every rock the rover
    /// cannot climb.
    fn full_knowledge_path(&self, rocks: &[RockFootprint]) -> Option<FullKnowledgePath> {
        let mapper = self.mapper.as_ref()?;
        let geometry = self.map_geometry()?;
        let kernel = hopnav_mapper::inflation::inflation_kernel(
            geometry.cell_size_m(),
            mapper.inflation_radius_m,
            mapper.lethal_radius_m,
            mapper.inflation_max_cost,
        );
        full_knowledge_path(
            rocks,
            self.climbable_height_m,
            &geometry,
            &kernel,
            self.start_m?,
            self.goal_m?,
        )
    }

    /// The planner's path from A to B had it known from the start the final map, classed as
    /// the planner classes the mapper's cells (a lethal margin, and a rock only the jumper
    /// saw, are doubtful obstacles).
    fn built_map_path(&self) -> Option<FullKnowledgePath> {
        let geometry = self.map_geometry()?;
        let width = geometry.width_cells() as usize;
        let rover_bit = 1u32 << Robot::Rover.code();
        let mut known =
            vec![KnownCell::Free { extra_cost: 0 }; width * geometry.height_cells() as usize];
        for (&(x, y), view) in &self.cells {
            let Some(slot) = known.get_mut(y as usize * width + x as usize) else {
                continue;
            };
            *slot = match view.class {
                CellClass::Obstacle if view.observed_by & rover_bit != 0 => KnownCell::Obstacle,
                CellClass::Obstacle | CellClass::Lethal => KnownCell::Doubtful,
                CellClass::Unknown | CellClass::Free | CellClass::Inflated => KnownCell::Free {
                    extra_cost: view.extra_cost,
                },
            };
        }
        plan_on_known_map(&known, &geometry, self.start_m?, self.goal_m?)
    }

    /// The mapper's grid, as the planner places it (`None` when the mapper config is invalid).
    fn map_geometry(&self) -> Option<hopnav_planner::mission::MapGeometry> {
        let grid = hopnav_mapper::process::grid_geometry(self.mapper.as_ref()?).ok()?;
        hopnav_planner::mission::MapGeometry::new(
            grid.origin_x_m,
            grid.origin_y_m,
            grid.cell_size_m,
            grid.width_cells,
            grid.height_cells,
        )
        .ok()
    }

    /// The final map's obstacles against the world's rocks; `None` without a map.
    fn map_accuracy(&self, rocks: &[RockFootprint]) -> Option<MapAccuracy> {
        let geometry = self.geometry?;
        let rover_bit = 1u32 << Robot::Rover.code();
        let jumper_bit = 1u32 << Robot::Jumper.code();
        let size_m = geometry.cell_size_m;
        let cells: Vec<ObstacleCell> = self
            .cells
            .iter()
            .filter(|(_, view)| view.class == CellClass::Obstacle)
            .map(|(&(x, y), view)| ObstacleCell {
                center_m: [
                    geometry.origin_m.0 + (f64::from(x) + 0.5) * size_m,
                    geometry.origin_m.1 + (f64::from(y) + 0.5) * size_m,
                ],
                by_rover: view.observed_by & rover_bit != 0,
                by_jumper: view.observed_by & jumper_bit != 0,
            })
            .collect();
        let track_m: Vec<[f64; 2]> = self.rover_track_m.iter().map(|&(x, y)| [x, y]).collect();
        Some(map_accuracy::evaluate(
            rocks,
            &cells,
            &track_m,
            size_m,
            self.traversable_height_m - HEIGHT_TOLERANCE_M,
            self.climbable_height_m,
        ))
    }

    /// The Fig.-6 figure of this launch, with the rover's and the jumper's true tracks and
    /// the outlines of the `rocks` the rover cannot climb.
    pub fn figure(&self, title: &str, rocks: Option<&[RockFootprint]>) -> Option<MapFigure> {
        let geometry = self.geometry?;
        let (start, goal) = (self.start_m?, self.goal_m?);
        let rover_label = format!("rover ({})", self.mode.name());
        let rocks = rocks
            .unwrap_or_default()
            .iter()
            .filter(|rock| rock.height_m > self.climbable_height_m)
            .map(|rock| RockOutline {
                center_m: (rock.center_m[0], rock.center_m[1]),
                radius_m: rock.radius_m,
            })
            .collect();
        Some(map_figure(
            title,
            geometry.origin_m,
            geometry.cell_size_m,
            self.mapped_cells(),
            (start[0], start[1]),
            (goal[0], goal[1]),
            vec![
                Track {
                    label: rover_label,
                    points_m: self.rover_track_m.clone(),
                    rgb: (0, 150, 60),
                    markers_only: false,
                },
                Track {
                    label: "jumper".into(),
                    points_m: self.jumper_track_m.clone(),
                    rgb: (230, 130, 0),
                    markers_only: true,
                },
            ],
            rocks,
        ))
    }

    /// The rover's true track, world metres.
    pub fn rover_track_m(&self) -> &[(f64, f64)] {
        &self.rover_track_m
    }

    fn mapped_cells(&self) -> Vec<MappedCell> {
        let rover_bit = 1u32 << Robot::Rover.code();
        let jumper_bit = 1u32 << Robot::Jumper.code();
        self.cells
            .iter()
            .filter_map(|(&(x, y), view)| {
                let class = match view.class {
                    CellClass::Unknown => return None,
                    CellClass::Free => MappedClass::Free,
                    CellClass::Obstacle => MappedClass::Obstacle,
                    CellClass::Inflated | CellClass::Lethal => MappedClass::Inflated,
                };
                let observer = match (
                    view.observed_by & rover_bit != 0,
                    view.observed_by & jumper_bit != 0,
                ) {
                    (true, true) => Observer::Both,
                    (false, true) => Observer::Jumper,
                    (true, false) => Observer::Rover,
                    (false, false) => Observer::Nobody,
                };
                Some(MappedCell {
                    x,
                    y,
                    class,
                    observer,
                })
            })
            .collect()
    }
}

/// A figure around start, goal and every track, with `cells` under them and the `rocks`
/// within view outlined.
#[allow(clippy::too_many_arguments)]
pub fn map_figure(
    title: &str,
    origin_m: (f64, f64),
    cell_size_m: f64,
    cells: Vec<MappedCell>,
    start_m: (f64, f64),
    goal_m: (f64, f64),
    tracks: Vec<Track>,
    rocks: Vec<RockOutline>,
) -> MapFigure {
    let points = tracks
        .iter()
        .flat_map(|track| track.points_m.iter().copied())
        .chain([start_m, goal_m])
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in points {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let margin_m = 4.0;
    let half_height_m = ((y1 - y0) / 2.0 + margin_m).max((x1 - x0) / 6.0);
    let centre_y = (y0 + y1) / 2.0;
    // Room on the right for the legend, so it never hides the goal or a track.
    let legend_m = 0.3 * (x1 - x0 + 2.0 * margin_m);
    let view_m = (
        x0 - margin_m,
        x1 + margin_m + legend_m,
        centre_y - half_height_m,
        centre_y + half_height_m,
    );
    let in_view = |rock: &RockOutline| {
        let (x, y, r) = (rock.center_m.0, rock.center_m.1, rock.radius_m);
        x + r > view_m.0 && x - r < view_m.1 && y + r > view_m.2 && y - r < view_m.3
    };
    MapFigure {
        title: title.to_owned(),
        origin_m,
        cell_size_m,
        cells,
        start_m,
        goal_m,
        tracks,
        rocks: rocks.into_iter().filter(in_view).collect(),
        view_m,
    }
}

fn push_if_moved(track: &mut Vec<(f64, f64)>, point: (f64, f64)) {
    let moved = track
        .last()
        .is_none_or(|last| (point.0 - last.0).hypot(point.1 - last.1) >= TRACK_STEP_M);
    if moved && point.0.is_finite() && point.1.is_finite() {
        track.push(point);
    }
}
