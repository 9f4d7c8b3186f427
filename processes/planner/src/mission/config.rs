//! Settings of the rover's navigation (`[planner]` in the config).

use hopnav_config::range::{Interval, OutOfRange, dotted_key};
use serde::{Deserialize, Serialize};

/// How the rover follows its path and when it gives up.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NavigatorConfig {
    /// The goal counts as reached within this distance, metres.
    pub goal_tolerance_m: f64,
    /// Commanded ground speed, m/s (physics clamps it to the rover's maximum).
    pub cruise_speed_mps: f64,
    /// The waypoint is the first path point at least this far ahead of the rover, metres.
    pub lookahead_m: f64,
    /// The rover's stereo camera maps reliably out to this range, metres.
    pub sensing_range_m: f64,
    /// Extra cost of a move into a cell nobody has mapped, in thousandths of a cell edge (a
    /// straight move costs 1000). Unknown ground stays traversable (D* Lite's optimism); the
    /// premium makes the planner prefer ground a robot has seen free, by up to this fraction
    /// of the path: the jumper's free corridors become routes. 0 plans unknown as free.
    pub unknown_extra_cost: u32,
    /// The rover counts as stuck when, told to drive, it neither moved `stall_distance_m` nor
    /// turned `stall_yaw_rad` in this long; it then backs off and the cell ahead is marked
    /// as an obstacle (a virtual bumper), seconds.
    pub stall_time_s: f64,
    /// See `stall_time_s`, metres.
    pub stall_distance_m: f64,
    /// See `stall_time_s`, radians.
    pub stall_yaw_rad: f64,
    /// The rover also counts as stuck when, told to drive, it got no further than
    /// `no_progress_distance_m` from where it was this long ago, however much it turned: a
    /// rover rocking between two waypoints, or creeping back and forth on one spot, turns
    /// enough to pass the stall check forever (seed 13 spun in place for 245 s), seconds.
    pub no_progress_time_s: f64,
    /// See `no_progress_time_s`, metres.
    pub no_progress_distance_m: f64,
    /// A stuck rover backs up this far, rear first, before it plans again, metres.
    pub back_off_m: f64,
    /// A back-off that makes no progress gives up after this long, seconds.
    pub back_off_timeout_s: f64,
    /// The cell this far ahead of a stuck rover is marked as an obstacle, metres (half the
    /// chassis length plus a little).
    pub bump_reach_m: f64,
    /// Cells whose centre lies within this of a bumped cell's centre are marked with it, so
    /// the next search keeps the rover's body clear of the rock as the mapper's lethal margin
    /// would (a path one cell over brushed the same rock again), metres. 0.75 m marks the
    /// eight neighbours of a 0.5 m cell, a three-cell disc of 0.25 m cells.
    pub bump_ring_m: f64,
    /// A back-off that stalls (neither moving nor turning for `stall_time_s`) has met
    /// something on the side it drives toward: end it then, not at `back_off_timeout_s`, mark
    /// the cell there (behind a reversing rover), and try the next way out. Off, a back-off
    /// pushes against the rock until its timeout and the rock stays unmarked.
    pub mark_back_off_stalls: bool,
    /// Driving on, the rover stops and backs off when its tilt (from the VO attitude, whose
    /// roll and pitch come from the IMU) exceeds this, and the cell ahead is marked: a crater
    /// wall is no obstacle to the mapper (nothing stands above the local ground) but wedges
    /// the rover at its 30° limit, radians.
    pub max_safe_tilt_rad: f64,
    /// When to ask the jumper to scout (cooperative mode only).
    pub scout: ScoutConfig,
    /// Before driving to a waypoint, sweep the rover's oriented footprint along the straight
    /// drive against the cells the mapper calls rocks (not their lethal margins), and take a
    /// nearer waypoint of the path when the body would touch one: the centre's lethal margin
    /// covers only the inscribed circle, the band beyond it depends on the heading.
    pub footprint_check: bool,
    /// The rover's body, from `[physics.rover]` (not a `[planner]` key).
    #[serde(skip)]
    pub rover_body: hopnav_robot::RoverBody,
}

impl Default for NavigatorConfig {
    fn default() -> Self {
        Self {
            goal_tolerance_m: 0.75,
            cruise_speed_mps: 0.5,
            lookahead_m: 1.5,
            sensing_range_m: 8.0,
            unknown_extra_cost: 0,
            stall_time_s: 2.0,
            stall_distance_m: 0.1,
            stall_yaw_rad: 0.1,
            no_progress_time_s: 15.0,
            no_progress_distance_m: 0.5,
            back_off_m: 0.6,
            back_off_timeout_s: 5.0,
            bump_reach_m: 0.8,
            bump_ring_m: 0.75,
            mark_back_off_stalls: false,
            max_safe_tilt_rad: 22f64.to_radians(),
            scout: ScoutConfig::default(),
            footprint_check: true,
            rover_body: hopnav_robot::RoverBody::default(),
        }
    }
}

