//! Coarsening to the size field (graded runs): where fronts from different
//! sides met, the rules and the fallbacks leave elements much smaller
//! than the size aimed for there. Each element under
//! `bound(graded_collapse_below, F)` times the size the field aims for at
//! its middle, smallest first, is removed by a collapse or a merge of the
//! patch round it (the clean-up's own changes), where the region round it,
//! smoothed, stays as far within every bound as it was: a coarser mesh,
//! never a worse one.

use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::size_field::SizeField;

use super::changes::{changes, Change, Op, Working, Worst};
use super::{best_change, finish, record, sine_rank, CleanupStats};

/// The changes that take elements away.
const OPS: [Op; 5] = [
    Op::Collapse(0),
    Op::Collapse(1),
    Op::Collapse(2),
    Op::Collapse(3),
    Op::Merge,
];

/// How many times the small elements are looked at again (a removal
/// makes its neighbours larger, and may let a next one go).
const ROUNDS: usize = 3;

/// Removes elements under `below` times the size `field` aims for at
/// their middle, where their region stays within the bounds it was
/// within. Returns what it did and the nodes round the changes.
pub fn coarsen_to_field(
    mesh: &mut Mesh,
    field: &SizeField,
    below: f64,
    coarsest_edge: f64,
    bounds: &ElementBounds,
) -> (CleanupStats, Vec<u32>) {
    let mut stats = CleanupStats::default();
    let mut touched: Vec<u32> = Vec::new();
    let mut w = Working::new(mesh, *bounds);
    let share = |w: &Working, q: u32| {
        let p = w.mesh.quad_points(q as usize);
        let area = crate::geometry::polygon_area(&p).abs();
        area.sqrt() / field.at((p[0] + p[1] + p[2] + p[3]) * 0.25)
    };
    let longest_allowed = coarsest_edge * field.max_size();
    for _ in 0..ROUNDS {
        let mut small: Vec<(f64, u32)> = (0..w.mesh.quads.len() as u32)
            .filter(|&q| w.alive[q as usize])
            .map(|q| (share(&w, q), q))
            .filter(|&(s, _)| s < below)
            .collect();
        small.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let before = stats.collapses;
        for (_, q) in small {
            if !w.alive[q as usize] || share(&w, q) >= below {
                continue;
            }
            let candidates: Vec<Change> = OPS.iter().flat_map(|&op| changes(&w, q, op)).collect();
            // kept where no corner gets further outside the window and
            // no shape or size further past its bound; the best corners
            // first
            let done = best_change(
                &mut w,
                &mut None,
                candidates,
                |w, changed| irregular_nodes(w, changed) as f64 + sine_rank(w, changed),
                |w, region| {
                    let worst = w.worst_of(region);
                    (worst, w.shape_excess(region), longest_edge(w, region))
                },
                |(before, shape_before, _): (Worst, f64, f64),
                 (after, shape_after, longest): (Worst, f64, f64)| {
                    (after.0.is_finite()
                        && after.0 <= before.0
                        && shape_after <= shape_before.max(1.0)
                        && longest <= longest_allowed)
                        .then_some(after.1)
                },
            );
            if let Some(done) = done {
                record(&w, &done, &mut stats, &mut touched);
            }
        }
        if stats.collapses == before {
            break;
        }
    }
    finish(w, stats, touched)
}

/// The longest edge of elements `qs`.
fn longest_edge(w: &Working, qs: &[u32]) -> f64 {
    qs.iter()
        .flat_map(|&q| {
            let p = w.mesh.quad_points(q as usize);
            (0..4).map(move |k| (p[(k + 1) % 4] - p[k]).length())
        })
        .fold(0.0, f64::max)
}

/// The interior nodes of elements `qs` whose valence is not 4: a removal
/// that leaves fewer is tried first (collapsing an element across two
/// nodes of valence 3 leaves a regular one).
fn irregular_nodes(w: &Working, qs: &[u32]) -> usize {
    let mut nodes: Vec<u32> = qs
        .iter()
        .flat_map(|&q| w.mesh.quads[q as usize])
        .filter(|&n| w.mesh.kinds[n as usize] == NodeKind::Interior)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
        .iter()
        .filter(|&&n| w.around[n as usize].len() != 4)
        .count()
}
