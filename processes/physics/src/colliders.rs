//! World colliders: the terrain heightfield and one convex hull per rock.
//!
//! # Terrain
//! Parry's heightfield is y-up with rows along local z and columns along local x, stored in a
//! column-major `Array2`. The world is z-up with row-major heights (`heights[j·nx + i]`,
//! column `i` along x, row `j` along y). The collider is rotated +90° about x (local y → world
//! z, local z → world −y), so row `r` of the parry matrix holds world row `j = ny − 1 − r`, and
//! it is translated to the grid centre. Parry triangulates each cell; on a plane this equals the
//! world's bilinear surface, elsewhere they differ by at most the cell's non-planarity.
//!
//! # Rocks
//! Each rock is the convex hull of its render mesh ([`rock_mesh`]: the lumpy half-buried
//! ellipsoid the camera draws), so what the robots touch is what the cameras see. Should the
//! hull fail (degenerate input) a yawed cuboid of the rock's half extents is used instead.
//! Hull points are stored relative to the rock centre to keep f32 precision.
//!
//! The hulls are grouped into **two compound colliders**: rocks taller than the rover's
//! `max_climbable_height_m` ([`BLOCKING_ROCK_GROUP`]) and the others
//! ([`CLIMBABLE_ROCK_GROUP`]); the rover's scene queries use these groups. Thousands of
//! separate fixed colliders would make rapier 0.36 rescan them every substep (its CCD
//! fixed-target cache is rebuilt whenever a body is moved by the user, as the kinematic rover
//! is): ≈ 60 µs per substep with the default world's ≈ 6000 rocks. A compound keeps one
//! static BVH of its parts. [`WorldColliders::rock_at`] maps a compound part back to its rock.

use hopnav_world::World;
use hopnav_world::mesh::rock_mesh;
use hopnav_world::rocks::Rock;
use hopnav_world::terrain::Heightfield;
use rapier3d::math::Pose;
use rapier3d::parry::query::intersection_test;
use rapier3d::parry::shape::{Shape, SharedShape};
use rapier3d::parry::utils::Array2;
use rapier3d::prelude::{
    ColliderBuilder, ColliderHandle, Group, InteractionGroups, InteractionTestMode, PhysicsWorld,
};

use crate::math::{DVec3, Vec3, to_f32};

/// Collision group of the terrain heightfield.
pub const TERRAIN_GROUP: Group = Group::GROUP_1;
/// Collision group of rocks the rover can drive over.
pub const CLIMBABLE_ROCK_GROUP: Group = Group::GROUP_2;
/// Collision group of rocks that block the rover.
pub const BLOCKING_ROCK_GROUP: Group = Group::GROUP_3;
/// Collision group of the jumper.
pub const JUMPER_GROUP: Group = Group::GROUP_4;
/// Collision group of the rover chassis.
pub const ROVER_GROUP: Group = Group::GROUP_5;

/// Member of `group`, interacting with everything.
pub fn member_of(group: Group) -> InteractionGroups {
    InteractionGroups::new(group, Group::ALL, InteractionTestMode::And)
}

/// Query groups that hit only colliders in `groups`.
pub fn query_groups(groups: Group) -> InteractionGroups {
    InteractionGroups::new(Group::ALL, groups, InteractionTestMode::And)
}

/// Parts of one rock compound (pose and shape of each rock) and their rock indices.
type RockParts = (Vec<(Pose, SharedShape)>, Vec<usize>);

/// The compound collider of one rock class and the rock index of each of its parts.
#[derive(Debug, Clone, PartialEq)]
pub struct RockCompound {
    /// Rapier handle of the compound collider.
    pub handle: ColliderHandle,
    /// `rock_indices[k]` is the index in [`World::rocks`] of compound part `k`.
    pub rock_indices: Vec<usize>,
}

/// Handles of the static world colliders.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldColliders {
    /// The terrain heightfield.
    pub terrain: ColliderHandle,
    /// Rocks the rover can climb (`None` when there are none).
    pub climbable: Option<RockCompound>,
    /// Rocks that block the rover (`None` when there are none).
    pub blocking: Option<RockCompound>,
    /// Rocks whose convex hull failed and that use a cuboid instead.
    pub fallback_cuboids: usize,
}

