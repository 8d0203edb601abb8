//! Mapping elements generated automatically (the paper's Fig. 17,
//! `freemesh mesh --blocks`): the rules mesh the domain at a coarse size
//! (`bound(block_size, K)` element sizes), each of those elements becomes
//! a block, the interval assignment gives every block edge its element
//! count (intervals.rs), and each block is meshed as a mapping element by
//! transfinite interpolation (mapping.rs). Most of the mesh is then a
//! structured grid; irregular nodes sit only where blocks meet at the
//! layout's irregular corners. Smoothing and clean-up then run over the
//! whole mesh, across the blocks' edges, as after the recursion.
//!
//! Blocks whose opposite sides cannot agree (fixed counts, the paper's
//! Fig. 18) are meshed free together by the rules (free_blocks.rs).
//! Where no layout can be made, or the free mesh does better, the domain
//! is meshed free by the rules at its size; the trace's first step says
//! which mesh was kept and what each layout gave.

mod coarser;
mod finishing;
mod four_sided;
mod free_blocks;
mod in_order;
pub mod intervals;
mod layouts;
mod mapping;
mod retries;
mod score;

use crate::input::curves::Curve;
use crate::input::domain::Domain;
use crate::kb::KnowledgeBase;
use crate::pipeline::{discretise_for_run, prepare_run, Error, MeshResult, Options};
use crate::recursion::Outcome;
use crate::report::trace::{By, TraceStep};
use intervals::{Chords, FixedCount};
use layouts::Layouts;
pub use score::irregular_nodes;
use score::{sharpest_input_corner, Score};

/// Meshes `domain` in blocks (see the module's comment).
pub fn mesh_in_blocks(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    progress: &mut dyn FnMut(usize),
) -> Result<MeshResult, Error> {
    let started = std::time::Instant::now();
    let settings = kb.settings()?;
    let kb_before = kb.stats;
    let mut tried: Vec<String> = Vec::new();
    // the time not spent on the kept mesh's own finishing
    let blocks_time =
        |r: &MeshResult| started.elapsed().as_secs_f64() - r.phases.smoothing - r.phases.check;
    let best = match best_block_mesh(domain, kb, opts, &settings, kb_before, 1.0, &mut tried)? {
        Some((b, mut r, name)) if b.outside == 0 => {
            progress(r.mesh.quads.len());
            r.phases.blocks = blocks_time(&r);
            return Ok(with_first_step(r, &name, tried));
        }
        other => other,
    };
    let before_free = started.elapsed().as_secs_f64();
    crate::pipeline::check_options(opts)?;
    let prepared = prepare_run(domain, discretise_for_run(domain, opts.size)?, kb, opts)?;
    // the free mesh's grading for a coarse boundary, told
    tried.extend(prepared.grown_to_words());
    let mut free = crate::pipeline::mesh_prepared(kb, prepared, progress)?;
    let score = Score::of(&free, &settings, domain);
    if let Some((_, mut r, name)) = best.filter(|(b, _, _)| *b < score) {
        r.phases.blocks = blocks_time(&r);
        return Ok(with_first_step(r, &name, tried));
    }
    free.phases.blocks = before_free;
    tried.push(format!("free: {}", score.words()));
    Ok(with_first_step(free, "free", tried))
}

/// Meshes `domain` by the rules for a uniform run without `--blocks`:
/// in blocks first (`bound(blocks_first, 1)`), on the layouts with at
/// most `bound(blocks_when_out_of_bounds, S)` of their blocks free (0:
/// never), a layout's mesh within the bounds kept and no free mesh made;
/// else free by the rules, as `mesh_boundary` does (from `boundary`
/// where the caller made it ready), and where that mesh has elements
/// outside the bounds, the better of the two kept, then the retries of
/// `retry_bound/3`. The trace's first step says which mesh was kept, and
/// what each tried gave. A graded run, and a domain with cracks, are
/// meshed free. Where the mesh kept has many more elements than the
/// domain's area asks for, it is meshed again coarser (coarser.rs).
pub fn mesh_free_then_blocks(
    domain: &Domain,
    boundary: Option<crate::pipeline::RunBoundary>,
    kb: &mut KnowledgeBase,
    opts: &Options,
    progress: &mut dyn FnMut(usize),
) -> Result<MeshResult, Error> {
    let started = std::time::Instant::now();
    let run = mesh_uniform_run(domain, boundary, kb, opts, Retries::Tried, progress)?;
    let first_run = started.elapsed().as_secs_f64();
    coarser::coarser_when_over(domain, kb, opts, run, first_run)
}

