//! Smoothing: the nodes moved, the elements as they are. Guarded Laplace
//! (Eq. 4, `laplace.rs`), untangling of corners outside [45, 135]
//! (`untangle.rs`), evening out of sizes and shapes (`sizes.rs`), all by
//! the compass search (`compass.rs`) where Laplace does not reach, a
//! large mesh in strips on all cores (`strips.rs`); `stage.rs` runs them
//! in turn. Boundary nodes slide along their curves where a corner next to
//! them is outside the window (`slide.rs`); input vertices never move.

mod compass;
mod laplace;
mod sizes;
mod slide;
mod stage;
mod strips;
mod untangle;

#[cfg(test)]
pub(crate) mod tests;

pub use compass::compass_search_steps;
pub use slide::slide_boundary_nodes;
pub use stage::{smooth, smooth_near};
