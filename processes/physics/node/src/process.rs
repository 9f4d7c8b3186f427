//! The `physics` process: stage 0 of every frame. It applies the latest drive command and
//! jump request, steps rapier for one frame, and publishes ground truth, the altimeter and the
//! IMU.

use hopnav_config::{ConfigError, HopnavConfig, parse_section};
use hopnav_ipc::messages::{self as msg, FrameTick, Pose3, SampleStamp};
use hopnav_ipc::node_error::NodeError;
use hopnav_ipc::process_loop::{Prepared, Process, ProcessContext, ProcessIdentity, take_prepared};
use hopnav_ipc::topics;
use hopnav_ipc::transport::{Publisher, Subscriber};
use hopnav_world::World;

use hopnav_physics::frame::{DriveCommand, FrameInputs, HopRequest};
use hopnav_physics::wire::{self, body_state};
use hopnav_physics::{PhysicsConfig, PhysicsError, PhysicsSim};

/// Why the physics process failed: the shared node plumbing, or building the simulation.
pub type PhysicsProcessError = NodeError<BuildError>;

/// Why the simulation could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The world could not be generated.
    #[error("world: {0}")]
    World(#[from] hopnav_world::WorldError),
    /// The simulation could not be built.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
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
    // The rover-only baseline keeps the jumper on the ground.
    if config.mission.mode == hopnav_config::MissionMode::RoverOnly {
        physics.jumper.initial_hop = false;
    }
    physics.validate().map_err(|error| match error {
        hopnav_physics::ConfigError::OutOfRange {
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
    hop_launches: Publisher<msg::HopLaunch>,
    hops_announced: u32,
    altimeter: Publisher<msg::AltimeterSample>,
    imu: Publisher<msg::ImuSample>,
    altimeter_sigma_m: f64,
    last_jump_request: Option<u64>,
    /// What a restarted physics resumes from, published every frame.
    state: Publisher<msg::PhysicsState>,
    /// A restarted incarnation: the supervisor's relay of the last state the previous one
    /// published, read once at the first step.
    resume: Option<Subscriber<msg::PhysicsState>>,
    /// Resume samples refused (by the message checks or as a state this simulation cannot
    /// continue from), counted with the rejected inputs.
    resume_rejected: u64,
}

fn seconds_to_ns(seconds: f64) -> u64 {
    (seconds.max(0.0) * 1e9).round() as u64
}

impl PhysicsProcess {
    /// Publishes what the jumper commanded when a new hop launched this frame: its launch
    /// attitude and velocity, and for the first hop the mission's known start point (for
    /// every hop with `physics.jumper.oracle_launch_position`).
    fn announce_hop(
        &mut self,
        outputs: &hopnav_physics::FrameOutputs,
        stamp: SampleStamp,
    ) -> Result<(), PhysicsProcessError> {
        let status = &outputs.jumper_status;
        let Some(hop) = status.current_hop else {
            return Ok(());
        };
        if status.hop_count <= self.hops_announced {
            return Ok(());
        }
        self.hops_announced = status.hop_count;
        let (sin_heading, cos_heading) = (hop.heading_rad / 2.0).sin_cos();
        let (sin_pitch, cos_pitch) = (-hop.launch_angle_rad / 2.0).sin_cos();
        // yaw(heading) · pitch(−angle): the attitude physics sets before the launch impulse.
        let orientation_xyzw = [
            -sin_heading * sin_pitch,
            cos_heading * sin_pitch,
            cos_pitch * sin_heading,
            cos_heading * cos_pitch,
        ];
        let (sin_angle, cos_angle) = hop.launch_angle_rad.sin_cos();
        let speed = hop.launch_speed_mps;
        let launch_time_ns = seconds_to_ns(outputs.sim_time_s - hop.flight_time_s);
        // The first hop starts at the mission's known point A; the oracle tells every hop's.
        let position_known = hop.index == 1 || self.sim.config().jumper.oracle_launch_position;
        self.hop_launches.send_with(|launch| {
            launch.stamp = stamp;
            launch.world_from_body = Pose3 {
                position_m: if position_known {
                    hop.launch_position_m
                } else {
                    [0.0; 3]
                },
                orientation_xyzw,
            };
            launch.velocity_mps = [
                speed * cos_angle * hop.heading_rad.cos(),
                speed * cos_angle * hop.heading_rad.sin(),
                speed * sin_angle,
            ];
            launch.launch_time_ns = launch_time_ns;
            launch.hop_index = hop.index;
            launch.position_known = u32::from(position_known);
        })?;
        Ok(())
    }
}

impl PhysicsProcess {
    /// A restarted incarnation continues the simulation from the last state the previous one
    /// published; without a usable one it says why and starts over (a fresh simulation is
    /// always a valid state, only a lossy one).
    fn resume(&mut self, resume: &Subscriber<msg::PhysicsState>) {
        let received = resume.receive_latest();
        self.resume_rejected = resume.rejected().total();
        let sample = match received {
            Ok(Some(sample)) => sample,
            Ok(None) if self.resume_rejected > 0 => {
                eprintln!(
                    "physics: rejected {} resume sample(s) that failed the message checks \
                     (corrupt or out of range); the simulation starts over at t = 0",
                    self.resume_rejected
                );
                return;
            }
            Ok(None) => {
                eprintln!(
                    "physics: restarted without a resume sample; the simulation starts over \
                     at t = 0"
                );
                return;
            }
            Err(error) => {
                eprintln!("physics: resume sample: {error}; the simulation starts over at t = 0");
                return;
            }
        };
        let period_s = self.sim.config().frame_period_s;
        let resumed = wire::resume_state(&sample, period_s)
            .map_err(|error| error.to_string())
            .and_then(|resume| {
                self.sim
                    .resume_from(&resume.snapshot)
                    .map_err(|error| error.to_string())
                    .map(|()| resume.last_jump_request)
            });
        match resumed {
            Ok(last_jump_request) => {
                self.last_jump_request = last_jump_request;
                self.hops_announced = self.sim.hop_count();
                eprintln!(
                    "physics: resumed at frame {} (t = {:.1} s, hop {}) from the last state \
                     published",
                    self.sim.frame_count(),
                    self.sim.sim_time_s(),
                    self.sim.hop_count()
                );
            }
            Err(error) => {
                self.resume_rejected += 1;
                eprintln!(
                    "physics: cannot resume from the last state published: {error}; the \
                     simulation starts over at t = 0"
                );
            }
        }
    }
}

/// The simulation at its start state and the altimeter's sigma, from the configuration file.
fn build_sim(config_path: &std::path::Path) -> Result<(PhysicsSim, f64), PhysicsProcessError> {
    let config = hopnav_config::load_file(config_path)?;
    let world_config: hopnav_world::WorldConfig = parse_section(&config, "world")?;
    let world = World::generate(&world_config).map_err(NodeError::own)?;
    let physics = physics_section(&config)?;
    let sim = PhysicsSim::new(&world, &physics, world_config.seed).map_err(NodeError::own)?;
    Ok((sim, physics.altimeter.sigma_m))
}

impl Process for PhysicsProcess {
    type Error = PhysicsProcessError;

    /// The world and the rapier scene built from it: the slow part of the start-up, which
    /// depends on the configuration only (a warm standby does it ahead).
    fn prepare(identity: &ProcessIdentity) -> Result<Prepared, PhysicsProcessError> {
        Ok(Prepared::new(build_sim(&identity.config_path)?))
    }

    fn new(context: &ProcessContext) -> Result<Self, PhysicsProcessError> {
        let (sim, altimeter_sigma_m) = match take_prepared::<(PhysicsSim, f64)>() {
            Some(prepared) => prepared,
            None => build_sim(&context.identity.config_path)?,
        };
        let node = &context.node;
        Ok(Self {
            altimeter_sigma_m,
            sim,
            drive_commands: Subscriber::open(node, &topics::DRIVE_COMMAND)?,
            jump_requests: Subscriber::open(node, &topics::JUMP_REQUEST)?,
            body_states: Publisher::open(node, &topics::BODY_STATES)?,
            hop_launches: Publisher::open(node, &topics::HOP_LAUNCH)?,
            hops_announced: 0,
            altimeter: Publisher::open(node, &topics::ALTIMETER)?,
            imu: Publisher::open(node, &topics::IMU)?,
            last_jump_request: None,
            state: Publisher::open(node, &topics::PHYSICS_STATE)?,
            resume: if context.identity.incarnation > 0 {
                Some(Subscriber::open(node, &topics::RESUME_PHYSICS_STATE)?)
            } else {
                None
            },
            resume_rejected: 0,
        })
    }

    fn step(
        &mut self,
        _context: &ProcessContext,
        tick: &FrameTick,
    ) -> Result<(), PhysicsProcessError> {
        if let Some(resume) = self.resume.take() {
            self.resume(&resume);
        }
        let mut inputs = FrameInputs::default();
        if let Some(command) = self.drive_commands.receive_latest()? {
            inputs.drive = Some(DriveCommand {
                waypoint_xy_m: [command.waypoint_x_m, command.waypoint_y_m],
                speed_mps: command.speed_mps,
                hold: command.hold != 0,
                reverse: command.direction == msg::DriveDirection::Reverse.code(),
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
        // The state is the one at the end of the frame's substeps: stamp that instant.
        let stamp = SampleStamp {
            frame_index: tick.stamp.frame_index,
            sim_time_ns: seconds_to_ns(outputs.sim_time_s),
            ..SampleStamp::default()
        };
        self.announce_hop(&outputs, stamp)?;
        let rover_collisions = self.sim.rover_collisions();
        self.body_states.send_with(|states| {
            states.stamp = stamp;
            states.jumper = body_state(&outputs.jumper, 0);
            states.rover = body_state(&outputs.rover, rover_collisions);
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
        let state = wire::physics_state(&self.sim.snapshot(), self.last_jump_request);
        self.state.send_with(|sample| {
            *sample = state;
            sample.stamp = stamp;
        })?;
        Ok(())
    }

    fn rejected_samples(&self) -> u64 {
        self.drive_commands.rejected().total()
            + self.jump_requests.rejected().total()
            + self.resume_rejected
    }
}
