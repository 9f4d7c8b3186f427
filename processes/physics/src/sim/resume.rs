//! The simulation's state at the end of a frame, and a fresh simulation resumed from it: a
//! restarted physics continues the mission (time, both robots, the hop in progress, the
//! sensor noise) instead of starting it over.

use crate::frame::{BodyState, FrameOutputs};
use crate::jumper::JumperSnapshot;
use crate::noise::NoiseRng;
use crate::rover::{RestoreError, RoverSnapshot};

use super::PhysicsSim;

/// Everything a simulation of the same world, configuration and seed needs to continue from
/// the end of a frame. The world and the rapier scene are rebuilt from the configuration;
/// rapier's contact caches are not part of it, so a resting or landing jumper continues
/// within solver tolerance, not bit for bit.
#[derive(Debug, Clone, PartialEq)]
pub struct SimSnapshot {
    /// Frames simulated so far (sim time = frames × frame period).
    pub frames_simulated: u64,
    /// Jumper ground truth.
    pub jumper: BodyState,
    /// Jumper hop cycle.
    pub jumper_cycle: JumperSnapshot,
    /// Rover ground truth.
    pub rover: BodyState,
    /// Rover controller.
    pub rover_drive: RoverSnapshot,
    /// The altimeter's noise generator.
    pub altimeter_noise: NoiseRng,
    /// The IMU's noise generator.
    pub imu_noise: NoiseRng,
    /// The IMU attitude's accumulated yaw error, radians.
    pub imu_yaw_error_rad: f64,
}

/// Why a simulation could not resume from a snapshot.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResumeError {
    /// Only a simulation that has not stepped yet can resume.
    #[error("the simulation already ran {frames} frames; only a fresh one can resume")]
    AlreadyStarted {
        /// Frames it ran.
        frames: u64,
    },
    /// The rover cannot be put back where the snapshot says it was.
    #[error(transparent)]
    Rover(#[from] RestoreError),
    /// A value no simulation of this world and configuration reaches (a garbled sample, or
    /// one of another world).
    #[error("{field} = {value} is outside [{min}, {max}]")]
    OutOfRange {
        /// Which value.
        field: &'static str,
        /// The value found.
        value: f64,
        /// Smallest allowed.
        min: f64,
        /// Largest allowed.
        max: f64,
    },
    /// The hop cycle contradicts itself: a hop in progress (in flight or landing) without the
    /// record of that hop.
    #[error("the jumper is {state:?} in hop {hop_count} but the snapshot has no record of it")]
    HopWithoutRecord {
        /// Phase in the snapshot.
        state: crate::frame::HopState,
        /// Hops launched, from the snapshot.
        hop_count: u32,
    },
}

/// Fastest jumper a snapshot may hold, m/s: launches are at most `max_launch_speed_mps`
/// (≈ 12 m/s by default) and a ballistic hop lands no faster than it left; ten times that
/// still leaves room for any legitimate launch configuration.
const MAX_JUMPER_SPEED_MPS: f64 = 150.0;
/// Fastest jumper spin a snapshot may hold, rad/s (launch spin is a few rad/s).
const MAX_JUMPER_SPIN_RADPS: f64 = 500.0;
/// How far the jumper's centre may be below the terrain under it, metres (penetration and
/// the heightfield's interpolation between nodes; the centre rests at least a half extent
/// above the ground).
const BELOW_GROUND_M: f64 = 1.0;
/// How far above the terrain the jumper's centre may be, metres (hops reach ≈ 10 m).
const ABOVE_GROUND_M: f64 = 1_000.0;
/// Rounding allowance on the rover's speed limits.
const LIMIT_SLACK: f64 = 1e-6;

fn within(field: &'static str, value: f64, min: f64, max: f64) -> Result<(), ResumeError> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(ResumeError::OutOfRange {
            field,
            value,
            min,
            max,
        })
    }
}

