//! Small f64 geometry helpers on glam types (re-exported by rapier through `glamx`).
//!
//! Rapier runs in f32; the crate keeps its own state and all outputs in f64 and converts at the
//! boundary with these helpers. Quaternions are exported as `[x, y, z, w]`.

pub use rapier3d::glamx::{DQuat, DVec3, EulerRot, Quat, Vec3};

/// `world_from_body` rotation of yaw (about z), then pitch (about the new y), then roll
/// (about the new x): `Rz(yaw) · Ry(pitch) · Rx(roll)`.
pub fn quat_from_yaw_pitch_roll(yaw_rad: f64, pitch_rad: f64, roll_rad: f64) -> DQuat {
    DQuat::from_euler(EulerRot::ZYX, yaw_rad, pitch_rad, roll_rad)
}

/// Quaternion as `[x, y, z, w]`.
pub fn quat_to_xyzw(q: DQuat) -> [f64; 4] {
    [q.x, q.y, q.z, q.w]
}

/// Vector as an array.
pub fn vec_to_array(v: DVec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// f32 vector → f64.
pub fn to_f64(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// f64 vector → f32 (rapier precision).
pub fn to_f32(v: DVec3) -> Vec3 {
    v.as_vec3()
}

/// Wraps an angle to `(−π, π]`.
pub fn wrap_angle(a_rad: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let mut a = a_rad.rem_euclid(tau);
    if a > std::f64::consts::PI {
        a -= tau;
    }
    a
}

/// World-frame angular velocity that turns `q0` into `q1` in `dt_s` (both `world_from_body`).
pub fn angular_velocity_world(q0: DQuat, q1: DQuat, dt_s: f64) -> DVec3 {
    if dt_s <= 0.0 {
        return DVec3::ZERO;
    }
    let mut dq = q1 * q0.conjugate();
    if dq.w < 0.0 {
        dq = -dq;
    }
    let s = DVec3::new(dq.x, dq.y, dq.z);
    let sin_half = s.length();
    if sin_half < 1e-12 {
        return 2.0 * s / dt_s;
    }
    let angle = 2.0 * sin_half.atan2(dq.w);
    s * (angle / (sin_half * dt_s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_and_rates() {
        assert!((wrap_angle(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_angle(-0.5) + 0.5).abs() < 1e-12);
        let q0 = quat_from_yaw_pitch_roll(0.3, 0.1, -0.2);
        let w = DVec3::new(0.1, -0.2, 0.5);
        let q1 = DQuat::from_scaled_axis(w * 0.01) * q0;
        let est = angular_velocity_world(q0, q1, 0.01);
        assert!((est - w).length() < 1e-9, "{est:?}");
    }

    #[test]
    fn pitch_sign_is_nose_down_for_positive_angle() {
        let q = quat_from_yaw_pitch_roll(0.0, 0.5, 0.0);
        assert!((q * DVec3::X).z < 0.0);
        let r = quat_from_yaw_pitch_roll(0.0, 0.0, 0.5);
        assert!((r * DVec3::Y).z > 0.0);
    }
}
