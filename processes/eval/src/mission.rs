//! A finished mission against the truth: the straight line and what was left of it, the
//! full-knowledge and built-map paths, the final map's accuracy and each robot's VO error.
//!
//! The world is regenerated from the run's config (evaluation only); the supervisor's
//! [`MissionRecord`] gives the final map, the true tracks and the VO pairs.

use std::io::Write;

use hopnav_config::HopnavConfig;
use hopnav_ipc::messages::{CellClass, Robot};
use hopnav_mapper::config::MapperConfig;
use hopnav_planner::mission::MapGeometry;
use hopnav_supervisor::mission_record::{MissionRecord, RecordedMap};
use hopnav_supervisor::mission_report::MissionReport;
use serde::{Deserialize, Serialize};

use crate::blocked_area_judges::judge_blocked_area;
use crate::contact_judge::{
    ContactGrid, JudgedContact, MapVerdict, count_by_verdict, judge_contacts,
};
use crate::full_knowledge::{FullKnowledgePath, KnownCell, full_knowledge_path, plan_on_known_map};
use crate::line_of_sight::LineOfSight;
use crate::map_accuracy::{self, MapAccuracy, ObstacleCell, RockFootprint};
use crate::traversability::{BlockedArea, RockOutline};
use crate::true_slope::TrueSlopes;
use crate::vo_accuracy::{VoAccuracy, accuracy};

/// Rocks this much lower than the obstacle threshold still make an obstacle cell true (the
/// clouds' height noise is a few centimetres), metres.
const HEIGHT_TOLERANCE_M: f64 = 0.05;

/// The world's texture for the truth, metres a texel: the largest the config allows.
const COARSEST_TEXEL_M: f64 = 0.5;

/// What the evaluation adds to the report's `mission` section. Any field may be missing from
/// a report (one written before the field existed, or without the evaluation): it reads as
/// its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MissionEvaluation {
    /// Straight-line distance from A to B, metres.
    pub straight_line_m: Option<f64>,
    /// True distance from the rover to B at the end, metres.
    pub final_distance_to_goal_m: Option<f64>,
    /// Length of the path the planner would have driven knowing every rock from the start,
    /// metres (the most any scouting could shorten the drive to).
    pub full_knowledge_path_m: Option<f64>,
    /// Length of the path the planner would have driven knowing from the start the map the
    /// robots built by the end (unknown cells free, as planned; the rover's bump marks left
    /// out), metres. Above `full_knowledge_path_m` by what the map's errors cost (false or
    /// misplaced obstacles, missed rocks); below the executed path by what learning the map
    /// on the way cost, the part a scout that arrives earlier can win back.
    pub built_map_path_m: Option<f64>,
    /// Obstacle cells against the world's rocks.
    pub map_accuracy: Option<MapAccuracy>,
    /// Each robot's VO against the truth of the same frames.
    pub vo: Vec<VoAccuracy>,
    /// The ground the map shuts the rover's centre out of, against the truth, over the cells
    /// the rover's camera had in sight from within 5 m (ground hidden behind a rock left out).
    pub blocked_area: Option<BlockedArea>,
    /// The same over every cell in the camera's horizontal field of view within 5 m, hidden
    /// or not (what `blocked_area` judged before the judge had a line of sight).
    pub blocked_area_in_view: Option<BlockedArea>,
    /// The same over every mapped cell within 5 m of the rover's track, whichever way its
    /// camera looked (rocks to the side seen only from afar count too).
    pub blocked_area_near_track: Option<BlockedArea>,
    /// `blocked_area` (in sight) in the map's own frame: the map carried onto the truth by the rigid
    /// motion in the ground plane that best aligns the rover's VO with its true track, so the
    /// few centimetres by which the VO misplaces the whole map do not count as the mapper's
    /// error.
    pub blocked_area_map_frame: Option<BlockedArea>,
    /// Each rock contact of the rover: what it was doing, the rock it met and what the map
    /// said of that rock at that moment.
    pub contacts: Vec<JudgedContact>,
}

impl MissionEvaluation {
    /// The evaluation a report's mission section carries (all `None` when it carries none or
    /// the fields cannot be read).
    pub fn of(report: &MissionReport) -> Self {
        serde_json::from_value(serde_json::Value::Object(report.evaluation.clone()))
            .unwrap_or_default()
    }

