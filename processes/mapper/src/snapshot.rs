//! Map snapshots: the cell statistics written to a file and read back, so a restarted mapper
//! keeps the map it had built (issue #7: recovery without loss).
//!
//! Encoding goes through [`hopnav_ipc::codec`] (the project's one serialization module).
//! Only the statistics are stored; classes, inflation and ground are recomputed on restore,
//! so a snapshot stays valid when thresholds change. The geometry must match. Only cells that
//! hold something are stored (with their index): a mission's map touches a few percent of its
//! grid, so a snapshot is about that share of the grid's size and restores in milliseconds. A
//! stored cell takes about 260 bytes; snapshots beyond the codec's 64 MiB decode limit are
//! refused at encoding ([`SnapshotError::TooLarge`]).
//!
//! ```
//! use hopnav_ipc::messages::{FeaturePoint, Robot};
//! use hopnav_mapper::{config::MapperConfig, map::FeatureMap, snapshot};
//! let config = MapperConfig::default();
//! let geometry = config.resolve_geometry((8.0, 8.0)).unwrap();
//! let mut map = FeatureMap::new(&config, geometry);
//! map.insert_cloud(Robot::Rover, &[FeaturePoint::default()]);
//! let mut bytes = Vec::new();
//! snapshot::encode(&map, &mut bytes).unwrap();
//! let mut restored = FeatureMap::new(&config, geometry);
//! snapshot::restore(&mut restored, &bytes).unwrap();
//! assert_eq!(restored.counters(), map.counters());
//! ```

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::belief::CellBelief;
use crate::cell::CellStats;
use crate::dome_layer::CellPoints;
use crate::geometry::GridGeometry;
use crate::map::{FeatureMap, MapCounters};

/// Version of the snapshot layout; bump when [`CellStats`], [`CellBelief`] or [`CellPoints`]
/// changes.
pub const SNAPSHOT_VERSION: u32 = 8;

/// Why a snapshot could not be written or restored.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    /// Encoding or decoding failed (corrupt or truncated file).
    #[error(transparent)]
    Codec(#[from] hopnav_ipc::codec::CodecError),
    /// The file could not be read or written.
    #[error("snapshot file {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The snapshot was written by another layout version.
    #[error("snapshot version {found}, expected {SNAPSHOT_VERSION}")]
    Version {
        /// Version in the file.
        found: u32,
    },
    /// The map is too large for the codec's decode limit: it could not be read back.
    #[error("snapshot of {bytes} bytes exceeds the codec limit of {limit} bytes")]
    TooLarge {
        /// Encoded size.
        bytes: usize,
        /// [`hopnav_ipc::codec::MAX_DECODE_BYTES`].
        limit: usize,
    },
    /// A stored cell lies outside the grid (a corrupt file).
    #[error("snapshot cell {index} outside the grid of {cells} cells")]
    CellOutOfGrid {
        /// The cell index in the file.
        index: u32,
        /// Cells in the grid.
        cells: usize,
    },
    /// The snapshot's grid differs from the map's.
    #[error("snapshot grid {found:?} differs from the configured grid {expected:?}")]
    Geometry {
        /// Grid in the file.
        found: GridGeometry,
        /// Grid of the map.
        expected: GridGeometry,
    },
}

#[derive(Serialize)]
struct SnapshotRef<'a> {
    version: u32,
    geometry: GridGeometry,
    counters: MapCounters,
    /// The cells whose statistics differ from the empty cell's, by index.
    stats: Vec<(u32, &'a CellStats)>,
    /// The `traversability` model keeps beliefs (false under the `features` model).
    has_beliefs: bool,
    /// The cells whose belief differs from the prior, by index.
    beliefs: Vec<(u32, &'a CellBelief)>,
    /// The fitted rocks' points by cell (empty without the fit).
    dome_points: &'a [(u32, CellPoints)],
}

#[derive(Deserialize)]
struct SnapshotOwned {
    version: u32,
    geometry: GridGeometry,
    counters: MapCounters,
    stats: Vec<(u32, CellStats)>,
    has_beliefs: bool,
    beliefs: Vec<(u32, CellBelief)>,
    dome_points: Vec<(u32, CellPoints)>,
}

/// The entries of `cells` that differ from `empty`, by index.
fn non_empty<'a, T: PartialEq>(cells: &'a [T], empty: &T) -> Vec<(u32, &'a T)> {
    cells
        .iter()
        .enumerate()
        .filter(|(_, cell)| *cell != empty)
        .map(|(index, cell)| (index as u32, cell))
        .collect()
}

/// `cell_count` empty cells with the stored ones put back; an index outside the grid is an
/// error.
fn expand<T: Copy>(
    stored: &[(u32, T)],
    empty: T,
    cell_count: usize,
) -> Result<Vec<T>, SnapshotError> {
    let mut cells = vec![empty; cell_count];
    for &(index, cell) in stored {
        let slot = cells
            .get_mut(index as usize)
            .ok_or(SnapshotError::CellOutOfGrid {
                index,
                cells: cell_count,
            })?;
        *slot = cell;
    }
    Ok(cells)
}

