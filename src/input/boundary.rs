//! Boundary discretisation and cutting lines (Fig. 2): the domain's loops
//! and inner lines become nodes, and holes and lines are joined to the
//! outer loop by cutting lines so that one loop remains.

use glam::DVec2;
use rustc_hash::FxHashMap;

use crate::geometry::{interior_angle, segments_intersect, SegmentRelation};
use crate::input::arc_corners::{self, CornerAim};
use crate::input::domain::{Chain, Curve, Domain, DomainError};
use crate::input::segment_counts::{segment_counts, CountBounds};
use crate::mesh::{BoundaryEdge, Mesh, NodeKind};

/// The discretised input: the mesh skeleton (boundary nodes and edges) and
/// the loops of the initial front.
#[derive(Debug, Clone)]
pub struct Discretised {
    /// Nodes (boundary, line and cutting-line nodes) and boundary edges.
    pub mesh: Mesh,
    /// The initial loops, domain on the left; nodes may repeat (both sides
    /// of a cut or an inner line). One loop, unless lines that reach the
    /// boundary or each other partition the domain: then one a region.
    pub front_loops: Vec<Vec<u32>>,
    /// The cutting lines made, as node paths (for the trace and pictures).
    #[allow(dead_code)] // no stage reads it yet
    pub cuts: Vec<Vec<u32>>,
    /// Whether a line ends on a loop or on another line (format 1.1).
    pub lines_meet: bool,
    /// Edges of the input given one segment count with the edges they
    /// face across a thin wall (see thin_walls.rs).
    pub thin_wall_edges: usize,
    /// Inner lines' edges given segments of their gap to another chain
    /// (see line_gaps.rs).
    pub near_line_edges: usize,
}

impl Discretised {
    /// The length of every segment of the initial loops.
    pub fn segment_lengths(&self) -> impl Iterator<Item = f64> + '_ {
        let nodes = &self.mesh.nodes;
        self.front_loops.iter().flat_map(move |l| {
            (0..l.len()).map(move |i| {
                (nodes[l[i] as usize] - nodes[l[(i + 1) % l.len()] as usize]).length()
            })
        })
    }
}

/// One component to join: the closed rings and open paths of node ids of
/// the chains that meet one another (one chain, unless lines end on a
/// loop or on each other).
#[derive(Debug, Clone, Default)]
struct Component {
    rings: Vec<Vec<u32>>,
    paths: Vec<Vec<u32>>,
    /// Nodes where chains meet: never the end of a cut.
    junctions: Vec<u32>,
}

/// The nodes of a chain, its boundary edges pushed to `mesh` with the
/// chain's group and the edges' tags (`tag_groups` maps a domain tag to
/// its group), and for each boundary edge its input edge in `sources`.
/// A line's vertex at a point where a vertex of an earlier chain lies
/// (a line ending on a loop or line) takes that vertex's node.
#[allow(clippy::too_many_arguments)]
fn chain_nodes(
    mesh: &mut Mesh,
    chain: &Chain,
    counts: &[usize],
    closed: bool,
    group: u32,
    reverse: bool,
    tag_groups: &[u32],
    vertices: &mut Vec<(DVec2, u32)>,
    sources: &mut Vec<usize>,
    aim: &CornerAim,
) -> Vec<u32> {
    let mut pts: Vec<DVec2> = Vec::new();
    let shares = arc_corners::end_shares(chain, counts, closed, !reverse, aim);
    // the input edge each segment lies on, and which points are vertices
    let mut seg_edge: Vec<usize> = Vec::new();
    let mut is_vertex: Vec<bool> = Vec::new();
    for (ei, (e, &n)) in chain.edges.iter().zip(counts).enumerate() {
        let p = arc_corners::divide(&e.curve, n, shares[ei], aim.growth);
        let k = match e.curve {
            Curve::Circle { .. } => p.len(),
            _ => n,
        };
        pts.extend(&p[..k]);
        is_vertex.extend((0..k).map(|i| i == 0 && !matches!(e.curve, Curve::Circle { .. })));
        seg_edge.extend(std::iter::repeat_n(ei, k));
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
        is_vertex.push(true);
    }
    if reverse {
        pts.reverse();
        is_vertex.reverse();
        // segment i now runs from point i to i+1 of the reversed list: it
        // was segment m-1-i (open) or, closed, segment n-2-i mod n
        let n = seg_edge.len();
        seg_edge = (0..n)
            .map(|i| {
                if closed {
                    seg_edge[(2 * n - 2 - i) % n]
                } else {
                    seg_edge[n - 1 - i]
                }
            })
            .collect();
    }
    let ids: Vec<u32> = pts
        .iter()
        .zip(&is_vertex)
        .map(|(&p, &vertex)| {
            let shared = (vertex && !closed)
                .then(|| vertices.iter().find(|(v, _)| *v == p).map(|&(_, id)| id))
                .flatten();
            let id = shared.unwrap_or_else(|| mesh.add_node(p, NodeKind::Boundary));
            if vertex && shared.is_none() {
                vertices.push((p, id));
            }
            id
        })
        .collect();
    let m = if closed { ids.len() } else { ids.len() - 1 };
    for i in 0..m {
        let ei = seg_edge[i];
        mesh.boundary.push(BoundaryEdge {
            a: ids[i],
            b: ids[(i + 1) % ids.len()],
            group,
            tag: chain.edges[ei].tag.map(|t| tag_groups[t as usize]),
        });
        sources.push(ei);
    }
    ids
}

