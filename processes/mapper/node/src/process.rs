//! The `mapper` process: drains both robots' feature clouds every frame, merges them into the
//! [`FeatureMap`], and publishes the changed cells on `MAP_UPDATES`.
//!
//! The first frame always publishes a `MapHeader` (possibly with no cells) so the planner
//! learns the grid geometry; after that only frames with changes publish. A change set larger
//! than one sample goes out in several samples of the same frame. Every `snapshot_every_frames`
//! frames the map statistics are written (by a helper thread) next to the launch's config
//! file; a restarted mapper
//! restores them and republishes its whole map (issue #7). With `republish_every_frames` the
//! whole known map is also sent periodically, for a planner that restarted.

use std::path::Path;

use hopnav_config::HopnavConfig;
use hopnav_ipc::messages::{CellUpdate, CloudHeader, FeaturePoint, FrameTick, MapHeader, Robot};
use hopnav_ipc::node_error::NodeError;
use hopnav_ipc::process_loop::{Prepared, Process, ProcessContext, ProcessIdentity, take_prepared};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{SlicePublisher, SliceSubscriber};

use hopnav_mapper::config::{MapperConfig, grid_geometry, mapper_section};
use hopnav_mapper::geometry::GridGeometry;
use hopnav_mapper::map::{CellState, FeatureMap, cloud_slot};
use hopnav_mapper::oracle_prior::{OraclePriorError, perfect_scout_report};
use hopnav_mapper::snapshot;
use hopnav_mapper::snapshot_writer::SnapshotWriter;

/// File name of the map snapshot, in the launch's run folder.
pub const SNAPSHOT_FILE: &str = "mapper_snapshot.bin";

/// Why the mapper process failed: the shared node plumbing, or the oracle prior map could
/// not be made.
pub type MapperProcessError = NodeError<OraclePriorError>;

/// Merges the clouds and publishes map updates once per frame.
pub struct MapperProcess {
    config: MapperConfig,
    map: FeatureMap,
    jumper_clouds: SliceSubscriber<CloudHeader>,
    rover_clouds: SliceSubscriber<CloudHeader>,
    updates: SlicePublisher<MapHeader>,
    snapshot_topic: SlicePublisher<MapHeader>,
    changes: Vec<CellUpdate>,
    /// Every known cell, for the snapshot topic (preallocated for the whole grid).
    known_cells: Vec<CellUpdate>,
    changed_since_republish: bool,
    /// False in rover-only missions: the jumper's clouds are drained and ignored.
    accept_jumper_clouds: bool,
    header_sent: bool,
    wrong_robot_clouds: u64,
    snapshots: Option<SnapshotWriter>,
    changed_since_snapshot: bool,
    frames: u64,
    /// After a restore: the last cloud frames (`[jumper, rover]`) the snapshot holds; the
    /// cloud topics' history redelivers those and the later ones.
    restored_cloud_frames: [Option<u64>; 2],
    /// After a restore: steps left in which the cloud history is awaited (see `catch_up`).
    catching_up_steps: u32,
    /// Per robot (`[jumper, rover]`): some of its cloud history has arrived.
    history_seen: [bool; 2],
    /// Clouds taken in while catching up.
    caught_up_clouds: usize,
}

/// What a standby builds ahead of need: the configuration and the empty, grid-sized map
/// (allocating and zeroing it takes tens of milliseconds at the default grid).
struct EmptyMap {
    config: HopnavConfig,
    section: MapperConfig,
    map: FeatureMap,
}

impl EmptyMap {
    fn build(config_path: &Path) -> Result<Self, MapperProcessError> {
        let config = hopnav_config::load_file(config_path)?;
        let section = mapper_section(&config)?;
        let geometry = grid_geometry(&section)?;
        let map = FeatureMap::new(&section, geometry);
        Ok(Self {
            config,
            section,
            map,
        })
    }
}

/// Steps in which a restarted mapper takes its clouds in frame by frame (the history comes at
/// the publishers' next frame; a VO that is down too delays it).
const CATCH_UP_STEPS: u32 = 10;

impl MapperProcess {
    /// Takes in every cloud received since the last frame (the jumper's first, as always).
    fn drain(&mut self) -> Result<(), MapperProcessError> {
        for robot in [Robot::Jumper, Robot::Rover] {
            while let Some(cloud) = self.subscriber(robot).receive()? {
                let header = *cloud.header();
                if self.wanted(robot, &header) {
                    self.take_in(robot, &header, cloud.elements());
                }
            }
        }
        Ok(())
    }