/// What `mesh_uniform_run` made, with the settings it went by and
/// whether it was graded by a `max_size` (coarser.rs asks both).
struct UniformRun {
    result: MeshResult,
    settings: crate::settings::Settings,
    graded: bool,
    /// Whether its mesh fell short and the retries were made.
    retried: bool,
    /// Where the run was graded for a coarse boundary, the elements its
    /// segment lengths ask for (the size alone asks for more).
    boundary_asks: Option<f64>,
}

/// Whether a uniform run meshes the domain again with the variants of
/// `retry_bound/3` where its mesh falls short.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Retries {
    Tried,
    /// Not tried: a coarser run where the first run made them (a retry
    /// builds its engine from the user's files and its own bounds alone,
    /// so they would be the first run's again, mesh for mesh), or where
    /// the first run is within the bounds (a variant is kept then only
    /// within them as made).
    LeftToTheFirstRun,
}

/// `mesh_free_then_blocks` but for the coarser meshes of coarser.rs.
fn mesh_uniform_run(
    domain: &Domain,
    boundary: Option<crate::pipeline::RunBoundary>,
    kb: &mut KnowledgeBase,
    opts: &Options,
    retries: Retries,
    progress: &mut dyn FnMut(usize),
) -> Result<UniformRun, Error> {
    let started = std::time::Instant::now();
    let kb_before = kb.stats;
    let boundary = match boundary {
        Some(b) => b,
        None => {
            crate::pipeline::check_options(opts)?;
            discretise_for_run(domain, opts.size)?
        }
    };
    let mut retried = false;
    if boundary.graded_by_a_max_size(domain, opts) {
        let (result, settings) =
            retries::graded_run(domain, boundary, kb, opts, retries, &mut retried, progress)?;
        return Ok(UniformRun {
            result,
            settings,
            graded: true,
            retried,
            boundary_asks: None,
        });
    }
    // graded by a coarse boundary only, the run is a uniform one's:
    // blocks, retries and all (the blocks follow the boundary's counts)
    let prepared = prepare_run(domain, boundary, kb, opts)?;
    let settings = prepared.settings().clone();
    let boundary_asks = prepared
        .is_graded_for_coarse_boundary()
        .then(|| prepared.elements_the_boundary_asks());
    let result = choose_uniform_mesh(
        domain,
        prepared,
        &settings,
        retries,
        &mut retried,
        started,
        kb_before,
        kb,
        opts,
        progress,
    )?;
    Ok(UniformRun {
        result,
        settings,
        graded: false,
        retried,
        boundary_asks,
    })
}

