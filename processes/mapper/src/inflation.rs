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
    let reach = (radius_m / cell_size_m).floor().max(0.0) as i32;
    let mut kernel = Vec::new();
    if max_cost == 0 && lethal_radius_m <= 0.0 {
        return kernel;
    }
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let distance_m = f64::from(dx).hypot(f64::from(dy)) * cell_size_m;
            if (dx, dy) == (0, 0) || distance_m > radius_m + 1e-9 {
                continue;
            }
            let fraction = 1.0 - distance_m / (radius_m + cell_size_m);
            let cost = (f64::from(max_cost) * fraction).round().max(1.0) as u32;
            let lethal = distance_m <= lethal_radius_m + 1e-9;
            kernel.push(KernelEntry {
                dx,
                dy,
                cost,
                lethal,
            });
        }
    }
    kernel
}

/// nav2-style inflation by the rover's footprint around one lethal cell (whose content may lie
/// anywhere in its square, so distances run to the square's nearest point):
///
/// - within `inscribed_m` the rover's body touches the rock whatever its heading: lethal for
///   its centre;
/// - out to `circumscribed_m` it may, depending on the heading ("possibly inscribed"):
///   `band_cost`, high but finite, and the drive checks the oriented footprint;
/// - beyond, out to `radius_m`, the cost decays as `band_cost · exp(−k·(d − circumscribed))`
///   (`k` = `cost_scaling_per_m`, nav2's `cost_scaling_factor`).
pub fn footprint_kernel(
    cell_size_m: f64,
    inscribed_m: f64,
    circumscribed_m: f64,
    radius_m: f64,
    band_cost: u32,
    cost_scaling_per_m: f64,
) -> Vec<KernelEntry> {
    let circumscribed_m = circumscribed_m.max(inscribed_m);
    let radius_m = radius_m.max(circumscribed_m);
    let reach = (radius_m / cell_size_m + 0.5).ceil().max(0.0) as i32;
    let mut kernel = Vec::new();
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            // From this cell's centre to the nearest point of the source cell's square.
            let gap = |d: i32| (f64::from(d.abs()) * cell_size_m - cell_size_m / 2.0).max(0.0);
            let distance_m = gap(dx).hypot(gap(dy));
            if (dx, dy) == (0, 0) || distance_m > radius_m + 1e-9 {
                continue;
            }
            let lethal = distance_m < inscribed_m - 1e-9;
            let cost = if distance_m <= circumscribed_m + 1e-9 {
                band_cost
            } else {
                let decay = (-cost_scaling_per_m * (distance_m - circumscribed_m)).exp();
                (f64::from(band_cost) * decay).round() as u32
            };
            if cost == 0 && !lethal {
                continue;
            }
            kernel.push(KernelEntry {
                dx,
                dy,
                cost: cost.max(1),
                lethal,
            });
        }
    }
    kernel
}

/// The kernel the mapper inflates with under `config` (its obstacle model and the rover's
/// body), for a grid of `cell_size_m`: the evaluation plans with the same one.
pub fn kernel_for(config: &crate::config::MapperConfig, cell_size_m: f64) -> Vec<KernelEntry> {
    match config.obstacle_model {
        crate::config::ObstacleModel::Features => inflation_kernel(
            cell_size_m,
            config.inflation_radius_m,
            config.lethal_radius_m,
            config.inflation_max_cost,
        ),
        crate::config::ObstacleModel::Traversability => footprint_kernel(
            cell_size_m,
            config.rover_body.inscribed_radius_m(),
            config.rover_body.circumscribed_radius_m(),
            config.inflation_radius_m,
            config.inflation_max_cost,
            config.cost_scaling_per_m,
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
        let kernel = footprint_kernel(0.25, 0.4, 0.68, 1.0, 2000, 3.0);
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
        let mut config = crate::config::MapperConfig::default();
        assert_eq!(
            kernel_for(&config, 0.5),
            inflation_kernel(0.5, 1.0, 0.75, 2000)
        );
        config.obstacle_model = crate::config::ObstacleModel::Traversability;
        let body = config.rover_body;
        assert_eq!(
            kernel_for(&config, 0.25),
            footprint_kernel(
                0.25,
                body.inscribed_radius_m(),
                body.circumscribed_radius_m(),
                1.0,
                2000,
                3.0
            )
        );
    }
}
