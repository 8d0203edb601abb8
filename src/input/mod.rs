//! The input: the domain as the user wrote it, validated, and its boundary
//! discretised with the cutting lines drawn.

pub mod arc_corners;
pub mod boundary;
pub mod curves;
pub mod domain;
mod keys;
mod line_gaps;
pub mod segment_counts;
mod thin_walls;
