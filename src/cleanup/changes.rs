//! The clean-up's changes: the mesh with each node's elements kept up to
//! date (`Working`), and the flips and collapses that may be made on it,
//! each with what undoes it (`Change`).

use glam::DVec2;

use crate::element_quality::{sine_worst_around, worst_around_every_corner, Star};
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::smoothing::compass_search_steps;

/// A region's worst corner: (degrees past the corner window, -smallest
/// sine).
/// An operation on the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// Flip the element's edge `k` (from corner k to corner k+1).
    Flip(u8),
    /// Join corner `k` onto the opposite corner k+2.
    Collapse(u8),
    /// Mesh a small patch round the element anew with fewer elements
    /// (see `Working::patches_of`): what a ring closing a small loop
    /// leaves, once smoothing made the loop good, is one element or two.
    Merge,
    /// Split the hexagon of the element and its neighbour across edge
    /// `k` into three round a new node in its middle (one variant of
    /// two), or into four round two new nodes (one of six: two opposite
    /// nodes of the hexagon get an element more each): where a node of
    /// the hexagon has one element too few (a lone element at a boundary
    /// node bent more than the window allows), a new node gives it a
    /// second.
    Split(u8),
}

pub(crate) type Worst = (f64, f64);

/// The mesh with each node's elements, kept up to date through the
/// operations; removed elements are left as holes until `finish`.
pub(crate) struct Working<'m> {
    pub(crate) mesh: &'m mut Mesh,
    pub(crate) around: Vec<Vec<u32>>,
    pub(crate) alive: Vec<bool>,
    pub(crate) constrained: rustc_hash::FxHashSet<(u32, u32)>,
    /// The corners, shapes and sizes aimed for.
    pub(crate) bounds: ElementBounds,
}

