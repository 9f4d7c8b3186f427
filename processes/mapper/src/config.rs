//! Settings of the mapper (`[mapper]` table): serde with defaults, `deny_unknown_fields`, and
//! [`MapperConfig::validate`] naming the offending key and its allowed range.
//!
//! The grid geometry keys are optional: absent, they cover the world terrain (see
//! [`MapperConfig::resolve_geometry`]).
//!
//! ```
//! use hopnav_mapper::config::MapperConfig;
//! let mut cfg = MapperConfig::default();
//! assert!(cfg.validate().is_ok());
//! cfg.traversable_height_m = -1.0;
//! let err = cfg.validate().unwrap_err().to_string();
//! assert!(err.contains("mapper.traversable_height_m"));
//! ```

use hopnav_config::range::Table;
use hopnav_config::{ConfigError, HopnavConfig, in_section, parse_section};
use serde::{Deserialize, Serialize};

use crate::geometry::{GridGeometry, MAX_CELLS};

/// Settings of [`crate::map::FeatureMap`] and the mapper process.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MapperConfig {
    /// Edge length of a map cell, metres.
    pub cell_size_m: f64,
    /// World x of the grid corner, metres (absent: the terrain's lower x edge).
    pub origin_x_m: Option<f64>,
    /// World y of the grid corner, metres (absent: the terrain's lower y edge).
    pub origin_y_m: Option<f64>,
    /// Cells along x (absent: enough to cover the terrain).
    pub width_cells: Option<u32>,
    /// Cells along y (absent: enough to cover the terrain).
    pub height_cells: Option<u32>,
    /// Features higher than this above the local ground are obstacles for the rover, metres.
    /// The rover climbs 0.2 m (`physics.rover.max_climbable_height_m`); the 5 cm margin
    /// covers the clouds' height noise (rover stereo ground RMS ≈ 4 cm), so a rock just above
    /// the limit is not missed.
    pub traversable_height_m: f64,
    /// Features higher than this above the local ground are outliers and ignored, metres.
    pub max_feature_height_m: f64,
    /// Features whose depth is less certain than this (one sigma) are ignored, metres: a
    /// monocular point triangulated at low parallax cannot tell a rock from the ground.
    pub max_depth_sigma_m: f64,
    /// A jumper feature counts as high only above `traversable_height_m` plus this many of
    /// its height sigmas (depth sigma times the vertical part of its viewing ray): monocular
    /// points seen steeply from ~10 m also carry pose and scale errors.
    pub jumper_height_sigma_factor: f64,
    /// The same for the rover's stereo features (their heights were measured to ≈ 4 cm).
    pub rover_height_sigma_factor: f64,
    /// High features a cell needs to become an obstacle (rejects single outliers).
    pub min_obstacle_support: u32,
    /// Once a cell has `fraction_min_features` judged features, at least this fraction of them
    /// must be high for it to be an obstacle (0 = off): outliers that pile up in one cell over
    /// a long mission stay a small fraction of its features. The jumper's measured features
    /// are judged only where its high ones count (its clouds agree, the rover has not
    /// overruled it).
    pub obstacle_min_fraction: f64,
    /// Judged features a cell needs before `obstacle_min_fraction` applies.
    pub fraction_min_features: u32,
    /// Jumper clouds (keyframes) that must each find a feature of the cell high before the
    /// jumper's high features count: one distorted cloud does not make a rock.
    pub min_high_clouds: u16,
    /// … and at least this fraction of the jumper clouds that judged a feature in the cell.
    pub min_high_cloud_fraction: f64,
    /// Rover features after which the rover's close look decides a cell alone: the jumper's
    /// measured high features there stop counting (its clouds carry metres of pose drift and
    /// depth error, and fatten rocks into the gaps between them; 0 = never).
    pub rover_overrules_jumper_after: u32,
    /// Features a cell needs to count as observed (free).
    pub min_free_support: u32,
    /// Radius of the neighbourhood whose lowest observations define the local ground, metres.
    pub ground_window_m: f64,
    /// Cells within this distance of an obstacle get an extra cost, metres (0 = off).
    pub inflation_radius_m: f64,
    /// Cells within this distance (centre to centre) of an obstacle cell are lethal: the
    /// rover's centre must not enter them, or its body would touch the rock, metres (0 =
    /// off; at most `inflation_radius_m`).
    pub lethal_radius_m: f64,
    /// Extra cost next to an obstacle, planner units (1000 = one straight cell); it falls
    /// linearly with distance.
    pub inflation_max_cost: u32,
    /// Most cells reclassified per frame (bounds the frame time after a large cloud; the rest
    /// follow in the next frames).
    pub max_cells_per_frame: u32,
    /// Frames between two map snapshots on disk (0 = never).
    pub snapshot_every_frames: u32,
    /// Frames between two publications of the whole known map on `MAP_SNAPSHOT` (history 1),
    /// so a restarted planner, or one that missed updates, recovers it (0 = never).
    pub republish_every_frames: u32,
    /// Evaluation only: start with every rock of the world on the map, as a flawless scout
    /// would have mapped it before the rover moved (see [`crate::oracle_prior`]); bounds
    /// what any scouting could give. Reads the world's truth, so never on in a real mission.
    pub oracle_prior_map: bool,
    /// How cells become obstacles: `features` counts features above `traversable_height_m`
    /// (the first mapper's rule, with a lethal ring of `lethal_radius_m`); `traversability`
    /// keeps a per-cell belief that something taller than the rover's climb limit stands
    /// there ([`crate::belief`]: a fused top with its sigma, log-odds with clamps and
    /// hysteresis, rays that clear what they pass through) and inflates lethal cells by the
    /// rover's footprint ([`crate::inflation::footprint_kernel`]).
    pub obstacle_model: ObstacleModel,
    /// `traversability`: a point's height sigma is at least this (the clouds' heights above
    /// the local ground also carry the ground's error: rover stereo ground RMS ≈ 4 cm), metres.
    pub height_sigma_floor_m: f64,
    /// `traversability`: a cloud votes a cell too tall when the cell's fused top stands this
    /// many of its sigmas above the climb limit less `hit_margin_m` (see
    /// [`crate::belief::BeliefParams`]).
    pub hit_sigmas: f64,
    /// `traversability`: a top this far below the climb limit already counts as too tall,
    /// metres: features sit on a rock's corners and flanks, not its apex, so its top reads low.
    pub hit_margin_m: f64,
    /// `traversability`: the stereo sees a rock's near face only; rocks are about twice as
    /// wide as they are tall, so a too-tall cell's margin may be measured from a box that
    /// also holds a square of this fraction of its top height as a half-width, set behind the
    /// seen face away from the rover's camera (0 = from the tall points only). Measured in
    /// docs/experiments/2026-12-06-traversability-first-measurements.md.
    pub rock_width_prior: f64,
    /// `traversability`: the rover's tall points of touching cells are fitted as one rock, a
    /// dome ([`crate::dome`]) whose base radius is expected to be this many times its height
    /// (Golombek's rocks and the world's are about twice as wide as tall: 1.0; the points may
    /// make it flatter or steeper, within ×0.5–×2), and the ground under its base, unseen
    /// back included, is the rock's. 0 = no fit: the cells' own beliefs only.
    pub dome_base_per_height: f64,
    /// `traversability`: a fitted rock is lethal when its height plus this many of its
    /// height sigmas stands above the climb limit, uncertain (a finite cost) when only its
    /// height plus two sigmas does. −1 waits for an 84 % chance that it is too tall; a
    /// cautious +1 (16 %) closed corridors and made the rover wind: over 20 seeds it reached
    /// B 16 and 13 times (rover-only, cooperative) against 18 and 17, with more collisions in
    /// cooperative missions (docs/experiments/2026-12-06-traversability-near-limit-rocks.md).
    pub rock_lethal_sigmas: f64,
    /// `traversability`: beyond the rover's circumscribed radius the extra cost decays as
    /// `inflation_max_cost · exp(−k·(d − r_circumscribed))` (nav2's `cost_scaling_factor`),
    /// out to `inflation_radius_m`, 1/m.
    pub cost_scaling_per_m: f64,
    /// `traversability`: extra cost of a cell whose belief is uncertain (maybe taller than the
    /// climb limit), planner units: dear enough to go round, cheap enough to go through when
    /// the detour is long, so the rover's closer look can settle it.
    pub uncertain_cost: u32,
    /// The rover's body, from `[physics.rover]` (not a `[mapper]` key): its climb limit and
    /// its footprint's radii, for the `traversability` model.
    #[serde(skip)]
    pub rover_body: hopnav_robot::RoverBody,
}