impl WorldColliders {
    /// Inserts the terrain and every rock of `world` as fixed colliders.
    ///
    /// Rocks with `height_m > max_climbable_height_m` are blocking.
    pub fn insert(
        pw: &mut PhysicsWorld,
        world: &World,
        terrain_friction: f64,
        rock_friction: f64,
        max_climbable_height_m: f64,
    ) -> Self {
        let terrain = pw.insert_collider(
            heightfield_collider(world.terrain())
                .friction(terrain_friction as f32)
                .collision_groups(member_of(TERRAIN_GROUP)),
            None,
        );
        let mut parts: [RockParts; 2] = Default::default();
        let mut fallback_cuboids = 0;
        for (index, rock) in world.rocks().iter().enumerate() {
            let (pose, shape, fallback) = rock_shape(rock);
            fallback_cuboids += usize::from(fallback);
            let class = &mut parts[usize::from(rock.height_m > max_climbable_height_m)];
            class.0.push((pose, shape));
            class.1.push(index);
        }
        let [climbable, blocking] = parts;
        let mut insert = |(shapes, rock_indices): RockParts, group: Group| {
            if shapes.is_empty() {
                return None;
            }
            let handle = pw.insert_collider(
                ColliderBuilder::compound(shapes)
                    .friction(rock_friction as f32)
                    .collision_groups(member_of(group)),
                None,
            );
            Some(RockCompound {
                handle,
                rock_indices,
            })
        };
        Self {
            terrain,
            climbable: insert(climbable, CLIMBABLE_ROCK_GROUP),
            blocking: insert(blocking, BLOCKING_ROCK_GROUP),
            fallback_cuboids,
        }
    }

    /// Number of rocks in both compounds.
    pub fn rock_count(&self) -> usize {
        self.climbable.as_ref().map_or(0, |c| c.rock_indices.len())
            + self.blocking.as_ref().map_or(0, |c| c.rock_indices.len())
    }

    /// Number of rocks that block the rover.
    pub fn blocking_count(&self) -> usize {
        self.blocking.as_ref().map_or(0, |c| c.rock_indices.len())
    }

    /// Index into [`World::rocks`] of the first rock (of the compound `handle`) that
    /// intersects `shape` at `pose`; `None` if `handle` is no rock compound or nothing overlaps.
    pub fn rock_at(
        &self,
        pw: &PhysicsWorld,
        handle: ColliderHandle,
        pose: &Pose,
        shape: &dyn Shape,
    ) -> Option<usize> {
        let compound = [&self.climbable, &self.blocking]
            .into_iter()
            .flatten()
            .find(|c| c.handle == handle)?;
        let collider = pw.colliders.get(handle)?;
        let parts = collider.shape().as_compound()?;
        parts
            .shapes()
            .iter()
            .zip(&compound.rock_indices)
            .find(|((part_pose, part), _)| {
                let world_from_part = *collider.position() * *part_pose;
                intersection_test(&world_from_part, part.as_ref(), pose, shape)
                    .is_ok_and(|hit| hit.intersecting)
            })
            .map(|(_, &index)| index)
    }
}

/// A fixed heightfield collider matching `hf` in world coordinates (see the module docs).
pub fn heightfield_collider(hf: &Heightfield) -> ColliderBuilder {
    let (nx, ny) = (hf.nx(), hf.ny());
    let heights = hf.heights_m();
    // Column-major: element (row r, col c) lives at r + c·nrows.
    let mut data = Vec::with_capacity(nx * ny);
    for c in 0..nx {
        for r in 0..ny {
            let j = ny - 1 - r;
            data.push(heights[j * nx + c] as f32);
        }
    }
    let matrix = Array2::new(ny, nx, data);
    let [ex, ey] = hf.extent_m();
    let [ox, oy] = hf.origin_m();
    let scale = Vec3::new(ex as f32, 1.0, ey as f32);
    ColliderBuilder::heightfield(matrix, scale)
        .translation(to_f32(DVec3::new(ox + ex / 2.0, oy + ey / 2.0, 0.0)))
        .rotation(Vec3::new(std::f32::consts::FRAC_PI_2, 0.0, 0.0))
}

