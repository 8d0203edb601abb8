//! The stages of a run in order, the one path every caller takes (`mesh`,
//! a batch, the REPL's `:run`): prepare (discretise the boundary, draw
//! the cutting lines, read the settings), the recursion (features,
//! initial design, redesign, final patterns, the fallbacks for stuck
//! loops), the last resort where the recursion stops short, smoothing,
//! clean-up, the check and the quality figures.

use std::time::Instant;

use crate::fallback::triangles::FallbackError;
use crate::features::FrontFeatures;
use crate::input::arc_corners::CornerAim;
use crate::input::boundary::{self, Discretised};
use crate::input::domain::{self, Domain, DomainError};
use crate::input::segment_counts::CountBounds;
use crate::kb::{KbError, KbStats, KnowledgeBase};
use crate::mesh::Mesh;
use crate::partial_mesh::MeshStats;
use crate::recursion::{MeshError, Mesher, Prepared};
use crate::report::check::{self, MeshCheckError};
use crate::report::quality::Quality;
use crate::report::trace::{TraceStep, Veto};
use crate::settings::{ElementBounds, HostBounds, Settings};

mod finish;
mod phases;
mod stuck;

pub(crate) use finish::finish_mesh;

pub use phases::Phases;

/// Options of one meshing run; `Options::default()` is what the `mesh`
/// command uses when no flag is given.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Replaces the domain's `size`, the target boundary segment length
    /// (default: the domain's own). Must be a positive number, and small
    /// enough only that the domain's area over its square stays under
    /// five million elements.
    pub size: Option<f64>,
    /// Replaces the domain's `max_size` (default: the domain's own).
    /// Above the size, the run is graded: the elements grow from the
    /// boundary's sizes to at most this inside (size_field.rs, the KB's
    /// feature coarsen); at the size or without one, every element is
    /// made at `size`, as the paper's uniform meshes are.
    pub max_size: Option<f64>,
    /// Sweeps of Laplace smoothing (Eq. 4); default 30.
    pub smoothing_passes: usize,
    /// Whether the inference trace is kept (`MeshResult::trace`); a run
    /// that writes no trace saves its time and memory. Default true.
    pub trace: bool,
    /// A developer's aid, default false: every element placed is checked
    /// against the elements near it for overlaps, and the fallbacks'
    /// passes are reported on standard error. Slow; it changes no mesh.
    pub self_check: bool,
    /// Whether the run makes a block layout (blocks/layouts.rs): its
    /// elements are blocks to be, mapped and then polished with the whole
    /// mesh, so its own finish does not polish the elements past the
    /// bounds. Default false.
    pub layout: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            size: None,
            max_size: None,
            smoothing_passes: 30,
            trace: true,
            self_check: false,
            layout: false,
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
    Fallback(#[from] FallbackError),
    /// The finished mesh failed its check (a defect: never written).
    #[error("the mesh failed its check before writing: {0}")]
    Check(#[from] MeshCheckError),
    /// An option of the run cannot be used.
    #[error(transparent)]
    Option(#[from] OptionError),
}

/// An option of [`Options`] (or the domain's own value it replaces).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunOption {
    /// [`Options::size`].
    Size,
    /// [`Options::max_size`].
    MaxSize,
}

impl std::fmt::Display for RunOption {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RunOption::Size => "size",
            RunOption::MaxSize => "max_size",
        })
    }
}

/// Why an option of a run cannot be used: which option, its value, and
/// what is wrong with it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OptionError {
    /// Not a positive finite number.
    #[error("{option} must be a positive number, got {value}")]
    NotPositive {
        /// The option.
        option: RunOption,
        /// Its value.
        value: f64,
    },
    /// The size asks for more elements than a run may make.
    #[error(
        "size {size} gives about {estimate:.2e} elements over the domain's area {area:.4e}, above the limit of {limit} (give a larger size)"
    )]
    TooManyElements {
        /// The boundary size asked for.
        size: f64,
        /// The domain's area over the size squared.
        estimate: f64,
        /// The domain's area.
        area: f64,
        /// The most elements a run may make.
        limit: usize,
    },
}

