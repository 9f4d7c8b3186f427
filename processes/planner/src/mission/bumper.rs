//! The virtual bumper: notices from the VO pose alone that the rover ran into something the map
//! does not show, and backs it away.
//!
//! A rover that neither moves nor turns while it is told to drive is against a rock its camera
//! missed (a rock just above the climbable height, or one hidden below the camera's view).
//! Turning counts as progress: a rover turning on the spot toward a new path is not stuck.
//! Over a longer window only distance counts: a rover that turns back and forth on one spot
//! (rocking between two waypoints) is going nowhere, and is treated as stuck too.
//! Once stuck, it backs up rear first, because turning on the spot against a rock would sweep
//! a corner of the chassis into it; the navigator marks the cell ahead as an obstacle. It
//! backs up along its own recent track where it has one (those poses were drivable: straight
//! back from a turn on a slope can tilt it further), else straight behind. When neither way
//! back gets anywhere, it drives straight ahead, nose first: a rover that swung its side into
//! a rock while turning is held by every reverse move, which slides it along or into the
//! rock, but not by driving on (compare seed 7 was held there for 180 s).
//!
//! ```
//! use hopnav_planner::mission::{Bumper, BumperEvent, NavigatorConfig, RoverPose};
//! let mut bumper = Bumper::new(&NavigatorConfig::default());
//! let pose = RoverPose { xy_m: [0.0, 0.0], yaw_rad: 0.0 };
//! let mut event = BumperEvent::Clear;
//! for frame in 0..40 {
//!     event = bumper.observe(pose, frame as f64 * 0.1, true);
//!     if event != BumperEvent::Clear {
//!         break;
//!     }
//! }
//! assert!(matches!(event, BumperEvent::Stuck { .. }));
//! assert!(bumper.back_off_waypoint().unwrap()[0] < 0.0);
//! ```

use super::config::NavigatorConfig;
use super::scout::distance_m;

/// The rover's planar pose as the VO estimates it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoverPose {
    /// Position (x, y), world metres.
    pub xy_m: [f64; 2],
    /// Heading about world z, radians (0 = +x).
    pub yaw_rad: f64,
}

impl RoverPose {
    /// The point `distance_m` ahead along the heading (behind for negative distances).
    pub fn ahead_m(&self, distance_m: f64) -> [f64; 2] {
        let (sin, cos) = self.yaw_rad.sin_cos();
        [
            self.xy_m[0] + distance_m * cos,
            self.xy_m[1] + distance_m * sin,
        ]
    }
}

/// What the bumper concluded this frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BumperEvent {
    /// Moving, turning, or not asked to drive.
    Clear,
    /// Stuck: something is in the way at about `obstacle_m`; backing off has begun.
    Stuck {
        /// Where the obstacle probably is (ahead along the heading, or behind a back-off that
        /// stalled reversing), world metres.
        obstacle_m: [f64; 2],
        /// The direction from the rover toward it, about world z, radians.
        bearing_rad: f64,
    },
    /// Backing off, rear first.
    BackingOff,
}

/// Settings (from `[planner]`).
#[derive(Debug, Clone, Copy, PartialEq)]
struct BumperConfig {
    stall_time_s: f64,
    stall_distance_m: f64,
    stall_yaw_rad: f64,
    no_progress_time_s: f64,
    no_progress_distance_m: f64,
    back_off_m: f64,
    back_off_timeout_s: f64,
    obstacle_reach_m: f64,
    mark_back_off_stalls: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct BackOff {
    from: RoverPose,
    since_s: f64,
    waypoint_m: [f64; 2],
    /// Nose first (the escape after failed back-offs), not rear first.
    forward: bool,
    /// Pose and time of the back-off's last progress.
    progress: (RoverPose, f64),
}

/// Positions of the recent track kept for backing off along it.
const TRAIL_POINTS: usize = 32;
/// Spacing of the kept track positions, metres.
const TRAIL_SPACING_M: f64 = 0.2;

/// Stall detection and the back-off manoeuvre.
#[derive(Debug, Clone, PartialEq)]
pub struct Bumper {
    config: BumperConfig,
    /// Pose and time of the last progress.
    anchor: Option<(RoverPose, f64)>,
    /// Position and time of the last progress in distance alone.
    distance_anchor: Option<([f64; 2], f64)>,
    backing_off: Option<BackOff>,
    stalls: u32,
    /// Back-offs in a row that timed out without getting anywhere; each new one tries the
    /// other way out (along the track, or straight behind).
    failed_back_offs: u32,
    /// Recent positions, oldest first, `TRAIL_SPACING_M` apart.
    trail: std::collections::VecDeque<[f64; 2]>,
}

impl Bumper {
    /// A bumper with the navigator's stall and back-off settings.
    pub fn new(config: &NavigatorConfig) -> Self {
        Self {
            config: BumperConfig {
                stall_time_s: config.stall_time_s,
                stall_distance_m: config.stall_distance_m,
                stall_yaw_rad: config.stall_yaw_rad,
                no_progress_time_s: config.no_progress_time_s,
                no_progress_distance_m: config.no_progress_distance_m,
                back_off_m: config.back_off_m,
                back_off_timeout_s: config.back_off_timeout_s,
                obstacle_reach_m: config.bump_reach_m,
                mark_back_off_stalls: config.mark_back_off_stalls,
            },
            anchor: None,
            distance_anchor: None,
            backing_off: None,
            stalls: 0,
            failed_back_offs: 0,
            trail: std::collections::VecDeque::with_capacity(TRAIL_POINTS),
        }
    }

