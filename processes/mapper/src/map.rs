//! The merged feature map: both robots' clouds aggregated into a fixed grid of fixed-size
//! cell statistics, classified into free / obstacle / inflated, and published as a diff.
//!
//! Per cloud call [`FeatureMap::insert_cloud`]; once per frame [`FeatureMap::update`]
//! reclassifies the cells the new features can affect (their own and, through the local
//! ground, their neighbours') and [`FeatureMap::collect_changes`] returns the cells whose
//! class, extra cost or observers changed since the last collection. Memory is allocated in
//! [`FeatureMap::new`] and does not grow, however long the mission.

use hopnav_ipc::messages::{CellClass, CellUpdate, Robot};
use serde::{Deserialize, Serialize};

use crate::belief::CellBelief;
use crate::cell::{CellStats, LOW_POINTS};
use crate::config::{MapperConfig, ObstacleModel};
use crate::dirty::DirtySet;
use crate::dome_layer::{Changed, DomeLayer};
use crate::geometry::GridGeometry;
use crate::ground::{GroundPlane, GroundScratch};
use crate::inflation::{FootprintCosts, KernelEntry, footprint_costs, kernel_for, kernel_reach};
use crate::slope::SlopeJudge;
use crate::traversability::BeliefLayer;

/// What the map did with the features it was given.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MapCounters {
    /// Features added to a cell.
    pub accepted: u64,
    /// Features with a non-finite position, sigma or an infinite height.
    pub non_finite: u64,
    /// Features outside the grid.
    pub outside_grid: u64,
    /// Features whose measured height is beyond `max_feature_height_m` (either sign).
    pub implausible_height: u64,
    /// Features whose depth sigma exceeds `max_depth_sigma_m`.
    pub uncertain: u64,
    /// Features with a negative depth sigma, or (`traversability` model, which weighs every
    /// point by its sigma) a zero one.
    #[serde(default)]
    pub bad_sigma: u64,
    /// Frame index of the last cloud taken in, per robot (`[jumper, rover]`): a restored
    /// snapshot holds the clouds up to these, so a restarted mapper takes in only later ones
    /// from the cloud topics' history.
    #[serde(default)]
    pub last_cloud_frame: [Option<u64>; 2],
}

/// Published state of one cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellState {
    /// Class.
    pub class: CellClass,
    /// Extra cost of moving into the cell, planner units.
    pub extra_cost: u32,
    /// Bit set of robot codes that observed the cell.
    pub observed_by: u32,
    /// Features supporting the class (high features of an obstacle, all features otherwise).
    pub support: u32,
}

impl Default for CellState {
    fn default() -> Self {
        Self {
            class: CellClass::Unknown,
            extra_cost: 0,
            observed_by: 0,
            support: 0,
        }
    }
}

impl CellState {
    /// Whether the planner would see a difference (support alone does not count).
    fn differs_from(&self, other: &CellState) -> bool {
        self.class != other.class
            || self.extra_cost != other.extra_cost
            || self.observed_by != other.observed_by
    }
}

/// Classification of a cell from its own features, before inflation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Base {
    class: BaseClass,
    support: u32,
    /// Features above the traversable height (measured + estimated).
    high: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum BaseClass {
    #[default]
    Unknown,
    Free,
    /// Maybe taller than the rover can climb (`traversability` model): a finite cost.
    Uncertain,
    Obstacle,
}

/// Classification thresholds in the units the cells use.
#[derive(Debug, Clone, Copy)]
struct Thresholds {
    traversable_height_m: f32,
    max_feature_height_m: f32,
    max_depth_sigma_m: f32,
    jumper_height_sigma_factor: f32,
    rover_height_sigma_factor: f32,
    min_high_clouds: u16,
    min_high_cloud_fraction: f64,
    rover_overrules_jumper_after: u32,
    min_obstacle_support: u32,
    obstacle_min_fraction: f64,
    fraction_min_features: u32,
    min_free_support: u32,
    ground_reach_cells: u32,
    max_cells_per_update: usize,
    uncertain_cost: u32,
    rock_width_prior: f32,
}

/// A point's heights above its local ground, for [`FeatureMap::feed_traversability`].
#[derive(Debug, Clone, Copy)]
struct PointHeights {
    /// As its cloud measured it (`None`: a monocular point of unknown height).
    measured_m: Option<f32>,
    /// What the map judges it by: the measured height, or its height above the fitted ground.
    judged_m: f32,
    /// One-sigma height uncertainty, metres.
    vertical_sigma_m: f32,
}

