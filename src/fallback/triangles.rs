//! The last resort: a valid all-quad mesh of any valid domain, for when
//! the rules and the loop subdivision both fail.
//!
//! The discretised boundary (every loop and inner line a chain of
//! constraint edges) and a lattice of interior points about one element
//! size apart are triangulated (constrained Delaunay, `spade`); the
//! triangles inside the domain are each split into three quadrilaterals
//! by the centroid and the midpoints of the edges. Such a quad is convex
//! whatever the triangle, neighbouring triangles share their edge's
//! midpoint, and the midpoints of boundary edges are put on their curves,
//! so the mesh is all-quad and conforming by construction. Every boundary
//! segment is halved (the parity of the counts does not matter here), and
//! the elements are about half the size the rules would make.

use glam::DVec2;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::{HashMap, HashSet, VecDeque};

use crate::input::boundary::Discretised;
use crate::input::domain::Domain;
use crate::mesh::{BoundaryEdge, Mesh, NodeKind};

/// Why the last resort could not mesh (a defect: a valid domain always
/// meshes).
#[derive(Debug, thiserror::Error)]
#[error("the rules stopped and the fallback cannot mesh the domain: {0}")]
pub struct FallbackError(pub(crate) String);

/// Meshes the discretised domain by triangles split into quads.
///
/// `size` is the boundary segment length; interior points are placed on a
/// lattice of that spacing, kept at least half of it from the boundary.
/// Where a thin triangle meets a strongly curved boundary segment so that
/// no centre makes its quads convex, that segment is split at its curve
/// point and the domain triangulated again (at most a few rounds).
pub fn mesh_by_triangles(
    domain: &Domain,
    disc: &Discretised,
    size: f64,
) -> Result<Mesh, FallbackError> {
    let src = &disc.mesh;
    // the boundary alone, in a compact numbering
    let mut nodes: Vec<DVec2> = Vec::new();
    let mut renumber: HashMap<u32, u32> = HashMap::new();
    let mut boundary: Vec<BoundaryEdge> = Vec::with_capacity(src.boundary.len());
    for e in &src.boundary {
        let mut id = |n: u32| {
            *renumber.entry(n).or_insert_with(|| {
                nodes.push(src.nodes[n as usize]);
                (nodes.len() - 1) as u32
            })
        };
        let (a, b) = (id(e.a), id(e.b));
        boundary.push(BoundaryEdge {
            a,
            b,
            group: e.group,
            tag: e.tag,
        });
    }
    let chains: Vec<&crate::input::domain::Chain> = domain.chains().collect();
    const SPLIT_ROUNDS: usize = 4;
    for round in 0..=SPLIT_ROUNDS {
        let last = round == SPLIT_ROUNDS;
        let to_split = match triangles_to_quads(domain, &nodes, &boundary, &src.groups, size, last)?
        {
            Ok(mesh) => return Ok(mesh),
            Err(edges) => edges,
        };
        let mut next = Vec::with_capacity(boundary.len() + to_split.len());
        for e in &boundary {
            if to_split.contains(&(e.a.min(e.b), e.a.max(e.b))) {
                let m = (nodes[e.a as usize] + nodes[e.b as usize]) / 2.0;
                nodes.push(project_on_chain(chains[e.group as usize], m));
                let n = (nodes.len() - 1) as u32;
                next.push(BoundaryEdge {
                    a: e.a,
                    b: n,
                    group: e.group,
                    tag: e.tag,
                });
                next.push(BoundaryEdge {
                    a: n,
                    b: e.b,
                    group: e.group,
                    tag: e.tag,
                });
            } else {
                next.push(*e);
            }
        }
        boundary = next;
    }
    unreachable!("the last round always gives a mesh")
}

