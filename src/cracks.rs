//! Cracks: a line with `"crack": true` is meshed like any inner line (the
//! elements follow it), then the mesh is cut open along it. Each node of
//! the crack gets one copy per fan of elements round it that the crack
//! separates, so a node inside the crack or at its mouth on a loop is
//! doubled, and the tip (an end inside the domain, round which the
//! elements still form one fan) stays one node. The two faces become
//! boundary groups of their own: `crack K +` (the side on the left of the
//! line's direction, K its number among the lines) and `crack K -`, or,
//! for an edge with a tag, `TAG +` and `TAG -`.

use rustc_hash::{FxHashMap, FxHashSet};

use crate::mesh::{BoundaryEdge, Mesh, NodeKind};

/// Opens the mesh along its crack lines (`Mesh::crack_lines`); returns
/// the number of nodes added.
pub fn open_cracks(mesh: &mut Mesh) -> usize {
    if mesh.crack_lines.is_empty() {
        return 0;
    }
    let crack_lines = mesh.crack_lines.clone();
    let is_crack = |e: &BoundaryEdge| crack_lines.contains(&e.group);
    let crack_edges: FxHashSet<(u32, u32)> = mesh
        .boundary
        .iter()
        .filter(|e| is_crack(e))
        .map(|e| (e.a.min(e.b), e.a.max(e.b)))
        .collect();
    let mut crack_nodes: Vec<u32> = crack_edges.iter().flat_map(|&(a, b)| [a, b]).collect();
    crack_nodes.sort_unstable();
    crack_nodes.dedup();
    let on_crack: FxHashSet<u32> = crack_nodes.iter().copied().collect();
    // the elements round each crack node, and the element on the left of
    // each directed element edge that touches one
    let mut around: FxHashMap<u32, Vec<usize>> = FxHashMap::default();
    let mut left_of: FxHashMap<(u32, u32), usize> = FxHashMap::default();
    for (qi, q) in mesh.quads.iter().enumerate() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            if on_crack.contains(&a) {
                around.entry(a).or_default().push(qi);
            }
            if on_crack.contains(&a) || on_crack.contains(&b) {
                left_of.insert((a, b), qi);
            }
        }
    }
    // the copy of each crack node each element uses
    let mut copy_in: FxHashMap<(u32, usize), u32> = FxHashMap::default();
    let before = mesh.nodes.len();
    for &n in &crack_nodes {
        let elements = &around[&n];
        // fans: elements round n joined across their edges at n that are
        // not on the crack
        let mut fan: Vec<usize> = (0..elements.len()).collect();
        fn root(fan: &mut [usize], mut i: usize) -> usize {
            while fan[i] != i {
                fan[i] = fan[fan[i]];
                i = fan[i];
            }
            i
        }
        for i in 0..elements.len() {
            for j in i + 1..elements.len() {
                let shared = edge_at(&mesh.quads[elements[i]], n)
                    .into_iter()
                    .find(|m| edge_at(&mesh.quads[elements[j]], n).contains(m));
                if let Some(m) = shared {
                    if !crack_edges.contains(&(n.min(m), n.max(m))) {
                        let (a, b) = (root(&mut fan, i), root(&mut fan, j));
                        fan[a.max(b)] = a.min(b);
                    }
                }
            }
        }
        // the fan of the first element keeps the node, each other a copy
        let mut node_of_root: FxHashMap<usize, u32> = FxHashMap::default();
        for (i, &qi) in elements.iter().enumerate() {
            let r = root(&mut fan, i);
            let id = match node_of_root.get(&r) {
                Some(&id) => id,
                None => {
                    let id = if node_of_root.is_empty() {
                        n
                    } else {
                        mesh.add_node(mesh.nodes[n as usize], NodeKind::Boundary)
                    };
                    node_of_root.insert(r, id);
                    id
                }
            };
            copy_in.insert((n, qi), id);
        }
    }
    let added = mesh.nodes.len() - before;
    if added == 0 {
        return 0;
    }
    let copy = |n: u32, qi: usize| *copy_in.get(&(n, qi)).unwrap_or(&n);
    // boundary edges follow the element they bound; a crack edge becomes
    // one edge per face
    let mut boundary = Vec::with_capacity(mesh.boundary.len() + crack_edges.len());
    let old = std::mem::take(&mut mesh.boundary);
    for e in old {
        if !on_crack.contains(&e.a) && !on_crack.contains(&e.b) {
            boundary.push(e);
            continue;
        }
        let left = left_of.get(&(e.a, e.b)).copied();
        let right = left_of.get(&(e.b, e.a)).copied();
        if !is_crack(&e) {
            if let Some(qi) = left.or(right) {
                boundary.push(BoundaryEdge {
                    a: copy(e.a, qi),
                    b: copy(e.b, qi),
                    ..e
                });
            }
            continue;
        }
        let base = match e.tag {
            Some(t) => mesh.groups[t as usize].clone(),
            None => format!("crack {}", line_number(mesh, e.group)),
        };
        for (side, qi) in [("+", left), ("-", right)] {
            let Some(qi) = qi else { continue };
            let tag = Some(mesh.group_named(&format!("{base} {side}")));
            boundary.push(BoundaryEdge {
                a: copy(e.a, qi),
                b: copy(e.b, qi),
                group: e.group,
                tag,
            });
        }
    }
    mesh.boundary = boundary;
    for (qi, q) in mesh.quads.iter_mut().enumerate() {
        for n in q.iter_mut() {
            *n = *copy_in.get(&(*n, qi)).unwrap_or(n);
        }
    }
    added
}