/// The merged, bounded map of both robots' features.
#[derive(Debug)]
pub struct FeatureMap {
    geometry: GridGeometry,
    thresholds: Thresholds,
    kernel: Vec<KernelEntry>,
    inflation_reach_cells: u32,
    stats: Vec<CellStats>,
    /// The ground plane each cell was last classified with (features of unknown height are
    /// judged against it on arrival).
    ground_cache: Vec<Option<GroundPlane>>,
    base: Vec<Base>,
    state: Vec<CellState>,
    published: Vec<CellState>,
    touched: DirtySet,
    reclassify: DirtySet,
    restate: DirtySet,
    changed: DirtySet,
    /// Cells whose statistics or belief changed since [`Self::refresh_copy`] last copied them
    /// (besides those still in `touched`).
    unsaved: DirtySet,
    /// Every cell is unsaved: nothing copied yet, or the whole map was restored.
    unsaved_whole: bool,
    ground: GroundScratch,
    counters: MapCounters,
    /// Number of the cloud being inserted (cells count each cloud's vote once).
    cloud_sequence: u32,
    /// The `traversability` model's beliefs (`None` under the `features` model).
    beliefs: Option<BeliefLayer>,
    /// The `traversability` model's footprint inflation.
    footprint_costs: Option<FootprintCosts>,
    /// The `traversability` model's rocks fitted as domes (`None` when off).
    domes: Option<DomeLayer>,
    /// The `traversability` model's judge of the ground's slope.
    slope: Option<SlopeJudge>,
}

impl FeatureMap {
    /// An empty map over `geometry` with the thresholds of `config` (validated by the caller).
    pub fn new(config: &MapperConfig, geometry: GridGeometry) -> Self {
        let cells = geometry.cell_count();
        let kernel = kernel_for(config, geometry.cell_size_m);
        let ground_reach_cells = (config.ground_window_m / geometry.cell_size_m)
            .ceil()
            .clamp(1.0, 64.0) as u32;
        let window = (2 * ground_reach_cells as usize + 1).pow(2);
        Self {
            geometry,
            thresholds: Thresholds {
                traversable_height_m: config.traversable_height_m as f32,
                max_feature_height_m: config.max_feature_height_m as f32,
                max_depth_sigma_m: config.max_depth_sigma_m as f32,
                jumper_height_sigma_factor: config.jumper_height_sigma_factor as f32,
                rover_height_sigma_factor: config.rover_height_sigma_factor as f32,
                min_high_clouds: config.min_high_clouds,
                min_high_cloud_fraction: config.min_high_cloud_fraction,
                rover_overrules_jumper_after: config.rover_overrules_jumper_after,
                min_obstacle_support: config.min_obstacle_support,
                obstacle_min_fraction: config.obstacle_min_fraction,
                fraction_min_features: config.fraction_min_features,
                min_free_support: config.min_free_support,
                ground_reach_cells,
                max_cells_per_update: config.max_cells_per_frame.max(1) as usize,
                uncertain_cost: config.uncertain_cost,
                rock_width_prior: config.rock_width_prior as f32,
            },
            inflation_reach_cells: kernel_reach(&kernel),
            kernel,
            stats: vec![CellStats::default(); cells],
            ground_cache: vec![None; cells],
            base: vec![Base::default(); cells],
            state: vec![CellState::default(); cells],
            published: vec![CellState::default(); cells],
            touched: DirtySet::new(cells),
            reclassify: DirtySet::new(cells),
            restate: DirtySet::new(cells),
            changed: DirtySet::new(cells),
            unsaved: DirtySet::new(cells),
            unsaved_whole: true,
            ground: GroundScratch::with_capacity(window * LOW_POINTS),
            counters: MapCounters::default(),
            cloud_sequence: 0,
            beliefs: (config.obstacle_model == ObstacleModel::Traversability)
                .then(|| BeliefLayer::new(config, cells)),
            footprint_costs: footprint_costs(config),
            slope: (config.obstacle_model == ObstacleModel::Traversability)
                .then(|| SlopeJudge::new(config.rover_body, geometry.cell_size_m)),
            domes: (config.obstacle_model == ObstacleModel::Traversability
                && config.dome_base_per_height > 0.0)
                .then(|| {
                    DomeLayer::new(
                        cells,
                        config.dome_base_per_height,
                        0.5 * config.rover_body.max_climbable_height_m as f32,
                    )
                }),
        }
    }

    /// The `traversability` model's fitted rocks (`None` when off).
    pub fn domes(&self) -> Option<&DomeLayer> {
        self.domes.as_ref()
    }

    /// The `traversability` model's beliefs (`None` under the `features` model).
    pub fn beliefs(&self) -> Option<&BeliefLayer> {
        self.beliefs.as_ref()
    }

    /// The grid geometry.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// What happened to the features so far.
    pub fn counters(&self) -> MapCounters {
        self.counters
    }

