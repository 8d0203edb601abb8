//! Sliding: a boundary node that is no input vertex moves along its
//! straight edge (the line through it and its two boundary neighbours) to
//! where the worst corner round it is best, when a corner there is
//! outside the window. Smoothing moves interior nodes only; at a sharp
//! tip or a chamfer the corners next to the boundary often can only be
//! mended by moving the boundary node itself.

use std::collections::HashSet;

use glam::DVec2;

use crate::element_quality::worst_around;
use crate::mesh::Mesh;
use crate::settings::ElementBounds;
use crate::smoothing::strips::node_elements;

/// How far a node may slide, as a share of the way to a boundary
/// neighbour: far enough to mend a corner, never onto the neighbour.
const REACH: f64 = 0.4;

/// A node's line between its boundary neighbours `a` and `b`: a point for
/// each parameter in [-1, 1] (0: the node where it is). Nodes on arcs stay:
/// sliding one would change the area the chords enclose.
struct Track {
    at: DVec2,
    to_a: DVec2,
    to_b: DVec2,
}

impl Track {
    /// The line through `a`, `p` and `b`, if they are on one.
    fn through(a: DVec2, p: DVec2, b: DVec2) -> Option<Track> {
        let (to_a, to_b) = (a - p, b - p);
        let scale = to_a.length_squared().max(to_b.length_squared());
        // collinear, and p between a and b
        let on_line = to_a.perp_dot(to_b).abs() <= 1e-12 * scale && to_a.dot(to_b) < 0.0;
        on_line.then_some(Track { at: p, to_a, to_b })
    }

    /// The point at `s` in [-1, 1]: towards `a` below 0, towards `b` above.
    fn at(&self, s: f64) -> DVec2 {
        if s < 0.0 {
            self.at - self.to_a * s
        } else {
            self.at + self.to_b * s
        }
    }
}

/// Slides the boundary nodes that are no input vertex (`fixed`: the input
/// vertices' coordinates) where a corner round them is outside the window.
/// Returns the nodes moved.
pub fn slide_boundary_nodes(mesh: &mut Mesh, fixed: &[DVec2], bounds: &ElementBounds) -> Vec<u32> {
    let fixed: HashSet<(u64, u64)> = fixed
        .iter()
        .map(|p| (p.x.to_bits(), p.y.to_bits()))
        .collect();
    let mut along: Vec<Vec<(u32, u32)>> = vec![Vec::new(); mesh.nodes.len()];
    for e in &mesh.boundary {
        along[e.a as usize].push((e.b, e.group));
        along[e.b as usize].push((e.a, e.group));
    }
    let around = node_elements(mesh);
    let mut moved = Vec::new();
    for n in 0..mesh.nodes.len() {
        let p = mesh.nodes[n];
        let [(a, ga), (b, gb)] = along[n][..] else {
            continue;
        };
        if ga != gb || around[n].is_empty() || fixed.contains(&(p.x.to_bits(), p.y.to_bits())) {
            continue;
        }
        let start = worst_around(mesh, &around[n], bounds);
        if start.0 == 0.0 {
            continue; // every corner round it is in the window
        }
        let Some(track) = Track::through(mesh.nodes[a as usize], p, mesh.nodes[b as usize]) else {
            continue;
        };
        // a search along the track, the step halving
        let (mut best, mut best_s) = (start, 0.0);
        let mut step = REACH / 2.0;
        for _ in 0..8 {
            let centre = best_s;
            for s in [centre - step, centre + step] {
                if s.abs() > REACH {
                    continue;
                }
                mesh.nodes[n] = track.at(s);
                let w = worst_around(mesh, &around[n], bounds);
                if w < best {
                    best = w;
                    best_s = s;
                }
            }
            step /= 2.0;
        }
        mesh.nodes[n] = if best_s == 0.0 { p } else { track.at(best_s) };
        if best_s != 0.0 {
            moved.push(n as u32);
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BoundaryEdge, NodeKind};

    /// A 2 x 1 strip of two quads whose middle nodes on the bottom and top
    /// edges are far apart: a corner of 32.8 deg at the top one.
    fn strip() -> Mesh {
        let mut m = Mesh::default();
        for p in [
            [0.0, 0.0],
            [0.05, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.6, 1.0],
            [0.0, 1.0],
        ] {
            m.add_node(DVec2::from(p), NodeKind::Boundary);
        }
        m.quads = vec![[0, 1, 4, 5], [1, 2, 3, 4]];
        m.boundary = (0..6)
            .map(|i| BoundaryEdge {
                a: i,
                b: (i + 1) % 6,
                group: 0,
                tag: None,
            })
            .collect();
        m
    }

    fn corners(m: &Mesh) -> Vec<f64> {
        (0..m.quads.len())
            .flat_map(|q| crate::geometry::quad_angles(m.quad_points(q)))
            .collect()
    }

    #[test]
    fn a_node_on_a_straight_edge_slides_along_it_to_mend_a_corner() {
        let mut m = strip();
        assert!(corners(&m).iter().any(|&a| a < 45.0));
        let fixed = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]].map(DVec2::from);
        let moved = slide_boundary_nodes(&mut m, &fixed, &ElementBounds::default());
        assert!(!moved.is_empty());
        let a = corners(&m);
        assert!(a.iter().all(|&a| (45.0..=135.0).contains(&a)), "{a:?}");
        // still on their edges, between their neighbours
        assert_eq!((m.nodes[1].y, m.nodes[4].y), (0.0, 1.0));
        assert!(m.nodes[1].x > 0.0 && m.nodes[1].x < 2.0);
        assert!(m.nodes[4].x > 0.0 && m.nodes[4].x < 2.0);
    }

    #[test]
    fn input_vertices_and_nodes_at_a_corner_of_the_boundary_stay() {
        let mut m = strip();
        let before = m.nodes.clone();
        // every node an input vertex
        slide_boundary_nodes(&mut m, &before, &ElementBounds::default());
        assert_eq!(m.nodes, before);
        // node 1 at a bend of the bottom edge: not on one line with its
        // neighbours
        let mut m = strip();
        m.nodes[1] = DVec2::new(0.05, 0.01);
        let fixed = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0], [1.6, 1.0]].map(DVec2::from);
        slide_boundary_nodes(&mut m, &fixed, &ElementBounds::default());
        assert_eq!(m.nodes[1], DVec2::new(0.05, 0.01));
    }
}
