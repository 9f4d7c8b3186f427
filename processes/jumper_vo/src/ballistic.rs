//! Least-squares fit of a ballistic flight: the launch velocity `v0` given the launch position
//! `p0`, launch time and known gravity.
//!
//! Model: `p(τ) = p0 + v0 τ − ½ g τ² ẑ`, `τ` = time since launch. Three kinds of rows, all
//! linear in `v0`, are accumulated into 3×3 normal equations (constant memory, O(1) per row):
//!
//! - altimeter: `v0_z τ = z_alt − p0_z + ½ g τ²`, σ = altimeter σ;
//! - VO direction `d` (unit, world frame) of the displacement between times `τa` and `τb`:
//!   `(I − d dᵀ)(v0 Δτ) = (I − d dᵀ)(½ g Δ(τ²) ẑ + known)`. Gravity's known, metric
//!   displacement makes the *length* along `d` observable: this is what fixes the monocular
//!   scale without relying on a per-frame altitude difference;
//! - an optional prior on `v0` (the commanded launch velocity).
//!
//! ```
//! use hopnav_jumper_vo::ballistic::BallisticFit;
//! use nalgebra::{Point3, Vector3};
//! let (p0, v0, g) = (Point3::new(0.0, 0.0, 1.0), Vector3::new(5.0, 0.0, 8.66), 3.711);
//! let mut fit = BallisticFit::new(p0, g);
//! let truth = |t: f64| p0 + v0 * t - Vector3::z() * (0.5 * g * t * t);
//! for k in 1..10 {
//!     let (ta, tb) = (0.1 * (k - 1) as f64, 0.1 * k as f64);
//!     fit.add_altitude(tb, truth(tb).z, 1.0);
//!     let d = (truth(tb) - truth(ta)).normalize();
//!     fit.add_direction(ta, tb, &d, &Vector3::zeros(), 0.01);
//! }
//! let v = fit.solve().unwrap();
//! assert!((v - v0).norm() < 1e-4);
//! ```

use nalgebra::{Matrix3, Point3, Vector3};

/// Normal equations of the launch-velocity fit.
#[derive(Debug, Clone, PartialEq)]
pub struct BallisticFit {
    launch_position_m: Point3<f64>,
    gravity_mps2: f64,
    normal: Matrix3<f64>,
    rhs: Vector3<f64>,
    altitude_rows: usize,
    direction_rows: usize,
    /// The bundle adjustment's launch velocity, which [`Self::solve`] returns once set.
    refined_mps: Option<Vector3<f64>>,
    /// Its covariance, when the adjustment gave one.
    refined_covariance: Option<Matrix3<f64>>,
}

impl BallisticFit {
    /// An empty fit for a launch at `launch_position_m` (τ = 0).
    pub fn new(launch_position_m: Point3<f64>, gravity_mps2: f64) -> Self {
        Self {
            launch_position_m,
            gravity_mps2,
            normal: Matrix3::zeros(),
            rhs: Vector3::zeros(),
            altitude_rows: 0,
            direction_rows: 0,
            refined_mps: None,
            refined_covariance: None,
        }
    }

    /// Launch position.
    pub fn launch_position_m(&self) -> Point3<f64> {
        self.launch_position_m
    }

    /// Altimeter samples used.
    pub fn altitude_rows(&self) -> usize {
        self.altitude_rows
    }

    /// VO directions used.
    pub fn direction_rows(&self) -> usize {
        self.direction_rows
    }

    fn add_row(&mut self, a: &Vector3<f64>, b: f64, weight: f64) {
        if a.iter().all(|v| v.is_finite()) && b.is_finite() && weight.is_finite() && weight > 0.0 {
            self.normal += a * a.transpose() * weight;
            self.rhs += a * (b * weight);
        }
    }

    /// Adds an altimeter sample `altitude_m` (body altitude) at `tau_s`.
    pub fn add_altitude(&mut self, tau_s: f64, altitude_m: f64, sigma_m: f64) {
        if !(tau_s > 0.0 && altitude_m.is_finite() && sigma_m > 0.0) {
            return;
        }
        let b = altitude_m - self.launch_position_m.z + 0.5 * self.gravity_mps2 * tau_s * tau_s;
        self.add_row(&Vector3::new(0.0, 0.0, tau_s), b, 1.0 / (sigma_m * sigma_m));
        self.altitude_rows += 1;
    }

    /// Adds a prior `v0 ≈ velocity_mps` with σ per axis.
    pub fn add_velocity_prior(&mut self, velocity_mps: &Vector3<f64>, sigma_mps: f64) {
        if sigma_mps.is_nan() || sigma_mps <= 0.0 {
            return;
        }
        let w = 1.0 / (sigma_mps * sigma_mps);
        for i in 0..3 {
            let mut a = Vector3::zeros();
            a[i] = 1.0;
            self.add_row(&a, velocity_mps[i], w);
        }
    }

