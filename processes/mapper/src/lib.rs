//! Mapper (work in progress).
#![warn(missing_docs)]
