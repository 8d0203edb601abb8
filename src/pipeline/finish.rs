//! The stages after the recursion: smoothing (weighted by a graded
//! run's size field where the KB says so), coarsening to that field,
//! clean-up, easing, polish, then the check and the quality figures.

use std::time::Instant;

use crate::cleanup;
use crate::kb::KbStats;
use crate::mesh::Mesh;
use crate::recursion::Outcome;
use crate::report::check;
use crate::report::quality;
use crate::report::trace::{TraceStep, Veto};
use crate::settings::ElementBounds;
use crate::smoothing;

use super::{Error, MeshResult, Options, Phases};

/// How many times at most the clean-up and the smoothing round its
/// changes run after the smoothing stage.
const CLEANUP_ROUNDS: usize = 3;

/// Drops the nodes no element uses; the trace's node ids follow (-1 for
/// a node that is gone).
fn compact_with_trace(mesh: &mut Mesh, trace: &mut [TraceStep], vetoes: &mut [Veto]) {
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
    for v in vetoes {
        v.edge = v.edge.map(remap);
    }
}

/// The stages after the recursion: smoothing, clean-up, check, quality.
pub(crate) fn finish_mesh(
    outcome: Outcome,
    bounds: &ElementBounds,
    opts: &Options,
    kb_before: KbStats,
    kb_after: KbStats,
) -> Result<MeshResult, Error> {
    let Outcome {
        mut mesh,
        mut trace,
        mut vetoes,
        mut stats,
        area,
        grading,
    } = outcome;
    check::check_boundary_followed(&mesh)?;
    compact_with_trace(&mut mesh, &mut trace, &mut vetoes);
    let t0 = Instant::now();
    let weights = grading
        .as_ref()
        .filter(|g| g.weighted_laplace)
        .map(|g| &g.field);
    smoothing::smooth(&mut mesh, opts.smoothing_passes, bounds, weights);
    // the nodes round a change smoothed again
    let smooth_round = |mesh: &mut Mesh, touched: &[u32]| {
        smoothing::smooth_near(mesh, opts.smoothing_passes / 3, touched, bounds, weights)
    };
    // a graded mesh coarsened where it is finer than its field asks
    let mut any_collapse = false;
    if let Some(g) = grading.as_ref().filter(|g| g.collapse_below > 0.0) {
        let (c, touched) = cleanup::coarsen_to_field(
            &mut mesh,
            &g.field,
            g.collapse_below,
            g.coarsest_edge,
            bounds,
        );
        stats.coarsened = c.collapses;
        any_collapse = c.collapses > 0;
        smooth_round(&mut mesh, &touched);
    }
    // where smoothing could not reach the bounds: the elements joined
    // up anew and the nodes round the changes smoothed again, a few
    // times while that changes something (the smoothing after a change
    // can leave a corner the next clean-up mends)
    let mut last_changes: Option<Vec<u32>> = None;
    for _ in 0..CLEANUP_ROUNDS {
        let (cleaned, touched) = cleanup::clean_up(&mut mesh, last_changes.as_deref(), bounds);
        stats.cleanup_flips += cleaned.flips;
        stats.cleanup_collapses += cleaned.collapses;
        stats.cleanup_splits += cleaned.splits;
        any_collapse |= cleaned.collapses > 0;
        if touched.is_empty() {
            break;
        }
        smooth_round(&mut mesh, &touched);
        last_changes = Some(touched);
    }
    // corners still outside the window: their neighbours make room (a node
    // slid along an arc, here or polished, changes the area enclosed: a
    // difference of exactly 0 where none moved)
    let enclosed = mesh.loops_area();
    stats.boundary_slides += smoothing::ease_bad_corners(&mut mesh, bounds).1;
    // (not a layout's: its blocks are polished once mapped)
    if !opts.layout {
        stats.polished = smoothing::polish_past_bounds(&mut mesh, bounds);
    }
    let area = area + (mesh.loops_area() - enclosed);
    if any_collapse {
        compact_with_trace(&mut mesh, &mut trace, &mut vetoes);
    }
    // the finished mesh cut open along its cracks, its regions found
    crate::cracks::open_cracks(&mut mesh);
    mesh.regions = crate::regions::find_regions(&mesh);
    let smoothing = t0.elapsed().as_secs_f64();
    // both only read the mesh: side by side
    let (checked, quality) = std::thread::scope(|scope| {
        let checked = scope.spawn(|| check::check_mesh(&mesh, area));
        let quality = quality::measure_within(&mesh, bounds);
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
    let kb_stats = kb_after.since(&kb_before);
    Ok(MeshResult {
        mesh,
        trace,
        vetoes,
        stats,
        quality,
        kb_stats,
        phases,
        stopped_short: None,
    })
}
