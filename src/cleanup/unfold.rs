//! Crowded corners: two elements or more sharing a boundary corner too
//! sharp for that many (an input corner of 80 degrees split into two of
//! 40, one of them outside the window wherever the nodes go). The flip or
//! collapse that takes one of them away leaves the other folded over
//! where the local smoothing starts from the nodes' places (its free
//! nodes must move well away); such a change is smoothed again from the
//! free nodes' neighbours' mean (`bound(unfold_crowded_corners, 1)`).

use glam::DVec2;

use super::changes::Working;
use crate::mesh::NodeKind;

impl Working<'_> {
    /// The boundary nodes of elements `qs` that are crowded, with their
    /// element counts: two elements or more share a corner too sharp for
    /// that many (under the count times the window's lower corner), so
    /// one of them at least has a corner outside the window wherever the
    /// nodes go (an input corner of 80 degrees split in two of 40).
    pub(crate) fn crowded_corners(&self, qs: &[u32]) -> Vec<(u32, usize)> {
        let mut out: Vec<(u32, usize)> = Vec::new();
        // (a split's new elements are not made yet)
        for &q in qs
            .iter()
            .filter(|&&q| self.alive.get(q as usize) == Some(&true))
        {
            for n in self.mesh.quads[q as usize] {
                let count = self.around[n as usize].len();
                if self.mesh.kinds[n as usize] != NodeKind::Boundary
                    || count < 2
                    || out.iter().any(|&(m, _)| m == n)
                {
                    continue;
                }
                let corner: f64 = self
                    .around_pairs(n)
                    .iter()
                    .map(|&(e, k)| {
                        crate::geometry::quad_angles(self.mesh.quad_points(e as usize))[k as usize]
                    })
                    .sum();
                if corner < count as f64 * self.bounds.lower_corner {
                    out.push((n, count));
                }
            }
        }
        out
    }

    /// The free ones of `nodes` moved, a few times over, to the mean of
    /// the nodes they share an element edge with: a change that leaves
    /// an element folded over (a flip or collapse at a sharp input corner
    /// split in two) is smoothed again from an unfolded place.
    pub(crate) fn place_at_neighbours_mean(&mut self, nodes: &[u32]) {
        for _ in 0..4 {
            for &n in nodes {
                if self.mesh.kinds[n as usize] != NodeKind::Interior {
                    continue;
                }
                let (mut sum, mut count) = (DVec2::ZERO, 0.0);
                for &q in &self.around[n as usize] {
                    let quad = self.mesh.quads[q as usize];
                    let c = quad.iter().position(|&m| m == n).unwrap_or(0);
                    for m in [quad[(c + 1) % 4], quad[(c + 3) % 4]] {
                        sum += self.mesh.nodes[m as usize];
                        count += 1.0;
                    }
                }
                if count > 0.0 {
                    self.mesh.nodes[n as usize] = sum / count;
                }
            }
        }
    }
}
