//! Regions: the parts of the domain that the loops and the lines enclose
//! (a line from a loop to a loop, or lines that meet, part the domain),
//! each an element group of its own (`region 1`, `region 2`, ...).

use rustc_hash::{FxHashMap, FxHashSet};

use crate::mesh::Mesh;

/// The region of each quad: a flood fill across the element edges that
/// are no boundary edge (no loop, line or crack face), the regions
/// numbered from 0 in the order of their first quad. A domain that no
/// line parts has one region, 0.
///
/// Linear in the number of quads.
pub fn find_regions(mesh: &Mesh) -> Vec<u32> {
    let walls: FxHashSet<(u32, u32)> = mesh
        .boundary
        .iter()
        .map(|e| (e.a.min(e.b), e.a.max(e.b)))
        .collect();
    let mut by_edge: FxHashMap<(u32, u32), Vec<u32>> =
        FxHashMap::with_capacity_and_hasher(2 * mesh.quads.len(), Default::default());
    for (qi, q) in mesh.quads.iter().enumerate() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let key = (a.min(b), a.max(b));
            if !walls.contains(&key) {
                by_edge.entry(key).or_default().push(qi as u32);
            }
        }
    }
    const NONE: u32 = u32::MAX;
    let mut region = vec![NONE; mesh.quads.len()];
    let mut next = 0;
    let mut stack = Vec::new();
    for first in 0..mesh.quads.len() {
        if region[first] != NONE {
            continue;
        }
        region[first] = next;
        stack.push(first as u32);
        while let Some(qi) = stack.pop() {
            let q = mesh.quads[qi as usize];
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                for &other in by_edge.get(&(a.min(b), a.max(b))).into_iter().flatten() {
                    if region[other as usize] == NONE {
                        region[other as usize] = next;
                        stack.push(other);
                    }
                }
            }
        }
        next += 1;
    }
    region
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BoundaryEdge, NodeKind};
    use glam::DVec2;

    /// Three unit squares in a row, [0, 3] x [0, 1].
    fn row_of_three() -> Mesh {
        let mut m = Mesh::default();
        for y in 0..2 {
            for x in 0..4 {
                m.add_node(DVec2::new(x as f64, y as f64), NodeKind::Boundary);
            }
        }
        m.quads = vec![[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6]];
        m
    }

    #[test]
    fn a_line_across_the_domain_parts_it_in_two_regions() {
        let mut m = row_of_three();
        m.boundary.push(BoundaryEdge {
            a: 2,
            b: 6,
            group: 1,
            tag: None,
        });
        assert_eq!(find_regions(&m), vec![0, 0, 1]);
    }

    #[test]
    fn a_domain_no_line_parts_is_one_region() {
        assert_eq!(find_regions(&row_of_three()), vec![0, 0, 0]);
    }
}
