//! Error types: one small enum per fallible operation, every variant documented.

use thiserror::Error;

/// A configuration value was rejected by [`PhysicsConfig::validate`](crate::PhysicsConfig::validate).
///
/// The message always names the full dotted key and the allowed range, e.g.
/// `physics.jumper.launch_speed_mps = 14 is out of range: allowed [0.5, 12] (bounds:
/// physics.jumper.min_launch_speed_mps, physics.jumper.max_launch_speed_mps)`.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// A value lies outside its allowed range (or is not finite).
    #[error("{key} = {value} is out of range: allowed {range}{}", bound_note(.bound_keys))]
    OutOfRange {
        /// Full dotted key, e.g. `physics.jumper.launch_speed_mps`.
        key: String,
        /// The rejected value as written.
        value: String,
        /// Allowed range in interval notation, e.g. `(0, 12]`.
        range: String,
        /// Keys whose values set the bounds (empty when the bounds are fixed).
        bound_keys: Vec<String>,
    },
}

fn bound_note(keys: &[String]) -> String {
    if keys.is_empty() {
        String::new()
    } else {
        format!(" (bounds: {})", keys.join(", "))
    }
}

/// Building a [`PhysicsSim`](crate::PhysicsSim) failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PhysicsError {
    /// The physics configuration did not validate.
    #[error("invalid physics config: {0}")]
    InvalidConfig(#[from] ConfigError),
    /// A start position lies outside the terrain grid.
    #[error(
        "{key} = [{x_m}, {y_m}] lies outside the terrain (x in [{min_x_m}, {max_x_m}], y in [{min_y_m}, {max_y_m}])"
    )]
    StartOutsideTerrain {
        /// Dotted config key of the start position.
        key: String,
        /// Requested x, metres.
        x_m: f64,
        /// Requested y, metres.
        y_m: f64,
        /// Smallest allowed x (terrain border plus the body's footprint), metres.
        min_x_m: f64,
        /// Largest allowed x, metres.
        max_x_m: f64,
        /// Smallest allowed y, metres.
        min_y_m: f64,
        /// Largest allowed y, metres.
        max_y_m: f64,
    },
    /// A body's start pose intersects a rock (taller than the rover can climb, for the rover).
    #[error(
        "{key} = [{x_m}, {y_m}] starts inside a rock (rock #{rock_index} at [{rock_x_m}, {rock_y_m}], {rock_height_m} m high); move the start or the rock"
    )]
    StartInsideRock {
        /// Dotted config key of the start position.
        key: String,
        /// Requested x, metres.
        x_m: f64,
        /// Requested y, metres.
        y_m: f64,
        /// Index of the rock in [`World::rocks`](hopnav_world::World::rocks).
        rock_index: usize,
        /// Rock centre x, metres.
        rock_x_m: f64,
        /// Rock centre y, metres.
        rock_y_m: f64,
        /// Rock height, metres.
        rock_height_m: f64,
    },
    /// The jumper and the rover start on top of each other.
    #[error("jumper and rover start {distance_m} m apart; at least {min_distance_m} m is needed")]
    StartsOverlap {
        /// Horizontal distance between the two start positions, metres.
        distance_m: f64,
        /// Smallest distance that keeps the bodies apart, metres.
        min_distance_m: f64,
    },
}

/// The physics benchmark could not run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BenchError {
    /// The world could not be generated.
    #[error("world: {0}")]
    World(#[from] hopnav_world::WorldError),
    /// The simulation could not be built.
    #[error("physics: {0}")]
    Physics(#[from] PhysicsError),
}