/// Discretises the domain with boundary segment length `size` and joins
/// every hole and inner line to the outer loop by cutting lines. Where
/// lines that reach the boundary or each other part the domain into
/// regions, each region's loop is made even: a free edge of a loop round
/// it (or of a line between two odd regions) gets one more segment.
/// `bounds` are the KB's bounds of the segment counts, `jump` its
/// `max_size_jump` (a cut's segments kept within it of the input
/// segments at its ends).
pub fn discretise(
    domain: &Domain,
    size: f64,
    bounds: CountBounds,
    jump: f64,
    aim: &CornerAim,
) -> Result<Discretised, DomainError> {
    let (mut counts, changed) = segment_counts(domain, size, bounds)?;
    let told = |disc: Discretised| Discretised {
        thin_wall_edges: changed.walled,
        near_line_edges: changed.near_lines,
        ..disc
    };
    let (disc, faces, sources) = discretise_with(domain, size, jump, aim, &counts)?;
    if faces.iter().all(|f| f.len % 2 == 0) {
        return Ok(told(disc));
    }
    even_regions(domain, &disc.mesh, &faces, &sources, &mut counts)?;
    let (disc, faces, _) = discretise_with(domain, size, jump, aim, &counts)?;
    match faces.iter().find(|f| f.len % 2 == 1) {
        None => Ok(told(disc)),
        Some(f) => Err(DomainError::Geometry(format!(
            "a region of the domain has an odd number of boundary segments ({}): no all-quad mesh exists",
            f.len
        ))),
    }
}

