//! Each block meshed as a mapping element (the paper's Fig. 17): its
//! sides divided as the interval assignment says, boundary sides along
//! the input's curves, and the inside by transfinite interpolation (a
//! Coons patch), so the blocks' elements make a structured grid.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use super::intervals::Chords;
use super::OnCurve;
use crate::input::curves::Curve;
use crate::input::domain::Domain;
use crate::mesh::{BoundaryEdge, Mesh, NodeKind};

/// The input curve each boundary edge of the layout lies on (keyed by
/// its ends, lower id first), None where one lies on none (a defect).
pub type BoundaryCurves = HashMap<(u32, u32), OnCurve>;

/// See `BoundaryCurves`.
pub fn boundary_curves(layout: &Mesh, domain: &Domain) -> Option<BoundaryCurves> {
    layout
        .boundary
        .iter()
        .map(|e| {
            let (a, b) = (e.a.min(e.b), e.a.max(e.b));
            let on = curve_between(domain, layout.nodes[a as usize], layout.nodes[b as usize])?;
            Some(((a, b), on))
        })
        .collect()
}

/// The input curve through `a` and `b` whose point halfway between them
/// is nearest the edge's middle (a short input edge's neighbours pass
/// through one of its ends, not both).
fn curve_between(domain: &Domain, a: DVec2, b: DVec2) -> Option<OnCurve> {
    let tol = 1e-6 * domain.scale();
    let mut best: Option<(f64, OnCurve)> = None;
    for chain in domain.chains() {
        for e in &chain.edges {
            let c = e.curve;
            if c.distance(a) > tol || c.distance(b) > tol {
                continue;
            }
            let (ta, mut tb) = (c.param_of(a), c.param_of(b));
            if let Curve::Circle { .. } = c {
                // the short way round: a layout edge spans at most 60 deg
                tb = ta + (tb - ta + 0.5).rem_euclid(1.0) - 0.5;
            } else if (tb - ta).abs() < 1e-12 {
                continue;
            }
            let off = (c.point_at(wrap(&c, (ta + tb) / 2.0)) - (a + b) / 2.0).length();
            if best.as_ref().is_none_or(|(d, _)| off < *d) {
                best = Some((
                    off,
                    OnCurve {
                        curve: c,
                        from: ta,
                        to: tb,
                    },
                ));
            }
        }
    }
    best.map(|(_, found)| found)
}

/// A circle's parameter taken into [0, 1).
fn wrap(c: &Curve, t: f64) -> f64 {
    match c {
        Curve::Circle { .. } => t.rem_euclid(1.0),
        _ => t,
    }
}