    /// The fields to merge into the report's mission section.
    pub fn to_fields(&self) -> serde_json::Map<String, serde_json::Value> {
        match serde_json::to_value(self) {
            Ok(serde_json::Value::Object(fields)) => fields,
            _ => serde_json::Map::new(),
        }
    }

    /// The summary lines of a mission whose runtime figures are `report`.
    pub fn print(&self, report: &MissionReport, out: &mut impl Write) -> std::io::Result<()> {
        let distance = |value: Option<f64>| value.map_or("-".to_owned(), |m| format!("{m:.1} m"));
        writeln!(
            out,
            "A–B {} in a straight line; {} left to B at the end",
            distance(self.straight_line_m),
            distance(self.final_distance_to_goal_m)
        )?;
        if let Some(accuracy) = &self.map_accuracy {
            writeln!(
                out,
                "map vs truth: {} obstacle cells on rocks, {} false (rover {}, jumper {} of which {} beside a rock, both {}); rocks the rover cannot climb near its track: {} of {} mapped",
                accuracy.true_obstacle_cells,
                accuracy.false_obstacle_cells(),
                accuracy.false_by_rover,
                accuracy.false_by_jumper,
                accuracy.false_by_jumper_misplaced,
                accuracy.false_by_both,
                accuracy.blocking_rocks_found,
                accuracy.blocking_rocks_near_track
            )?;
        }
        if let Some(best_m) = self.full_knowledge_path_m {
            // The comparison means something only for a drive that got to B.
            let comparison = if report.goal_reached {
                format!(
                    "; the rover drove {:+.1} % more",
                    100.0 * (report.executed_path_m / best_m.max(1e-9) - 1.0)
                )
            } else {
                String::new()
            };
            writeln!(
                out,
                "full-knowledge path (every rock known from the start): {best_m:.1} m{comparison}"
            )?;
        }
        if let Some(built_m) = self.built_map_path_m {
            writeln!(
                out,
                "built-map path (the final map known from the start): {built_m:.1} m; what was learnt on the way cost {:+.1} m",
                report.executed_path_m - built_m
            )?;
        }
        if let Some(blocked) = &self.blocked_area {
            writeln!(
                out,
                "ground lethal for the rover's centre where its camera had it in sight within 5 m: map {:.1} m², rocks {:.1} m² (ratio {}); truly lethal cells left traversable: {} of {} (held uncertain: {}), false lethal cells: {}; unclimbable rocks there: {} lethal, {} only costly, {} seen but free, {} not seen",
                blocked.mapped_lethal_m2,
                blocked.true_lethal_m2,
                blocked
                    .blocked_area_ratio
                    .map_or("-".to_owned(), |ratio| format!("{ratio:.2}")),
                blocked.missed_lethal_cells,
                blocked.true_lethal_cells,
                blocked.uncertain_lethal_cells,
                blocked.false_lethal_cells,
                blocked.rocks_by_outcome[0],
                blocked.rocks_by_outcome[1],
                blocked.rocks_by_outcome[2],
                blocked.rocks_by_outcome[3]
            )?;
        }
        if !self.contacts.is_empty() {
            writeln!(out, "{}", contacts_line(&self.contacts))?;
        }
        for vo in &self.vo {
            writeln!(
                out,
                "{} VO vs truth over {} poses: ATE Sim(3) {:.3} m, SE(3) {:.3} m, unaligned RMSE {:.3} m, final error {:.3} m after {:.1} m travelled ({:.2} %)",
                vo.robot,
                vo.poses,
                vo.ate_sim3_m,
                vo.ate_se3_m,
                vo.unaligned_rmse_m,
                vo.final_error_m,
                vo.travelled_m,
                vo.drift_percent
            )?;
            if vo.robot == "jumper" && !vo.rest_errors_m.is_empty() {
                let errors: Vec<String> =
                    vo.rest_errors_m.iter().map(|e| format!("{e:.2}")).collect();
                writeln!(
                    out,
                    "jumper error at rest after each hop, metres: {}",
                    errors.join(" ")
                )?;
            }
        }
        Ok(())
    }
}