/// How the mapper decides that a cell blocks the rover (see [`MapperConfig::obstacle_model`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ObstacleModel {
    /// Count features above `traversable_height_m` (the first mapper's binary rule).
    #[default]
    Features,
    /// A per-cell belief against the rover's climb limit, inflated by its footprint.
    Traversability,
}

impl Default for MapperConfig {
    fn default() -> Self {
        Self {
            cell_size_m: 0.25,
            origin_x_m: None,
            origin_y_m: None,
            width_cells: None,
            height_cells: None,
            traversable_height_m: 0.15,
            max_feature_height_m: 5.0,
            max_depth_sigma_m: 0.25,
            jumper_height_sigma_factor: 2.0,
            rover_height_sigma_factor: 0.0,
            min_obstacle_support: 3,
            obstacle_min_fraction: 0.1,
            fraction_min_features: 20,
            min_high_clouds: 2,
            min_high_cloud_fraction: 0.3,
            rover_overrules_jumper_after: 10,
            min_free_support: 1,
            ground_window_m: 2.0,
            inflation_radius_m: 1.0,
            lethal_radius_m: 0.75,
            inflation_max_cost: 2000,
            max_cells_per_frame: 2000,
            snapshot_every_frames: 50,
            republish_every_frames: 20,
            oracle_prior_map: false,
            obstacle_model: ObstacleModel::Traversability,
            height_sigma_floor_m: 0.03,
            hit_sigmas: 0.5,
            hit_margin_m: 0.03,
            rock_width_prior: 0.0,
            dome_base_per_height: 1.0,
            rock_lethal_sigmas: -1.0,
            cost_scaling_per_m: 3.0,
            uncertain_cost: 1500,
            rover_body: hopnav_robot::RoverBody::default(),
        }
    }
}

