//! Writes map snapshots on a helper thread, so encoding (≈ 20 ms for a 128 × 128 map) and file
//! I/O stay out of the frame: the frame only copies the cell statistics into a buffer
//! allocated at start.
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
            }),
            worker: Some(worker),
        })
    }

    /// Hands a copy of `map` to the writer; `false` if the previous snapshot is still being
    /// written (nothing is copied then).
    pub fn request(&mut self, map: &FeatureMap) -> bool {
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
        if job.stats.len() != map.stats_slice().len() {
            self.spare = Some(job);
            return false;
        }
        job.stats.copy_from_slice(map.stats_slice());
        if let Some(layer) = map.beliefs()
            && layer.beliefs().len() == job.beliefs.len()
        {
            job.beliefs.copy_from_slice(layer.beliefs());
        }
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
    use crate::config::MapperConfig;

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
        assert!(writer.request(&map));
        writer.finish();
        assert!(!writer.request(&map), "finished writers refuse work");
        let mut restored = FeatureMap::new(&config, geometry);
        assert!(snapshot::restore_file(&mut restored, &path).expect("restore"));
        assert_eq!(restored.counters().accepted, 5);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }
}