/// The outcome of a meshing run.
#[derive(Debug, Clone)]
pub struct MeshResult {
    /// The mesh.
    pub mesh: Mesh,
    /// The inference trace.
    pub trace: Vec<TraceStep>,
    /// The designs the validity check refused, in order (kept with the
    /// trace; counted in `stats.vetoes` always).
    pub vetoes: Vec<Veto>,
    /// Counters of the recursion.
    pub stats: MeshStats,
    /// Quality figures.
    pub quality: Quality,
    /// Engine use during the run.
    pub kb_stats: KbStats,
    /// Where the time went.
    pub phases: Phases,
    /// Where the rules and their fallbacks stopped, when they did and the
    /// last resort meshed the domain instead (see `MeshStats`), for a
    /// person finding out why.
    pub stopped_short: Option<StoppedShort>,
}

/// The state of a run where the recursion stopped short.
#[derive(Debug, Clone)]
pub struct StoppedShort {
    /// Why it stopped (the stuck loop, or a runaway).
    pub reason: String,
    /// The elements made and the front left, as an SVG picture.
    pub picture: String,
    /// The inference trace up to there (empty when the run keeps none).
    pub trace: Vec<TraceStep>,
}

/// A domain's boundary made ready for a run: discretised, the cutting
/// lines drawn, the area it encloses. The part of a run that needs no
/// knowledge base, so it can be done while the engine loads.
pub struct RunBoundary {
    disc: Discretised,
    size: f64,
    area: f64,
    /// The bounds the segment counts were made with (`thin_wall`,
    /// `line_gap`, `line_gap_floor`).
    counts: CountBounds,
    /// The `max_size_jump` bound the cutting lines were drawn with.
    jump: f64,
    /// What the arcs' first chords at input corners were held to.
    aim: CornerAim,
}

impl RunBoundary {
    /// Whether a run on this boundary is graded by a max_size (the
    /// options' or the domain's), as `prepare_run` makes it.
    pub(crate) fn graded_by_a_max_size(&self, domain: &Domain, opts: &Options) -> bool {
        opts.max_size
            .or(domain.max_size())
            .is_some_and(|m| crate::recursion::grades(m, self.size))
    }

    /// About how many elements of the boundary size cover the domain (its
    /// area over the size squared): what a caller knows of a run's length
    /// before it starts.
    pub fn elements_of_the_size(&self) -> f64 {
        self.area / (self.size * self.size)
    }

    /// The boundary's nodes and edges, and the initial loops (domain on
    /// the left).
    pub(crate) fn parts(&self) -> (&Mesh, &[Vec<u32>]) {
        (&self.disc.mesh, &self.disc.front_loops)
    }
}

/// Discretises a domain's boundary with boundary size `size` (the
/// domain's own when None) and draws the cutting lines, with the built-in
/// segment count (`CountBounds`), `max_size_jump` and corner bounds (a
/// run whose KB sets others discretises again).
pub fn discretise_for_run(domain: &Domain, size: Option<f64>) -> Result<RunBoundary, Error> {
    let (host, element) = (HostBounds::default(), ElementBounds::default());
    let aim = CornerAim::of(&host, &element);
    discretise_with_bounds(
        domain,
        size,
        CountBounds::of(&host),
        element.max_size_jump,
        aim,
    )
}

fn discretise_with_bounds(
    domain: &Domain,
    size: Option<f64>,
    counts: CountBounds,
    jump: f64,
    aim: CornerAim,
) -> Result<RunBoundary, Error> {
    let size = size.unwrap_or(domain.size);
    if !(size.is_finite() && size > 0.0) {
        return Err(OptionError::NotPositive {
            option: RunOption::Size,
            value: size,
        }
        .into());
    }
    let area = domain.area();
    let estimate = area / (size * size);
    if estimate > domain::MAX_ELEMENTS as f64 {
        return Err(OptionError::TooManyElements {
            size,
            estimate,
            area,
            limit: domain::MAX_ELEMENTS,
        }
        .into());
    }
    let disc = boundary::discretise(domain, size, counts, jump, &aim)?;
    let area = disc.mesh.boundary_area(1 + domain.holes.len() as u32);
    Ok(RunBoundary {
        disc,
        size,
        area,
        counts,
        jump,
        aim,
    })
}

