//! The cells a viewing ray crosses, and how high above the ground it crosses them: the
//! free-space evidence of a cloud (a ray that reached a point passed through every cell
//! before it, so nothing taller than the ray stood there).
//!
//! A 2-D grid traversal (Amanatides & Woo) from the camera to the point. For every cell the
//! ray crosses before the point's own cell, the visitor gets the lowest height of the ray in
//! that cell above the point's local ground (the ground a rover or a hop sees is locally
//! flat at the few metres where a ray runs low). Cells where the ray runs higher than
//! `max_height_m` are skipped without visiting: they can hide no rock the map would claim.
//!
//! ```
//! use hopnav_mapper::geometry::GridGeometry;
//! use hopnav_mapper::rays::for_each_cell_below;
//! let grid = GridGeometry { origin_x_m: 0.0, origin_y_m: 0.0, cell_size_m: 0.25,
//!     width_cells: 40, height_cells: 40 };
//! let mut visited = Vec::new();
//! // A camera 1 m up at x = 0.1 looks at a ground point at x = 2.1 (the ground at z = 0).
//! for_each_cell_below(&grid, [0.1, 0.1, 1.0], [2.1, 0.1, 0.0], 0.0, 0.5, |index, height_m| {
//!     visited.push((grid.coords(index).0, height_m));
//! });
//! // Only the cells where the ray is below 0.5 m, not the point's own cell (x = 8).
//! assert_eq!(visited.iter().map(|v| v.0).collect::<Vec<_>>(), vec![4, 5, 6, 7]);
//! assert!(visited.windows(2).all(|pair| pair[1].1 < pair[0].1), "the ray descends");
//! ```

use crate::geometry::GridGeometry;

/// Calls `visit(cell index, lowest ray height above ground in the cell, metres)` for every
/// cell the ray from `camera_m` to `point_m` crosses before the point's cell, wherever the
/// ray runs lower than `max_height_m` above `ground_z_m`. Non-finite input visits nothing.
pub fn for_each_cell_below(
    geometry: &GridGeometry,
    camera_m: [f64; 3],
    point_m: [f64; 3],
    ground_z_m: f64,
    max_height_m: f64,
    mut visit: impl FnMut(usize, f32),
) {
    let finite = camera_m.iter().chain(&point_m).all(|v| v.is_finite());
    if !finite || !ground_z_m.is_finite() || !max_height_m.is_finite() {
        return;
    }
    let [cx, cy, cz] = camera_m;
    let [px, py, pz] = point_m;
    let height_at = |t: f64| cz + (pz - cz) * t - ground_z_m;
    let Some(t_start) = first_below(height_at(0.0), height_at(1.0), max_height_m) else {
        return;
    };
    let (dx, dy) = (px - cx, py - cy);
    let size = geometry.cell_size_m;
    let to_cell = |x: f64, y: f64| {
        (
            ((x - geometry.origin_x_m) / size).floor(),
            ((y - geometry.origin_y_m) / size).floor(),
        )
    };
    let (mut ix, mut iy) = to_cell(cx + dx * t_start, cy + dy * t_start);
    let (end_x, end_y) = to_cell(px, py);
    let step_x = dx.signum();
    let step_y = dy.signum();
    let (mut t_max_x, t_delta_x) = axis_crossings(ix, cx, dx, geometry.origin_x_m, size);
    let (mut t_max_y, t_delta_y) = axis_crossings(iy, cy, dy, geometry.origin_y_m, size);
    let mut t_enter = t_start;
    // A ray crosses at most this many cells (bounds the loop on any input).
    let max_steps = (end_x - ix).abs() + (end_y - iy).abs() + 2.0;
    let mut steps = 0.0;
    while (ix, iy) != (end_x, end_y) && steps < max_steps {
        let t_exit = t_max_x.min(t_max_y).min(1.0);
        let inside = ix >= 0.0
            && iy >= 0.0
            && ix < f64::from(geometry.width_cells)
            && iy < f64::from(geometry.height_cells);
        let lowest_m = height_at(t_enter).min(height_at(t_exit));
        if inside && lowest_m < max_height_m {
            visit(geometry.index(ix as u32, iy as u32), lowest_m as f32);
        }
        if t_max_x < t_max_y {
            ix += step_x;
            t_max_x += t_delta_x;
        } else {
            iy += step_y;
            t_max_y += t_delta_y;
        }
        t_enter = t_exit;
        steps += 1.0;
    }
}

/// The ray parameter where a ray whose height above ground runs from `h0` (at 0) to `h1` (at
/// 1) first runs below `max_height_m` (it may start there); `None` if it never does.
fn first_below(h0: f64, h1: f64, max_height_m: f64) -> Option<f64> {
    if h0 <= max_height_m {
        Some(0.0)
    } else if h1 < max_height_m {
        Some((h0 - max_height_m) / (h0 - h1))
    } else {
        None
    }
}

/// Along one axis, for a ray from `c` with direction component `d` starting in cell `i`: the
/// ray parameter at the next cell boundary, and between boundaries (infinite for `d = 0`).
fn axis_crossings(i: f64, c: f64, d: f64, origin: f64, size: f64) -> (f64, f64) {
    if d == 0.0 {
        return (f64::INFINITY, f64::INFINITY);
    }
    let boundary = origin + (i + d.signum().max(0.0)) * size;
    ((boundary - c) / d, size / d.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> GridGeometry {
        GridGeometry {
            origin_x_m: -5.0,
            origin_y_m: -5.0,
            cell_size_m: 0.25,
            width_cells: 40,
            height_cells: 40,
        }
    }

    #[test]
    fn a_diagonal_ray_visits_a_connected_chain_of_cells_up_to_the_point() {
        let grid = grid();
        let mut cells = Vec::new();
        for_each_cell_below(
            &grid,
            [-4.0, -3.9, 1.0],
            [1.1, 2.3, 0.0],
            0.0,
            10.0,
            |i, _| {
                cells.push(grid.coords(i));
            },
        );
        assert!(cells.len() > 20);
        for pair in cells.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let step = a.0.abs_diff(b.0) + a.1.abs_diff(b.1);
            assert_eq!(step, 1, "cells {a:?} and {b:?} are not neighbours");
        }
        let last = *cells.last().unwrap();
        let end = grid.cell_of(1.1, 2.3).unwrap();
        assert!(
            last.0.abs_diff(end.0) + last.1.abs_diff(end.1) == 1,
            "stops before the point"
        );
    }

    #[test]
    fn cells_outside_the_grid_are_skipped_and_bad_input_visits_nothing() {
        let grid = grid();
        let mut count = 0;
        for_each_cell_below(
            &grid,
            [-9.0, 0.1, 1.0],
            [-4.0, 0.1, 0.0],
            0.0,
            5.0,
            |_, _| {
                count += 1;
            },
        );
        assert_eq!(count, 4, "only the grid's cells before the point");
        for bad in [f64::NAN, f64::INFINITY] {
            for_each_cell_below(&grid, [bad, 0.0, 1.0], [1.0, 0.0, 0.0], 0.0, 5.0, |_, _| {
                panic!("visited on bad input")
            });
        }
    }

    #[test]
    fn a_ray_higher_than_the_limit_everywhere_visits_nothing() {
        let grid = grid();
        for_each_cell_below(&grid, [0.0, 0.0, 3.0], [2.0, 0.0, 2.0], 0.0, 1.0, |_, _| {
            panic!("the ray never runs below 1 m")
        });
    }
}
