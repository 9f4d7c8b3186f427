//! Height of cloud points above the **local** ground, and the rover's height above the ground.
//!
//! 1. A robust plane `z = a + b·x + c·y` through the cloud: least squares, then refits on the
//!    lower part of the residuals (rocks stand above the ground, so the ground is the lower
//!    envelope).
//! 2. Each point's residual to that plane, minus the same robust plane fitted to the residuals
//!    of the points within `radius_m` (horizontal) of its grid cell's centre (cells of
//!    `radius_m / 2`, one local fit per occupied cell) and evaluated at the point: the local
//!    ground around it. A rock's top therefore gets a positive height even on a slope or in a
//!    crater; ground points get ≈ 0.
//!
//! ```
//! use hopnav_rover_vo::ground::{GroundModel, LocalGround};
//! use nalgebra::Point3;
//! let mut pts: Vec<Point3<f64>> = (0..100)
//!     .map(|i| Point3::new((i % 10) as f64 * 0.5, (i / 10) as f64 * 0.5, 0.1 * (i % 10) as f64 * 0.5))
//!     .collect();
//! pts.push(Point3::new(2.2, 2.2, 0.1 * 2.2 + 0.6)); // a rock top on the slope
//! let mut ground = LocalGround::new(256);
//! let mut heights = Vec::new();
//! ground.heights(&pts, 2.0, 0.6, &mut heights);
//! assert!((heights[100] - 0.6).abs() < 0.05 && heights[0].abs() < 0.05);
//! let plane = GroundModel::fit(&pts, 0.6, &mut Vec::new()).unwrap();
//! assert!((plane.height_at(0.0, 0.0)).abs() < 0.05);
//! ```

use nalgebra::{Matrix3, Point3, Vector3};

/// A ground plane `z = a + b·x + c·y`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundModel {
    /// Coefficients `[a, b, c]`.
    pub coefficients: [f64; 3],
}

impl GroundModel {
    /// Robust fit (least squares, then three refits on the lowest `keep_fraction` of the
    /// residuals). `scratch` holds residuals. `None` with fewer than 3 points or degenerate.
    pub fn fit(points: &[Point3<f64>], keep_fraction: f64, scratch: &mut Vec<f64>) -> Option<Self> {
        let mut model = Self::least_squares(points, f64::INFINITY, None)?;
        for _ in 0..3 {
            scratch.clear();
            scratch.extend(points.iter().map(|p| p.z - model.height_at(p.x, p.y)));
            let k = (scratch.len() as f64 * keep_fraction.clamp(0.05, 1.0)) as usize;
            let k = k.min(scratch.len().saturating_sub(1));
            let (_, &mut cut, _) = scratch.select_nth_unstable_by(k, f64::total_cmp);
            model = Self::least_squares(points, cut, Some(&model)).unwrap_or(model);
        }
        Some(model)
    }

    fn least_squares(
        points: &[Point3<f64>],
        max_residual: f64,
        prior: Option<&Self>,
    ) -> Option<Self> {
        let mut a = Matrix3::<f64>::zeros();
        let mut b = Vector3::<f64>::zeros();
        let mut n = 0;
        for p in points {
            if let Some(m) = prior
                && p.z - m.height_at(p.x, p.y) > max_residual
            {
                continue;
            }
            if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
                continue;
            }
            let row = Vector3::new(1.0, p.x, p.y);
            a += row * row.transpose();
            b += row * p.z;
            n += 1;
        }
        if n < 3 {
            return None;
        }
        let x = a.try_inverse()? * b;
        x.iter().all(|v| v.is_finite()).then_some(Self {
            coefficients: [x[0], x[1], x[2]],
        })
    }

    /// Plane height at `(x, y)`.
    pub fn height_at(&self, x: f64, y: f64) -> f64 {
        let [a, b, c] = self.coefficients;
        a + b * x + c * y
    }
}