    /// Records that `robot`'s cloud of frame `frame_index` has been taken in.
    pub fn note_cloud_frame(&mut self, robot: Robot, frame_index: u64) {
        self.counters.last_cloud_frame[cloud_slot(robot)] = Some(frame_index);
    }

    /// Frame index of the last cloud of `robot` taken in, if any.
    pub fn last_cloud_frame(&self, robot: Robot) -> Option<u64> {
        self.counters.last_cloud_frame[cloud_slot(robot)]
    }

    /// Reclassifies the cells the features inserted since the last update can affect (at most
    /// `max_cells_per_frame`; the rest wait for the next update, see [`Self::pending_cells`]),
    /// and inflates around obstacles that appeared or vanished. Returns the cells whose
    /// published state may have changed.
    pub fn update(&mut self) -> usize {
        let reach = self.thresholds.ground_reach_cells;
        for &index in self.touched.as_slice() {
            let index = index as usize;
            self.unsaved.insert(index);
            self.reclassify.insert(index);
            if let Some(domes) = self.domes.as_mut() {
                // Rays may have refuted the cell's points: its rock is fitted again.
                domes.mark(index);
            }
            let (x, y) = self.geometry.coords(index);
            if let Some(slope) = &self.slope {
                // The cell's ground enters its own slope and its neighbours'.
                slope.dependents(&self.geometry, x, y, |cell| self.restate.insert(cell));
            }
            let (x0, y0, x1, y1) = self.geometry.window(x, y, reach);
            for ny in y0..=y1 {
                for nx in x0..=x1 {
                    let neighbour = self.geometry.index(nx, ny);
                    // Only estimated heights depend on the neighbours' ground.
                    if self.stats[neighbour].high_len > 0 {
                        self.reclassify.insert(neighbour);
                    }
                }
            }
        }
        self.touched.clear();
        if let (Some(domes), Some(layer)) = (self.domes.as_mut(), self.beliefs.as_ref()) {
            let inflation_m = self.footprint_costs.as_ref().map_or(0.0, |c| c.radius_m);
            domes.refit(
                &self.geometry,
                layer,
                &mut Changed {
                    reclassify: &mut self.reclassify,
                    restate: &mut self.restate,
                    inflation_m,
                },
            );
        }
        let batch = self
            .reclassify
            .len()
            .min(self.thresholds.max_cells_per_update);
        for i in 0..batch {
            let index = self.reclassify.as_slice()[i] as usize;
            let base = self.classify(index);
            // Obstacles inflate, and (at a lower cost) uncertain cells too.
            let inflates = |class: BaseClass| {
                class == BaseClass::Obstacle
                    || class == BaseClass::Uncertain && self.beliefs.is_some()
            };
            let was_obstacle = self.base[index].class == BaseClass::Obstacle;
            let is_obstacle = base.class == BaseClass::Obstacle;
            let inflation_changed = inflates(self.base[index].class) != inflates(base.class)
                || was_obstacle != is_obstacle;
            self.base[index] = base;
            self.restate.insert(index);
            if inflation_changed {
                if self.beliefs.is_some() && was_obstacle != is_obstacle {
                    // A rock's flanks join it or leave it with its top (next update).
                    self.reclassify_neighbours(index);
                }
                let (x, y) = self.geometry.coords(index);
                let (x0, y0, x1, y1) = self.geometry.window(x, y, self.inflation_reach_cells);
                for ny in y0..=y1 {
                    for nx in x0..=x1 {
                        self.restate.insert(self.geometry.index(nx, ny));
                    }
                }
            }
        }
        self.reclassify.remove_first(batch);
        for i in 0..self.restate.len() {
            let index = self.restate.as_slice()[i] as usize;
            self.state[index] = self.derive_state(index);
            self.changed.insert(index);
        }
        self.restate.clear();
        self.changed.len()
    }

    /// Cells waiting to be reclassified by the next [`Self::update`].
    pub fn pending_cells(&self) -> usize {
        self.reclassify.len() + self.touched.len()
    }

    /// Appends the cells whose class, extra cost or observers differ from what the last call
    /// returned (the first call: from an all-unknown map) to `out`, and remembers them as
    /// published. `out` is not cleared.
    pub fn collect_changes(&mut self, out: &mut Vec<CellUpdate>) -> usize {
        let before = out.len();
        for &index in self.changed.as_slice() {
            let index = index as usize;
            let state = self.state[index];
            if state.differs_from(&self.published[index]) {
                let (x, y) = self.geometry.coords(index);
                out.push(CellUpdate {
                    x,
                    y,
                    class: state.class.code(),
                    extra_cost: state.extra_cost,
                    observed_by: state.observed_by,
                    support: state.support,
                });
            }
            self.published[index] = state;
        }
        self.changed.clear();
        out.len() - before
    }

