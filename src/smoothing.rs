//! Laplace smoothing (Eq. 4), guarded so that it never spoils an element.
//!
//! Each free node moves to the mean, over the elements round it, of its two
//! neighbours in each element: X_i = 1/(2 N_i) Σ (X_nj + X_ni). A move is
//! kept only if every element round the node stays convex and its worst
//! corner gets no worse than a bound; input boundary nodes never move.

use glam::DVec2;

use crate::geometry::{orient2d, quad_angles};
use crate::mesh::{Mesh, NodeKind};

/// For each node, the elements that use it and the node's corner index.
pub fn node_elements(mesh: &Mesh) -> Vec<Vec<(u32, u8)>> {
    let mut out = vec![Vec::new(); mesh.nodes.len()];
    for (qi, q) in mesh.quads.iter().enumerate() {
        for (c, &n) in q.iter().enumerate() {
            out[n as usize].push((qi as u32, c as u8));
        }
    }
    out
}

/// How far an element's worst corner is from the [45, 135] window
/// (degrees; 0 inside it), or infinity if the element is not convex.
fn badness(q: [DVec2; 4]) -> f64 {
    for i in 0..4 {
        if orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) <= 0.0 {
            return f64::INFINITY;
        }
    }
    // Most elements have every corner inside the window: |cos| <= cos 45
    // at each, tested without trigonometry.
    let inside = (0..4).all(|i| {
        let a = q[(i + 1) % 4] - q[i];
        let b = q[(i + 3) % 4] - q[i];
        let d = a.dot(b);
        2.0 * d * d <= a.length_squared() * b.length_squared()
    });
    if inside {
        return 0.0;
    }
    quad_angles(q)
        .iter()
        .map(|&a| (45.0 - a).max(a - 135.0).max(0.0))
        .fold(0.0, f64::max)
}

