//! Fresh impact craters: a parabolic bowl with a raised rim and an ejecta apron.
//!
//! Profile with `R = D/2`, `ρ = r/R`, rim height `h_r` and depth `d` (rim crest to floor):
//! inside (`ρ ≤ 1`) `Δz = h_r − d + d·ρ²`; outside `Δz = h_r·(ρ⁻³ − ρ_max⁻³)/(1 − ρ_max⁻³)`
//! up to `ρ_max = 3`, then 0. Defaults follow fresh Martian craters: `d ≈ 0.2·D`,
//! `h_r ≈ 0.04·D`.
//!
//! ```
//! use hopnav_world::craters::Crater;
//! let c = Crater { center_m: [0.0, 0.0], diameter_m: 5.0, depth_m: 1.0, rim_height_m: 0.2 };
//! assert!((c.delta_z_m(2.5) - 0.2).abs() < 1e-12);
//! assert!((c.delta_z_m(0.0) + 0.8).abs() < 1e-12);
//! ```

use crate::config::{CraterConfig, ScenarioConfig};
use crate::rng::Rng;
use crate::rocks::clear_of;
use crate::terrain::Heightfield;

/// Stream number of the crater placement.
const CRATER_STREAM: u64 = 0x6372_6174_6572; // "crater"
/// Apron radius over rim radius.
const APRON_RATIO: f64 = 3.0;
/// Placement attempts per crater before it is dropped.
const PLACE_ATTEMPTS: usize = 64;

/// One crater.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crater {
    /// Centre (x, y), metres.
    pub center_m: [f64; 2],
    /// Rim crest diameter, metres.
    pub diameter_m: f64,
    /// Rim crest to floor, metres.
    pub depth_m: f64,
    /// Rim crest above the surroundings, metres.
    pub rim_height_m: f64,
}

impl Crater {
    /// Height change at distance `r_m` from the centre, metres.
    pub fn delta_z_m(&self, r_m: f64) -> f64 {
        let radius = self.diameter_m / 2.0;
        if radius <= 0.0 {
            return 0.0;
        }
        let rho = r_m / radius;
        if rho <= 1.0 {
            self.rim_height_m - self.depth_m + self.depth_m * rho * rho
        } else if rho < APRON_RATIO {
            let tail = APRON_RATIO.powi(-3);
            self.rim_height_m * (rho.powi(-3) - tail) / (1.0 - tail)
        } else {
            0.0
        }
    }

    /// Radius beyond which the crater leaves the terrain unchanged, metres.
    pub fn influence_radius_m(&self) -> f64 {
        self.diameter_m / 2.0 * APRON_RATIO
    }
}

/// Places `cfg.count` craters uniformly over the heightfield (log-uniform diameters).
///
/// A crater's rim keeps `scenario.clear_radius_m` away from the scenario points: a bowl
/// walled at up to 39° around start A or goal B is a trap the rover can never leave (seed 14
/// of the compare sweep started inside one). A crater with no clear spot in
/// `PLACE_ATTEMPTS` draws is dropped.
pub fn sample_craters(
    seed: u64,
    cfg: &CraterConfig,
    scenario: &ScenarioConfig,
    hf: &Heightfield,
) -> Vec<Crater> {
    let mut rng = Rng::new(seed, CRATER_STREAM);
    let [ox, oy] = hf.origin_m();
    let [ex, ey] = hf.extent_m();
    let (lo, hi) = (cfg.diameter_min_m.ln(), cfg.diameter_max_m.ln());
    let clear: Vec<[f64; 2]> = scenario.clear_points().collect();
    let mut craters = Vec::with_capacity(cfg.count as usize);
    for _ in 0..cfg.count {
        let diameter_m = rng.uniform(lo, hi).exp();
        let rim_radius_m = diameter_m / 2.0;
        let margin = rim_radius_m.min(ex.min(ey) / 2.0);
        let placed = (0..PLACE_ATTEMPTS)
            .map(|_| {
                [
                    ox + rng.uniform(margin, ex - margin),
                    oy + rng.uniform(margin, ey - margin),
                ]
            })
            .find(|&xy| clear_of(&clear, scenario.clear_radius_m, xy, rim_radius_m));
        if let Some(center_m) = placed {
            craters.push(Crater {
                center_m,
                diameter_m,
                depth_m: cfg.depth_ratio * diameter_m,
                rim_height_m: cfg.rim_height_ratio * diameter_m,
            });
        }
    }
    craters
}

/// Adds the craters to the heightfield, in order.
pub fn apply_craters(hf: &mut Heightfield, craters: &[Crater]) {
    let nx = hf.nx();
    let ny = hf.ny();
    let s = hf.spacing_m();
    let [ox, oy] = hf.origin_m();
    for c in craters {
        let r = c.influence_radius_m();
        let to_idx = |v: f64, n: usize| -> usize { v.clamp(0.0, (n - 1) as f64) as usize };
        let i0 = to_idx(((c.center_m[0] - r - ox) / s).floor(), nx);
        let i1 = to_idx(((c.center_m[0] + r - ox) / s).ceil(), nx);
        let j0 = to_idx(((c.center_m[1] - r - oy) / s).floor(), ny);
        let j1 = to_idx(((c.center_m[1] + r - oy) / s).ceil(), ny);
        let heights = hf.heights_mut();
        for j in j0..=j1 {
            for i in i0..=i1 {
                let dx = ox + i as f64 * s - c.center_m[0];
                let dy = oy + j as f64 * s - c.center_m[1];
                heights[j * nx + i] += c.delta_z_m((dx * dx + dy * dy).sqrt());
            }
        }
    }
}
