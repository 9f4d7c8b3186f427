//! The `traversability` obstacle model's state in the map: a [`CellBelief`] per cell, fed
//! with every accepted point's height and sigma and with the free space its ray crossed.
//!
//! Memory is one fixed array, allocated with the map.

use hopnav_ipc::messages::Robot;

use crate::belief::{BeliefClass, BeliefParams, CellBelief};
use crate::config::MapperConfig;
use crate::dirty::DirtySet;
use crate::dome_layer::RockEvidence;
use crate::geometry::GridGeometry;
use crate::rays::for_each_cell_below;

/// Rays are followed only where they run lower than this above the ground, metres: a rock
/// the map claims taller than that is not cleared by rays (none of the Golombek rocks the
/// rover meets is).
const RAY_MAX_HEIGHT_M: f64 = 2.0;

/// Where a point comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSource {
    /// The robot whose cloud it is.
    pub robot: Robot,
    /// The map's number of that cloud (a cell counts each cloud's vote once).
    pub cloud: u32,
    /// Where the camera stood, when known (the rover's: which side of a rock it saw).
    pub camera_xy_m: Option<[f64; 2]>,
}

/// Per-cell beliefs of the whole grid.
#[derive(Debug)]
pub struct BeliefLayer {
    params: BeliefParams,
    /// The same with the jumper's points judged one by one, never fused into a top (see
    /// [`BeliefParams::point_hit_sigmas`]).
    jumper_params: BeliefParams,
    sigma_floor_m: f32,
    beliefs: Vec<CellBelief>,
    rays_counted: u64,
}

impl BeliefLayer {
    /// Unknown everywhere, for `cells` cells, with the rover's climb limit of `config`.
    pub fn new(config: &MapperConfig, cells: usize) -> Self {
        let params = BeliefParams {
            hit_sigmas: config.hit_sigmas as f32,
            hit_margin_m: config.hit_margin_m as f32,
            rock_lethal_sigmas: config.rock_lethal_sigmas as f32,
            ..BeliefParams::new(config.rover_body.max_climbable_height_m)
        };
        Self {
            params,
            jumper_params: BeliefParams {
                point_hit_sigmas: Some(config.jumper_height_sigma_factor as f32),
                fuse_top: false,
                ..params
            },
            sigma_floor_m: config.height_sigma_floor_m as f32,
            beliefs: vec![CellBelief::default(); cells],
            rays_counted: 0,
        }
    }

    /// A point of `source` at `xy_m` in cell `index`, `height_m` above its local ground, with
    /// a one-sigma height uncertainty `sigma_m` (raised to the configured floor).
    pub fn add_point(
        &mut self,
        index: usize,
        source: PointSource,
        xy_m: [f32; 2],
        height_m: f32,
        sigma_m: f32,
    ) {
        let PointSource {
            robot,
            cloud,
            camera_xy_m,
        } = source;
        let sigma_m = self.floored_sigma_m(sigma_m);
        let flank_m = 0.5 * self.params.climb_limit_m;
        if let Some(belief) = self.beliefs.get_mut(index) {
            let params = match robot {
                Robot::Rover => &self.params,
                Robot::Jumper => &self.jumper_params,
            };
            belief.add_point(params, cloud, height_m, sigma_m);
            if height_m >= flank_m {
                belief.extend(xy_m);
                if let Some([cx, cy]) = camera_xy_m {
                    belief.add_view([
                        (f64::from(xy_m[0]) - cx) as f32,
                        (f64::from(xy_m[1]) - cy) as f32,
                    ]);
                }
            }
        }
    }

    /// The rover saw the ground at world height `ground_z_m` (± `sigma_m`, raised to the
    /// configured floor) in cell `index`.
    pub fn add_ground(&mut self, index: usize, ground_z_m: f32, sigma_m: f32) {
        let sigma_m = self.floored_sigma_m(sigma_m);
        if let Some(belief) = self.beliefs.get_mut(index) {
            belief.ground.add(ground_z_m, sigma_m);
        }
    }

    /// The ground's elevation in cell `index`, metres (`None` where the rover saw none).
    pub fn ground_z_m(&self, index: usize) -> Option<f32> {
        self.beliefs.get(index)?.ground.z_m()
    }

