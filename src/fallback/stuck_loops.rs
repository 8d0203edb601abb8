//! The fallback for the loops the rules and the loop subdivision leave
//! open: only those loops are meshed by triangles split into quads, and
//! the elements the rules made stay.
//!
//! Splitting a triangle into three quads puts a node in the middle of
//! each of its edges, so every edge of an open loop is halved. The rules'
//! element on the other side of such an edge must be halved with it: it
//! is split in two across the edge, which halves its opposite edge, and
//! so on along the element's chord (the row of elements across from the
//! edge) until the chord ends on the domain's boundary or comes back to
//! an open loop. An element two chords cross is split in four. The
//! halved elements are about half as wide as their neighbours: a size
//! step of the square root of two, within the paper's smooth transition.
//! Where the loop's triangles pair into quads (pairs.rs) only those left
//! over are split so.

use glam::DVec2;
use std::collections::HashMap;

pub use super::open_region::Spacing;
use super::open_region::{halving, key, EdgeQuads};
use super::pairs;
use super::triangles::{place_centre, project_on_chain, split_in_three, FallbackError};
use crate::geometry::{segments_intersect, SegmentRelation};
use crate::input::domain::Domain;
use crate::mesh::{BoundaryEdge, Mesh, NodeKind};

/// The mesh with its open loops closed, and what it took.
pub struct LoopsClosed {
    /// The whole mesh: the rules' elements (some split) and the loops'.
    pub mesh: Mesh,
    /// Elements made inside the open loops.
    pub loop_elements: usize,
    /// Rules' elements split to carry the halving along their chords.
    pub split_elements: usize,
    /// Rules' elements taken back (after a runaway).
    pub taken_back: usize,
    /// The loops' triangles were paired into quads (no element split).
    pub paired: bool,
}

/// The element size open loops are closed at: the run's `size`, or in a
/// `graded` run the mean of the loops' edges where that is larger (the
/// loops left inside are coarser than the boundary).
pub fn open_loop_size(mesh: &Mesh, loops: &[Vec<u32>], size: f64, graded: bool) -> f64 {
    if !graded {
        return size;
    }
    let nodes = mesh.nodes();
    let (mut sum, mut n) = (0.0, 0usize);
    for l in loops {
        for (i, &a) in l.iter().enumerate() {
            let b = l[(i + 1) % l.len()];
            sum += (nodes[a as usize] - nodes[b as usize]).length();
            n += 1;
        }
    }
    if n == 0 {
        size
    } else {
        (sum / n as f64).max(size)
    }
}

/// Meshes the open `loops` (node ids of `mesh`, in loop order, the open
/// region on their left) by triangles split into quads, and halves the
/// elements of `mesh` along the chords that leave the loops. `spacing` is
/// the spacing of the interior points (a lattice triangle is split into
/// three quads: 1.5 sizes gives quads of about two-thirds of the size,
/// near the halved rows beside them). With `take_back` (after a runaway:
/// the rules made ever smaller elements), the elements next to the open
/// loops whose area is under `take_back`, and those next to them, are
/// taken back first and meshed with the loops.
pub fn close_open_loops(
    mesh: &Mesh,
    loops: &[Vec<u32>],
    domain: &Domain,
    spacing: Spacing,
    take_back: Option<f64>,
) -> Result<LoopsClosed, FallbackError> {
    // The open region's edges, directed with the region on their left.
    let mut directed: Vec<(u32, u32)> = Vec::new();
    for l in loops {
        for i in 0..l.len() {
            directed.push((l[i], l[(i + 1) % l.len()]));
        }
    }
    // the one copy of the mesh, its rules' elements taken out to be split
    let mut out = mesh.clone();
    let on_curve = on_curve(&out);
    let taken = match take_back {
        Some(area) => {
            let taken = small_ones(&out, &directed, &on_curve, area);
            take_back_marked(&mut out, &mut directed, &on_curve, &taken)
        }
        None => 0,
    };
    close_region(out, directed, &on_curve, domain, spacing, taken)
}

