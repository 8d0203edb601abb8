//! Easing: where an element is still past the bounds after smoothing and
//! clean-up (a corner outside the window, or its size against a
//! neighbour, its aspect or taper), the free nodes within two rings of it
//! move, a few rounds over: first to bring the corners round them nearer
//! the window, then the sizes and shapes nearer their bounds, then to
//! lower how far the corners come near the window's edges (the squared
//! degrees past a margin inside it). The neighbours make room that the
//! bad element's own nodes then take; a node moving alone cannot, since
//! its own worst corner decides (untangle.rs). No move makes the worst
//! corner round a node worse, nor the sizes and shapes past their bounds.

use crate::element_quality::{badness_of, fixed_tips, quad_area, size_shape_excess, worst_around};
use crate::geometry::quad_angles;
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::smoothing::compass::compass_search;
use crate::smoothing::strips::{element_neighbours, node_elements};

/// How far inside the window (degrees) a corner starts to count.
const MARGIN: f64 = 6.0;
/// The share of the size and shape bounds easing aims within (at the
/// bound itself, rounding would leave an element either side of it).
const SHAPE_AIM: f64 = 0.99;
/// Rounds over the nodes round the bad elements.
const ROUNDS: usize = 8;

/// Eases the nodes round the elements with a corner outside the window;
/// returns the moves kept (0, and the mesh untouched, when there is none).
pub fn ease_bad_corners(mesh: &mut Mesh, bounds: &ElementBounds) -> usize {
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    let bad: Vec<u32> = (0..mesh.quads.len() as u32)
        .filter(|&q| {
            badness_of(mesh, q as usize, bounds) > 0.0
                || size_shape_excess(
                    mesh,
                    q,
                    &neighbours[q as usize],
                    &|e| quad_area(mesh, e),
                    bounds,
                ) > 1.0
        })
        .collect();
    if bad.is_empty() {
        return 0;
    }
    // the free nodes within two rings of the bad elements
    let mut near = vec![false; mesh.nodes.len()];
    let mut quads = bad;
    for ring in 0..3 {
        let mut next = Vec::new();
        for &q in &quads {
            for n in mesh.quads[q as usize] {
                if !near[n as usize] {
                    near[n as usize] = true;
                    if ring < 2 {
                        next.extend(around[n as usize].iter().map(|&(e, _)| e));
                    }
                }
            }
        }
        next.sort_unstable();
        next.dedup();
        quads = next;
    }
    let nodes: Vec<usize> = (0..mesh.nodes.len())
        .filter(|&n| near[n] && mesh.kinds[n] == NodeKind::Interior && !around[n].is_empty())
        .collect();
    let mut moved = 0;
    for _ in 0..ROUNDS {
        let mut any = false;
        for &n in &nodes {
            let elements: Vec<u32> = around[n].iter().map(|&(q, _)| q).collect();
            // the elements whose size against a neighbour the move changes
            let mut judged = elements.clone();
            for &q in &elements {
                judged.extend(neighbours[q as usize].iter().flatten());
            }
            judged.sort_unstable();
            judged.dedup();
            let shape = |m: &Mesh| {
                judged
                    .iter()
                    .map(|&q| {
                        size_shape_excess(
                            m,
                            q,
                            &neighbours[q as usize],
                            &|e| quad_area(m, e),
                            bounds,
                        )
                    })
                    .fold(0.0, f64::max)
            };
            // past the size and shape bounds: how far, as a share of them
            let past = |m: &Mesh| (shape(m) - SHAPE_AIM).max(0.0);
            let (worst, _) = worst_around(mesh, &around[n], bounds);
            let start = (worst, past(mesh), strain(mesh, &around[n], bounds));
            let old = mesh.nodes[n];
            let best = compass_search(
                mesh,
                n,
                &around[n],
                start,
                |m, best| {
                    let (w, _) = worst_around(m, &around[n], bounds);
                    if !w.is_finite() || w > best.0 + 1e-9 {
                        return None;
                    }
                    let p = past(m);
                    if p > best.1 + 1e-12 {
                        return None;
                    }
                    Some((w, p, strain(m, &around[n], bounds)))
                },
                // corners first, then size and shape, then room
                |w, best| {
                    w.0 < best.0 - 1e-9
                        || (w.0 <= best.0 + 1e-9
                            && (w.1 < best.1 - 1e-12
                                || (w.1 <= best.1 + 1e-12 && w.2 < best.2 * (1.0 - 1e-6))))
                },
            );
            if best != old {
                mesh.nodes[n] = best;
                moved += 1;
                any = true;
            }
        }
        if !any {
            break;
        }
    }
    moved
}

/// The squared degrees the corners round a node come within `MARGIN` of
/// the window's edges or past them (fixed tips left out).
fn strain(mesh: &Mesh, around: &[(u32, u8)], bounds: &ElementBounds) -> f64 {
    let (lo, hi) = (bounds.lower_corner + MARGIN, bounds.upper_corner - MARGIN);
    around
        .iter()
        .map(|&(q, _)| {
            let skip = fixed_tips(mesh, q as usize, bounds);
            let a = quad_angles(mesh.quad_points(q as usize));
            (0..4)
                .filter(|&i| !skip[i])
                .map(|i| {
                    let over = (a[i] - hi).max(0.0) + (lo - a[i]).max(0.0);
                    over * over
                })
                .sum::<f64>()
        })
        .sum()
}