impl Working<'_> {
    pub(crate) fn around_pairs(&self, n: u32) -> Vec<(u32, u8)> {
        self.around[n as usize]
            .iter()
            .map(|&q| {
                let c = self.mesh.quads[q as usize]
                    .iter()
                    .position(|&m| m == n)
                    .unwrap_or(0);
                (q, c as u8)
            })
            .collect()
    }

    pub(crate) fn set_quad(&mut self, q: u32, new: [u32; 4]) {
        for &n in &self.mesh.quads[q as usize] {
            self.around[n as usize].retain(|&x| x != q);
        }
        self.mesh.quads[q as usize] = new;
        for &n in &new {
            self.around[n as usize].push(q);
        }
    }

    /// Adds a free node (the next) at `p`.
    pub(crate) fn add_node(&mut self, p: DVec2) {
        self.mesh.nodes.push(p);
        self.mesh.kinds.push(NodeKind::Interior);
        self.around.push(Vec::new());
    }

    /// Takes the last node back (its elements gone first).
    pub(crate) fn pop_node(&mut self) {
        self.mesh.nodes.pop();
        self.mesh.kinds.pop();
        self.around.pop();
    }

    /// Adds an element (the next), in the block of element `like`.
    pub(crate) fn add_quad(&mut self, nodes: [u32; 4], like: u32) {
        let q = self.mesh.quads.len() as u32;
        self.mesh.quads.push(nodes);
        self.alive.push(true);
        if !self.mesh.blocks.is_empty() {
            let b = self.mesh.blocks[like as usize];
            self.mesh.blocks.push(b);
        }
        for &n in &nodes {
            self.around[n as usize].push(q);
        }
    }

    /// Takes the last element back.
    pub(crate) fn pop_quad(&mut self) {
        let q = self.mesh.quads.len() as u32 - 1;
        self.remove_quad(q);
        self.mesh.quads.pop();
        self.alive.pop();
        if !self.mesh.blocks.is_empty() {
            self.mesh.blocks.pop();
        }
    }

    pub(crate) fn remove_quad(&mut self, q: u32) {
        for &n in &self.mesh.quads[q as usize] {
            self.around[n as usize].retain(|&x| x != q);
        }
        self.alive[q as usize] = false;
    }

    /// The worst corner over elements `qs` (infinite if one is not convex),
    /// every corner counted: a change of topology makes and unmakes corners.
    pub(crate) fn worst_of(&self, qs: &[u32]) -> Worst {
        let pairs: Vec<(u32, u8)> = qs.iter().map(|&q| (q, 0)).collect();
        worst_around_every_corner(self.mesh, &pairs, &self.bounds)
    }

    /// How far elements `qs` are past the paper's bounds on shape and size
    /// as a share of each bound (aspect ratio, taper, size against a
    /// neighbour's): at most 1 when within them.
    pub(crate) fn shape_excess(&self, qs: &[u32]) -> f64 {
        let area = |q: u32| crate::geometry::polygon_area(&self.mesh.quad_points(q as usize)).abs();
        let mut worst: f64 = 0.0;
        for &q in qs {
            let (aspect, taper) =
                crate::element_quality::aspect_taper(self.mesh.quad_points(q as usize));
            worst = worst
                .max(aspect / self.bounds.max_aspect)
                .max(taper / self.bounds.max_taper);
            let mine = area(q).max(1e-300);
            for k in 0..4 {
                if let Some((o, _)) = self.across(q, k) {
                    let other = area(o).max(1e-300);
                    worst = worst
                        .max((mine / other).max(other / mine).sqrt() / self.bounds.max_size_jump);
                }
            }
        }
        worst
    }

    /// The elements round the nodes of elements `qs`.
    pub(crate) fn region(&self, qs: &[u32]) -> Vec<u32> {
        let mut r: Vec<u32> = qs
            .iter()
            .flat_map(|&q| self.mesh.quads[q as usize])
            .flat_map(|n| self.around[n as usize].iter().copied())
            .collect();
        r.sort_unstable();
        r.dedup();
        r
    }

    /// The positions of the nodes of elements `qs`, to put back.
    pub(crate) fn snapshot(&self, qs: &[u32]) -> Vec<(u32, DVec2)> {
        let mut nodes: Vec<u32> = qs
            .iter()
            .flat_map(|&q| self.mesh.quads[q as usize])
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
            .into_iter()
            .map(|n| (n, self.mesh.nodes[n as usize]))
            .collect()
    }

    pub(crate) fn restore(&mut self, saved: &[(u32, DVec2)]) {
        for &(n, p) in saved {
            self.mesh.nodes[n as usize] = p;
        }
    }

    /// Two sweeps of the compass search over the free ones of `nodes`.
    pub(crate) fn smooth_locally(&mut self, nodes: &[u32]) {
        self.smooth_sweeps(nodes, 2);
    }

    /// `sweeps` sweeps of the compass search over the free ones of `nodes`.
    pub(crate) fn smooth_sweeps(&mut self, nodes: &[u32], sweeps: usize) {
        for _ in 0..sweeps {
            for &n in nodes {
                if self.mesh.kinds[n as usize] != NodeKind::Interior {
                    continue;
                }
                let pairs = self.around_pairs(n);
                let bounds = self.bounds;
                let start = sine_worst_around(self.mesh, &pairs, &bounds);
                let star = Star::new(self.mesh, n, &pairs, &bounds);
                let best = compass_search_steps(
                    self.mesh,
                    n as usize,
                    &pairs,
                    start,
                    |m, best| star.sine_worst_under(m, best, &bounds),
                    |w, b| w < b,
                    COMPASS_STEPS,
                );
                self.mesh.nodes[n as usize] = best;
            }
        }
    }

    pub(crate) fn edge_free(&self, a: u32, b: u32) -> bool {
        !self.constrained.contains(&(a.min(b), a.max(b)))
    }

    /// The element across edge k of element q, and where the edge is in it.
    pub(crate) fn across(&self, q: u32, k: usize) -> Option<(u32, usize)> {
        let quad = self.mesh.quads[q as usize];
        let (a, b) = (quad[k], quad[(k + 1) % 4]);
        self.around[a as usize].iter().find_map(|&o| {
            if o == q {
                return None;
            }
            let oq = self.mesh.quads[o as usize];
            (0..4)
                .find(|&j| oq[j] == b && oq[(j + 1) % 4] == a)
                .map(|j| (o, j))
        })
    }

    /// Element q without corner k, joined onto corner k+2: the elements
    /// changed (with their new nodes) and where the kept node goes; None
    /// when it would spoil the boundary or the mesh.
    pub(crate) fn collapse(&self, q: u32, k: usize) -> Option<(Vec<(u32, [u32; 4])>, u32, DVec2)> {
        let quad = self.mesh.quads[q as usize];
        let (gone, kept) = (quad[k], quad[(k + 2) % 4]);
        let kinds = &self.mesh.kinds;
        if kinds[gone as usize] != NodeKind::Interior {
            return None;
        }
        if (0..4).any(|i| !self.edge_free(quad[i], quad[(i + 1) % 4])) {
            return None;
        }
        // the two other corners keep an element each besides q
        for side in [quad[(k + 1) % 4], quad[(k + 3) % 4]] {
            if self.around[side as usize].len() < 2 {
                return None;
            }
        }
        let to = if kinds[kept as usize] == NodeKind::Interior {
            (self.mesh.nodes[gone as usize] + self.mesh.nodes[kept as usize]) / 2.0
        } else {
            self.mesh.nodes[kept as usize]
        };
        let mut changed = Vec::new();
        for &o in &self.around[gone as usize] {
            if o == q {
                continue;
            }
            let oq = self.mesh.quads[o as usize];
            if oq.contains(&kept) {
                return None; // it would lose a corner
            }
            changed.push((o, oq.map(|n| if n == gone { kept } else { n })));
        }
        Some((changed, kept, to))
    }

    /// The small patches round element q that may be meshed anew with
    /// fewer elements: the elements round a few free nodes (a corner of
    /// q, the two ends of an edge of q, the four corners of q, those of q
    /// and a neighbour, or the same of a neighbour of q), when
    /// their outline is one loop of four or six other nodes. What a ring
    /// closing a small loop leaves (a middle element, or two, in a ring)
    /// is such a patch. Each: the patch's elements and its outline,
    /// counter-clockwise.
    pub(crate) fn patches_of(&self, q: u32) -> Vec<(Vec<u32>, Vec<u32>)> {
        let mut seeds: Vec<u32> = vec![q];
        seeds.extend((0..4).filter_map(|k| self.across(q, k).map(|(o, _)| o)));
        let mut sets: Vec<Vec<u32>> = Vec::new();
        for &s in &seeds {
            let quad = self.mesh.quads[s as usize];
            for i in 0..4 {
                sets.push(vec![quad[i]]);
                sets.push(vec![quad[i], quad[(i + 1) % 4]]);
            }
            sets.push(quad.to_vec());
            for k in 0..4 {
                if let Some((o, _)) = self.across(s, k) {
                    let mut set: Vec<u32> = quad.to_vec();
                    set.extend(self.mesh.quads[o as usize]);
                    sets.push(set);
                }
            }
        }
        let mut found: Vec<(Vec<u32>, Vec<u32>)> = Vec::new();
        for mut set in sets {
            set.sort_unstable();
            set.dedup();
            if let Some(p) = self.patch(&set) {
                if !found.iter().any(|f| f.0 == p.0) {
                    found.push(p);
                }
            }
        }
        found
    }

    /// The elements round free nodes `inner` (sorted) and their outline,
    /// if it is one loop of four or six nodes not among them and every
    /// edge inside is free.
    fn patch(&self, inner: &[u32]) -> Option<(Vec<u32>, Vec<u32>)> {
        if inner
            .iter()
            .any(|&n| self.mesh.kinds[n as usize] != NodeKind::Interior)
        {
            return None;
        }
        let mut qs: Vec<u32> = inner
            .iter()
            .flat_map(|&n| self.around[n as usize].iter().copied())
            .collect();
        qs.sort_unstable();
        qs.dedup();
        if qs.len() > 12 {
            return None;
        }
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for &o in &qs {
            let quad = self.mesh.quads[o as usize];
            for i in 0..4 {
                edges.push((quad[i], quad[(i + 1) % 4]));
            }
        }
        let mut outline: Vec<(u32, u32)> = Vec::new();
        for &(a, b) in &edges {
            if edges.contains(&(b, a)) {
                if !self.edge_free(a, b) {
                    return None;
                }
            } else {
                outline.push((a, b));
            }
        }
        let k = outline.len();
        if k != 4 && k != 6 {
            return None;
        }
        let mut lp = vec![outline[0].0];
        while lp.len() < k {
            let last = *lp.last()?;
            let next = outline.iter().find(|e| e.0 == last)?.1;
            lp.push(next);
        }
        let mut seen = lp.clone();
        seen.sort_unstable();
        seen.dedup();
        let closes = outline.iter().any(|&e| e == (lp[k - 1], lp[0]));
        if seen.len() < k || !closes || lp.iter().any(|n| inner.binary_search(n).is_ok()) {
            return None;
        }
        // every node of the patch is inside or on the outline
        let all_placed = qs.iter().all(|&o| {
            self.mesh.quads[o as usize]
                .iter()
                .all(|n| inner.binary_search(n).is_ok() || lp.contains(n))
        });
        // fewer elements than now
        (all_placed && qs.len() > (k - 2) / 2).then_some((qs, lp))
    }
}