/// The `[mapper]` keys, for their range checks.
const KEYS: Table = Table::new("mapper");

impl MapperConfig {
    /// Checks every value; the error names `mapper.<key>` and the allowed range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_grid()?;
        self.validate_feature_rule()?;
        self.validate_traversability()
    }

    /// The grid's cell size, origin and size.
    fn validate_grid(&self) -> Result<(), ConfigError> {
        KEYS.real("cell_size_m", self.cell_size_m, 0.05, 10.0)?;
        if let Some(x) = self.origin_x_m {
            KEYS.real("origin_x_m", x, -1e6, 1e6)?;
        }
        if let Some(y) = self.origin_y_m {
            KEYS.real("origin_y_m", y, -1e6, 1e6)?;
        }
        if let Some(w) = self.width_cells {
            KEYS.int("width_cells", u64::from(w), 1, MAX_CELLS)?;
        }
        if let Some(h) = self.height_cells {
            KEYS.int("height_cells", u64::from(h), 1, MAX_CELLS)?;
        }
        Ok(())
    }

    /// The features' heights and the first (`features`) rule's votes.
    fn validate_feature_rule(&self) -> Result<(), ConfigError> {
        KEYS.real(
            "traversable_height_m",
            self.traversable_height_m,
            0.01,
            10.0,
        )?;
        KEYS.real(
            "max_feature_height_m",
            self.max_feature_height_m,
            self.traversable_height_m,
            1000.0,
        )?;
        KEYS.real("max_depth_sigma_m", self.max_depth_sigma_m, 0.001, 100.0)?;
        KEYS.real(
            "jumper_height_sigma_factor",
            self.jumper_height_sigma_factor,
            0.0,
            10.0,
        )?;
        KEYS.real(
            "rover_height_sigma_factor",
            self.rover_height_sigma_factor,
            0.0,
            10.0,
        )?;
        KEYS.int(
            "min_obstacle_support",
            u64::from(self.min_obstacle_support),
            1,
            1_000_000,
        )?;
        KEYS.real(
            "obstacle_min_fraction",
            self.obstacle_min_fraction,
            0.0,
            1.0,
        )?;
        KEYS.int(
            "fraction_min_features",
            u64::from(self.fraction_min_features),
            1,
            1_000_000,
        )?;
        KEYS.int("min_high_clouds", u64::from(self.min_high_clouds), 1, 1000)?;
        KEYS.real(
            "min_high_cloud_fraction",
            self.min_high_cloud_fraction,
            0.0,
            1.0,
        )?;
        KEYS.int(
            "rover_overrules_jumper_after",
            u64::from(self.rover_overrules_jumper_after),
            0,
            1_000_000,
        )?;
        KEYS.int(
            "min_free_support",
            u64::from(self.min_free_support),
            1,
            1_000_000,
        )?;
        Ok(())
    }

    /// The ground window, the inflation and costs, and the `traversability` model's beliefs
    /// and fitted rocks.
    fn validate_traversability(&self) -> Result<(), ConfigError> {
        KEYS.real(
            "ground_window_m",
            self.ground_window_m,
            self.cell_size_m,
            25.0 * self.cell_size_m,
        )?;
        KEYS.real(
            "inflation_radius_m",
            self.inflation_radius_m,
            0.0,
            25.0 * self.cell_size_m,
        )?;
        KEYS.real(
            "lethal_radius_m",
            self.lethal_radius_m,
            0.0,
            self.inflation_radius_m,
        )?;
        KEYS.int(
            "max_cells_per_frame",
            u64::from(self.max_cells_per_frame),
            1,
            MAX_CELLS,
        )?;
        KEYS.int(
            "inflation_max_cost",
            u64::from(self.inflation_max_cost),
            0,
            1_000_000,
        )?;
        KEYS.real("height_sigma_floor_m", self.height_sigma_floor_m, 0.0, 1.0)?;
        KEYS.real("cost_scaling_per_m", self.cost_scaling_per_m, 0.0, 100.0)?;
        KEYS.real("hit_sigmas", self.hit_sigmas, 0.0, 10.0)?;
        KEYS.real("rock_width_prior", self.rock_width_prior, 0.0, 2.0)?;
        KEYS.real("dome_base_per_height", self.dome_base_per_height, 0.0, 5.0)?;
        KEYS.real("rock_lethal_sigmas", self.rock_lethal_sigmas, -1.9, 1.9)?;
        KEYS.real("hit_margin_m", self.hit_margin_m, -1.0, 1.0)?;
        KEYS.int(
            "uncertain_cost",
            u64::from(self.uncertain_cost),
            0,
            1_000_000,
        )?;
        Ok(())
    }

    /// The grid geometry: explicit keys win; absent ones cover the terrain square
    /// `[-size_x_m/2, size_x_m/2] × [-size_y_m/2, size_y_m/2]` (the world crate centres its
    /// heightfield on the origin). Errors if the grid is too large.
    pub fn resolve_geometry(
        &self,
        terrain_size_m: (f64, f64),
    ) -> Result<GridGeometry, ConfigError> {
        let (size_x_m, size_y_m) = terrain_size_m;
        let cells = |size_m: f64| (size_m / self.cell_size_m).ceil().clamp(1.0, 1e9) as u32;
        let geometry = GridGeometry {
            origin_x_m: self.origin_x_m.unwrap_or(-size_x_m / 2.0),
            origin_y_m: self.origin_y_m.unwrap_or(-size_y_m / 2.0),
            cell_size_m: self.cell_size_m,
            width_cells: self.width_cells.unwrap_or_else(|| cells(size_x_m)),
            height_cells: self.height_cells.unwrap_or_else(|| cells(size_y_m)),
        };
        let count = geometry.cell_count() as u64;
        if count > MAX_CELLS {
            return Err(in_section(
                "mapper",
                "width_cells",
                format!(
                    "{}x{} = {count} cells",
                    geometry.width_cells, geometry.height_cells
                ),
                format!("at most {MAX_CELLS} cells in all (raise cell_size_m)"),
            ));
        }
        Ok(geometry)
    }
}

