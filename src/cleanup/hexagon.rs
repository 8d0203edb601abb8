//! The hexagons of two neighbouring elements (they share an edge) and
//! the ways to mesh one anew: two elements along another diagonal (a
//! flip), three round a new node (a split), or four round two new nodes
//! (a split into four: two opposite nodes of the hexagon get an element
//! more each and none loses one, where a lone element spans two edges of
//! a tight arc at the node between them; no split into three can give
//! that node a second element without taking one from its neighbour).

use glam::DVec2;

use super::changes::Working;
use crate::mesh::NodeKind;

impl Working<'_> {
    /// The hexagon of q and the element across its edge k,
    /// counter-clockwise from v round q to u, round o (the edge k is u-v),
    /// with o; None on a constrained edge or where the two share more
    /// than the edge.
    fn hexagon(&self, q: u32, k: usize) -> Option<(u32, [u32; 6])> {
        let quad = self.mesh.quads[q as usize];
        let (u, v) = (quad[k], quad[(k + 1) % 4]);
        if !self.edge_free(u, v) {
            return None;
        }
        let (o, j) = self.across(q, k)?;
        let oq = self.mesh.quads[o as usize];
        let h = [
            v,
            quad[(k + 2) % 4],
            quad[(k + 3) % 4],
            u,
            oq[(j + 2) % 4],
            oq[(j + 3) % 4],
        ];
        let mut seen = h.to_vec();
        seen.sort_unstable();
        seen.dedup();
        (seen.len() == 6).then_some((o, h))
    }

    /// The two other splits of the hexagon of q and the element across
    /// its edge k: (q's new nodes, the other's new nodes) each.
    pub(crate) fn flips(&self, q: u32, k: usize) -> Option<(u32, [[[u32; 4]; 2]; 2])> {
        let (o, h) = self.hexagon(q, k)?;
        let split = |d: usize| {
            let i = |x: usize| h[(d + x) % 6];
            [[i(0), i(1), i(2), i(3)], [i(3), i(4), i(5), i(0)]]
        };
        Some((o, [split(1), split(2)]))
    }

    /// The splits of the hexagon of q and the element across its edge k,
    /// each as its elements and its new nodes' places (the new nodes
    /// numbered next), with o. First the two into three round a new node
    /// at the hexagon's centre; then, with `bound(split_into_four, 1)`,
    /// those into four round two new nodes: hexagon [a, b, c, d, e, f]
    /// in turn from each node gives [a, b, m, f], [b, c, n, m],
    /// [c, d, e, n] and [n, e, f, m], so b and e get an element more and
    /// every other node keeps its count; only those that give a lone
    /// element's boundary node a second (elsewhere the split into three
    /// or a flip does as well with fewer elements).
    pub(crate) fn splits(&self, q: u32, k: usize) -> Option<(u32, Vec<HexagonSplit>)> {
        let (o, h) = self.hexagon(q, k)?;
        let m = self.mesh.nodes.len() as u32;
        let n = m + 1;
        let at = |x: u32| self.mesh.nodes[x as usize];
        let centre = h.iter().map(|&x| at(x)).fold(DVec2::ZERO, |s, p| s + p) / 6.0;
        let into_three = |d: usize| {
            let i = |x: usize| h[(d + x) % 6];
            let quads = vec![
                [i(0), i(1), i(2), m],
                [i(2), i(3), i(4), m],
                [i(4), i(5), i(0), m],
            ];
            (quads, vec![centre])
        };
        let into_four = |r: usize| {
            let [a, b, c, d, e, f] = std::array::from_fn(|x| h[(r + x) % 6]);
            // each new node two thirds of the way from the centre to
            // the middle of the two hexagon nodes it joins: every
            // element convex on a regular hexagon
            let places = vec![
                (at(b) + at(f) + centre) / 3.0,
                (at(c) + at(e) + centre) / 3.0,
            ];
            let quads = vec![[a, b, m, f], [b, c, n, m], [c, d, e, n], [n, e, f, m]];
            (quads, places)
        };
        let lone = |x: u32| {
            self.mesh.kinds[x as usize] != NodeKind::Interior && self.around[x as usize].len() == 1
        };
        let four = self.bounds.split_into_four >= 1.0;
        let wanted = (0..6).filter(|&r| four && (lone(h[(r + 1) % 6]) || lone(h[(r + 4) % 6])));
        let splits = (0..2).map(into_three).chain(wanted.map(into_four));
        Some((o, splits.collect()))
    }
}

/// A split of a hexagon: its elements (the first two in place of the
/// hexagon's two) and its new nodes' places.
pub(crate) type HexagonSplit = (Vec<[u32; 4]>, Vec<DVec2>);