/// A change the clean-up may make, with what undoes it.
#[derive(Debug, Clone)]
pub(crate) enum Change {
    /// Elements q and o get new nodes.
    Flip {
        q: u32,
        o: u32,
        old: [[u32; 4]; 2],
        new: [[u32; 4]; 2],
    },
    /// Element q goes, node `gone` joins `kept` (moved from `from` to
    /// `to`).
    Collapse {
        q: u32,
        kept: u32,
        from: DVec2,
        to: DVec2,
        changed: Vec<(u32, [u32; 4], [u32; 4])>,
    },
    /// A patch meshed anew with fewer elements: elements `kept` get new
    /// nodes (old, new), the others (`gone`) go.
    Merge {
        kept: Vec<(u32, [u32; 4], [u32; 4])>,
        gone: Vec<u32>,
    },
    /// Elements get new nodes (`changed`: element, old, new), elements
    /// `added` are added (numbered from `first`, the next) and nodes at
    /// `at` (numbered from the next): a split (two elements into three
    /// round a new node).
    Add {
        changed: Vec<(u32, [u32; 4], [u32; 4])>,
        added: Vec<[u32; 4]>,
        first: u32,
        at: Vec<DVec2>,
    },
}

impl Change {
    /// The elements it changes, as they are once it is made.
    pub(crate) fn changed(&self) -> Vec<u32> {
        match self {
            Change::Flip { q, o, .. } => vec![*q, *o],
            Change::Collapse { changed, .. } => changed.iter().map(|c| c.0).collect(),
            Change::Merge { kept, .. } => kept.iter().map(|k| k.0).collect(),
            Change::Add {
                changed,
                added,
                first,
                ..
            } => changed
                .iter()
                .map(|c| c.0)
                .chain(*first..*first + added.len() as u32)
                .collect(),
        }
    }

