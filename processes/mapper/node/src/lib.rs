//! The `mapper` node: [`MapperProcess`] drains both robots' feature clouds into the map of
//! `hopnav-mapper` every frame and publishes the changed cells and periodic snapshots over
//! iceoryx2; a restarted mapper restores its map from [`SNAPSHOT_FILE`].
//!
//! The map itself has no IPC and lives in `hopnav-mapper`; this crate only binds it.
#![warn(missing_docs)]

mod process;

pub use process::{MapperProcess, MapperProcessError, SNAPSHOT_FILE};
