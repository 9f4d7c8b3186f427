//! A read-only view of the map for plots and reports (e.g. a Fig.-6 style picture).
//!
//! ```
//! use hopnav_ipc::messages::CellClass;
//! use hopnav_mapper::{config::MapperConfig, map::FeatureMap, view::MapView};
//! let config = MapperConfig::default();
//! let map = FeatureMap::new(&config, config.resolve_geometry((8.0, 8.0)).unwrap());
//! let view = MapView::new(&map);
//! assert_eq!((view.width_cells(), view.height_cells()), (32, 32));
//! assert!(view.cells().all(|cell| cell.class == CellClass::Unknown));
//! ```

use hopnav_ipc::messages::CellClass;

use crate::geometry::GridGeometry;
use crate::map::FeatureMap;

/// One cell as a plot needs it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellView {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// Class (after inflation).
    pub class: CellClass,
    /// Extra cost, planner units.
    pub extra_cost: u32,
    /// Bit set of robot codes that observed the cell (bit = 1 << code).
    pub observed_by: u32,
    /// Features in the cell.
    pub feature_count: u32,
}

/// Borrowed, read-only access to a [`FeatureMap`].
#[derive(Debug, Clone, Copy)]
pub struct MapView<'a> {
    map: &'a FeatureMap,
}

impl<'a> MapView<'a> {
    /// A view of `map`.
    pub fn new(map: &'a FeatureMap) -> Self {
        Self { map }
    }

    /// The grid geometry (world position of every cell).
    pub fn geometry(&self) -> &GridGeometry {
        self.map.geometry()
    }

    /// Cells along x.
    pub fn width_cells(&self) -> u32 {
        self.map.geometry().width_cells
    }

    /// Cells along y.
    pub fn height_cells(&self) -> u32 {
        self.map.geometry().height_cells
    }

    /// Cell `(x, y)`, `None` outside the grid.
    pub fn cell(&self, x: u32, y: u32) -> Option<CellView> {
        let state = self.map.cell_state(x, y)?;
        let stats = self.map.cell_stats(x, y)?;
        Some(CellView {
            x,
            y,
            class: state.class,
            extra_cost: state.extra_cost,
            observed_by: state.observed_by,
            feature_count: stats.count,
        })
    }

    /// Every cell, row by row.
    pub fn cells(&self) -> impl Iterator<Item = CellView> + 'a {
        let map = self.map;
        let geometry = *map.geometry();
        (0..geometry.height_cells).flat_map(move |y| {
            (0..geometry.width_cells).filter_map(move |x| MapView { map }.cell(x, y))
        })
    }
}