/// One line on `contacts`: how many, what the rover was doing, and what the map said of the
/// rocks it met.
pub fn contacts_line<'a>(contacts: impl IntoIterator<Item = &'a JudgedContact>) -> String {
    let contacts: Vec<&JudgedContact> = contacts.into_iter().collect();
    let of_motion = |motion: &str| {
        contacts
            .iter()
            .filter(|contact| contact.motion == motion)
            .count()
    };
    let said: Vec<String> = MapVerdict::ALL
        .iter()
        .zip(count_by_verdict(contacts.iter().copied()))
        .filter(|(_, count)| *count > 0)
        .map(|(verdict, count)| format!("{} {count}", verdict.name()))
        .collect();
    let mut heights_m: Vec<f64> = contacts
        .iter()
        .filter_map(|contact| contact.rock_height_m)
        .collect();
    heights_m.sort_by(f64::total_cmp);
    let heights = match (heights_m.first(), heights_m.get(heights_m.len() / 2)) {
        (Some(lowest_m), Some(median_m)) => {
            format!("; rocks met: median {median_m:.2} m, lowest {lowest_m:.2} m")
        }
        _ => String::new(),
    };
    format!(
        "rock contacts: {} (driving {}, reversing {}, turning {}, unknown {}); the map held the rock met {}{heights}",
        contacts.len(),
        of_motion("driving"),
        of_motion("reversing"),
        of_motion("turning"),
        of_motion("unknown"),
        said.join(", ")
    )
}

/// The truth a mission is scored against, read from the run's config.
#[derive(Debug, Clone)]
pub struct MissionTruth {
    /// The scenario's A, world metres.
    pub start_m: Option<[f64; 2]>,
    /// The scenario's B, world metres.
    pub goal_m: Option<[f64; 2]>,
    /// The world's rocks, regenerated from the config (`None` when it cannot be).
    pub rocks: Option<Vec<RockFootprint>>,
    /// The footprints of the rocks the rover cannot climb, as the physics' collision hulls
    /// have them (what its body truly meets; their half-extent ellipses are off by the
    /// lumps, ±5 cm).
    pub rock_outlines: Option<Vec<RockOutline>>,
    /// The mapper's obstacle threshold, metres.
    pub traversable_height_m: f64,
    /// The rover's climb limit, metres.
    pub climbable_height_m: f64,
    /// The rover's inscribed radius, metres.
    pub inscribed_m: f64,
    /// Half the rover's footprint along and across its heading, metres.
    pub rover_half_extents_m: [f64; 2],
    /// The mapper's grid and inflation (`None` when its config is invalid).
    pub mapper: Option<MapperConfig>,
    /// The rover's camera (`None` when the camera config is invalid).
    pub rover_camera: Option<RoverCamera>,
    /// The ground's true slope on the mapper's grid (`None` when the world or the grid is
    /// invalid).
    pub slopes: Option<TrueSlopes>,
    /// The world as the rover's left camera renders it, for the cells it had in sight (`None`
    /// when the world or the camera is invalid).
    pub line_of_sight: Option<LineOfSight>,
}

/// Where the rover's camera sits and how wide it sees, for the cells it observed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoverCamera {
    /// Its position in the body frame (x forward, y left), metres.
    pub body_xy_m: [f64; 2],
    /// Its viewing direction about body z, radians.
    pub yaw_rad: f64,
    /// Half its horizontal field of view, radians.
    pub half_fov_rad: f64,
}

