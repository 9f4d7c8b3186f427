//! The map cells the rover's camera had in sight: the true world (terrain, craters, the rocks'
//! lumpy meshes) rendered from the rover's left camera at its true poses, and every pixel's
//! depth carried back to the ground or rock it shows. A cell is in sight when some pixel within
//! reach landed in it. Ground hidden behind a rock or below a crater's rim is not: a map can
//! only infer it, and the traversability judge leaves it out (the issue's "cells the rover
//! observed"), where the field-of-view judge ([`Reach::InView`](crate::traversability::Reach))
//! counts it.
//!
//! The camera renders the same scene, so what this calls in sight is what the stereo images
//! held, texture aside (a cell in sight may still be too bare for a feature).

use std::sync::Arc;

use hopnav_planner::mission::MapGeometry;
use hopnav_world::camera::CameraConfig;
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use hopnav_world::{RenderError, World, WorldError};
use nalgebra::{Isometry3, Point3};

/// A view is rendered when the camera moved this far since the last one rendered, metres.
const VIEW_STEP_M: f64 = 0.1;
/// … or turned this much, radians.
const VIEW_TURN_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// What rendering the rover camera's views needs, built once per world.
#[derive(Debug, Clone)]
pub struct LineOfSight {
    scene: Arc<RenderScene>,
    camera: CameraConfig,
    body_from_camera: Isometry3<f64>,
}

