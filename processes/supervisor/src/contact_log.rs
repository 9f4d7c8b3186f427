//! The rover's rock contacts as the truth shows them: where it was, what it was doing, and
//! what the map said of the ground around it at that moment. The evaluation names the rock
//! and judges the map's verdict on it; the runtime only records.

use crate::mission_record::RecordedCell;
use crate::rover_motion::RoverMotion;
use hopnav_ipc::messages::BodyState;

/// The map's cells within this of the rover's centre are kept with a contact, metres: the
/// rover's corners reach 0.61 m, and the rock it touched lies just beyond.
pub const CELLS_AROUND_M: f64 = 1.2;

/// One contact episode: the physics counted a collision in the frame at `time_s`.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedContact {
    /// Simulation time of the frame that counted it, seconds.
    pub time_s: f64,
    /// The rover's true position, world metres.
    pub rover_m: [f64; 2],
    /// The rover's true heading, radians.
    pub yaw_rad: f64,
    /// Its motion just before.
    pub motion: RoverMotion,
    /// The map's cells within [`CELLS_AROUND_M`] as the supervisor last received them.
    pub cells_around: Vec<RecordedCell>,
}

/// Watches the rover's collision counter and its motion.
#[derive(Debug, Default)]
pub struct ContactLog {
    collisions_seen: u32,
    last_motion: RoverMotion,
    contacts: Vec<RecordedContact>,
}

impl ContactLog {
    /// Takes one frame of the rover's truth, with its `motion` and heading `yaw_rad` (from
    /// [`crate::rover_motion::motion_of`]); when its collision count rose, records a contact
    /// with the cells `cells_around` gives for the rover's position.
    pub fn observe(
        &mut self,
        time_s: f64,
        rover: &BodyState,
        (motion, yaw_rad): (RoverMotion, f64),
        cells_around: impl FnOnce([f64; 2]) -> Vec<RecordedCell>,
    ) {
        if motion != RoverMotion::Still {
            self.last_motion = motion;
        }
        if rover.collisions > self.collisions_seen {
            let [x_m, y_m, _] = rover.world_from_body.position_m;
            let rover_m = [x_m, y_m];
            // One record per frame even when two episodes began in it (they share the pose).
            self.contacts.push(RecordedContact {
                time_s,
                rover_m,
                yaw_rad,
                motion: self.last_motion,
                cells_around: cells_around(rover_m),
            });
        }
        self.collisions_seen = self.collisions_seen.max(rover.collisions);
    }

    /// The contacts so far, oldest first.
    pub fn contacts(&self) -> &[RecordedContact] {
        &self.contacts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rover_motion::motion_of;
    use hopnav_ipc::messages::{CellClass, Pose3};

    fn rover(forward_mps: f64, yaw_rate_radps: f64, collisions: u32) -> BodyState {
        // Heading +y (yaw 90°), so forward speed is along y.
        let half = std::f64::consts::FRAC_PI_4;
        BodyState {
            world_from_body: Pose3 {
                position_m: [2.0, 3.0, 0.0],
                orientation_xyzw: [0.0, 0.0, half.sin(), half.cos()],
            },
            linear_velocity_mps: [0.0, forward_mps, 0.0],
            angular_velocity_radps: [0.0, 0.0, yaw_rate_radps],
            in_contact: 1,
            collisions,
        }
    }

    fn one_cell(_: [f64; 2]) -> Vec<RecordedCell> {
        vec![RecordedCell {
            x: 1,
            y: 2,
            class: CellClass::Uncertain,
            observed_by: 1,
            extra_cost: 5,
        }]
    }

    fn observe(log: &mut ContactLog, time_s: f64, rover: BodyState) {
        log.observe(time_s, &rover, motion_of(&rover), one_cell);
    }

    #[test]
    fn a_contact_after_a_turn_on_the_spot_is_a_turning_one_and_keeps_the_cells() {
        let mut log = ContactLog::default();
        observe(&mut log, 0.1, rover(0.0, 0.3, 0));
        // The refused move leaves the rover still: its last motion stands.
        observe(&mut log, 0.2, rover(0.0, 0.0, 1));
        observe(&mut log, 0.3, rover(0.0, 0.0, 1));
        let contacts = log.contacts();
        assert_eq!(contacts.len(), 1, "one record per rise of the count");
        assert_eq!(contacts[0].motion, RoverMotion::Turning);
        assert!((contacts[0].time_s - 0.2).abs() < 1e-12);
        assert!((contacts[0].rover_m[0] - 2.0).abs() < 1e-12);
        assert!((contacts[0].yaw_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        assert_eq!(contacts[0].cells_around, one_cell([0.0, 0.0]));
    }

    #[test]
    fn driving_and_reversing_are_told_apart_by_the_heading() {
        let mut log = ContactLog::default();
        observe(&mut log, 0.1, rover(0.1, 0.5, 1));
        observe(&mut log, 0.2, rover(-0.1, 0.0, 2));
        let motions: Vec<_> = log.contacts().iter().map(|c| c.motion).collect();
        assert_eq!(
            motions,
            [RoverMotion::Driving, RoverMotion::Reversing],
            "moving wins over the yaw rate"
        );
    }
}
