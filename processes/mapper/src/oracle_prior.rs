//! The perfect-scout oracle (`[mapper] oracle_prior_map`, evaluation only): the mapper starts
//! with the clouds a flawless scout would have sent before the rover moved, every rock of the
//! world sampled on its true surface. A mission run with it bounds what any scouting (a better
//! jumper VO, registration, more hops, other hop targets) could give the rover: its path,
//! replans and success are the ceiling of cooperative mode.
//!
//! The points are stereo-quality rover points (exact heights above the ground, tiny sigma),
//! so the map classifies them as it would the rover's own close look: the planner takes them
//! at once, with no jumper vote, batch or doubt.
//!
//! ```
//! use hopnav_mapper::oracle_prior::rock_surface_points;
//! use hopnav_world::rocks::{Rock, RockSource};
//! let rock = Rock {
//!     center_m: [1.0, 2.0, 0.0],
//!     diameter_m: 1.0,
//!     height_m: 0.5,
//!     half_extents_m: [0.5, 0.5, 0.5],
//!     yaw_rad: 0.0,
//!     shape_seed: 0,
//!     source: RockSource::Explicit(0),
//! };
//! let points = rock_surface_points(&[rock], 0.2, 0.1);
//! assert!(rock_surface_points(&[rock], 0.5, 0.1).is_empty(), "a rock the rover climbs");
//! assert!(points.iter().any(|p| p.height_above_ground_m > 0.45));
//! assert!(points.iter().all(|p| p.height_above_ground_m <= 0.5));
//! ```

use hopnav_config::{ConfigError, HopnavConfig, parse_section};
use hopnav_ipc::messages::FeaturePoint;
use hopnav_world::rocks::Rock;

/// Depth sigma of an oracle point, metres: exact, but positive like a real measurement.
const ORACLE_DEPTH_SIGMA_M: f32 = 0.01;
/// Lattice spacing of the oracle's rock points, metres: 25 points per 0.5 m cell.
const ORACLE_POINT_SPACING_M: f64 = 0.1;

/// Why the perfect scout's points could not be made.
#[derive(Debug, thiserror::Error)]
pub enum OraclePriorError {
    /// `[world]` or `[physics.rover]` could not be parsed.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The world could not be generated.
    #[error("mapper.oracle_prior_map: cannot generate the world: {0}")]
    World(String),
}

/// What a perfect scout reports of the world `config` describes.
#[derive(Debug)]
pub struct ScoutReport {
    /// The points of [`rock_surface_points`] on every rock the rover cannot climb.
    pub points: Vec<FeaturePoint>,
    /// How many rocks those are.
    pub rocks_reported: usize,
    /// How many rocks the world has.
    pub rocks_in_world: usize,
}

/// Generates the world of `config` and samples every rock taller than the rover's
/// `physics.rover.max_climbable_height_m`: a flawless scout knows which rocks the rover
/// climbs, so only the others are reported (the mapper's lower threshold is a margin for
/// measurement noise).
pub fn perfect_scout_report(config: &HopnavConfig) -> Result<ScoutReport, OraclePriorError> {
    let world: hopnav_world::WorldConfig = parse_section(config, "world")?;
    let world = hopnav_world::World::generate(&world)
        .map_err(|error| OraclePriorError::World(error.to_string()))?;
    let climbable_height_m = hopnav_robot::RoverBody::from_config(config)?.max_climbable_height_m;
    let unclimbable: Vec<Rock> = world
        .rocks()
        .iter()
        .filter(|rock| rock.height_m > climbable_height_m)
        .copied()
        .collect();
    Ok(ScoutReport {
        points: rock_surface_points(&unclimbable, climbable_height_m, ORACLE_POINT_SPACING_M),
        rocks_reported: unclimbable.len(),
        rocks_in_world: world.rocks().len(),
    })
}