    /// The elements whose corners it changes, before it is made.
    pub(crate) fn region(&self, w: &Working) -> Vec<u32> {
        match self {
            Change::Flip { q, o, .. } => w.region(&[*q, *o]),
            Change::Collapse { q, .. } => w.region(&[*q]),
            Change::Merge { kept, gone } => {
                let mut qs = gone.clone();
                qs.extend(kept.iter().map(|k| k.0));
                w.region(&qs)
            }
            Change::Add { changed, .. } => {
                w.region(&changed.iter().map(|c| c.0).collect::<Vec<_>>())
            }
        }
    }

    pub(crate) fn apply(&self, w: &mut Working) {
        match self {
            Change::Flip { q, o, new, .. } => {
                w.set_quad(*q, new[0]);
                w.set_quad(*o, new[1]);
            }
            Change::Collapse {
                q,
                kept,
                to,
                changed,
                ..
            } => {
                w.remove_quad(*q);
                for &(o, _, new) in changed {
                    w.set_quad(o, new);
                }
                w.mesh.nodes[*kept as usize] = *to;
            }
            Change::Merge { kept, gone } => {
                for &g in gone {
                    w.remove_quad(g);
                }
                for &(q, _, new) in kept {
                    w.set_quad(q, new);
                }
            }
            Change::Add {
                changed, added, at, ..
            } => {
                for &p in at {
                    w.add_node(p);
                }
                for &(q, _, new) in changed {
                    w.set_quad(q, new);
                }
                for &new in added {
                    w.add_quad(new, changed[0].0);
                }
            }
        }
    }

    /// Undoes `apply` (nodes smoothed since are put back by the caller).
    pub(crate) fn revert(&self, w: &mut Working) {
        match self {
            Change::Flip { q, o, old, .. } => {
                w.set_quad(*q, old[0]);
                w.set_quad(*o, old[1]);
            }
            Change::Collapse {
                q,
                kept,
                from,
                changed,
                ..
            } => {
                for &(o, old, _) in changed {
                    w.set_quad(o, old);
                }
                w.mesh.nodes[*kept as usize] = *from;
                w.alive[*q as usize] = true;
                for n in w.mesh.quads[*q as usize] {
                    w.around[n as usize].push(*q);
                }
            }
            Change::Merge { kept, gone } => {
                for &(q, old, _) in kept {
                    w.set_quad(q, old);
                }
                for &g in gone {
                    w.alive[g as usize] = true;
                    for n in w.mesh.quads[g as usize] {
                        w.around[n as usize].push(g);
                    }
                }
            }
            Change::Add {
                changed, added, at, ..
            } => {
                for _ in added {
                    w.pop_quad();
                }
                for &(q, old, _) in changed {
                    w.set_quad(q, old);
                }
                for _ in at {
                    w.pop_node();
                }
            }
        }
    }