/// Computes heights above the local ground; buffers reused between calls.
#[derive(Debug, Clone, Default)]
pub struct LocalGround {
    residuals: Vec<f64>,
    neighbours: Vec<Point3<f64>>,
    scratch: Vec<f64>,
    cells: Vec<(i64, i64, usize)>,
}

impl LocalGround {
    /// Buffers for clouds of up to `capacity` points.
    pub fn new(capacity: usize) -> Self {
        Self {
            residuals: Vec::with_capacity(capacity),
            neighbours: Vec::with_capacity(capacity),
            scratch: Vec::with_capacity(capacity),
            cells: Vec::with_capacity(capacity),
        }
    }

    /// Fills `heights` (one per point) with the height above the local ground, metres
    /// (`NaN` if no plane could be fitted). `keep_fraction`: share of the lowest residuals the
    /// robust plane fits keep.
    pub fn heights(
        &mut self,
        points: &[Point3<f64>],
        radius_m: f64,
        keep_fraction: f64,
        heights: &mut Vec<f64>,
    ) {
        heights.clear();
        let Some(plane) = GroundModel::fit(points, keep_fraction, &mut self.scratch) else {
            heights.resize(points.len(), f64::NAN);
            return;
        };
        self.residuals.clear();
        self.residuals
            .extend(points.iter().map(|p| p.z - plane.height_at(p.x, p.y)));
        heights.resize(points.len(), f64::NAN);
        let r2 = radius_m * radius_m;
        let cell_m = (0.5 * radius_m).max(1e-3);
        self.cells.clear();
        for (i, p) in points.iter().enumerate() {
            if p.x.is_finite() && p.y.is_finite() {
                self.cells.push((
                    (p.x / cell_m).floor() as i64,
                    (p.y / cell_m).floor() as i64,
                    i,
                ));
            }
        }
        self.cells.sort_unstable();
        let mut start = 0;
        while start < self.cells.len() {
            let (ix, iy, _) = self.cells[start];
            let mut end = start;
            while end < self.cells.len() && self.cells[end].0 == ix && self.cells[end].1 == iy {
                end += 1;
            }
            let (cx, cy) = ((ix as f64 + 0.5) * cell_m, (iy as f64 + 0.5) * cell_m);
            self.neighbours.clear();
            for (q, &r) in points.iter().zip(&self.residuals) {
                let (dx, dy) = (q.x - cx, q.y - cy);
                if dx * dx + dy * dy <= r2 {
                    self.neighbours.push(Point3::new(dx, dy, r));
                }
            }
            let local = if self.neighbours.len() >= 8 {
                GroundModel::fit(&self.neighbours, keep_fraction, &mut self.scratch)
            } else {
                None
            };
            for &(_, _, i) in &self.cells[start..end] {
                let p = &points[i];
                let ground = local.map_or(0.0, |m| m.height_at(p.x - cx, p.y - cy));
                heights[i] = self.residuals[i] - ground;
            }
            start = end;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rock_in_a_crater_is_above_local_ground() {
        // Bowl-shaped ground (crater) with a 0.5 m rock at its bottom.
        let mut pts = Vec::new();
        for i in 0..30 {
            for j in 0..30 {
                let (x, y) = (i as f64 * 0.4 - 6.0, j as f64 * 0.4 - 6.0);
                pts.push(Point3::new(x, y, 0.02 * (x * x + y * y)));
            }
        }
        for k in 0..6 {
            pts.push(Point3::new(0.05 * k as f64, 0.0, 0.5));
        }
        let mut ground = LocalGround::new(1000);
        let mut h = Vec::new();
        ground.heights(&pts, 1.5, 0.6, &mut h);
        let n = pts.len();
        for k in 0..6 {
            assert!(h[n - 1 - k] > 0.35, "rock height {}", h[n - 1 - k]);
        }
        let ground_max = h[..900].iter().cloned().fold(f64::MIN, f64::max);
        assert!(ground_max < 0.2, "ground height {ground_max}");
    }
}
