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

use serde::{Deserialize, Serialize};

use crate::error::ConfigError;

/// Largest number of grid nodes along one side of the heightfield.
pub const MAX_GRID_NODES: usize = 4097;
/// Largest number of texels along one side of the baked terrain texture.
pub const MAX_TEXTURE_TEXELS: usize = 4096;

/// Joins a key prefix and a field name with a dot.
pub(crate) fn key(prefix: &str, field: &str) -> String {
    if prefix.is_empty() {
        field.to_string()
    } else {
        format!("{prefix}.{field}")
    }
}

/// An interval used to check and describe a value.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Interval {
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
}

impl Interval {
    /// `[lo, hi]`.
    pub(crate) const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: false,
            hi_open: false,
        }
    }
    /// `(lo, hi]`.
    pub(crate) const fn left_open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: false,
        }
    }
    fn contains(&self, v: f64) -> bool {
        let lo_ok = if self.lo_open {
            v > self.lo
        } else {
            v >= self.lo
        };
        let hi_ok = if self.hi_open {
            v < self.hi
        } else {
            v <= self.hi
        };
        lo_ok && hi_ok && v.is_finite()
    }
    fn describe(&self) -> String {
        format!(
            "{}{}, {}{}",
            if self.lo_open { '(' } else { '[' },
            self.lo,
            self.hi,
            if self.hi_open { ')' } else { ']' }
        )
    }
    /// Checks `v` and names `prefix.field` on failure.
    pub(crate) fn check(&self, prefix: &str, field: &str, v: f64) -> Result<(), ConfigError> {
        if self.contains(v) {
            Ok(())
        } else {
            Err(ConfigError::OutOfRange {
                key: key(prefix, field),
                range: self.describe(),
                value: format!("{v}"),
            })
        }
    }
}

/// Checks an integer against an inclusive range.
pub(crate) fn check_int(
    prefix: &str,
    field: &str,
    v: u64,
    lo: u64,
    hi: u64,
) -> Result<(), ConfigError> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(ConfigError::OutOfRange {
            key: key(prefix, field),
            range: format!("[{lo}, {hi}]"),
            value: v.to_string(),
        })
    }
}

fn inconsistent(prefix: &str, field: &str, reason: String) -> ConfigError {
    ConfigError::Inconsistent {
        key: key(prefix, field),
        reason,
    }
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
        self.texture.validate("texture", &self.terrain)?;
        self.lighting.validate("lighting")?;
        self.scenario.validate("scenario", &self.terrain)?;
        for (i, m) in self.markers.iter().enumerate() {
            m.validate(&format!("markers[{i}]"))?;
        }
        Ok(())
    }
}

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
        Interval::left_open(0.0, 1000.0).check(prefix, "diameter_min_m", self.diameter_min_m)?;
        Interval::left_open(0.0, 1000.0).check(prefix, "diameter_max_m", self.diameter_max_m)?;
        if self.diameter_max_m < self.diameter_min_m {
            return Err(inconsistent(
                prefix,
                "diameter_max_m",
                format!("must be >= {} (diameter_min_m)", self.diameter_min_m),
            ));
        }
        Interval::left_open(0.0, 0.5).check(prefix, "depth_ratio", self.depth_ratio)?;
        Interval::closed(0.0, 0.2).check(prefix, "rim_height_ratio", self.rim_height_ratio)?;
        Ok(())
    }
}

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
        Interval::closed(0.02, 10.0).check(prefix, "diameter_min_m", self.diameter_min_m)?;
        Interval::closed(0.02, 10.0).check(prefix, "diameter_max_m", self.diameter_max_m)?;
        if self.diameter_max_m < self.diameter_min_m {
            return Err(inconsistent(
                prefix,
                "diameter_max_m",
                format!("must be >= {} (diameter_min_m)", self.diameter_min_m),
            ));
        }
        Interval::left_open(0.0, 2.0).check(prefix, "height_ratio", self.height_ratio)?;
        for (i, c) in self.clusters.iter().enumerate() {
            c.validate(&key(prefix, &format!("clusters[{i}]")))?;
        }
        for (i, r) in self.explicit.iter().enumerate() {
            r.validate(&key(prefix, &format!("explicit[{i}]")))?;
        }
        self.boulder_fields.validate(&key(prefix, "boulder_fields"))
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
        Interval::closed(0.5, 50.0).check(prefix, "radius_min_m", self.radius_min_m)?;
        Interval::closed(0.5, 50.0).check(prefix, "radius_max_m", self.radius_max_m)?;
        if self.radius_max_m < self.radius_min_m {
            return Err(inconsistent(
                prefix,
                "radius_max_m",
                format!("must be >= {} (radius_min_m)", self.radius_min_m),
            ));
        }
        Interval::closed(0.0, 6.0).check(prefix, "opening_rad", self.opening_rad)?;
        Interval::closed(0.1, 10.0).check(prefix, "diameter_min_m", self.diameter_min_m)?;
        Interval::closed(0.1, 10.0).check(prefix, "diameter_max_m", self.diameter_max_m)?;
        if self.diameter_max_m < self.diameter_min_m {
            return Err(inconsistent(
                prefix,
                "diameter_max_m",
                format!("must be >= {} (diameter_min_m)", self.diameter_min_m),
            ));
        }
        Interval::left_open(0.0, 2.0).check(prefix, "height_ratio", self.height_ratio)?;
        Interval::closed(0.0, 100.0).check(prefix, "lateral_spread_m", self.lateral_spread_m)
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
        Interval::closed(0.02, 10.0).check(prefix, "diameter_min_m", self.diameter_min_m)?;
        Interval::closed(0.02, 10.0).check(prefix, "diameter_max_m", self.diameter_max_m)?;
        if self.diameter_max_m < self.diameter_min_m {
            return Err(inconsistent(
                prefix,
                "diameter_max_m",
                format!("must be >= {} (diameter_min_m)", self.diameter_min_m),
            ));
        }
        Interval::left_open(0.0, 2.0).check(prefix, "height_ratio", self.height_ratio)
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

