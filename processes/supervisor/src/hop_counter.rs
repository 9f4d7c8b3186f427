//! Counts the jumper's hops from ground truth: a hop is a flight that rises at least
//! [`MIN_HOP_RISE_M`] above its takeoff, so the bounces of a landing are not counted as hops.

/// Rise above the takeoff point that makes a flight a hop, metres. The shortest scout hop
/// (6 m at the 60° launch elevation) climbs ~2.6 m. In boulder-fields seed 12 the 19 hops rose
/// 3.7-9.4 m and the 8 landing bounces, once counted as hops too, at most 0.25 m.
pub const MIN_HOP_RISE_M: f64 = 1.0;

/// Hop counter fed with every truth sample of the jumper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HopCounter {
    in_contact: bool,
    /// Altitude at the last takeoff, while that flight has not yet counted.
    takeoff_z_m: Option<f64>,
    hops: u32,
}

impl Default for HopCounter {
    fn default() -> Self {
        Self {
            in_contact: true,
            takeoff_z_m: None,
            hops: 0,
        }
    }
}

impl HopCounter {
    /// One truth sample: whether the jumper touches the ground, and its altitude, metres.
    pub fn observe(&mut self, in_contact: bool, z_m: f64) {
        if in_contact {
            self.takeoff_z_m = None;
        } else if self.in_contact && z_m.is_finite() {
            self.takeoff_z_m = Some(z_m);
        }
        if let Some(takeoff_z_m) = self.takeoff_z_m
            && z_m - takeoff_z_m >= MIN_HOP_RISE_M
        {
            self.hops = self.hops.saturating_add(1);
            self.takeoff_z_m = None;
        }
        self.in_contact = in_contact;
    }

    /// Hops so far.
    pub fn hops(&self) -> u32 {
        self.hops
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds a ballistic flight from `z0_m` with vertical speed `vz_mps` (Mars gravity) at
    /// 10 Hz until it comes back down, then one ground contact.
    fn fly(counter: &mut HopCounter, z0_m: f64, vz_mps: f64) {
        counter.observe(true, z0_m);
        for k in 1.. {
            let t_s = 0.1 * f64::from(k);
            let z_m = z0_m + vz_mps * t_s - 0.5 * 3.71 * t_s * t_s;
            if z_m <= z0_m {
                break;
            }
            counter.observe(false, z_m);
        }
        counter.observe(true, z0_m);
    }

    #[test]
    fn a_hop_counts_once_and_landing_bounces_do_not() {
        let mut counter = HopCounter::default();
        fly(&mut counter, 2.0, 4.4); // the shortest scout hop: ~2.6 m apex
        assert_eq!(counter.hops(), 1);
        for _ in 0..3 {
            fly(&mut counter, 2.0, 1.5); // bounces: ~0.3 m apex
        }
        assert_eq!(counter.hops(), 1);
        fly(&mut counter, -3.0, 8.7); // a Table-1 hop from a crater floor
        assert_eq!(counter.hops(), 2);
    }

    #[test]
    fn a_non_finite_altitude_is_ignored() {
        let mut counter = HopCounter::default();
        counter.observe(false, f64::NAN);
        counter.observe(false, 5.0);
        assert_eq!(counter.hops(), 0);
        counter.observe(true, 0.0);
        counter.observe(false, 0.1);
        counter.observe(false, f64::NAN);
        counter.observe(false, 1.2);
        assert_eq!(counter.hops(), 1);
    }
}