/// Where the rules' elements lost boundary or inner-line segments (no
/// element has them as an edge): the elements within `rings` of their
/// ends, and any element across them, are taken back, and the region they
/// leave, with the segments in it, is meshed by triangles split into quads
/// as an open loop is. `lost` is directed as the region's edges are (the
/// region on their left): both ways for a segment inside the region, one
/// way for one bounding it. The rest of the mesh stays as the rules made
/// it.
pub fn reopen_lost_segment(
    mesh: &Mesh,
    lost: &[(u32, u32)],
    rings: usize,
    domain: &Domain,
    spacing: Spacing,
) -> Result<LoopsClosed, FallbackError> {
    let mut out = mesh.clone();
    let on_curve = on_curve(&out);
    let mut near: Vec<bool> = vec![false; out.nodes.len()];
    for &(a, b) in lost {
        near[a as usize] = true;
        near[b as usize] = true;
    }
    // an element across a lost segment is taken too, with its rings
    let crosses = |p: DVec2, q: DVec2| {
        lost.iter().any(|&(a, b)| {
            let (pa, pb) = (out.nodes[a as usize], out.nodes[b as usize]);
            segments_intersect(p, q, pa, pb) == SegmentRelation::Cross
        })
    };
    for q in &out.quads {
        if (0..4).any(|i| crosses(out.nodes[q[i] as usize], out.nodes[q[(i + 1) % 4] as usize])) {
            for &n in q {
                near[n as usize] = true;
            }
        }
    }
    let mut taken = vec![false; out.quads.len()];
    for _ in 0..rings {
        for (qi, q) in out.quads.iter().enumerate() {
            if q.iter().any(|&n| near[n as usize]) {
                taken[qi] = true;
            }
        }
        for (qi, q) in out.quads.iter().enumerate() {
            if taken[qi] {
                for &n in q {
                    near[n as usize] = true;
                }
            }
        }
    }
    let mut directed = lost.to_vec();
    let count = take_back_marked(&mut out, &mut directed, &on_curve, &taken);
    close_region(out, directed, &on_curve, domain, spacing, count)
}

/// The input's boundary and line segments, each with its chain.
fn on_curve(mesh: &Mesh) -> HashMap<(u32, u32), u32> {
    mesh.boundary
        .iter()
        .map(|e| (key(e.a, e.b), e.group))
        .collect()
}