/// The body of `mesh_uniform_run`: blocks first, free, retries, from a
/// prepared run (`started` and `kb_before` taken before it was prepared);
/// `retried` is set where the retries are made.
#[allow(clippy::too_many_arguments)]
fn choose_uniform_mesh(
    domain: &Domain,
    mut prepared: crate::pipeline::PreparedRun,
    settings: &crate::settings::Settings,
    retries: Retries,
    retried: &mut bool,
    started: std::time::Instant,
    kb_before: crate::kb::KbStats,
    kb: &mut KnowledgeBase,
    opts: &Options,
    progress: &mut dyn FnMut(usize),
) -> Result<MeshResult, Error> {
    let coarse_boundary = prepared.is_graded_for_coarse_boundary();
    let share = settings.host.blocks_when_out_of_bounds;
    let mut tried: Vec<String> = prepared.grown_to_words().into_iter().collect();
    // the blocks first: where a layout's mesh is within the bounds, no
    // free mesh is made (None: not tried)
    let mut first_blocks = None;
    if settings.host.blocks_first > 0.0 && share > 0.0 && !has_cracks(domain) {
        tried.push(format!(
            "blocks first (bound(blocks_first, {}))",
            settings.host.blocks_first
        ));
        let best = best_block_mesh(domain, kb, opts, settings, kb_before, share, &mut tried)?;
        if let Some((b, mut r, name)) = best {
            if b.outside == 0 {
                match score::blocks_over_free_words(&r, &prepared, settings) {
                    None => {
                        r.phases.blocks =
                            started.elapsed().as_secs_f64() - r.phases.smoothing - r.phases.check;
                        progress(r.mesh.quads.len());
                        return Ok(with_first_step(r, &name, tried));
                    }
                    Some(words) => tried.push(words),
                }
            }
            first_blocks = Some(Some((b, r, name)));
        } else {
            first_blocks = Some(None);
        }
        prepared.restart_clock(kb);
    }
    let before_free = started.elapsed().as_secs_f64();
    let mut free = crate::pipeline::mesh_prepared(kb, prepared, progress)?;
    if share <= 0.0 {
        return Ok(told(free, tried));
    }
    let score = Score::of(&free, settings, domain);
    if score.outside == 0 {
        // blocks within the bounds but with many elements (above): kept
        // unless they have many more than the free mesh
        match first_blocks.take() {
            Some(Some((b, mut r, name))) if b.outside == 0 => {
                let over = settings.host.blocks_over_free;
                let (blocks, free_count) = (r.mesh.quads.len(), free.mesh.quads.len());
                let keep_blocks = (blocks as f64) <= over * free_count as f64;
                tried.push(format!(
                    "free: within the bounds, {free_count} elements, {} irregular nodes: {}",
                    score.irregular,
                    if keep_blocks {
                        format!("the blocks kept (at most bound(blocks_over_free, {over}) times its elements)")
                    } else {
                        format!("kept (the blocks have over bound(blocks_over_free, {over}) times its elements)")
                    }
                ));
                if keep_blocks {
                    r.phases.blocks =
                        started.elapsed().as_secs_f64() - r.phases.smoothing - r.phases.check;
                    progress(r.mesh.quads.len());
                    return Ok(with_first_step(r, &name, tried));
                }
                free.phases.blocks = before_free;
                return Ok(with_first_step(free, "free", tried));
            }
            other => first_blocks = other,
        }
        if first_blocks.is_some() {
            // the blocks' time before it, and what they gave, told
            free.phases.blocks = before_free;
            tried.push(format!(
                "free: within the bounds, {} irregular nodes",
                score.irregular
            ));
            return Ok(with_first_step(free, "free", tried));
        }
        return Ok(told(free, tried));
    }
    tried.push(format!(
        "free: {}; blocks tried (bound(blocks_when_out_of_bounds, {share}))",
        score.words()
    ));
    // a layout mostly of free blocks would mesh the domain free again
    let best = match first_blocks {
        Some(best) => best,
        None => best_block_mesh(domain, kb, opts, settings, kb_before, share, &mut tried)?,
    };
    let best = best.filter(|(b, _, _)| *b < score);
    // (a coarser run leaves them to the first run: the coarser pass's
    // own line says so)
    let (best, retries_time, retry_kept) = if retries == Retries::Tried {
        let short = retries::Short {
            free: &free.mesh,
            best,
            score,
            blocks_share: share,
            coarse_boundary,
            graded: false,
        };
        retries::retry_where_short(domain, short, settings, opts, kb, &mut tried, retried)?
    } else {
        (best, 0.0, false)
    };
    match best {
        Some((_, mut r, name)) => {
            let ph = &mut r.phases;
            let own = ph.own();
            let before_retries = started.elapsed().as_secs_f64() - retries_time;
            if retry_kept {
                // the kept mesh's own stages are among the retries
                ph.blocks = before_retries;
                ph.retries = retries_time - own;
            } else {
                ph.blocks = before_retries - ph.smoothing - ph.check;
                ph.retries = retries_time;
            }
            progress(r.mesh.quads.len());
            Ok(with_first_step(r, &name, tried))
        }
        None => {
            // the blocks', before the free mesh and after it
            free.phases.blocks = started.elapsed().as_secs_f64() - retries_time - free.phases.own();
            free.phases.retries = retries_time;
            Ok(with_first_step(free, "free", tried))
        }
    }
}

/// The free mesh as it is, or with a first step telling what was
/// decided before it (the run graded for a coarse boundary).
fn told(free: MeshResult, tried: Vec<String>) -> MeshResult {
    if tried.is_empty() {
        free
    } else {
        with_first_step(free, "free", tried)
    }
}

/// Whether an inner line of `domain` is a crack (such a domain is meshed
/// free, never in blocks).
fn has_cracks(domain: &Domain) -> bool {
    domain.lines.iter().any(|l| l.crack)
}

/// Whether an edge of `domain` has a fixed segment count (a retry of
/// `retry_bound/3` may need one: `retry_needs(V, fixed_counts)`).
fn has_fixed_counts(domain: &Domain) -> bool {
    domain
        .chains()
        .any(|c| c.edges.iter().any(|e| e.segments.is_some()))
}

