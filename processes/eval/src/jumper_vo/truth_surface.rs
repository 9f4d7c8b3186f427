//! The world's surface as the jumper's camera renders it, for judging its points: a viewing
//! ray cast onto the terrain (marched in small steps) and the rocks' rendered meshes
//! (intersected exactly, Möller–Trumbore).

use hopnav_world::World;
use hopnav_world::mesh::{TriMesh, rock_mesh};
use nalgebra::{Point3, Vector3};
use std::collections::HashMap;

/// Rays are followed this far from the camera, metres.
pub const MAX_RAY_M: f64 = 80.0;
/// Step of the terrain march, metres.
const RAY_STEP_M: f64 = 0.02;

/// What a viewing ray hit first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SurfaceHit {
    /// Bare terrain, this far from the nearest rock's bounding circle, metres.
    Ground {
        /// Distance to the nearest rock's bounding circle (∞ without rocks), metres.
        rock_clearance_m: f64,
    },
    /// A rock's surface, this high above the terrain under it, metres.
    Rock {
        /// Height of the hit above the terrain, metres.
        true_height_m: f64,
    },
}

/// The world's surface for ray casting: the terrain, marched in small steps, and the rocks'
/// rendered meshes ([`rock_mesh`]), intersected exactly. Rocks are bucketed in 1 m cells so a
/// ray looks only at the rocks along it.
pub struct TruthSurface<'a> {
    world: &'a World,
    rock_meshes: Vec<TriMesh>,
    rocks_by_cell: HashMap<(i64, i64), Vec<usize>>,
}

impl<'a> TruthSurface<'a> {
    /// Meshes and indexes `world`'s rocks.
    pub fn new(world: &'a World) -> Self {
        let mut rocks_by_cell: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (index, rock) in world.rocks().iter().enumerate() {
            let radius_m = rock.bounding_radius_m() * MESH_BOUND_FACTOR;
            let [x, y, _] = rock.center_m;
            for cx in (x - radius_m).floor() as i64..=(x + radius_m).floor() as i64 {
                for cy in (y - radius_m).floor() as i64..=(y + radius_m).floor() as i64 {
                    rocks_by_cell.entry((cx, cy)).or_default().push(index);
                }
            }
        }
        Self {
            world,
            rock_meshes: world.rocks().iter().map(rock_mesh).collect(),
            rocks_by_cell,
        }
    }

