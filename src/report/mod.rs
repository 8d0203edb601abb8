//! What a run reports: the mesh's check, its quality, the inference trace.

pub mod check;
pub mod quality;
pub mod trace;