/// Gives each region with an odd number of boundary segments one more:
/// on the free edge of a loop round it with the longest segments, or,
/// where it has none, on a free edge of a line it shares with another
/// odd region (both become even).
fn even_regions(
    domain: &Domain,
    mesh: &Mesh,
    faces: &[Face],
    sources: &[usize],
    counts: &mut [Vec<usize>],
) -> Result<(), DomainError> {
    let loops = 1 + domain.holes.len() as u32;
    let chains: Vec<&Chain> = domain.chains().collect();
    let input_edge = |i: usize| (mesh.boundary[i].group as usize, sources[i]);
    let free = |(ci, ei): (usize, usize)| chains[ci].edges[ei].segments.is_none();
    let mut odd: Vec<bool> = faces.iter().map(|f| f.len % 2 == 1).collect();
    let mut faces_of: std::collections::HashMap<usize, Vec<usize>> = Default::default();
    for (fi, f) in faces.iter().enumerate() {
        for &e in &f.edges {
            faces_of.entry(e).or_default().push(fi);
        }
    }
    for fi in 0..faces.len() {
        if !odd[fi] {
            continue;
        }
        let on_loop = faces[fi]
            .edges
            .iter()
            .filter(|&&e| mesh.boundary[e].group < loops)
            .map(|&e| input_edge(e))
            .filter(|&x| free(x))
            .map(|(ci, ei)| {
                let len = chains[ci].edges[ei].curve.length() / counts[ci][ei] as f64;
                (len, ci, ei)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        if let Some((_, ci, ei)) = on_loop {
            counts[ci][ei] += 1;
            odd[fi] = false;
            continue;
        }
        let on_line = faces[fi].edges.iter().find_map(|&e| {
            let other = faces_of[&e].iter().copied().find(|&g| g != fi && odd[g])?;
            (mesh.boundary[e].group >= loops && free(input_edge(e))).then_some((e, other))
        });
        match on_line {
            Some((e, other)) => {
                let (ci, ei) = input_edge(e);
                counts[ci][ei] += 1;
                odd[fi] = false;
                odd[other] = false;
            }
            None => {
                return Err(DomainError::Geometry(format!(
                    "a region of the domain has {} boundary segments, an odd number, and no free edge to add one to: no all-quad mesh exists",
                    faces[fi].len
                )))
            }
        }
    }
    Ok(())
}

/// A loop of the initial front, as `discretise` sees it for parity: its
/// length and the boundary edges (indices into `Mesh::boundary`) it runs
/// along.
struct Face {
    len: usize,
    edges: Vec<usize>,
}

/// A discretisation with given segment counts, its faces, and the input
/// edge (within its chain) of each boundary edge.
fn discretise_with(
    domain: &Domain,
    size: f64,
    jump: f64,
    aim: &CornerAim,
    counts: &[Vec<usize>],
) -> Result<(Discretised, Vec<Face>, Vec<usize>), DomainError> {
    let mut mesh = Mesh::default();
    let mut vertices = Vec::new();
    let mut sources = Vec::new();
    let mut chains: Vec<(Vec<u32>, bool)> = Vec::new();
    mesh.groups.push("outer".into());
    for i in 0..domain.holes.len() {
        mesh.groups.push(format!("hole {}", i + 1));
    }
    for i in 0..domain.lines.len() {
        mesh.groups.push(format!("line {}", i + 1));
    }
    let tag_groups: Vec<u32> = domain.tags.iter().map(|t| mesh.group_named(t)).collect();
    let first_line = 1 + domain.holes.len() as u32;
    mesh.crack_lines = (0..domain.lines.len() as u32)
        .filter(|&i| domain.lines[i as usize].crack)
        .map(|i| first_line + i)
        .collect();
    let outer_ccw = domain.outer.signed_area() > 0.0;
    for (ci, chain) in domain.chains().enumerate() {
        let closed = ci <= domain.holes.len();
        // the outer loop is walked counter-clockwise, holes clockwise: the
        // domain is then on the left
        let reverse = match ci {
            0 => !outer_ccw,
            _ if closed => chain.signed_area() > 0.0,
            _ => false,
        };
        let nodes = chain_nodes(
            &mut mesh,
            chain,
            &counts[ci],
            closed,
            ci as u32,
            reverse,
            &tag_groups,
            &mut vertices,
            &mut sources,
            aim,
        );
        chains.push((nodes, closed));
    }
    let mut at: Vec<[u64; 2]> = vertices
        .iter()
        .map(|(p, _)| [p.x.to_bits(), p.y.to_bits()])
        .collect();
    at.sort_unstable();
    mesh.input_vertices = Some(at);
    let comps = components(&chains);
    let lines_meet = comps.iter().any(|c| !c.junctions.is_empty());
    // a cut's segments within the size jump of the input segments at its
    // ends, as far as a cut allows
    let cuts = join_components(&mut mesh, &comps, size, jump)?;
    let (front_loops, faces) = trace_faces(&mesh, 1 + domain.holes.len() as u32, &cuts);
    Ok((
        Discretised {
            mesh,
            front_loops,
            cuts,
            lines_meet,
            thin_wall_edges: 0,
            near_line_edges: 0,
        },
        faces,
        sources,
    ))
}

/// The chains grouped into components: chains that share a node (a line
/// ending on a loop or another line) are one component. In the order of
/// their first chain, so the outer loop's comes first.
fn components(chains: &[(Vec<u32>, bool)]) -> Vec<Component> {
    let n = chains.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut owner: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
    let mut junctions: Vec<u32> = Vec::new();
    for (ci, (nodes, _)) in chains.iter().enumerate() {
        for &v in nodes {
            match owner.get(&v) {
                Some(&cj) if cj != ci => {
                    let (a, b) = (root(&mut parent, ci), root(&mut parent, cj));
                    parent[a.max(b)] = a.min(b);
                    junctions.push(v);
                }
                Some(_) => {}
                None => {
                    owner.insert(v, ci);
                }
            }
        }
    }
    let mut index: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut comps: Vec<Component> = Vec::new();
    for (ci, (nodes, closed)) in chains.iter().enumerate() {
        let r = root(&mut parent, ci);
        let k = *index.entry(r).or_insert_with(|| {
            comps.push(Component::default());
            comps.len() - 1
        });
        if *closed {
            comps[k].rings.push(nodes.clone());
        } else {
            comps[k].paths.push(nodes.clone());
        }
    }
    for c in &mut comps {
        c.junctions = junctions
            .iter()
            .copied()
            .filter(|j| c.rings.iter().chain(&c.paths).any(|r| r.contains(j)))
            .collect();
    }
    comps
}

/// The candidate attachment nodes of a component: ring nodes and line
/// ends, but no node where chains meet.
fn attach_nodes(c: &Component) -> Vec<u32> {
    c.rings
        .iter()
        .flat_map(|r| r.iter().copied())
        .chain(
            c.paths
                .iter()
                .flat_map(|p| [p[0], *p.last().expect("lines have points")]),
        )
        .filter(|v| !c.junctions.contains(v))
        .collect()
}

/// The wedge of directions into the domain at a ring node of a component:
/// (direction to next, interior angle), domain on the left of the walk;
/// a line end is open all round (None).
fn wedge(mesh: &Mesh, c: &Component, node: u32) -> Option<(DVec2, f64)> {
    let ring = c.rings.iter().find(|r| r.contains(&node))?;
    let k = ring.iter().position(|&n| n == node)?;
    let n = ring.len();
    let p = mesh.nodes[ring[(k + n - 1) % n] as usize];
    let v = mesh.nodes[node as usize];
    let x = mesh.nodes[ring[(k + 1) % n] as usize];
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

/// Joins every component to the outer loop's by the shortest clear
/// cutting lines (Fig. 2); returns the cuts as node paths, each from the
/// joined side to the component it joins.
fn join_components(
    mesh: &mut Mesh,
    comps: &[Component],
    size: f64,
    jump: f64,
) -> Result<Vec<Vec<u32>>, DomainError> {
    let n = comps.len();
    // All input segments, for the crossing tests of candidate cuts.
    let mut segs: Vec<(DVec2, DVec2, u32, u32)> = Vec::new();
    for c in comps {
        let rings = c.rings.iter().map(|r| (r, true));
        for (nodes, closed) in rings.chain(c.paths.iter().map(|p| (p, false))) {
            let m = if closed { nodes.len() } else { nodes.len() - 1 };
            for i in 0..m {
                let (a, b) = (nodes[i], nodes[(i + 1) % nodes.len()]);
                segs.push((mesh.nodes[a as usize], mesh.nodes[b as usize], a, b));
            }
        }
    }
    // The shortest input segment at each node: a cut's segments (about
    // `size` long) next to much shorter ones would start the mesh with a
    // size jump there (the sharp trailing edge of a blade).
    let mut shortest_at: FxHashMap<u32, f64> = FxHashMap::default();
    for &(a, b, na, nb) in &segs {
        let l = (b - a).length();
        for x in [na, nb] {
            let e = shortest_at.entry(x).or_insert(f64::INFINITY);
            *e = e.min(l);
        }
    }
    let grade = |node: u32, len: f64| -> f64 {
        let seg = len / ((len / size).round().max(1.0));
        let local = shortest_at.get(&node).copied().unwrap_or(f64::INFINITY);
        (seg / (jump * local)).max(1.0)
    };
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
            let (best, ended) = best_cut(mesh, comps, &segs, &cut_segs, &used, &cands, &grade);
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
    Ok(cuts
        .iter()
        .map(|c| {
            std::iter::once(c.0)
                .chain(c.3.iter().copied())
                .chain(std::iter::once(c.1))
                .collect()
        })
        .collect())
}

/// The loops of the initial front: the faces of the plane graph of the
/// boundary edges (loops walked one way, domain on the left; lines and
/// cuts both ways), each walked turning as far right as it can at every
/// node, so the region is on the left. The first loop starts where the
/// walk round the outer loop leaves its first node. With one region this
/// is the one loop round the outer ring that detours along each cut and
/// round every line and hole it reaches.
fn trace_faces(mesh: &Mesh, loops: u32, cuts: &[Vec<u32>]) -> (Vec<Vec<u32>>, Vec<Face>) {
    use std::f64::consts::TAU;
    // half-edges: (from, to, boundary edge it runs along)
    let mut half: Vec<(u32, u32, Option<usize>)> = Vec::new();
    for (i, e) in mesh.boundary.iter().enumerate() {
        half.push((e.a, e.b, Some(i)));
        if e.group >= loops {
            half.push((e.b, e.a, Some(i)));
        }
    }
    for c in cuts {
        for w in c.windows(2) {
            half.push((w[0], w[1], None));
            half.push((w[1], w[0], None));
        }
    }
    let mut out_of: std::collections::HashMap<u32, Vec<usize>> = std::collections::HashMap::new();
    for (h, &(a, _, _)) in half.iter().enumerate() {
        out_of.entry(a).or_default().push(h);
    }
    let dir = |a: u32, b: u32| {
        let d = mesh.nodes[b as usize] - mesh.nodes[a as usize];
        d.y.atan2(d.x)
    };
    // the half-edge after h: the first out of its end clockwise from the
    // way back (the way back itself last)
    let next = |h: usize| -> usize {
        let (a, v, _) = half[h];
        let back = dir(v, a);
        let turn = |g: usize| {
            let t = (back - dir(v, half[g].1)).rem_euclid(TAU);
            if half[g].1 == a && t < 1e-12 {
                TAU
            } else {
                t
            }
        };
        *out_of[&v]
            .iter()
            .min_by(|&&g, &&k| turn(g).total_cmp(&turn(k)).then(g.cmp(&k)))
            .expect("a boundary node has a way on")
    };
    let mut seen = vec![false; half.len()];
    let mut loops_out = Vec::new();
    let mut faces = Vec::new();
    let outer_len = mesh.boundary.iter().take_while(|e| e.group == 0).count();
    let first = (outer_len > 0).then(|| next(outer_len - 1));
    for start in first.into_iter().chain(0..half.len()) {
        if seen[start] {
            continue;
        }
        let (mut nodes, mut edges) = (Vec::new(), Vec::new());
        let mut h = start;
        while !seen[h] {
            seen[h] = true;
            nodes.push(half[h].0);
            edges.extend(half[h].2);
            h = next(h);
        }
        faces.push(Face {
            len: nodes.len(),
            edges,
        });
        loops_out.push(nodes);
    }
    (loops_out, faces)
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
    grade: &dyn Fn(u32, f64) -> f64,
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
        // A cut whose segments would be more than `jump` times the
        // input segments at an end is worse by that much.
        let score = len / q.sin() * grade(u, len).max(grade(v, len));
        if best.is_none_or(|b| score < b.0) {
            best = Some((score, v, u, ci));
        }
    }
    (best, false)
}

#[cfg(test)]
mod tests {
    use super::discretise;
    use crate::input::arc_corners::CornerAim;
    use crate::input::domain::Domain;
    use crate::input::segment_counts::CountBounds;

    /// A cut does not start at a sharp tip whose input segments are far
    /// shorter than the cut's (a blade's trailing edge next to the outer
    /// loop), though it is the shortest way out.
    #[test]
    fn a_cut_leaves_a_hole_away_from_its_short_segments() {
        let domain = Domain::from_json_str(
            r#"{"size": 0.2,
                "outer": {"points": [[-3, -3], [3, -3], [3, 3], [-3, 3]]},
                "holes": [{"points": [[2.5, 0], [2.49, 0.003], [0, 0.5], [-1, 0],
                                      [0, -0.5], [2.49, -0.003]]}]}"#,
        )
        .unwrap();
        let disc = discretise(&domain, 0.2, CountBounds::PLAIN, 2.0, &CornerAim::paper()).unwrap();
        assert_eq!(disc.cuts.len(), 1);
        let tip = glam::DVec2::new(2.5, 0.0);
        for end in [disc.cuts[0][0], *disc.cuts[0].last().unwrap()] {
            let p = disc.mesh.nodes[end as usize];
            assert!((p - tip).length() > 0.05, "the cut ends at {p} by the tip");
        }
        // the bound is the KB's to set: with no limit on the jump the
        // shortest cut, from the tip, wins
        let loose =
            discretise(&domain, 0.2, CountBounds::PLAIN, 100.0, &CornerAim::paper()).unwrap();
        let ends = [loose.cuts[0][0], *loose.cuts[0].last().unwrap()];
        assert!(
            ends.iter()
                .any(|&e| (loose.mesh.nodes[e as usize] - tip).length() < 0.05),
            "{:?}",
            ends.map(|e| loose.mesh.nodes[e as usize])
        );
    }
}
