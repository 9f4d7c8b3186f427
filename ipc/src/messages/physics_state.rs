//! physics → its own next incarnation (relayed by the supervisor): everything a restarted
//! physics needs to resume the simulation instead of starting it over, in one sample (two
//! samples could come from different frames if physics dies between sending them).

use iceoryx2::prelude::ZeroCopySend;

use super::{BodyState, SampleStamp, Vec3, coded_enum};

coded_enum! {
    /// Phase of the jumper's hop cycle.
    HopPhase {
        /// At rest; ready to hop.
        Settled = 0,
        /// Launched, not yet touched the ground.
        InFlight = 1,
        /// Touched the ground, still moving.
        Landing = 2,
    }
}

coded_enum! {
    /// Why the rover's last move was refused.
    BlockCode {
        /// Not blocked.
        None = 0,
        /// A rock it cannot climb.
        Rock = 1,
        /// The move would tilt it too far.
        Slope = 2,
        /// A wheel would leave the terrain.
        Boundary = 3,
    }
}

/// The jumper's hop cycle. Flags are 0 or 1.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::JumperCycle")]
pub struct JumperCycle {
    /// A [`HopPhase`] code.
    pub phase: u32,
    /// Hops launched so far; the hop fields below describe hop number `hop_count`.
    pub hop_count: u32,
    /// 1 once the body has left the ground in the current hop.
    pub airborne: u32,
    /// Consecutive slow frames since landing.
    pub settle_frames: u32,
    /// Time since the first ground contact of the current hop, seconds.
    pub since_landing_s: f64,
    /// Heading of the last launch (or the start yaw), radians.
    pub yaw_rad: f64,
    /// 1 when a hop request waits for the jumper to settle.
    pub has_pending_target: u32,
    /// 1 when the current hop was requested toward `hop_target_m` (not the initial hop).
    pub hop_has_target: u32,
    /// Target of the waiting request, world (x, y), metres.
    pub pending_target_m: [f64; 2],
    /// Requested target of the current hop, world (x, y), metres.
    pub hop_target_m: [f64; 2],
    /// Launch speed of the current hop, m/s.
    pub launch_speed_mps: f64,
    /// Launch elevation of the current hop, radians.
    pub launch_angle_rad: f64,
    /// Launch heading of the current hop, radians.
    pub heading_rad: f64,
    /// Body centre at launch, world metres.
    pub launch_position_m: Vec3,
    /// Body centre at the first ground contact, world metres (when `has_landed`).
    pub landing_position_m: Vec3,
    /// 1 once the current hop touched the ground.
    pub has_landed: u32,
    /// 1 when the current hop's launch parameters were clamped to the limits.
    pub clamped: u32,
    /// Highest centre z above the launch centre z so far, metres.
    pub apex_height_m: f64,
    /// Time from launch to first contact (so far, while in flight), seconds.
    pub flight_time_s: f64,
}

/// The rover's controller. Flags are 0 or 1.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::RoverDrive")]
pub struct RoverDrive {
    /// Wheel-contact centre (x, y), world metres (the body origin sits above it, tilted).
    pub xy_m: [f64; 2],
    /// Heading, radians.
    pub yaw_rad: f64,
    /// Current forward speed, m/s.
    pub forward_speed_mps: f64,
    /// Current yaw rate, rad/s.
    pub yaw_rate_radps: f64,
    /// Steering angle of each wheel (FL, FR, RL, RR), radians.
    pub steer_angles_rad: [f64; 4],
    /// Pose (x, y, yaw) at which the current rock contact began (when `in_rock_contact`).
    pub rock_contact: Vec3,
    /// The drive command in force (when `has_command`): waypoint (x, y), metres.
    pub command_waypoint_m: [f64; 2],
    /// Its speed, m/s.
    pub command_speed_mps: f64,
    /// 1 when a drive command is in force.
    pub has_command: u32,
    /// 1 when the command says hold.
    pub command_hold: u32,
    /// 1 when the command says drive rear first.
    pub command_reverse: u32,
    /// 1 once the rover arrived at the command's waypoint.
    pub arrived: u32,
    /// 1 while turning on the spot.
    pub turning: u32,
    /// 1 during a rock contact episode.
    pub in_rock_contact: u32,
    /// A [`BlockCode`].
    pub blocked: u32,
    /// Collisions with rocks it cannot climb so far.
    pub collisions: u32,
}

/// The state of one seeded noise generator (xoshiro256** words and the cached second
/// Box–Muller sample), so a restarted sensor continues its noise sequence.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::NoiseState")]
pub struct NoiseState {
    /// Generator words; never all zero.
    pub words: [u64; 4],
    /// The cached sample (when `has_spare`).
    pub spare: f64,
    /// 1 when `spare` holds a cached sample.
    pub has_spare: u32,
    /// Padding, 0.
    pub reserved: u32,
}

/// physics' own state at the end of a frame: both bodies (as in
/// [`BodyStates`](super::BodyStates)) and the bookkeeping behind them. Published every frame;
/// only a restarted physics reads it (through the supervisor's relay).
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::PhysicsState")]
pub struct PhysicsState {
    /// Frame identity and timing: the same as the [`BodyStates`](super::BodyStates) of this
    /// frame (`sim_time_ns` is `frames_simulated` frame periods).
    pub stamp: SampleStamp,
    /// Frames simulated so far (sim time = frames × frame period).
    pub frames_simulated: u64,
    /// Id of the last jump request taken (when `has_jump_request`).
    pub last_jump_request_id: u64,
    /// 1 when a jump request was taken.
    pub has_jump_request: u32,
    /// Padding, 0.
    pub reserved: u32,
    /// The jumper's pose, velocities and contact.
    pub jumper_body: BodyState,
    /// The rover's pose, velocities and contact (`collisions` as in `rover.collisions`).
    pub rover_body: BodyState,
    /// The jumper's hop cycle.
    pub jumper: JumperCycle,
    /// The rover's controller.
    pub rover: RoverDrive,
    /// The altimeter's noise generator.
    pub altimeter_noise: NoiseState,
    /// The IMU's noise generator.
    pub imu_noise: NoiseState,
    /// The IMU attitude's accumulated yaw error, radians.
    pub imu_yaw_error_rad: f64,
}

const _: () = assert!(size_of::<JumperCycle>() == 168);
const _: () = assert!(size_of::<RoverDrive>() == 152);
const _: () = assert!(size_of::<NoiseState>() == 48);
const _: () = assert!(size_of::<PhysicsState>() == 704);
