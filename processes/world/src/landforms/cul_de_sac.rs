//! Cul-de-sacs: U-shaped walls of touching boulders between A and B, their mouths toward A.
//! A rover driving toward B enters the mouth and sees the back wall only when its stereo
//! reaches it, 10–20 m in; from a hop the jumper sees the whole U.
//!
//! ```
//! use hopnav_world::config::CulDeSacConfig;
//! use hopnav_world::landforms::{AbFrame, cul_de_sac::place_cul_de_sacs};
//! let config = CulDeSacConfig { count: 2, ..CulDeSacConfig::default() };
//! let frame = AbFrame::new([-50.0, 0.0], [50.0, 0.0]).unwrap();
//! let sacs = place_cul_de_sacs(7, &config, &frame);
//! assert_eq!(sacs.len(), 2);
//! // Each opens toward A.
//! assert!(sacs.iter().all(|sac| sac.opening_direction_rad.cos() < -0.9));
//! ```

use super::{AbFrame, boulders_along};
use crate::boulder_fields::Boulder;
use crate::config::CulDeSacConfig;
use crate::rng::Rng;

const CUL_DE_SAC_STREAM: u64 = 0x6375_6c64_6573; // "culdes"

/// Where a cul-de-sac lies and how it is shaped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CulDeSac {
    /// Middle of the back wall (x, y), world metres.
    pub back_center_m: [f64; 2],
    /// Direction from the back wall out through the mouth, radians (toward A).
    pub opening_direction_rad: f64,
    /// Length of the arms, metres.
    pub depth_m: f64,
    /// Distance between the arms, metres.
    pub width_m: f64,
}

impl CulDeSac {
    /// The wall's corners: mouth left, back left, back right, mouth right.
    pub fn corners_m(&self) -> [[f64; 2]; 4] {
        let (sin, cos) = self.opening_direction_rad.sin_cos();
        let (out, across) = ([cos, sin], [-sin, cos]);
        let at = |out_m: f64, across_m: f64| {
            [
                self.back_center_m[0] + out[0] * out_m + across[0] * across_m,
                self.back_center_m[1] + out[1] * out_m + across[1] * across_m,
            ]
        };
        let half_m = 0.5 * self.width_m;
        [
            at(self.depth_m, half_m),
            at(0.0, half_m),
            at(0.0, -half_m),
            at(self.depth_m, -half_m),
        ]
    }
}

/// Places `config.count` cul-de-sacs: back walls spread over 35–85 % of the way from A to
/// B, each mouth at least 10 % of the way from A, centre lines up to `lateral_spread_m` to
/// either side, mouths facing A (± 0.2 rad).
pub fn place_cul_de_sacs(seed: u64, config: &CulDeSacConfig, frame: &AbFrame) -> Vec<CulDeSac> {
    let mut rng = Rng::new(seed, CUL_DE_SAC_STREAM);
    let count = f64::from(config.count.max(1));
    (0..config.count)
        .map(|index| {
            let depth_m = rng.uniform(config.depth_min_m, config.depth_max_m);
            let width_m = rng.uniform(config.width_min_m, config.width_max_m);
            let slot = (f64::from(index) + 0.5) / count;
            let back_along_m = ((0.35 + 0.5 * slot + rng.uniform(-0.04, 0.04)) * frame.length_m)
                .max(0.1 * frame.length_m + depth_m);
            let side_m = rng.uniform(-config.lateral_spread_m, config.lateral_spread_m);
            CulDeSac {
                back_center_m: frame.world_m(back_along_m, side_m),
                opening_direction_rad: frame.heading_rad()
                    + std::f64::consts::PI
                    + rng.uniform(-0.2, 0.2),
                depth_m,
                width_m,
            }
        })
        .collect()
}

/// The boulders of cul-de-sac number `index`.
pub fn cul_de_sac_boulders(
    seed: u64,
    index: u32,
    config: &CulDeSacConfig,
    sac: &CulDeSac,
) -> Vec<Boulder> {
    let mut rng = Rng::new(seed, CUL_DE_SAC_STREAM ^ (u64::from(index + 1) << 40));
    boulders_along(&sac.corners_m(), &mut rng, &config.boulders)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> AbFrame {
        AbFrame::new([-50.0, 0.0], [50.0, 0.0]).expect("frame")
    }

    fn config() -> CulDeSacConfig {
        CulDeSacConfig {
            count: 3,
            ..CulDeSacConfig::default()
        }
    }

    #[test]
    fn placement_is_deterministic_per_seed() {
        assert_eq!(
            place_cul_de_sacs(5, &config(), &frame()),
            place_cul_de_sacs(5, &config(), &frame())
        );
        assert_ne!(
            place_cul_de_sacs(5, &config(), &frame()),
            place_cul_de_sacs(6, &config(), &frame())
        );
    }

    #[test]
    fn a_cul_de_sac_is_walled_on_three_sides_and_open_toward_a() {
        let frame = frame();
        for seed in 1..=5 {
            for (index, sac) in (0u32..).zip(place_cul_de_sacs(seed, &config(), &frame)) {
                // Each boulder in the cul-de-sac's own frame: out from the back wall toward
                // the mouth, and across.
                let (sin, cos) = sac.opening_direction_rad.sin_cos();
                let own: Vec<(f64, f64)> = cul_de_sac_boulders(seed, index, &config(), &sac)
                    .iter()
                    .map(|b| {
                        let (dx, dy) = (
                            b.center_m[0] - sac.back_center_m[0],
                            b.center_m[1] - sac.back_center_m[1],
                        );
                        (dx * cos + dy * sin, -dx * sin + dy * cos)
                    })
                    .collect();
                let half_width_m = 0.5 * sac.width_m;
                let mouth = own.iter().filter(|&&(out, across)| {
                    out > 0.8 * sac.depth_m && across.abs() < 0.5 * half_width_m
                });
                assert_eq!(mouth.count(), 0, "seed {seed}: the mouth is walled");
                let back = own
                    .iter()
                    .filter(|&&(out, across)| out.abs() < 0.5 && across.abs() < half_width_m)
                    .count();
                assert!(
                    back as f64 >= sac.width_m / 1.2,
                    "seed {seed}: {back} at the back"
                );
                let arm_ends = own
                    .iter()
                    .filter(|&&(out, across)| {
                        out > 0.8 * sac.depth_m && (across.abs() - half_width_m).abs() < 0.5
                    })
                    .count();
                assert!(arm_ends >= 2, "seed {seed}: the arms are short");
                // The mouth faces A.
                let (back_along, _) = frame.local_m(sac.back_center_m);
                let (mouth_along, _) = frame.local_m([
                    sac.back_center_m[0] + cos * sac.depth_m,
                    sac.back_center_m[1] + sin * sac.depth_m,
                ]);
                assert!(mouth_along < back_along - 0.9 * sac.depth_m && mouth_along > 0.0);
            }
        }
    }
}
