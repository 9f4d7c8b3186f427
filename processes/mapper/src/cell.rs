//! Fixed-size statistics of one map cell: however many features a cell receives, it keeps the
//! same few counters and a handful of extreme points, never a list that grows.
//!
//! Two kinds of features arrive. Those with a measured `height_above_ground_m` (the rover's
//! stereo cloud) are counted against the traversable height right away. Those without (NaN:
//! a monocular cloud without a ground plane) keep their absolute position; the cell keeps the
//! [`HIGH_POINTS`] highest of them and the map classifies them later against a ground plane
//! fitted to the neighbourhood's lowest observations ([`LOW_POINTS`] per cell, every feature
//! contributing its ground point).

use serde::{Deserialize, Serialize};

/// Lowest ground observations kept per cell.
pub const LOW_POINTS: usize = 4;
/// Highest features of unknown height kept per cell.
pub const HIGH_POINTS: usize = 6;
/// Robot codes that have their own counter (codes 0..ROBOT_SLOTS).
pub const ROBOT_SLOTS: usize = 4;

/// The jumper's robot code (its clouds vote per cell).
const JUMPER_CODE: u32 = 1;

/// A world position in metres, single precision (as in the feature messages).
pub type PointM = [f32; 3];

/// Statistics of the features that fell into one cell. `Copy`, fixed size (~170 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CellStats {
    /// Accepted features (saturating).
    pub count: u32,
    /// Accepted features per robot code (saturating).
    pub count_by_robot: [u32; ROBOT_SLOTS],
    /// Bit set of robot codes that observed the cell (bit = 1 << code).
    pub observed_by: u32,
    /// Features with a measured height above ground.
    pub measured_count: u32,
    /// Measured features higher than the traversable height.
    pub measured_high: u32,
    /// Of them, the jumper's (whose clouds must also agree, see [`CellStats::vote`]).
    pub jumper_measured_high: u32,
    /// Measured features from the jumper (high or not).
    pub jumper_measured_count: u32,
    /// Smallest measured height above ground, metres (valid if `measured_count > 0`).
    pub min_height_m: f32,
    /// Largest measured height above ground, metres (valid if `measured_count > 0`).
    pub max_height_m: f32,
    /// Sum of measured heights above ground, metres (for the mean).
    pub sum_height_m: f64,
    /// Lowest absolute feature z, metres (valid if `count > 0`).
    pub min_z_m: f32,
    /// Highest absolute feature z, metres (valid if `count > 0`).
    pub max_z_m: f32,
    /// Lowest ground points, ascending z; the first `low_len` are valid.
    pub low: [PointM; LOW_POINTS],
    /// Valid entries of `low`.
    pub low_len: u8,
    /// Highest features of unknown height, descending z; the first `high_len` are valid.
    pub high: [PointM; HIGH_POINTS],
    /// Valid entries of `high`.
    pub high_len: u8,
    /// Features of unknown height judged at insertion against the cell's last ground plane.
    pub provisional_count: u32,
    /// Of those, the ones above the traversable height.
    pub provisional_high: u32,
    /// Jumper clouds that judged a feature in this cell (saturating).
    pub judged_clouds: u16,
    /// Of them, the clouds that found a feature here high.
    pub high_clouds: u16,
    /// Sequence number of the last cloud that judged a feature here.
    pub last_cloud: u32,
    /// That cloud already found a feature here high.
    pub last_cloud_high: bool,
}

impl Default for CellStats {
    fn default() -> Self {
        Self {
            count: 0,
            count_by_robot: [0; ROBOT_SLOTS],
            observed_by: 0,
            measured_count: 0,
            measured_high: 0,
            jumper_measured_high: 0,
            jumper_measured_count: 0,
            min_height_m: 0.0,
            max_height_m: 0.0,
            sum_height_m: 0.0,
            min_z_m: 0.0,
            max_z_m: 0.0,
            low: [[0.0; 3]; LOW_POINTS],
            low_len: 0,
            high: [[0.0; 3]; HIGH_POINTS],
            high_len: 0,
            provisional_count: 0,
            provisional_high: 0,
            judged_clouds: 0,
            high_clouds: 0,
            last_cloud: 0,
            last_cloud_high: false,
        }
    }
}

/// Inserts `point` into the sorted prefix `list[..*len]`, keeping the `list.len()` points that
/// come first in the order `before` (a strict "comes before" on z).
fn insert_extreme(list: &mut [PointM], len: &mut u8, point: PointM, before: fn(f32, f32) -> bool) {
    let used = usize::from(*len).min(list.len());
    let position = list[..used]
        .iter()
        .position(|kept| before(point[2], kept[2]))
        .unwrap_or(used);
    if position >= list.len() {
        return;
    }
    let last = (used + 1).min(list.len());
    list.copy_within(position..last - 1, position + 1);
    list[position] = point;
    *len = last as u8;
}

