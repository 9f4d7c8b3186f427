//! Mapper: merges both robots' feature clouds into a bounded grid map of obstacles,
//! inflation and observers, and publishes the changed cells.
//!
//! The algorithms are plain modules; the `mapper` process (`hopnav-mapper-node`) wires them
//! to iceoryx2.
//!
//! - [`geometry`]: the fixed grid of the mission area (by default the `[world.terrain]` square).
//! - [`cell`]: fixed-size statistics per cell (counts per robot, observers, measured heights,
//!   the few lowest ground points and highest features): memory never grows with the mission.
//! - [`ground`]: the local ground, a robust plane through the neighbourhood's lowest
//!   observations, for features whose producer could not measure their height (NaN).
//! - [`map`]: insertion, classification and the diff of changed cells. Under the default
//!   `traversability` model: a per-cell belief ([`belief`], [`traversability`], cleared along
//!   stereo rays by [`rays`]), rocks fitted as domes ([`dome`], [`dome_layer`]) and the
//!   rover's footprint inflation ([`inflation`]). Under the first rule (`features`): obstacle
//!   = at least `min_obstacle_support` features more than `traversable_height_m` above the
//!   local ground, voted by the jumper's clouds, with a lethal ring.
//! - [`oracle_prior`]: evaluation only, the clouds of a flawless scout (every true rock).
//! - [`snapshot`]: save and restore the statistics; [`view`]: read-only access for plots.
//!
//! ```
//! use hopnav_ipc::messages::{CellClass, FeaturePoint, Robot};
//! use hopnav_mapper::config::MapperConfig;
//! use hopnav_mapper::map::FeatureMap;
//!
//! let config = MapperConfig::default();
//! let geometry = config.resolve_geometry((16.0, 16.0)).expect("valid");
//! let mut map = FeatureMap::new(&config, geometry);
//! // Three rover features 0.5 m above the ground in the cell at (1.2, 1.2), in two keyframes.
//! let rock = FeaturePoint {
//!     position_m: [1.2, 1.2, 0.5],
//!     height_above_ground_m: 0.5,
//!     depth_sigma_m: 0.03,
//!     ..FeaturePoint::default()
//! };
//! map.insert_cloud(Robot::Rover, &[rock; 3]);
//! map.insert_cloud(Robot::Rover, &[rock; 3]);
//! map.update();
//! let mut changes = Vec::new();
//! map.collect_changes(&mut changes);
//! let (x, y) = geometry.cell_of(1.2, 1.2).expect("inside");
//! assert_eq!(map.cell_state(x, y).unwrap().class, CellClass::Obstacle);
//! assert!(changes.len() > 1, "the obstacle and its inflation ring");
//! ```
#![warn(missing_docs)]

pub mod belief;
pub mod cell;
pub mod config;
pub mod dirty;
pub mod dome;
pub mod dome_layer;
pub mod foot;
pub mod geometry;
pub mod ground;
pub mod inflation;
pub mod map;
pub mod oracle_prior;
pub mod rays;
pub mod slope;
pub mod snapshot;
pub mod snapshot_writer;
pub mod traversability;
pub mod view;
