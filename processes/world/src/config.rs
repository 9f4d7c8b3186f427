//! World configuration: serde types with defaults and `validate()`.
//!
//! Every struct is `#[serde(default, deny_unknown_fields)]`, so a TOML file only lists what it
//! changes and a misspelt key is an error. `validate()` rejects out-of-range values with an
//! error that names the dotted key and the allowed range.
//!
//! ```
//! use hopnav_world::WorldConfig;
//! let mut cfg = WorldConfig::default();
//! cfg.terrain.spacing_m = 2.0;
//! let err = cfg.validate().unwrap_err();
//! assert_eq!(err.to_string(), "terrain.spacing_m must be in (0, 1], got 2");
//! ```

mod landforms;
mod rocks;
mod scenario;
mod surface;
mod terrain;

pub(crate) use hopnav_config::range::{Interval, check_int, dotted_key};
use serde::{Deserialize, Serialize};

pub use landforms::{
    CorridorFieldConfig, CulDeSacConfig, LandformConfig, ScarpConfig, WallBoulders,
};
pub use rocks::{BoulderFieldConfig, ExplicitRockConfig, RockClusterConfig, RockConfig};
pub use scenario::{MarkerConfig, ScenarioConfig};
pub use surface::{LightingConfig, TextureConfig};
pub use terrain::{CraterConfig, TerrainConfig};

use crate::error::ConfigError;

/// Largest number of grid nodes along one side of the heightfield.
pub const MAX_GRID_NODES: usize = 4097;
/// Largest number of texels along one side of the baked terrain texture.
pub const MAX_TEXTURE_TEXELS: usize = 4096;

/// A value that contradicts another; the error names `prefix.field`.
pub(crate) fn inconsistent(prefix: &str, field: &str, reason: String) -> ConfigError {
    ConfigError::Inconsistent {
        key: dotted_key(prefix, field),
        reason,
    }
}

/// Checks a pair of fields that bound a size: each inside `range`, then the maximum not
/// below the minimum (that error names `max_field`).
pub(crate) fn min_max_pair(
    prefix: &str,
    (min_field, min): (&str, f64),
    (max_field, max): (&str, f64),
    range: Interval,
) -> Result<(), ConfigError> {
    range.check(prefix, min_field, min)?;
    range.check(prefix, max_field, max)?;
    if max < min {
        return Err(inconsistent(
            prefix,
            max_field,
            format!("must be >= {min} ({min_field})"),
        ));
    }
    Ok(())
}

/// Largest rock diameter any rock population may ask for, metres.
const LARGEST_ROCK_DIAMETER_M: f64 = 10.0;

/// Checks the size fields every rock population has: `diameter_min_m` and `diameter_max_m` in
/// `[smallest_diameter_m, 10]` and ordered, then `height_ratio` in (0, 2].
pub(crate) fn rock_sizes(
    prefix: &str,
    smallest_diameter_m: f64,
    [diameter_min_m, diameter_max_m]: [f64; 2],
    height_ratio: f64,
) -> Result<(), ConfigError> {
    min_max_pair(
        prefix,
        ("diameter_min_m", diameter_min_m),
        ("diameter_max_m", diameter_max_m),
        Interval::closed(smallest_diameter_m, LARGEST_ROCK_DIAMETER_M),
    )?;
    Interval::left_open(0.0, 2.0).check(prefix, "height_ratio", height_ratio)?;
    Ok(())
}

/// Whole world: terrain, craters, rocks, texture, lighting, scenario points and test markers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WorldConfig {
    /// Master seed; every random stream of the world derives from it.
    pub seed: u64,
    /// Heightfield size, spacing and fractal relief.
    pub terrain: TerrainConfig,
    /// Crater population.
    pub craters: CraterConfig,
    /// Rock population (Golombek model, clusters, explicit rocks).
    pub rocks: RockConfig,
    /// Cul-de-sacs, a scarp and a corridor field between A and B (all off by default).
    pub landforms: LandformConfig,
    /// Procedural surface texture.
    pub texture: TextureConfig,
    /// Sun direction and ambient light (baked into the texture).
    pub lighting: LightingConfig,
    /// Optional start and goal points, kept free of random rocks.
    pub scenario: ScenarioConfig,
    /// Flat square marks of known position (for geometry checks and calibration).
    pub markers: Vec<MarkerConfig>,
}

impl Default for WorldConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            terrain: TerrainConfig::default(),
            craters: CraterConfig::default(),
            rocks: RockConfig::default(),
            landforms: LandformConfig::default(),
            texture: TextureConfig::default(),
            lighting: LightingConfig::default(),
            scenario: ScenarioConfig::default(),
            markers: Vec::new(),
        }
    }
}

impl WorldConfig {
    /// Checks every value; the error names the first offending key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.terrain.validate("terrain")?;
        self.craters.validate("craters")?;
        self.rocks.validate("rocks")?;
        self.landforms.validate("landforms", &self.terrain)?;
        self.texture.validate("texture", &self.terrain)?;
        self.lighting.validate("lighting")?;
        self.scenario.validate("scenario", &self.terrain)?;
        for (i, m) in self.markers.iter().enumerate() {
            m.validate(&format!("markers[{i}]"))?;
        }
        Ok(())
    }
}