/// Meshes the open region of `directed` (the region on their left) in
/// `out`: triangulated, its triangles paired into quads where they pair
/// up (fallback/pairs.rs), and the triangles left over split into three
/// quads each, the halving of their edges carried along the chords of
/// the quads round them, the loop's and the rules' (see
/// `close_open_loops`). Where every triangle is paired no element is
/// split; where none is, every loop edge is halved.
fn close_region(
    mut out: Mesh,
    directed: Vec<(u32, u32)>,
    on_curve: &HashMap<(u32, u32), u32>,
    domain: &Domain,
    spacing: Spacing,
    taken: usize,
) -> Result<LoopsClosed, FallbackError> {
    let chains: Vec<&crate::input::domain::Chain> = domain.chains().collect();
    // The region's edges: an edge met once bounds the open region; met
    // twice (both sides of a line, a slit) it lies inside it.
    let mut loop_edges: Vec<(u32, u32)> = Vec::new();
    let mut times: HashMap<(u32, u32), u32> = HashMap::new();
    for &(a, b) in &directed {
        let k = key(a, b);
        let t = times.entry(k).or_insert(0);
        if *t == 0 {
            loop_edges.push(k);
        }
        *t += 1;
    }
    if loop_edges.is_empty() {
        return Err(FallbackError("no open loop".into()));
    }

    let rule_quads = std::mem::take(&mut out.quads);
    let rules = EdgeQuads::new(&rule_quads);
    let region = pairs::pair_region(&out.nodes, &rules, &loop_edges, &times, spacing)?;
    // the lattice points become mesh nodes
    let mut ids = region.ids;
    for &p in &region.points[ids.len()..] {
        ids.push(out.add_node(p, NodeKind::Interior));
    }
    let paired: Vec<[u32; 4]> = region
        .pairs
        .iter()
        .map(|q| q.map(|n| ids[n as usize]))
        .collect();
    let triangles: Vec<[u32; 3]> = region
        .left_over
        .iter()
        .map(|t| t.map(|n| ids[n as usize]))
        .collect();

    // The halving: every edge of a triangle left over, carried along the
    // chords of the quads.
    let halved = halving(&rules, &paired, &triangles);
    let mut is_halved: HashMap<(u32, u32), u32> = halved.iter().map(|&k| (k, u32::MAX)).collect();
    let rule_count = rule_quads.len();
    let any_paired = !paired.is_empty();
    let all_quads: Vec<[u32; 4]> = rule_quads.into_iter().chain(paired).collect();
    for &k in &halved {
        let m = (out.nodes[k.0 as usize] + out.nodes[k.1 as usize]) / 2.0;
        let id = match on_curve.get(&k) {
            Some(&g) => out.add_node(project_on_chain(chains[g as usize], m), NodeKind::Boundary),
            None => out.add_node(m, NodeKind::Interior),
        };
        is_halved.insert(k, id);
    }

    // The quads, split where their edges are halved.
    let mid = |a: u32, b: u32| is_halved.get(&key(a, b)).copied();
    let mut quads: Vec<[u32; 4]> = Vec::with_capacity(all_quads.len() + 4 * halved.len());
    let mut split_elements = 0;
    let mut loop_elements = 0;
    for (qi, &q) in all_quads.iter().enumerate() {
        let before = quads.len();
        let [a, b, c, d] = q;
        match (mid(a, b), mid(b, c)) {
            (None, None) => quads.push(q),
            (Some(mab), None) => {
                let mcd = mid(c, d).ok_or_else(|| FallbackError("a chord broke off".into()))?;
                quads.push([a, mab, mcd, d]);
                quads.push([mab, b, c, mcd]);
            }
            (None, Some(mbc)) => {
                let mda = mid(d, a).ok_or_else(|| FallbackError("a chord broke off".into()))?;
                quads.push([a, b, mbc, mda]);
                quads.push([mda, mbc, c, d]);
            }
            (Some(mab), Some(mbc)) => {
                let (mcd, mda) = match (mid(c, d), mid(d, a)) {
                    (Some(x), Some(y)) => (x, y),
                    _ => return Err(FallbackError("a chord broke off".into())),
                };
                let centre = [mab, mbc, mcd, mda]
                    .iter()
                    .map(|&n| out.nodes[n as usize])
                    .sum::<DVec2>()
                    / 4.0;
                let g = out.add_node(centre, NodeKind::Interior);
                quads.push([a, mab, g, mda]);
                quads.push([mab, b, mbc, g]);
                quads.push([g, mbc, c, mcd]);
                quads.push([mda, g, mcd, d]);
            }
        }
        if qi < rule_count {
            split_elements += usize::from(quads.len() - before > 1);
        } else {
            loop_elements += quads.len() - before;
        }
    }
    out.quads = quads;
    pull_back_curved_midpoints(&mut out, &halved, &is_halved, on_curve);

    // Each triangle left over split into three quads by its edges'
    // midpoints.
    for [a, b, c] in triangles {
        let mids = [(a, b), (b, c), (c, a)].map(|(x, y)| is_halved[&key(x, y)]);
        let (g, three) = split_in_three(&mut out, [a, b, c], mids);
        let centre = out.nodes[g as usize];
        let convex = three
            .iter()
            .all(|&q| crate::geometry::quad_is_convex(out.quad_points(q)));
        if !convex && !place_centre(&mut out, [a, b, c], g, three) {
            return Err(FallbackError(format!(
                "no centre makes the quads of the triangle at ({:.6}, {:.6}) convex",
                centre.x, centre.y
            )));
        }
        loop_elements += 3;
    }

    // the halved boundary edges, each now two
    let mut boundary = Vec::with_capacity(out.boundary.len() + halved.len());
    for e in &out.boundary {
        match is_halved.get(&key(e.a, e.b)) {
            Some(&m) => {
                boundary.push(BoundaryEdge { b: m, ..*e });
                boundary.push(BoundaryEdge { a: m, ..*e });
            }
            None => boundary.push(*e),
        }
    }
    out.boundary = boundary;
    Ok(LoopsClosed {
        mesh: out,
        loop_elements,
        split_elements,
        taken_back: taken,
        paired: any_paired,
    })
}

