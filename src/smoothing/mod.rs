//! Smoothing: the nodes moved, the elements as they are. Guarded Laplace
//! (Eq. 4, `laplace.rs`), untangling of corners outside [45, 135]
//! (`untangle.rs`), evening out of sizes and shapes (`sizes.rs`), all by
//! the compass search (`compass.rs`) where Laplace does not reach, a
//! large mesh in strips on all cores (`strips.rs`); `stage.rs` runs them
//! in turn; `ease.rs` works round the corners still outside the window.
//! Input boundary nodes stay where they are, but for easing: a node
//! inside a straight input edge may slide along it there (`ease.rs`).

mod compass;
mod ease;
mod laplace;
mod polish;
mod sizes;
mod stage;
mod strips;
mod untangle;

#[cfg(test)]
pub(crate) mod tests;

pub(crate) use compass::compass_search_from;
pub use compass::compass_search_steps;
pub use ease::ease_bad_corners;
pub use polish::polish_past_bounds;
pub use stage::{smooth, smooth_near};
