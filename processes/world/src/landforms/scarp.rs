//! A scarp: a step in the ground across A–B and across the whole terrain, too steep for the
//! rover to drive up or down except on ramps placed well to the side of the A–B line. From
//! the ground the rover sees the face (or, above a drop, nothing) but not where the ramps
//! are; from a hop the jumper sees them.
//!
//! The step follows a smoothstep across a meandering line: `z += ±h · S(d / w)`, `d` the
//! distance past the line along A–B, `w` the face width (the ramp length on a ramp), so its
//! steepest slope is `1.5 · h / w`.

use super::AbFrame;
use crate::config::ScarpConfig;
use crate::rng::Rng;
use crate::terrain::Heightfield;

const SCARP_STREAM: u64 = 0x7363_6172_7073; // "scarps"

/// Wavelength of the scarp line's meander, metres.
const MEANDER_WAVELENGTH_M: f64 = 40.0;
/// Over this distance to the side a ramp blends into the face, metres.
const RAMP_BLEND_M: f64 = 2.0;

/// Where the scarp lies, drawn from the seed.
#[derive(Debug, Clone, PartialEq)]
pub struct Scarp {
    /// The step's height, signed: positive when the side toward B is higher, metres.
    pub rise_m: f64,
    /// Distance of the scarp line from A along A–B, metres (before the meander).
    pub along_m: f64,
    /// Phase of the meander, radians.
    pub meander_phase_rad: f64,
    /// Side offsets of the ramps' centres from the A–B line, metres.
    pub ramp_sides_m: Vec<f64>,
}

/// The scarp of `config` (`None` when its height is 0).
pub fn place_scarp(seed: u64, config: &ScarpConfig, frame: &AbFrame) -> Option<Scarp> {
    if config.height_m <= 0.0 {
        return None;
    }
    let mut rng = Rng::new(seed, SCARP_STREAM);
    let rise_sign = if rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
    let meander_phase_rad = rng.uniform(0.0, std::f64::consts::TAU);
    let first_side = if rng.next_f64() < 0.5 { -1.0 } else { 1.0 };
    let ramp_sides_m = (0..config.gap_count)
        .map(|index| {
            // Alternate sides, so two ramps do not pile up on one.
            let side = if index % 2 == 0 {
                first_side
            } else {
                -first_side
            };
            side * rng.uniform(config.gap_offset_min_m, config.gap_offset_max_m)
        })
        .collect();
    Some(Scarp {
        rise_m: rise_sign * config.height_m,
        along_m: config.at_fraction * frame.length_m,
        meander_phase_rad,
        ramp_sides_m,
    })
}

impl Scarp {
    /// Distance of `(along, side)` past the scarp line, metres.
    fn past_line_m(&self, config: &ScarpConfig, along_m: f64, side_m: f64) -> f64 {
        let meander =
            (std::f64::consts::TAU * side_m / MEANDER_WAVELENGTH_M + self.meander_phase_rad).sin();
        along_m - self.along_m - config.meander_m * meander
    }

    /// How much of a ramp lies at `side_m`: 1 on its core, 0 away from every ramp.
    fn ramp_share(&self, config: &ScarpConfig, side_m: f64) -> f64 {
        self.ramp_sides_m
            .iter()
            .map(|&centre_m| {
                let beyond_core_m = (side_m - centre_m).abs() - 0.5 * config.gap_width_m;
                if beyond_core_m <= 0.0 {
                    1.0
                } else if beyond_core_m >= RAMP_BLEND_M {
                    0.0
                } else {
                    0.5 * (1.0 + (std::f64::consts::PI * beyond_core_m / RAMP_BLEND_M).cos())
                }
            })
            .fold(0.0, f64::max)
    }

    /// The step's height change at `(along, side)`, metres.
    pub fn delta_z_m(&self, config: &ScarpConfig, along_m: f64, side_m: f64) -> f64 {
        let share = self.ramp_share(config, side_m);
        let width_m = config.face_width_m + (config.ramp_length_m - config.face_width_m) * share;
        let t = (self.past_line_m(config, along_m, side_m) / width_m + 0.5).clamp(0.0, 1.0);
        self.rise_m * t * t * (3.0 - 2.0 * t)
    }
}

