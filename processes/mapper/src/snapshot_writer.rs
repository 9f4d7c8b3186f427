//! Writes map snapshots on a helper thread, so encoding (≈ 20 ms for a 128 × 128 map) and file
//! I/O stay out of the frame: the frame only copies the cell statistics into a buffer
//! allocated at start, and after the first snapshot only the cells changed since the last
//! one (the buffer comes back from the thread holding that snapshot).
//!
//! One snapshot is in flight at a time; a request while the writer is busy is refused and the
//! caller simply tries again at its next period.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};
use std::thread::JoinHandle;

use crate::belief::CellBelief;
use crate::cell::CellStats;
use crate::dome_layer::CellPoints;
use crate::map::FeatureMap;
use crate::snapshot;

/// One snapshot's worth of buffers, passed to the writer and back.
struct Job {
    geometry: crate::geometry::GridGeometry,
    counters: crate::map::MapCounters,
    stats: Vec<CellStats>,
    beliefs: Vec<CellBelief>,
    dome_points: Vec<(u32, CellPoints)>,
    bytes: Vec<u8>,
    /// `stats` and `beliefs` hold the map as of the last request (not yet at the start).
    holds_last_request: bool,
}

/// Background snapshot writer of one map file.
#[derive(Debug)]
pub struct SnapshotWriter {
    to_worker: Option<SyncSender<Job>>,
    from_worker: Receiver<Job>,
    spare: Option<Job>,
    worker: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Job {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job")
            .field("cells", &self.stats.len())
            .finish()
    }
}

impl SnapshotWriter {
    /// A writer of snapshots of `map` (sized for it) to `path`. Errors only if the thread
    /// cannot be started.
    pub fn new(map: &FeatureMap, path: PathBuf) -> std::io::Result<Self> {
        let (to_worker, jobs) = sync_channel::<Job>(1);
        let (done, from_worker) = sync_channel::<Job>(1);
        let worker = std::thread::Builder::new()
            .name("mapper-snapshot".into())
            .spawn(move || {
                for mut job in jobs {
                    let written = snapshot::encode_parts(
                        &job.geometry,
                        job.counters,
                        &job.stats,
                        &job.beliefs,
                        &job.dome_points,
                        &mut job.bytes,
                    )
                    .and_then(|()| snapshot::write_file(&path, &job.bytes));
                    if let Err(error) = written {
                        // The map itself is fine; a missed snapshot only matters after a crash.
                        eprintln!("mapper: snapshot not written: {error}");
                    }
                    if done.send(job).is_err() {
                        break;
                    }
                }
            })?;
        let cells = map.stats_slice().len();
        Ok(Self {
            to_worker: Some(to_worker),
            from_worker,
            spare: Some(Job {
                geometry: *map.geometry(),
                counters: map.counters(),
                stats: vec![CellStats::default(); cells],
                beliefs: map
                    .beliefs()
                    .map_or_else(Vec::new, |layer| layer.beliefs().to_vec()),
                dome_points: Vec::new(),
                bytes: Vec::with_capacity(size_of_val(map.stats_slice()) + 4096),
                holds_last_request: false,
            }),
            worker: Some(worker),
        })
    }

    /// Hands a copy of `map` to the writer; `false` if the previous snapshot is still being
    /// written (nothing is copied then). Every request must come from the map the writer was
    /// made for: the copy is brought up to date with the cells changed since the last one.
    pub fn request(&mut self, map: &mut FeatureMap) -> bool {
        let Some(to_worker) = &self.to_worker else {
            return false;
        };
        let Some(mut job) = self
            .spare
            .take()
            .or_else(|| self.from_worker.try_recv().ok())
        else {
            return false;
        };
        if !map.refresh_copy(&mut job.stats, &mut job.beliefs, !job.holds_last_request) {
            self.spare = Some(job);
            return false;
        }
        job.holds_last_request = true;
        match map.domes() {
            Some(domes) => domes.stored_points_into(&mut job.dome_points),
            None => job.dome_points.clear(),
        }
        job.geometry = *map.geometry();
        job.counters = map.counters();
        match to_worker.try_send(job) {
            Ok(()) => true,
            Err(TrySendError::Full(job) | TrySendError::Disconnected(job)) => {
                self.spare = Some(job);
                false
            }
        }
    }

