//! Boundary discretisation and cutting lines (Fig. 2): the domain's loops
//! and inner lines become nodes, and holes and lines are joined to the
//! outer loop by cutting lines so that one loop remains.

use glam::DVec2;

use crate::geometry::{interior_angle, segments_intersect, SegmentRelation};
use crate::input::domain::{Chain, Curve, Domain, DomainError, MAX_BOUNDARY_SEGMENTS};
use crate::mesh::{BoundaryEdge, Mesh, NodeKind};

/// The fewest segments a curve may have: one per 60 deg of arc.
fn min_arc_segments(c: &Curve) -> usize {
    let sweep = match *c {
        Curve::Line { .. } => return 1,
        Curve::Arc { bulge, .. } => (4.0 * bulge.atan()).abs(),
        Curve::Circle { .. } => 2.0 * std::f64::consts::PI,
    };
    (sweep / (std::f64::consts::PI / 3.0) - 1e-9)
        .ceil()
        .max(1.0) as usize
}

/// The segment count of every edge of every chain (outer, holes, lines in
/// that order), with an even total: where the total of the derived counts
/// is odd, the free edge of a loop with the longest segments gets one more.
pub fn segment_counts(domain: &Domain, size: f64) -> Result<Vec<Vec<usize>>, DomainError> {
    let mut counts = Vec::new();
    let mut total: u128 = 0;
    // (segment length, chain, edge) of the free edges of loops
    let mut best_free: Option<(f64, usize, usize)> = None;
    let n_loops = 1 + domain.holes.len();
    for (ci, chain) in domain.chains().enumerate() {
        let mut row = Vec::new();
        for (ei, e) in chain.edges.iter().enumerate() {
            let len = e.curve.length();
            let n = match e.segments {
                Some(n) => n,
                None => {
                    let est = (len / size).round();
                    if !est.is_finite() || est > MAX_BOUNDARY_SEGMENTS as f64 {
                        return Err(DomainError::Geometry(format!(
                            "{} edge {ei}: size {size} gives about {est:.3e} segments, above the limit of {MAX_BOUNDARY_SEGMENTS}",
                            chain.label
                        )));
                    }
                    // No segment spans more than 60 deg of arc, so the
                    // chords stay close to the curve: a circle gets at
                    // least 6, a half circle 3.
                    let n = (est as usize).max(1).max(min_arc_segments(&e.curve));
                    if ci < n_loops {
                        let cand = (len / n as f64, ci, ei);
                        if best_free.is_none_or(|b| (cand.0, cand.1, cand.2) >= b) {
                            best_free = Some(cand);
                        }
                    }
                    n
                }
            };
            total += n as u128 * if ci >= n_loops { 2 } else { 1 };
            row.push(n);
        }
        counts.push(row);
    }
    if total > MAX_BOUNDARY_SEGMENTS as u128 {
        return Err(DomainError::Geometry(format!(
            "{total} boundary segments is above the limit of {MAX_BOUNDARY_SEGMENTS}"
        )));
    }
    if total % 2 == 1 {
        match best_free {
            Some((_, ci, ei)) => counts[ci][ei] += 1,
            None => {
                let per: Vec<String> = domain
                    .chains()
                    .zip(&counts)
                    .map(|(c, r)| format!("{} {}", c.label, r.iter().sum::<usize>()))
                    .collect();
                return Err(DomainError::Geometry(format!(
                    "the fixed segment counts total {total}, which is odd: no all-quad mesh exists ({})",
                    per.join(", ")
                )));
            }
        }
    }
    Ok(counts)
}

/// The discretised input: the mesh skeleton (boundary nodes and edges) and
/// the one loop of the initial front.
#[derive(Debug, Clone)]
pub struct Discretised {
    /// Nodes (boundary, line and cutting-line nodes) and boundary edges.
    pub mesh: Mesh,
    /// The initial loop, domain on the left; nodes may repeat (both sides of
    /// a cut or an inner line).
    pub front_loop: Vec<u32>,
    /// The cutting lines made, as node paths (for the trace and pictures).
    #[allow(dead_code)] // no stage reads it yet
    pub cuts: Vec<Vec<u32>>,
}

