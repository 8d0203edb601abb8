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
//! ```no_run
//! use freemesh::{mesh_domain, Domain, KnowledgeBase, Options};
//! let domain = Domain::from_file("examples/plugger.json").unwrap();
//! let mut kb = KnowledgeBase::builtin().unwrap();
//! let result = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
//! assert!(result.mesh.quads.len() > 0);
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod boundary;
pub mod check;
pub mod cleanup;
pub mod design;
pub mod domain;
pub mod front;
pub mod geometry;
pub mod kb;
pub mod mesh;
pub mod mesh_reader;
pub mod mesher;
mod msh_binary;
pub mod output;
pub mod quality;
pub mod repl;
pub mod second_engine;
pub mod smoothing;
pub mod trace;
pub mod triangle_fallback;

pub use domain::{Domain, DomainError};
pub use kb::{KbError, KnowledgeBase};
pub use mesh::{Mesh, NodeKind};
pub use mesher::{MeshError, MeshStats};
pub use quality::Quality;
pub use trace::TraceStep;

/// How many times at most the clean-up and the smoothing round its
/// changes run after the smoothing stage.
const CLEANUP_ROUNDS: usize = 3;

/// Options of one meshing run.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Replaces the domain's `size`.
    pub size: Option<f64>,
    /// Replaces the domain's `max_size`.
    pub max_size: Option<f64>,
    /// Sweeps of Laplace smoothing (Eq. 4).
    pub smoothing_passes: usize,
    /// Whether the inference trace is kept (`MeshResult::trace`); a run
    /// that writes no trace saves its time and memory.
    pub trace: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            size: None,
            max_size: None,
            smoothing_passes: 30,
            trace: true,
        }
    }
}

impl Options {
    /// Sets the boundary size.
    pub fn with_size(mut self, size: Option<f64>) -> Self {
        self.size = size;
        self
    }
    /// Sets the largest interior size.
    pub fn with_max_size(mut self, max_size: Option<f64>) -> Self {
        self.max_size = max_size;
        self
    }
    /// Keeps the inference trace, or not.
    pub fn with_trace(mut self, trace: bool) -> Self {
        self.trace = trace;
        self
    }
}