    /// A restarted mapper's first clouds: the cloud topics' history, which holds clouds the
    /// snapshot already has and those published since. The later ones are taken in frame by
    /// frame, with the map's update after each frame as the uninterrupted mapper did it, so
    /// the map comes back as it would have been. (The history reaches a new subscriber at its
    /// publisher's next frame.)
    fn catch_up(&mut self) -> Result<(), MapperProcessError> {
        let mut history: Vec<(u64, Robot, CloudHeader, Vec<FeaturePoint>)> = Vec::new();
        for robot in [Robot::Jumper, Robot::Rover] {
            while let Some(cloud) = self.subscriber(robot).receive()? {
                let header = *cloud.header();
                let slot = cloud_slot(robot);
                if !self.history_seen[slot]
                    && let Some(mark) = self.restored_cloud_frames[slot]
                    && header.stamp.frame_index > mark.saturating_add(1)
                {
                    eprintln!(
                        "mapper: the {robot:?} cloud history starts at frame {}, after the \
                         snapshot's {mark}: clouds published in between, if any, are lost",
                        header.stamp.frame_index
                    );
                }
                self.history_seen[slot] = true;
                if self.wanted(robot, &header) {
                    history.push((
                        header.stamp.frame_index,
                        robot,
                        header,
                        cloud.elements().to_vec(),
                    ));
                }
            }
        }
        // Stable: within a frame the jumper's clouds stay first.
        history.sort_by_key(|(frame_index, ..)| *frame_index);
        let clouds_taken_in = history.len();
        for (index, (frame_index, robot, header, points)) in history.iter().enumerate() {
            self.take_in(*robot, header, points);
            // Between frames; the last frame's update is the caller's, as every frame.
            if history
                .get(index + 1)
                .is_some_and(|(next_frame, ..)| next_frame != frame_index)
            {
                self.map.update();
            }
        }
        self.caught_up_clouds += clouds_taken_in;
        Ok(())
    }

    fn subscriber(&self, robot: Robot) -> &SliceSubscriber<CloudHeader> {
        match robot {
            Robot::Jumper => &self.jumper_clouds,
            Robot::Rover => &self.rover_clouds,
        }
    }

    /// Whether a cloud on `robot`'s topic is to be taken in: from that robot, accepted in this
    /// mode, and not already in a restored snapshot. Counts clouds of the wrong robot.
    fn wanted(&mut self, robot: Robot, header: &CloudHeader) -> bool {
        if header.robot != robot.code() {
            self.wrong_robot_clouds += 1;
            return false;
        }
        if robot == Robot::Jumper && !self.accept_jumper_clouds {
            return false;
        }
        self.restored_cloud_frames[cloud_slot(robot)]
            .is_none_or(|last| header.stamp.frame_index > last)
    }

    fn take_in(&mut self, robot: Robot, header: &CloudHeader, points: &[FeaturePoint]) {
        self.map.note_cloud_frame(robot, header.stamp.frame_index);
        let camera_m = header.world_from_camera.position_m;
        if self
            .map
            .insert_cloud_seen_from(robot, Some(camera_m), points)
            > 0
        {
            self.changed_since_snapshot = true;
        }
    }

    fn publish(&mut self, tick: &FrameTick) -> Result<(), MapperProcessError> {
        let geometry = *self.map.geometry();
        let header = |count: usize| {
            move |header: &mut MapHeader| fill_map_header(header, tick, &geometry, count)
        };
        if self.changes.is_empty() {
            if !self.header_sent {
                self.updates
                    .send_from_fn(0, header(0), |_| CellUpdate::default())?;
                self.header_sent = true;
            }
            return Ok(());
        }
        let max_len = self.updates.max_len();
        for chunk in self.changes.chunks(max_len) {
            self.updates
                .send_from_fn(chunk.len(), header(chunk.len()), |index| chunk[index])?;
        }
        self.header_sent = true;
        Ok(())
    }

    /// Publishes every known cell on `MAP_SNAPSHOT` (one sample; the publisher holds the grid).
    fn publish_snapshot(&mut self, tick: &FrameTick) -> Result<(), MapperProcessError> {
        let geometry = *self.map.geometry();
        self.known_cells.clear();
        for y in 0..geometry.height_cells {
            for x in 0..geometry.width_cells {
                if let Some(state) = self.map.cell_state(x, y)
                    && state != CellState::default()
                {
                    self.known_cells.push(CellUpdate {
                        x,
                        y,
                        class: state.class.code(),
                        extra_cost: state.extra_cost,
                        observed_by: state.observed_by,
                        support: state.support,
                    });
                }
            }
        }
        let cells = &self.known_cells;
        self.snapshot_topic.send_from_fn(
            cells.len(),
            |header: &mut MapHeader| fill_map_header(header, tick, &geometry, cells.len()),
            |index| cells[index],
        )?;
        Ok(())
    }