fn norm(v: [f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

impl PhysicsSim {
    /// The state at the end of the last frame (the start state before the first).
    pub fn snapshot(&self) -> SimSnapshot {
        SimSnapshot {
            frames_simulated: self.frame_index,
            jumper: self.jumper.body_state(&self.pw),
            jumper_cycle: self.jumper.snapshot(),
            rover: self.rover.body_state(),
            rover_drive: self.rover.snapshot(),
            altimeter_noise: self.altimeter.noise().clone(),
            imu_noise: self.imu.noise().clone(),
            imu_yaw_error_rad: self.imu.yaw_error_rad(),
        }
    }

    /// Continues from `snapshot` (taken from a simulation of the same world, configuration
    /// and seed): the next frame is frame `frames_simulated`, sim time carries on, and the
    /// jumper keeps its hop (no fresh initial hop). Call on a fresh simulation; on an error
    /// it stays fresh.
    pub fn resume_from(&mut self, snapshot: &SimSnapshot) -> Result<(), ResumeError> {
        if self.frame_index != 0 {
            return Err(ResumeError::AlreadyStarted {
                frames: self.frame_index,
            });
        }
        self.check(snapshot)?;
        // The only step that can fail comes first and changes nothing when it does.
        self.rover.restore(
            &mut self.pw,
            &self.cfg.rover,
            &self.terrain,
            &snapshot.rover,
            &snapshot.rover_drive,
        )?;
        self.jumper.restore(
            &mut self.pw,
            &self.cfg.jumper,
            &snapshot.jumper,
            &snapshot.jumper_cycle,
        );
        self.altimeter
            .restore_noise(snapshot.altimeter_noise.clone());
        self.imu
            .restore(snapshot.imu_noise.clone(), snapshot.imu_yaw_error_rad);
        self.imu_acc = Default::default();
        self.frame_index = snapshot.frames_simulated;
        self.sim_time_s = snapshot.frames_simulated as f64 * self.cfg.frame_period_s;
        self.last = FrameOutputs {
            frame_index: snapshot.frames_simulated.saturating_sub(1),
            sim_time_s: self.sim_time_s,
            jumper: self.jumper.body_state(&self.pw),
            rover: self.rover.body_state(),
            jumper_status: self.jumper.status(),
            rover_status: self.rover.status(),
            ..FrameOutputs::default()
        };
        Ok(())
    }

    /// Refuses a snapshot this world and configuration cannot have produced (the message
    /// checks only say its numbers are finite and its codes known).
    fn check(&self, snapshot: &SimSnapshot) -> Result<(), ResumeError> {
        let jumper = &snapshot.jumper;
        let [x_m, y_m, z_m] = jumper.position_m;
        let [origin_x_m, origin_y_m] = self.terrain.origin_m();
        let [extent_x_m, extent_y_m] = self.terrain.extent_m();
        within("jumper x_m", x_m, origin_x_m, origin_x_m + extent_x_m)?;
        within("jumper y_m", y_m, origin_y_m, origin_y_m + extent_y_m)?;
        let ground_m = self.terrain.height_at(x_m, y_m);
        within(
            "jumper z_m",
            z_m,
            ground_m - BELOW_GROUND_M,
            ground_m + ABOVE_GROUND_M,
        )?;
        within(
            "jumper speed_mps",
            norm(jumper.linear_velocity_mps),
            0.0,
            MAX_JUMPER_SPEED_MPS,
        )?;
        within(
            "jumper spin_radps",
            norm(jumper.angular_velocity_radps),
            0.0,
            MAX_JUMPER_SPIN_RADPS,
        )?;
        let cycle = &snapshot.jumper_cycle;
        let hop_matches = cycle
            .hop
            .is_some_and(|hop| hop.index == cycle.hop_count && cycle.hop_count > 0);
        let idle = cycle.state == crate::frame::HopState::Settled;
        if !(hop_matches || idle && cycle.hop_count == 0 && cycle.hop.is_none()) {
            return Err(ResumeError::HopWithoutRecord {
                state: cycle.state,
                hop_count: cycle.hop_count,
            });
        }
        within(
            "jumper since_landing_s",
            cycle.since_landing_s,
            0.0,
            f64::MAX,
        )?;
        if let Some(hop) = cycle.hop {
            within("jumper flight_time_s", hop.flight_time_s, 0.0, f64::MAX)?;
        }
        let rover_cfg = &self.cfg.rover;
        let drive = &snapshot.rover_drive;
        let max_speed_mps = rover_cfg.max_speed_mps + LIMIT_SLACK;
        let max_yaw_rate_radps = rover_cfg.max_yaw_rate_radps + LIMIT_SLACK;
        within(
            "rover forward_speed_mps",
            drive.forward_speed_mps,
            -max_speed_mps,
            max_speed_mps,
        )?;
        within(
            "rover yaw_rate_radps",
            drive.yaw_rate_radps,
            -max_yaw_rate_radps,
            max_yaw_rate_radps,
        )?;
        if let Some(command) = drive.command {
            within(
                "rover command speed_mps",
                command.speed_mps,
                0.0,
                max_speed_mps,
            )?;
        }
        Ok(())
    }
}
