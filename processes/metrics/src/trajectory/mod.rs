//! Trajectory evaluation shared by both VO processes: Umeyama alignment, ATE/RPE/drift and TUM
//! files (`evo_ape` reads them).

pub mod align;
pub mod errors;
pub mod tum;
