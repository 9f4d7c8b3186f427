//! Per-cell traversability belief: is something in this cell taller than the rover can
//! climb? Fixed size per cell, updated point by point, cloud by cloud.
//!
//! Two estimates, after elevation_mapping and OctoMap:
//!
//! - **The top**: the tallest thing in the cell above the local ground, with its variance.
//!   Points from `top_band_sigmas` below the current top to `gate_sigmas` above it (a
//!   Mahalanobis gate) are fused (inverse-variance, as a Kalman update); points further below
//!   are flanks or ground and leave it alone; points far above it start a candidate top that
//!   replaces the current one only once a second point confirms it, so one outlier cannot
//!   raise a cell.
//! - **The log-odds** that the cell holds something the rover cannot climb. Each cloud casts
//!   at most one vote per cell: a hit when one of its points may stand above the climb limit
//!   and the top, with that point fused, stands above it (its estimate minus `hit_sigmas` of
//!   its sigma above the limit less `hit_margin_m`), a miss when its points there are all
//!   confidently below the limit, or when one of its rays passes through the cell
//!   below the cell's claimed top (the claimed rock would have hidden what the ray saw). A hit
//!   in the same cloud overrides a miss. Votes are clamped, so a cell can always be cleared.
//!
//! The class follows the log-odds with hysteresis: lethal from `lethal_enter` up, back only
//! below `lethal_exit`; a cell with some evidence of a tall thing, or a top that straddles the
//! limit, is uncertain (a finite cost that a closer look settles).
//!
//! ```
//! use hopnav_mapper::belief::{BeliefClass, BeliefParams, CellBelief};
//! let params = BeliefParams::new(0.2);
//! let mut cell = CellBelief::default();
//! // Two clouds each see a 0.30 m rock top (σ 2 cm): lethal.
//! for cloud in 1..=2 {
//!     cell.add_point(&params, cloud, 0.30, 0.02);
//! }
//! assert_eq!(cell.class(&params), BeliefClass::Lethal);
//! // A 0.18 m rock, well measured, stays traversable.
//! let mut low = CellBelief::default();
//! for cloud in 1..=5 {
//!     low.add_point(&params, cloud, 0.18, 0.005);
//! }
//! assert_eq!(low.class(&params), BeliefClass::Traversable);
//! ```

use serde::{Deserialize, Serialize};

/// The knobs of the belief, in the units the cells use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeliefParams {
    /// The rover's climb limit, metres.
    pub climb_limit_m: f32,
    /// A point is confidently below the limit (a miss), and a top straddles it (uncertain),
    /// within this many sigmas.
    pub confidence_sigmas: f32,
    /// A cloud's hit needs the fused top this many of its sigmas above `climb_limit_m −
    /// hit_margin_m`.
    pub hit_sigmas: f32,
    /// How far below the climb limit a top already counts as too tall, metres: features sit
    /// on a rock's corners and flanks rather than its apex, so its fused top reads low.
    pub hit_margin_m: f32,
    /// Mahalanobis gate of the top estimate, sigmas: a point this far above the top starts a
    /// candidate top.
    pub gate_sigmas: f32,
    /// Points at most this many sigmas below the top are fused into it; lower ones are the
    /// thing's flanks or the ground beside it (so the top tracks the tallest cluster, not the
    /// mean of a dome).
    pub top_band_sigmas: f32,
    /// Log-odds added by a hit (OctoMap: +0.85).
    pub hit: f32,
    /// Log-odds added by a miss (OctoMap: −0.4).
    pub miss: f32,
    /// Clamps of the log-odds (OctoMap: [−2, 3.5]).
    pub min_log_odds: f32,
    /// See `min_log_odds`.
    pub max_log_odds: f32,
    /// A cell becomes lethal at this log-odds…
    pub lethal_enter: f32,
    /// … and stops being lethal below this one.
    pub lethal_exit: f32,
    /// When set, a point votes a hit only if it stands this many of its own sigmas above
    /// `climb_limit_m − hit_margin_m`, whatever the fused top says: for clouds whose errors
    /// are shared by all their points (the jumper's pose drift tilts or lifts a whole cloud),
    /// fusing many points shrinks the top's sigma below the truth.
    pub point_hit_sigmas: Option<f32>,
    /// The points' heights are fused into the cell's top (off for such clouds too: their
    /// shared errors would make a confident top of noise, and every cell they saw a
    /// maybe-rock).
    pub fuse_top: bool,
    /// A fitted rock is lethal when its height plus this many of its sigmas stands above the
    /// climb limit (see [`crate::traversability::BeliefLayer::judge_rock`]).
    pub rock_lethal_sigmas: f32,
}