/// One round: the mesh, or (when not `last`) the boundary segments to
/// split because no centre makes their triangle's quads convex.
#[allow(clippy::type_complexity)]
fn triangles_to_quads(
    domain: &Domain,
    boundary_nodes: &[DVec2],
    boundary: &[BoundaryEdge],
    groups: &[String],
    size: f64,
    last: bool,
) -> Result<Result<Mesh, HashSet<(u32, u32)>>, FallbackError> {
    let loops = 1 + domain.holes.len() as u32;
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handle_node: HashMap<FixedVertexHandle, u32> = HashMap::new();
    let mut node_handle: HashMap<u32, FixedVertexHandle> = HashMap::new();
    let mut mesh = Mesh {
        groups: groups.to_vec(),
        ..Mesh::default()
    };
    for &p in boundary_nodes {
        let id = mesh.add_node(p, NodeKind::Boundary);
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|e| FallbackError(format!("boundary node {id}: {e:?}")))?;
        if handle_node.insert(h, id).is_some() {
            return Err(FallbackError(format!(
                "two boundary nodes at ({}, {})",
                p.x, p.y
            )));
        }
        node_handle.insert(id, h);
    }
    for e in boundary {
        let made = cdt.try_add_constraint(node_handle[&e.a], node_handle[&e.b]);
        if made.len() != 1 {
            let m = (boundary_nodes[e.a as usize] + boundary_nodes[e.b as usize]) / 2.0;
            let name = groups
                .get(e.group as usize)
                .map_or("the boundary", String::as_str);
            return Err(FallbackError(format!(
                "near ({:.6}, {:.6}) on {name}, the boundary's segments at this size cross \
                 another part of the boundary (two parts closer than an element there: \
                 a smaller size or a wider corner may mesh it)",
                m.x, m.y
            )));
        }
    }
    for p in lattice_points(&mesh.nodes, boundary, loops, size) {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|e| FallbackError(format!("interior point: {e:?}")))?;
        if let std::collections::hash_map::Entry::Vacant(v) = handle_node.entry(h) {
            v.insert(mesh.add_node(p, NodeKind::Interior));
        }
    }
    let triangles = inside_triangles(&cdt, &handle_node, boundary, loops)?;
    // split each triangle into three quads
    let on_boundary: HashMap<(u32, u32), u32> = boundary
        .iter()
        .map(|e| ((e.a.min(e.b), e.a.max(e.b)), e.group))
        .collect();
    let chains: Vec<&crate::input::domain::Chain> = domain.chains().collect();
    let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
    let mut mid = |mesh: &mut Mesh, a: u32, b: u32| -> u32 {
        let key = (a.min(b), a.max(b));
        *midpoint.entry(key).or_insert_with(|| {
            let m = (mesh.nodes[a as usize] + mesh.nodes[b as usize]) / 2.0;
            match on_boundary.get(&key) {
                Some(&g) => {
                    mesh.add_node(project_on_chain(chains[g as usize], m), NodeKind::Boundary)
                }
                None => mesh.add_node(m, NodeKind::Interior),
            }
        })
    };
    // Midpoints first, so each centre can follow its edges' midpoints:
    // the centre is the mean of the hexagon of corners and midpoints,
    // the centroid where the edges are straight, moved with a curved
    // edge's midpoint where one is projected onto its curve.
    let mids: Vec<[u32; 3]> = triangles
        .iter()
        .map(|&[a, b, c]| {
            [
                mid(&mut mesh, a, b),
                mid(&mut mesh, b, c),
                mid(&mut mesh, c, a),
            ]
        })
        .collect();
    let mut centres = Vec::with_capacity(triangles.len());
    for (&tri, &m) in triangles.iter().zip(&mids) {
        centres.push(split_in_three(&mut mesh, tri, m).0);
    }
    // Where a midpoint on a strongly curved boundary makes a quad of its
    // (thin) triangle non-convex: first look for a better centre; failing
    // that, pull the midpoint back towards its chord a step at a time,
    // looking for the centre again at each step (the mesh stays valid;
    // such a node is then off its curve by less than the sagitta).
    let mut to_split = HashSet::new();
    for t in 0..triangles.len() {
        let quads = [3 * t, 3 * t + 1, 3 * t + 2];
        if quads.iter().all(|&q| quad_convex(&mesh, q)) {
            continue;
        }
        let [a, b, c] = triangles[t];
        let g = centres[t];
        if place_centre(&mut mesh, [a, b, c], g, quads) {
            continue;
        }
        let curved: Vec<(u32, DVec2, DVec2)> =
            [(a, b, mids[t][0]), (b, c, mids[t][1]), (c, a, mids[t][2])]
                .iter()
                .filter(|(x, y, _)| on_boundary.contains_key(&((*x).min(*y), (*x).max(*y))))
                .map(|&(x, y, m)| {
                    let chord = (mesh.nodes[x as usize] + mesh.nodes[y as usize]) / 2.0;
                    (m, chord, mesh.nodes[m as usize])
                })
                .collect();
        if !last && !curved.is_empty() {
            for (x, y) in [(a, b), (b, c), (c, a)] {
                if on_boundary.contains_key(&(x.min(y), x.max(y))) {
                    to_split.insert((x.min(y), x.max(y)));
                }
            }
            continue;
        }
        for step in 1..=10 {
            let f = 1.0 - step as f64 / 10.0;
            for &(m, chord, curve) in &curved {
                mesh.nodes[m as usize] = chord + (curve - chord) * f;
            }
            if place_centre(&mut mesh, [a, b, c], g, quads) {
                break;
            }
        }
    }
    if !to_split.is_empty() {
        return Ok(Err(to_split));
    }
    for e in boundary {
        let m = midpoint[&(e.a.min(e.b), e.a.max(e.b))];
        mesh.boundary.push(BoundaryEdge {
            a: e.a,
            b: m,
            group: e.group,
            tag: e.tag,
        });
        mesh.boundary.push(BoundaryEdge {
            a: m,
            b: e.b,
            group: e.group,
            tag: e.tag,
        });
    }
    Ok(Ok(mesh))
}

