//! Did a replan move the rover's route, or only re-price it?
//!
//! A replan (see [`NavigatorCounters::replans`](super::NavigatorCounters)) counts every map
//! change that alters the cost of the path being followed, including an inflated cell whose
//! cost rose while the route stayed put. A route change is a replan after which the rover
//! follows a different way: some cell of the new path lies more than
//! [`ROUTE_TOLERANCE_CELLS`] away from every cell of the old one. The tolerance ignores a
//! search that swaps between equal-cost neighbours (a diagonal step before or after a straight
//! one) and a rover that drifted a cell off its path.

use crate::grid::Cell;

/// Chebyshev distance, in cells, within which a new path cell counts as on the old route.
pub const ROUTE_TOLERANCE_CELLS: u32 = 1;

/// True when some cell of `new_path` lies more than [`ROUTE_TOLERANCE_CELLS`] from every cell
/// of `old_path`. The new path's cells before it first comes near the old one are the way
/// back to it (a rover that backed off a rock, or was pushed off its path), not another
/// route; a new path that never comes near the old one is. An empty old path (no route yet)
/// is never a change.
pub fn route_moved(old_path: &[Cell], new_path: &[Cell]) -> bool {
    if old_path.is_empty() {
        return false;
    }
    let near_old = |new: &Cell| {
        old_path
            .iter()
            .any(|old| chebyshev_cells(*old, *new) <= ROUTE_TOLERANCE_CELLS)
    };
    match new_path.iter().position(near_old) {
        Some(rejoin) => new_path
            .get(rejoin..)
            .is_some_and(|rest| !rest.iter().all(near_old)),
        None => !new_path.is_empty(),
    }
}

fn chebyshev_cells(a: Cell, b: Cell) -> u32 {
    a.x.abs_diff(b.x).max(a.y.abs_diff(b.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(y: u32, xs: std::ops::Range<u32>) -> Vec<Cell> {
        xs.map(|x| Cell::new(x, y)).collect()
    }

    #[test]
    fn the_same_route_or_its_remainder_is_no_change() {
        let old = row(5, 0..20);
        assert!(!route_moved(&old, &old));
        assert!(!route_moved(&old, &old[7..]));
    }

    #[test]
    fn a_route_one_cell_over_is_no_change() {
        let old = row(5, 0..20);
        let mut new = row(5, 0..8);
        new.extend(row(6, 8..12));
        new.extend(row(5, 12..20));
        assert!(!route_moved(&old, &new));
    }

    #[test]
    fn a_detour_two_cells_away_is_a_change() {
        let old = row(5, 0..20);
        let mut new = row(5, 0..8);
        new.push(Cell::new(8, 6));
        new.extend(row(7, 9..12));
        new.push(Cell::new(12, 6));
        new.extend(row(5, 13..20));
        assert!(route_moved(&old, &new));
    }

    #[test]
    fn a_way_back_to_the_old_route_is_no_change_and_a_route_that_never_meets_it_is() {
        let old = row(5, 0..20);
        // Backed off three cells below the route, then back onto it.
        let mut back = vec![Cell::new(3, 8), Cell::new(4, 7)];
        back.extend(row(5, 5..20));
        assert!(!route_moved(&old, &back));
        assert!(route_moved(&old, &row(12, 0..20)));
    }

    #[test]
    fn a_first_route_is_no_change() {
        assert!(!route_moved(&[], &row(5, 0..20)));
    }
}
