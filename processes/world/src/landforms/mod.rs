//! Landforms that give a scout something to find, placed between the scenario's start A and
//! goal B from the world seed: [`cul_de_sac`]s (U-shaped boulder walls opening toward A), a
//! [`scarp`] (a step too steep to drive, with ramps far off the A–B line) and a
//! [`corridor_field`] (dense boulders with a few clear corridors). A rover at ground level
//! sees the front of each but not where it is closed or open; the jumper, from a hop, does.
//!
//! All are off in the default world; `config/scenarios/scout_*.toml` switch them on.

pub mod corridor_field;
pub mod cul_de_sac;
pub mod scarp;

use crate::boulder_fields::Boulder;
use crate::config::{LandformConfig, ScenarioConfig, WallBoulders};
use crate::rng::{Rng, mix64};
use crate::rocks::{Rock, RockSource, make_rock};
use crate::terrain::Heightfield;

const LANDFORM_SHAPE_STREAM: u64 = 0x6c61_6e64_6672; // "landfr"

/// The A–B frame of the scenario (`None` without both points).
pub fn scenario_frame(scenario: &ScenarioConfig) -> Option<AbFrame> {
    AbFrame::new(scenario.start_m?, scenario.goal_m?)
}

/// Adds the scarp, if any, to the heightfield (before rocks are set on it).
pub fn shape_terrain(
    seed: u64,
    config: &LandformConfig,
    scenario: &ScenarioConfig,
    hf: &mut Heightfield,
) {
    let Some(frame) = scenario_frame(scenario) else {
        return;
    };
    if let Some(found) = scarp::place_scarp(seed, &config.scarp, &frame) {
        scarp::apply_scarp(hf, &found, &config.scarp, &frame);
    }
}

/// The boulders of the cul-de-sacs and the corridor field, resting on `hf`.
pub fn landform_rocks(
    seed: u64,
    config: &LandformConfig,
    scenario: &ScenarioConfig,
    hf: &Heightfield,
) -> Vec<Rock> {
    let Some(frame) = scenario_frame(scenario) else {
        return Vec::new();
    };
    let mut boulders: Vec<(Boulder, RockSource)> = Vec::new();
    let sacs = cul_de_sac::place_cul_de_sacs(seed, &config.cul_de_sacs, &frame);
    for (index, sac) in (0u32..).zip(&sacs) {
        boulders.extend(
            cul_de_sac::cul_de_sac_boulders(seed, index, &config.cul_de_sacs, sac)
                .into_iter()
                .map(|boulder| (boulder, RockSource::CulDeSac(index))),
        );
    }
    let [extent_x_m, extent_y_m] = hf.extent_m();
    let half_span_m = 0.5 * extent_x_m.hypot(extent_y_m);
    let corridors = corridor_field::place_corridors(seed, &config.corridor_field);
    boulders.extend(
        corridor_field::field_boulders(
            seed,
            &config.corridor_field,
            &frame,
            half_span_m,
            &corridors,
        )
        .into_iter()
        .map(|boulder| (boulder, RockSource::CorridorField)),
    );
    let mut rng = Rng::new(seed, LANDFORM_SHAPE_STREAM);
    (0u64..)
        .zip(boulders)
        .filter(|(_, (boulder, _))| hf.contains(boulder.center_m[0], boulder.center_m[1]))
        .map(|(n, (boulder, source))| {
            make_rock(
                hf,
                &mut rng,
                boulder.center_m,
                boulder.diameter_m,
                boulder.height_m,
                mix64(seed ^ LANDFORM_SHAPE_STREAM ^ n),
                source,
            )
        })
        .collect()
}

/// Coordinates along the A–B line: `along` from A toward B, `side` to the left of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbFrame {
    /// A, world metres.
    pub start_m: [f64; 2],
    /// Unit vector from A toward B.
    pub unit: [f64; 2],
    /// Distance from A to B, metres.
    pub length_m: f64,
}