/// `passes` sweeps of guarded Laplace smoothing; returns how many moves
/// were kept in the last sweep.
pub fn laplace(mesh: &mut Mesh, passes: usize) -> usize {
    let around = node_elements(mesh);
    // A node none of whose elements changed since it was last looked at
    // would come out the same: only the dirty ones are looked at (the
    // sweeps give the same mesh as looking at every node).
    let mut dirty = vec![true; mesh.nodes.len()];
    let mut kept = 0;
    for _ in 0..passes {
        kept = 0;
        for n in 0..mesh.nodes.len() {
            if !std::mem::take(&mut dirty[n])
                || mesh.kinds[n] != NodeKind::Interior
                || around[n].is_empty()
            {
                continue;
            }
            // Eq. 4: the two neighbours of n in each of its elements
            let mut sum = DVec2::ZERO;
            for &(q, c) in &around[n] {
                let quad = mesh.quads[q as usize];
                sum += mesh.nodes[quad[(c as usize + 1) % 4] as usize]
                    + mesh.nodes[quad[(c as usize + 3) % 4] as usize];
            }
            let target = sum / (2.0 * around[n].len() as f64);
            let old = mesh.nodes[n];
            // settled: a move under a thousandth of an element's edge is
            // not worth the checks (and sweeps stop where all are settled)
            let (q0, c0) = around[n][0];
            let edge = mesh.nodes[mesh.quads[q0 as usize][(c0 as usize + 1) % 4] as usize] - old;
            if (target - old).length_squared() <= 1e-6 * edge.length_squared() {
                continue;
            }
            let before = around[n]
                .iter()
                .map(|&(q, _)| badness(mesh.quad_points(q as usize)))
                .fold(0.0, f64::max);
            // try the full move, then half of it
            for t in [1.0, 0.5] {
                mesh.nodes[n] = old + (target - old) * t;
                let after = around[n]
                    .iter()
                    .map(|&(q, _)| badness(mesh.quad_points(q as usize)))
                    .fold(0.0, f64::max);
                if after.is_finite() && after <= before.max(0.0) + 1e-9 {
                    kept += 1;
                    for &(q, _) in &around[n] {
                        for m in mesh.quads[q as usize] {
                            dirty[m as usize] = true;
                        }
                    }
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

/// The worst corner of the elements round a node: (badness, -smallest
/// sine of a corner), smaller is better; infinite if one is not convex.
fn worst_around(mesh: &Mesh, around: &[(u32, u8)]) -> (f64, f64) {
    let mut bad: f64 = 0.0;
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        let p = mesh.quad_points(q as usize);
        let b = badness(p);
        if !b.is_finite() {
            return (f64::INFINITY, f64::INFINITY);
        }
        bad = bad.max(b);
        min_sin = min_sin.min(crate::quality::scaled_jacobian(p));
    }
    (bad, -min_sin)
}

/// True when every corner of the elements round a node has a sine above
/// 0.8 (between 53 and 127 degrees, so convex and inside [45, 135]):
/// the common case, told without trigonometry.
fn corners_fine(mesh: &Mesh, around: &[(u32, u8)]) -> bool {
    around.iter().all(|&(q, _)| {
        let p = mesh.quad_points(q as usize);
        (0..4).all(|i| {
            let a = p[(i + 1) % 4] - p[i];
            let b = p[(i + 3) % 4] - p[i];
            let d = a.dot(b);
            a.perp_dot(b) > 0.0 && d * d < 0.36 * a.length_squared() * b.length_squared()
        })
    })
}

/// Moves each free node next to an element with a corner outside
/// [45, 135] to the place, found by a compass search, where the worst
/// corner round it is best; `passes` sweeps. Never makes an element worse
/// than it was, never inverts one. Returns the moves kept.
pub fn untangle_angles(mesh: &mut Mesh, passes: usize) -> usize {
    let around = node_elements(mesh);
    // as in `laplace`: a node whose elements did not change since it was
    // last searched would stay where it is
    let mut dirty = vec![true; mesh.nodes.len()];
    let mut moved = 0;
    for _ in 0..passes {
        let mut any = false;
        for n in 0..mesh.nodes.len() {
            if !std::mem::take(&mut dirty[n])
                || mesh.kinds[n] != NodeKind::Interior
                || around[n].is_empty()
            {
                continue;
            }
            if corners_fine(mesh, &around[n]) {
                continue;
            }
            let start = worst_around(mesh, &around[n]);
            if start.0 == 0.0 && start.1 < -0.8 {
                continue; // every corner round it is fine
            }
            let old = mesh.nodes[n];
            let h = around[n]
                .iter()
                .map(|&(q, c)| {
                    let quad = mesh.quads[q as usize];
                    (mesh.nodes[quad[(c as usize + 1) % 4] as usize] - old).length()
                })
                .fold(f64::INFINITY, f64::min);
            let mut best = (start, old);
            let mut step = 0.25 * h;
            for _ in 0..6 {
                let centre = best.1;
                for k in 0..8 {
                    let a = k as f64 * std::f64::consts::FRAC_PI_4;
                    mesh.nodes[n] = centre + DVec2::new(a.cos(), a.sin()) * step;
                    let w = worst_around(mesh, &around[n]);
                    if w < best.0 {
                        best = (w, mesh.nodes[n]);
                    }
                }
                step *= 0.5;
            }
            mesh.nodes[n] = best.1;
            if best.1 != old {
                moved += 1;
                any = true;
                for &(q, _) in &around[n] {
                    for m in mesh.quads[q as usize] {
                        dirty[m as usize] = true;
                    }
                }
            }
        }
        if !any {
            break;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four unit squares round one free centre node (id 4).
    fn two_by_two_block() -> Mesh {
        let mut m = Mesh::default();
        for y in 0..3 {
            for x in 0..3 {
                let kind = if x == 1 && y == 1 {
                    NodeKind::Interior
                } else {
                    NodeKind::Boundary
                };
                m.add_node(DVec2::new(x as f64, y as f64), kind);
            }
        }
        m.quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        m
    }

    #[test]
    fn centre_node_of_a_two_by_two_block_moves_to_the_middle() {
        let mut m = two_by_two_block();
        m.nodes[4] = DVec2::new(1.3, 0.8);
        laplace(&mut m, 20);
        assert!((m.nodes[4] - DVec2::new(1.0, 1.0)).length() < 1e-6);
    }

    #[test]
    fn compass_search_repairs_a_pinched_corner() {
        let mut m = two_by_two_block();
        m.nodes[4] = DVec2::new(0.6, 0.6); // a corner of 157 deg at the centre
        assert!(untangle_angles(&mut m, 5) > 0);
        let worst = (0..4)
            .flat_map(|q| quad_angles(m.quad_points(q)))
            .fold(0.0, f64::max);
        assert!(worst <= 135.0 + 1e-6, "worst corner {worst}");
    }

    #[test]
    fn boundary_nodes_never_move() {
        let mut m = Mesh::default();
        m.add_node(DVec2::ZERO, NodeKind::Boundary);
        m.add_node(DVec2::X, NodeKind::Boundary);
        m.add_node(DVec2::new(1.0, 1.0), NodeKind::Boundary);
        m.add_node(DVec2::new(0.2, 0.9), NodeKind::Boundary);
        m.quads = vec![[0, 1, 2, 3]];
        let before = m.nodes.clone();
        laplace(&mut m, 5);
        assert_eq!(m.nodes, before);
    }
}