    /// Forgets what was published: the next [`Self::collect_changes`] returns every cell that
    /// is not plain unknown (a full map for a subscriber that starts from nothing).
    pub fn republish_all(&mut self) {
        for index in 0..self.state.len() {
            self.published[index] = CellState::default();
            if self.state[index] != CellState::default() {
                self.changed.insert(index);
            }
        }
    }

    /// The current state of cell `(x, y)`, `None` outside the grid.
    pub fn cell_state(&self, x: u32, y: u32) -> Option<CellState> {
        (x < self.geometry.width_cells && y < self.geometry.height_cells)
            .then(|| self.state[self.geometry.index(x, y)])
    }

    /// The statistics of cell `(x, y)`, `None` outside the grid.
    pub fn cell_stats(&self, x: u32, y: u32) -> Option<&CellStats> {
        (x < self.geometry.width_cells && y < self.geometry.height_cells)
            .then(|| &self.stats[self.geometry.index(x, y)])
    }

    /// Bytes held by the map (constant after [`Self::new`]).
    pub fn memory_bytes(&self) -> usize {
        let cells = self.stats.capacity() * size_of::<CellStats>()
            + self.ground_cache.capacity() * size_of::<Option<GroundPlane>>()
            + self.base.capacity() * size_of::<Base>()
            + (self.state.capacity() + self.published.capacity()) * size_of::<CellState>()
            + self.beliefs.as_ref().map_or(0, BeliefLayer::memory_bytes)
            + self.domes.as_ref().map_or(0, DomeLayer::memory_bytes);
        let sets = 5 * self.geometry.cell_count() * (size_of::<bool>() + size_of::<u32>());
        cells + sets + self.ground.samples.capacity() * 5 * size_of::<f64>()
    }

    pub(crate) fn stats_slice(&self) -> &[CellStats] {
        &self.stats
    }

    pub(crate) fn set_beliefs(&mut self, beliefs: &[CellBelief]) {
        if let Some(layer) = self.beliefs.as_mut() {
            layer.set_beliefs(beliefs);
        }
        self.unsaved_whole = true;
    }

    /// Brings a copy of the cells' statistics and beliefs up to date, copying only the cells
    /// changed since the last call (every cell on the first call, after a restore, or when
    /// `whole`: a copy this map did not fill before). False, with nothing copied, when
    /// `stats` or (under the traversability model) `beliefs` is not as long as the map's:
    /// then the next call copies everything again.
    ///
    /// The whole grid is megabytes, and the frame that copies it all overruns its budget.
    pub(crate) fn refresh_copy(
        &mut self,
        stats: &mut [CellStats],
        beliefs: &mut [CellBelief],
        whole: bool,
    ) -> bool {
        let layer = self.beliefs.as_ref().map(BeliefLayer::beliefs);
        if stats.len() != self.stats.len() || layer.is_some_and(|l| l.len() != beliefs.len()) {
            self.unsaved_whole = true;
            return false;
        }
        if whole || self.unsaved_whole {
            stats.copy_from_slice(&self.stats);
            if let Some(layer) = layer {
                beliefs.copy_from_slice(layer);
            }
        } else {
            for &index in self
                .unsaved
                .as_slice()
                .iter()
                .chain(self.touched.as_slice())
            {
                let index = index as usize;
                stats[index] = self.stats[index];
                if let Some(layer) = layer {
                    beliefs[index] = layer[index];
                }
            }
        }
        self.unsaved.clear();
        self.unsaved_whole = false;
        true
    }

    pub(crate) fn set_dome_points(&mut self, cells: &[(u32, crate::dome_layer::CellPoints)]) {
        if let Some(domes) = self.domes.as_mut() {
            domes.set_stored_points(cells);
        }
    }

    pub(crate) fn set_stats(&mut self, stats: &[CellStats], counters: MapCounters) {
        self.stats.copy_from_slice(stats);
        self.counters = counters;
        self.unsaved_whole = true;
        for index in 0..self.stats.len() {
            if self.stats[index].count > 0 {
                self.touched.insert(index);
            }
        }
    }
}

/// Index of `robot` in [`MapCounters::last_cloud_frame`].
pub fn cloud_slot(robot: Robot) -> usize {
    match robot {
        Robot::Jumper => 0,
        Robot::Rover => 1,
    }
}

#[path = "map_classify.rs"]
mod classify;

#[path = "map_insert.rs"]
mod insert;

#[cfg(test)]
impl FeatureMap {
    /// A 16 m × 16 m map (origin (−8, −8)) with `config`, the tests' usual ground.
    pub(crate) fn sixteen_m_square(config: &MapperConfig) -> Self {
        let geometry = config.resolve_geometry((16.0, 16.0)).expect("valid");
        Self::new(config, geometry)
    }
}

#[cfg(test)]
#[path = "map_tests.rs"]
mod tests;
