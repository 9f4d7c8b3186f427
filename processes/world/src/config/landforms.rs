//! Landforms that give a scout something to find: cul-de-sacs, a scarp and a corridor field
//! between the scenario's start A and goal B (see [`landforms`](crate::landforms)). Each is
//! off by default; each needs `scenario.start_m` and `scenario.goal_m`.

use serde::{Deserialize, Serialize};

use super::{
    Interval, TerrainConfig, check_int, dotted_key, inconsistent, min_max_pair, rock_sizes,
};
use crate::error::ConfigError;
use crate::landforms::corridor_field::MAX_FIELD_BOULDERS;

/// All landforms of the world.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LandformConfig {
    /// U-shaped boulder walls opening toward A.
    pub cul_de_sacs: CulDeSacConfig,
    /// A step in the ground across A–B, too steep to drive, with ramps far off the line.
    pub scarp: ScarpConfig,
    /// A band of dense boulders across A–B with a few clear corridors.
    pub corridor_field: CorridorFieldConfig,
}

impl LandformConfig {
    /// Checks the values under `prefix`, and that the corridor field's lattice over the
    /// `terrain` stays within [`MAX_FIELD_BOULDERS`].
    pub fn validate(&self, prefix: &str, terrain: &TerrainConfig) -> Result<(), ConfigError> {
        self.cul_de_sacs
            .validate(&dotted_key(prefix, "cul_de_sacs"))?;
        self.scarp.validate(&dotted_key(prefix, "scarp"))?;
        let field_prefix = dotted_key(prefix, "corridor_field");
        self.corridor_field.validate(&field_prefix)?;
        let field = &self.corridor_field;
        if field.depth_m > 0.0 {
            let span_m = terrain.size_x_m.hypot(terrain.size_y_m);
            let lattice =
                (field.depth_m / field.spacing_m + 1.0) * (span_m / field.spacing_m + 1.0);
            if lattice > MAX_FIELD_BOULDERS as f64 {
                return Err(inconsistent(
                    &field_prefix,
                    "spacing_m",
                    format!(
                        "places about {lattice:.0} boulders over this terrain; at most {MAX_FIELD_BOULDERS} are allowed (a wider spacing or a shallower field)"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The boulders a wall is built of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WallBoulders {
    /// Smallest boulder diameter, metres.
    pub diameter_min_m: f64,
    /// Largest boulder diameter, metres.
    pub diameter_max_m: f64,
    /// Boulder height over diameter.
    pub height_ratio: f64,
}

impl Default for WallBoulders {
    fn default() -> Self {
        Self {
            diameter_min_m: 0.9,
            diameter_max_m: 1.4,
            height_ratio: 0.6,
        }
    }
}

impl WallBoulders {
    fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        rock_sizes(
            prefix,
            0.2,
            [self.diameter_min_m, self.diameter_max_m],
            self.height_ratio,
        )
    }
}

/// Cul-de-sacs: U-shaped walls of touching boulders, `depth` long arms toward A and a back
/// wall `width` wide; from A the rover sees into the mouth but not whether the back is
/// closed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CulDeSacConfig {
    /// Cul-de-sacs to place (0 = none).
    pub count: u32,
    /// Shortest arm, metres.
    pub depth_min_m: f64,
    /// Longest arm, metres.
    pub depth_max_m: f64,
    /// Narrowest mouth (between the arms' centre lines), metres.
    pub width_min_m: f64,
    /// Widest mouth, metres.
    pub width_max_m: f64,
    /// Their centre lines lie up to this far to either side of the A–B line, metres.
    pub lateral_spread_m: f64,
    /// The walls' boulders.
    pub boulders: WallBoulders,
}

impl Default for CulDeSacConfig {
    fn default() -> Self {
        Self {
            count: 0,
            depth_min_m: 10.0,
            depth_max_m: 20.0,
            width_min_m: 8.0,
            width_max_m: 14.0,
            lateral_spread_m: 3.0,
            boulders: WallBoulders::default(),
        }
    }
}

impl CulDeSacConfig {
    fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        check_int(prefix, "count", u64::from(self.count), 0, 20)?;
        min_max_pair(
            prefix,
            ("depth_min_m", self.depth_min_m),
            ("depth_max_m", self.depth_max_m),
            Interval::closed(1.0, 200.0),
        )?;
        min_max_pair(
            prefix,
            ("width_min_m", self.width_min_m),
            ("width_max_m", self.width_max_m),
            Interval::closed(2.0, 200.0),
        )?;
        Interval::closed(0.0, 500.0).check(prefix, "lateral_spread_m", self.lateral_spread_m)?;
        self.boulders.validate(&dotted_key(prefix, "boulders"))
    }
}

/// A scarp: the ground beyond a line across A–B stands `height_m` higher or lower, the step
/// too steep for the rover except on ramps (gaps) placed at least `gap_offset_min_m` to the
/// side of the A–B line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ScarpConfig {
    /// Height of the step, metres (0 = no scarp); whether the far side is higher or lower
    /// follows the seed.
    pub height_m: f64,
    /// Horizontal width of the steep face, metres.
    pub face_width_m: f64,
    /// Where the scarp crosses A–B, as a fraction of the way from A.
    pub at_fraction: f64,
    /// Amplitude of the scarp line's sideways meander, metres.
    pub meander_m: f64,
    /// Ramps through the face.
    pub gap_count: u32,
    /// Width of a ramp's drivable core, metres.
    pub gap_width_m: f64,
    /// Horizontal length of a ramp, metres (its slope is about `1.5 · height / length`).
    pub ramp_length_m: f64,
    /// A ramp's centre lies at least this far to the side of the A–B line, metres.
    pub gap_offset_min_m: f64,
    /// And at most this far.
    pub gap_offset_max_m: f64,
}

impl Default for ScarpConfig {
    fn default() -> Self {
        Self {
            height_m: 0.0,
            face_width_m: 0.5,
            at_fraction: 0.5,
            meander_m: 2.0,
            gap_count: 1,
            gap_width_m: 5.0,
            ramp_length_m: 10.0,
            gap_offset_min_m: 12.0,
            gap_offset_max_m: 24.0,
        }
    }
}

impl ScarpConfig {
    fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(0.0, 20.0).check(prefix, "height_m", self.height_m)?;
        Interval::left_open(0.0, 20.0).check(prefix, "face_width_m", self.face_width_m)?;
        Interval::closed(0.1, 0.9).check(prefix, "at_fraction", self.at_fraction)?;
        Interval::closed(0.0, 50.0).check(prefix, "meander_m", self.meander_m)?;
        check_int(prefix, "gap_count", u64::from(self.gap_count), 0, 10)?;
        Interval::closed(1.0, 100.0).check(prefix, "gap_width_m", self.gap_width_m)?;
        Interval::closed(1.0, 200.0).check(prefix, "ramp_length_m", self.ramp_length_m)?;
        min_max_pair(
            prefix,
            ("gap_offset_min_m", self.gap_offset_min_m),
            ("gap_offset_max_m", self.gap_offset_max_m),
            Interval::closed(0.0, 1000.0),
        )
    }
}

/// A corridor field: a band `depth_m` deep across A–B (and across the whole terrain) packed
/// with boulders too close for the rover to pass between, crossed by `corridors` clear
/// corridors that bend once, each entering and leaving at least `corridor_offset_min_m` to
/// the side of the A–B line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CorridorFieldConfig {
    /// Depth of the band along A–B, metres (0 = no field).
    pub depth_m: f64,
    /// Where the band begins, as a fraction of the way from A.
    pub start_fraction: f64,
    /// Boulder lattice spacing, metres (with the boulders' diameters this sets the gaps).
    pub spacing_m: f64,
    /// Clear corridors through the band.
    pub corridors: u32,
    /// Clear width of a corridor, metres.
    pub corridor_width_m: f64,
    /// A corridor's entry, bend and exit lie at least this far to the side of A–B, metres.
    pub corridor_offset_min_m: f64,
    /// And at most this far.
    pub corridor_offset_max_m: f64,
    /// The band's boulders.
    pub boulders: WallBoulders,
}

impl Default for CorridorFieldConfig {
    fn default() -> Self {
        Self {
            depth_m: 0.0,
            start_fraction: 0.4,
            spacing_m: 1.0,
            corridors: 2,
            corridor_width_m: 4.0,
            corridor_offset_min_m: 6.0,
            corridor_offset_max_m: 22.0,
            boulders: WallBoulders {
                diameter_min_m: 0.7,
                diameter_max_m: 1.1,
                height_ratio: 0.6,
            },
        }
    }
}

impl CorridorFieldConfig {
    fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(0.0, 500.0).check(prefix, "depth_m", self.depth_m)?;
        Interval::closed(0.0, 0.95).check(prefix, "start_fraction", self.start_fraction)?;
        Interval::closed(0.3, 10.0).check(prefix, "spacing_m", self.spacing_m)?;
        check_int(prefix, "corridors", u64::from(self.corridors), 0, 10)?;
        Interval::closed(0.5, 50.0).check(prefix, "corridor_width_m", self.corridor_width_m)?;
        min_max_pair(
            prefix,
            ("corridor_offset_min_m", self.corridor_offset_min_m),
            ("corridor_offset_max_m", self.corridor_offset_max_m),
            Interval::closed(0.0, 1000.0),
        )?;
        self.boulders.validate(&dotted_key(prefix, "boulders"))
    }
}