    /// The ray of cloud `cloud` from `camera_m` to `point_m` (whose local ground is at
    /// `ground_z_m`) crossed the cells before the point: a miss for each whose claimed top it
    /// passed under. The cells whose belief changed go into `touched`.
    pub fn add_ray(
        &mut self,
        geometry: &GridGeometry,
        camera_m: [f64; 3],
        point_m: [f64; 3],
        ground_z_m: f64,
        cloud: u32,
        touched: &mut DirtySet,
    ) {
        let (params, beliefs) = (&self.params, &mut self.beliefs);
        let mut counted = 0;
        for_each_cell_below(
            geometry,
            camera_m,
            point_m,
            ground_z_m,
            RAY_MAX_HEIGHT_M,
            |index, ray_height_m| {
                if let Some(belief) = beliefs.get_mut(index)
                    && belief.add_ray(params, cloud, ray_height_m)
                {
                    touched.insert(index);
                    counted += 1;
                }
            },
        );
        self.rays_counted += counted;
    }

    /// What the belief says of cell `index` (unknown outside the grid).
    pub fn class(&self, index: usize) -> BeliefClass {
        self.beliefs
            .get(index)
            .map_or(BeliefClass::Unknown, |belief| belief.class(&self.params))
    }

    /// What a fitted rock of `height_m` ± `sigma_m` makes of the ground under it: lethal when
    /// its height plus `rock_lethal_sigmas` sigmas stands above the climb limit (−1 by
    /// default: a sigma above it), uncertain when its height plus two sigmas does,
    /// traversable otherwise. No margin for reading low: the fit models the dome, not its
    /// flanks.
    pub fn judge_rock(&self, height_m: f32, sigma_m: f32) -> BeliefClass {
        let p = &self.params;
        if height_m + p.rock_lethal_sigmas * sigma_m > p.climb_limit_m {
            BeliefClass::Lethal
        } else if height_m + p.confidence_sigmas * sigma_m > p.climb_limit_m {
            BeliefClass::Uncertain
        } else {
            BeliefClass::Traversable
        }
    }

    /// A height sigma raised to the configured floor, as the beliefs fuse it.
    pub fn floored_sigma_m(&self, sigma_m: f32) -> f32 {
        sigma_m.hypot(self.sigma_floor_m)
    }

    /// The belief of cell `index`.
    pub fn belief(&self, index: usize) -> Option<&CellBelief> {
        self.beliefs.get(index)
    }

    /// The rover's climb limit the beliefs judge against, metres.
    pub fn climb_limit_m(&self) -> f32 {
        self.params.climb_limit_m
    }

    /// Ray crossings that counted as a miss so far.
    pub fn rays_counted(&self) -> u64 {
        self.rays_counted
    }

    /// Every cell's belief, for snapshots.
    pub fn beliefs(&self) -> &[CellBelief] {
        &self.beliefs
    }

    /// Restores the beliefs of a snapshot (same length as the grid; a shorter or longer one
    /// is refused by the caller).
    pub fn set_beliefs(&mut self, beliefs: &[CellBelief]) {
        if beliefs.len() == self.beliefs.len() {
            self.beliefs.copy_from_slice(beliefs);
        }
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.beliefs.capacity() * size_of::<CellBelief>()
    }
}

impl RockEvidence for BeliefLayer {
    fn usable(&self, cell: usize) -> bool {
        self.belief(cell).is_some_and(|belief| !belief.ray_cleared)
    }

    fn view_direction(&self, cell: usize) -> Option<[f32; 2]> {
        self.belief(cell).and_then(CellBelief::view_direction)
    }

    fn seen_top(&self, cell: usize) -> Option<(f32, f32)> {
        self.belief(cell)
            .filter(|belief| belief.top_count >= 2)
            .map(|belief| (belief.top_m, belief.top_sigma_m()))
    }

    fn judge(&self, height_m: f32, sigma_m: f32) -> BeliefClass {
        self.judge_rock(height_m, sigma_m)
    }
}

#[cfg(test)]
#[path = "traversability_tests.rs"]
mod tests;
