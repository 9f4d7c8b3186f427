//! Boulder fields: arcs of large rocks between the scenario's start A and goal B, open toward
//! A. From A the rover sees the front of such a field but not whether its back is closed (a
//! cul-de-sac) until it is inside; from a hop's height the jumper sees the whole arc. This is
//! the situation of the paper's Fig. 6 (obstacles that occlude the rover's view), placed at
//! random from the world seed so a comparison can run over many terrains.
//!
//! ```
//! use hopnav_world::boulder_fields::place_fields;
//! use hopnav_world::config::BoulderFieldConfig;
//! let config = BoulderFieldConfig { count: 2, ..BoulderFieldConfig::default() };
//! let fields = place_fields(7, &config, [-20.0, 0.0], [20.0, 0.0]);
//! assert_eq!(fields.len(), 2);
//! // Each field lies between A and B, its opening toward A.
//! for field in &fields {
//!     assert!(field.center_m[0] > -12.0 && field.center_m[0] < 12.0);
//!     assert!(field.opening_direction_rad.cos() < 0.0);
//! }
//! ```

use crate::config::BoulderFieldConfig;
use crate::rng::Rng;

const FIELD_STREAM: u64 = 0x626f_756c_6465; // "boulde"

/// Where a field lies and which way it opens.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldPlacement {
    /// Centre of the arc (x, y), metres.
    pub center_m: [f64; 2],
    /// Arc radius, metres.
    pub radius_m: f64,
    /// Direction from the centre through the middle of the opening, radians (toward A).
    pub opening_direction_rad: f64,
}

/// One boulder of a field, before it is set on the terrain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Boulder {
    /// Centre (x, y), metres.
    pub center_m: [f64; 2],
    /// Diameter, metres.
    pub diameter_m: f64,
    /// Height, metres.
    pub height_m: f64,
}

/// Places `config.count` fields along the segment from `start_m` to `goal_m`: centres at
/// 30–75 % of the way, spread sideways by up to `lateral_spread_m`, openings facing A
/// (± 0.3 rad).
pub fn place_fields(
    seed: u64,
    config: &BoulderFieldConfig,
    start_m: [f64; 2],
    goal_m: [f64; 2],
) -> Vec<FieldPlacement> {
    let mut rng = Rng::new(seed, FIELD_STREAM);
    let (dx, dy) = (goal_m[0] - start_m[0], goal_m[1] - start_m[1]);
    let length_m = dx.hypot(dy).max(1e-9);
    let (ux, uy) = (dx / length_m, dy / length_m);
    let count = config.count.max(1) as f64;
    (0..config.count)
        .map(|index| {
            let slot = (f64::from(index) + 0.5) / count;
            let along = (0.3 + 0.45 * slot + rng.uniform(-0.05, 0.05)) * length_m;
            let side_m = rng.uniform(-config.lateral_spread_m, config.lateral_spread_m);
            let center_m = [
                start_m[0] + ux * along - uy * side_m,
                start_m[1] + uy * along + ux * side_m,
            ];
            let toward_start = (start_m[1] - center_m[1]).atan2(start_m[0] - center_m[0]);
            FieldPlacement {
                center_m,
                radius_m: rng.uniform(config.radius_min_m, config.radius_max_m),
                opening_direction_rad: toward_start + rng.uniform(-0.3, 0.3),
            }
        })
        .collect()
}

/// The boulders of one field: along its arc, from one side of the opening round to the other,
/// so close together (80 % of their diameters apart) that no rover fits between them.
pub fn field_boulders(
    seed: u64,
    index: u32,
    config: &BoulderFieldConfig,
    field: &FieldPlacement,
) -> Vec<Boulder> {
    let mut rng = Rng::new(seed, FIELD_STREAM ^ (u64::from(index + 1) << 40));
    let half_opening_rad = 0.5 * config.opening_rad;
    let end_rad = std::f64::consts::TAU - half_opening_rad;
    let mut offset_rad = half_opening_rad;
    let mut boulders = Vec::new();
    let mut diameter_m = rng.uniform(config.diameter_min_m, config.diameter_max_m);
    while offset_rad <= end_rad {
        let angle_rad = field.opening_direction_rad + offset_rad;
        boulders.push(Boulder {
            center_m: [
                field.center_m[0] + field.radius_m * angle_rad.cos(),
                field.center_m[1] + field.radius_m * angle_rad.sin(),
            ],
            diameter_m,
            height_m: config.height_ratio * diameter_m * rng.uniform(0.9, 1.1),
        });
        // Centres 80 % of the two diameters' mean apart along the arc: they overlap.
        let next_m = rng.uniform(config.diameter_min_m, config.diameter_max_m);
        offset_rad += 0.4 * (diameter_m + next_m) / field.radius_m.max(0.1);
        diameter_m = next_m;
    }
    boulders
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> BoulderFieldConfig {
        BoulderFieldConfig {
            count: 3,
            ..BoulderFieldConfig::default()
        }
    }

    #[test]
    fn fields_are_seeded_and_keep_away_from_start_and_goal() {
        let (a, b) = ([-20.0, 0.0], [20.0, 0.0]);
        let fields = place_fields(3, &config(), a, b);
        assert_eq!(fields, place_fields(3, &config(), a, b));
        assert_ne!(fields, place_fields(4, &config(), a, b));
        for field in &fields {
            for point in [a, b] {
                let distance_m = (field.center_m[0] - point[0]).hypot(field.center_m[1] - point[1]);
                assert!(distance_m > field.radius_m + 3.0, "{field:?}");
            }
        }
    }

    #[test]
    fn boulders_close_the_arc_but_for_the_opening() {
        let config = config();
        let field = FieldPlacement {
            center_m: [0.0, 0.0],
            radius_m: 4.0,
            opening_direction_rad: std::f64::consts::PI,
        };
        let boulders = field_boulders(1, 0, &config, &field);
        assert!(boulders.len() > 10);
        for pair in boulders.windows(2) {
            let gap_m = (pair[0].center_m[0] - pair[1].center_m[0])
                .hypot(pair[0].center_m[1] - pair[1].center_m[1]);
            assert!(
                gap_m < 0.5 * (pair[0].diameter_m + pair[1].diameter_m),
                "boulders overlap"
            );
        }
        // The opening faces −x: no boulder within it.
        let half_opening = 0.5 * config.opening_rad;
        for boulder in &boulders {
            let angle = boulder.center_m[1].atan2(boulder.center_m[0]);
            let from_opening = (angle - std::f64::consts::PI).rem_euclid(std::f64::consts::TAU);
            let from_opening = from_opening.min(std::f64::consts::TAU - from_opening);
            assert!(from_opening >= half_opening - 1e-9, "{boulder:?}");
        }
    }
}