/// One component to join: a closed ring or an open path of node ids.
#[derive(Debug, Clone)]
struct Component {
    nodes: Vec<u32>,
    closed: bool,
}

fn chain_nodes(
    mesh: &mut Mesh,
    chain: &Chain,
    counts: &[usize],
    closed: bool,
    group: u32,
    reverse: bool,
) -> Vec<u32> {
    let mut pts: Vec<DVec2> = Vec::new();
    for (e, &n) in chain.edges.iter().zip(counts) {
        let p = e.curve.divide(n);
        match e.curve {
            Curve::Circle { .. } => pts.extend(p),
            _ => pts.extend(&p[..n]),
        }
    }
    if !closed {
        pts.push(
            chain
                .edges
                .last()
                .expect("a chain has edges")
                .curve
                .point_at(1.0),
        );
    }
    if reverse {
        pts.reverse();
    }
    let ids: Vec<u32> = pts
        .iter()
        .map(|&p| mesh.add_node(p, NodeKind::Boundary))
        .collect();
    let m = if closed { ids.len() } else { ids.len() - 1 };
    for i in 0..m {
        mesh.boundary.push(BoundaryEdge {
            a: ids[i],
            b: ids[(i + 1) % ids.len()],
            group,
        });
    }
    ids
}

/// Discretises the domain with boundary segment length `size` and joins
/// every hole and inner line to the outer loop by cutting lines.
pub fn discretise(domain: &Domain, size: f64) -> Result<Discretised, DomainError> {
    let counts = segment_counts(domain, size)?;
    let mut mesh = Mesh::default();
    let mut comps = Vec::new();
    mesh.groups.push("outer".into());
    let outer_ccw = domain.outer.signed_area() > 0.0;
    comps.push(Component {
        nodes: chain_nodes(&mut mesh, &domain.outer, &counts[0], true, 0, !outer_ccw),
        closed: true,
    });
    for (i, h) in domain.holes.iter().enumerate() {
        mesh.groups.push(format!("hole {}", i + 1));
        let ccw = h.signed_area() > 0.0;
        // holes are walked clockwise: the domain is then on the left
        let g = mesh.groups.len() as u32 - 1;
        comps.push(Component {
            nodes: chain_nodes(&mut mesh, h, &counts[1 + i], true, g, ccw),
            closed: true,
        });
    }
    for (i, l) in domain.lines.iter().enumerate() {
        mesh.groups.push(format!("line {}", i + 1));
        let g = mesh.groups.len() as u32 - 1;
        comps.push(Component {
            nodes: chain_nodes(
                &mut mesh,
                l,
                &counts[1 + domain.holes.len() + i],
                false,
                g,
                false,
            ),
            closed: false,
        });
    }
    let (front_loop, cuts) = join_components(&mut mesh, &comps, size)?;
    Ok(Discretised {
        mesh,
        front_loop,
        cuts,
    })
}

/// A candidate attachment node of a component: ring nodes, or a line's ends.
fn attach_nodes(c: &Component) -> Vec<u32> {
    if c.closed {
        c.nodes.clone()
    } else {
        vec![c.nodes[0], *c.nodes.last().expect("lines have points")]
    }
}

/// The wedge of directions into the domain at a node of a component:
/// (direction to next, direction to prev, interior angle), domain on the
/// left of the walk; a line end is open all round.
fn wedge(mesh: &Mesh, c: &Component, node: u32) -> Option<(DVec2, f64)> {
    if !c.closed {
        return None;
    }
    let k = c.nodes.iter().position(|&n| n == node)?;
    let n = c.nodes.len();
    let p = mesh.nodes[c.nodes[(k + n - 1) % n] as usize];
    let v = mesh.nodes[node as usize];
    let x = mesh.nodes[c.nodes[(k + 1) % n] as usize];
    Some(((x - v).normalize_or_zero(), interior_angle(p, v, x)))
}

/// The angle, counter-clockwise from `from`, of direction `d` (0..2π).
fn ccw_angle(from: DVec2, d: DVec2) -> f64 {
    let a = from.perp_dot(d).atan2(from.dot(d));
    if a < 0.0 {
        a + 2.0 * std::f64::consts::PI
    } else {
        a
    }
}

