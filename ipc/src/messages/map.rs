//! mapper → planner: changed grid cells only, a `[CellUpdate]` slice with a [`MapHeader`].

use iceoryx2::prelude::ZeroCopySend;

use super::{SampleStamp, coded_enum};

coded_enum! {
    /// What a map cell holds.
    CellClass {
        /// Nothing known yet.
        Unknown = 0,
        /// Observed and traversable.
        Free = 1,
        /// Features clustered above the rover's traversable height.
        Obstacle = 2,
        /// Near an obstacle: traversable at extra cost.
        Inflated = 3,
        /// So close to an obstacle that the rover's body would touch it: its centre must not
        /// enter (the planner treats the cell as an obstacle).
        Lethal = 4,
        /// Maybe too tall to climb (its height straddles the climb limit within its
        /// uncertainty), or so close to such a rock that the rover's body would touch it
        /// whatever its heading: traversable at extra cost until the rover's closer look
        /// settles it.
        Uncertain = 5,
    }
}

/// User header of a map update sample; the grid geometry never changes during a mission.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::MapHeader")]
pub struct MapHeader {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// World x of the corner of cell (0, 0), metres.
    pub origin_x_m: f64,
    /// World y of the corner of cell (0, 0), metres.
    pub origin_y_m: f64,
    /// Edge length of a cell, metres.
    pub cell_size_m: f64,
    /// Cells along x.
    pub width_cells: u32,
    /// Cells along y.
    pub height_cells: u32,
    /// Updates in the slice.
    pub update_count: u32,
    /// Reserved, zero.
    pub reserved: u32,
}

/// New state of one grid cell.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::CellUpdate")]
pub struct CellUpdate {
    /// Column index.
    pub x: u32,
    /// Row index.
    pub y: u32,
    /// A [`CellClass`] code.
    pub class: u32,
    /// Extra traversal cost added to moves into the cell (planner units, 1000 = one cell).
    pub extra_cost: u32,
    /// Bit set of [`Robot`](super::Robot) codes that observed the cell (bit = 1 << code).
    pub observed_by: u32,
    /// Number of features supporting the classification.
    pub support: u32,
}

const _: () = assert!(size_of::<MapHeader>() == 72);
const _: () = assert!(size_of::<CellUpdate>() == 24);