/// The two neighbours of node `n` in quad `q` (the ends of its edges at n).
fn edge_at(q: &[u32; 4], n: u32) -> Vec<u32> {
    match q.iter().position(|&x| x == n) {
        Some(k) => vec![q[(k + 1) % 4], q[(k + 3) % 4]],
        None => vec![],
    }
}

/// The number K of the line whose group is `group` (its group is named
/// `line K`).
fn line_number(mesh: &Mesh, group: u32) -> String {
    mesh.groups[group as usize]
        .strip_prefix("line ")
        .unwrap_or(&mesh.groups[group as usize])
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// A 2x2 grid of unit squares over [0, 2]^2; the line along y = 1
    /// from x = 0 to x = 1 (nodes 3, 4) is a crack from the left edge to
    /// the middle.
    fn grid_with_an_edge_crack() -> Mesh {
        let mut m = Mesh::default();
        for y in 0..3 {
            for x in 0..3 {
                m.add_node(DVec2::new(x as f64, y as f64), NodeKind::Boundary);
            }
        }
        m.quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        m.groups = vec!["outer".into(), "line 1".into()];
        let ring = [0, 1, 2, 5, 8, 7, 6, 3];
        for k in 0..8 {
            m.boundary.push(BoundaryEdge {
                a: ring[k],
                b: ring[(k + 1) % 8],
                group: 0,
                tag: None,
            });
        }
        m.boundary.push(BoundaryEdge {
            a: 3,
            b: 4,
            group: 1,
            tag: None,
        });
        m.crack_lines = vec![1];
        m
    }

    #[test]
    fn an_edge_crack_doubles_its_mouth_but_not_its_tip() {
        let mut m = grid_with_an_edge_crack();
        assert_eq!(open_cracks(&mut m), 1);
        // node 3 (the mouth, on the outer loop) is doubled, node 4 (the tip) not
        assert_eq!(m.nodes.len(), 10);
        assert_eq!(m.nodes[9], DVec2::new(0.0, 1.0));
        assert_eq!(m.quads[0], [0, 1, 4, 3]);
        assert_eq!(m.quads[2], [9, 4, 7, 6]);
        // the faces: + above the line (left of 3 -> 4), - below
        let faces: Vec<(u32, u32, &str)> = m
            .boundary
            .iter()
            .filter(|e| e.group == 1)
            .map(|e| (e.a, e.b, m.groups[e.output_group() as usize].as_str()))
            .collect();
        assert_eq!(faces, vec![(9, 4, "crack 1 +"), (3, 4, "crack 1 -")]);
        // the outer edge 6 -> 3 now ends at the copy
        assert!(m.boundary.iter().any(|e| (e.a, e.b) == (6, 9)));
        assert!(m.boundary.iter().any(|e| (e.a, e.b) == (3, 0)));
    }

    #[test]
    fn a_mesh_without_cracks_is_left_alone() {
        let mut m = grid_with_an_edge_crack();
        m.crack_lines.clear();
        let before = (m.nodes.clone(), m.quads.clone(), m.boundary.clone());
        assert_eq!(open_cracks(&mut m), 0);
        assert_eq!((m.nodes, m.quads, m.boundary), before);
    }
}