    /// Times the rover was found stuck.
    pub fn stalls(&self) -> u32 {
        self.stalls
    }

    /// One frame at `time_s`. `driving`: the rover was told to drive forward (not holding).
    pub fn observe(&mut self, pose: RoverPose, time_s: f64, driving: bool) -> BumperEvent {
        self.extend_trail(pose.xy_m);
        if let Some(mut back_off) = self.backing_off {
            let escaped = distance_m(back_off.from.xy_m, pose.xy_m) >= self.config.back_off_m;
            let timed_out = time_s - back_off.since_s >= self.config.back_off_timeout_s;
            if !escaped && !timed_out {
                if !self.config.mark_back_off_stalls {
                    return BumperEvent::BackingOff;
                }
                let (at, since_s) = back_off.progress;
                if self.progressed(at, pose) {
                    back_off.progress = (pose, time_s);
                    self.backing_off = Some(back_off);
                } else if time_s - since_s >= self.config.stall_time_s {
                    return self.back_off_stalled(back_off, pose, time_s);
                }
                return BumperEvent::BackingOff;
            }
            self.failed_back_offs = if escaped {
                0
            } else {
                self.failed_back_offs + 1
            };
            self.backing_off = None;
            self.anchor = Some((pose, time_s));
        }
        if !driving {
            self.anchor = None;
            self.distance_anchor = None;
            return BumperEvent::Clear;
        }
        if self.going_nowhere(pose.xy_m, time_s) {
            self.stalls += 1;
            return self.start_back_off(pose, time_s);
        }
        let Some((anchor, since_s)) = self.anchor else {
            self.anchor = Some((pose, time_s));
            return BumperEvent::Clear;
        };
        if self.progressed(anchor, pose) {
            self.anchor = Some((pose, time_s));
            return BumperEvent::Clear;
        }
        if time_s - since_s < self.config.stall_time_s {
            return BumperEvent::Clear;
        }
        self.stalls += 1;
        self.start_back_off(pose, time_s)
    }

    /// The rover moved or turned enough since `anchor` to count as progress.
    fn progressed(&self, anchor: RoverPose, pose: RoverPose) -> bool {
        let turned_rad = wrap_angle(pose.yaw_rad - anchor.yaw_rad).abs();
        distance_m(anchor.xy_m, pose.xy_m) > self.config.stall_distance_m
            || turned_rad > self.config.stall_yaw_rad
    }

    /// A back-off stalled: whatever holds the rover lies the way it was driving (behind, rear
    /// first). It failed; the next way out begins now.
    fn back_off_stalled(&mut self, back_off: BackOff, pose: RoverPose, time_s: f64) -> BumperEvent {
        self.failed_back_offs += 1;
        self.stalls += 1;
        self.backing_off = None;
        let bearing_rad = if back_off.forward {
            pose.yaw_rad
        } else {
            wrap_angle(pose.yaw_rad + std::f64::consts::PI)
        };
        self.start_back_off_from(pose, time_s, bearing_rad)
    }