/// The block meshes finished in order until one is within the bounds:
/// the four-sided patches and the layouts (layouts.rs), all three in
/// order of their irregular nodes, or, where the first layout has more
/// than `bound(finer_layouts_up_to, K)` blocks, from the coarsest, each
/// made only when the meshes before it fell short. The best of
/// them (fewest elements outside the bounds, then fewest irregular
/// nodes) with its action in the trace's first step, or none; what each
/// gave is added to `tried`. A layout with more than `max_free_share` of
/// its blocks free is dropped.
fn best_block_mesh(
    domain: &Domain,
    kb: &mut KnowledgeBase,
    opts: &Options,
    settings: &crate::settings::Settings,
    kb_before: crate::kb::KbStats,
    max_free_share: f64,
    tried: &mut Vec<String>,
) -> Result<Option<(Score, MeshResult, String)>, Error> {
    if has_cracks(domain) {
        tried.push("a domain with cracks is meshed free".into());
        return Ok(None);
    }
    let size = opts.size.unwrap_or(domain.size());
    let max_pairs = settings.host.four_sided_pairs as usize;
    let four_sided = (max_pairs > 0)
        .then(|| four_sided::outcome(domain, size, max_pairs, &settings.element))
        .flatten()
        .map(|made| {
            made.map(|(o, pairs)| {
                (
                    format!("four_sided({pairs})"),
                    format!("four sides in patches round {pairs} pairs of irregular nodes"),
                    o,
                )
            })
        });
    let mut layouts = Layouts::new(domain, kb, opts, settings, (max_free_share, blocks_of));
    let first = layouts.next();
    let blocks = first
        .as_ref()
        .and_then(|c| c.as_ref().ok())
        .map_or(0, |(_, _, o)| o.mesh.block_count());
    let up_to = settings.host.finer_layouts_up_to;
    let by = finishing::Finishing {
        domain,
        settings,
        opts,
        kb_before,
    };
    let best = if blocks as f64 > up_to {
        // the finer layouts only where this one's mesh falls short
        tried.push(format!(
            "the first layout has {blocks} blocks, over bound(finer_layouts_up_to, {up_to}): the finer ones made only where its mesh falls short"
        ));
        by.best_finished(
            four_sided.into_iter().chain(first).chain(&mut layouts),
            tried,
        )
    } else {
        // every layout made, their block meshes in order of their
        // irregular nodes (among equals the four-sided patches, then the
        // coarser layout, first; the lines of those that gave none first
        // of all), each finished meanwhile on the spare core where the
        // finest layout is made on it
        let helper = layouts.made_away();
        by.best_made_first(
            four_sided.into_iter().chain(first).chain(&mut layouts),
            helper,
            tried,
        )
    };
    let kb = layouts.stop();
    // the questions of every layout made, the kept one's finishing too
    best.map(|best| {
        best.map(|(score, mut r, name)| {
            r.kb_stats = kb.stats.since(&kb_before);
            (score, r, name)
        })
    })
}

/// A `--blocks` run's trace with its first step: the mesh kept,
/// `layout(F)` (blocks of F element sizes) or `free`, and what each
/// layout tried gave (none where the run keeps no trace).
fn with_first_step(mut r: MeshResult, action: &str, tried: Vec<String>) -> MeshResult {
    if !r.trace.is_empty() {
        r.trace.insert(
            0,
            TraceStep {
                step: 0,
                edge: [-1, -1],
                angles: Default::default(),
                feature: "block".into(),
                action: action.into(),
                by: By::Block,
                redesign: tried,
                element: vec![],
            },
        );
        renumber(&mut r.trace);
        // each step is one later now: the vetoes before it too
        for v in &mut r.vetoes {
            v.before_step += 1;
        }
    }
    r
}

/// The trace's steps numbered from 1 in their order.
fn renumber(trace: &mut [TraceStep]) {
    for (k, t) in trace.iter_mut().enumerate() {
        t.step = k + 1;
    }
}