    /// Adds a unit direction `d_world` of the body displacement from `tau_a_s` to `tau_b_s`.
    ///
    /// `known_offset_m` is a known non-ballistic part of that displacement (e.g. the lever arm
    /// of the camera turning with the body), subtracted before the fit. `sigma_rad` is the
    /// angular σ of `d_world`; rows are weighted by the predicted displacement length.
    pub fn add_direction(
        &mut self,
        tau_a_s: f64,
        tau_b_s: f64,
        d_world: &Vector3<f64>,
        known_offset_m: &Vector3<f64>,
        sigma_rad: f64,
    ) {
        let dt = tau_b_s - tau_a_s;
        let Some(d) = d_world.try_normalize(1e-9) else {
            return;
        };
        if !(dt > 1e-6
            && sigma_rad > 0.0
            && d.iter().chain(known_offset_m.iter()).all(|v| v.is_finite())
            && tau_a_s.is_finite())
        {
            return;
        }
        let gravity_m =
            -Vector3::z() * (0.5 * self.gravity_mps2 * (tau_b_s * tau_b_s - tau_a_s * tau_a_s));
        // Predicted length (from the current fit if any) sets the metric σ of the row.
        let predicted_len_m = self
            .solve()
            .map(|v| (v * dt + gravity_m).norm())
            .unwrap_or(dt * 5.0)
            .max(0.05);
        let projector = Matrix3::identity() - d * d.transpose();
        let target = projector * (-gravity_m - known_offset_m);
        let w = 1.0 / (sigma_rad * predicted_len_m).powi(2);
        // Two independent rows: project onto an orthonormal basis of the plane ⟂ d.
        let e1 = d.cross(&Vector3::x());
        let e1 = if e1.norm() > 0.3 {
            e1
        } else {
            d.cross(&Vector3::y())
        };
        let Some(e1) = e1.try_normalize(1e-9) else {
            return;
        };
        let e2 = d.cross(&e1);
        for e in [e1, e2] {
            self.add_row(&(e * dt), e.dot(&target), w);
        }
        self.direction_rows += 1;
    }

    /// Least-squares launch velocity; `None` while unobservable (needs a prior or directions
    /// for the horizontal part). A tiny ridge keeps an altimeter-only fit solvable in z with
    /// zero horizontal velocity.
    pub fn solve(&self) -> Option<Vector3<f64>> {
        if self.refined_mps.is_some() {
            return self.refined_mps;
        }
        let v = self.ridged_normal().cholesky()?.solve(&self.rhs);
        v.iter().all(|x| x.is_finite()).then_some(v)
    }

    /// The normal matrix with a tiny ridge that keeps an altimeter-only fit solvable.
    fn ridged_normal(&self) -> Matrix3<f64> {
        self.normal + Matrix3::identity() * (1e-12 * (1.0 + self.normal.trace()))
    }

    /// Hands the launch velocity to a better estimate (the bundle adjustment, which reads the
    /// same altimeter samples and the tracks the directions came from): [`Self::solve`]
    /// returns it from now on. Non-finite velocities are ignored.
    pub fn set_refined(&mut self, velocity_mps: &Vector3<f64>, covariance: Option<Matrix3<f64>>) {
        if velocity_mps.iter().all(|v| v.is_finite()) {
            self.refined_mps = Some(*velocity_mps);
            self.refined_covariance = covariance.filter(|c| c.iter().all(|v| v.is_finite()));
        }
    }

    /// Covariance of the launch velocity, (m/s)²: the adjustment's once it gave one, else the
    /// inverse of these normal equations (their rows are weighted by 1/σ²); `None` while
    /// unobservable.
    pub fn velocity_covariance(&self) -> Option<Matrix3<f64>> {
        if self.refined_mps.is_some() && self.refined_covariance.is_some() {
            return self.refined_covariance;
        }
        let covariance = self.ridged_normal().cholesky()?.inverse();
        covariance
            .iter()
            .all(|v| v.is_finite())
            .then_some(covariance)
    }

    /// Fitted body position at `tau_s`, if solvable.
    pub fn position_m(&self, tau_s: f64) -> Option<Point3<f64>> {
        let v = self.solve()?;
        Some(self.predict(&v, tau_s))
    }

    /// Position for a given launch velocity at `tau_s`.
    pub fn predict(&self, v0_mps: &Vector3<f64>, tau_s: f64) -> Point3<f64> {
        self.launch_position_m + v0_mps * tau_s
            - Vector3::z() * (0.5 * self.gravity_mps2 * tau_s * tau_s)
    }

    /// Velocity for a given launch velocity at `tau_s`.
    pub fn velocity(&self, v0_mps: &Vector3<f64>, tau_s: f64) -> Vector3<f64> {
        v0_mps - Vector3::z() * (self.gravity_mps2 * tau_s)
    }

    /// Predicted touchdown time (back at the launch altitude), if the fit climbs.
    pub fn touchdown_tau_s(&self) -> Option<f64> {
        let v = self.solve()?;
        (v.z > 0.0).then(|| 2.0 * v.z / self.gravity_mps2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::NoiseRng;

    #[test]
    fn altimeter_only_recovers_vertical_velocity() {
        let p0 = Point3::new(1.0, 2.0, 3.0);
        let mut fit = BallisticFit::new(p0, 3.711);
        let mut rng = NoiseRng::new(1);
        for k in 1..=46 {
            let t = 0.1 * k as f64;
            let z = p0.z + 8.66 * t - 0.5 * 3.711 * t * t + rng.gaussian();
            fit.add_altitude(t, z, 1.0);
        }
        let v = fit.solve().unwrap();
        assert!((v.z - 8.66).abs() < 0.2, "{v}");
        assert!(v.x.abs() < 1e-3 && v.y.abs() < 1e-3);
        assert!((fit.touchdown_tau_s().unwrap() - 4.667).abs() < 0.2);
    }

    #[test]
    fn rejects_non_finite_rows() {
        let mut fit = BallisticFit::new(Point3::origin(), 3.711);
        fit.add_altitude(0.5, f64::NAN, 1.0);
        fit.add_direction(
            0.0,
            0.1,
            &Vector3::new(f64::NAN, 0.0, 1.0),
            &Vector3::zeros(),
            0.01,
        );
        assert_eq!(fit.altitude_rows() + fit.direction_rows(), 0);
    }
}
