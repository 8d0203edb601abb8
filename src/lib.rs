//! # freemesh
//!
//! FREEMESH, the knowledge-based free quadrilateral mesher: a plane domain
//! is meshed from its boundary inward, one quadrilateral at a time
//! (Ω_n = ⟨Q_i, Ω_{n−i}⟩). The boundary features of the remaining domain
//! are recognised by rules in a Prolog knowledge base (`kb/*.pl`, run by
//! scryer-prolog embedded as a library), design rules turn a feature into
//! an action, redesign rules correct an element that would spoil the rest,
//! final patterns close the last loops, and Laplace smoothing finishes.
//!
//! ```
//! use freemesh::{mesh_domain, Domain, KnowledgeBase, Options};
//! let domain = Domain::from_file("examples/plugger.json").unwrap();
//! let mut kb = KnowledgeBase::builtin().unwrap();
//! let result = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
//! assert!(result.mesh.quads.len() > 0);
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

// Data flows down this list: a module uses only those above it.
mod cleanup;
mod element_quality;
mod fallback;
mod features;
mod final_patterns;
mod front;
mod geometry;
mod initial_design;
mod input;
mod io;
mod kb;
mod mesh;
mod partial_mesh;
mod pipeline;
mod recursion;
mod redesign;
mod repl;
mod report;
mod settings;
mod smoothing;
mod validity;

pub use features::{EdgeFeature, FrontFeatures, NodeFeature};
pub use input::domain::{Domain, DomainError};
pub use io::mesh_reader::{read_mesh, ReadError, ReadMesh};
pub use io::output::{render, write_all, Format, OutputError};
pub use kb::{KbError, KbStats, KnowledgeBase};
pub use mesh::{Mesh, NodeKind};
pub use partial_mesh::MeshStats;
pub use pipeline::{
    discretise_for_run, domain_features, mesh_boundary, mesh_domain, Error, MeshResult, Options,
    Phases, RunBoundary,
};
pub use recursion::MeshError;
pub use repl::{Flow, Repl};
pub use report::quality::{angle_bins, angle_histogram, measure as measure_quality, Quality};
pub use report::trace::{json_lines as trace_json_lines, By, TraceStep, Veto};
