//! Per-frame inputs and outputs: plain `Copy` structs, no heap data, so a process can copy
//! them into shared-memory messages without allocation.
//!
//! Frames: world is z up; velocities and angular velocities of [`BodyState`] are in the world
//! frame; IMU quantities are in the rover body frame (x forward, y left, z up).

/// A drive command for the rover; it stays in force until the next one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveCommand {
    /// Waypoint (x, y), world metres.
    pub waypoint_xy_m: [f64; 2],
    /// Requested speed, m/s (clamped to `[0, rover.max_speed_mps]`).
    pub speed_mps: f64,
    /// Stop and stay (the waypoint is ignored).
    pub hold: bool,
    /// Drive rear first toward a waypoint behind the rover (to back away from a rock: turning
    /// on the spot against it would sweep the chassis into it).
    pub reverse: bool,
}

/// A request for the jumper to hop toward a target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HopRequest {
    /// Target (x, y), world metres.
    pub target_xy_m: [f64; 2],
}

/// What arrives for one frame. `None` keeps the previous drive command / asks for no hop.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameInputs {
    /// New drive command for the rover.
    pub drive: Option<DriveCommand>,
    /// Hop request; honoured once the jumper has settled (the latest request wins).
    pub hop_request: Option<HopRequest>,
}

/// Ground-truth state of one body (evaluation only).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyState {
    /// Position of the body origin, world metres.
    pub position_m: [f64; 3],
    /// `world_from_body` rotation as `[x, y, z, w]`.
    pub orientation_xyzw: [f64; 4],
    /// Linear velocity, world frame, m/s.
    pub linear_velocity_mps: [f64; 3],
    /// Angular velocity, world frame, rad/s.
    pub angular_velocity_radps: [f64; 3],
    /// Whether the body touches the ground, a rock or the other robot.
    pub in_contact: bool,
}

/// One barometric altimeter sample of the jumper.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AltimeterSample {
    /// Measured pressure, pascals (from the noisy altitude, then quantised).
    pub pressure_pa: f64,
    /// Measured altitude above the datum, metres (true altitude plus Gaussian noise).
    pub altitude_m: f64,
    /// True altitude of the body centre above the datum, metres (evaluation only).
    pub true_altitude_m: f64,
}

/// One rover IMU sample (mean over the frame's substeps, plus noise).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImuSample {
    /// Reported `world_from_body` attitude `[x, y, z, w]` (noise and yaw drift included).
    pub orientation_xyzw: [f64; 4],
    /// Angular rate, body frame, rad/s.
    pub angular_velocity_body_radps: [f64; 3],
    /// Specific force `Rᵀ·(a − g)`, body frame, m/s² (at rest: `+g` along body z).
    pub specific_force_body_mps2: [f64; 3],
}

/// Phase of the jumper's hop cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HopState {
    /// At rest; ready to hop.
    #[default]
    Settled,
    /// Launched, not yet touched the ground.
    InFlight,
    /// Touched the ground, still moving.
    Landing,
}

/// The record of one hop.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HopRecord {
    /// 1-based hop number.
    pub index: u32,
    /// Requested target (x, y), metres, if the hop was requested (not the initial hop).
    pub target_xy_m: Option<[f64; 2]>,
    /// Launch speed used, m/s.
    pub launch_speed_mps: f64,
    /// Launch elevation angle used, radians.
    pub launch_angle_rad: f64,
    /// Launch heading about world z, radians.
    pub heading_rad: f64,
    /// Whether the launch parameters had to be clamped to the configured limits.
    pub clamped: bool,
    /// Body centre at launch, world metres.
    pub launch_position_m: [f64; 3],
    /// Body centre at the first ground contact, world metres (`None` while in flight).
    pub landing_position_m: Option<[f64; 3]>,
    /// Highest centre z above the launch centre z, metres.
    pub apex_height_m: f64,
    /// Time from launch to first ground contact (so far, while in flight), seconds.
    pub flight_time_s: f64,
}

impl HopRecord {
    /// Horizontal distance from launch to first contact, metres (`None` while in flight).
    pub fn range_m(&self) -> Option<f64> {
        self.landing_position_m.map(|l| {
            let dx = l[0] - self.launch_position_m[0];
            let dy = l[1] - self.launch_position_m[1];
            dx.hypot(dy)
        })
    }
}

/// Jumper status at the end of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JumperStatus {
    /// Current phase.
    pub state: HopState,
    /// Hops launched so far.
    pub hop_count: u32,
    /// The hop in progress, or the last one.
    pub current_hop: Option<HopRecord>,
    /// Target of a request waiting for the jumper to settle.
    pub pending_target_xy_m: Option<[f64; 2]>,
}

/// What the rover controller is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RoverMode {
    /// No command yet.
    #[default]
    Idle,
    /// Holding still on command.
    Holding,
    /// Turning on the spot toward the waypoint.
    Turning,
    /// Driving toward the waypoint.
    Driving,
    /// Backing up, rear first, toward a waypoint behind.
    Reversing,
    /// Within the arrival tolerance of the waypoint.
    Arrived,
}

/// Why the rover could not make its last move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockReason {
    /// A rock taller than `max_climbable_height_m` is in the way (counted as a collision).
    Rock,
    /// The move would tilt the rover beyond `max_tilt_rad`.
    Slope,
    /// A wheel would leave the terrain grid.
    Boundary,
}

/// Rover status at the end of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RoverStatus {
    /// Controller mode.
    pub mode: RoverMode,
    /// Set while the rover is blocked.
    pub blocked: Option<BlockReason>,
    /// Collisions with non-climbable rocks so far (each contact episode counts once).
    pub collision_count: u32,
    /// Steering angle of each wheel (FL, FR, RL, RR), radians, 0 = straight ahead.
    pub steer_angles_rad: [f64; 4],
    /// Speed each wheel is driven at along its rolling direction, m/s (a blocked chassis
    /// spins its wheels: this is not its ground speed).
    pub wheel_speeds_mps: [f64; 4],
    /// Commanded forward speed of the chassis, m/s.
    pub forward_speed_mps: f64,
    /// Commanded yaw rate of the chassis, rad/s.
    pub yaw_rate_radps: f64,
    /// Horizontal distance to the current waypoint, metres (0 without a command).
    pub distance_to_waypoint_m: f64,
}

/// Everything the physics produces for one frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameOutputs {
    /// Index of the frame just simulated (0-based).
    pub frame_index: u64,
    /// Simulated time at the end of the frame, seconds.
    pub sim_time_s: f64,
    /// Jumper ground truth.
    pub jumper: BodyState,
    /// Rover ground truth.
    pub rover: BodyState,
    /// Jumper altimeter.
    pub altimeter: AltimeterSample,
    /// Rover IMU.
    pub imu: ImuSample,
    /// Jumper hop status.
    pub jumper_status: JumperStatus,
    /// Rover controller status.
    pub rover_status: RoverStatus,
    /// Inputs rejected so far (non-finite numbers).
    pub rejected_inputs: u32,
}
