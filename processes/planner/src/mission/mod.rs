//! The rover's side of the mission, without IPC: follow the D* Lite path from A to B over the
//! map the mapper publishes, and ask the jumper to scout where the rover cannot see.
//!
//! - [`geometry`]: world metres ↔ grid cells.
//! - [`bumper`]: a rover that neither moves nor turns is stuck against something unmapped:
//!   back it off and mark the cell ahead.
//! - [`navigator`]: replans on map changes and rover motion, picks the next waypoint, decides
//!   when the goal is reached or unreachable.
//! - [`route_change`]: whether a replan moved the route or only re-priced it.
//! - [`scout`]: the paper's cooperative rule: when the path runs into unknown cells beyond the
//!   rover's sensing range or behind an obstacle, request a hop that flies over them.
//! - [`scout_batch`]: a hop's jumper-only cells, held until its clouds stop coming.
//!
//! ```
//! use hopnav_planner::mission::{MapGeometry, Navigator, NavigatorConfig, RoverPose};
//! let geometry = MapGeometry::new(-8.0, -8.0, 0.5, 32, 32)?;
//! let mut navigator = Navigator::new(geometry, [-6.0, 0.0], [6.0, 0.0], NavigatorConfig::default())?;
//! let rover = RoverPose { xy_m: [-6.0, 0.0], yaw_rad: 0.0 };
//! let decision = navigator.step(rover, None, 0.0)?;
//! assert!(decision.waypoint_m[0] > -6.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod bumper;
mod config;
mod geometry;
mod navigator;
mod route_change;
mod scout;
mod scout_batch;

pub use bumper::{Bumper, BumperEvent, RoverPose};
pub use config::{NavigatorConfig, ScoutConfig};
pub use geometry::{GeometryError, MapGeometry};
pub use navigator::{
    DOUBTFUL_OBSTACLE_COST, Decision, MapChange, MissionStatus, NavigationError, Navigator,
    NavigatorCounters,
};
pub use route_change::{ROUTE_TOLERANCE_CELLS, route_moved};
pub use scout::{ScoutDecision, find_region_of_interest};
pub use scout_batch::{SCOUT_BATCH_MAX_AGE_S, SCOUT_BATCH_QUIET_S};