/// The cooperative rule's knobs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ScoutConfig {
    /// Ask for hops at all (the mission mode switches it off for rover-only runs).
    pub enabled: bool,
    /// Hop target: this far along the path from the jumper, at most, metres (the default
    /// Table-1 hop flies 23.3 m; the rear camera maps the ground it flies over).
    pub hop_range_m: f64,
    /// Hops shorter than this are not worth a request, metres.
    pub min_hop_m: f64,
    /// Wait at least this long between requests (flight ≈ 4.7 s, then landing and settling),
    /// and after the mission start (the jumper's first hop launches at start), seconds.
    pub min_interval_s: f64,
    /// Most hops the rover may ask for in one mission. At 8, a dense field used them all on
    /// the first corridor and the rover chose its detour blind (seed 17 of `hopnav compare`
    /// failed); at 20 it reached the goal.
    pub max_requests: u32,
}

impl Default for ScoutConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            hop_range_m: 20.0,
            min_hop_m: 6.0,
            min_interval_s: 10.0,
            max_requests: 20,
        }
    }
}

/// The table the planner's keys live in.
const TABLE: &str = "planner";

/// A key (relative to `[planner]`), its value and the allowed closed range.
type RangeCheck = (&'static str, f64, f64, f64);

/// The first check whose value is not finite or is outside its range; the error names
/// `planner.<key>` and states the range as `low..=high`.
fn first_out_of_range(checks: &[RangeCheck]) -> Result<(), OutOfRange> {
    for &(key, value, low, high) in checks {
        if !Interval::closed(low, high).contains(value) {
            return Err(OutOfRange {
                key: dotted_key(TABLE, key),
                value: value.to_string(),
                range: format!("{low}..={high}"),
            });
        }
    }
    Ok(())
}

impl NavigatorConfig {
    /// Checks every value; the error names the key (`planner.<key>`) and its range.
    pub fn validate(&self) -> Result<(), OutOfRange> {
        first_out_of_range(&self.stuck_checks())?;
        first_out_of_range(&self.driving_checks())?;
        first_out_of_range(&self.scout_checks())?;
        if self.scout.min_hop_m > self.scout.hop_range_m {
            return Err(OutOfRange {
                key: dotted_key(TABLE, "scout.min_hop_m"),
                value: self.scout.min_hop_m.to_string(),
                range: "at most scout.hop_range_m".into(),
            });
        }
        Ok(())
    }

    /// The stall, no-progress, back-off, bump and tilt limits.
    fn stuck_checks(&self) -> [RangeCheck; 10] {
        [
            ("stall_time_s", self.stall_time_s, 0.5, 600.0),
            ("no_progress_time_s", self.no_progress_time_s, 1.0, 3600.0),
            (
                "no_progress_distance_m",
                self.no_progress_distance_m,
                0.01,
                10.0,
            ),
            ("stall_yaw_rad", self.stall_yaw_rad, 0.001, 3.0),
            ("back_off_m", self.back_off_m, 0.0, 10.0),
            ("back_off_timeout_s", self.back_off_timeout_s, 0.1, 600.0),
            ("bump_reach_m", self.bump_reach_m, 0.1, 10.0),
            ("bump_ring_m", self.bump_ring_m, 0.0, 5.0),
            ("max_safe_tilt_rad", self.max_safe_tilt_rad, 0.05, 1.5),
            ("stall_distance_m", self.stall_distance_m, 0.01, 10.0),
        ]
    }

    /// Goal, speed, lookahead, sensing and the unknown-cell premium.
    fn driving_checks(&self) -> [RangeCheck; 5] {
        [
            ("goal_tolerance_m", self.goal_tolerance_m, 0.05, 20.0),
            ("cruise_speed_mps", self.cruise_speed_mps, 0.01, 10.0),
            ("lookahead_m", self.lookahead_m, 0.1, 20.0),
            ("sensing_range_m", self.sensing_range_m, 0.5, 100.0),
            (
                "unknown_extra_cost",
                f64::from(self.unknown_extra_cost),
                0.0,
                100_000.0,
            ),
        ]
    }

    /// The cooperative rule (`scout.*`).
    fn scout_checks(&self) -> [RangeCheck; 4] {
        [
            ("scout.hop_range_m", self.scout.hop_range_m, 1.0, 100.0),
            ("scout.min_hop_m", self.scout.min_hop_m, 0.0, 100.0),
            (
                "scout.min_interval_s",
                self.scout.min_interval_s,
                0.0,
                600.0,
            ),
            (
                "scout.max_requests",
                f64::from(self.scout.max_requests),
                0.0,
                1000.0,
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid_and_an_out_of_range_value_names_its_key() {
        let mut config = NavigatorConfig::default();
        assert_eq!(config.validate(), Ok(()));
        config.unknown_extra_cost = 200_000;
        let rejected = config.validate().unwrap_err();
        assert_eq!(
            (
                rejected.key.as_str(),
                rejected.value.as_str(),
                rejected.range.as_str()
            ),
            ("planner.unknown_extra_cost", "200000", "0..=100000")
        );
    }
}
