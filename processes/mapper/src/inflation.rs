//! Extra cost around obstacles: a precomputed disc of cell offsets and their costs.
//!
//! A cell at distance `d` (centre to centre) from an obstacle, `0 < d ≤ radius`, costs
//! `max_cost · (1 − d / (radius + cell_size))`: highest next to the obstacle, falling linearly,
//! still positive at the radius. A cell near several obstacles takes the largest cost. Cells
//! with `d ≤ lethal_radius` are lethal: the rover's body would touch the rock.

/// One offset of the inflation disc.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KernelEntry {
    /// Column offset.
    pub dx: i32,
    /// Row offset.
    pub dy: i32,
    /// Extra cost at that offset, planner units.
    pub cost: u32,
    /// Within the lethal radius.
    pub lethal: bool,
}

/// The inflation disc for a grid with `cell_size_m`.
pub fn inflation_kernel(
    cell_size_m: f64,
    radius_m: f64,
    lethal_radius_m: f64,
    max_cost: u32,
) -> Vec<KernelEntry> {
    let radius_m = radius_m.max(lethal_radius_m);
    if max_cost == 0 && lethal_radius_m <= 0.0 {
        return Vec::new();
    }
    let reach = (radius_m / cell_size_m).floor().max(0.0) as i32;
    kernel_within(reach, |dx, dy| {
        let distance_m = f64::from(dx).hypot(f64::from(dy)) * cell_size_m;
        if distance_m > radius_m + 1e-9 {
            return None;
        }
        let fraction = 1.0 - distance_m / (radius_m + cell_size_m);
        let cost = (f64::from(max_cost) * fraction).round().max(1.0) as u32;
        Some((cost, distance_m <= lethal_radius_m + 1e-9))
    })
}

/// The entries `entry_at(dx, dy)` gives (cost, lethal) for, over the square of `reach`
/// cells around the obstacle (the obstacle's own cell left out).
fn kernel_within(
    reach: i32,
    entry_at: impl Fn(i32, i32) -> Option<(u32, bool)>,
) -> Vec<KernelEntry> {
    let mut kernel = Vec::new();
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            if (dx, dy) == (0, 0) {
                continue;
            }
            if let Some((cost, lethal)) = entry_at(dx, dy) {
                kernel.push(KernelEntry {
                    dx,
                    dy,
                    cost,
                    lethal,
                });
            }
        }
    }
    kernel
}

/// The rover's footprint against one obstacle, for nav2-style inflation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootprintCosts {
    /// Radius of the largest circle inside the footprint, metres.
    pub inscribed_m: f64,
    /// Radius of the smallest circle holding the footprint, metres.
    pub circumscribed_m: f64,
    /// Inflation reaches this far, metres.
    pub radius_m: f64,
    /// Cost of the "possibly inscribed" band, planner units.
    pub band_cost: u32,
    /// Decay rate beyond the band, 1/m.
    pub cost_scaling_per_m: f64,
}

impl FootprintCosts {
    /// The extra cost and lethality of a cell whose centre lies `distance_m` from the
    /// obstacle; `None` beyond the inflation radius:
    ///
    /// - within `inscribed_m` the rover's body touches the rock whatever its heading: lethal
    ///   for its centre;
    /// - out to `circumscribed_m` it may, depending on the heading ("possibly inscribed"):
    ///   `band_cost`, high but finite, and the drive checks the oriented footprint;
    /// - beyond, out to `radius_m`, `band_cost · exp(−k·(d − circumscribed))` (`k` =
    ///   `cost_scaling_per_m`, nav2's `cost_scaling_factor`).
    pub fn at(&self, distance_m: f64) -> Option<(u32, bool)> {
        let circumscribed_m = self.circumscribed_m.max(self.inscribed_m);
        let radius_m = self.radius_m.max(circumscribed_m);
        // NaN distances fall through to `None` too.
        if distance_m.is_nan() || distance_m > radius_m + 1e-9 {
            return None;
        }
        let lethal = distance_m < self.inscribed_m - 1e-9;
        let cost = if distance_m <= circumscribed_m + 1e-9 {
            self.band_cost
        } else {
            let decay = (-self.cost_scaling_per_m * (distance_m - circumscribed_m)).exp();
            (f64::from(self.band_cost) * decay).round() as u32
        };
        (cost > 0 || lethal).then_some((cost.max(1), lethal))
    }

    /// How far (in cells of `cell_size_m`) the inflation reaches from an obstacle cell.
    pub fn reach_cells(&self, cell_size_m: f64) -> i32 {
        let radius_m = self
            .radius_m
            .max(self.circumscribed_m)
            .max(self.inscribed_m);
        (radius_m / cell_size_m + 0.5).ceil().max(0.0) as i32
    }
}

/// [`FootprintCosts`] around one obstacle cell whose content may lie anywhere in its square
/// (distances run to the square's nearest point): the kernel of a cell without a measured
/// extent, and of the full-knowledge map.
pub fn footprint_kernel(cell_size_m: f64, costs: &FootprintCosts) -> Vec<KernelEntry> {
    // From this cell's centre to the nearest point of the source cell's square.
    let gap = |d: i32| (f64::from(d.abs()) * cell_size_m - cell_size_m / 2.0).max(0.0);
    kernel_within(costs.reach_cells(cell_size_m), |dx, dy| {
        costs.at(gap(dx).hypot(gap(dy)))
    })
}

