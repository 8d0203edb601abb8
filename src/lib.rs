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
//! One call meshes a domain: [`mesh_domain`] takes a validated
//! [`Domain`], the [`KnowledgeBase`] and the [`Options`], and gives the
//! mesh with its report ([`MeshResult`]: the trace, the counters, the
//! quality figures) or one typed [`Error`] saying what is wrong.
//!
//! ```
//! use freemesh::{mesh_domain, Domain, KnowledgeBase, Options};
//! // a 2 x 1 rectangle with a boundary size of 0.25
//! let domain = Domain::from_json_str(
//!     r#"{"name": "plate", "size": 0.25,
//!         "outer": {"points": [[0, 0], [2, 0], [2, 1], [0, 1]]}}"#,
//! )?;
//! let mut kb = KnowledgeBase::builtin()?;
//! let result = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {})?;
//! // 8 by 4 squares of the boundary size fill it
//! assert_eq!(result.mesh.quads().len(), 32);
//! assert!(result.quality.min_angle > 80.0);
//! assert!(result.stopped_short.is_none());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

// One module a concept of the paper; the README's "How it works" maps
// them to the stages in the order data flows through them.
mod blocks;
mod cleanup;
mod cracks;
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
mod regions;
mod repl;
mod report;
mod second_order;
mod settings;
mod size_field;
mod smoothing;
mod validity;

// The entry point, what it takes and what it gives.
pub use blocks::{mesh_free_then_blocks, mesh_in_blocks};
pub use input::domain::{Domain, DomainError};
pub use kb::answer_store;
pub use kb::{KbError, KbStats, KnowledgeBase, More, SecondEngineLoading, UserAnswer};
pub use mesh::{Mesh, NodeKind};
pub use partial_mesh::MeshStats;
pub use pipeline::{
    mesh_domain, Error, MeshResult, OptionError, Options, Phases, RunOption, StoppedShort,
};
pub use recursion::MeshError;
pub use report::quality::Quality;
pub use report::trace::{json_lines as trace_json_lines, By, TraceStep, Veto};
pub use second_order::{ElementKind, SecondOrder};

// The binary's other commands: the boundary made ready while the engine
// loads, the features of a domain, the writers and the mesh reader, the
// quality figures of a mesh file, the REPL.
pub use features::{EdgeFeature, FrontFeatures, NodeFeature};
pub use io::dxf::{read_dxf, DomainFile, Outline};
pub use io::mesh_reader::{read_mesh, ReadError, ReadMesh};
pub use io::output::{
    check_writable, interrupt as interrupt_writes, interrupted_flag, render, was_interrupted,
    write_all, Format, OutputError,
};
pub use pipeline::{discretise_for_run, domain_features, mesh_boundary, RunBoundary};
pub use repl::{Flow, Repl};
pub use report::quality::{angle_bins, angle_histogram, measure as measure_quality};
