//! The ground's slope under the rover's centre, from the cells' ground elevation: too steep a
//! slope stops the rover as surely as a rock does (a fresh crater's wall rises to 39° at its
//! rim; the physics refuses a pitch or roll beyond the body's `max_tilt_rad`). The gradient
//! is taken across the wheelbase, the span over which the ground tilts the body, so one
//! bump does not read as a slope.
//!
//! ```
//! use hopnav_mapper::geometry::GridGeometry;
//! use hopnav_mapper::slope::SlopeJudge;
//! use hopnav_robot::{RoverBody, SlopeClass};
//! let geometry = GridGeometry { origin_x_m: 0.0, origin_y_m: 0.0, cell_size_m: 0.25, width_cells: 16, height_cells: 16 };
//! let judge = SlopeJudge::new(RoverBody::default(), geometry.cell_size_m);
//! // Ground rising 0.8 m per metre along x (a crater's wall near its rim).
//! let wall = |index: usize| Some(0.8 * geometry.coords(index).0 as f32 * 0.25);
//! assert_eq!(judge.class_at(&geometry, 8, 8, wall), SlopeClass::TooSteep);
//! assert_eq!(judge.class_at(&geometry, 8, 8, |_| Some(1.0)), SlopeClass::Level);
//! ```

use hopnav_robot::{RoverBody, SlopeClass};

use crate::geometry::GridGeometry;

/// Judges the ground's slope for one rover body on one grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlopeJudge {
    body: RoverBody,
    /// Cells from the centre to where the gradient is read, along each axis.
    span_cells: u32,
    cell_size_m: f64,
}

impl SlopeJudge {
    /// For `body` on cells of `cell_size_m` (> 0).
    pub fn new(body: RoverBody, cell_size_m: f64) -> Self {
        let span_cells = (body.slope_half_span_m() / cell_size_m).round().max(1.0) as u32;
        Self {
            body,
            span_cells,
            cell_size_m,
        }
    }

    /// Calls `f` with every cell whose slope the ground of cell `(x, y)` enters: itself and
    /// the cells the span away along each axis.
    pub fn dependents(&self, geometry: &GridGeometry, x: u32, y: u32, mut f: impl FnMut(usize)) {
        f(geometry.index(x, y));
        for (dx, dy) in self.axis_offsets() {
            if let Some(index) = offset(geometry, x, y, dx, dy) {
                f(index);
            }
        }
    }

    /// What the slope under cell `(x, y)` does to the rover, `ground_z_m` giving each cell's
    /// ground elevation (`None` where unseen). Unseen ground says nothing: `Level`.
    pub fn class_at(
        &self,
        geometry: &GridGeometry,
        x: u32,
        y: u32,
        ground_z_m: impl Fn(usize) -> Option<f32>,
    ) -> SlopeClass {
        let z = |dx: i64, dy: i64| offset(geometry, x, y, dx, dy).and_then(&ground_z_m);
        let span = i64::from(self.span_cells);
        let centre = z(0, 0);
        let along = |unit: (i64, i64)| {
            let (minus, plus) = (
                z(-unit.0 * span, -unit.1 * span),
                z(unit.0 * span, unit.1 * span),
            );
            let run_m = self.cell_size_m * span as f64;
            match (minus, centre, plus) {
                (Some(lo), _, Some(hi)) => Some(f64::from(hi - lo) / (2.0 * run_m)),
                (None, Some(mid), Some(hi)) => Some(f64::from(hi - mid) / run_m),
                (Some(lo), Some(mid), None) => Some(f64::from(mid - lo) / run_m),
                _ => None,
            }
        };
        match (along((1, 0)), along((0, 1))) {
            (None, None) => SlopeClass::Level,
            (gx, gy) => self
                .body
                .slope_class(gx.unwrap_or(0.0).hypot(gy.unwrap_or(0.0))),
        }
    }

    fn axis_offsets(&self) -> [(i64, i64); 4] {
        let span = i64::from(self.span_cells);
        [(-span, 0), (span, 0), (0, -span), (0, span)]
    }
}

/// The index of the cell `(dx, dy)` from `(x, y)`, `None` off the grid.
fn offset(geometry: &GridGeometry, x: u32, y: u32, dx: i64, dy: i64) -> Option<usize> {
    let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
    let inside = (0..i64::from(geometry.width_cells)).contains(&nx)
        && (0..i64::from(geometry.height_cells)).contains(&ny);
    inside.then(|| geometry.index(nx as u32, ny as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> GridGeometry {
        GridGeometry {
            origin_x_m: 0.0,
            origin_y_m: 0.0,
            cell_size_m: 0.25,
            width_cells: 20,
            height_cells: 20,
        }
    }

    #[test]
    fn a_gentle_slope_is_level_a_steep_one_costly_and_a_crater_wall_too_steep() {
        let geometry = geometry();
        let judge = SlopeJudge::new(RoverBody::default(), 0.25);
        let plane = |rise: f32| {
            move |index: usize| {
                let (x, y) = geometry.coords(index);
                Some(rise * 0.25 * (0.6 * x as f32 + 0.8 * y as f32))
            }
        };
        // At the grid's edge the one-sided difference still judges.
        for (x, y, rise, class) in [
            (10, 10, 0.2, SlopeClass::Level),
            (10, 10, 0.5, SlopeClass::Steep),
            (10, 10, 0.8, SlopeClass::TooSteep),
            (0, 0, 0.8, SlopeClass::TooSteep),
        ] {
            assert_eq!(
                judge.class_at(&geometry, x, y, plane(rise)),
                class,
                "{rise} at ({x}, {y})"
            );
        }
        // Beside unseen ground too.
        let half_seen = |index: usize| {
            let (x, _) = geometry.coords(index);
            (x >= 10).then_some(0.8 * 0.25 * x as f32)
        };
        assert_eq!(
            judge.class_at(&geometry, 10, 10, half_seen),
            SlopeClass::TooSteep
        );
        // Nothing seen around: no verdict.
        assert_eq!(
            judge.class_at(&geometry, 10, 10, |_| None),
            SlopeClass::Level
        );
    }

    #[test]
    fn a_lone_bump_narrower_than_the_wheelbase_is_no_slope() {
        let geometry = geometry();
        let judge = SlopeJudge::new(RoverBody::default(), 0.25);
        let bump = |index: usize| {
            Some(if geometry.coords(index) == (10, 10) {
                0.3
            } else {
                0.0
            })
        };
        assert_eq!(judge.class_at(&geometry, 10, 10, bump), SlopeClass::Level);
    }

    #[test]
    fn the_dependents_are_the_cell_and_the_span_away_on_each_axis() {
        let geometry = geometry();
        let judge = SlopeJudge::new(RoverBody::default(), 0.25);
        let mut cells = Vec::new();
        judge.dependents(&geometry, 1, 10, |index| cells.push(geometry.coords(index)));
        // Two cells (0.5 m, the nearest to half the 0.8 m wheelbase) each way; (−1, 10) is off.
        assert_eq!(cells, vec![(1, 10), (3, 10), (1, 8), (1, 12)]);
    }
}
