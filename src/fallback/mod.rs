//! The fallbacks for where the rules get stuck, each confined to the
//! stuck loop: chords (the loop subdivision), slits and pinches, taking
//! elements back, rings; the loops still open closed by triangles paired
//! into quads (those left over split in three); and the last resort for
//! the whole domain, triangles split into quads.

pub mod chords;
mod open_region;
mod pairs;
pub mod rings;
pub mod slits;
pub mod stuck_loops;
pub mod triangles;
pub mod unmesh;
