//! Mission points and test markers.

use serde::{Deserialize, Serialize};

use super::{Interval, TerrainConfig};
use crate::error::ConfigError;

/// Mission points of a scenario; random rocks keep `clear_radius_m` away from them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ScenarioConfig {
    /// Start point A (x, y), metres.
    pub start_m: Option<[f64; 2]>,
    /// Goal point B (x, y), metres.
    pub goal_m: Option<[f64; 2]>,
    /// Radius around start and goal kept free of random rocks, metres.
    pub clear_radius_m: f64,
}

impl Default for ScenarioConfig {
    fn default() -> Self {
        Self {
            start_m: None,
            goal_m: None,
            clear_radius_m: 1.5,
        }
    }
}

impl ScenarioConfig {
    /// Checks the values under `prefix`; points must lie on the terrain.
    pub fn validate(&self, prefix: &str, terrain: &TerrainConfig) -> Result<(), ConfigError> {
        Interval::closed(0.0, 100.0).check(prefix, "clear_radius_m", self.clear_radius_m)?;
        let hx = terrain.size_x_m / 2.0;
        let hy = terrain.size_y_m / 2.0;
        for (name, p) in [("start_m", self.start_m), ("goal_m", self.goal_m)] {
            if let Some(p) = p {
                Interval::closed(-hx, hx).check(prefix, &format!("{name}[0]"), p[0])?;
                Interval::closed(-hy, hy).check(prefix, &format!("{name}[1]"), p[1])?;
            }
        }
        Ok(())
    }

    /// The points that must stay clear of random rocks.
    pub fn clear_points(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        self.start_m.into_iter().chain(self.goal_m)
    }
}

/// A flat horizontal square of constant brightness, drawn on top of the terrain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MarkerConfig {
    /// Centre of the square, world metres.
    pub center_m: [f64; 3],
    /// Half the side length, metres.
    pub half_size_m: f64,
    /// Brightness in digital numbers.
    pub value_dn: u8,
}

impl Default for MarkerConfig {
    fn default() -> Self {
        Self {
            center_m: [0.0, 0.0, 0.0],
            half_size_m: 0.05,
            value_dn: 255,
        }
    }
}

impl MarkerConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        for (i, v) in self.center_m.iter().enumerate() {
            Interval::closed(-1e4, 1e4).check(prefix, &format!("center_m[{i}]"), *v)?;
        }
        Interval::left_open(0.0, 100.0).check(prefix, "half_size_m", self.half_size_m)?;
        Ok(())
    }
}