/// Points on the upper surface of every rock taller than `min_height_m` (the rover climbs the
/// others; a half-ellipsoid on its yawed footprint), `spacing_m` apart on a lattice over the
/// footprint, with their exact height above the ground the rock rests on. A non-positive or
/// non-finite spacing gives no points.
pub fn rock_surface_points(rocks: &[Rock], min_height_m: f64, spacing_m: f64) -> Vec<FeaturePoint> {
    let mut points = Vec::new();
    if !(spacing_m.is_finite() && spacing_m > 0.0) {
        return points;
    }
    for rock in rocks.iter().filter(|rock| rock.height_m > min_height_m) {
        let [a, b, c] = rock.half_extents_m;
        if !(a > 0.0 && b > 0.0 && c > 0.0) {
            continue;
        }
        let (sin, cos) = rock.yaw_rad.sin_cos();
        let steps_u = (a / spacing_m).floor() as i64;
        let steps_v = (b / spacing_m).floor() as i64;
        for i in -steps_u..=steps_u {
            for j in -steps_v..=steps_v {
                // (u, v) along the rock's yawed axes.
                let (u, v) = (i as f64 * spacing_m, j as f64 * spacing_m);
                let inside = 1.0 - (u / a).powi(2) - (v / b).powi(2);
                if inside < 0.0 {
                    continue;
                }
                let height_m = c * inside.sqrt();
                let x = rock.center_m[0] + cos * u - sin * v;
                let y = rock.center_m[1] + sin * u + cos * v;
                points.push(FeaturePoint {
                    position_m: [x as f32, y as f32, (rock.center_m[2] + height_m) as f32],
                    height_above_ground_m: height_m as f32,
                    track_id: points.len() as u32,
                    depth_sigma_m: ORACLE_DEPTH_SIGMA_M,
                });
            }
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::MapperConfig;
    use crate::map::FeatureMap;
    use hopnav_ipc::messages::{CellClass, Robot};
    use hopnav_world::rocks::RockSource;

    fn rock(center: [f64; 2], half_extents_m: [f64; 3], yaw_rad: f64) -> Rock {
        Rock {
            center_m: [center[0], center[1], 0.3],
            diameter_m: 2.0 * (half_extents_m[0] * half_extents_m[1]).sqrt(),
            height_m: half_extents_m[2],
            half_extents_m,
            yaw_rad,
            shape_seed: 0,
            source: RockSource::Explicit(0),
        }
    }

    #[test]
    fn points_follow_the_yawed_footprint() {
        // A 2 m × 0.4 m rock turned 90°: long along y, narrow along x.
        let points = rock_surface_points(
            &[rock(
                [0.0, 0.0],
                [1.0, 0.2, 0.6],
                std::f64::consts::FRAC_PI_2,
            )],
            0.2,
            0.1,
        );
        let max_x = points
            .iter()
            .map(|p| p.position_m[0].abs())
            .fold(0.0, f32::max);
        let max_y = points
            .iter()
            .map(|p| p.position_m[1].abs())
            .fold(0.0, f32::max);
        assert!(max_x <= 0.2 + 1e-5 && max_y > 0.95, "{max_x} {max_y}");
        let top = points
            .iter()
            .map(|p| p.height_above_ground_m)
            .fold(0.0, f32::max);
        assert!((top - 0.6).abs() < 1e-6);
        assert!(points.iter().all(|p| p.position_m[2] >= 0.3));
    }

    #[test]
    fn a_tall_rock_becomes_an_obstacle_and_a_climbable_one_is_left_out() {
        let config = MapperConfig::default();
        let geometry = config.resolve_geometry((16.0, 16.0)).expect("valid");
        let mut map = FeatureMap::new(&config, geometry);
        let tall = rock([2.25, 2.25], [0.5, 0.5, 0.5], 0.0);
        // 0.18 m: above the mapper's 0.15 m threshold, but the rover climbs it.
        let low = rock([-3.25, -3.25], [0.5, 0.5, 0.18], 0.0);
        let points = rock_surface_points(&[tall, low], 0.2, 0.1);
        assert!(
            points.iter().all(|p| p.position_m[0] > 0.0),
            "only the tall rock"
        );
        map.insert_cloud(Robot::Rover, &points);
        map.update();
        let class_at = |x: f64, y: f64| {
            let (cx, cy) = geometry.cell_of(x, y).expect("inside");
            map.cell_state(cx, cy).expect("cell").class
        };
        assert_eq!(class_at(2.25, 2.25), CellClass::Obstacle);
        assert_ne!(class_at(-3.25, -3.25), CellClass::Obstacle);
    }

    #[test]
    fn a_bad_spacing_gives_no_points() {
        let rocks = [rock([0.0, 0.0], [0.5, 0.5, 0.5], 0.0)];
        assert!(rock_surface_points(&rocks, 0.2, 0.0).is_empty());
        assert!(rock_surface_points(&rocks, 0.2, f64::NAN).is_empty());
    }
}