/// Splits the triangle `tri` into three quads by its edges' midpoints
/// `mids` (a-b, b-c, c-a) and a centre node: the mean of the hexagon of
/// corners and midpoints (the centroid where the edges are straight).
/// Returns the centre and the new quads' indices.
pub(super) fn split_in_three(mesh: &mut Mesh, tri: [u32; 3], mids: [u32; 3]) -> (u32, [usize; 3]) {
    let ([a, b, c], [mab, mbc, mca]) = (tri, mids);
    let centre = [a, b, c, mab, mbc, mca]
        .iter()
        .map(|&n| mesh.nodes[n as usize])
        .sum::<DVec2>()
        / 6.0;
    let g = mesh.add_node(centre, NodeKind::Interior);
    let first = mesh.quads.len();
    mesh.quads.push([a, mab, g, mca]);
    mesh.quads.push([b, mbc, g, mab]);
    mesh.quads.push([c, mca, g, mbc]);
    (g, [first, first + 1, first + 2])
}

fn quad_convex(mesh: &Mesh, q: usize) -> bool {
    crate::geometry::quad_is_convex(mesh.quad_points(q))
}

/// Moves centre node `g` of triangle `tri` (whose three quads are
/// `quads`) to the point of a barycentric grid over the triangle that
/// makes the three quads convex with the widest margin. False if none
/// does (g is left where it was).
pub(super) fn place_centre(mesh: &mut Mesh, tri: [u32; 3], g: u32, quads: [usize; 3]) -> bool {
    let corners = tri.map(|n| mesh.nodes[n as usize]);
    let original = mesh.nodes[g as usize];
    let margin = |mesh: &Mesh| {
        quads
            .iter()
            .flat_map(|&q| {
                let p = mesh.quad_points(q);
                (0..4).map(move |i| crate::geometry::orient2d(p[i], p[(i + 1) % 4], p[(i + 2) % 4]))
            })
            .fold(f64::MAX, f64::min)
    };
    let mut best = (margin(mesh), original);
    const STEPS: usize = 40;
    for i in 1..STEPS {
        for j in 1..STEPS - i {
            let (u, v) = (i as f64 / STEPS as f64, j as f64 / STEPS as f64);
            let cand = corners[0] * (1.0 - u - v) + corners[1] * u + corners[2] * v;
            mesh.nodes[g as usize] = cand;
            let m = margin(mesh);
            if m > best.0 {
                best = (m, cand);
            }
        }
    }
    mesh.nodes[g as usize] = best.1;
    best.0 > 0.0
}

/// The point of the chain's curves nearest to `p`.
pub(super) fn project_on_chain(chain: &crate::input::domain::Chain, p: DVec2) -> DVec2 {
    chain
        .edges
        .iter()
        .map(|e| e.curve.project(p))
        .min_by(|x, y| {
            (*x - p)
                .length_squared()
                .total_cmp(&(*y - p).length_squared())
        })
        .unwrap_or(p)
}