/// The fine mesh of a layout, with its trace: the layout's steps, then a
/// step a block. Err says why no block mesh is made.
fn blocks_of(
    layout: MeshResult,
    domain: &Domain,
    size: f64,
    kb: &mut KnowledgeBase,
    record_trace: bool,
    max_free_share: f64,
) -> Result<Outcome, String> {
    let coarse = &layout.mesh;
    let chords: Chords = intervals::chords(&coarse.quads);
    let on_curve = mapping::boundary_curves(coarse, domain)
        .ok_or("a block edge on the boundary lies on no input curve")?;
    let targets: Vec<f64> = chords
        .edges
        .iter()
        .map(|&(a, b)| {
            let straight = (coarse.nodes[a as usize] - coarse.nodes[b as usize]).length();
            let along = on_curve.get(&(a, b)).map_or(straight, |c| c.length());
            along / size
        })
        .collect();
    let fixed = fixed_counts(domain, &chords, &on_curve);
    let (counts, apart) = intervals::assign(&chords, &targets, &fixed, true).map_err(|d| {
        format!(
            "the blocks' sides cannot share the counts: an input edge fixed at {} segments \
                 crosses block chords that need {}",
            d.count, d.chords_give
        )
    })?;
    // each layout edge's count: its chord's, or its own where a fixed
    // count disagreed; a block whose opposite sides then differ is free
    let mut edge_counts: Vec<usize> = (0..chords.edges.len())
        .map(|e| counts[chords.chord_of[e]])
        .collect();
    for &(e, n) in &apart {
        edge_counts[e] = n;
    }
    let mut free: Vec<bool> = chords
        .sides
        .iter()
        .map(|s| edge_counts[s[0]] != edge_counts[s[2]] || edge_counts[s[1]] != edge_counts[s[3]])
        .collect();
    free_blocks::even_regions(&chords, &edge_counts, &mut free);
    let n_free = free.iter().filter(|&&f| f).count();
    if n_free as f64 > max_free_share * free.len() as f64 {
        return Err(format!(
            "{n_free} of its {} blocks free, more than the share {max_free_share}",
            free.len()
        ));
    }
    let (mut mesh, edge_nodes) =
        mapping::mesh_blocks(coarse, &chords, &edge_counts, &free, &on_curve)
            .ok_or("a block's opposite sides disagree")?;
    mesh.crack_lines = Vec::new();
    let mut trace = layout.trace;
    if free.iter().any(|&f| f) {
        let steps = free_blocks::mesh_free_regions(
            &mut mesh,
            coarse,
            &chords,
            &edge_nodes,
            &free,
            kb,
            &Options::default()
                .with_size(Some(size))
                .with_max_size(Some(size))
                .with_trace(record_trace),
        )?;
        trace.extend(steps);
    }
    for (bi, q) in coarse.quads.iter().enumerate() {
        if free[bi] {
            continue;
        }
        let s = chords.sides[bi];
        trace.push(map_step(*q, [edge_counts[s[0]], edge_counts[s[1]]]));
    }
    renumber(&mut trace);
    let mut stats = layout.stats;
    stats.blocks = free.iter().filter(|&&f| !f).count();
    let loops = 1 + domain.holes.len() as u32;
    Ok(Outcome {
        area: mesh.boundary_area(loops),
        mesh,
        trace,
        vetoes: layout.vetoes,
        stats,
        grading: None,
    })
}

/// The trace's step for a block meshed as a mapping element: `block ->
/// map(N, M)` over its corners `q` (N segments along its first side, M
/// along its second).
fn map_step(q: [u32; 4], counts: [usize; 2]) -> TraceStep {
    TraceStep {
        step: 0,
        edge: [q[0] as i64, q[1] as i64],
        angles: Default::default(),
        feature: "block".into(),
        action: format!("map({}, {})", counts[0], counts[1]),
        by: By::Block,
        redesign: vec![],
        element: q.iter().map(|&x| x as i64).collect(),
    }
}

/// The blocks numbered from 0 without gaps, in their order, once the mesh
/// is finished: a region of free blocks is one block of the output, and
/// the clean-up may take a small block's last element (an empty group is
/// no use to a reader).
fn number_without_gaps(blocks: &mut [u32]) {
    let mut used = blocks.to_vec();
    used.sort_unstable();
    used.dedup();
    for b in blocks {
        *b = used.binary_search(b).expect("a block in use") as u32;
    }
}

/// Each input edge with a fixed count: the layout edges along it.
fn fixed_counts(
    domain: &Domain,
    chords: &Chords,
    on_curve: &mapping::BoundaryCurves,
) -> Vec<FixedCount> {
    let mut out = Vec::new();
    for chain in domain.chains() {
        for e in &chain.edges {
            let Some(count) = e.segments else { continue };
            let edges: Vec<usize> = chords
                .edges
                .iter()
                .enumerate()
                .filter(|(_, k)| on_curve.get(k).is_some_and(|c| c.curve == e.curve))
                .map(|(i, _)| i)
                .collect();
            if !edges.is_empty() {
                out.push(FixedCount { edges, count });
            }
        }
    }
    out
}

/// A layout edge on the boundary: the input curve it lies on and its
/// ends' parameters.
#[derive(Debug, Clone, Copy)]
pub struct OnCurve {
    /// The input curve.
    pub curve: Curve,
    /// The parameter of the edge's lower-id end.
    pub from: f64,
    /// The parameter of its other end (a circle's: the short way round,
    /// possibly outside [0, 1)).
    pub to: f64,
}

impl OnCurve {
    /// The length along the curve.
    pub fn length(&self) -> f64 {
        self.curve.length() * (self.to - self.from).abs()
    }
}