    /// Hands a snapshot to the writer thread when one is due (`force`: at stop) and the map
    /// changed since the last one.
    fn maybe_snapshot(&mut self, force: bool) {
        let every = u64::from(self.config.snapshot_every_frames);
        let Some(writer) = &mut self.snapshots else {
            return;
        };
        let due = every > 0 && (force || self.frames.is_multiple_of(every));
        if due && self.changed_since_snapshot && writer.request(&mut self.map) {
            self.changed_since_snapshot = false;
        }
    }
}

/// Restores `map` from the snapshot at `path`; true if there was one.
fn restore_snapshot(map: &mut FeatureMap, path: &Path) -> bool {
    match snapshot::restore_file(map, path) {
        Ok(true) => {
            let marks = map.counters().last_cloud_frame;
            eprintln!(
                "mapper: map restored from {} (clouds up to frame {} of the jumper, {} \
                 of the rover; later ones come from the cloud topics' history)",
                path.display(),
                frame_text(marks[0]),
                frame_text(marks[1])
            );
            true
        }
        Ok(false) => false,
        Err(error) => {
            eprintln!("mapper: starting with an empty map: {error}");
            false
        }
    }
}

/// Puts the world's unclimbable rocks on `map`, as a perfect scout would report them
/// (evaluation only).
fn insert_oracle_prior(
    map: &mut FeatureMap,
    config: &HopnavConfig,
) -> Result<(), MapperProcessError> {
    let report = perfect_scout_report(config).map_err(NodeError::Own)?;
    let accepted = map.insert_cloud(Robot::Rover, &report.points);
    eprintln!(
        "mapper: oracle prior map (evaluation only): {accepted} points on the {} rocks \
         the rover cannot climb (of {})",
        report.rocks_reported, report.rocks_in_world
    );
    Ok(())
}

/// The writer of snapshots to `path`, or none (said) if its thread cannot start.
fn snapshot_writer(map: &FeatureMap, path: &Path) -> Option<SnapshotWriter> {
    match SnapshotWriter::new(map, path.to_path_buf()) {
        Ok(writer) => Some(writer),
        Err(error) => {
            eprintln!("mapper: no snapshots (writer thread: {error})");
            None
        }
    }
}

impl Process for MapperProcess {
    type Error = MapperProcessError;

    fn prepare(identity: &ProcessIdentity) -> Result<Prepared, MapperProcessError> {
        Ok(Prepared::new(EmptyMap::build(&identity.config_path)?))
    }

    fn new(context: &ProcessContext) -> Result<Self, MapperProcessError> {
        let EmptyMap {
            config,
            section,
            mut map,
        } = match take_prepared::<EmptyMap>() {
            Some(prepared) => prepared,
            None => EmptyMap::build(&context.identity.config_path)?,
        };
        let geometry = *map.geometry();
        let cells = geometry.cell_count();
        let node = &context.node;
        let snapshot_path = context
            .identity
            .config_path
            .parent()
            .map(|dir| dir.join(SNAPSHOT_FILE));
        // Only a restart restores: a first start in a reused run folder must not take the
        // previous launch's map.
        let restored = context.identity.incarnation > 0
            && snapshot_path
                .as_deref()
                .is_some_and(|path| restore_snapshot(&mut map, path));
        // A restored map already holds the oracle's points.
        if section.oracle_prior_map && !restored {
            insert_oracle_prior(&mut map, &config)?;
        }
        let snapshots = match (&snapshot_path, section.snapshot_every_frames) {
            (Some(path), 1..) => snapshot_writer(&map, path),
            _ => None,
        };
        let restored_cloud_frames = if restored {
            map.counters().last_cloud_frame
        } else {
            [None, None]
        };
        Ok(Self {
            updates: SlicePublisher::open(node, &topics::MAP_UPDATES, cells)?,
            snapshot_topic: SlicePublisher::open(node, &topics::MAP_SNAPSHOT, cells)?,
            known_cells: Vec::with_capacity(cells),
            // A restored map is published at once.
            changed_since_republish: true,
            accept_jumper_clouds: config.mission.mode == hopnav_config::MissionMode::Cooperative,
            jumper_clouds: SliceSubscriber::open(node, &topics::JUMPER_CLOUD)?,
            rover_clouds: SliceSubscriber::open(node, &topics::ROVER_CLOUD)?,
            changes: Vec::with_capacity(cells),
            config: section,
            map,
            header_sent: false,
            wrong_robot_clouds: 0,
            snapshots,
            changed_since_snapshot: false,
            frames: 0,
            restored_cloud_frames,
            catching_up_steps: if restored { CATCH_UP_STEPS } else { 0 },
            history_seen: [false; 2],
            caught_up_clouds: 0,
        })
    }