/// The boundary discretised again where the KB's segment count bounds
/// (`CountBounds`), `max_size_jump` or corner bounds (see `CornerAim`)
/// are not the ones it was made with.
fn with_kb_bounds(
    domain: &Domain,
    run_boundary: RunBoundary,
    settings: &Settings,
) -> Result<RunBoundary, Error> {
    let (counts, jump) = (
        CountBounds::of(&settings.host),
        settings.element.max_size_jump,
    );
    let aim = CornerAim::of(&settings.host, &settings.element);
    if run_boundary.counts == counts && run_boundary.jump == jump && run_boundary.aim == aim {
        return Ok(run_boundary);
    }
    discretise_with_bounds(domain, Some(run_boundary.size), counts, jump, aim)
}

/// The boundary features of a domain's initial loop (after the cutting
/// lines), as the KB recognises them.
pub fn domain_features(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    size: Option<f64>,
) -> Result<FrontFeatures, Error> {
    let settings = kb.settings()?;
    let run_boundary = discretise_for_run(domain, size)?;
    let RunBoundary {
        disc, size, area, ..
    } = with_kb_bounds(domain, run_boundary, &settings)?;
    let prepared = Prepared::new(disc, size, area, settings).with_max_size(domain.max_size());
    Ok(Mesher::start_from(kb, prepared).front_features()?)
}

/// Meshes a domain with the knowledge base: the library's entry point.
///
/// The boundary is discretised at the size of `opts` (the domain's own by
/// default), the rules of `kb` mesh it from the boundary inward, one
/// quadrilateral at a time, the fallbacks close the loops the rules leave,
/// and the mesh is smoothed (Eq. 4), cleaned up and checked before it is
/// returned. `progress` is called with the number of elements made after
/// each step of the recursion.
///
/// The same domain, knowledge base and options give the same mesh and
/// trace, on any machine and number of cores. A domain the rules cannot
/// finish is meshed whole by the last resort (triangles split into three
/// quadrilaterals) and says so in [`MeshResult::stopped_short`]; a mesh is
/// returned only if it passed its check (every element convex and
/// positive, the boundary followed, the area covered once).
///
/// # Errors
///
/// [`Error::Option`] for an option that cannot be used (a size that is
/// not a positive number, or so small that the domain would need more
/// than five million elements), [`Error::Domain`] for a boundary that
/// cannot be discretised at that size, [`Error::Kb`] when a rule of the
/// knowledge base fails (an exception, a runaway, an answer the host
/// cannot read) and [`Error::Mesh`] when the recursion stops on a fault
/// of its own; [`Error::Fallback`] and [`Error::Check`] are defects,
/// never seen on a valid domain.
///
/// # Examples
///
/// ```
/// use freemesh::{mesh_domain, Domain, Error, KnowledgeBase, Options, RunOption, OptionError};
/// // an L-shaped plate: a concave corner for the rules to work round
/// let domain = Domain::from_json_str(
///     r#"{"size": 0.5, "outer": {"points": [[0,0],[4,0],[4,2],[2,2],[2,4],[0,4]]}}"#,
/// ).unwrap();
/// let mut kb = KnowledgeBase::builtin().unwrap();
/// let mut steps = 0;
/// let result = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| steps += 1).unwrap();
/// assert!(steps > 0);
/// // the elements cover the L's area, 12, once
/// let area: f64 = (0..result.mesh.quads().len())
///     .map(|q| {
///         let p = result.mesh.quad_points(q);
///         (0..4).map(|i| p[i].perp_dot(p[(i + 1) % 4]) / 2.0).sum::<f64>()
///     })
///     .sum();
/// assert!((area - 12.0).abs() < 1e-9);
/// assert!(result.quality.min_angle > 45.0);
/// // the trace says which rule made each element
/// assert!(!result.trace.is_empty());
///
/// // an option out of range is a typed error, naming the option
/// let bad = Options::default().with_size(Some(-1.0));
/// match mesh_domain(&domain, &mut kb, &bad, &mut |_| {}) {
///     Err(Error::Option(OptionError::NotPositive { option, value })) => {
///         assert_eq!((option, value), (RunOption::Size, -1.0));
///     }
///     other => panic!("expected an option error, got {other:?}"),
/// }
/// ```
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

