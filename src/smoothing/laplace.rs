//! Laplace smoothing (Eq. 4), guarded so that it never spoils an element.
//!
//! Each free node moves to the mean, over the elements round it, of its two
//! neighbours in each element: X_i = 1/(2 N_i) Σ (X_nj + X_ni). A move is
//! kept only if every element round the node stays convex, its worst
//! corner gets no worse than a bound and its aspect and taper do not
//! leave theirs; input boundary nodes never move.
//!
//! In a graded run (`bound(weighted_laplace, 1)`, a graded bound) each
//! neighbour counts by the inverse of the size the field aims for at the
//! middle of the edge to it: in a row of elements growing by r, the
//! plain mean pulls each node toward the coarse side (the sizes even
//! out); weighted by 1/h, the finer side counts r times more, so a node
//! already where the grading puts it stays.

use glam::DVec2;

use crate::element_quality::{badness_of, shape_worst_around, shapes_clearly_within};
use crate::mesh::Mesh;
use crate::settings::ElementBounds;
use crate::size_field::SizeField;
use crate::smoothing::strips::{mark_nodes, take_free_dirty, Nodes};

pub(crate) fn laplace_sweeps(
    mesh: &mut Mesh,
    passes: usize,
    nodes: &Nodes,
    dirty: &mut [bool],
    bounds: &ElementBounds,
    weights: Option<&SizeField>,
) -> usize {
    let around = nodes.around;
    // only dirty nodes are looked at: the same mesh as looking at all
    let mut kept = 0;
    for _ in 0..passes {
        kept = 0;
        for &n in nodes.visit {
            let n = n as usize;
            if !take_free_dirty(mesh, nodes, dirty, n) {
                continue;
            }
            // Eq. 4: the two neighbours of n in each of its elements
            let old = mesh.nodes[n];
            // (plain: every weight 1, each element's pair added first:
            // the plain mean bit for bit)
            let weight = |p: DVec2| weights.map_or(1.0, |field| 1.0 / field.at((old + p) * 0.5));
            let (mut sum, mut total) = (DVec2::ZERO, 0.0);
            for &(q, c) in &around[n] {
                let quad = mesh.quads[q as usize];
                let a = mesh.nodes[quad[(c as usize + 1) % 4] as usize];
                let b = mesh.nodes[quad[(c as usize + 3) % 4] as usize];
                let (wa, wb) = (weight(a), weight(b));
                sum += a * wa + b * wb;
                total += wa + wb;
            }
            let target = sum / total;
            // settled: a move under a thousandth of an element's edge is
            // not worth the checks (and sweeps stop where all are settled)
            let (q0, c0) = around[n][0];
            let edge = mesh.nodes[mesh.quads[q0 as usize][(c0 as usize + 1) % 4] as usize] - old;
            if (target - old).length_squared() <= 1e-6 * edge.length_squared() {
                continue;
            }
            let worst = |mesh: &Mesh| {
                around[n]
                    .iter()
                    .map(|&(q, _)| badness_of(mesh, q as usize, bounds))
                    .fold(0.0, f64::max)
            };
            // the elements' worst before the move, measured only for a
            // move that leaves a corner outside the window (most leave
            // none, and pass whatever it was)
            let mut before: Option<f64> = None;
            // try the full move, then half of it
            for t in [1.0, 0.5] {
                let moved = old + (target - old) * t;
                mesh.nodes[n] = moved;
                let after = worst(mesh);
                let no_worse = after <= 1e-9 || {
                    mesh.nodes[n] = old;
                    let was = *before.get_or_insert_with(|| worst(mesh));
                    mesh.nodes[n] = moved;
                    after <= was.max(0.0) + 1e-9
                };
                if after.is_finite() && no_worse && shapes_allowed(mesh, n, old, &around[n], bounds)
                {
                    kept += 1;
                    mark_nodes(mesh, around[n].iter().map(|&(q, _)| q), dirty);
                    // after half a move the target is still ahead
                    dirty[n] = t < 1.0;
                    break;
                }
                mesh.nodes[n] = old;
            }
        }
    }
    kept
}

/// Whether node `n`, moved from `old`, leaves the shapes of its elements
/// within the aspect and taper bounds, or no further past them than they
/// were: the plain test first, as most moves pass it.
fn shapes_allowed(
    mesh: &mut Mesh,
    n: usize,
    old: DVec2,
    around: &[(u32, u8)],
    bounds: &ElementBounds,
) -> bool {
    if shapes_clearly_within(mesh, around, bounds) {
        return true;
    }
    let after = shape_worst_around(mesh, around, bounds);
    let moved = mesh.nodes[n];
    mesh.nodes[n] = old;
    let before = shape_worst_around(mesh, around, bounds);
    mesh.nodes[n] = moved;
    after <= before.max(1.0) + 1e-9
}
