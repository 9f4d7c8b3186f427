//! The local ground under a cell: a robust plane `z = z0 + gx·(x − cx) + gy·(y − cy)` fitted
//! to the lowest observations of the neighbouring cells.
//!
//! Rock tops are the high outliers of that sample: three passes of least squares drop points
//! more than 2 robust σ above the plane (and 3 σ below: triangulation outliers). With too few
//! or collinear samples the ground is flat at the lower quartile of the samples.

use nalgebra::{Matrix3, Vector3};

/// Smallest robust σ used for rejection, metres (perfectly planar synthetic ground).
const MIN_SIGMA_M: f64 = 0.03;

/// A ground plane around a centre point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundPlane {
    /// Centre x, metres.
    pub centre_x_m: f64,
    /// Centre y, metres.
    pub centre_y_m: f64,
    /// Ground height at the centre, metres.
    pub z0_m: f64,
    /// Slope along x (dz/dx).
    pub slope_x: f64,
    /// Slope along y (dz/dy).
    pub slope_y: f64,
}

impl GroundPlane {
    /// Ground height at `(x_m, y_m)`, metres.
    pub fn height_at(&self, x_m: f64, y_m: f64) -> f64 {
        self.z0_m + self.slope_x * (x_m - self.centre_x_m) + self.slope_y * (y_m - self.centre_y_m)
    }
}

/// Reusable buffers of [`fit_ground`]; allocate once with the largest sample count.
#[derive(Debug, Default)]
pub struct GroundScratch {
    /// Samples `[x, y, z]`, metres.
    pub samples: Vec<[f64; 3]>,
    keep: Vec<bool>,
    residuals: Vec<f64>,
}

impl GroundScratch {
    /// Buffers for up to `capacity` samples.
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            samples: Vec::with_capacity(capacity),
            keep: Vec::with_capacity(capacity),
            residuals: Vec::with_capacity(capacity),
        }
    }
}

/// Fits the ground plane to `scratch.samples` around `(centre_x_m, centre_y_m)`; `None`
/// without samples. Allocation-free while the scratch capacity suffices.
pub fn fit_ground(
    scratch: &mut GroundScratch,
    centre_x_m: f64,
    centre_y_m: f64,
) -> Option<GroundPlane> {
    let GroundScratch {
        samples,
        keep,
        residuals,
    } = scratch;
    if samples.is_empty() {
        return None;
    }
    keep.clear();
    keep.resize(samples.len(), true);
    let mut plane = flat_lower_quartile(samples, residuals, centre_x_m, centre_y_m);
    for _ in 0..3 {
        let mut normal = Matrix3::zeros();
        let mut rhs = Vector3::zeros();
        let mut used = 0;
        for (sample, _) in samples.iter().zip(keep.iter()).filter(|(_, k)| **k) {
            let a = Vector3::new(1.0, sample[0] - centre_x_m, sample[1] - centre_y_m);
            normal += a * a.transpose();
            rhs += a * sample[2];
            used += 1;
        }
        // A plane needs three samples spread in x and y; otherwise stay flat.
        let solved = if used >= 3 && normal.determinant().abs() > 1e-6 * (used as f64).powi(3) {
            normal.try_inverse().map(|inverse| inverse * rhs)
        } else {
            None
        };
        let Some(coefficients) = solved else {
            break;
        };
        plane = GroundPlane {
            centre_x_m,
            centre_y_m,
            z0_m: coefficients.x,
            slope_x: coefficients.y,
            slope_y: coefficients.z,
        };
        residuals.clear();
        residuals.extend(
            samples
                .iter()
                .map(|s| (s[2] - plane.height_at(s[0], s[1])).abs()),
        );
        let sigma = 1.4826 * median_in_place(residuals) + MIN_SIGMA_M;
        for (k, s) in keep.iter_mut().zip(samples.iter()) {
            let residual = s[2] - plane.height_at(s[0], s[1]);
            *k = residual < 2.0 * sigma && residual > -3.0 * sigma;
        }
    }
    Some(plane)
}

fn flat_lower_quartile(
    samples: &[[f64; 3]],
    buffer: &mut Vec<f64>,
    centre_x_m: f64,
    centre_y_m: f64,
) -> GroundPlane {
    buffer.clear();
    buffer.extend(samples.iter().map(|s| s[2]));
    buffer.sort_by(f64::total_cmp);
    let z0_m = buffer.get(buffer.len() / 4).copied().unwrap_or(0.0);
    GroundPlane {
        centre_x_m,
        centre_y_m,
        z0_m,
        slope_x: 0.0,
        slope_y: 0.0,
    }
}

fn median_in_place(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let middle = values.len() / 2;
    let (_, median, _) = values.select_nth_unstable_by(middle, f64::total_cmp);
    *median
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_is_recovered_despite_rock_tops() {
        let mut scratch = GroundScratch::with_capacity(400);
        for i in 0..20 {
            for j in 0..20 {
                let (x, y) = (f64::from(i) * 0.25, f64::from(j) * 0.25);
                let rock = if (8..11).contains(&i) && (8..11).contains(&j) {
                    0.6
                } else {
                    0.0
                };
                scratch.samples.push([x, y, 0.3 * x - 0.1 * y + 1.0 + rock]);
            }
        }
        let plane = fit_ground(&mut scratch, 2.5, 2.5).expect("plane");
        assert!((plane.slope_x - 0.3).abs() < 1e-6, "{plane:?}");
        assert!((plane.slope_y + 0.1).abs() < 1e-6, "{plane:?}");
        assert!((plane.height_at(0.0, 0.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn collinear_samples_give_a_flat_ground() {
        let mut scratch = GroundScratch::with_capacity(8);
        scratch
            .samples
            .extend([[0.0, 0.0, 1.0], [1.0, 0.0, 2.0], [2.0, 0.0, 3.0]]);
        let plane = fit_ground(&mut scratch, 0.0, 0.0).expect("plane");
        assert_eq!((plane.slope_x, plane.slope_y), (0.0, 0.0));
        assert_eq!(plane.z0_m, 1.0);
        scratch.samples.clear();
        assert!(fit_ground(&mut scratch, 0.0, 0.0).is_none());
    }
}