pub(crate) fn check_options(opts: &Options) -> Result<(), Error> {
    match opts.max_size {
        Some(m) if !(m.is_finite() && m > 0.0) => Err(OptionError::NotPositive {
            option: RunOption::MaxSize,
            value: m,
        }
        .into()),
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
    let prepared = prepare_run(domain, run_boundary, kb, opts)?;
    mesh_prepared(kb, prepared, progress)
}

/// A prepared run meshed to the end: the recursion, then `finish`.
pub(crate) fn mesh_prepared(
    kb: &mut KnowledgeBase,
    prepared: PreparedRun,
    progress: &mut dyn FnMut(usize),
) -> Result<MeshResult, Error> {
    let mut run = Run::start(kb, prepared);
    run.recursion(progress)?;
    run.finish()
}

/// A run in progress: the recursion can be taken a step at a time (the
/// REPL) or to the end, and `finish` does the rest, the last resort
/// included.
pub struct Run<'k> {
    mesher: Mesher<'k>,
    domain: Domain,
    /// The boundary as it was discretised, for the last resort.
    boundary: Discretised,
    size: f64,
    opts: Options,
    kb_before: KbStats,
    t0: Instant,
    prepare: f64,
    /// Why the recursion stopped short, if it did: the last resort meshes
    /// the domain when the run is finished.
    stopped: Option<String>,
    /// A block layout's run whose finish judges the blocks by their
    /// corners and taper alone (`finish_by_corners_and_taper`).
    corners_and_taper: bool,
}

/// Everything of a run's start that can fail, done with the KB only
/// borrowed: the settings read, the boundary kept for the last resort.
pub struct PreparedRun {
    prepared: Prepared,
    domain: Domain,
    boundary: Discretised,
    size: f64,
    opts: Options,
    kb_before: KbStats,
    t0: Instant,
    /// The interior's limit where the run is graded for a coarse boundary
    /// without a `max_size` (see `coarse_boundary_limit`).
    grown_to: Option<f64>,
}

/// Prepares a run over a domain whose boundary `discretise_for_run` made
/// ready with the size of `opts`: reads the settings from the KB.
pub fn prepare_run(
    domain: &Domain,
    run_boundary: RunBoundary,
    kb: &mut KnowledgeBase,
    opts: &Options,
) -> Result<PreparedRun, Error> {
    check_options(opts)?;
    let kb_before = kb.stats;
    let t0 = Instant::now();
    // the settings read once, here, and handed to the stages
    let settings = kb.settings()?;
    let RunBoundary {
        disc, size, area, ..
    } = with_kb_bounds(domain, run_boundary, &settings)?;
    let boundary = disc.clone();
    let user_limit = opts.max_size.or(domain.max_size());
    let grown_to = match user_limit {
        Some(_) => None,
        None => coarse_boundary_limit(&disc, size, settings.host.coarse_boundary_grading),
    };
    let prepared = Prepared::new(disc, size, area, settings).with_max_size(user_limit.or(grown_to));
    Ok(PreparedRun {
        prepared,
        domain: domain.clone(),
        boundary,
        size,
        opts: opts.clone(),
        kb_before,
        t0,
        grown_to,
    })
}