/// Adds the scarp to the heightfield.
pub fn apply_scarp(hf: &mut Heightfield, scarp: &Scarp, config: &ScarpConfig, frame: &AbFrame) {
    let (nx, [ox, oy], spacing_m) = (hf.nx(), hf.origin_m(), hf.spacing_m());
    for (index, height) in hf.heights_mut().iter_mut().enumerate() {
        // Node (i, j) of the row-major grid, at `node_xy_m(i, j)`.
        let (i, j) = (index % nx, index / nx);
        let node_m = [ox + i as f64 * spacing_m, oy + j as f64 * spacing_m];
        let (along_m, side_m) = frame.local_m(node_m);
        *height += scarp.delta_z_m(config, along_m, side_m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> ScarpConfig {
        ScarpConfig {
            height_m: 1.5,
            gap_count: 2,
            ..ScarpConfig::default()
        }
    }

    fn scarp_on_flat_ground(seed: u64) -> (Heightfield, Scarp, AbFrame) {
        let frame = AbFrame::new([-40.0, 0.0], [40.0, 0.0]).expect("frame");
        let mut hf = Heightfield::flat(401, 257, 0.25, 0.0);
        let scarp = place_scarp(seed, &config(), &frame).expect("a scarp");
        apply_scarp(&mut hf, &scarp, &config(), &frame);
        (hf, scarp, frame)
    }

    /// The steepest slope met driving along A–B at `side_m` across the whole terrain.
    fn steepest_along(hf: &Heightfield, frame: &AbFrame, side_m: f64) -> f64 {
        (0..640)
            .map(|step| {
                let along_m = 0.125 * f64::from(step);
                let ([x0, y0], [x1, y1]) = (
                    frame.world_m(along_m, side_m),
                    frame.world_m(along_m + 0.125, side_m),
                );
                (hf.height_at(x1, y1) - hf.height_at(x0, y0)).abs() / 0.125
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_scarp_is_too_steep_on_the_line_and_its_ramps_are_drivable() {
        let too_steep = 30_f64.to_radians().tan();
        let steep = 22.5_f64.to_radians().tan();
        for seed in 1..=5 {
            let (hf, scarp, frame) = scarp_on_flat_ground(seed);
            assert_eq!(scarp.ramp_sides_m.len(), 2);
            assert!(
                steepest_along(&hf, &frame, 0.0) > too_steep,
                "seed {seed}: the line crosses the face"
            );
            for &side_m in &scarp.ramp_sides_m {
                assert!(side_m.abs() >= 12.0, "seed {seed}: a ramp at {side_m} m");
                let slope = steepest_along(&hf, &frame, side_m);
                assert!(
                    slope < steep,
                    "seed {seed}: the ramp at {side_m} m rises {slope}"
                );
                // The ramp's core is as wide as promised.
                for edge_m in [-2.0, 2.0] {
                    assert!(steepest_along(&hf, &frame, side_m + edge_m) < steep);
                }
            }
            // The step is whole across the terrain: A's side and B's differ by its height.
            let (a, b) = (frame.world_m(2.0, 5.0), frame.world_m(78.0, 5.0));
            let rise = hf.height_at(b[0], b[1]) - hf.height_at(a[0], a[1]);
            assert!(
                (rise - scarp.rise_m).abs() < 1e-9,
                "seed {seed}: rise {rise}"
            );
        }
    }

    #[test]
    fn no_height_no_scarp_and_the_same_seed_the_same_scarp() {
        let frame = AbFrame::new([0.0, 0.0], [10.0, 0.0]).expect("frame");
        assert!(place_scarp(1, &ScarpConfig::default(), &frame).is_none());
        assert_eq!(
            place_scarp(9, &config(), &frame),
            place_scarp(9, &config(), &frame)
        );
    }
}