impl AbFrame {
    /// The frame of the segment from `start_m` to `goal_m` (`None` when they coincide or are
    /// not finite).
    pub fn new(start_m: [f64; 2], goal_m: [f64; 2]) -> Option<Self> {
        let (dx, dy) = (goal_m[0] - start_m[0], goal_m[1] - start_m[1]);
        let length_m = dx.hypot(dy);
        (length_m.is_finite() && length_m > 1e-6).then(|| Self {
            start_m,
            unit: [dx / length_m, dy / length_m],
            length_m,
        })
    }

    /// World (x, y) of the point `along_m` from A and `side_m` to the left of A–B.
    pub fn world_m(&self, along_m: f64, side_m: f64) -> [f64; 2] {
        let [ux, uy] = self.unit;
        [
            self.start_m[0] + ux * along_m - uy * side_m,
            self.start_m[1] + uy * along_m + ux * side_m,
        ]
    }

    /// `(along, side)` of the world point `xy_m`, metres.
    pub fn local_m(&self, xy_m: [f64; 2]) -> (f64, f64) {
        let (dx, dy) = (xy_m[0] - self.start_m[0], xy_m[1] - self.start_m[1]);
        let [ux, uy] = self.unit;
        (dx * ux + dy * uy, -dx * uy + dy * ux)
    }

    /// Direction of A–B about world z, radians.
    pub fn heading_rad(&self) -> f64 {
        self.unit[1].atan2(self.unit[0])
    }
}

/// Boulders along the polyline `corners_m`, touching: each next centre 80 % of the two
/// diameters' mean further on, so no rover passes between them.
pub fn boulders_along(
    corners_m: &[[f64; 2]],
    rng: &mut Rng,
    boulders: &WallBoulders,
) -> Vec<Boulder> {
    let mut placed = Vec::new();
    let mut diameter_m = rng.uniform(boulders.diameter_min_m, boulders.diameter_max_m);
    // Distance still to go along the polyline before the next boulder, metres.
    let mut to_next_m = 0.0;
    for pair in corners_m.windows(2) {
        let ([x0, y0], [x1, y1]) = (pair[0], pair[1]);
        let length_m = (x1 - x0).hypot(y1 - y0);
        let mut at_m = to_next_m;
        while at_m <= length_m {
            let t = if length_m > 0.0 { at_m / length_m } else { 0.0 };
            placed.push(Boulder {
                center_m: [x0 + t * (x1 - x0), y0 + t * (y1 - y0)],
                diameter_m,
                height_m: boulders.height_ratio * diameter_m * rng.uniform(0.9, 1.1),
            });
            let next_m = rng.uniform(boulders.diameter_min_m, boulders.diameter_max_m);
            at_m += 0.4 * (diameter_m + next_m);
            diameter_m = next_m;
        }
        to_next_m = at_m - length_m;
    }
    placed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ab_frame_round_trips_and_puts_left_on_the_left() {
        let frame = AbFrame::new([-10.0, 0.0], [10.0, 0.0]).expect("frame");
        assert_eq!(frame.world_m(5.0, 2.0), [-5.0, 2.0]);
        let (along, side) = frame.local_m([3.0, -4.0]);
        assert!((along - 13.0).abs() < 1e-12 && (side + 4.0).abs() < 1e-12);
        assert!(AbFrame::new([1.0, 1.0], [1.0, 1.0]).is_none());
        assert!(AbFrame::new([f64::NAN, 1.0], [1.0, 1.0]).is_none());
    }

    #[test]
    fn boulders_along_a_wall_leave_no_gap() {
        let mut rng = Rng::new(3, 4);
        let wall = boulders_along(
            &[[0.0, 0.0], [10.0, 0.0], [10.0, 5.0]],
            &mut rng,
            &WallBoulders::default(),
        );
        for pair in wall.windows(2) {
            let gap_m = (pair[1].center_m[0] - pair[0].center_m[0])
                .hypot(pair[1].center_m[1] - pair[0].center_m[1])
                - 0.5 * (pair[0].diameter_m + pair[1].diameter_m);
            assert!(gap_m < 0.0, "boulders overlap along the wall, gap {gap_m}");
        }
        let last = wall.last().expect("boulders");
        assert!((last.center_m[0] - 10.0).abs() < 1e-9 && last.center_m[1] > 3.5);
    }
}