impl BeliefParams {
    /// OctoMap's votes and clamps; lethal after two clean hits, cleared after a few misses.
    pub fn new(climb_limit_m: f64) -> Self {
        Self {
            climb_limit_m: climb_limit_m as f32,
            confidence_sigmas: 2.0,
            hit_sigmas: 0.5,
            hit_margin_m: 0.03,
            gate_sigmas: 3.0,
            top_band_sigmas: 1.0,
            hit: 0.85,
            miss: -0.4,
            min_log_odds: -2.0,
            max_log_odds: 3.5,
            lethal_enter: 1.5,
            lethal_exit: 0.5,
            point_hit_sigmas: None,
            fuse_top: true,
            rock_lethal_sigmas: -1.0,
        }
    }
}

/// What the belief says of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeliefClass {
    /// No point fell in it.
    Unknown,
    /// Observed, and nothing in it is taller than the rover can climb.
    Traversable,
    /// Maybe taller than the limit: a finite cost the rover's closer look settles.
    Uncertain,
    /// Taller than the rover can climb, with confidence.
    Lethal,
}

/// The belief of one cell. `Copy`, 64 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CellBelief {
    /// Estimate of the tallest thing above the local ground, metres (valid if `top_count > 0`).
    pub top_m: f32,
    /// Its variance, m².
    pub top_var_m2: f32,
    /// A higher top waiting for a second point, metres (valid if `pending_count > 0`).
    pub pending_m: f32,
    /// Its variance, m².
    pub pending_var_m2: f32,
    /// Log-odds that the cell holds something the rover cannot climb.
    pub log_odds: f32,
    /// The last cloud that voted here.
    pub last_cloud: u32,
    /// Points fused into the top (saturating).
    pub top_count: u16,
    /// Points behind the pending top (0 or 1).
    pub pending_count: u8,
    /// That cloud's vote: −1 miss, +1 hit, 0 none.
    pub last_vote: i8,
    /// Lethal now (the hysteresis state).
    pub lethal: bool,
    /// Any point fell here.
    pub observed: bool,
    /// The last vote on the cell was a ray passing under its claimed top (a hit resets it).
    pub ray_cleared: bool,
    /// Corner of the box holding the cell's points at least half the climb limit tall, world
    /// metres (empty while `extent_min_m > extent_max_m`): where in the cell the thing
    /// stands, so its margin is measured from it, not from the whole cell.
    pub extent_min_m: [f32; 2],
    /// The opposite corner.
    pub extent_max_m: [f32; 2],
    /// Sum of the horizontal unit vectors from the camera to the cell's tall points (rover
    /// clouds): which way the unseen back of the thing lies.
    pub view_sum: [f32; 2],
    /// The ground's elevation under the cell, from the rover's points on it.
    pub ground: GroundElevation,
}

/// A cell's ground elevation: the inverse-variance weighted mean of the ground heights under
/// the rover's points in it (its stereo's local ground, which a rock does not lift).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct GroundElevation {
    /// Sum of weight × world z of the ground, metres.
    weighted_z_sum: f32,
    /// Sum of the weights (1/σ², 1/m²).
    weight_sum: f32,
}

impl GroundElevation {
    /// Adds the ground at world height `ground_z_m` measured with one-sigma `sigma_m` (> 0);
    /// non-finite values are ignored.
    pub fn add(&mut self, ground_z_m: f32, sigma_m: f32) {
        if !(ground_z_m.is_finite() && sigma_m.is_finite() && sigma_m > 0.0) {
            return;
        }
        let weight = 1.0 / (sigma_m * sigma_m);
        self.weighted_z_sum += weight * ground_z_m;
        self.weight_sum += weight;
    }

    /// The mean elevation, metres (`None` before any ground was seen).
    pub fn z_m(&self) -> Option<f32> {
        (self.weight_sum > 0.0).then(|| self.weighted_z_sum / self.weight_sum)
    }
}

impl Default for CellBelief {
    fn default() -> Self {
        Self {
            top_m: 0.0,
            top_var_m2: 0.0,
            pending_m: 0.0,
            pending_var_m2: 0.0,
            log_odds: 0.0,
            last_cloud: 0,
            top_count: 0,
            pending_count: 0,
            last_vote: 0,
            lethal: false,
            observed: false,
            ray_cleared: false,
            extent_min_m: [f32::INFINITY; 2],
            extent_max_m: [f32::NEG_INFINITY; 2],
            view_sum: [0.0; 2],
            ground: GroundElevation::default(),
        }
    }
}

