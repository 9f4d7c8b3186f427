//! Rocks: the Golombek background, clusters, explicit rocks and boulder fields.

use serde::{Deserialize, Serialize};

use super::{Interval, check_int, dotted_key, min_max_pair, rock_sizes};
use crate::error::ConfigError;

/// Rock population: Golombek background, clusters and explicit rocks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RockConfig {
    /// Golombek total rock abundance k (0.07 moderate, 0.16 rocky; 0 disables random rocks).
    pub golombek_k: f64,
    /// Smallest sampled rock diameter, metres.
    pub diameter_min_m: f64,
    /// Largest sampled rock diameter, metres.
    pub diameter_max_m: f64,
    /// Rock height over diameter (Golombek: ≈ 0.5).
    pub height_ratio: f64,
    /// Rock clusters placed in addition to the background population.
    pub clusters: Vec<RockClusterConfig>,
    /// Individual rocks at given positions.
    pub explicit: Vec<ExplicitRockConfig>,
    /// Arcs of boulders between the scenario's start and goal, placed from the seed.
    pub boulder_fields: BoulderFieldConfig,
}

impl Default for RockConfig {
    fn default() -> Self {
        Self {
            golombek_k: 0.07,
            diameter_min_m: 0.1,
            diameter_max_m: 2.0,
            height_ratio: 0.5,
            clusters: Vec::new(),
            explicit: Vec::new(),
            boulder_fields: BoulderFieldConfig::default(),
        }
    }
}

impl RockConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(0.0, 0.5).check(prefix, "golombek_k", self.golombek_k)?;
        rock_sizes(
            prefix,
            0.02,
            [self.diameter_min_m, self.diameter_max_m],
            self.height_ratio,
        )?;
        for (i, c) in self.clusters.iter().enumerate() {
            c.validate(&dotted_key(prefix, &format!("clusters[{i}]")))?;
        }
        for (i, r) in self.explicit.iter().enumerate() {
            r.validate(&dotted_key(prefix, &format!("explicit[{i}]")))?;
        }
        self.boulder_fields
            .validate(&dotted_key(prefix, "boulder_fields"))
    }
}

/// Boulder fields: arcs of large rocks between the scenario's start A and goal B, open
/// toward A, so the rover cannot see whether their back is closed (see
/// [`boulder_fields`](crate::boulder_fields)). Placed at random from the world seed; they need
/// `scenario.start_m` and `scenario.goal_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BoulderFieldConfig {
    /// Fields to place (0 = none).
    pub count: u32,
    /// Smallest arc radius, metres.
    pub radius_min_m: f64,
    /// Largest arc radius, metres.
    pub radius_max_m: f64,
    /// Angular width of the opening that faces A, radians.
    pub opening_rad: f64,
    /// Smallest boulder diameter, metres.
    pub diameter_min_m: f64,
    /// Largest boulder diameter, metres.
    pub diameter_max_m: f64,
    /// Boulder height over diameter.
    pub height_ratio: f64,
    /// Field centres lie up to this far to either side of the A–B line, metres.
    pub lateral_spread_m: f64,
}

impl Default for BoulderFieldConfig {
    fn default() -> Self {
        Self {
            count: 0,
            radius_min_m: 3.0,
            radius_max_m: 5.0,
            opening_rad: 100f64.to_radians(),
            diameter_min_m: 0.8,
            diameter_max_m: 1.4,
            height_ratio: 0.6,
            lateral_spread_m: 2.0,
        }
    }
}

impl BoulderFieldConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        check_int(prefix, "count", u64::from(self.count), 0, 20)?;
        min_max_pair(
            prefix,
            ("radius_min_m", self.radius_min_m),
            ("radius_max_m", self.radius_max_m),
            Interval::closed(0.5, 50.0),
        )?;
        Interval::closed(0.0, 6.0).check(prefix, "opening_rad", self.opening_rad)?;
        rock_sizes(
            prefix,
            0.1,
            [self.diameter_min_m, self.diameter_max_m],
            self.height_ratio,
        )?;
        Interval::closed(0.0, 100.0).check(prefix, "lateral_spread_m", self.lateral_spread_m)?;
        Ok(())
    }
}

/// A cluster of rocks inside an axis-aligned ellipse (e.g. a field that blocks the view).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RockClusterConfig {
    /// Ellipse centre (x, y), metres.
    pub center_m: [f64; 2],
    /// Ellipse half-axes along x and y, metres.
    pub half_extents_m: [f64; 2],
    /// Number of rocks.
    pub count: u32,
    /// Smallest diameter, metres (uniform between min and max).
    pub diameter_min_m: f64,
    /// Largest diameter, metres.
    pub diameter_max_m: f64,
    /// Height over diameter for this cluster.
    pub height_ratio: f64,
}

impl Default for RockClusterConfig {
    fn default() -> Self {
        Self {
            center_m: [0.0, 0.0],
            half_extents_m: [2.0, 2.0],
            count: 20,
            diameter_min_m: 0.6,
            diameter_max_m: 1.6,
            height_ratio: 0.5,
        }
    }
}

impl RockClusterConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(-1e4, 1e4).check(prefix, "center_m[0]", self.center_m[0])?;
        Interval::closed(-1e4, 1e4).check(prefix, "center_m[1]", self.center_m[1])?;
        Interval::closed(0.0, 500.0).check(prefix, "half_extents_m[0]", self.half_extents_m[0])?;
        Interval::closed(0.0, 500.0).check(prefix, "half_extents_m[1]", self.half_extents_m[1])?;
        check_int(prefix, "count", u64::from(self.count), 0, 100_000)?;
        rock_sizes(
            prefix,
            0.02,
            [self.diameter_min_m, self.diameter_max_m],
            self.height_ratio,
        )
    }
}

/// One rock at a given horizontal position; it sits on the terrain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExplicitRockConfig {
    /// Centre (x, y), metres.
    pub center_m: [f64; 2],
    /// Equivalent-area diameter, metres.
    pub diameter_m: f64,
    /// Height above the ground, metres (default: half the diameter).
    pub height_m: Option<f64>,
}

impl Default for ExplicitRockConfig {
    fn default() -> Self {
        Self {
            center_m: [0.0, 0.0],
            diameter_m: 1.0,
            height_m: None,
        }
    }
}

impl ExplicitRockConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(-1e4, 1e4).check(prefix, "center_m[0]", self.center_m[0])?;
        Interval::closed(-1e4, 1e4).check(prefix, "center_m[1]", self.center_m[1])?;
        Interval::closed(0.02, 20.0).check(prefix, "diameter_m", self.diameter_m)?;
        if let Some(h) = self.height_m {
            Interval::left_open(0.0, 20.0).check(prefix, "height_m", h)?;
        }
        Ok(())
    }
}