/// Any error of a meshing run.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The domain is invalid.
    #[error(transparent)]
    Domain(#[from] DomainError),
    /// The knowledge base failed.
    #[error(transparent)]
    Kb(#[from] KbError),
    /// Meshing stopped short.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The last-resort fallback failed (a defect: never on a valid domain).
    #[error(transparent)]
    Fallback(#[from] triangle_fallback::FallbackError),
    /// The finished mesh failed its check (a defect: never written).
    #[error("the mesh failed its check before writing: {0}")]
    Check(#[from] check::MeshCheckError),
    /// An option is out of range.
    #[error("{0}")]
    Option(String),
}

/// The outcome of a meshing run.
#[derive(Debug, Clone)]
pub struct MeshResult {
    /// The mesh.
    pub mesh: Mesh,
    /// The inference trace.
    pub trace: Vec<TraceStep>,
    /// Counters of the recursion.
    pub stats: MeshStats,
    /// Quality figures.
    pub quality: Quality,
    /// Engine use during the run.
    pub kb_stats: kb::KbStats,
    /// Where the time went.
    pub phases: Phases,
}

/// Wall time of each phase of a run (seconds).
#[derive(Debug, Default, Clone, Copy)]
pub struct Phases {
    /// Discretising the boundary, cutting lines, the first front.
    pub prepare: f64,
    /// The recursion: features, designs, redesigns, fallbacks.
    pub recursion: f64,
    /// Laplace smoothing and the angle clean-up.
    pub smoothing: f64,
    /// The mesh's check and quality figures.
    pub check: f64,
}

/// A meshing run over a domain, ready to step: the boundary discretised
/// with boundary size `size` (the domain's own when None), the cutting
/// lines drawn, the front made.
pub fn start_mesher<'k>(
    domain: &Domain,
    kb: &'k mut KnowledgeBase,
    size: Option<f64>,
) -> Result<mesher::Mesher<'k>, Error> {
    let prepared = prepare_run(domain, kb, size)?;
    Ok(mesher::Mesher::start_from(kb, prepared))
}

/// Everything of `start_mesher` that can fail, with the KB only borrowed.
pub fn prepare_run(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    size: Option<f64>,
) -> Result<mesher::Prepared, Error> {
    let RunBoundary { disc, size, area } = discretise_for_run(domain, size)?;
    Ok(mesher::Prepared::new(kb, disc, size, area)?)
}

/// A domain's boundary made ready for a run: discretised, the cutting
/// lines drawn, the area it encloses. The part of a run that needs no
/// knowledge base, so it can be done while the engine loads.
pub struct RunBoundary {
    disc: boundary::Discretised,
    size: f64,
    area: f64,
}

/// Discretises a domain's boundary with boundary size `size` (the
/// domain's own when None) and draws the cutting lines.
pub fn discretise_for_run(domain: &Domain, size: Option<f64>) -> Result<RunBoundary, Error> {
    let size = size.unwrap_or(domain.size);
    if !(size.is_finite() && size > 0.0) {
        return Err(Error::Option(format!(
            "--size must be a positive number, got {size}"
        )));
    }
    let area = domain.outer.signed_area().abs()
        - domain
            .holes
            .iter()
            .map(|h| h.signed_area().abs())
            .sum::<f64>();
    let estimate = area / (size * size);
    if estimate > domain::MAX_ELEMENTS as f64 {
        return Err(Error::Option(format!(
            "size {size} gives about {estimate:.2e} elements over the domain's area {area:.4e}, above the limit of {} (give a larger size)",
            domain::MAX_ELEMENTS
        )));
    }
    let disc = boundary::discretise(domain, size)?;
    let area = boundary_area(&disc.mesh, 1 + domain.holes.len() as u32);
    Ok(RunBoundary { disc, size, area })
}

/// The boundary features of a domain's initial loop (after the cutting
/// lines), as the KB recognises them.
pub fn domain_features(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    size: Option<f64>,
) -> Result<mesher::FrontFeatures, Error> {
    Ok(start_mesher(domain, kb, size)?.front_features()?)
}

/// Meshes a domain with the knowledge base, smooths and checks the mesh.
pub fn mesh_domain(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    progress: &mut dyn FnMut(usize),
) -> Result<MeshResult, Error> {
    check_options(opts)?;
    let run_boundary = discretise_for_run(domain, opts.size)?;
    mesh_boundary(domain, run_boundary, kb, opts, progress)
}

fn check_options(opts: &Options) -> Result<(), Error> {
    match opts.max_size {
        Some(m) if !(m.is_finite() && m > 0.0) => Err(Error::Option(format!(
            "--max-size must be a positive number, got {m}"
        ))),
        _ => Ok(()),
    }
}

/// `mesh_domain` on a boundary `discretise_for_run` made ready with the
/// same size.
pub fn mesh_boundary(
    domain: &Domain,
    run_boundary: RunBoundary,
    kb: &mut KnowledgeBase,
    opts: &Options,
    progress: &mut dyn FnMut(usize),
) -> Result<MeshResult, Error> {
    check_options(opts)?;
    let kb_before = kb.stats;
    let t0 = std::time::Instant::now();
    let RunBoundary { disc, size, area } = run_boundary;
    let prepared = mesher::Prepared::new(kb, disc, size, area)?;
    let mut m = mesher::Mesher::start_from(kb, prepared);
    m.record_trace = opts.trace;
    let prepare = t0.elapsed().as_secs_f64();
    let by_rules = m.run(progress).map_err(Error::from).and_then(|()| {
        let recursion = t0.elapsed().as_secs_f64() - prepare;
        let mut r = finish(&mut m, opts, kb_before)?;
        r.phases.prepare = prepare;
        r.phases.recursion = recursion;
        Ok(r)
    });
    match by_rules {
        Ok(r) => Ok(r),
        // The rules and the loop subdivision gave up, or made a mesh that
        // fails its check: the last resort meshes the whole domain (see
        // triangle_fallback.rs). A KB fault is not recovered: it is the
        // user's rule, and the run stops naming it.
        Err(
            e @ (Error::Mesh(mesher::MeshError::Stuck { .. })
            | Error::Mesh(mesher::MeshError::Runaway(_))
            | Error::Check(_)),
        ) => {
            // A debugging aid: the state where meshing stopped, as a picture.
            if let Ok(path) = std::env::var("FREEMESH_DEBUG_SVG") {
                let _ = std::fs::write(
                    &path,
                    output::to_svg(&m.mesh, &m.front_node_loops(), "stopped"),
                );
                let lines: Vec<String> = m.trace.iter().map(|t| t.to_json_line()).collect();
                let _ = std::fs::write(format!("{path}.trace"), lines.join("\n"));
            }
            let size = opts.size.unwrap_or(domain.size);
            let disc = boundary::discretise(domain, size)?;
            let mesh = triangle_fallback::mesh_by_triangles(domain, &disc, size)?;
            let mut stats = m.stats;
            stats.triangle_fallbacks += 1;
            let reason = e.to_string();
            let trace = vec![TraceStep {
                step: 1,
                edge: [-1, -1],
                angles: Default::default(),
                feature: "stuck".into(),
                action: format!("triangle_split({})", mesh.quads.len()),
                redesign: vec![reason],
                element: vec![],
            }];
            let kb_stats = m.kb().stats;
            let area = boundary_area(&mesh, 1 + domain.holes.len() as u32);
            // the rules' attempt and the fallback count as the recursion
            let recursion = t0.elapsed().as_secs_f64() - prepare;
            let mut r = finish_mesh(mesh, trace, stats, area, opts, kb_before, kb_stats)?;
            r.phases.prepare = prepare;
            r.phases.recursion = recursion;
            Ok(r)
        }
        Err(e) => Err(e.into()),
    }
}

/// The area inside the loops' boundary edges (groups below `loops`).
fn boundary_area(mesh: &Mesh, loops: u32) -> f64 {
    mesh.boundary
        .iter()
        .filter(|e| e.group < loops)
        .map(|e| mesh.nodes[e.a as usize].perp_dot(mesh.nodes[e.b as usize]) / 2.0)
        .sum()
}

/// Finishes a run whose recursion is done: drops the nodes no element
/// kept (the trace's ids follow), smooths, checks and measures the mesh.
/// The run is left empty.
pub fn finish(
    m: &mut mesher::Mesher,
    opts: &Options,
    kb_before: kb::KbStats,
) -> Result<MeshResult, Error> {
    m.release_working_state();
    let mesh = std::mem::take(&mut m.mesh);
    let trace = std::mem::take(&mut m.trace);
    let kb_after = m.kb().stats;
    finish_mesh(mesh, trace, m.stats, m.area, opts, kb_before, kb_after)
}

/// Drops the nodes no element uses; the trace's node ids follow (-1 for
/// a node that is gone).
fn compact_with_trace(mesh: &mut Mesh, trace: &mut [TraceStep]) {
    let map = mesh.compact();
    let remap = |x: i64| {
        if x < 0 {
            return x;
        }
        map.get(x as usize)
            .copied()
            .flatten()
            .map_or(-1, |n| n as i64)
    };
    for t in trace {
        t.edge = t.edge.map(remap);
        for n in &mut t.element {
            *n = remap(*n);
        }
    }
}

fn finish_mesh(
    mut mesh: Mesh,
    mut trace: Vec<TraceStep>,
    mut stats: MeshStats,
    area: f64,
    opts: &Options,
    kb_before: kb::KbStats,
    kb_after: kb::KbStats,
) -> Result<MeshResult, Error> {
    check::check_boundary_followed(&mesh)?;
    compact_with_trace(&mut mesh, &mut trace);
    let t0 = std::time::Instant::now();
    smoothing::smooth(&mut mesh, opts.smoothing_passes);
    // where smoothing could not reach the bounds: the elements joined
    // up anew and the nodes round the changes smoothed again, a few
    // times while that changes something (the smoothing after a change
    // can leave a corner the next clean-up mends)
    let mut any_collapse = false;
    let mut last_changes: Option<Vec<u32>> = None;
    for _ in 0..CLEANUP_ROUNDS {
        let (cleaned, touched) = cleanup::clean_up(&mut mesh, last_changes.as_deref());
        stats.cleanup_flips += cleaned.flips;
        stats.cleanup_collapses += cleaned.collapses;
        any_collapse |= cleaned.collapses > 0;
        if touched.is_empty() {
            break;
        }
        smoothing::smooth_near(&mut mesh, opts.smoothing_passes / 3, &touched);
        last_changes = Some(touched);
    }
    if any_collapse {
        compact_with_trace(&mut mesh, &mut trace);
    }
    let smoothing = t0.elapsed().as_secs_f64();
    // both only read the mesh: side by side
    let (checked, quality) = std::thread::scope(|scope| {
        let checked = scope.spawn(|| check::check_mesh(&mesh, area));
        let quality = quality::measure(&mesh);
        let checked = checked
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        (checked, quality)
    });
    checked?;
    let phases = Phases {
        smoothing,
        check: t0.elapsed().as_secs_f64() - smoothing,
        ..Default::default()
    };
    let mut kb_stats = kb_after;
    kb_stats.engine_queries -= kb_before.engine_queries;
    kb_stats.cached_queries -= kb_before.cached_queries;
    kb_stats.engine_time -= kb_before.engine_time;
    kb_stats.second_engine_queries -= kb_before.second_engine_queries;
    kb_stats.second_engine_time -= kb_before.second_engine_time;
    Ok(MeshResult {
        mesh,
        trace,
        stats,
        quality,
        kb_stats,
        phases,
    })
}