impl CellBelief {
    /// Adds a point of cloud `cloud` standing `height_m` above the local ground with a
    /// one-sigma height uncertainty of `sigma_m` (> 0; smaller values are raised to 1 mm).
    pub fn add_point(&mut self, params: &BeliefParams, cloud: u32, height_m: f32, sigma_m: f32) {
        if !(height_m.is_finite() && sigma_m.is_finite()) {
            return;
        }
        let sigma_m = sigma_m.max(1e-3);
        self.observed = true;
        if params.fuse_top {
            self.fuse_top(params, height_m, sigma_m * sigma_m);
        }
        let margin_m = params.confidence_sigmas * sigma_m;
        let hit_above_m = params.climb_limit_m - params.hit_margin_m;
        let top_confident = match params.point_hit_sigmas {
            Some(sigmas) => height_m - sigmas * sigma_m > hit_above_m,
            None => self.top_m - params.hit_sigmas * self.top_sigma_m() > hit_above_m,
        };
        if height_m + margin_m < params.climb_limit_m {
            self.vote(params, cloud, -1);
        } else if top_confident {
            // The point may stand above the limit, and the top it helped fuse confidently
            // does: many points of one rock pin its height down better than any one of them.
            self.vote(params, cloud, 1);
            self.ray_cleared = false;
        }
        self.update_class(params);
    }

    /// A ray of cloud `cloud` passed through the cell `ray_height_m` above its local ground:
    /// a miss if that is below the claimed top (or below the climb limit when the cell holds
    /// evidence of a tall thing but no top yet). True when it counted.
    pub fn add_ray(&mut self, params: &BeliefParams, cloud: u32, ray_height_m: f32) -> bool {
        if !ray_height_m.is_finite() || self.log_odds <= 0.0 && !self.claims_tall(params) {
            return false;
        }
        let claimed_m = if self.top_count > 0 {
            self.top_m.max(params.climb_limit_m)
        } else {
            params.climb_limit_m
        };
        if ray_height_m >= claimed_m {
            return false;
        }
        self.vote(params, cloud, -1);
        self.ray_cleared = self.last_vote < 0;
        self.update_class(params);
        true
    }

    /// The class the belief gives the cell now.
    pub fn class(&self, params: &BeliefParams) -> BeliefClass {
        if self.lethal {
            BeliefClass::Lethal
        } else if !self.observed {
            BeliefClass::Unknown
        } else if self.log_odds > 0.0 || self.top_straddles(params) {
            BeliefClass::Uncertain
        } else {
            BeliefClass::Traversable
        }
    }

    /// Grows the extent by a point at `xy_m` (world metres) that stands at least half the
    /// climb limit tall.
    pub fn extend(&mut self, xy_m: [f32; 2]) {
        if xy_m.iter().all(|v| v.is_finite()) {
            for (axis, value) in xy_m.into_iter().enumerate() {
                self.extent_min_m[axis] = self.extent_min_m[axis].min(value);
                self.extent_max_m[axis] = self.extent_max_m[axis].max(value);
            }
        }
    }

    /// Adds the horizontal direction `from camera to a tall point` (normalized here; a zero
    /// or non-finite one is ignored).
    pub fn add_view(&mut self, direction: [f32; 2]) {
        let length = direction[0].hypot(direction[1]);
        if length.is_finite() && length > 1e-6 {
            self.view_sum[0] += direction[0] / length;
            self.view_sum[1] += direction[1] / length;
        }
    }

    /// The mean viewing direction of the tall points, a unit vector (`None` without one).
    pub fn view_direction(&self) -> Option<[f32; 2]> {
        let length = self.view_sum[0].hypot(self.view_sum[1]);
        (length.is_finite() && length > 1e-6)
            .then(|| [self.view_sum[0] / length, self.view_sum[1] / length])
    }

    /// The box of the cell's tall points, `None` while empty.
    pub fn extent_m(&self) -> Option<([f32; 2], [f32; 2])> {
        (self.extent_min_m[0] <= self.extent_max_m[0]
            && self.extent_min_m[1] <= self.extent_max_m[1])
            .then_some((self.extent_min_m, self.extent_max_m))
    }

