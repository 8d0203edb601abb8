//! The recursion strategy (Eq. 1): the design queue (`queue.rs`) and the
//! run that takes the next edge, designs, redesigns, checks and commits
//! its element, closes loops with the final patterns and turns to the
//! fallbacks where the rules are stuck (`mesher.rs`).

mod mesher;
mod queue;

pub use mesher::{grades, MeshError, Mesher, Outcome, Prepared};