/// Where a halving node projected onto a strongly curved boundary leaves
/// one of its elements non-convex, the interior nodes of its elements
/// are first moved as the projection moved it (the node stays on its
/// curve, as the judge and a solver's geometry want); only where that
/// leaves an element non-convex is the node pulled back towards the
/// segment's chord a step at a time (off its curve by less than the
/// sagitta), as the last resort does.
fn pull_back_curved_midpoints(
    out: &mut Mesh,
    halved: &[(u32, u32)],
    is_halved: &HashMap<(u32, u32), u32>,
    on_curve: &HashMap<(u32, u32), u32>,
) {
    let mut quads_at: HashMap<u32, Vec<usize>> = HashMap::new();
    for (qi, q) in out.quads.iter().enumerate() {
        for &n in q {
            quads_at.entry(n).or_default().push(qi);
        }
    }
    for k in halved.iter().filter(|k| on_curve.contains_key(k)) {
        let m = is_halved[k];
        let around = quads_at.get(&m).map(Vec::as_slice).unwrap_or(&[]);
        let convex = |out: &Mesh| {
            around
                .iter()
                .all(|&q| crate::geometry::quad_is_convex(out.quad_points(q)))
        };
        if convex(out) {
            continue;
        }
        let chord = (out.nodes[k.0 as usize] + out.nodes[k.1 as usize]) / 2.0;
        if push_interior_along(out, m, out.nodes[m as usize] - chord, &quads_at)
            || untangle_round(out, m, &quads_at)
        {
            continue;
        }
        let curve = out.nodes[m as usize];
        for step in 1..=10 {
            let f = 1.0 - step as f64 / 10.0;
            out.nodes[m as usize] = chord + (curve - chord) * f;
            if convex(out) {
                break;
            }
        }
    }
}

/// Moves the interior nodes of the elements round boundary node `m`
/// along `moved` (how far its projection onto the curve moved it),
/// half of it at a time up to twice, until every element round `m` and
/// round them is convex; true where it then is (else they are back where
/// they were).
fn push_interior_along(
    out: &mut Mesh,
    m: u32,
    moved: DVec2,
    quads_at: &HashMap<u32, Vec<usize>>,
) -> bool {
    let (near, touched) = interior_near(out, m, quads_at, 1);
    let from: Vec<DVec2> = near.iter().map(|&x| out.nodes[x as usize]).collect();
    for step in 1..=4 {
        let t = step as f64 / 2.0;
        for (&x, &p) in near.iter().zip(&from) {
            out.nodes[x as usize] = p + moved * t;
        }
        if touched
            .iter()
            .all(|&q| crate::geometry::quad_is_convex(out.quad_points(q)))
        {
            return true;
        }
    }
    for (&x, &p) in near.iter().zip(&from) {
        out.nodes[x as usize] = p;
    }
    false
}

/// Where pushing them along did not do, the interior nodes within two
/// elements of the halving node `m` (on its curve) each moved in turn by
/// a compass search to where the least corner cross product of its
/// elements is largest (a fold's reflex corner has a sine near -1
/// wherever the node is near: the cross product, twice the corner's
/// triangle's signed area, grows as it unfolds), a few sweeps, until
/// every element round them is convex (true); else they are put back
/// (false).
fn untangle_round(out: &mut Mesh, m: u32, quads_at: &HashMap<u32, Vec<usize>>) -> bool {
    let (near, touched) = interior_near(out, m, quads_at, 2);
    let from: Vec<DVec2> = near.iter().map(|&x| out.nodes[x as usize]).collect();
    let all_convex = |out: &Mesh| {
        touched
            .iter()
            .all(|&q| crate::geometry::quad_is_convex(out.quad_points(q)))
    };
    // the search's first step a quarter of the mean edge round the
    // nodes as they were (an edge shrinking as a fold closes must not
    // shrink the step with it)
    let (sum, count) = touched.iter().fold((0.0, 0), |(s, n), &q| {
        let p = out.quad_points(q);
        (
            s + (0..4)
                .map(|k| (p[(k + 1) % 4] - p[k]).length())
                .sum::<f64>(),
            n + 4,
        )
    });
    let first_step = 0.25 * sum / count.max(1) as f64;
    let none: &[usize] = &[];
    for _ in 0..UNTANGLE_SWEEPS {
        for &x in &near {
            let around = quads_at.get(&x).map(Vec::as_slice).unwrap_or(none);
            let least = |out: &Mesh| {
                around
                    .iter()
                    .map(|&q| least_corner_cross(out.quad_points(q)))
                    .fold(f64::INFINITY, f64::min)
            };
            let start = least(out);
            out.nodes[x as usize] = crate::smoothing::compass_search_from(
                out,
                &[x as usize],
                first_step,
                start,
                |o, _| Some(least(o)),
                |w, best| w > best,
                6,
            );
        }
        if all_convex(out) {
            return true;
        }
    }
    for (&x, &p) in near.iter().zip(&from) {
        out.nodes[x as usize] = p;
    }
    false
}

