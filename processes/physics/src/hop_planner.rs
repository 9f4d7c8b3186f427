//! Hop planning: launch parameters that carry the jumper to a target, inside the limits.
//!
//! Drag-free ballistics under gravity `g` from launch height 0 to a target at horizontal
//! distance `d` and height difference `Δz`, at elevation `θ`:
//! `v² = g·d² / (2·cos²θ·(d·tanθ − Δz))`.
//! The planner keeps the configured angle and solves for the speed; if the target is too high
//! for that angle it steepens up to the largest allowed angle. The speed is then clamped into
//! `[min, max]`; a clamped plan says so and predicts the range it will really fly.
//!
//! ```
//! use hopnav_physics::hop_planner::{HopLimits, plan_hop};
//! let limits = HopLimits { min_speed_mps: 0.5, max_speed_mps: 12.0,
//!     min_angle_rad: 0.35, max_angle_rad: 1.4 };
//! let plan = plan_hop([0.0, 0.0, 0.0], [23.3, 0.0, 0.0], 60f64.to_radians(), 0.0, &limits, 3.711);
//! assert!((plan.launch_speed_mps - 10.0).abs() < 0.01);
//! assert!(!plan.clamped);
//! ```

/// Launch limits of the jumper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HopLimits {
    /// Smallest launch speed, m/s.
    pub min_speed_mps: f64,
    /// Largest launch speed, m/s.
    pub max_speed_mps: f64,
    /// Smallest elevation angle, radians.
    pub min_angle_rad: f64,
    /// Largest elevation angle, radians.
    pub max_angle_rad: f64,
}

/// Launch parameters chosen for one hop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HopPlan {
    /// Heading about world z, radians.
    pub heading_rad: f64,
    /// Launch speed, m/s.
    pub launch_speed_mps: f64,
    /// Elevation angle, radians.
    pub launch_angle_rad: f64,
    /// Whether the ideal parameters had to be clamped to the limits.
    pub clamped: bool,
    /// Horizontal distance to the target, metres.
    pub target_distance_m: f64,
    /// Predicted horizontal range to the target's height, metres (at the apex distance if
    /// the hop cannot reach that height).
    pub predicted_range_m: f64,
}

/// Plans a hop from `from_m` (ground point under the jumper) to `target_m` (ground point),
/// preferring `angle_rad`; `fallback_heading_rad` is used when the target is the start point.
///
/// Never panics; non-finite inputs give a minimum-speed hop along the fallback heading.
pub fn plan_hop(
    from_m: [f64; 3],
    target_m: [f64; 3],
    angle_rad: f64,
    fallback_heading_rad: f64,
    limits: &HopLimits,
    gravity_mps2: f64,
) -> HopPlan {
    let dx = target_m[0] - from_m[0];
    let dy = target_m[1] - from_m[1];
    let dz = target_m[2] - from_m[2];
    let d = dx.hypot(dy);
    let g = gravity_mps2;
    let mut angle = clamp(angle_rad, limits.min_angle_rad, limits.max_angle_rad);
    let finite = d.is_finite() && dz.is_finite() && g.is_finite() && g > 0.0;
    let heading = if finite && d > 1e-9 {
        dy.atan2(dx)
    } else {
        fallback_heading_rad
    };
    if !finite || d <= 1e-9 {
        return finish(heading, limits.min_speed_mps, angle, true, 0.0, dz, g);
    }
    // Steepen if the target is above the line of sight at the preferred angle.
    if d * angle.tan() - dz <= 0.0 {
        angle = limits.max_angle_rad;
    }
    let denom = 2.0 * angle.cos().powi(2) * (d * angle.tan() - dz);
    let (ideal, reachable) = if denom > 0.0 {
        ((g * d * d / denom).sqrt(), true)
    } else {
        (f64::INFINITY, false)
    };
    let speed = clamp(ideal, limits.min_speed_mps, limits.max_speed_mps);
    let clamped = !reachable
        || speed != ideal
        || angle != clamp(angle_rad, limits.min_angle_rad, limits.max_angle_rad);
    finish(heading, speed, angle, clamped, d, dz, g)
}

fn finish(
    heading_rad: f64,
    speed: f64,
    angle: f64,
    clamped: bool,
    d: f64,
    dz: f64,
    g: f64,
) -> HopPlan {
    HopPlan {
        heading_rad,
        launch_speed_mps: speed,
        launch_angle_rad: angle,
        clamped,
        target_distance_m: d,
        predicted_range_m: ballistic_range_m(
            speed,
            angle,
            if dz.is_finite() { dz } else { 0.0 },
            g,
        ),
    }
}

/// Horizontal distance at which a hop (speed, angle) comes down to height `dz` (descending
/// branch); if it never reaches `dz`, the distance of the apex.
pub fn ballistic_range_m(speed_mps: f64, angle_rad: f64, dz_m: f64, gravity_mps2: f64) -> f64 {
    if gravity_mps2.is_nan() || gravity_mps2 <= 0.0 {
        return 0.0;
    }
    let (s, c) = angle_rad.sin_cos();
    let vz = speed_mps * s;
    let vh = speed_mps * c;
    let disc = vz * vz - 2.0 * gravity_mps2 * dz_m;
    let t = if disc >= 0.0 {
        (vz + disc.sqrt()) / gravity_mps2
    } else {
        vz / gravity_mps2
    };
    vh * t
}

fn clamp(v: f64, lo: f64, hi: f64) -> f64 {
    if v.is_nan() { lo } else { v.max(lo).min(hi) }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: HopLimits = HopLimits {
        min_speed_mps: 0.5,
        max_speed_mps: 12.0,
        min_angle_rad: 0.35,
        max_angle_rad: 1.4,
    };

    #[test]
    fn table1_range() {
        let r = ballistic_range_m(10.0, 60f64.to_radians(), 0.0, 3.711);
        assert!((r - 23.34).abs() < 0.01, "{r}");
    }

    #[test]
    fn solves_uphill_and_downhill() {
        for dz in [-3.0, 0.0, 2.0] {
            let p = plan_hop([1.0, 2.0, 0.0], [9.0, 8.0, dz], 1.0, 0.0, &LIMITS, 3.711);
            assert!(!p.clamped);
            assert!((p.predicted_range_m - 10.0).abs() < 1e-9, "{p:?}");
            assert!((p.heading_rad - (6f64).atan2(8.0)).abs() < 1e-12);
        }
    }

    #[test]
    fn clamps_far_and_steep_targets() {
        let far = plan_hop([0.0; 3], [200.0, 0.0, 0.0], 1.0, 0.0, &LIMITS, 3.711);
        assert!(far.clamped && far.launch_speed_mps == 12.0);
        assert!(far.predicted_range_m < 40.0);
        let cliff = plan_hop([0.0; 3], [1.0, 0.0, 50.0], 1.0, 0.0, &LIMITS, 3.711);
        assert!(cliff.clamped && cliff.launch_angle_rad == 1.4);
        let here = plan_hop([0.0; 3], [0.0, 0.0, 0.0], 1.0, 0.7, &LIMITS, 3.711);
        assert!(here.clamped && here.heading_rad == 0.7 && here.launch_speed_mps == 0.5);
        let nan = plan_hop(
            [0.0; 3],
            [f64::NAN, 0.0, 0.0],
            f64::NAN,
            0.2,
            &LIMITS,
            3.711,
        );
        assert!(nan.launch_speed_mps.is_finite() && nan.launch_angle_rad == 0.35);
    }
}
