//! File formats users already know (DESIGN.md §6): 8-bit PGM images, TUM trajectories.

pub mod pgm;
pub mod tum;
