//! Rover stereo visual odometry (work in progress).
#![warn(missing_docs)]