/// How well a cut leaving `node` in direction `d` splits its wedge: the
/// smaller of the two angles it makes (radians), or None if it leaves the
/// domain.
fn split_quality(mesh: &Mesh, c: &Component, node: u32, d: DVec2) -> Option<f64> {
    match wedge(mesh, c, node) {
        None => Some(std::f64::consts::PI),
        Some((to_next, theta)) => {
            let a = ccw_angle(to_next, d);
            if a <= 1e-9 || a >= theta - 1e-9 {
                return None;
            }
            Some(a.min(theta - a))
        }
    }
}

fn join_components(
    mesh: &mut Mesh,
    comps: &[Component],
    size: f64,
) -> Result<(Vec<u32>, Vec<Vec<u32>>), DomainError> {
    let n = comps.len();
    // All input segments, for the crossing tests of candidate cuts.
    let mut segs: Vec<(DVec2, DVec2, u32, u32)> = Vec::new();
    for c in comps {
        let m = if c.closed {
            c.nodes.len()
        } else {
            c.nodes.len() - 1
        };
        for i in 0..m {
            let (a, b) = (c.nodes[i], c.nodes[(i + 1) % c.nodes.len()]);
            segs.push((mesh.nodes[a as usize], mesh.nodes[b as usize], a, b));
        }
    }
    let mut joined = vec![false; n];
    joined[0] = true;
    let mut used = std::collections::HashSet::new();
    // cut: (parent node, child node, child component, interior node ids)
    let mut cuts: Vec<(u32, u32, usize, Vec<u32>)> = Vec::new();
    let mut cut_segs: Vec<(DVec2, DVec2)> = Vec::new();
    type Cand = (f64, u32, u32, usize, usize);
    // In order of length (ties by node ids: a total order).
    let order = |a: &Cand, b: &Cand| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2));
    for _ in 1..n {
        // The shortest admissible cut from any joined to any unjoined one.
        // The pairs of nodes are many (their number grows with the square
        // of the boundary's), so only those up to a length are listed, the
        // length doubling until the search ends inside the list: the same
        // cut as searching the whole sorted list.
        let pairs = || {
            comps
                .iter()
                .enumerate()
                .filter(|(ci, _)| !joined[*ci])
                .flat_map(|(ci, c)| {
                    comps
                        .iter()
                        .enumerate()
                        .filter(|(di, _)| joined[*di])
                        .flat_map(move |(di, d)| {
                            attach_nodes(c).into_iter().flat_map(move |u| {
                                attach_nodes(d).into_iter().map(move |v| (u, v, ci, di))
                            })
                        })
                })
        };
        let pair_len = |u: u32, v: u32| (mesh.nodes[u as usize] - mesh.nodes[v as usize]).length();
        let shortest = pairs()
            .map(|(u, v, _, _)| pair_len(u, v))
            .fold(f64::INFINITY, f64::min);
        // most searches end a little past the shortest pair
        let mut margin = 0.05 * shortest + 4.0 * size;
        let best = loop {
            let mut cands: Vec<Cand> = Vec::new();
            let mut all_listed = true;
            for (u, v, ci, di) in pairs() {
                let len = pair_len(u, v);
                if len <= shortest + margin {
                    cands.push((len, v, u, ci, di));
                } else {
                    all_listed = false;
                }
            }
            cands.sort_by(order);
            let (best, ended) = best_cut(mesh, comps, &segs, &cut_segs, &used, &cands);
            // a candidate past the list is longer than its limit: it cannot
            // beat a cut whose score is within it
            if ended || all_listed || best.is_some_and(|b| b.0 <= shortest + margin) {
                break best;
            }
            margin *= 2.0;
        };
        let Some((_, v, u, ci)) = best else {
            return Err(DomainError::Geometry("cannot join the holes and lines to the outer loop: no clear cutting line (are they too close?)".into()));
        };
        used.insert(u);
        used.insert(v);
        let (pv, pu) = (mesh.nodes[v as usize], mesh.nodes[u as usize]);
        let k = (((pu - pv).length() / size).round() as usize).max(1);
        let interior: Vec<u32> = (1..k)
            .map(|i| mesh.add_node(pv + (pu - pv) * (i as f64 / k as f64), NodeKind::Interior))
            .collect();
        cut_segs.push((pv, pu));
        cuts.push((v, u, ci, interior));
        joined[ci] = true;
    }
    // Walk: the loop round the outer ring, detouring along each cut.
    let mut child_of = std::collections::HashMap::new();
    for (i, c) in cuts.iter().enumerate() {
        child_of.insert(c.0, i);
    }
    let mut out = Vec::new();
    tour(comps, &cuts, &child_of, 0, comps[0].nodes[0], &mut out);
    let cut_paths = cuts
        .iter()
        .map(|c| {
            std::iter::once(c.0)
                .chain(c.3.iter().copied())
                .chain(std::iter::once(c.1))
                .collect()
        })
        .collect();
    Ok((out, cut_paths))
}

