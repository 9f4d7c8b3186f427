//! Random rocky-terrain grids for tests and benchmarks.
//!
//! Obstacles come in clusters (discs and short elongated blobs of random size), like rock
//! fields rather than salt-and-pepper noise, until a target obstacle fraction is reached.
//! A disc around the start and the goal is kept clear.

use crate::cost::{MOVES, neighbour};
use crate::grid::{Cell, CellState, Grid, GridError};
use crate::rng::SplitMix64;

/// Parameters of a random obstacle map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RandomMapConfig {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Target fraction of obstacle cells, 0.0–0.9.
    pub obstacle_fraction: f64,
    /// Largest cluster radius in cells (≥ 1).
    pub max_cluster_radius: u32,
    /// Radius kept free around the start and goal.
    pub clear_radius: u32,
}

impl Default for RandomMapConfig {
    fn default() -> Self {
        Self {
            width: 257,
            height: 257,
            obstacle_fraction: 0.15,
            max_cluster_radius: 6,
            clear_radius: 3,
        }
    }
}

/// A grid with clustered obstacles (all other cells free), keeping `keep_clear` cells and a
/// disc around them free.
pub fn clustered_obstacles(
    config: &RandomMapConfig,
    keep_clear: &[Cell],
    rng: &mut SplitMix64,
) -> Result<Grid, GridError> {
    let mut grid = Grid::new(config.width, config.height, CellState::Free)?;
    let target = (config.obstacle_fraction.clamp(0.0, 0.9) * grid.cell_count() as f64) as usize;
    let max_radius = config.max_cluster_radius.max(1);
    let mut blocked = 0;
    let mut attempts = 0;
    while blocked < target && attempts < 1_000_000 {
        attempts += 1;
        let center = Cell::new(rng.below_u32(config.width), rng.below_u32(config.height));
        let radius = 1 + rng.below_u32(max_radius);
        // Elongate some clusters into ridges.
        let stretch = 1 + rng.below_u32(3);
        let horizontal = rng.chance(1, 2);
        let (rx, ry) = if horizontal {
            (radius * stretch, radius)
        } else {
            (radius, radius * stretch)
        };
        for dy in -(ry as i64)..=(ry as i64) {
            for dx in -(rx as i64)..=(rx as i64) {
                let inside = (dx * dx) as f64 / f64::from((rx * rx).max(1))
                    + (dy * dy) as f64 / f64::from((ry * ry).max(1))
                    <= 1.0;
                let x = i64::from(center.x) + dx;
                let y = i64::from(center.y) + dy;
                if !inside || x < 0 || y < 0 {
                    continue;
                }
                let cell = Cell::new(x as u32, y as u32);
                if grid.state(cell) == Some(CellState::Free)
                    && !near_any(cell, keep_clear, config.clear_radius)
                {
                    grid.set(cell, CellState::Obstacle, 0)?;
                    blocked += 1;
                }
            }
        }
    }
    Ok(grid)
}

/// Adds `cost` to every free cell 8-adjacent to an obstacle (a one-cell inflation ring).
pub fn inflate_obstacles(grid: &mut Grid, cost: u32) -> Result<(), GridError> {
    let mut ring = Vec::new();
    for index in 0..grid.cell_count() {
        let Some(cell) = grid.cell_at(index) else {
            continue;
        };
        if grid.state(cell) != Some(CellState::Free) {
            continue;
        }
        let touches_obstacle = MOVES.iter().any(|&step| {
            neighbour(grid, cell, step).is_some_and(|next| !grid.is_traversable(next))
        });
        if touches_obstacle {
            ring.push(cell);
        }
    }
    for cell in ring {
        grid.set(cell, CellState::Free, cost)?;
    }
    Ok(())
}

fn near_any(cell: Cell, centers: &[Cell], radius: u32) -> bool {
    centers.iter().any(|center| {
        let dx = u64::from(cell.x.abs_diff(center.x));
        let dy = u64::from(cell.y.abs_diff(center.y));
        dx * dx + dy * dy <= u64::from(radius) * u64::from(radius)
    })
}