impl MissionTruth {
    /// Reads the scenario, the rocks, the rover's body and the mapper's rules from
    /// `config`; `None` when the world or the rover's body is invalid.
    pub fn from_config(config: &HopnavConfig) -> Option<Self> {
        let mut world: hopnav_world::WorldConfig =
            hopnav_config::parse_section(config, "world").ok()?;
        // Nothing here reads the texture; the coarsest atlas bakes in milliseconds.
        world.texture.texel_m = COARSEST_TEXEL_M;
        let body = hopnav_robot::RoverBody::from_config(config).ok()?;
        let mapper = hopnav_mapper::config::mapper_section(config).ok();
        let generated = hopnav_world::World::generate(&world).ok();
        let rocks = generated.as_ref().map(|world| {
            world
                .rocks()
                .iter()
                .map(|rock| RockFootprint {
                    center_m: [rock.center_m[0], rock.center_m[1]],
                    radius_m: rock.bounding_radius_m(),
                    height_m: rock.height_m,
                })
                .collect()
        });
        // Only the rocks the rover cannot climb are lethal; the others need no hull.
        let rock_outlines = generated.as_ref().map(|world| {
            world
                .rocks()
                .iter()
                .filter(|rock| rock.height_m > body.max_climbable_height_m)
                .map(|rock| RockOutline {
                    outline_m: hopnav_world::footprint::rock_outline_m(rock),
                    center_m: [rock.center_m[0], rock.center_m[1]],
                    height_m: rock.height_m,
                })
                .collect()
        });
        let slopes = generated.as_ref().and_then(|world| {
            let geometry = map_geometry(mapper.as_ref()?)?;
            Some(TrueSlopes::new(&geometry, &body, |x, y| {
                world.ground_height_at(x, y)
            }))
        });
        let rig = hopnav_robot::camera::CameraRig::from_config(config).ok();
        let line_of_sight = generated
            .as_ref()
            .zip(rig.as_ref())
            .and_then(|(world, rig)| {
                LineOfSight::new(world, &rig.rover, rig.rover_body_from_left())
                    .inspect_err(|error| eprintln!("warning: {error}"))
                    .ok()
            });
        Some(Self {
            start_m: world.scenario.start_m,
            goal_m: world.scenario.goal_m,
            rocks,
            rock_outlines,
            traversable_height_m: mapper
                .as_ref()
                .map_or(MapperConfig::default(), Clone::clone)
                .traversable_height_m,
            climbable_height_m: body.max_climbable_height_m,
            inscribed_m: body.inscribed_radius_m(),
            rover_half_extents_m: [
                0.5 * body.footprint_length_m(),
                0.5 * body.footprint_width_m(),
            ],
            mapper,
            rover_camera: rig.map(|camera| RoverCamera {
                body_xy_m: [
                    camera.rover_mount.position_m[0],
                    camera.rover_mount.position_m[1],
                ],
                yaw_rad: camera.rover_mount.yaw_rad,
                half_fov_rad: 0.5 * camera.rover.hfov_rad,
            }),
            slopes,
            line_of_sight,
        })
    }

    /// The mapper's grid, as the planner places it (`None` when the mapper config is invalid).
    pub fn map_geometry(&self) -> Option<MapGeometry> {
        map_geometry(self.mapper.as_ref()?)
    }
}

/// The grid of `mapper`, as the planner places it (`None` when it is invalid).
fn map_geometry(mapper: &MapperConfig) -> Option<MapGeometry> {
    let grid = hopnav_mapper::config::grid_geometry(mapper).ok()?;
    MapGeometry::new(
        grid.origin_x_m,
        grid.origin_y_m,
        grid.cell_size_m,
        grid.width_cells,
        grid.height_cells,
    )
    .ok()
}

/// Scores `record` against `truth`.
pub fn evaluate(truth: &MissionTruth, record: &MissionRecord) -> MissionEvaluation {
    let distance = |a: Option<[f64; 2]>, b: Option<[f64; 2]>| match (a, b) {
        (Some(a), Some(b)) => Some((a[0] - b[0]).hypot(a[1] - b[1])),
        _ => None,
    };
    let rocks = truth.rocks.as_deref();
    let judged = judge_blocked_area(truth, record);
    MissionEvaluation {
        straight_line_m: distance(truth.start_m, truth.goal_m),
        final_distance_to_goal_m: distance(truth.goal_m, record.last_rover_m),
        full_knowledge_path_m: rocks
            .and_then(|rocks| full_knowledge(truth, rocks))
            .map(|path| path.length_m),
        built_map_path_m: built_map_path(truth, record).map(|path| path.length_m),
        map_accuracy: rocks.and_then(|rocks| {
            let map = record.map.as_ref()?;
            Some(score_map(truth, map, &record.rover_track_m, rocks))
        }),
        vo: record
            .vo
            .iter()
            .filter_map(|vo| accuracy(vo.robot, vo.track.pairs()))
            .collect(),
        blocked_area: judged.in_sight,
        blocked_area_in_view: judged.in_view,
        blocked_area_map_frame: judged.in_sight_map_frame,
        blocked_area_near_track: judged.near_track,
        contacts: judge_mission_contacts(truth, record),
    }
}