/// The search of `join_components` over candidate cuts sorted by length:
/// the best-scoring admissible cut (score, parent node, child node, child
/// component), and whether the search ended before the list did.
fn best_cut(
    mesh: &Mesh,
    comps: &[Component],
    segs: &[(DVec2, DVec2, u32, u32)],
    cut_segs: &[(DVec2, DVec2)],
    used: &std::collections::HashSet<u32>,
    cands: &[(f64, u32, u32, usize, usize)],
) -> (Option<(f64, u32, u32, usize)>, bool) {
    let mut best: Option<(f64, u32, u32, usize)> = None;
    let mut checked = 0;
    for &(len, v, u, ci, di) in cands {
        if used.contains(&u) || used.contains(&v) || len <= 0.0 {
            continue;
        }
        // score >= len: no longer candidate can win; the cap bounds time
        if best.is_some_and(|b| len >= b.0) || checked > 3000 {
            return (best, true);
        }
        checked += 1;
        let (pv, pu) = (mesh.nodes[v as usize], mesh.nodes[u as usize]);
        let dir = (pu - pv) / len;
        let (Some(qv), Some(qu)) = (
            split_quality(mesh, &comps[di], v, dir),
            split_quality(mesh, &comps[ci], u, -dir),
        ) else {
            continue;
        };
        let clear = segs.iter().all(|&(a, b, na, nb)| {
            if na == u || na == v || nb == u || nb == v {
                return true;
            }
            segments_intersect(pv, pu, a, b) == SegmentRelation::Disjoint
        }) && cut_segs
            .iter()
            .all(|&(a, b)| segments_intersect(pv, pu, a, b) == SegmentRelation::Disjoint);
        if !clear {
            continue;
        }
        // Shorter is better; a cut meeting a wall at a slant is worse.
        let q = qv.min(qu).min(std::f64::consts::FRAC_PI_2);
        let score = len / q.sin();
        if best.is_none_or(|b| score < b.0) {
            best = Some((score, v, u, ci));
        }
    }
    (best, false)
}

type Cut = (u32, u32, usize, Vec<u32>);

/// Emits the loop round component `ci` from node `start` (not repeating
/// `start` at the end), detouring through each cut that hangs from it.
fn tour(
    comps: &[Component],
    cuts: &[Cut],
    child_of: &std::collections::HashMap<u32, usize>,
    ci: usize,
    start: u32,
    out: &mut Vec<u32>,
) {
    let c = &comps[ci];
    let order: Vec<u32> = if c.closed {
        let k = c
            .nodes
            .iter()
            .position(|&x| x == start)
            .expect("start is on the ring");
        (0..c.nodes.len())
            .map(|i| c.nodes[(k + i) % c.nodes.len()])
            .collect()
    } else {
        // out to the far end and back along the other side
        let mut p = c.nodes.clone();
        if p[0] != start {
            p.reverse();
        }
        let back: Vec<u32> = p[1..p.len() - 1].iter().rev().copied().collect();
        p.extend(back);
        p
    };
    for (i, &v) in order.iter().enumerate() {
        out.push(v);
        if i == 0 && ci != 0 {
            continue; // the start hangs from the parent's cut
        }
        if let Some(&k) = child_of.get(&v) {
            let (_, u, child, interior) = &cuts[k];
            out.extend(interior.iter().copied());
            tour(comps, cuts, child_of, *child, *u, out);
            out.push(*u);
            out.extend(interior.iter().rev().copied());
            out.push(v);
        }
    }
}