    /// Distance from (x, y) to the nearest rock's bounding circle, metres (∞ without rocks).
    fn rock_clearance_m(&self, x_m: f64, y_m: f64) -> f64 {
        self.world
            .rocks()
            .iter()
            .map(|rock| {
                (x_m - rock.center_m[0]).hypot(y_m - rock.center_m[1])
                    - rock.bounding_radius_m() * MESH_BOUND_FACTOR
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The first surface along the unit ray from `origin`, within [`MAX_RAY_M`].
    pub fn cast(&self, origin: &Point3<f64>, direction: &Vector3<f64>) -> Option<SurfaceHit> {
        // The terrain first, then any rock met before it.
        let mut terrain_range_m = None;
        let mut candidates: Vec<usize> = Vec::new();
        let mut last_cell = None;
        let mut range_m = 0.0;
        while range_m < MAX_RAY_M {
            let at = origin + direction * range_m;
            let cell = (at.x.floor() as i64, at.y.floor() as i64);
            if last_cell != Some(cell) {
                candidates.extend(self.rocks_by_cell.get(&cell).into_iter().flatten());
                last_cell = Some(cell);
            }
            if at.z <= self.world.ground_height_at(at.x, at.y) {
                terrain_range_m = Some(range_m);
                break;
            }
            range_m += RAY_STEP_M;
        }
        candidates.sort_unstable();
        candidates.dedup();
        let rock_hit = candidates
            .iter()
            .filter_map(|&index| {
                let mesh = self.rock_meshes.get(index)?;
                ray_mesh_range_m(origin, direction, mesh).map(|range_m| (range_m, index))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match (rock_hit, terrain_range_m) {
            (Some((rock_range_m, _)), Some(ground_range_m)) if rock_range_m > ground_range_m => {
                Some(self.ground_hit(origin, direction, ground_range_m))
            }
            (Some((rock_range_m, _)), _) => {
                let at = origin + direction * rock_range_m;
                Some(SurfaceHit::Rock {
                    true_height_m: at.z - self.world.ground_height_at(at.x, at.y),
                })
            }
            (None, Some(ground_range_m)) => {
                Some(self.ground_hit(origin, direction, ground_range_m))
            }
            (None, None) => None,
        }
    }

    fn ground_hit(
        &self,
        origin: &Point3<f64>,
        direction: &Vector3<f64>,
        range_m: f64,
    ) -> SurfaceHit {
        let at = origin + direction * range_m;
        SurfaceHit::Ground {
            rock_clearance_m: self.rock_clearance_m(at.x, at.y),
        }
    }
}

/// A rock mesh's lumps reach past its ellipsoid by up to this factor (five waves of at most
/// 0.1 plus 0.1 of jitter).
const MESH_BOUND_FACTOR: f64 = 1.6;

/// Range to the nearest triangle of `mesh` the unit ray crosses (Möller–Trumbore).
fn ray_mesh_range_m(origin: &Point3<f64>, direction: &Vector3<f64>, mesh: &TriMesh) -> Option<f64> {
    let vertex = |index: u32| {
        mesh.positions_m
            .get(index as usize)
            .map(|p| Vector3::new(p[0], p[1], p[2]))
    };
    mesh.triangles
        .iter()
        .filter_map(|triangle| {
            let (a, b, c) = (
                vertex(triangle[0])?,
                vertex(triangle[1])?,
                vertex(triangle[2])?,
            );
            let (edge1, edge2) = (b - a, c - a);
            let p = direction.cross(&edge2);
            let det = edge1.dot(&p);
            if det.abs() < 1e-12 {
                return None;
            }
            let to_origin = origin.coords - a;
            let u = to_origin.dot(&p) / det;
            let q = to_origin.cross(&edge1);
            let v = direction.dot(&q) / det;
            let range_m = edge2.dot(&q) / det;
            (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && range_m > 0.0).then_some(range_m)
        })
        .min_by(f64::total_cmp)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use hopnav_world::WorldConfig;
    use hopnav_world::config::ExplicitRockConfig;

    /// Flat ground at z = 0, no random rocks or craters, one rock 1 m across and `height_m`
    /// tall at `center_m`.
    pub(crate) fn flat_config_with_a_rock(center_m: [f64; 2], height_m: f64) -> WorldConfig {
        let mut config = WorldConfig::default();
        config.terrain.relief_amplitude_m = 0.0;
        config.craters.count = 0;
        config.rocks.golombek_k = 0.0;
        config.rocks.explicit = vec![ExplicitRockConfig {
            center_m,
            diameter_m: 1.0,
            height_m: Some(height_m),
        }];
        config
    }

    /// Flat ground at z = 0, no random rocks or craters, one 0.4 m rock at (0, 0).
    pub(crate) fn flat_world_with_a_rock() -> World {
        World::generate(&flat_config_with_a_rock([0.0, 0.0], 0.4)).unwrap()
    }

    #[test]
    fn a_ray_straight_down_hits_the_rock_top_and_beside_it_the_ground() {
        let world = flat_world_with_a_rock();
        let surface = TruthSurface::new(&world);
        let down = -Vector3::z();
        let ground_m = world.ground_height_at(0.0, 0.0);
        match surface.cast(&Point3::new(0.0, 0.0, ground_m + 10.0), &down) {
            Some(SurfaceHit::Rock { true_height_m }) => {
                // The mesh top is 0.4 m at its highest vertex, a little lower elsewhere.
                assert!(
                    true_height_m > 0.3 && true_height_m <= 0.4 + 1e-9,
                    "{true_height_m}"
                )
            }
            other => panic!("expected the rock, got {other:?}"),
        }
        match surface.cast(&Point3::new(3.0, 0.0, ground_m + 10.0), &down) {
            Some(SurfaceHit::Ground { rock_clearance_m }) => {
                assert!(
                    rock_clearance_m > 2.0 && rock_clearance_m < 3.0,
                    "{rock_clearance_m}"
                )
            }
            other => panic!("expected the ground, got {other:?}"),
        }
        assert_eq!(
            surface.cast(&Point3::new(3.0, 0.0, 10.0), &Vector3::z()),
            None
        );
    }
}