    /// One-sigma uncertainty of the top, metres (infinite without one).
    pub fn top_sigma_m(&self) -> f32 {
        if self.top_count > 0 {
            self.top_var_m2.sqrt()
        } else {
            f32::INFINITY
        }
    }

    /// The top estimate stands above the limit (a tall thing is claimed here).
    fn claims_tall(&self, params: &BeliefParams) -> bool {
        self.top_count > 0 && self.top_m > params.climb_limit_m
    }

    /// The top's confidence interval contains the limit, and the top itself stands at least
    /// half the limit tall: ground seen through a wide sigma (the jumper's, from tens of
    /// metres up) is ground, not a maybe-rock, or everything the jumper sees would cost.
    fn top_straddles(&self, params: &BeliefParams) -> bool {
        self.top_count > 0
            && self.top_m >= 0.5 * params.climb_limit_m
            && self.top_m + params.confidence_sigmas * self.top_sigma_m() > params.climb_limit_m
    }

    fn fuse_top(&mut self, params: &BeliefParams, height_m: f32, var_m2: f32) {
        if self.top_count == 0 {
            (self.top_m, self.top_var_m2, self.top_count) = (height_m, var_m2, 1);
            return;
        }
        let distance = (height_m - self.top_m) / (self.top_var_m2 + var_m2).sqrt();
        if (-params.top_band_sigmas..=params.gate_sigmas).contains(&distance) {
            (self.top_m, self.top_var_m2) = fuse(self.top_m, self.top_var_m2, height_m, var_m2);
            self.top_count = self.top_count.saturating_add(1);
        } else if distance > params.gate_sigmas {
            self.fuse_pending(params, height_m, var_m2);
        }
        // Far below the top: a flank or the ground beside the tall thing.
    }

    /// A point far above the top: it starts a candidate, or confirms one (the top then jumps
    /// to it).
    fn fuse_pending(&mut self, params: &BeliefParams, height_m: f32, var_m2: f32) {
        if self.pending_count > 0 {
            let distance = (height_m - self.pending_m) / (self.pending_var_m2 + var_m2).sqrt();
            if distance.abs() <= params.gate_sigmas {
                let (top_m, top_var_m2) =
                    fuse(self.pending_m, self.pending_var_m2, height_m, var_m2);
                (self.top_m, self.top_var_m2, self.top_count) = (top_m, top_var_m2, 2);
                self.pending_count = 0;
                return;
            }
            if height_m < self.pending_m {
                // A lower candidate is the more cautious one to keep waiting on.
                return;
            }
        }
        (self.pending_m, self.pending_var_m2, self.pending_count) = (height_m, var_m2, 1);
    }

    /// Casts cloud `cloud`'s vote (`+1` hit, `−1` miss): one per cloud, a hit wins.
    fn vote(&mut self, params: &BeliefParams, cloud: u32, vote: i8) {
        let delta = |vote: i8| match vote {
            1 => params.hit,
            -1 => params.miss,
            _ => 0.0,
        };
        if self.last_cloud == cloud && self.last_vote != 0 {
            if vote <= self.last_vote {
                return;
            }
            // A hit after a miss in the same cloud: the miss is taken back.
            self.log_odds -= delta(self.last_vote);
        }
        self.log_odds =
            (self.log_odds + delta(vote)).clamp(params.min_log_odds, params.max_log_odds);
        self.last_cloud = cloud;
        self.last_vote = vote;
    }

    fn update_class(&mut self, params: &BeliefParams) {
        self.lethal = if self.lethal {
            self.log_odds >= params.lethal_exit
        } else {
            self.log_odds >= params.lethal_enter
        };
    }
}