impl CellStats {
    /// Records a feature at `position_m` seen by robot `robot_code`.
    ///
    /// `height_above_ground_m` is the producer's measured height (finite) or `None`;
    /// `traversable_height_m` is the obstacle threshold. The caller has checked that the
    /// numbers are finite.
    pub fn add(
        &mut self,
        position_m: PointM,
        height_above_ground_m: Option<f32>,
        robot_code: u32,
        traversable_height_m: f32,
    ) {
        let z = position_m[2];
        widen(&mut self.min_z_m, &mut self.max_z_m, z, self.count == 0);
        self.count = self.count.saturating_add(1);
        if let Some(slot) = self.count_by_robot.get_mut(robot_code as usize) {
            *slot = slot.saturating_add(1);
        }
        if robot_code < 32 {
            self.observed_by |= 1 << robot_code;
        }
        match height_above_ground_m {
            Some(height) => {
                widen(
                    &mut self.min_height_m,
                    &mut self.max_height_m,
                    height,
                    self.measured_count == 0,
                );
                self.measured_count = self.measured_count.saturating_add(1);
                if robot_code == JUMPER_CODE {
                    self.jumper_measured_count = self.jumper_measured_count.saturating_add(1);
                }
                self.sum_height_m += f64::from(height);
                if height > traversable_height_m {
                    self.measured_high = self.measured_high.saturating_add(1);
                    if robot_code == JUMPER_CODE {
                        self.jumper_measured_high = self.jumper_measured_high.saturating_add(1);
                    }
                }
                let ground = [position_m[0], position_m[1], z - height];
                insert_extreme(&mut self.low, &mut self.low_len, ground, |a, b| a < b);
            }
            None => {
                insert_extreme(&mut self.low, &mut self.low_len, position_m, |a, b| a < b);
                insert_extreme(&mut self.high, &mut self.high_len, position_m, |a, b| a > b);
            }
        }
    }

    /// Records the verdict on a feature of unknown height judged against a known ground.
    pub fn add_provisional(&mut self, is_high: bool) {
        self.provisional_count = self.provisional_count.saturating_add(1);
        if is_high {
            self.provisional_high = self.provisional_high.saturating_add(1);
        }
    }

    /// Records that cloud number `cloud` judged a feature in this cell, high or not: a cloud
    /// counts once however many of its features fall here. A distorted cloud (a keyframe pair
    /// with a wrong relative pose) reads bare ground as high everywhere it looks; clouds that
    /// saw the same cell as ground outvote it.
    pub fn vote(&mut self, cloud: u32, is_high: bool) {
        if self.judged_clouds == 0 || cloud != self.last_cloud {
            self.judged_clouds = self.judged_clouds.saturating_add(1);
            self.last_cloud = cloud;
            self.last_cloud_high = false;
        }
        if is_high && !self.last_cloud_high {
            self.high_clouds = self.high_clouds.saturating_add(1);
            self.last_cloud_high = true;
        }
    }

    /// Fraction of the judged features (measured or provisional) above the traversable
    /// height, `None` with fewer than `min_judged` of them. Without `count_jumper` the
    /// jumper's measured features are left out of both counts: where its high features do not
    /// count, its ground features must not dilute the rover's evidence either (seen from
    /// metres up, a 0.25 m rock's top is not high by two of its height sigmas).
    pub fn high_fraction(&self, min_judged: u32, count_jumper: bool) -> Option<f64> {
        let (jumper_judged, jumper_high) = if count_jumper {
            (0, 0)
        } else {
            (
                self.jumper_measured_count.min(self.measured_count),
                self.jumper_measured_high.min(self.measured_high),
            )
        };
        let judged =
            u64::from(self.measured_count - jumper_judged) + u64::from(self.provisional_count);
        let high = u64::from(self.measured_high - jumper_high) + u64::from(self.provisional_high);
        (judged >= u64::from(min_judged) && judged > 0).then(|| high as f64 / judged as f64)
    }

    /// Mean measured height above ground, metres (`None` without measured features).
    pub fn mean_height_m(&self) -> Option<f64> {
        (self.measured_count > 0).then(|| self.sum_height_m / f64::from(self.measured_count))
    }

    /// The kept lowest ground points.
    pub fn low_points(&self) -> &[PointM] {
        &self.low[..usize::from(self.low_len).min(LOW_POINTS)]
    }

    /// The kept highest features of unknown height.
    pub fn high_points(&self) -> &[PointM] {
        &self.high[..usize::from(self.high_len).min(HIGH_POINTS)]
    }
}

/// Widens the range `[min, max]` to hold `value`; the `first` value sets both ends.
fn widen(min: &mut f32, max: &mut f32, value: f32, first: bool) {
    if first {
        *min = value;
        *max = value;
    } else {
        *min = min.min(value);
        *max = max.max(value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_only_the_extremes() {
        let mut cell = CellStats::default();
        for i in 0..100 {
            let z = ((i * 37) % 100) as f32 * 0.01;
            cell.add([0.0, 0.0, z], None, 1, 0.3);
        }
        assert_eq!(cell.count, 100);
        let low: Vec<i32> = cell
            .low_points()
            .iter()
            .map(|p| (p[2] * 100.0).round() as i32)
            .collect();
        let high: Vec<i32> = cell
            .high_points()
            .iter()
            .map(|p| (p[2] * 100.0).round() as i32)
            .collect();
        assert_eq!(low, vec![0, 1, 2, 3]);
        assert_eq!(high, vec![99, 98, 97, 96, 95, 94]);
        assert_eq!(cell.count_by_robot[1], 100);
        assert_eq!(cell.observed_by, 1 << 1);
    }

    #[test]
    fn each_cloud_votes_once_per_cell() {
        let mut cell = CellStats::default();
        cell.vote(7, true);
        cell.vote(7, true);
        cell.vote(7, false);
        cell.vote(8, false);
        cell.vote(9, false);
        cell.vote(9, true);
        assert_eq!((cell.judged_clouds, cell.high_clouds), (3, 2));
    }

    #[test]
    fn measured_heights_count_against_the_threshold() {
        let mut cell = CellStats::default();
        cell.add([0.0, 0.0, 2.5], Some(0.5), 2, 0.3);
        cell.add([0.0, 0.0, 2.1], Some(0.1), 2, 0.3);
        assert_eq!((cell.measured_count, cell.measured_high), (2, 1));
        assert!((cell.low_points()[0][2] - 2.0).abs() < 1e-6);
        assert!((cell.mean_height_m().unwrap() - 0.3).abs() < 1e-6);
        assert!(cell.high_points().is_empty());
    }
}
