//! The sliding window of one hop's keyframe sightings and altimeter samples the adjustment
//! reads.

use nalgebra::Vector2;

/// One track seen in one keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sighting {
    /// Keyframe instant, seconds since the launch.
    pub tau_s: f64,
    /// The tracker's track identity.
    pub track_id: u32,
    /// Where it was seen, normalized image coordinates (`x/z`, `y/z`).
    pub normalized: Vector2<f64>,
}

/// One altimeter sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AltitudeSample {
    /// Seconds since the launch.
    pub tau_s: f64,
    /// Body altitude, metres.
    pub altitude_m: f64,
}

/// The last keyframes of a hop, their sightings, and every altimeter sample since the launch.
/// Non-finite input is dropped and counted.
#[derive(Debug, Clone, Default)]
pub struct HopWindow {
    /// Instants of the keyframes held, oldest first.
    keyframe_tau_s: Vec<f64>,
    sightings: Vec<Sighting>,
    altitudes: Vec<AltitudeSample>,
    max_keyframes: usize,
    rejected: usize,
}

/// Altitudes beyond this are no reading, metres.
const MAX_ABS_ALTITUDE_M: f64 = 1e5;

/// Altimeter samples kept per hop (a hop has about 50 frames).
const MAX_ALTITUDE_SAMPLES: usize = 512;

impl HopWindow {
    /// An empty window that keeps the last `max_keyframes` keyframes (at least 2).
    pub fn new(max_keyframes: usize) -> Self {
        Self {
            max_keyframes: max_keyframes.max(2),
            ..Self::default()
        }
    }

    /// Forgets everything (a new hop).
    pub fn clear(&mut self) {
        self.keyframe_tau_s.clear();
        self.sightings.clear();
        self.altitudes.clear();
    }

    /// Adds a keyframe at `tau_s` with its tracks (identity, normalized position); the oldest
    /// keyframe leaves when the window is full. A keyframe not later than the last is ignored.
    pub fn add_keyframe(
        &mut self,
        tau_s: f64,
        tracks: impl IntoIterator<Item = (u32, Vector2<f64>)>,
    ) {
        if !tau_s.is_finite() || self.keyframe_tau_s.last().is_some_and(|&t| t >= tau_s) {
            self.rejected += 1;
            return;
        }
        if self.keyframe_tau_s.len() >= self.max_keyframes {
            let oldest = self.keyframe_tau_s.remove(0);
            self.sightings.retain(|s| s.tau_s != oldest);
        }
        self.keyframe_tau_s.push(tau_s);
        for (track_id, normalized) in tracks {
            if normalized.iter().all(|v| v.is_finite()) {
                self.sightings.push(Sighting {
                    tau_s,
                    track_id,
                    normalized,
                });
            } else {
                self.rejected += 1;
            }
        }
    }

    /// Adds an altimeter sample (non-finite or absurd ones are dropped and counted: one
    /// 1e300 m reading would make every cost infinite for the rest of the hop).
    pub fn add_altitude(&mut self, tau_s: f64, altitude_m: f64) {
        if !(tau_s.is_finite() && altitude_m.abs() <= MAX_ABS_ALTITUDE_M) {
            self.rejected += 1;
            return;
        }
        if self.altitudes.len() < MAX_ALTITUDE_SAMPLES {
            self.altitudes.push(AltitudeSample { tau_s, altitude_m });
        }
    }

    /// Keyframes held.
    pub fn keyframes(&self) -> usize {
        self.keyframe_tau_s.len()
    }

    /// Sightings held, in keyframe order.
    pub fn sightings(&self) -> &[Sighting] {
        &self.sightings
    }

    /// Altimeter samples held.
    pub fn altitudes(&self) -> &[AltitudeSample] {
        &self.altitudes
    }

    /// Inputs dropped as non-finite or out of order.
    pub fn rejected(&self) -> usize {
        self.rejected
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_oldest_keyframe_leaves_with_its_sightings_and_bad_input_is_counted() {
        let mut window = HopWindow::new(2);
        window.add_keyframe(0.1, [(1, Vector2::new(0.0, 0.0))]);
        window.add_keyframe(
            0.2,
            [
                (1, Vector2::new(0.1, 0.0)),
                (2, Vector2::new(f64::NAN, 0.0)),
            ],
        );
        window.add_keyframe(0.3, [(2, Vector2::new(0.2, 0.0))]);
        window.add_keyframe(0.25, [(3, Vector2::new(0.2, 0.0))]);
        window.add_altitude(0.1, f64::INFINITY);
        window.add_altitude(0.1, 1e300);
        window.add_altitude(0.1, 2.0);
        assert_eq!(window.keyframes(), 2);
        assert_eq!(window.sightings().len(), 2);
        assert!(window.sightings().iter().all(|s| s.tau_s >= 0.2));
        assert_eq!(window.altitudes().len(), 1);
        assert_eq!(window.rejected(), 4);
    }
}
