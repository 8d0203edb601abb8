//! Untangling: each free node next to an element with a corner outside
//! the window (`bound/2`'s lower and upper corner) moves, by a compass search, to where the worst corner round
//! it is best, no element's aspect or taper taken past its bound.

use crate::element_quality::{
    corners_fine, shape_worst_around, shapes_clearly_within, worst_around, worst_around_under,
};
use crate::mesh::Mesh;
use crate::settings::ElementBounds;
use crate::smoothing::compass::compass_search;
use crate::smoothing::strips::{mark_nodes, take_free_dirty, Nodes};

pub(crate) fn untangle_sweeps(
    mesh: &mut Mesh,
    passes: usize,
    nodes: &Nodes,
    dirty: &mut [bool],
    bounds: &ElementBounds,
) -> usize {
    let around = nodes.around;
    let mut moved = 0;
    for _ in 0..passes {
        let mut any = false;
        for &n in nodes.visit {
            let n = n as usize;
            if !take_free_dirty(mesh, nodes, dirty, n) {
                continue;
            }
            if corners_fine(mesh, &around[n], bounds) {
                continue;
            }
            let start = worst_around(mesh, &around[n], bounds);
            if start.0 == 0.0 && start.1 < -0.8 {
                continue; // every corner round it is fine
            }
            let old = mesh.nodes[n];
            // no corner bought with a shape past the bounds
            let shape_allowed = shape_worst_around(mesh, &around[n], bounds).max(1.0) + 1e-9;
            let best = compass_search(
                mesh,
                n,
                &around[n],
                start,
                |m, best| {
                    worst_around_under(m, &around[n], best, bounds).filter(|_| {
                        // the plain test first, as in Laplace's guard
                        shapes_clearly_within(m, &around[n], bounds)
                            || shape_worst_around(m, &around[n], bounds) <= shape_allowed
                    })
                },
                |w, best| w < best,
            );
            mesh.nodes[n] = best;
            if best != old {
                moved += 1;
                any = true;
                mark_nodes(mesh, around[n].iter().map(|&(q, _)| q), dirty);
            }
        }
        if !any {
            break;
        }
    }
    moved
}