/// Parses and validates `[mapper]`; errors name `mapper.<key>` and the allowed range. Absent
/// grid keys are filled in to cover the `[world.terrain]` heightfield (centred on the origin),
/// so the returned config always holds an explicit grid (see [`grid_geometry`]).
pub fn mapper_section(config: &HopnavConfig) -> Result<MapperConfig, ConfigError> {
    let mut section: MapperConfig = parse_section(config, "mapper")?;
    section.validate()?;
    section.rover_body = hopnav_robot::RoverBody::from_config(config)?;
    let world: hopnav_world::WorldConfig = parse_section(config, "world")?;
    let terrain = &world.terrain;
    let (nodes_x, nodes_y) = terrain.grid_nodes();
    let extent_m = |nodes: usize| nodes.saturating_sub(1) as f64 * terrain.spacing_m;
    let geometry = section.resolve_geometry((extent_m(nodes_x), extent_m(nodes_y)))?;
    section.origin_x_m = Some(geometry.origin_x_m);
    section.origin_y_m = Some(geometry.origin_y_m);
    section.width_cells = Some(geometry.width_cells);
    section.height_cells = Some(geometry.height_cells);
    Ok(section)
}

/// The grid of a config returned by [`mapper_section`].
pub fn grid_geometry(section: &MapperConfig) -> Result<GridGeometry, ConfigError> {
    section.resolve_geometry((0.0, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_geometry_covers_the_default_terrain() {
        let geometry = MapperConfig::default()
            .resolve_geometry((64.0, 64.0))
            .expect("valid");
        assert_eq!(geometry.origin_x_m, -32.0);
        assert_eq!((geometry.width_cells, geometry.height_cells), (256, 256));
    }

    #[test]
    fn errors_name_the_key_and_range() {
        let cfg = MapperConfig {
            min_obstacle_support: 0,
            ..MapperConfig::default()
        };
        let err = cfg.validate().unwrap_err().to_string();
        assert!(err.contains("mapper.min_obstacle_support"), "{err}");
        assert!(err.contains("[1, 1000000]"), "{err}");
        let cfg = MapperConfig {
            cell_size_m: f64::NAN,
            ..MapperConfig::default()
        };
        assert!(
            cfg.validate()
                .unwrap_err()
                .to_string()
                .contains("mapper.cell_size_m")
        );
        let cfg = MapperConfig {
            cell_size_m: 0.05,
            ..MapperConfig::default()
        };
        let err = cfg
            .resolve_geometry((2048.0, 2048.0))
            .unwrap_err()
            .to_string();
        assert!(err.contains("mapper.width_cells"), "{err}");
    }
}