/// The fine mesh of a layout (`layout`, its quads the blocks) whose
/// edges have the counts `counts`, but for the blocks marked `free`
/// (their sides only; see free_blocks.rs), and each layout edge's nodes
/// from its lower id to its higher: the layout's nodes keep their ids
/// (the layout's trace reads the same in the fine mesh), then each layout
/// edge's inner nodes, then each block's inner nodes. Each quad's block
/// is in `Mesh::blocks`. None where a block's opposite sides disagree
/// (a defect of the assignment; the caller meshes the domain free).
pub fn mesh_blocks(
    layout: &Mesh,
    chords: &Chords,
    counts: &[usize],
    free: &[bool],
    on_curve: &BoundaryCurves,
) -> Option<(Mesh, Vec<Vec<u32>>)> {
    let mut mesh = Mesh {
        nodes: layout.nodes.clone(),
        kinds: layout.kinds.clone(),
        groups: layout.groups.clone(),
        ..Mesh::default()
    };
    // each layout edge's nodes from its lower id to its higher
    let mut edge_nodes: Vec<Vec<u32>> = Vec::with_capacity(chords.edges.len());
    for (e, &(a, b)) in chords.edges.iter().enumerate() {
        let n = counts[e];
        let (pa, pb) = (layout.nodes[a as usize], layout.nodes[b as usize]);
        let boundary = on_curve.get(&(a, b)).copied();
        let point = |f: f64| match boundary {
            Some(OnCurve { curve, from, to }) => {
                curve.point_at(wrap(&curve, from + (to - from) * f))
            }
            None => pa + (pb - pa) * f,
        };
        let kind = if boundary.is_some() {
            NodeKind::Boundary
        } else {
            NodeKind::Interior
        };
        let mut ids = Vec::with_capacity(n + 1);
        ids.push(a);
        for k in 1..n {
            ids.push(mesh.add_node(point(k as f64 / n as f64), kind));
        }
        ids.push(b);
        edge_nodes.push(ids);
    }
    // the boundary edges, each layout edge's in its direction
    let index: HashMap<(u32, u32), usize> = chords
        .edges
        .iter()
        .enumerate()
        .map(|(i, &e)| (e, i))
        .collect();
    for e in &layout.boundary {
        let i = index.get(&(e.a.min(e.b), e.a.max(e.b)))?;
        let mut ids = edge_nodes[*i].clone();
        if ids[0] != e.a {
            ids.reverse();
        }
        for w in ids.windows(2) {
            mesh.boundary.push(BoundaryEdge {
                a: w[0],
                b: w[1],
                group: e.group,
                tag: e.tag,
            });
        }
    }
    for (bi, q) in layout.quads.iter().enumerate() {
        if free[bi] {
            continue;
        }
        let s = chords.sides[bi];
        // a side's nodes from corner k to corner k + 1
        let side = |k: usize| -> Vec<u32> {
            let mut ids = edge_nodes[s[k]].clone();
            if ids[0] != q[k] {
                ids.reverse();
            }
            ids
        };
        let (bottom, right) = (side(0), side(1));
        let (mut top, mut left) = (side(2), side(3));
        top.reverse(); // corner 3 to corner 2
        left.reverse(); // corner 0 to corner 3
        let (n, m) = (bottom.len() - 1, right.len() - 1);
        if top.len() != n + 1 || left.len() != m + 1 {
            return None; // opposite sides disagree: not a mapping element
        }
        for q in coons_grid(&mut mesh, &bottom, &right, &top, &left) {
            mesh.quads.push(q);
            mesh.blocks.push(bi as u32);
        }
    }
    Some((mesh, edge_nodes))
}

/// The structured grid of a mapping element by transfinite interpolation
/// (a Coons patch) of its sides' nodes: `bottom` from corner 0 to corner
/// 1, `right` from 1 to 2, `top` from 3 to 2, `left` from 0 to 3 (opposite
/// sides have the same count); its quads, counter-clockwise, the inner
/// nodes added to `mesh`.
pub fn coons_grid(
    mesh: &mut Mesh,
    bottom: &[u32],
    right: &[u32],
    top: &[u32],
    left: &[u32],
) -> Vec<[u32; 4]> {
    let (n, m) = (bottom.len() - 1, right.len() - 1);
    debug_assert!(top.len() == n + 1 && left.len() == m + 1);
    let at = |ids: &[u32]| -> Vec<DVec2> { ids.iter().map(|&i| mesh.nodes[i as usize]).collect() };
    let (pb, pt, pl, pr) = (at(bottom), at(top), at(left), at(right));
    let corner = [pb[0], pb[n], pt[n], pt[0]];
    let mut grid = vec![vec![0u32; m + 1]; n + 1];
    for i in 0..=n {
        for j in 0..=m {
            grid[i][j] = if j == 0 {
                bottom[i]
            } else if j == m {
                top[i]
            } else if i == 0 {
                left[j]
            } else if i == n {
                right[j]
            } else {
                let (u, v) = (i as f64 / n as f64, j as f64 / m as f64);
                let at = (1.0 - v) * pb[i] + v * pt[i] + (1.0 - u) * pl[j] + u * pr[j]
                    - ((1.0 - u) * (1.0 - v) * corner[0]
                        + u * (1.0 - v) * corner[1]
                        + u * v * corner[2]
                        + (1.0 - u) * v * corner[3]);
                mesh.add_node(at, NodeKind::Interior)
            };
        }
    }
    let mut quads = Vec::with_capacity(n * m);
    for i in 0..n {
        for j in 0..m {
            quads.push([
                grid[i][j],
                grid[i + 1][j],
                grid[i + 1][j + 1],
                grid[i][j + 1],
            ]);
        }
    }
    quads
}
