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
}
