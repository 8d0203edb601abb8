//! The hexagons of two neighbouring elements (they share an edge) and
//! the ways to mesh one anew: two elements along another diagonal (a
//! flip), three round a new node (a split), or four round two new nodes
//! (a split into four: two opposite nodes of the hexagon get an element
//! more each and none loses one, where a lone element spans two edges of
//! a tight arc at the node between them; no split into three can give
//! that node a second element without taking one from its neighbour).

use glam::DVec2;

use super::changes::{HexagonSplits, Working};
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

    /// The two splits of the hexagon of q and the element across its
    /// edge k into three elements round a new node at the hexagon's
    /// centre: (o, the new node's place, the three elements) each, the
    /// new node numbered next.
    pub(crate) fn splits(&self, q: u32, k: usize) -> Option<HexagonSplits> {
        let (o, h) = self.hexagon(q, k)?;
        let m = self.mesh.nodes.len() as u32;
        let centre = h
            .iter()
            .map(|&n| self.mesh.nodes[n as usize])
            .fold(DVec2::ZERO, |a, p| a + p)
            / 6.0;
        let split = |d: usize| {
            let i = |x: usize| h[(d + x) % 6];
            [
                [i(0), i(1), i(2), m],
                [i(2), i(3), i(4), m],
                [i(4), i(5), i(0), m],
            ]
        };
        Some((o, centre, [split(0), split(1)]))
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

    /// The six splits of the hexagon of q and the element across its edge
    /// k into four elements round two new nodes (numbered next): (o, each
    /// split's four elements and its two nodes' places). Hexagon
    /// [a, b, c, d, e, f] in turn from each node gives [a, b, m, f],
    /// [b, c, n, m], [c, d, e, n] and [n, e, f, m]: b and e get an
    /// element more, every other node keeps its count. Only those that
    /// give a lone element's boundary node a second (elsewhere the split
    /// into three or a flip does as well with fewer elements). None with
    /// `bound(split_into_four, 0)`.
    pub(crate) fn splits_into_four(&self, q: u32, k: usize) -> Option<(u32, Vec<FourSplit>)> {
        if self.bounds.split_into_four < 1.0 {
            return None;
        }
        let (o, h) = self.hexagon(q, k)?;
        let m = self.mesh.nodes.len() as u32;
        let n = m + 1;
        let at = |x: u32| self.mesh.nodes[x as usize];
        let centre = h.iter().map(|&x| at(x)).fold(DVec2::ZERO, |s, p| s + p) / 6.0;
        let split = |r: usize| {
            let [a, b, c, d, e, f] = std::array::from_fn(|x| h[(r + x) % 6]);
            // each new node two thirds of the way from the centre to
            // the middle of the two hexagon nodes it joins: every
            // element convex on a regular hexagon
            let places = [
                (at(b) + at(f) + centre) / 3.0,
                (at(c) + at(e) + centre) / 3.0,
            ];
            let quads = [[a, b, m, f], [b, c, n, m], [c, d, e, n], [n, e, f, m]];
            (quads, places)
        };
        let lone = |x: u32| {
            self.mesh.kinds[x as usize] != NodeKind::Interior && self.around[x as usize].len() == 1
        };
        let wanted = (0..6).filter(|&r| lone(h[(r + 1) % 6]) || lone(h[(r + 4) % 6]));
        Some((o, wanted.map(split).collect()))
    }
}

/// A split of a hexagon into four elements and its two new nodes' places.
pub(crate) type FourSplit = ([[u32; 4]; 4], [DVec2; 2]);
