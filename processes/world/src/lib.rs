//! # hopnav-world
//!
//! The simulated Mars world shared by the `physics` and `camera` processes:
//!
//! - [`WorldConfig`]: serde configuration with `validate()` naming the offending key;
//! - [`World`]: a seeded, bitwise-reproducible heightfield ([`terrain::Heightfield`]) with
//!   fractal relief and [`craters`], plus [`rocks`] from the Golombek size-frequency model,
//!   clusters and explicit rocks;
//! - [`mesh`]: triangle meshes of terrain and rocks (e.g. for colliders);
//! - [`footprint`]: a rock's outline as the rover's body meets it (for the evaluation);
//! - [`texture`], [`bake`], [`shadows`]: procedural textures with baked shading and cast
//!   shadows;
//! - [`raster`]: a hand-written z-buffer rasterizer with perspective-correct texturing,
//!   near-plane clipping, chunk culling and LOD, drawing 8-bit grayscale into a caller's buffer;
//! - [`camera`]: pinhole intrinsics from the field of view, look-at and stereo helpers;
//! - [`bench`](mod@bench): an own-harness render benchmark.
//!
//! # Conventions
//! - World: metres, **z up**, x/y horizontal; the terrain grid is centred on the origin.
//! - Camera: OpenCV frame (x right, y down, z forward); poses are `world_from_camera`;
//!   pixel centres at integer coordinates.
//! - Angles in radians.
//!
//! ```
//! use hopnav_world::{World, WorldConfig};
//! use hopnav_world::camera::{CameraConfig, look_at};
//! use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
//! use nalgebra::{Point3, Vector3};
//!
//! let mut cfg = WorldConfig::default();
//! cfg.terrain.size_x_m = 8.0;
//! cfg.terrain.size_y_m = 8.0;
//! let world = World::generate(&cfg).unwrap();
//! let scene = RenderScene::new(&world).unwrap();
//! let mut renderer = Renderer::new(&CameraConfig::default(), &RenderConfig::default()).unwrap();
//! let pose = look_at(&Point3::new(0.0, -3.0, 2.0), &Point3::new(0.0, 0.0, 0.0), &Vector3::z());
//! let mut image = vec![0u8; 320 * 320];
//! renderer.render(&scene, &pose, 0, &mut image, 320).unwrap();
//! ```

#![warn(missing_docs)]

pub mod bake;
pub mod bench;
pub mod boulder_fields;
pub mod camera;
pub mod config;
pub mod craters;
pub mod error;
pub mod footprint;
pub mod landforms;
pub mod mesh;
pub mod noise;
pub mod raster;
pub mod rng;
pub mod rocks;
pub mod shadows;
pub mod terrain;
pub mod texture;
pub mod world;

pub use config::WorldConfig;
pub use error::{ConfigError, RenderError, SimError, WorldError};
pub use world::World;