/// The record's contacts judged against the true rocks (none when the world cannot be
/// regenerated). The contacts' cells are on the published map's grid; without a map they
/// hold none, and every rock met is unseen.
fn judge_mission_contacts(truth: &MissionTruth, record: &MissionRecord) -> Vec<JudgedContact> {
    let Some(rocks) = truth.rock_outlines.as_deref() else {
        return Vec::new();
    };
    let grid = record.map.as_ref().map_or(
        ContactGrid {
            origin_m: (0.0, 0.0),
            cell_size_m: 1.0,
        },
        |map| ContactGrid {
            origin_m: map.origin_m,
            cell_size_m: map.cell_size_m,
        },
    );
    judge_contacts(&record.contacts, rocks, grid, truth.rover_half_extents_m)
}

/// The planner's path from A to B had it known from the start every rock the rover cannot
/// climb.
fn full_knowledge(truth: &MissionTruth, rocks: &[RockFootprint]) -> Option<FullKnowledgePath> {
    let mapper = truth.mapper.as_ref()?;
    let geometry = truth.map_geometry()?;
    // The mapper's own kernel: the full-knowledge path is planned with the same cost model.
    let kernel = hopnav_mapper::inflation::kernel_for(mapper, geometry.cell_size_m());
    full_knowledge_path(
        rocks,
        truth.climbable_height_m,
        truth.slopes.as_ref().map_or(&[][..], TrueSlopes::classes),
        &geometry,
        &kernel,
        truth.start_m?,
        truth.goal_m?,
    )
}

/// The planner's path from A to B had it known from the start the final map, classed as the
/// planner classes the mapper's cells (a lethal margin, and a rock only the jumper saw, are
/// doubtful obstacles).
fn built_map_path(truth: &MissionTruth, record: &MissionRecord) -> Option<FullKnowledgePath> {
    let geometry = truth.map_geometry()?;
    let width = geometry.width_cells() as usize;
    let rover_bit = 1u32 << Robot::Rover.code();
    let mut known =
        vec![KnownCell::Free { extra_cost: 0 }; width * geometry.height_cells() as usize];
    for cell in record.map.iter().flat_map(|map| &map.cells) {
        let Some(slot) = known.get_mut(cell.y as usize * width + cell.x as usize) else {
            continue;
        };
        *slot = match cell.class {
            CellClass::Obstacle if cell.observed_by & rover_bit != 0 => KnownCell::Obstacle,
            CellClass::Obstacle | CellClass::Lethal => KnownCell::Doubtful,
            CellClass::Unknown | CellClass::Free | CellClass::Inflated | CellClass::Uncertain => {
                KnownCell::Free {
                    extra_cost: cell.extra_cost,
                }
            }
        };
    }
    plan_on_known_map(&known, &geometry, truth.start_m?, truth.goal_m?)
}

/// The final map's obstacles against the world's rocks.
fn score_map(
    truth: &MissionTruth,
    map: &RecordedMap,
    rover_track_m: &[(f64, f64)],
    rocks: &[RockFootprint],
) -> MapAccuracy {
    let rover_bit = 1u32 << Robot::Rover.code();
    let jumper_bit = 1u32 << Robot::Jumper.code();
    let size_m = map.cell_size_m;
    let cells: Vec<ObstacleCell> = map
        .cells
        .iter()
        .filter(|cell| cell.class == CellClass::Obstacle)
        .map(|cell| ObstacleCell {
            center_m: [
                map.origin_m.0 + (f64::from(cell.x) + 0.5) * size_m,
                map.origin_m.1 + (f64::from(cell.y) + 0.5) * size_m,
            ],
            by_rover: cell.observed_by & rover_bit != 0,
            by_jumper: cell.observed_by & jumper_bit != 0,
        })
        .collect();
    let track_m: Vec<[f64; 2]> = rover_track_m.iter().map(|&(x, y)| [x, y]).collect();
    map_accuracy::evaluate(
        rocks,
        &cells,
        &track_m,
        size_m,
        truth.traversable_height_m - HEIGHT_TOLERANCE_M,
        truth.climbable_height_m,
    )
}
