//! The ground the terrain itself shuts: where the true slope under the rover's centre tilts
//! its body beyond what it accepts (a fresh crater's wall), as the physics would find it.
//! The truth a map and a full-knowledge path are judged against holds these cells as well
//! as the rocks, so a map that marks a crater's wall lethal is not charged with false
//! lethal cells, and the full-knowledge path does not drive through the crater.
//!
//! The slope is the world's ground height differenced half the wheelbase either side of a
//! point along x and along y: the pitch the body would take driven up or down it, judged by
//! [`RoverBody::slope_class`], the same rule the mapper applies to the ground it measured.
//!
//! ```
//! use hopnav_eval::true_slope::slope_class_at;
//! use hopnav_robot::{RoverBody, SlopeClass};
//! let body = RoverBody::default();
//! let wall = |x: f64, _y: f64| 0.8 * x;
//! assert_eq!(slope_class_at(&body, wall, [1.0, 1.0]), SlopeClass::TooSteep);
//! assert_eq!(slope_class_at(&body, |_, _| 2.0, [1.0, 1.0]), SlopeClass::Level);
//! ```

use hopnav_planner::mission::MapGeometry;
use hopnav_robot::{RoverBody, SlopeClass};

/// What the slope of the ground `height_at(x, y)` does to `body` with its centre at `xy_m`.
pub fn slope_class_at(
    body: &RoverBody,
    height_at: impl Fn(f64, f64) -> f64,
    xy_m: [f64; 2],
) -> SlopeClass {
    let half_m = body.slope_half_span_m();
    if half_m <= 0.0 {
        return SlopeClass::Level;
    }
    let [x, y] = xy_m;
    let gx = (height_at(x + half_m, y) - height_at(x - half_m, y)) / (2.0 * half_m);
    let gy = (height_at(x, y + half_m) - height_at(x, y - half_m)) / (2.0 * half_m);
    body.slope_class(gx.hypot(gy))
}

/// The true slope class of every cell of a map grid, judged at the cells' centres.
#[derive(Debug, Clone, PartialEq)]
pub struct TrueSlopes {
    geometry: MapGeometry,
    /// Row-major, one per cell of `geometry`.
    classes: Vec<SlopeClass>,
}

impl TrueSlopes {
    /// Judges every cell of `geometry` for `body` on the ground `height_at(x, y)`.
    pub fn new(
        geometry: &MapGeometry,
        body: &RoverBody,
        height_at: impl Fn(f64, f64) -> f64,
    ) -> Self {
        let (width, height) = (geometry.width_cells(), geometry.height_cells());
        let classes = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let centre_m = geometry.center_of(hopnav_planner::Cell::new(x, y));
                slope_class_at(body, &height_at, centre_m)
            })
            .collect();
        Self {
            geometry: *geometry,
            classes,
        }
    }

    /// The class of each cell, row-major over the grid.
    pub fn classes(&self) -> &[SlopeClass] {
        &self.classes
    }

    /// The class of the cell holding `xy_m` (`Level` off the grid).
    pub fn class_at_m(&self, xy_m: [f64; 2]) -> SlopeClass {
        self.geometry
            .cell_of(xy_m)
            .map(|cell| cell.y as usize * self.geometry.width_cells() as usize + cell.x as usize)
            .and_then(|index| self.classes.get(index).copied())
            .unwrap_or(SlopeClass::Level)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_crater_bowl_is_too_steep_near_its_rim_and_level_at_its_floor() {
        // A parabolic bowl of 8 m diameter, 1.6 m deep (the world's fresh craters):
        // slope 0.8·ρ, 39° at the rim.
        let bowl = |x: f64, y: f64| {
            let rho = x.hypot(y) / 4.0;
            if rho <= 1.0 { 1.6 * rho * rho } else { 1.6 }
        };
        let geometry = MapGeometry::new(-6.0, -6.0, 0.25, 48, 48).expect("grid");
        let slopes = TrueSlopes::new(&geometry, &RoverBody::default(), bowl);
        assert_eq!(slopes.class_at_m([0.1, 0.1]), SlopeClass::Level);
        assert_eq!(slopes.class_at_m([3.6, 0.1]), SlopeClass::TooSteep);
        assert_eq!(slopes.class_at_m([5.5, 5.5]), SlopeClass::Level);
        assert_eq!(slopes.class_at_m([60.0, 0.0]), SlopeClass::Level);
        assert_eq!(slopes.classes().len(), 48 * 48);
    }
}