    /// The nodes to smooth once it is made.
    pub(crate) fn nodes(&self, w: &Working) -> Vec<u32> {
        let mut nodes: Vec<u32> = match self {
            Change::Flip { new, .. } => new.concat(),
            Change::Collapse { kept, .. } => w.around[*kept as usize]
                .iter()
                .flat_map(|&o| w.mesh.quads[o as usize])
                .collect(),
            Change::Merge { kept, .. } => kept
                .iter()
                .flat_map(|k| k.2)
                .flat_map(|n| w.around[n as usize].iter())
                .flat_map(|&o| w.mesh.quads[o as usize])
                .collect(),
            Change::Add { changed, added, .. } => changed
                .iter()
                .map(|c| c.2)
                .chain(added.iter().copied())
                .flatten()
                .collect(),
        };
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }
}

/// The changes operation `op` can make on element q.
pub(crate) fn changes(w: &Working, q: u32, op: Op) -> Vec<Change> {
    match op {
        Op::Flip(k) => match w.flips(q, k as usize) {
            Some((o, splits)) => splits
                .into_iter()
                .map(|new| Change::Flip {
                    q,
                    o,
                    old: [w.mesh.quads[q as usize], w.mesh.quads[o as usize]],
                    new,
                })
                .collect(),
            None => Vec::new(),
        },
        Op::Collapse(k) => match w.collapse(q, k as usize) {
            Some((changed, kept, to)) => vec![Change::Collapse {
                q,
                kept,
                from: w.mesh.nodes[kept as usize],
                to,
                changed: changed
                    .into_iter()
                    .map(|(o, new)| (o, w.mesh.quads[o as usize], new))
                    .collect(),
            }],
            None => Vec::new(),
        },
        Op::Split(k) => match w.splits(q, k as usize) {
            Some((o, splits)) => splits
                .into_iter()
                .map(|(new, at)| Change::Add {
                    changed: vec![
                        (q, w.mesh.quads[q as usize], new[0]),
                        (o, w.mesh.quads[o as usize], new[1]),
                    ],
                    added: new[2..].to_vec(),
                    first: w.mesh.quads.len() as u32,
                    at,
                })
                .collect(),
            None => Vec::new(),
        },
        Op::Merge => {
            let mut out = Vec::new();
            for (qs, lp) in w.patches_of(q) {
                let k = lp.len();
                // one element over a loop of four; over six, two, split
                // along each of the three diagonals in turn
                let splits: Vec<Vec<[u32; 4]>> = if k == 4 {
                    vec![vec![[lp[0], lp[1], lp[2], lp[3]]]]
                } else {
                    (0..3)
                        .map(|d| {
                            let i = |x: usize| lp[(d + x) % 6];
                            vec![[i(0), i(1), i(2), i(3)], [i(3), i(4), i(5), i(0)]]
                        })
                        .collect()
                };
                for new in splits {
                    let gone = qs[new.len()..].to_vec();
                    let kept = qs
                        .iter()
                        .zip(new)
                        .map(|(&o, n)| (o, w.mesh.quads[o as usize], n))
                        .collect();
                    out.push(Change::Merge { kept, gone });
                }
            }
            out
        }
    }
}

/// The compass search's step halvings when a change is judged (the
/// smoothing after the clean-up refines the kept ones).
pub(crate) const COMPASS_STEPS: usize = 4;

impl<'m> Working<'m> {
    pub(crate) fn new(mesh: &'m mut Mesh, bounds: ElementBounds) -> Working<'m> {
        let mut constrained = rustc_hash::FxHashSet::default();
        for e in &mesh.boundary {
            constrained.insert((e.a.min(e.b), e.a.max(e.b)));
        }
        let alive = vec![true; mesh.quads.len()];
        let mut w = Working {
            mesh,
            around: Vec::new(),
            alive,
            constrained,
            bounds,
        };
        w.index();
        w
    }

    /// The live elements within `rings` elements of these nodes.
    pub(crate) fn elements_near(&self, nodes: &[u32], rings: usize) -> Vec<u32> {
        let mut seen = vec![false; self.mesh.quads.len()];
        let mut found: Vec<u32> = Vec::new();
        let mut frontier: Vec<u32> = nodes.to_vec();
        for _ in 0..rings {
            let mut next = Vec::new();
            for &n in &frontier {
                for &q in &self.around[n as usize] {
                    if !std::mem::replace(&mut seen[q as usize], true) {
                        found.push(q);
                        next.extend(self.mesh.quads[q as usize]);
                    }
                }
            }
            frontier = next;
        }
        found.sort_unstable();
        found
    }

    /// Each node's live elements, worked out afresh.
    pub(crate) fn index(&mut self) {
        let mut around = vec![Vec::new(); self.mesh.nodes.len()];
        for (q, quad) in self.mesh.quads.iter().enumerate() {
            if self.alive[q] {
                for &n in quad {
                    around[n as usize].push(q as u32);
                }
            }
        }
        self.around = around;
    }
}