/// Procedural surface texture parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TextureConfig {
    /// Texel size of the baked terrain texture, metres.
    pub texel_m: f64,
    /// Texel size of the tiled fine-detail texture (sand, grit), metres.
    pub detail_texel_m: f64,
    /// Mean ground albedo in digital numbers (before shading).
    pub albedo_dn: f64,
    /// Relative albedo variation of the multi-scale noise (0 = uniform ground).
    pub macro_contrast: f64,
    /// Relative contrast of the fine-detail texture (0 = none).
    pub detail_contrast: f64,
    /// Pebbles (1–8 cm) per square metre baked into the terrain texture.
    pub pebble_density_per_m2: f64,
    /// Amplitude of the centimetre-scale bumps used for shading, metres.
    pub bump_amplitude_m: f64,
    /// Mean rock albedo in digital numbers.
    pub rock_albedo_dn: f64,
}

impl Default for TextureConfig {
    fn default() -> Self {
        Self {
            texel_m: 0.02,
            detail_texel_m: 0.004,
            albedo_dn: 150.0,
            macro_contrast: 0.35,
            detail_contrast: 0.4,
            pebble_density_per_m2: 60.0,
            bump_amplitude_m: 0.01,
            rock_albedo_dn: 140.0,
        }
    }
}

impl TextureConfig {
    /// Checks the values under `prefix`; the texture may not exceed
    /// [`MAX_TEXTURE_TEXELS`] per side over the terrain.
    pub fn validate(&self, prefix: &str, terrain: &TerrainConfig) -> Result<(), ConfigError> {
        Interval::closed(0.002, 0.5).check(prefix, "texel_m", self.texel_m)?;
        Interval::closed(0.0005, 0.05).check(prefix, "detail_texel_m", self.detail_texel_m)?;
        Interval::closed(1.0, 255.0).check(prefix, "albedo_dn", self.albedo_dn)?;
        Interval::closed(0.0, 1.0).check(prefix, "macro_contrast", self.macro_contrast)?;
        Interval::closed(0.0, 1.0).check(prefix, "detail_contrast", self.detail_contrast)?;
        Interval::closed(0.0, 5000.0).check(
            prefix,
            "pebble_density_per_m2",
            self.pebble_density_per_m2,
        )?;
        Interval::closed(0.0, 0.2).check(prefix, "bump_amplitude_m", self.bump_amplitude_m)?;
        Interval::closed(1.0, 255.0).check(prefix, "rock_albedo_dn", self.rock_albedo_dn)?;
        let side_m = terrain.size_x_m.max(terrain.size_y_m);
        let min_texel = side_m / MAX_TEXTURE_TEXELS as f64;
        if self.texel_m < min_texel {
            return Err(inconsistent(
                prefix,
                "texel_m",
                format!(
                    "must be >= {min_texel} for a {side_m} m terrain \
                     (at most {MAX_TEXTURE_TEXELS} texels per side), got {}",
                    self.texel_m
                ),
            ));
        }
        Ok(())
    }
}

/// Sun and ambient light, baked into the terrain texture and rock vertices.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LightingConfig {
    /// Sun azimuth, radians, counter-clockwise from world +x.
    pub sun_azimuth_rad: f64,
    /// Sun elevation above the horizon, radians.
    pub sun_elevation_rad: f64,
    /// Ambient fraction of the light in `[0, 1]`.
    pub ambient: f64,
}

impl Default for LightingConfig {
    fn default() -> Self {
        Self {
            sun_azimuth_rad: 2.3,
            sun_elevation_rad: 0.6,
            ambient: 0.3,
        }
    }
}

impl LightingConfig {
    /// Checks the values under `prefix`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        let tau = std::f64::consts::TAU;
        Interval::closed(-tau, tau).check(prefix, "sun_azimuth_rad", self.sun_azimuth_rad)?;
        Interval::left_open(0.0, std::f64::consts::FRAC_PI_2).check(
            prefix,
            "sun_elevation_rad",
            self.sun_elevation_rad,
        )?;
        Interval::closed(0.0, 1.0).check(prefix, "ambient", self.ambient)
    }

    /// Unit vector towards the sun in world coordinates (z up).
    pub fn sun_direction(&self) -> [f64; 3] {
        let (se, ce) = self.sun_elevation_rad.sin_cos();
        let (sa, ca) = self.sun_azimuth_rad.sin_cos();
        [ce * ca, ce * sa, se]
    }
}

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
        Interval::left_open(0.0, 100.0).check(prefix, "half_size_m", self.half_size_m)
    }
}