/// The interior nodes of the elements round boundary node `m` (`rings`
/// 1), or of those and the elements round them (2), and every element
/// round `m` or one of them, each once.
fn interior_near(
    out: &Mesh,
    m: u32,
    quads_at: &HashMap<u32, Vec<usize>>,
    rings: usize,
) -> (Vec<u32>, Vec<usize>) {
    let none: &[usize] = &[];
    let at = |n: u32| quads_at.get(&n).map(Vec::as_slice).unwrap_or(none);
    let mut near: Vec<u32> = Vec::new();
    let mut from = vec![m];
    for _ in 0..rings {
        let before = near.len();
        for &n in &from {
            for &q in at(n) {
                for x in out.quads[q] {
                    if out.kinds[x as usize] == NodeKind::Interior && !near.contains(&x) {
                        near.push(x);
                    }
                }
            }
        }
        from = near[before..].to_vec();
    }
    let mut touched: Vec<usize> = at(m).to_vec();
    for &x in &near {
        touched.extend_from_slice(at(x));
    }
    touched.sort_unstable();
    touched.dedup();
    (near, touched)
}

/// Sweeps of `untangle_round` before it gives up.
const UNTANGLE_SWEEPS: usize = 8;

/// The least of a quad's corner cross products (of its two edges from
/// the corner): negative at a reflex corner.
fn least_corner_cross(p: [DVec2; 4]) -> f64 {
    (0..4)
        .map(|k| (p[(k + 1) % 4] - p[k]).perp_dot(p[(k + 3) % 4] - p[k]))
        .fold(f64::INFINITY, f64::min)
}

/// The elements reached from the open region through elements under
/// `area` (each element next to the region, or next to one reached, is
/// reached if it is that small).
fn small_ones(
    mesh: &Mesh,
    directed: &[(u32, u32)],
    on_curve: &HashMap<(u32, u32), u32>,
    area: f64,
) -> Vec<bool> {
    let mut owner: HashMap<(u32, u32), usize> = HashMap::new();
    for (qi, q) in mesh.quads.iter().enumerate() {
        for i in 0..4 {
            owner.insert((q[i], q[(i + 1) % 4]), qi);
        }
    }
    let small = |mesh: &Mesh, q: usize| {
        let p = mesh.quad_points(q);
        let a = 0.5 * ((p[2] - p[0]).perp_dot(p[3] - p[1]));
        a < area
    };
    let mut taken = vec![false; mesh.quads.len()];
    let mut stack: Vec<usize> = Vec::new();
    let reach = |edges: &[(u32, u32)], taken: &mut Vec<bool>, stack: &mut Vec<usize>| {
        for &(a, b) in edges {
            if on_curve.contains_key(&key(a, b)) {
                continue;
            }
            // the element across: it has the edge the other way round
            if let Some(&q) = owner.get(&(b, a)) {
                if !taken[q] && small(mesh, q) {
                    taken[q] = true;
                    stack.push(q);
                }
            }
        }
    };
    reach(directed, &mut taken, &mut stack);
    while let Some(q) = stack.pop() {
        let n = mesh.quads[q];
        let edges: Vec<(u32, u32)> = (0..4).map(|i| (n[i], n[(i + 1) % 4])).collect();
        reach(&edges, &mut taken, &mut stack);
    }
    taken
}