/// Encodes the map's statistics into `buffer` (cleared first; its allocation is reused).
pub fn encode(map: &FeatureMap, buffer: &mut Vec<u8>) -> Result<(), SnapshotError> {
    let beliefs = map.beliefs().map_or(&[][..], |layer| layer.beliefs());
    let mut dome_points = Vec::new();
    if let Some(domes) = map.domes() {
        domes.stored_points_into(&mut dome_points);
    }
    encode_parts(
        map.geometry(),
        map.counters(),
        map.stats_slice(),
        beliefs,
        &dome_points,
        buffer,
    )
}

/// Encodes a copy of a map's statistics (see [`crate::snapshot_writer`]).
pub(crate) fn encode_parts(
    geometry: &GridGeometry,
    counters: MapCounters,
    stats: &[CellStats],
    beliefs: &[CellBelief],
    dome_points: &[(u32, CellPoints)],
    buffer: &mut Vec<u8>,
) -> Result<(), SnapshotError> {
    let snapshot = SnapshotRef {
        version: SNAPSHOT_VERSION,
        geometry: *geometry,
        counters,
        stats: non_empty(stats, &CellStats::default()),
        has_beliefs: !beliefs.is_empty(),
        beliefs: non_empty(beliefs, &CellBelief::default()),
        dome_points,
    };
    hopnav_ipc::codec::encode_into(&snapshot, buffer)?;
    let limit = hopnav_ipc::codec::MAX_DECODE_BYTES;
    if buffer.len() > limit {
        return Err(SnapshotError::TooLarge {
            bytes: buffer.len(),
            limit,
        });
    }
    Ok(())
}

/// Replaces the statistics of `map` by the snapshot in `bytes`; the next
/// [`FeatureMap::update`] reclassifies every observed cell. On error `map` is unchanged.
pub fn restore(map: &mut FeatureMap, bytes: &[u8]) -> Result<(), SnapshotError> {
    let snapshot: SnapshotOwned = hopnav_ipc::codec::decode(bytes)?;
    if snapshot.version != SNAPSHOT_VERSION {
        return Err(SnapshotError::Version {
            found: snapshot.version,
        });
    }
    let expected = *map.geometry();
    if snapshot.geometry != expected {
        return Err(SnapshotError::Geometry {
            found: snapshot.geometry,
            expected,
        });
    }
    let cell_count = expected.cell_count();
    let stats = expand(&snapshot.stats, CellStats::default(), cell_count)?;
    // A snapshot of the other obstacle model has no beliefs (or the map keeps none): the
    // beliefs then start empty and the statistics alone come back.
    let beliefs = if snapshot.has_beliefs {
        expand(&snapshot.beliefs, CellBelief::default(), cell_count)?
    } else {
        Vec::new()
    };
    map.set_stats(&stats, snapshot.counters);
    map.set_beliefs(&beliefs);
    map.set_dome_points(&snapshot.dome_points);
    Ok(())
}

/// Writes `buffer` to `path` atomically (a temporary file, then a rename).
pub fn write_file(path: &Path, buffer: &[u8]) -> Result<(), SnapshotError> {
    let io = |source| SnapshotError::Io {
        path: path.display().to_string(),
        source,
    };
    let temporary = path.with_extension("tmp");
    std::fs::write(&temporary, buffer).map_err(io)?;
    std::fs::rename(&temporary, path).map_err(io)
}

/// Restores `map` from the file at `path`; `Ok(false)` when there is no such file.
pub fn restore_file(map: &mut FeatureMap, path: &Path) -> Result<bool, SnapshotError> {
    match std::fs::read(path) {
        Ok(bytes) => restore(map, &bytes).map(|()| true),
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => Ok(false),
        Err(source) => Err(SnapshotError::Io {
            path: path.display().to_string(),
            source,
        }),
    }
}

#[cfg(test)]
mod tests {
    use hopnav_ipc::messages::{CellClass, FeaturePoint, Robot};

    use super::*;
    use crate::config::{MapperConfig, ObstacleModel};

    /// The first rule's statistics (the `traversability` model's beliefs and rocks have their
    /// own snapshot test in `traversability_tests.rs`).
    fn config() -> MapperConfig {
        MapperConfig {
            obstacle_model: ObstacleModel::Features,
            ..MapperConfig::default()
        }
    }