/// Without a `max_size`, the format lets the interior grow as far as a
/// smooth transition from the boundary allows. Where fixed segment counts
/// make boundary segments coarser than `factor` times the size
/// (`bound(coarse_boundary_grading, F)`), the interior may grow to the
/// longest of them, so that the elements along a coarse edge are not
/// flattened to the size (aspect ratios past 10, size jumps past 2, three
/// times the elements of a mesh that follows the boundary). Returns that
/// limit, or None (a uniform run at the size, as where every count comes
/// from the size: those segments are at most 1.5 times it).
fn coarse_boundary_limit(disc: &Discretised, size: f64, factor: f64) -> Option<f64> {
    if factor <= 0.0 {
        return None;
    }
    let longest = disc.segment_lengths().fold(0.0, f64::max);
    (longest > factor * size).then_some(longest)
}

impl PreparedRun {
    /// The settings the run read from the KB.
    pub(crate) fn settings(&self) -> &crate::settings::Settings {
        self.prepared.settings()
    }

    /// Whether the run is graded for a coarse boundary only (no
    /// `max_size`; see `coarse_boundary_limit`).
    pub(crate) fn is_graded_for_coarse_boundary(&self) -> bool {
        self.grown_to.is_some()
    }

    /// How many elements the boundary's segments ask for: the domain's
    /// area over the square of their mean length (as many as a mesh has
    /// whose elements follow the boundary's segment lengths inward).
    pub(crate) fn elements_the_boundary_asks(&self) -> f64 {
        let (length, count) =
            (self.boundary.segment_lengths()).fold((0.0, 0), |(l, n), x| (l + x, n + 1));
        let mean = length / count.max(1) as f64;
        if mean > 0.0 {
            self.domain.area() / (mean * mean)
        } else {
            0.0
        }
    }

    /// The trace's words where the run is graded for a coarse boundary
    /// without a `max_size`.
    pub(crate) fn grown_to_words(&self) -> Option<String> {
        let limit = self.grown_to?;
        let factor = self.prepared.settings().host.coarse_boundary_grading;
        Some(format!(
            "no max_size, boundary segments up to {:.3} times the size (over bound(coarse_boundary_grading, {factor})): the interior may grow to {limit:.6}",
            limit / self.size
        ))
    }

    /// The run's clock and its count of KB questions started again, for
    /// a run started after other work with the same KB (the blocks
    /// tried first): its stages then count its own time only.
    pub(crate) fn restart_clock(&mut self, kb: &KnowledgeBase) {
        self.kb_before = kb.stats;
        self.t0 = Instant::now();
    }
}

impl<'k> Run<'k> {
    /// Starts a prepared run.
    pub fn start(kb: &'k mut KnowledgeBase, p: PreparedRun) -> Run<'k> {
        let mut mesher = Mesher::start_from(kb, p.prepared);
        mesher.set_record_trace(p.opts.trace);
        mesher.set_self_check(p.opts.self_check);
        let prepare = p.t0.elapsed().as_secs_f64();
        Run {
            mesher,
            domain: p.domain,
            boundary: p.boundary,
            size: p.size,
            opts: p.opts,
            kb_before: p.kb_before,
            t0: p.t0,
            prepare,
            stopped: None,
            corners_and_taper: false,
        }
    }

    /// The recursion under way.
    pub fn mesher(&mut self) -> &mut Mesher<'k> {
        &mut self.mesher
    }