    /// Waits until every requested snapshot is on disk and stops the thread.
    pub fn finish(&mut self) {
        self.to_worker = None;
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

impl Drop for SnapshotWriter {
    fn drop(&mut self) {
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use hopnav_ipc::messages::{FeaturePoint, Robot};

    use super::*;
    use crate::config::{MapperConfig, ObstacleModel};

    fn traversability_map() -> FeatureMap {
        FeatureMap::sixteen_m_square(&MapperConfig {
            obstacle_model: ObstacleModel::Traversability,
            cell_size_m: 0.25,
            ..MapperConfig::default()
        })
    }

    /// Rover stereo points on a 10 cm lattice over `[x0, x1] × [-1, 1]`, with a `height_m`
    /// bump over `x ∈ [2, 2.3]`.
    fn rover_cloud((x0, x1): (f32, f32), height_m: f32) -> Vec<FeaturePoint> {
        let mut cloud = Vec::new();
        for i in 0..=((x1 - x0) / 0.1).round() as i32 {
            for j in -10..=10 {
                let (x, y) = (x0 + 0.1 * i as f32, 0.1 * j as f32);
                let h = if (2.0..=2.3).contains(&x) {
                    height_m
                } else {
                    0.0
                };
                cloud.push(FeaturePoint {
                    position_m: [x, y, h],
                    height_above_ground_m: h,
                    depth_sigma_m: 0.02,
                    ..FeaturePoint::default()
                });
            }
        }
        cloud
    }

    fn encoded(map: &FeatureMap, stats: &[CellStats], beliefs: &[CellBelief]) -> Vec<u8> {
        let mut bytes = Vec::new();
        snapshot::encode_parts(
            map.geometry(),
            map.counters(),
            stats,
            beliefs,
            &[],
            &mut bytes,
        )
        .expect("encode");
        bytes
    }

    #[test]
    fn a_copy_refreshed_with_the_changed_cells_equals_the_map() {
        let mut map = traversability_map();
        let cells = map.stats_slice().len();
        let layer = |map: &FeatureMap| map.beliefs().expect("layer").beliefs().to_vec();
        let (mut stats, mut beliefs) = (vec![CellStats::default(); cells], layer(&map));
        let camera = Some([0.0, 0.0, 1.0]);
        map.insert_cloud_seen_from(Robot::Rover, camera, &rover_cloud((0.5, 3.0), 0.4));
        map.update();
        assert!(
            map.refresh_copy(&mut stats, &mut beliefs, false),
            "first: whole"
        );
        let first = encoded(&map, &stats, &beliefs);
        // The same ground, the rock gone: rays clear beliefs in cells with no new point.
        // The second cloud is not yet classified when the copy is refreshed.
        map.insert_cloud_seen_from(Robot::Rover, camera, &rover_cloud((2.4, 4.0), 0.0));
        map.update();
        map.insert_cloud_seen_from(Robot::Rover, camera, &rover_cloud((0.5, 3.0), 0.0));
        // A cell the changes did not reach: a refresh that copied it would overwrite this.
        stats[0].count = 77;
        assert!(map.refresh_copy(&mut stats, &mut beliefs, false));
        assert_eq!(stats[0].count, 77, "an unchanged cell was copied");
        stats[0].count = map.stats_slice()[0].count;
        let map_beliefs = layer(&map);
        assert_eq!(
            encoded(&map, &stats, &beliefs),
            encoded(&map, map.stats_slice(), &map_beliefs)
        );
        assert_ne!(first, encoded(&map, &stats, &beliefs), "nothing changed");
    }

    #[test]
    fn a_copy_of_another_size_is_refused_and_the_next_is_whole() {
        let mut map = traversability_map();
        let cells = map.stats_slice().len();
        let layer_len = map.beliefs().expect("layer").beliefs().len();
        let fresh = || {
            (
                vec![CellStats::default(); cells],
                vec![CellBelief::default(); layer_len],
            )
        };
        // A first copy taken and the cloud's cells classified: nothing is pending.
        map.insert_cloud(Robot::Rover, &rover_cloud((0.5, 1.0), 0.0));
        map.update();
        let (mut stats, mut beliefs) = fresh();
        assert!(map.refresh_copy(&mut stats, &mut beliefs, false));
        // Copies of the wrong size, of stats or of beliefs, are refused ...
        assert!(!map.refresh_copy(&mut [CellStats::default(); 3], &mut beliefs, false));
        assert!(!map.refresh_copy(&mut stats, &mut [CellBelief::default(); 3], false));
        // ... and the next copy is whole: a fresh buffer gets the first cloud's cells too.
        map.insert_cloud(Robot::Rover, &rover_cloud((2.0, 2.5), 0.0));
        map.update();
        let (mut stats, mut beliefs) = fresh();
        assert!(map.refresh_copy(&mut stats, &mut beliefs, false));
        assert_eq!(stats, map.stats_slice());
    }

    #[test]
    fn incremental_snapshots_restore_the_map_as_it_was() {
        let mut map = traversability_map();
        let dir = std::env::temp_dir().join(format!("hopnav-mapper-inc-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("map.bin");
        let mut writer = SnapshotWriter::new(&map, path.clone()).expect("thread");
        let camera = Some([0.0, 0.0, 1.0]);
        for (x_range, height_m) in [((0.5, 3.0), 0.4), ((2.4, 4.0), 0.0), ((0.5, 3.0), 0.0)] {
            map.insert_cloud_seen_from(Robot::Rover, camera, &rover_cloud(x_range, height_m));
            map.update();
            let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
            while !writer.request(&mut map) {
                assert!(
                    std::time::Instant::now() < deadline,
                    "the writer never took it"
                );
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
        }
        writer.finish();
        let mut restored = traversability_map();
        assert!(snapshot::restore_file(&mut restored, &path).expect("restore"));
        let (mut expected, mut got) = (Vec::new(), Vec::new());
        snapshot::encode(&map, &mut expected).expect("encode");
        snapshot::encode(&restored, &mut got).expect("encode");
        assert_eq!(got, expected);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn snapshots_written_in_the_background_restore() {
        let config = MapperConfig::default();
        let geometry = config.resolve_geometry((8.0, 8.0)).expect("valid");
        let mut map = FeatureMap::new(&config, geometry);
        let point = FeaturePoint {
            depth_sigma_m: 0.02,
            ..FeaturePoint::default()
        };
        map.insert_cloud(Robot::Rover, &[point; 5]);
        let dir = std::env::temp_dir().join(format!("hopnav-mapper-writer-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("map.bin");
        let mut writer = SnapshotWriter::new(&map, path.clone()).expect("thread");
        assert!(writer.request(&mut map));
        writer.finish();
        assert!(!writer.request(&mut map), "finished writers refuse work");
        let mut restored = FeatureMap::new(&config, geometry);
        assert!(snapshot::restore_file(&mut restored, &path).expect("restore"));
        assert_eq!(restored.counters().accepted, 5);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }
}
