//! Scale of the unit VO translation: the paper's eq. (4) and the ballistic-fit default.

use crate::ballistic::BallisticFit;
use nalgebra::Vector3;

/// Paper eq. (4)–(5): `λ = (z_b − z_a) / t_z^w`, with `t^w` the unit camera displacement in the
/// world frame and `z` camera altitudes from the altimeter. `None` when singular (|t_z^w| below
/// `min_tz`), non-finite, negative or above `max_scale_m`.
pub fn paper_eq4(
    altitude_a_m: f64,
    altitude_b_m: f64,
    direction_world: &Vector3<f64>,
    min_tz: f64,
    max_scale_m: f64,
) -> Option<f64> {
    let tz = direction_world.z;
    if tz.is_nan() || tz.abs() < min_tz {
        return None;
    }
    let lambda = (altitude_b_m - altitude_a_m) / tz;
    (lambda.is_finite() && lambda > 0.0 && lambda <= max_scale_m).then_some(lambda)
}

/// Ballistic scale: length of the fitted camera displacement from `tau_a_s` to `tau_b_s`
/// projected on the VO direction. `None` if the fit is unsolvable or disagrees in sign.
pub fn ballistic(
    fit: &BallisticFit,
    tau_a_s: f64,
    tau_b_s: f64,
    direction_world: &Vector3<f64>,
    lever_change_m: &Vector3<f64>,
) -> Option<f64> {
    let v0 = fit.solve()?;
    let delta = fit.predict(&v0, tau_b_s) - fit.predict(&v0, tau_a_s) + lever_change_m;
    let s = direction_world.dot(&delta);
    (s.is_finite() && s > 0.0).then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq4_is_singular_at_the_apex() {
        let d = Vector3::new(1.0, 0.0, 0.001).normalize();
        assert_eq!(paper_eq4(10.0, 10.1, &d, 0.05, 5.0), None);
        let d = Vector3::new(1.0, 0.0, 1.0).normalize();
        let l = paper_eq4(1.0, 2.0, &d, 0.05, 5.0).unwrap();
        assert!((l - 2f64.sqrt()).abs() < 1e-12);
        // Noise that reverses the altitude change gives no scale.
        assert_eq!(paper_eq4(2.0, 1.0, &d, 0.05, 5.0), None);
    }
}
