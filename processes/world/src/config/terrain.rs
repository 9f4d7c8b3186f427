//! The heightfield and its craters.

use serde::{Deserialize, Serialize};

use super::{Interval, MAX_GRID_NODES, check_int, inconsistent, min_max_pair};
use crate::error::ConfigError;

/// Heightfield extent, resolution and fractal relief.
///
/// The grid is centred on the world origin: x spans `[-(nx-1)·spacing/2, +(nx-1)·spacing/2]`
/// with `nx = round(size_x_m / spacing_m) + 1`, likewise y.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TerrainConfig {
    /// Extent along world x, metres.
    pub size_x_m: f64,
    /// Extent along world y, metres.
    pub size_y_m: f64,
    /// Grid spacing, metres.
    pub spacing_m: f64,
    /// Amplitude of the coarsest relief octave, metres.
    pub relief_amplitude_m: f64,
    /// Wavelength of the coarsest relief octave, metres.
    pub relief_wavelength_m: f64,
    /// Number of octaves (each halves the wavelength).
    pub relief_octaves: u32,
    /// Amplitude ratio between successive octaves.
    pub relief_gain: f64,
}

impl Default for TerrainConfig {
    fn default() -> Self {
        Self {
            size_x_m: 64.0,
            size_y_m: 64.0,
            spacing_m: 0.25,
            relief_amplitude_m: 0.6,
            relief_wavelength_m: 24.0,
            relief_octaves: 7,
            relief_gain: 0.45,
        }
    }
}

impl TerrainConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(2.0, 2048.0).check(prefix, "size_x_m", self.size_x_m)?;
        Interval::closed(2.0, 2048.0).check(prefix, "size_y_m", self.size_y_m)?;
        Interval::left_open(0.0, 1.0).check(prefix, "spacing_m", self.spacing_m)?;
        Interval::closed(0.0, 50.0).check(prefix, "relief_amplitude_m", self.relief_amplitude_m)?;
        Interval::closed(0.1, 10_000.0).check(
            prefix,
            "relief_wavelength_m",
            self.relief_wavelength_m,
        )?;
        check_int(
            prefix,
            "relief_octaves",
            u64::from(self.relief_octaves),
            0,
            16,
        )?;
        Interval::closed(0.0, 1.0).check(prefix, "relief_gain", self.relief_gain)?;
        let (nx, ny) = self.grid_nodes();
        if nx.max(ny) > MAX_GRID_NODES {
            return Err(inconsistent(
                prefix,
                "spacing_m",
                format!(
                    "gives a {nx}x{ny} grid; at most {MAX_GRID_NODES} nodes per side are allowed"
                ),
            ));
        }
        Ok(())
    }

    /// Grid nodes along x and y (at least 2 each).
    pub fn grid_nodes(&self) -> (usize, usize) {
        let n = |size: f64| -> usize {
            let cells = (size / self.spacing_m).round();
            if cells.is_finite() && cells >= 1.0 {
                (cells as usize).saturating_add(1)
            } else {
                2
            }
        };
        (n(self.size_x_m), n(self.size_y_m))
    }
}

/// Crater population: count, size range and shape ratios.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CraterConfig {
    /// Number of craters placed at random.
    pub count: u32,
    /// Smallest rim diameter, metres.
    pub diameter_min_m: f64,
    /// Largest rim diameter, metres (diameters are log-uniform in between).
    pub diameter_max_m: f64,
    /// Rim-crest-to-floor depth over diameter (fresh craters ≈ 0.2).
    pub depth_ratio: f64,
    /// Rim height above the surroundings over diameter (fresh craters ≈ 0.04).
    pub rim_height_ratio: f64,
}

impl Default for CraterConfig {
    fn default() -> Self {
        Self {
            count: 8,
            diameter_min_m: 1.5,
            diameter_max_m: 10.0,
            depth_ratio: 0.2,
            rim_height_ratio: 0.04,
        }
    }
}

impl CraterConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        check_int(prefix, "count", u64::from(self.count), 0, 10_000)?;
        min_max_pair(
            prefix,
            ("diameter_min_m", self.diameter_min_m),
            ("diameter_max_m", self.diameter_max_m),
            Interval::left_open(0.0, 1000.0),
        )?;
        Interval::left_open(0.0, 0.5).check(prefix, "depth_ratio", self.depth_ratio)?;
        Interval::closed(0.0, 0.2).check(prefix, "rim_height_ratio", self.rim_height_ratio)?;
        Ok(())
    }
}
