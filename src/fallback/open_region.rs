//! An open region of the mesh, the loops the rules left open: the lattice
//! spacings it is closed at, its constrained triangulation, and the edges
//! that splitting its triangles in three halves (shared by the closing in
//! stuck_loops.rs and the pairing in pairs.rs).

use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::{HashMap, HashSet};

use super::triangles::{inside_triangles, lattice_points, FallbackError};
use crate::mesh::BoundaryEdge;

/// How far apart the interior points of an open loop's triangles are:
/// `pairs` where they are paired into quads (tried first; in lengths of
/// the loop's edges, their mean; 0: never), `split` where each is split
/// in three (a length).
#[derive(Clone, Copy, Debug)]
pub struct Spacing {
    pub pairs: f64,
    pub split: f64,
}

pub(super) fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Quads with, for each of their edges, the quads that have it and on
/// which side: built once for the rules' elements, read by every halving
/// tried on an open region.
pub(super) struct EdgeQuads<'a> {
    pub quads: &'a [[u32; 4]],
    of: HashMap<(u32, u32), Vec<(usize, usize)>>,
}

impl<'a> EdgeQuads<'a> {
    pub(super) fn new(quads: &'a [[u32; 4]]) -> EdgeQuads<'a> {
        let mut of: HashMap<(u32, u32), Vec<(usize, usize)>> = HashMap::new();
        for (qi, q) in quads.iter().enumerate() {
            for i in 0..4 {
                of.entry(key(q[i], q[(i + 1) % 4]))
                    .or_default()
                    .push((qi, i));
            }
        }
        EdgeQuads { quads, of }
    }

    /// The quads with edge `k`, and the side it is.
    fn at(&self, k: (u32, u32)) -> &[(usize, usize)] {
        self.of.get(&k).map(Vec::as_slice).unwrap_or(&[])
    }
}

/// The edges halved where `triangles` are split in three: theirs, and
/// the edges across from those in the `rules`' quads and the `pairs`',
/// along each chord until it meets the boundary or a halved edge.
pub(super) fn halving(
    rules: &EdgeQuads,
    pairs: &[[u32; 4]],
    triangles: &[[u32; 3]],
) -> Vec<(u32, u32)> {
    let pairs = EdgeQuads::new(pairs);
    let mut halved: Vec<(u32, u32)> = Vec::new();
    let mut seen: HashSet<(u32, u32)> = HashSet::new();
    for t in triangles {
        for i in 0..3 {
            let k = key(t[i], t[(i + 1) % 3]);
            if seen.insert(k) {
                halved.push(k);
            }
        }
    }
    let mut next = 0;
    while next < halved.len() {
        let k = halved[next];
        next += 1;
        for quads in [rules, &pairs] {
            for &(qi, i) in quads.at(k) {
                let q = quads.quads[qi];
                let opposite = key(q[(i + 2) % 4], q[(i + 3) % 4]);
                if seen.insert(opposite) {
                    halved.push(opposite);
                }
            }
        }
    }
    halved
}

/// How many elements the `rules`' and the `pairs`' quads become where
/// the edges of `halved` are halved: one a quad, two where one pair of
/// its sides is halved, four where both are.
pub(super) fn after_halving(rules: &EdgeQuads, pairs: &[[u32; 4]], halved: &[(u32, u32)]) -> usize {
    let pairs = EdgeQuads::new(pairs);
    let is_halved: HashSet<(u32, u32)> = halved.iter().copied().collect();
    let mut extra = 0;
    for quads in [rules, &pairs] {
        let touched: HashSet<usize> = halved
            .iter()
            .flat_map(|&k| quads.at(k).iter().map(|&(qi, _)| qi))
            .collect();
        for qi in touched {
            let q = quads.quads[qi];
            let h = |i: usize| is_halved.contains(&key(q[i], q[(i + 1) % 4]));
            extra += if h(0) && h(1) { 3 } else { 1 };
        }
    }
    rules.quads.len() + pairs.quads.len() + extra
}

/// An open region's triangulation: its points (the loop's nodes first,
/// `ids` their mesh ids; then the lattice's), and its triangles,
/// counter-clockwise, as indices into the points.
pub(super) struct Triangulated {
    pub points: Vec<DVec2>,
    pub ids: Vec<u32>,
    pub triangles: Vec<[u32; 3]>,
}

/// The open region triangulated: its nodes (the loop's, then interior
/// points on a lattice of `spacing`) with their mesh ids for the loop's
/// (the lattice's get theirs when they are kept), and the triangles
/// inside it, counter-clockwise, as indices into those points. The
/// region's edges are constraints: met once they bound it, twice (both
/// sides of a line, a slit) they lie inside it.
pub(super) fn triangulate_region(
    nodes: &[DVec2],
    loop_edges: &[(u32, u32)],
    times: &HashMap<(u32, u32), u32>,
    spacing: f64,
) -> Result<Triangulated, FallbackError> {
    // The open region: its nodes in a compact numbering for the
    // triangulation, its edges the constraints (group 0 bounds it,
    // group 1 lies inside it).
    let mut ids: Vec<u32> = Vec::new();
    let mut compact: HashMap<u32, u32> = HashMap::new();
    let mut region_edges: Vec<BoundaryEdge> = Vec::with_capacity(loop_edges.len());
    for &(a, b) in loop_edges {
        let mut id = |n: u32| {
            *compact.entry(n).or_insert_with(|| {
                ids.push(n);
                (ids.len() - 1) as u32
            })
        };
        let (ca, cb) = (id(a), id(b));
        region_edges.push(BoundaryEdge {
            a: ca,
            b: cb,
            group: if times[&(a, b)] == 1 { 0 } else { 1 },
            tag: None,
        });
    }
    let mut points: Vec<DVec2> = ids.iter().map(|&n| nodes[n as usize]).collect();
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handle_node = HashMap::new();
    let mut handles = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|e| FallbackError(format!("loop node: {e:?}")))?;
        if handle_node.insert(h, i as u32).is_some() {
            return Err(FallbackError(format!(
                "two loop nodes at ({}, {})",
                p.x, p.y
            )));
        }
        handles.push(h);
    }
    for e in &region_edges {
        if cdt
            .try_add_constraint(handles[e.a as usize], handles[e.b as usize])
            .len()
            != 1
        {
            return Err(FallbackError("an open loop's edge crosses another".into()));
        }
    }
    for p in lattice_points(&points, &region_edges, 1, spacing) {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|e| FallbackError(format!("interior point: {e:?}")))?;
        if let std::collections::hash_map::Entry::Vacant(v) = handle_node.entry(h) {
            points.push(p);
            v.insert((points.len() - 1) as u32);
        }
    }
    let triangles = inside_triangles(&cdt, &handle_node, &region_edges, 1)?;
    Ok(Triangulated {
        points,
        ids,
        triangles,
    })
}
