//! The attitude and time of the hop's recent keyframes, by keyframe serial, so a cloud can
//! triangulate a track from the keyframe it was born in (see
//! [`JumperVoConfig::cloud_track_keyframes`](crate::config::JumperVoConfig)).
//!
//! Only the attitude is kept: a keyframe's position is re-read from the hop's ballistic fit
//! when the cloud is made, because the fit keeps improving over the flight and the position
//! stored at the keyframe predates that (its error tilts a long baseline).

use nalgebra::{Isometry3, UnitQuaternion};

use crate::config::MAX_CLOUD_TRACK_KEYFRAMES;

/// One flight keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct KeyframeRecord {
    /// The tracker's keyframe serial.
    pub serial: u32,
    /// Launch instant of the hop it belongs to, seconds.
    pub launch_t_s: f64,
    /// Time since that launch, seconds.
    pub tau_s: f64,
    /// Camera pose as the VO had it then (position used only without a fit).
    pub world_from_cam: Isometry3<f64>,
}

impl KeyframeRecord {
    /// The camera attitude.
    pub fn rotation(&self) -> UnitQuaternion<f64> {
        self.world_from_cam.rotation
    }
}

/// A fixed ring of the last [`MAX_CLOUD_TRACK_KEYFRAMES`] keyframes (no allocation per frame).
#[derive(Debug, Clone)]
pub(crate) struct KeyframeHistory {
    slots: [Option<KeyframeRecord>; MAX_CLOUD_TRACK_KEYFRAMES as usize],
}

impl Default for KeyframeHistory {
    fn default() -> Self {
        Self {
            slots: [None; MAX_CLOUD_TRACK_KEYFRAMES as usize],
        }
    }
}

impl KeyframeHistory {
    fn slot(serial: u32) -> usize {
        (serial % MAX_CLOUD_TRACK_KEYFRAMES) as usize
    }

    /// Remembers `record`, overwriting the keyframe [`MAX_CLOUD_TRACK_KEYFRAMES`] serials older.
    pub fn record(&mut self, record: KeyframeRecord) {
        self.slots[Self::slot(record.serial)] = Some(record);
    }

    /// The keyframe with `serial` of the hop launched at `launch_t_s`, if still kept.
    pub fn get(&self, serial: u32, launch_t_s: f64) -> Option<&KeyframeRecord> {
        self.slots[Self::slot(serial)]
            .as_ref()
            .filter(|record| record.serial == serial && record.launch_t_s == launch_t_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(serial: u32, launch_t_s: f64) -> KeyframeRecord {
        KeyframeRecord {
            serial,
            launch_t_s,
            tau_s: 0.1 * f64::from(serial),
            world_from_cam: Isometry3::translation(f64::from(serial), 0.0, 0.0),
        }
    }

    #[test]
    fn keeps_the_last_keyframes_of_the_hop_and_forgets_older_or_other_hops() {
        let mut history = KeyframeHistory::default();
        for serial in 0..40 {
            history.record(record(serial, 5.0));
        }
        assert_eq!(history.get(39, 5.0), Some(&record(39, 5.0)));
        assert_eq!(history.get(8, 5.0), Some(&record(8, 5.0)));
        // Serial 39 took serial 7's slot.
        assert_eq!(history.get(7, 5.0), None);
        // Same serial, another hop.
        assert_eq!(history.get(39, 6.0), None);
        assert_eq!(history.get(40, 5.0), None);
    }
}
