//! The `physics` process: stage 0 of every frame. It applies the latest drive command and
//! jump request, steps rapier for one frame, and publishes ground truth, the altimeter and the
//! IMU.

use hopnav_config::{ConfigError, HopnavConfig, parse_section};
use hopnav_ipc::messages::{self as msg, FrameTick, Pose3, SampleStamp};
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{Publisher, Subscriber};
use hopnav_world::World;

use crate::frame::{BodyState, DriveCommand, FrameInputs, HopRequest};
use crate::{PhysicsConfig, PhysicsError, PhysicsSim};

/// Why the physics process failed.
#[derive(Debug, thiserror::Error)]
pub enum PhysicsProcessError {
    /// The configuration could not be loaded or is invalid.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The world could not be generated.
    #[error("world: {0}")]
    World(#[from] hopnav_world::WorldError),
    /// The simulation could not be built.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// A port could not be opened.
    #[error(transparent)]
    Open(#[from] hopnav_ipc::transport::OpenError),
    /// A sample could not be sent.
    #[error(transparent)]
    Send(#[from] hopnav_ipc::transport::SendError),
    /// A sample could not be received.
    #[error(transparent)]
    Receive(#[from] hopnav_ipc::transport::ReceiveError),
}

/// Parses and validates `[physics]`: the frame period comes from `run.frame_rate_hz`, and a
/// scenario's start point A (`world.scenario.start_m`) places both robots beside it unless
/// `physics.*.start_xy_m` says otherwise.
pub fn physics_section(config: &HopnavConfig) -> Result<PhysicsConfig, ConfigError> {
    let mut physics: PhysicsConfig = parse_section(config, "physics")?;
    physics.frame_period_s = config.run.frame_period_s();
    let world: hopnav_world::WorldConfig = parse_section(config, "world")?;
    if let Some([start_x_m, start_y_m]) = world.scenario.start_m {
        let set_explicitly = |robot: &str| {
            config
                .sections
                .get("physics")
                .and_then(|physics| physics.get(robot))
                .and_then(|robot| robot.get("start_xy_m"))
                .is_some()
        };
        if !set_explicitly("jumper") {
            physics.jumper.start_xy_m = [start_x_m, start_y_m + SCENARIO_START_OFFSET_M];
        }
        if !set_explicitly("rover") {
            physics.rover.start_xy_m = [start_x_m, start_y_m - SCENARIO_START_OFFSET_M];
        }
    }
    physics.validate().map_err(|error| match error {
        crate::ConfigError::OutOfRange {
            key, value, range, ..
        } => ConfigError::OutOfRange {
            key,
            value,
            allowed: range,
        },
    })?;
    Ok(physics)
}

/// The robots start side by side at a scenario's point A, this far to either side of it.
const SCENARIO_START_OFFSET_M: f64 = 1.5;

/// Steps the simulation once per frame.
pub struct PhysicsProcess {
    sim: PhysicsSim,
    drive_commands: Subscriber<msg::DriveCommand>,
    jump_requests: Subscriber<msg::JumpRequest>,
    body_states: Publisher<msg::BodyStates>,
    altimeter: Publisher<msg::AltimeterSample>,
    imu: Publisher<msg::ImuSample>,
    altimeter_sigma_m: f64,
    last_jump_request: Option<u64>,
}

fn body_state(state: &BodyState) -> msg::BodyState {
    msg::BodyState {
        world_from_body: Pose3 {
            position_m: state.position_m,
            orientation_xyzw: state.orientation_xyzw,
        },
        linear_velocity_mps: state.linear_velocity_mps,
        angular_velocity_radps: state.angular_velocity_radps,
        in_contact: u32::from(state.in_contact),
        reserved: 0,
    }
}

impl Process for PhysicsProcess {
    type Error = PhysicsProcessError;

    fn new(context: &ProcessContext) -> Result<Self, PhysicsProcessError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        let world_config: hopnav_world::WorldConfig = parse_section(&config, "world")?;
        let world = World::generate(&world_config)?;
        let physics = physics_section(&config)?;
        let node = &context.node;
        Ok(Self {
            altimeter_sigma_m: physics.altimeter.sigma_m,
            sim: PhysicsSim::new(&world, &physics, world_config.seed)?,
            drive_commands: Subscriber::open(node, &topics::DRIVE_COMMAND)?,
            jump_requests: Subscriber::open(node, &topics::JUMP_REQUEST)?,
            body_states: Publisher::open(node, &topics::BODY_STATES)?,
            altimeter: Publisher::open(node, &topics::ALTIMETER)?,
            imu: Publisher::open(node, &topics::IMU)?,
            last_jump_request: None,
        })
    }

    fn step(
        &mut self,
        _context: &ProcessContext,
        tick: &FrameTick,
    ) -> Result<(), PhysicsProcessError> {
        let mut inputs = FrameInputs::default();
        if let Some(command) = self.drive_commands.receive_latest()? {
            inputs.drive = Some(DriveCommand {
                waypoint_xy_m: [command.waypoint_x_m, command.waypoint_y_m],
                speed_mps: command.speed_mps,
                hold: command.hold != 0,
            });
        }
        if let Some(request) = self.jump_requests.receive_latest()?
            && self.last_jump_request != Some(request.request_id)
        {
            self.last_jump_request = Some(request.request_id);
            inputs.hop_request = Some(HopRequest {
                target_xy_m: [request.target_m[0], request.target_m[1]],
            });
        }
        let outputs = self.sim.step_frame(&inputs);
        let stamp = SampleStamp {
            frame_index: tick.stamp.frame_index,
            sim_time_ns: tick.stamp.sim_time_ns,
            ..SampleStamp::default()
        };
        self.body_states.send_with(|states| {
            states.stamp = stamp;
            states.jumper = body_state(&outputs.jumper);
            states.rover = body_state(&outputs.rover);
        })?;
        let sigma_m = self.altimeter_sigma_m;
        self.altimeter.send_with(|sample| {
            sample.stamp = stamp;
            sample.pressure_pa = outputs.altimeter.pressure_pa;
            sample.altitude_m = outputs.altimeter.altitude_m;
            sample.altitude_sigma_m = sigma_m;
        })?;
        self.imu.send_with(|sample| {
            sample.stamp = stamp;
            sample.attitude_xyzw = outputs.imu.orientation_xyzw;
            sample.angular_rate_radps = outputs.imu.angular_velocity_body_radps;
            sample.specific_force_mps2 = outputs.imu.specific_force_body_mps2;
        })?;
        Ok(())
    }

    fn rejected_samples(&self) -> u64 {
        self.drive_commands.rejected().total() + self.jump_requests.rejected().total()
    }
}