    /// True when the rover, told to drive, has stayed within `no_progress_distance_m` of one
    /// spot for `no_progress_time_s` (the watch then starts over).
    fn going_nowhere(&mut self, xy_m: [f64; 2], time_s: f64) -> bool {
        match self.distance_anchor {
            Some((from_m, since_s))
                if distance_m(from_m, xy_m) < self.config.no_progress_distance_m =>
            {
                let stuck = time_s - since_s >= self.config.no_progress_time_s;
                if stuck {
                    self.distance_anchor = None;
                }
                stuck
            }
            _ => {
                self.distance_anchor = Some((xy_m, time_s));
                false
            }
        }
    }

    /// The rover, driving forward, tilted beyond what is safe at `time_s`: back off now, as
    /// from a stall (a frame already backing off goes on with it).
    pub fn tilted(&mut self, pose: RoverPose, time_s: f64) -> BumperEvent {
        if self.backing_off.is_some() {
            return self.observe(pose, time_s, true);
        }
        self.extend_trail(pose.xy_m);
        self.start_back_off(pose, time_s)
    }

    fn start_back_off(&mut self, pose: RoverPose, time_s: f64) -> BumperEvent {
        self.start_back_off_from(pose, time_s, pose.yaw_rad)
    }

    /// Starts the next way out from a rover held by something toward `bearing_rad`.
    fn start_back_off_from(
        &mut self,
        pose: RoverPose,
        time_s: f64,
        bearing_rad: f64,
    ) -> BumperEvent {
        self.anchor = None;
        let (waypoint_m, forward) = self.back_off_target(pose);
        self.backing_off = Some(BackOff {
            from: pose,
            since_s: time_s,
            waypoint_m,
            forward,
            progress: (pose, time_s),
        });
        let toward = RoverPose {
            xy_m: pose.xy_m,
            yaw_rad: bearing_rad,
        };
        BumperEvent::Stuck {
            obstacle_m: toward.ahead_m(self.config.obstacle_reach_m),
            bearing_rad,
        }
    }

    /// While backing off: where to back up to.
    pub fn back_off_waypoint(&self) -> Option<[f64; 2]> {
        self.backing_off.map(|back_off| back_off.waypoint_m)
    }

    /// While backing off: true when the way out is nose first (see the module notes).
    pub fn backing_off_forward(&self) -> bool {
        self.backing_off.is_some_and(|back_off| back_off.forward)
    }

    fn extend_trail(&mut self, xy_m: [f64; 2]) {
        if self
            .trail
            .back()
            .is_some_and(|&last| distance_m(last, xy_m) < TRAIL_SPACING_M)
        {
            return;
        }
        if self.trail.len() == TRAIL_POINTS {
            self.trail.pop_front();
        }
        self.trail.push_back(xy_m);
    }