/// The footprint costs of `config`'s rover (`None` under the `features` model).
pub fn footprint_costs(config: &crate::config::MapperConfig) -> Option<FootprintCosts> {
    (config.obstacle_model == crate::config::ObstacleModel::Traversability).then(|| {
        FootprintCosts {
            inscribed_m: config.rover_body.inscribed_radius_m(),
            circumscribed_m: config.rover_body.circumscribed_radius_m(),
            radius_m: config.inflation_radius_m,
            band_cost: config.inflation_max_cost,
            cost_scaling_per_m: config.cost_scaling_per_m,
        }
    })
}

/// The kernel the mapper inflates with under `config` (its obstacle model and the rover's
/// body), for a grid of `cell_size_m`: the evaluation plans with the same one.
pub fn kernel_for(config: &crate::config::MapperConfig, cell_size_m: f64) -> Vec<KernelEntry> {
    match footprint_costs(config) {
        Some(costs) => footprint_kernel(cell_size_m, &costs),
        None => inflation_kernel(
            cell_size_m,
            config.inflation_radius_m,
            config.lethal_radius_m,
            config.inflation_max_cost,
        ),
    }
}

/// Cells of the kernel's square: how far (in cells) an obstacle's influence reaches.
pub fn kernel_reach(kernel: &[KernelEntry]) -> u32 {
    kernel
        .iter()
        .map(|entry| entry.dx.unsigned_abs().max(entry.dy.unsigned_abs()))
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cost_falls_with_distance_inside_the_radius() {
        let kernel = inflation_kernel(0.5, 1.0, 0.75, 2000);
        let cost = |dx, dy| {
            kernel
                .iter()
                .find(|e| (e.dx, e.dy) == (dx, dy))
                .map(|e| e.cost)
        };
        assert_eq!(cost(1, 0), Some(1333));
        assert!(cost(1, 1) < cost(1, 0));
        assert_eq!(cost(2, 0), Some(667));
        assert_eq!(cost(2, 1), None, "1.118 m is beyond the radius");
        assert_eq!(cost(0, 0), None);
        assert_eq!(kernel_reach(&kernel), 2);
        assert!(inflation_kernel(0.5, 0.0, 0.0, 2000).is_empty());
        // Neighbours and diagonals are lethal at 0.75 m, two cells away is not.
        let lethal = |dx, dy| kernel.iter().any(|e| (e.dx, e.dy) == (dx, dy) && e.lethal);
        assert!(lethal(1, 0) && lethal(1, 1) && !lethal(2, 0));
    }

    #[test]
    fn the_footprint_kernel_is_lethal_inside_the_inscribed_radius_only() {
        // 0.25 m cells, the default rover: inscribed 0.4 m, circumscribed 0.68 m.
        let costs = FootprintCosts {
            inscribed_m: 0.4,
            circumscribed_m: 0.68,
            radius_m: 1.0,
            band_cost: 2000,
            cost_scaling_per_m: 3.0,
        };
        let kernel = footprint_kernel(0.25, &costs);
        let entry = |dx, dy| kernel.iter().find(|e| (e.dx, e.dy) == (dx, dy)).copied();
        // Gaps to the source square: 1 cell 0.125 m, 2 cells 0.375 m, 3 cells 0.625 m.
        assert!(entry(1, 0).unwrap().lethal && entry(2, 0).unwrap().lethal);
        assert!(entry(2, 1).unwrap().lethal, "0.395 m < 0.4 m");
        assert!(!entry(3, 0).unwrap().lethal && !entry(2, 2).unwrap().lethal);
        // The "possibly inscribed" band costs the band cost; beyond, the cost decays.
        assert_eq!(entry(3, 0).unwrap().cost, 2000);
        let far = entry(4, 0).unwrap();
        let expected = (2000.0 * (-3.0f64 * (0.875 - 0.68)).exp()).round() as u32;
        assert!(!far.lethal && far.cost == expected, "{far:?}");
        assert!(entry(5, 0).is_none(), "1.125 m is beyond the 1 m radius");
        assert!(entry(0, 0).is_none());
    }

    #[test]
    fn the_kernel_follows_the_obstacle_model() {
        let mut config = crate::config::MapperConfig {
            obstacle_model: crate::config::ObstacleModel::Features,
            ..crate::config::MapperConfig::default()
        };
        assert_eq!(
            kernel_for(&config, 0.5),
            inflation_kernel(0.5, 1.0, 0.75, 2000)
        );
        config.obstacle_model = crate::config::ObstacleModel::Traversability;
        let costs = footprint_costs(&config).expect("traversability");
        assert_eq!(costs.inscribed_m, config.rover_body.inscribed_radius_m());
        assert_eq!(kernel_for(&config, 0.25), footprint_kernel(0.25, &costs));
    }
}
