//! Easing: where a corner is still outside the window after smoothing and
//! clean-up, the free nodes within two rings of its element move, a few
//! rounds over, to lower how far the corners round them come near the
//! window's edges (the squared degrees past a margin inside it). The
//! neighbours make room that the bad corner's own nodes then take; a node
//! moving alone cannot, since its own worst corner decides (untangle.rs).
//! No move makes a corner round the node worse than the worst there was,
//! nor takes an element past the size and shape bounds it kept.

use crate::element_quality::{badness_of, fixed_tips, size_shape_excess, worst_around};
use crate::geometry::quad_angles;
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::smoothing::compass::compass_search;
use crate::smoothing::strips::{element_neighbours, node_elements};

/// How far inside the window (degrees) a corner starts to count.
const MARGIN: f64 = 6.0;
/// Rounds over the nodes round the bad elements.
const ROUNDS: usize = 8;

/// Eases the nodes round the elements with a corner outside the window;
/// returns the moves kept (0, and the mesh untouched, when there is none).
pub fn ease_bad_corners(mesh: &mut Mesh, bounds: &ElementBounds) -> usize {
    let bad: Vec<u32> = (0..mesh.quads.len() as u32)
        .filter(|&q| badness_of(mesh, q as usize, bounds) > 0.0)
        .collect();
    if bad.is_empty() {
        return 0;
    }
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
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
    let area = |m: &Mesh, q: u32| crate::element_quality::quad_area(m, q);
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
                    .map(|&q| size_shape_excess(m, q, &neighbours[q as usize], &|e| area(m, e), bounds))
                    .fold(0.0, f64::max)
            };
            let shape_cap = shape(mesh).max(1.0);
            let (worst, _) = worst_around(mesh, &around[n], bounds);
            let start = (worst, strain(mesh, &around[n], bounds));
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
                    let s = strain(m, &around[n], bounds);
                    if s >= best.1 || shape(m) > shape_cap + 1e-9 {
                        return None;
                    }
                    Some((w, s))
                },
                |w, best| w.0 < best.0 - 1e-9 || (w.0 <= best.0 + 1e-9 && w.1 < best.1 * (1.0 - 1e-6)),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use glam::DVec2;

    /// A 3 x 1 row of unit squares over a 3 x 1 row, the middle nodes of
    /// the shared line pushed sideways so that the elements are sheared
    /// past the window; the top and bottom rows' outer nodes are fixed.
    #[test]
    fn a_sheared_corner_is_eased_back_into_the_window() {
        let mut m = Mesh::default();
        // 4 x 3 grid of nodes, x = 0..3, y = 0..2
        for y in 0..3 {
            for x in 0..4 {
                let kind = if y == 1 && (x == 1 || x == 2) {
                    NodeKind::Interior
                } else {
                    NodeKind::Boundary
                };
                m.add_node(DVec2::new(x as f64, y as f64), kind);
            }
        }
        let id = |x: u32, y: u32| y * 4 + x;
        for y in 0..2 {
            for x in 0..3 {
                m.quads.push([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
        m.nodes[id(1, 1) as usize].x += 0.55;
        m.nodes[id(2, 1) as usize].x += 0.55;
        let bounds = ElementBounds::new(45.0, 135.0, 10.0, 10.0, 2.0).unwrap();
        let worst = |m: &Mesh| {
            (0..m.quads.len())
                .map(|q| badness_of(m, q, &bounds))
                .fold(0.0, f64::max)
        };
        assert!(worst(&m) > 0.0);
        assert!(ease_bad_corners(&mut m, &bounds) > 0);
        assert_eq!(worst(&m), 0.0);
    }
}