/// Interior points on a triangular lattice of spacing `size` over the
/// domain, each at least half a spacing from every boundary edge.
pub(super) fn lattice_points(
    nodes: &[DVec2],
    boundary: &[BoundaryEdge],
    loops: u32,
    size: f64,
) -> Vec<DVec2> {
    let lo = nodes.iter().fold(DVec2::splat(f64::MAX), |a, &b| a.min(b));
    let hi = nodes.iter().fold(DVec2::splat(f64::MIN), |a, &b| a.max(b));
    // boundary edges bucketed on a grid of cell `size`, for the clearance
    let cell = size;
    let key = |p: DVec2| {
        (
            ((p.x - lo.x) / cell).floor() as i64,
            ((p.y - lo.y) / cell).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, e) in boundary.iter().enumerate() {
        let (a, b) = (nodes[e.a as usize], nodes[e.b as usize]);
        let (k0, k1) = (key(a.min(b)), key(a.max(b)));
        for x in k0.0..=k1.0 {
            for y in k0.1..=k1.1 {
                grid.entry((x, y)).or_default().push(i);
            }
        }
    }
    let rows = ((hi.y - lo.y) / (size * 0.866)).ceil() as i64;
    let cols = ((hi.x - lo.x) / size).ceil() as i64;
    let mut out = Vec::new();
    for r in 0..=rows {
        let shift = if r % 2 == 1 { 0.5 * size } else { 0.0 };
        for c in 0..=cols {
            let p = DVec2::new(
                lo.x + shift + c as f64 * size,
                lo.y + r as f64 * size * 0.866,
            );
            let k = key(p);
            let clear = (-1..=1).all(|dx| {
                (-1..=1).all(|dy| {
                    grid.get(&(k.0 + dx, k.1 + dy)).is_none_or(|es| {
                        es.iter().all(|&i| {
                            let e = &boundary[i];
                            crate::geometry::point_segment_distance(
                                p,
                                nodes[e.a as usize],
                                nodes[e.b as usize],
                            ) >= 0.5 * size
                        })
                    })
                })
            });
            if clear && inside(p, nodes, boundary, loops) {
                out.push(p);
            }
        }
    }
    out
}

/// Even-odd test of `p` against the loops' edges.
fn inside(p: DVec2, nodes: &[DVec2], boundary: &[BoundaryEdge], loops: u32) -> bool {
    let mut odd = false;
    for e in boundary.iter().filter(|e| e.group < loops) {
        let (a, b) = (nodes[e.a as usize], nodes[e.b as usize]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            odd = !odd;
        }
    }
    odd
}

/// The triangles inside the domain, counter-clockwise, as node ids: a
/// flood fill from the outside that changes sides at every loop edge
/// (inner lines are constraints too, but both their sides are inside).
pub(super) fn inside_triangles(
    cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>,
    handle_node: &HashMap<FixedVertexHandle, u32>,
    boundary: &[BoundaryEdge],
    loops: u32,
) -> Result<Vec<[u32; 3]>, FallbackError> {
    let loop_edges: HashSet<(u32, u32)> = boundary
        .iter()
        .filter(|e| e.group < loops)
        .map(|e| (e.a.min(e.b), e.a.max(e.b)))
        .collect();
    let node = |h: FixedVertexHandle| handle_node[&h];
    let mut side: HashMap<spade::handles::FixedFaceHandle<spade::handles::InnerTag>, bool> =
        HashMap::new();
    let mut queue = VecDeque::new();
    // faces on the convex hull are outside unless a loop edge is the hull
    for e in cdt.convex_hull() {
        let Some(f) = e.face().as_inner().or_else(|| e.rev().face().as_inner()) else {
            continue;
        };
        let (a, b) = (node(e.from().fix()), node(e.to().fix()));
        let inner = loop_edges.contains(&(a.min(b), a.max(b)));
        if let std::collections::hash_map::Entry::Vacant(v) = side.entry(f.fix()) {
            v.insert(inner);
            queue.push_back(f.fix());
        }
    }
    while let Some(f) = queue.pop_front() {
        let here = side[&f];
        for e in cdt.face(f).adjacent_edges() {
            let Some(g) = e.rev().face().as_inner() else {
                continue;
            };
            if side.contains_key(&g.fix()) {
                continue;
            }
            let (a, b) = (node(e.from().fix()), node(e.to().fix()));
            let crosses = loop_edges.contains(&(a.min(b), a.max(b)));
            side.insert(g.fix(), here ^ crosses);
            queue.push_back(g.fix());
        }
    }
    if side.len() != cdt.num_inner_faces() {
        return Err(FallbackError("a triangle was not reached".into()));
    }
    let mut tris: Vec<[u32; 3]> = cdt
        .inner_faces()
        .filter(|f| side[&f.fix()])
        .map(|f| f.vertices().map(|v| node(v.fix())))
        .collect();
    tris.sort_unstable(); // the same mesh whatever the hash order
    Ok(tris)
}