    /// Where to back off to, and whether nose first. In turn after failed tries: the newest
    /// track position a little beyond the back-off distance; the point straight behind; the
    /// point straight ahead (each beyond the back-off distance, so the rover does not slow to
    /// a stop before it gets there).
    fn back_off_target(&self, pose: RoverPose) -> ([f64; 2], bool) {
        let beyond_m = self.config.back_off_m + 0.5;
        match self.failed_back_offs % 3 {
            // The track did not lead out last time (a corner swept into a rock): straight.
            1 => (pose.ahead_m(-beyond_m), false),
            // Neither way back did: the rock is at the side or the rear.
            2 => (pose.ahead_m(beyond_m), true),
            _ => {
                let reach_m = self.config.back_off_m + 0.3;
                let along_track_m = self
                    .trail
                    .iter()
                    .rev()
                    .find(|&&point| distance_m(point, pose.xy_m) >= reach_m)
                    .copied()
                    .unwrap_or(pose.ahead_m(-beyond_m));
                (along_track_m, false)
            }
        }
    }
}

/// `angle` in `(−π, π]`.
fn wrap_angle(angle: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let wrapped = angle.rem_euclid(tau);
    if wrapped > std::f64::consts::PI {
        wrapped - tau
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x_m: f64, yaw_rad: f64) -> RoverPose {
        RoverPose {
            xy_m: [x_m, 0.0],
            yaw_rad,
        }
    }

    fn run(bumper: &mut Bumper, frames: usize, at: impl Fn(usize) -> RoverPose) -> BumperEvent {
        let mut last = BumperEvent::Clear;
        for frame in 0..frames {
            last = bumper.observe(at(frame), frame as f64 * 0.1, true);
            if matches!(last, BumperEvent::Stuck { .. }) {
                return last;
            }
        }
        last
    }

    #[test]
    fn turning_on_the_spot_is_progress_not_a_stall() {
        let mut bumper = Bumper::new(&NavigatorConfig::default());
        // Half a turn at 0.3 rad/s takes ~10 s without moving.
        let event = run(&mut bumper, 100, |frame| pose(0.0, frame as f64 * 0.03));
        assert_eq!(event, BumperEvent::Clear);
        assert_eq!(bumper.stalls(), 0);
    }

    #[test]
    fn a_rover_that_neither_moves_nor_turns_is_stuck_and_backs_off_then_resumes() {
        let config = NavigatorConfig::default();
        let mut bumper = Bumper::new(&config);
        let event = run(&mut bumper, 100, |_| pose(2.0, 0.0));
        let BumperEvent::Stuck { obstacle_m, .. } = event else {
            panic!("not stuck: {event:?}");
        };
        assert!(obstacle_m[0] > 2.4 && obstacle_m[0] < 3.0, "{obstacle_m:?}");
        assert_eq!(bumper.stalls(), 1);
        // Backing off until it is back_off_m behind.
        let waypoint = bumper.back_off_waypoint().unwrap();
        assert!(waypoint[0] < 2.0 - config.back_off_m);
        let stuck_s = config.stall_time_s;
        assert_eq!(
            bumper.observe(pose(1.8, 0.0), stuck_s + 0.5, true),
            BumperEvent::BackingOff
        );
        assert_eq!(
            bumper.observe(pose(2.0 - config.back_off_m, 0.0), stuck_s + 1.0, true),
            BumperEvent::Clear
        );
        assert_eq!(bumper.back_off_waypoint(), None);
    }

    #[test]
    fn a_blocked_back_off_gives_up_after_its_timeout() {
        let config = NavigatorConfig::default();
        let mut bumper = Bumper::new(&config);
        let event = run(&mut bumper, 100, |_| pose(0.0, 0.0));
        assert!(matches!(event, BumperEvent::Stuck { .. }));
        // Stuck after stall_time_s (frames from t = 0); the back-off makes no progress either.
        let stuck_s = config.stall_time_s;
        assert_eq!(
            bumper.observe(pose(0.0, 0.0), stuck_s + 0.5, true),
            BumperEvent::BackingOff
        );
        let later_s = stuck_s + config.back_off_timeout_s + 0.2;
        assert_eq!(
            bumper.observe(pose(0.0, 0.0), later_s, true),
            BumperEvent::Clear
        );
    }

    #[test]
    fn a_back_off_that_stalls_reversing_names_the_rock_behind_and_tries_the_next_way_out() {
        let config = NavigatorConfig {
            mark_back_off_stalls: true,
            ..NavigatorConfig::default()
        };
        let mut bumper = Bumper::new(&config);
        let held = pose(0.0, 0.0);
        let event = run(&mut bumper, 100, |_| held);
        let BumperEvent::Stuck { bearing_rad, .. } = event else {
            panic!("not stuck: {event:?}");
        };
        assert_eq!(bearing_rad, 0.0, "the first stall is ahead");
        assert!(!bumper.backing_off_forward());
        // Reversing gets nowhere: after stall_time_s, well before the timeout, the rock behind.
        let stuck_s = config.stall_time_s;
        let mut time_s = stuck_s;
        let mut event = BumperEvent::BackingOff;
        while event == BumperEvent::BackingOff {
            time_s += 0.1;
            event = bumper.observe(held, time_s, true);
        }
        assert!(
            time_s - stuck_s < config.back_off_timeout_s - 1.0,
            "{time_s}"
        );
        let BumperEvent::Stuck {
            obstacle_m,
            bearing_rad,
        } = event
        else {
            panic!("not stuck behind: {event:?}");
        };
        assert!((bearing_rad.abs() - std::f64::consts::PI).abs() < 1e-9);
        assert!(
            obstacle_m[0] < -0.5 && obstacle_m[1].abs() < 1e-9,
            "{obstacle_m:?}"
        );
        assert_eq!(bumper.stalls(), 2);
        assert!(
            bumper.back_off_waypoint().is_some(),
            "the next way out has begun"
        );
    }

    #[test]
    fn a_back_off_that_moves_is_not_a_stall() {
        let config = NavigatorConfig {
            mark_back_off_stalls: true,
            ..NavigatorConfig::default()
        };
        let mut bumper = Bumper::new(&config);
        let event = run(&mut bumper, 100, |_| pose(0.0, 0.0));
        assert!(matches!(event, BumperEvent::Stuck { .. }));
        // Backing up at 10 cm/s (the back-off drives at 0.25 m/s): 0.2 m per stall time.
        let start_s = config.stall_time_s;
        for frame in 1..50 {
            let event = bumper.observe(
                pose(-0.01 * frame as f64, 0.0),
                start_s + 0.1 * frame as f64,
                true,
            );
            assert_eq!(event, BumperEvent::BackingOff, "frame {frame}");
        }
    }

    #[test]
    fn when_neither_way_back_gets_anywhere_it_drives_out_nose_first() {
        let config = NavigatorConfig::default();
        let mut bumper = Bumper::new(&config);
        let held = pose(0.0, 0.0);
        let mut time_s = 0.0;
        let mut ways_out = Vec::new();
        for _ in 0..4 {
            // Stalls, then the back-off times out where it began.
            let mut event = BumperEvent::Clear;
            while !matches!(event, BumperEvent::Stuck { .. }) {
                event = bumper.observe(held, time_s, true);
                time_s += 0.1;
            }
            let waypoint = bumper.back_off_waypoint().unwrap();
            ways_out.push((waypoint[0].signum(), bumper.backing_off_forward()));
            time_s += config.back_off_timeout_s + 0.1;
            assert_eq!(bumper.observe(held, time_s, true), BumperEvent::Clear);
        }
        // Rear first (no track: straight behind), rear first, nose first ahead, then over.
        assert_eq!(
            ways_out,
            [(-1.0, false), (-1.0, false), (1.0, true), (-1.0, false)]
        );
    }

    #[test]
    fn it_backs_off_along_its_own_track_when_it_has_one() {
        let mut bumper = Bumper::new(&NavigatorConfig::default());
        // Drove up along +y, then turned toward +x and got stuck.
        for frame in 0..30 {
            let pose = RoverPose {
                xy_m: [0.0, frame as f64 * 0.05],
                yaw_rad: std::f64::consts::FRAC_PI_2,
            };
            assert_eq!(
                bumper.observe(pose, frame as f64 * 0.1, true),
                BumperEvent::Clear
            );
        }
        let stuck = RoverPose {
            xy_m: [0.0, 1.45],
            yaw_rad: 0.0,
        };
        let event = run(&mut bumper, 100, |_| stuck);
        assert!(matches!(event, BumperEvent::Stuck { .. }));
        let waypoint = bumper.back_off_waypoint().unwrap();
        // Back down the track (−y), not straight behind the new heading (−x).
        assert!(
            waypoint[0].abs() < 1e-9 && waypoint[1] < 1.45 - 0.6,
            "{waypoint:?}"
        );
    }

    #[test]
    fn rocking_on_one_spot_is_stuck_however_much_it_turns() {
        let config = NavigatorConfig::default();
        let mut bumper = Bumper::new(&config);
        // Turning 0.9 rad back and forth every 2 s and creeping 3 cm to and fro: the turns
        // pass the stall check, but the rover never gets anywhere.
        let rocking = |frame: usize| {
            let phase = (frame as f64 * 0.1 * std::f64::consts::PI).sin();
            pose(0.03 * phase, 2.8 + 0.45 * phase)
        };
        let frames = (config.no_progress_time_s * 10.0) as usize + 20;
        let event = run(&mut bumper, frames, rocking);
        assert!(matches!(event, BumperEvent::Stuck { .. }), "{event:?}");
        assert_eq!(bumper.stalls(), 1);
    }

    #[test]
    fn a_slow_drive_with_long_turns_is_not_going_nowhere() {
        let config = NavigatorConfig::default();
        let mut bumper = Bumper::new(&config);
        // 5 cm/s, turning all the while: slow, but 0.5 m every 10 s.
        let event = run(&mut bumper, 600, |frame| {
            pose(frame as f64 * 0.005, frame as f64 * 0.02)
        });
        assert_eq!(event, BumperEvent::Clear);
        assert_eq!(bumper.stalls(), 0);
    }

    #[test]
    fn holding_still_is_not_a_stall() {
        let mut bumper = Bumper::new(&NavigatorConfig::default());
        for frame in 0..200 {
            assert_eq!(
                bumper.observe(pose(0.0, 0.0), frame as f64 * 0.1, false),
                BumperEvent::Clear
            );
        }
    }
}