    /// The recursion under way, to read.
    pub fn mesher_ref(&self) -> &Mesher<'k> {
        &self.mesher
    }

    /// Ends the run, handing back the knowledge base.
    pub fn into_kb(self) -> &'k mut KnowledgeBase {
        self.mesher.into_kb()
    }

    /// Why the recursion stopped short, if it did.
    pub fn stopped(&self) -> Option<&str> {
        self.stopped.as_deref()
    }

    /// One step of the recursion; false when it is done, or stopped
    /// short (the rules and the fallbacks stuck, or a runaway: `finish`
    /// then takes the last resort). A fault of the KB is an error.
    pub fn step(&mut self) -> Result<bool, Error> {
        if self.stopped.is_some() {
            return Ok(false);
        }
        match self.mesher.step() {
            Ok(more) => Ok(more),
            Err(e @ (MeshError::Stuck { .. } | MeshError::Runaway(_))) => {
                self.stopped = Some(e.to_string());
                Ok(false)
            }
            Err(e) => Err(e.into()),
        }
    }

    /// The recursion to the end (see `step`).
    pub fn recursion(&mut self, progress: &mut dyn FnMut(usize)) -> Result<(), Error> {
        while self.step()? {
            progress(self.mesher.mesh().quads.len());
        }
        Ok(())
    }

    /// Has a block layout's finish judge its blocks by their corners and
    /// taper alone (`ElementBounds::for_layout`; blocks/layouts.rs says
    /// which layouts).
    pub(crate) fn finish_by_corners_and_taper(&mut self) {
        self.corners_and_taper = self.opts.layout;
    }

    /// The bounds its finish aims for: the elements' own, or a layout's
    /// blocks' (`finish_by_corners_and_taper`).
    fn finish_bounds(&self) -> ElementBounds {
        let element = self.mesher.settings().element;
        if self.corners_and_taper {
            element.for_layout()
        } else {
            element
        }
    }

    /// Finishes a run whose recursion is done: drops the nodes no element
    /// kept (the trace's ids follow), smooths, cleans up, checks and
    /// measures the mesh. Where the recursion stopped short, or made a
    /// mesh that fails its check, the last resort meshes the whole domain
    /// (see fallback/triangles.rs). The run is left empty.
    pub fn finish(&mut self) -> Result<MeshResult, Error> {
        let mut r = self.finish_run()?;
        r.stats.thin_wall_edges = self.boundary.thin_wall_edges;
        r.stats.near_line_edges = self.boundary.near_line_edges;
        Ok(r)
    }

    fn finish_run(&mut self) -> Result<MeshResult, Error> {
        let recursion = self.t0.elapsed().as_secs_f64() - self.prepare;
        // a boundary or line segment the rules' elements lost: said before
        // the outcome is taken, so the debug picture shows where
        // (where the rules stopped short, the open loops' segments have no
        // element yet: those are closed below, not mended)
        let lost_segments = match self.stopped {
            Some(_) => Vec::new(),
            None => check::lost_segments(self.mesher.mesh()),
        };
        let reason = match (self.stopped.take(), lost_segments.first()) {
            (Some(reason), _) => reason,
            (None, Some(&(a, b))) => {
                Error::Check(MeshCheckError::BoundaryNotFollowed(a, b)).to_string()
            }
            (None, None) => {
                let bounds = self.finish_bounds();
                let outcome = self.mesher.take_outcome();
                let kb_after = self.mesher.kb().stats;
                match finish_mesh(outcome, &bounds, &self.opts, self.kb_before, kb_after) {
                    Ok(mut r) => {
                        r.phases.prepare = self.prepare;
                        r.phases.recursion = recursion;
                        return Ok(r);
                    }
                    Err(e @ Error::Check(_)) => e.to_string(),
                    Err(e) => return Err(e),
                }
            }
        };
        // the state where meshing stopped, kept for whoever asks why
        let stopped_short = StoppedShort {
            picture: crate::io::output::to_svg(
                self.mesher.mesh(),
                &self.mesher.front_node_loops(),
                "stopped",
            ),
            trace: self.mesher.trace().to_vec(),
            reason: reason.clone(),
        };
        if !lost_segments.is_empty() {
            if let Some(r) = self.reopen_lost_segments(&lost_segments, &reason, &stopped_short)? {
                return Ok(r);
            }
        }
        if let Some(r) = self.close_open_loops(&reason, &stopped_short)? {
            return Ok(r);
        }
        self.last_resort(reason, stopped_short)
    }
}