/// Takes the elements marked in `taken` back into the open region: the
/// region grows by them, its directed edges updated (an edge between the
/// region and a taken element is no longer a boundary of it, except on an
/// input line). Returns how many.
fn take_back_marked(
    mesh: &mut Mesh,
    directed: &mut Vec<(u32, u32)>,
    on_curve: &HashMap<(u32, u32), u32>,
    taken: &[bool],
) -> usize {
    let count = taken.iter().filter(|&&t| t).count();
    if count == 0 {
        return 0;
    }
    // the region's edges: the loops' and the taken elements', a pair of
    // opposite edges cancelled where the region meets itself (but not on
    // an input line, which stays a constraint inside it)
    let mut all: Vec<(u32, u32)> = std::mem::take(directed);
    for (qi, q) in mesh.quads.iter().enumerate() {
        if taken[qi] {
            all.extend((0..4).map(|i| (q[i], q[(i + 1) % 4])));
        }
    }
    let mut count_of: HashMap<(u32, u32), usize> = HashMap::new();
    for &e in &all {
        *count_of.entry(e).or_insert(0) += 1;
    }
    for &(a, b) in &all {
        let cancels =
            !on_curve.contains_key(&key(a, b)) && count_of.get(&(b, a)).copied().unwrap_or(0) > 0;
        if !cancels {
            directed.push((a, b));
        }
    }
    let mut i = 0;
    mesh.quads.retain(|_| {
        i += 1;
        !taken[i - 1]
    });
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::arc_corners::CornerAim;
    use crate::input::boundary::discretise;
    use crate::input::segment_counts::CountBounds;

    /// Triangles split in three only (the halving's tests).
    const SPLIT: Spacing = Spacing {
        pairs: 0.0,
        split: 1.0,
    };

    /// A 3 by 3 square meshed by the rules but for its middle cell.
    fn ring_round_open_cell() -> (Mesh, Domain, Vec<u32>) {
        ring_round_open_block(3, 1)
    }

    /// An n by n square of unit cells meshed by the rules but for the
    /// block of cells from (m, m) to (n - m, n - m), the open loop.
    fn ring_round_open_block(n: usize, m: usize) -> (Mesh, Domain, Vec<u32>) {
        let domain = Domain::from_json_str(&format!(
            r#"{{"name": "sq", "size": 1, "outer": {{"points": [[0,0],[{n},0],[{n},{n}],[0,{n}]]}}}}"#
        ))
        .unwrap();
        let mut mesh = discretise(&domain, 1.0, CountBounds::PLAIN, 2.0, &CornerAim::paper())
            .unwrap()
            .mesh;
        assert_eq!(mesh.nodes.len(), 4 * n);
        let mut at = |x: f64, y: f64| -> u32 {
            let p = DVec2::new(x, y);
            match mesh.nodes.iter().position(|&n| (n - p).length() < 1e-9) {
                Some(i) => i as u32,
                None => mesh.add_node(p, NodeKind::Interior),
            }
        };
        let mut quads = Vec::new();
        let open = |i: usize| i >= m && i < n - m;
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (i as f64, j as f64);
                let q = [
                    at(x, y),
                    at(x + 1.0, y),
                    at(x + 1.0, y + 1.0),
                    at(x, y + 1.0),
                ];
                if !(open(i) && open(j)) {
                    quads.push(q);
                }
            }
        }
        // the open block's outline, counter-clockwise
        let (lo, hi) = (m as f64, (n - m) as f64);
        let mut outline = Vec::new();
        let k = n - 2 * m;
        for t in 0..k {
            outline.push(at(lo + t as f64, lo));
        }
        for t in 0..k {
            outline.push(at(hi, lo + t as f64));
        }
        for t in 0..k {
            outline.push(at(hi - t as f64, hi));
        }
        for t in 0..k {
            outline.push(at(lo, hi - t as f64));
        }
        mesh.quads = quads;
        (mesh, domain, outline)
    }

    /// Conforming: every element edge has at most one element each side;
    /// the edges with none on one side are returned.
    fn outline_edges(m: &Mesh) -> usize {
        let mut sides: HashMap<(u32, u32), usize> = HashMap::new();
        for q in &m.quads {
            for i in 0..4 {
                *sides.entry((q[i], q[(i + 1) % 4])).or_insert(0) += 1;
            }
        }
        assert!(sides.values().all(|&n| n == 1));
        sides
            .keys()
            .filter(|&&(a, b)| !sides.contains_key(&(b, a)))
            .count()
    }

    fn area(m: &Mesh) -> f64 {
        (0..m.quads.len())
            .map(|q| {
                let p = m.quad_points(q);
                0.5 * (p[2] - p[0]).perp_dot(p[3] - p[1])
            })
            .sum()
    }

    /// A boundary node put on its curve past the interior node above it
    /// (the elements round it folded): the interior nodes near it move
    /// until every element round them is convex, the node itself stays.
    #[test]
    fn a_fold_at_a_node_put_on_its_curve_is_untangled_round_it() {
        let (mut mesh, _, _) = ring_round_open_block(4, 2);
        let m = mesh
            .nodes
            .iter()
            .position(|&p| (p - DVec2::new(2.0, 0.0)).length() < 1e-9)
            .unwrap() as u32;
        let put = DVec2::new(2.0, 1.3);
        mesh.nodes[m as usize] = put;
        let convex = |mesh: &Mesh| {
            (0..mesh.quads.len()).all(|q| crate::geometry::quad_is_convex(mesh.quad_points(q)))
        };
        assert!(!convex(&mesh));
        let mut quads_at: HashMap<u32, Vec<usize>> = HashMap::new();
        for (qi, q) in mesh.quads.iter().enumerate() {
            for &n in q {
                quads_at.entry(n).or_default().push(qi);
            }
        }
        assert!(untangle_round(&mut mesh, m, &quads_at));
        assert!(convex(&mesh));
        assert_eq!(mesh.nodes[m as usize], put);
    }

    #[test]
    fn an_open_block_is_closed_by_pairs_and_no_element_round_it_is_split() {
        let (mesh, domain, open) = ring_round_open_block(6, 1);
        let spacing = Spacing {
            pairs: 1.0,
            split: 1.5,
        };
        let closed = close_open_loops(&mesh, &[open], &domain, spacing, None).unwrap();
        assert!(closed.paired);
        assert_eq!(closed.split_elements, 0);
        let m = &closed.mesh;
        // the rules' 20 elements as they were, the 4 by 4 block paired
        assert_eq!(m.quads.len(), 20 + closed.loop_elements);
        assert_eq!(&m.quads[..20], &mesh.quads[..]);
        assert_eq!(m.boundary.len(), 24, "no boundary segment halved");
        assert_eq!(outline_edges(m), 24);
        assert!((area(m) - 36.0).abs() < 1e-9, "area {}", area(m));
        assert!((0..m.quads.len()).all(|q| crate::geometry::quad_is_convex(m.quad_points(q))));
        // about one element a unit of area: the block is 16
        assert!(
            (10..=24).contains(&closed.loop_elements),
            "{}",
            closed.loop_elements
        );
    }

    #[test]
    fn an_open_cell_is_closed_and_its_halving_carried_to_the_boundary() {
        let (mesh, domain, open) = ring_round_open_cell();
        let closed = close_open_loops(&mesh, &[open], &domain, SPLIT, None).unwrap();
        // the four rows across the cell's edges split; the corners not
        assert_eq!(closed.split_elements, 4);
        // the cell: two triangles, three quads each
        assert_eq!(closed.loop_elements, 6);
        let m = &closed.mesh;
        assert_eq!(m.quads.len(), 4 + 8 + 6);
        // four boundary segments halved, each now two
        assert_eq!(m.boundary.len(), 16);
        assert!((area(m) - 9.0).abs() < 1e-9, "area {}", area(m));
        assert!((0..m.quads.len()).all(|q| crate::geometry::quad_is_convex(m.quad_points(q))));
        assert_eq!(outline_edges(m), 16, "the outline's edges only");
    }

    #[test]
    fn small_elements_by_the_open_loop_are_taken_back() {
        let (mesh, domain, open) = ring_round_open_cell();
        // every element is 1 by 1: under an area of 1.5 all are taken
        let closed = close_open_loops(
            &mesh,
            std::slice::from_ref(&open),
            &domain,
            SPLIT,
            Some(1.5),
        )
        .unwrap();
        assert_eq!(closed.taken_back, 8);
        assert_eq!(closed.split_elements, 0);
        assert_eq!(closed.mesh.quads.len(), closed.loop_elements);
        // under an area of 0.5 none is
        let kept = close_open_loops(&mesh, &[open], &domain, SPLIT, Some(0.5)).unwrap();
        assert_eq!(kept.taken_back, 0);
        assert_eq!(kept.split_elements, 4);
    }
}
