//! The generated world: heightfield with craters, and rocks. No textures (see
//! [`RenderScene`](crate::raster::RenderScene) for what only the camera needs).
//!
//! ```
//! use hopnav_world::{World, WorldConfig};
//! let mut cfg = WorldConfig::default();
//! cfg.terrain.size_x_m = 8.0;
//! cfg.terrain.size_y_m = 8.0;
//! let a = World::generate(&cfg).unwrap();
//! let b = World::generate(&cfg).unwrap();
//! assert_eq!(a.terrain().heights_m(), b.terrain().heights_m());
//! assert_eq!(a.rocks(), b.rocks());
//! ```

use crate::config::{MarkerConfig, WorldConfig};
use crate::craters::{Crater, apply_craters, sample_craters};
use crate::error::WorldError;
use crate::landforms;
use crate::rocks::{Rock, generate_rocks};
use crate::terrain::Heightfield;

/// Terrain, craters and rocks generated from one [`WorldConfig`].
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    config: WorldConfig,
    terrain: Heightfield,
    craters: Vec<Crater>,
    rocks: Vec<Rock>,
}

impl World {
    /// Validates the config and generates the world. Same config → bitwise-identical world.
    pub fn generate(config: &WorldConfig) -> Result<Self, WorldError> {
        config.validate()?;
        let mut terrain = Heightfield::from_relief(config.seed, &config.terrain);
        let craters = sample_craters(config.seed, &config.craters, &config.scenario, &terrain);
        apply_craters(&mut terrain, &craters);
        landforms::shape_terrain(
            config.seed,
            &config.landforms,
            &config.scenario,
            &mut terrain,
        );
        let mut rocks = generate_rocks(config.seed, &config.rocks, &config.scenario, &terrain);
        rocks.extend(landforms::landform_rocks(
            config.seed,
            &config.landforms,
            &config.scenario,
            &terrain,
        ));
        Ok(Self {
            config: config.clone(),
            terrain,
            craters,
            rocks,
        })
    }

    /// The configuration the world was generated from.
    pub fn config(&self) -> &WorldConfig {
        &self.config
    }

    /// The heightfield (relief and craters; rocks are separate).
    pub fn terrain(&self) -> &Heightfield {
        &self.terrain
    }

    /// The craters, in the order they were applied.
    pub fn craters(&self) -> &[Crater] {
        &self.craters
    }

    /// The rocks: Golombek background, then clusters, then explicit rocks.
    pub fn rocks(&self) -> &[Rock] {
        &self.rocks
    }

    /// The flat marks of the config.
    pub fn markers(&self) -> &[MarkerConfig] {
        &self.config.markers
    }

    /// Terrain height at (x, y) without rocks, metres.
    pub fn ground_height_at(&self, x_m: f64, y_m: f64) -> f64 {
        self.terrain.height_at(x_m, y_m)
    }

    /// Fraction of the map area covered by rock footprints.
    pub fn rock_area_fraction(&self) -> f64 {
        let [ex, ey] = self.terrain.extent_m();
        self.rocks.iter().map(Rock::footprint_area_m2).sum::<f64>() / (ex * ey)
    }
}