/// Inverse-variance fusion of two estimates.
fn fuse(a_m: f32, a_var_m2: f32, b_m: f32, b_var_m2: f32) -> (f32, f32) {
    let total = a_var_m2 + b_var_m2;
    if total <= 0.0 {
        return (a_m.max(b_m), 0.0);
    }
    (
        (a_m * b_var_m2 + b_m * a_var_m2) / total,
        a_var_m2 * b_var_m2 / total,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> BeliefParams {
        BeliefParams::new(0.2)
    }

    #[test]
    fn a_rock_taller_than_the_limit_is_lethal_after_two_clouds_not_one() {
        let p = params();
        let mut cell = CellBelief::default();
        for _ in 0..20 {
            cell.add_point(&p, 1, 0.26, 0.02);
        }
        assert_eq!(
            cell.class(&p),
            BeliefClass::Uncertain,
            "one cloud is one vote"
        );
        cell.add_point(&p, 2, 0.27, 0.02);
        assert_eq!(cell.class(&p), BeliefClass::Lethal);
        assert!((cell.top_m - 0.26).abs() < 0.01, "{}", cell.top_m);
    }

    #[test]
    fn a_climbable_rock_measured_well_stays_traversable() {
        let p = params();
        let mut cell = CellBelief::default();
        for cloud in 1..=10 {
            cell.add_point(&p, cloud, 0.17, 0.01);
            cell.add_point(&p, cloud, 0.02, 0.01);
        }
        assert_eq!(cell.class(&p), BeliefClass::Traversable);
    }

    #[test]
    fn a_noisy_point_near_the_limit_makes_the_cell_uncertain_not_lethal() {
        let p = params();
        let mut cell = CellBelief::default();
        cell.add_point(&p, 1, 0.19, 0.05);
        assert_eq!(cell.class(&p), BeliefClass::Uncertain);
    }

    #[test]
    fn one_high_outlier_does_not_raise_the_top_but_two_agreeing_points_do() {
        let p = params();
        let mut cell = CellBelief::default();
        for _ in 0..5 {
            cell.add_point(&p, 1, 0.05, 0.01);
        }
        cell.add_point(&p, 1, 0.9, 0.01);
        assert!(cell.top_m < 0.1, "outlier raised the top to {}", cell.top_m);
        cell.add_point(&p, 2, 0.91, 0.01);
        assert!((cell.top_m - 0.905).abs() < 0.01, "{}", cell.top_m);
    }

    #[test]
    fn rays_below_the_claimed_top_clear_a_false_rock() {
        let p = params();
        let mut cell = CellBelief::default();
        // Two misplaced clouds draw a 0.5 m rock.
        cell.add_point(&p, 1, 0.5, 0.05);
        cell.add_point(&p, 2, 0.5, 0.05);
        assert_eq!(cell.class(&p), BeliefClass::Lethal);
        // Rover rays pass 0.3 m above the ground there, cloud after cloud.
        let mut cloud = 3;
        while cell.class(&p) == BeliefClass::Lethal {
            assert!(cell.add_ray(&p, cloud, 0.3));
            cloud += 1;
            assert!(cloud < 10, "never cleared");
        }
        assert!(cloud <= 7, "cleared after {} rays", cloud - 3);
        // A ray above the claimed top says nothing.
        assert!(!cell.add_ray(&p, 99, 0.8));
    }

    #[test]
    fn a_true_rock_under_alternating_evidence_does_not_flip_every_frame() {
        let p = params();
        let mut cell = CellBelief::default();
        let mut classes = Vec::new();
        for cloud in 1..=40u32 {
            if cloud % 2 == 0 {
                cell.add_point(&p, cloud, 0.35, 0.02);
            } else {
                cell.add_ray(&p, cloud, 0.1);
            }
            classes.push(cell.class(&p));
        }
        let flips = classes.windows(2).filter(|pair| pair[0] != pair[1]).count();
        assert!(flips <= 2, "{flips} flips: {classes:?}");
        assert_eq!(classes.last(), Some(&BeliefClass::Lethal));
    }

    #[test]
    fn the_log_odds_stay_clamped_so_a_cell_can_always_be_cleared() {
        let p = params();
        let mut cell = CellBelief::default();
        for cloud in 1..=1000 {
            cell.add_point(&p, cloud, 1.0, 0.01);
        }
        assert_eq!(cell.log_odds, p.max_log_odds);
        let mut cloud = 2000;
        while cell.class(&p) == BeliefClass::Lethal {
            cell.add_ray(&p, cloud, 0.05);
            cloud += 1;
        }
        assert!(cloud - 2000 <= 8);
    }

    #[test]
    fn non_finite_input_changes_nothing() {
        let p = params();
        let mut cell = CellBelief::default();
        cell.add_point(&p, 1, f32::NAN, 0.01);
        cell.add_point(&p, 1, 0.3, f32::INFINITY);
        assert!(!cell.add_ray(&p, 1, f32::NAN));
        assert_eq!(cell, CellBelief::default());
    }

    #[test]
    fn a_hit_in_the_same_cloud_takes_back_its_miss() {
        let p = params();
        let mut cell = CellBelief::default();
        cell.add_point(&p, 1, 0.3, 0.01);
        cell.add_point(&p, 2, 0.02, 0.01);
        cell.add_point(&p, 2, 0.3, 0.01);
        assert!((cell.log_odds - 2.0 * p.hit).abs() < 1e-6);
    }
}