    fn step(
        &mut self,
        _context: &ProcessContext,
        tick: &FrameTick,
    ) -> Result<(), MapperProcessError> {
        if self.catching_up_steps > 0 {
            self.catch_up()?;
            self.catching_up_steps -= 1;
            if self.catching_up_steps == 0 {
                // Caught up: later clouds are all new (and frame indices need not grow).
                self.restored_cloud_frames = [None, None];
                eprintln!(
                    "mapper: took in {} clouds published since the snapshot, frame by frame",
                    self.caught_up_clouds
                );
            }
        } else {
            self.drain()?;
        }
        self.map.update();
        self.changes.clear();
        self.map.collect_changes(&mut self.changes);
        self.changed_since_republish |= !self.changes.is_empty();
        self.publish(tick)?;
        let every = u64::from(self.config.republish_every_frames);
        if every > 0 && self.frames.is_multiple_of(every) && self.changed_since_republish {
            self.publish_snapshot(tick)?;
            self.changed_since_republish = false;
        }
        self.frames += 1;
        self.maybe_snapshot(false);
        Ok(())
    }

    /// Samples refused whole, and points refused inside accepted clouds (non-finite, or a
    /// sigma that cannot weigh them).
    fn rejected_samples(&self) -> u64 {
        let points = self.map.counters();
        self.jumper_clouds.rejected().total()
            + self.rover_clouds.rejected().total()
            + self.wrong_robot_clouds
            + points.non_finite
            + points.bad_sigma
    }

    fn stop(&mut self, _context: &ProcessContext) {
        self.maybe_snapshot(true);
        if let Some(writer) = &mut self.snapshots {
            writer.finish();
        }
    }
}

fn frame_text(frame: Option<u64>) -> String {
    frame.map_or_else(|| "none".to_owned(), |frame| frame.to_string())
}

/// The header of a map sample of `count` cells on the grid `geometry`, for frame `tick`.
fn fill_map_header(
    header: &mut MapHeader,
    tick: &FrameTick,
    geometry: &GridGeometry,
    count: usize,
) {
    header.stamp.frame_index = tick.stamp.frame_index;
    header.stamp.sim_time_ns = tick.stamp.sim_time_ns;
    header.origin_x_m = geometry.origin_x_m;
    header.origin_y_m = geometry.origin_y_m;
    header.cell_size_m = geometry.cell_size_m;
    header.width_cells = geometry.width_cells;
    header.height_cells = geometry.height_cells;
    header.update_count = count as u32;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn section_defaults_cover_the_world_terrain() {
        let config = hopnav_config::load(None).expect("defaults");
        let section = mapper_section(&config).expect("valid");
        let geometry = grid_geometry(&section).expect("explicit");
        assert_eq!((geometry.origin_x_m, geometry.origin_y_m), (-32.0, -32.0));
        assert_eq!((geometry.width_cells, geometry.height_cells), (256, 256));
    }

    #[test]
    fn the_embedded_default_config_equals_the_code_defaults() {
        let config = hopnav_config::load(None).expect("ok");
        assert_eq!(config.processes["mapper"].stage, 3);
        // The section resolves the grid from the terrain; everything else is the default.
        let section = mapper_section(&config).expect("valid");
        let resolved = MapperConfig {
            origin_x_m: section.origin_x_m,
            origin_y_m: section.origin_y_m,
            width_cells: section.width_cells,
            height_cells: section.height_cells,
            ..MapperConfig::default()
        };
        assert_eq!(section, resolved);
    }

    #[test]
    fn section_errors_name_the_key_and_range() {
        let config = hopnav_config::load(Some("[mapper]\ncell_size_m = 0.0\n")).expect("toml");
        let error = mapper_section(&config).unwrap_err().to_string();
        assert!(error.contains("mapper.cell_size_m"), "{error}");
        assert!(error.contains("[0.05, 10]"), "{error}");
        let config = hopnav_config::load(Some("[mapper]\ncell_size = 0.5\n")).expect("toml");
        let error = mapper_section(&config).unwrap_err().to_string();
        assert!(error.contains("mapper.cell_size"), "{error}");
    }

    #[test]
    fn explicit_grid_keys_win_over_the_terrain() {
        let text =
            "[mapper]\norigin_x_m = 0.0\nwidth_cells = 10\n[world.terrain]\nsize_y_m = 32.0\n";
        let config = hopnav_config::load(Some(text)).expect("toml");
        let geometry = grid_geometry(&mapper_section(&config).expect("valid")).expect("grid");
        assert_eq!((geometry.origin_x_m, geometry.width_cells), (0.0, 10));
        assert_eq!((geometry.origin_y_m, geometry.height_cells), (-16.0, 128));
    }
}