    fn map_with_rock() -> FeatureMap {
        let config = config();
        let mut map = FeatureMap::new(&config, config.resolve_geometry((8.0, 8.0)).unwrap());
        let mut cloud = Vec::new();
        for i in 0..40 {
            for j in 0..40 {
                let (x, y) = (-2.0 + i as f32 * 0.1, -2.0 + j as f32 * 0.1);
                let rock = (0.0..0.5).contains(&x) && (0.0..0.5).contains(&y);
                cloud.push(FeaturePoint {
                    position_m: [x, y, 0.2 * x + if rock { 0.5 } else { 0.0 }],
                    height_above_ground_m: f32::NAN,
                    ..FeaturePoint::default()
                });
            }
        }
        // Two keyframes see the rock (one cloud alone never makes an obstacle).
        map.insert_cloud(Robot::Jumper, &cloud);
        map.insert_cloud(Robot::Jumper, &cloud);
        map.update();
        map
    }

    #[test]
    fn restore_rebuilds_the_same_map() {
        let mut original = map_with_rock();
        let mut original_changes = Vec::new();
        original.collect_changes(&mut original_changes);
        let mut bytes = Vec::new();
        encode(&original, &mut bytes).unwrap();

        let config = config();
        let mut restored = FeatureMap::new(&config, *original.geometry());
        restore(&mut restored, &bytes).unwrap();
        restored.update();
        let mut restored_changes = Vec::new();
        restored.collect_changes(&mut restored_changes);
        let key = |c: &hopnav_ipc::messages::CellUpdate| (c.y, c.x);
        original_changes.sort_by_key(key);
        restored_changes.sort_by_key(key);
        assert_eq!(original_changes, restored_changes);
        assert!(
            original_changes
                .iter()
                .any(|c| c.class == CellClass::Obstacle.code())
        );
        assert_eq!(restored.counters(), original.counters());
    }

    #[test]
    fn a_restored_map_knows_which_clouds_it_already_holds() {
        let mut original = map_with_rock();
        original.note_cloud_frame(Robot::Rover, 435);
        original.note_cloud_frame(Robot::Jumper, 409);
        let mut bytes = Vec::new();
        encode(&original, &mut bytes).unwrap();
        let mut restored = FeatureMap::new(&config(), *original.geometry());
        assert_eq!(restored.last_cloud_frame(Robot::Rover), None);
        restore(&mut restored, &bytes).unwrap();
        assert_eq!(restored.last_cloud_frame(Robot::Rover), Some(435));
        assert_eq!(restored.last_cloud_frame(Robot::Jumper), Some(409));
    }

    #[test]
    fn corrupt_or_foreign_snapshots_are_refused() {
        let map = map_with_rock();
        let mut bytes = Vec::new();
        encode(&map, &mut bytes).unwrap();
        let config = config();
        let mut other = FeatureMap::new(&config, config.resolve_geometry((9.0, 8.0)).unwrap());
        assert!(matches!(
            restore(&mut other, &bytes),
            Err(SnapshotError::Geometry { .. })
        ));
        let mut same = FeatureMap::new(&config, *map.geometry());
        assert!(restore(&mut same, &bytes[..bytes.len() / 2]).is_err());
        bytes[0] = 9;
        assert!(matches!(
            restore(&mut same, &bytes),
            Err(SnapshotError::Version { .. })
        ));
        assert_eq!(same.counters(), MapCounters::default());
    }

    #[test]
    fn only_cells_that_hold_something_are_stored_and_one_off_the_grid_is_refused() {
        let map = map_with_rock();
        let mut bytes = Vec::new();
        encode(&map, &mut bytes).unwrap();
        let whole_grid_bytes = size_of_val(map.stats_slice());
        assert!(
            // The rock's cloud covers about a fifth of this small grid.
            bytes.len() * 3 < whole_grid_bytes,
            "{} bytes for a grid of {whole_grid_bytes}",
            bytes.len()
        );
        // A file that stores a cell past the grid's end.
        let geometry = *map.geometry();
        let mut stats = map.stats_slice().to_vec();
        stats.push(CellStats {
            count: 1,
            ..CellStats::default()
        });
        encode_parts(&geometry, map.counters(), &stats, &[], &[], &mut bytes).unwrap();
        let mut restored = FeatureMap::new(&config(), geometry);
        assert!(matches!(
            restore(&mut restored, &bytes),
            Err(SnapshotError::CellOutOfGrid { .. })
        ));
        assert_eq!(restored.counters(), MapCounters::default());
    }

    #[test]
    fn files_round_trip_and_a_missing_file_is_no_error() {
        let dir = std::env::temp_dir().join(format!("hopnav-mapper-snap-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("map.bin");
        let map = map_with_rock();
        let mut bytes = Vec::new();
        encode(&map, &mut bytes).unwrap();
        write_file(&path, &bytes).unwrap();
        let config = config();
        let mut restored = FeatureMap::new(&config, *map.geometry());
        assert!(restore_file(&mut restored, &path).unwrap());
        assert!(!restore_file(&mut restored, &dir.join("none.bin")).unwrap());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