/// Why the cells in sight could not be found.
#[derive(Debug, thiserror::Error)]
pub enum LineOfSightError {
    /// The world's render scene could not be built.
    #[error("line of sight: cannot build the render scene: {0}")]
    Scene(#[from] WorldError),
    /// The camera config is invalid.
    #[error("line of sight: invalid camera config: {0}")]
    Camera(#[from] hopnav_world::ConfigError),
    /// A view could not be rendered.
    #[error("line of sight: rendering a view failed: {0}")]
    Render(#[from] RenderError),
}

impl LineOfSight {
    /// The scene of `world` seen through `camera` mounted at `body_from_camera` (OpenCV
    /// frame: z along the optical axis).
    pub fn new(
        world: &World,
        camera: &CameraConfig,
        body_from_camera: Isometry3<f64>,
    ) -> Result<Self, LineOfSightError> {
        camera.validate("camera.rover")?;
        Ok(Self {
            scene: Arc::new(RenderScene::new(world)?),
            camera: camera.clone(),
            body_from_camera,
        })
    }

    /// The cells of `geometry` the camera had in sight within `reach_m` (horizontally) at
    /// some pose of `world_from_body` (views closer than 0.1 m and 3° to the last rendered
    /// one are skipped: they add next to nothing).
    pub fn seen_cells<'a>(
        &self,
        world_from_body: impl IntoIterator<Item = &'a Isometry3<f64>>,
        geometry: &MapGeometry,
        reach_m: f64,
    ) -> Result<SeenCells, LineOfSightError> {
        let render = RenderConfig {
            noise_sigma_dn: 0.0,
            detail_texture: false,
            ..RenderConfig::default()
        };
        let mut renderer = Renderer::new(&self.camera, &render)?;
        let intrinsics = *renderer.camera();
        let (width, height) = (intrinsics.width_px as usize, intrinsics.height_px as usize);
        let mut image = vec![0_u8; width * height];
        let mut seen = SeenCells::none(*geometry);
        let mut last: Option<Isometry3<f64>> = None;
        for pose in world_from_body {
            let world_from_camera = pose * self.body_from_camera;
            if last.is_some_and(|last| close_views(&last, &world_from_camera)) {
                continue;
            }
            last = Some(world_from_camera);
            renderer.render(&self.scene, &world_from_camera, 0, &mut image, width)?;
            let eye = world_from_camera.translation.vector;
            for (index, &inverse_depth) in renderer.inverse_depth().iter().enumerate() {
                if inverse_depth <= 0.0 || !inverse_depth.is_finite() {
                    continue;
                }
                let z_m = 1.0 / f64::from(inverse_depth);
                let (u, v) = ((index % width) as f64, (index / width) as f64);
                let in_camera = Point3::new(
                    (u - intrinsics.cx_px) / intrinsics.fx_px * z_m,
                    (v - intrinsics.cy_px) / intrinsics.fy_px * z_m,
                    z_m,
                );
                let point = world_from_camera * in_camera;
                if (point.x - eye.x).hypot(point.y - eye.y) <= reach_m {
                    seen.mark([point.x, point.y]);
                }
            }
        }
        Ok(seen)
    }
}

/// Two camera poses close enough that the second adds next to nothing to the first.
fn close_views(a: &Isometry3<f64>, b: &Isometry3<f64>) -> bool {
    (a.translation.vector - b.translation.vector).norm() < VIEW_STEP_M
        && a.rotation.angle_to(&b.rotation) < VIEW_TURN_RAD
}

/// A set of cells of a map grid.
#[derive(Debug, Clone, PartialEq)]
pub struct SeenCells {
    geometry: MapGeometry,
    /// Row-major, one per cell of `geometry`.
    seen: Vec<bool>,
}

impl SeenCells {
    /// No cell of `geometry`.
    pub fn none(geometry: MapGeometry) -> Self {
        let cells = geometry.width_cells() as usize * geometry.height_cells() as usize;
        Self {
            geometry,
            seen: vec![false; cells],
        }
    }

    /// Adds the cell holding `point_m` (nothing off the grid).
    pub fn mark(&mut self, point_m: [f64; 2]) {
        if let Some(index) = self.index(point_m) {
            self.seen[index] = true;
        }
    }

    /// The cell holding `point_m` is in the set.
    pub fn contains(&self, point_m: [f64; 2]) -> bool {
        self.index(point_m).is_some_and(|index| self.seen[index])
    }

    /// Cells in the set.
    pub fn count(&self) -> usize {
        self.seen.iter().filter(|seen| **seen).count()
    }

    fn index(&self, point_m: [f64; 2]) -> Option<usize> {
        let cell = self.geometry.cell_of(point_m)?;
        Some(cell.y as usize * self.geometry.width_cells() as usize + cell.x as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jumper_vo::truth_surface::tests::flat_config_with_a_rock;
    use hopnav_robot::camera::{CameraMount, CameraRig};

    /// A flat 16 m world with one rock 0.6 m tall and 1 m across, 3 m ahead of the origin.
    fn world_with_a_rock() -> World {
        let mut config = flat_config_with_a_rock([3.0, 0.0], 0.6);
        config.terrain.size_x_m = 16.0;
        config.terrain.size_y_m = 16.0;
        config.texture.texel_m = 0.5;
        World::generate(&config).expect("a valid flat world")
    }

    /// The rover's camera 0.8 m above its body's origin, looking along +x and 15° down.
    fn camera_on_a_mast(world: &World) -> LineOfSight {
        let mount = CameraMount {
            position_m: [0.0, 0.0, 0.8],
            yaw_rad: 0.0,
            pitch_down_rad: 15_f64.to_radians(),
        };
        LineOfSight::new(world, &CameraRig::default().rover, mount.body_from_camera())
            .expect("a valid camera")
    }

    fn grid() -> MapGeometry {
        MapGeometry::new(-8.0, -8.0, 0.25, 64, 64).expect("a valid grid")
    }

    #[test]
    fn the_ground_behind_a_rock_is_out_of_sight_and_the_ground_beside_it_in_sight() {
        let world = world_with_a_rock();
        let ground_m = world.ground_height_at(0.0, 0.0);
        let pose = Isometry3::translation(0.0, 0.0, ground_m);
        let seen = camera_on_a_mast(&world)
            .seen_cells([&pose], &grid(), 5.0)
            .expect("renders");
        assert!(seen.contains([2.1, 0.1]), "the ground before the rock");
        assert!(seen.contains([2.9, 0.1]), "the rock's top");
        assert!(
            !seen.contains([3.9, 0.1]),
            "the ground right behind the rock"
        );
        assert!(!seen.contains([4.6, 0.1]), "farther behind it");
        assert!(seen.contains([3.9, 1.6]), "the ground beside it");
        assert!(!seen.contains([-2.0, 0.1]), "behind the camera");
        assert!(!seen.contains([5.9, 1.6]), "beyond reach");
        assert!(!seen.contains([3.0, 4.5]), "outside the field of view");
    }

    #[test]
    fn driving_past_the_rock_brings_the_ground_behind_it_into_sight() {
        let world = world_with_a_rock();
        let ground_m = world.ground_height_at(0.0, 0.0);
        let track: Vec<Isometry3<f64>> = (0..=30)
            .map(|step| {
                // Along y = -2, then turned toward the rock's far side.
                let x_m = 0.2 * f64::from(step);
                Isometry3::new(
                    nalgebra::Vector3::new(x_m, -2.0, ground_m),
                    nalgebra::Vector3::z() * if x_m > 3.0 { 1.2 } else { 0.0 },
                )
            })
            .collect();
        let seen = camera_on_a_mast(&world)
            .seen_cells(&track, &grid(), 5.0)
            .expect("renders");
        assert!(
            seen.contains([3.9, 0.1]),
            "the rock's far side seen from beside it"
        );
        assert!(seen.count() > 100, "{} cells", seen.count());
    }

    #[test]
    fn a_point_off_the_grid_is_neither_marked_nor_contained() {
        let mut seen = SeenCells::none(grid());
        seen.mark([100.0, 0.0]);
        seen.mark([f64::NAN, 0.0]);
        assert_eq!(seen.count(), 0);
        assert!(!seen.contains([100.0, 0.0]));
        seen.mark([0.1, 0.1]);
        assert!(seen.contains([0.2, 0.2]) && !seen.contains([0.3, 0.1]));
    }
}