/// The shape of `rock` and its pose in the world: the convex hull of its mesh, or a cuboid
/// fallback (third value `true`).
pub fn rock_shape(rock: &Rock) -> (Pose, SharedShape, bool) {
    let centre = DVec3::from_array(rock.center_m);
    let mesh = rock_mesh(rock);
    let points: Vec<Vec3> = mesh
        .positions_m
        .iter()
        .map(|p| to_f32(DVec3::from_array(*p) - centre))
        .collect();
    match SharedShape::convex_hull(&points) {
        Some(shape) => (Pose::from_translation(to_f32(centre)), shape, false),
        None => {
            let [a, b, c] = rock.half_extents_m;
            let pose = Pose::new(to_f32(centre), Vec3::new(0.0, 0.0, rock.yaw_rad as f32));
            (
                pose,
                SharedShape::cuboid(a as f32, b as f32, c as f32),
                true,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::prelude::{QueryFilter, Ray};

    /// The default terrain on `size_x_m × size_y_m`, without craters or random rocks.
    fn bare_world(size_x_m: f64, size_y_m: f64) -> hopnav_world::WorldConfig {
        let mut cfg = hopnav_world::WorldConfig::default();
        cfg.terrain.size_x_m = size_x_m;
        cfg.terrain.size_y_m = size_y_m;
        cfg.craters.count = 0;
        cfg.rocks.golombek_k = 0.0;
        cfg
    }

    #[test]
    fn heightfield_matches_world_heights() {
        // A tilted plane plus one bump at a node: rays straight down hit the world height.
        let mut cfg = bare_world(6.0, 4.0);
        cfg.terrain.spacing_m = 0.5;
        let world = World::generate(&cfg).unwrap();
        let hf = world.terrain();
        let mut pw = PhysicsWorld::new();
        let _ = pw.insert_collider(heightfield_collider(hf), None);
        pw.detect_collisions(&(), &());
        for j in 0..hf.ny() {
            for i in 0..hf.nx() {
                let [x, y] = hf.node_xy_m(i, j);
                // Stay inside the border and off the grid lines, with a slight tilt: parry
                // 0.31's heightfield ray cast misses some vertical rays and rays starting
                // exactly above grid lines (e.g. x = 0 or (1.5, 1.5) here).
                let x = (x + 0.0371).clamp(-2.98, 2.98);
                let y = (y + 0.0293).clamp(-1.98, 1.98);
                let dir = Vec3::new(1e-3, 1e-3, -1.0).normalize();
                let ray = Ray::new(Vec3::new(x as f32, y as f32, 5.0), dir);
                let hit = pw.cast_ray(&ray, 100.0, true, QueryFilter::default());
                let Some((_, toi)) = hit else {
                    panic!("no hit at ({x}, {y})");
                };
                let p = ray.point_at(toi);
                let (z, expected) = (f64::from(p.z), hf.height_at(f64::from(p.x), f64::from(p.y)));
                // Bilinear vs triangulated surface: they agree at nodes and differ by the
                // cell's non-planarity in between (< 1 cm for this relief at 0.5 m cells).
                assert!((z - expected).abs() < 0.01, "({x}, {y}): {z} vs {expected}");
            }
        }
    }

    #[test]
    fn rock_hull_covers_its_top() {
        let mut cfg = bare_world(8.0, 8.0);
        cfg.terrain.relief_amplitude_m = 0.0;
        cfg.rocks
            .explicit
            .push(hopnav_world::config::ExplicitRockConfig {
                center_m: [1.0, -1.0],
                diameter_m: 1.0,
                height_m: Some(0.5),
            });
        let world = World::generate(&cfg).unwrap();
        let mut pw = PhysicsWorld::new();
        let cols = WorldColliders::insert(&mut pw, &world, 0.8, 0.8, 0.2);
        pw.detect_collisions(&(), &());
        assert_eq!(
            (
                cols.blocking_count(),
                cols.rock_count(),
                cols.fallback_cuboids
            ),
            (1, 1, 0)
        );
        let ray = Ray::new(Vec3::new(1.0, -1.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let (h, toi) = pw
            .cast_ray(&ray, 10.0, true, QueryFilter::default())
            .unwrap();
        let probe = rapier3d::parry::shape::Ball::new(0.05);
        let at = Pose::from_translation(Vec3::new(1.0, -1.0, 0.2));
        assert_eq!(cols.rock_at(&pw, h, &at, &probe), Some(0));
        let top = 5.0 - f64::from(toi);
        assert!((top - 0.5).abs() < 0.15, "top {top}");
    }
}
