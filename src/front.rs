//! The front: the boundary loops of the remaining domain Ω, as cyclic
//! doubly linked lists of node occurrences, with a spatial grid for the
//! "near" tests.
//!
//! A node may occur more than once in a loop (the two sides of a cutting
//! line or an inner line). Every loop is walked with the remaining domain
//! on its left. Changes go through a journal so that a commit that would
//! leave a loop of odd length (no all-quad mesh exists for it) is undone.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use crate::geometry::interior_angle;

/// Index of a front occurrence ("front vertex").
pub type Fv = u32;
/// Marks no occurrence.
pub const NONE: Fv = u32::MAX;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Occurrence {
    node: u32,
    prev: Fv,
    next: Fv,
    lp: u32,
    alive: bool,
    /// How many element layers lie between this occurrence and the input
    /// boundary: the strategy's tie-break, so rows are laid in order.
    layer: u32,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct LoopRec {
    head: Fv,
    len: usize,
    alive: bool,
}

#[derive(Debug, Clone, Copy)]
enum Change {
    Occ(Fv, Occurrence),
    NewOcc,
    Loop(u32, LoopRec),
    NewLoop,
}

/// `v.floor().clamp(-1e9, 1e9) as i32` without the call into libm that
/// `floor` is on a baseline x86-64 (a search asks for a dozen cells).
fn floor_clamped(v: f64) -> i32 {
    let c = v.clamp(-1e9, 1e9);
    let t = c as i32;
    if (t as f64) > c {
        t - 1
    } else {
        t
    }
}

/// The loops of the remaining domain.
#[derive(Debug, Clone, Default)]
pub struct Front {
    occ: Vec<Occurrence>,
    loops: Vec<LoopRec>,
    journal: Vec<Change>,
    cell: f64,
    grid: HashMap<(i32, i32), Vec<(Fv, u32, u32)>>,
    /// Occurrences changed since the last call of `take_touched`.
    touched: Vec<Fv>,
    occurrences_of: HashMap<u32, Vec<Fv>>,
    /// Grid entries written since the stale ones were last dropped.
    indexed_since_compaction: usize,
}

impl Front {
    /// A front of one loop through `nodes` (in order, domain on the left).
    pub fn new(nodes: &[u32], cell: f64) -> Front {
        let mut f = Front {
            cell: cell.max(1e-300),
            ..Default::default()
        };
        f.add_loop(nodes, &[]);
        f.journal.clear();
        f
    }

    /// Adds a loop (after a fallback split, say). Returns its id.
    pub fn add_loop(&mut self, nodes: &[u32], layers: &[u32]) -> u32 {
        let lp = self.loops.len() as u32;
        let base = self.occ.len() as Fv;
        let n = nodes.len() as u32;
        for (i, &node) in nodes.iter().enumerate() {
            let i = i as u32;
            self.occ.push(Occurrence {
                node,
                prev: base + (i + n - 1) % n,
                next: base + (i + 1) % n,
                lp,
                alive: true,
                layer: layers.get(i as usize).copied().unwrap_or(0),
            });
            self.journal.push(Change::NewOcc);
            self.occurrences_of.entry(node).or_default().push(base + i);
            self.touched.push(base + i);
        }
        self.loops.push(LoopRec {
            head: base,
            len: nodes.len(),
            alive: true,
        });
        self.journal.push(Change::NewLoop);
        lp
    }

    /// Starts a transaction: changes from here can be undone by `rollback`.
    pub fn begin(&mut self) {
        self.journal.clear();
    }

    /// Undoes every change since `begin`.
    pub fn rollback(&mut self) {
        while let Some(c) = self.journal.pop() {
            match c {
                Change::Occ(fv, o) => self.occ[fv as usize] = o,
                Change::NewOcc => {
                    let o = self.occ.pop().expect("journal out of step");
                    if let Some(v) = self.occurrences_of.get_mut(&o.node) {
                        v.retain(|&x| (x as usize) < self.occ.len());
                    }
                }
                Change::Loop(l, r) => self.loops[l as usize] = r,
                Change::NewLoop => {
                    self.loops.pop();
                }
            }
        }
        self.touched.clear();
    }

    /// Keeps the changes since `begin`, indexing the new front edges.
    pub fn commit(&mut self, pos: &[DVec2]) {
        self.journal.clear();
        // edges that left the front stay in the grid until dropped here;
        // often enough that a search does not wade through them
        if self.indexed_since_compaction > self.occ.len() / 2 + 4096 {
            self.compact_grid();
        }
        let touched = std::mem::take(&mut self.touched);
        for &fv in &touched {
            let o = self.occ[fv as usize];
            if o.alive {
                self.index_edge(fv, pos);
                let p = o.prev;
                if self.occ[p as usize].alive {
                    self.index_edge(p, pos);
                }
            }
        }
        self.touched = touched;
    }

    /// The live loops touched by the current transaction.
    pub fn touched_loops(&self) -> Vec<u32> {
        let mut v: Vec<u32> = self
            .touched
            .iter()
            .filter(|&&fv| self.occ[fv as usize].alive)
            .map(|&fv| self.occ[fv as usize].lp)
            .collect();
        v.sort_unstable();
        v.dedup();
        v.retain(|&l| self.loops[l as usize].alive);
        v
    }

    /// The live occurrences touched by the current transaction.
    pub fn touched_live(&self) -> Vec<Fv> {
        self.touched
            .iter()
            .copied()
            .filter(|&fv| self.occ[fv as usize].alive)
            .collect()
    }

    /// Occurrences changed since the last call (for re-classification).
    pub fn take_touched(&mut self) -> Vec<Fv> {
        std::mem::take(&mut self.touched)
    }

    fn index_edge(&mut self, fv: Fv, pos: &[DVec2]) {
        let a = self.occ[fv as usize].node;
        let b = self.occ[self.occ[fv as usize].next as usize].node;
        let (pa, pb) = (pos[a as usize], pos[b as usize]);
        let lo = pa.min(pb);
        let hi = pa.max(pb);
        let (x0, y0) = self.cell_of(lo);
        let (x1, y1) = self.cell_of(hi);
        // A very long edge (coarse interior) is indexed at most over a
        // bounded number of cells along its length.
        if (x1 - x0 + 1) as i64 * (y1 - y0 + 1) as i64 > 64 {
            let steps = (((pb - pa).length() / self.cell).ceil() as usize).max(1);
            for k in 0..=steps {
                let c = self.cell_of(pa + (pb - pa) * (k as f64 / steps as f64));
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        self.grid
                            .entry((c.0 + dx, c.1 + dy))
                            .or_default()
                            .push((fv, a, b));
                        self.indexed_since_compaction += 1;
                    }
                }
            }
            return;
        }
        for x in x0..=x1 {
            for y in y0..=y1 {
                self.grid.entry((x, y)).or_default().push((fv, a, b));
                self.indexed_since_compaction += 1;
            }
        }
    }

    fn cell_of(&self, p: DVec2) -> (i32, i32) {
        (
            floor_clamped(p.x / self.cell),
            floor_clamped(p.y / self.cell),
        )
    }

    /// Room for `more` occurrences without growing.
    pub fn reserve(&mut self, more: usize) {
        self.occ.reserve(more);
    }

    /// Indexes every live edge (call once after building, with positions).
    pub fn index_all(&mut self, pos: &[DVec2]) {
        self.grid.clear();
        for fv in 0..self.occ.len() as Fv {
            if self.occ[fv as usize].alive {
                self.index_edge(fv, pos);
            }
        }
        self.touched.clear();
    }

    /// Live front edges (by their first occurrence) with a point within
    /// the box `lo`..`hi`, each once.
    pub fn edges_near(&self, lo: DVec2, hi: DVec2, out: &mut Vec<Fv>) {
        out.clear();
        let (x0, y0) = self.cell_of(lo);
        let (x1, y1) = self.cell_of(hi);
        for x in x0..=x1 {
            for y in y0..=y1 {
                if let Some(v) = self.grid.get(&(x, y)) {
                    for &(fv, a, b) in v {
                        let o = &self.occ[fv as usize];
                        if o.alive && o.node == a && self.occ[o.next as usize].node == b {
                            out.push(fv);
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }

    /// Drops stale grid entries (they are skipped anyway; this bounds memory).
    pub fn compact_grid(&mut self) {
        self.indexed_since_compaction = 0;
        let occ = &self.occ;
        self.grid.retain(|_, v| {
            v.retain(|&(fv, a, b)| {
                let o = &occ[fv as usize];
                o.alive && o.node == a && occ[o.next as usize].node == b
            });
            !v.is_empty()
        });
    }

    fn save(&mut self, fv: Fv) {
        self.journal.push(Change::Occ(fv, self.occ[fv as usize]));
        self.touched.push(fv);
    }

    fn save_loop(&mut self, l: u32) {
        self.journal.push(Change::Loop(l, self.loops[l as usize]));
    }

    /// The node of an occurrence.
    pub fn node(&self, fv: Fv) -> u32 {
        self.occ[fv as usize].node
    }
    /// The next occurrence along the loop.
    pub fn next(&self, fv: Fv) -> Fv {
        self.occ[fv as usize].next
    }
    /// The previous occurrence along the loop.
    pub fn prev(&self, fv: Fv) -> Fv {
        self.occ[fv as usize].prev
    }
    /// The loop of an occurrence.
    pub fn loop_of(&self, fv: Fv) -> u32 {
        self.occ[fv as usize].lp
    }
    /// Whether the occurrence is still on the front.
    pub fn alive(&self, fv: Fv) -> bool {
        self.occ[fv as usize].alive
    }
    /// The layer of an occurrence.
    pub fn layer(&self, fv: Fv) -> u32 {
        self.occ[fv as usize].layer
    }
    /// Number of edges of a loop.
    pub fn loop_len(&self, l: u32) -> usize {
        self.loops[l as usize].len
    }
    /// Some occurrence of a live loop.
    pub fn loop_head(&self, l: u32) -> Fv {
        self.loops[l as usize].head
    }
    /// Whether loop `l` is still on the front (a loop closed, or merged
    /// into another when elements were taken back, is not).
    pub fn is_live(&self, l: u32) -> bool {
        self.loops[l as usize].alive
    }
    /// Ids of the live loops.
    pub fn live_loops(&self) -> Vec<u32> {
        (0..self.loops.len() as u32)
            .filter(|&l| self.loops[l as usize].alive)
            .collect()
    }
    /// Number of occurrence slots (live or not).
    pub fn capacity(&self) -> usize {
        self.occ.len()
    }

    /// The live occurrences of a node.
    pub fn occurrences(&self, node: u32) -> impl Iterator<Item = Fv> + '_ {
        self.occurrences_of
            .get(&node)
            .into_iter()
            .flatten()
            .copied()
            .filter(move |&fv| self.occ[fv as usize].alive && self.occ[fv as usize].node == node)
    }

    /// The occurrences of a loop in order, from its head.
    pub fn loop_fvs(&self, l: u32) -> Vec<Fv> {
        let head = self.loops[l as usize].head;
        let mut out = Vec::with_capacity(self.loops[l as usize].len);
        let mut fv = head;
        loop {
            out.push(fv);
            fv = self.occ[fv as usize].next;
            if fv == head || out.len() > self.occ.len() {
                break;
            }
        }
        out
    }

    /// Interior angle of the remaining domain at an occurrence (degrees).
    pub fn angle(&self, fv: Fv, pos: &[DVec2]) -> f64 {
        let o = &self.occ[fv as usize];
        let p = pos[self.occ[o.prev as usize].node as usize];
        let n = pos[self.occ[o.next as usize].node as usize];
        interior_angle(p, pos[o.node as usize], n).to_degrees()
    }

    /// Replaces the front path strictly between `a` and `b` (a before b on
    /// one loop) by new occurrences of `nodes`; returns them. The nodes may
    /// be new or already on the front (then `split_pinch` follows).
    pub fn replace_path(&mut self, a: Fv, b: Fv, nodes: &[u32], layer: u32) -> Vec<Fv> {
        let l = self.occ[a as usize].lp;
        self.save_loop(l);
        // Remove the occurrences strictly between a and b.
        let mut removed = 0usize;
        let mut fv = self.occ[a as usize].next;
        while fv != b {
            let nx = self.occ[fv as usize].next;
            self.save(fv);
            self.occ[fv as usize].alive = false;
            removed += 1;
            fv = nx;
        }
        let mut prev = a;
        let mut made = Vec::with_capacity(nodes.len());
        for &node in nodes {
            let id = self.occ.len() as Fv;
            self.occ.push(Occurrence {
                node,
                prev,
                next: NONE,
                lp: l,
                alive: true,
                layer,
            });
            self.journal.push(Change::NewOcc);
            self.occurrences_of.entry(node).or_default().push(id);
            self.touched.push(id);
            if prev == a {
                self.save(a);
                self.occ[a as usize].next = id;
            } else {
                self.occ[prev as usize].next = id;
            }
            made.push(id);
            prev = id;
        }
        if prev == a {
            self.save(a);
            self.occ[a as usize].next = b;
        } else {
            self.occ[prev as usize].next = b;
        }
        self.save(b);
        self.occ[b as usize].prev = prev;
        let rec = &mut self.loops[l as usize];
        rec.len = rec.len + nodes.len() + 1 - (removed + 1);
        rec.head = a;
        made
    }

    /// Exchanges the successors of two occurrences of one node: on one
    /// loop this cuts it in two at the node, on two loops it joins them.
    fn swap_next(&mut self, u: Fv, v: Fv) {
        let un = self.occ[u as usize].next;
        let vn = self.occ[v as usize].next;
        for fv in [u, v, un, vn] {
            self.save(fv);
        }
        self.occ[u as usize].next = vn;
        self.occ[vn as usize].prev = u;
        self.occ[v as usize].next = un;
        self.occ[un as usize].prev = v;
    }

    /// Splits a loop at a pinch: `u` and `v` are two occurrences of the same
    /// node on one loop. Afterwards each heads its own loop; a loop of two
    /// edges between the same two nodes (an edge now inside the mesh) is
    /// dropped. Returns the loops that remain, of the two.
    pub fn split_pinch(&mut self, u: Fv, v: Fv) -> Vec<u32> {
        let l = self.occ[u as usize].lp;
        self.swap_next(u, v);
        // Walk both cycles in step to find the shorter, relabel it.
        let total = self.loops[l as usize].len;
        let (mut a, mut b) = (u, v);
        let (mut la, mut lb) = (0usize, 0usize);
        let short_head;
        let short_len;
        loop {
            a = self.occ[a as usize].next;
            la += 1;
            if a == u {
                short_head = u;
                short_len = la;
                break;
            }
            b = self.occ[b as usize].next;
            lb += 1;
            if b == v {
                short_head = v;
                short_len = lb;
                break;
            }
        }
        let long_head = if short_head == u { v } else { u };
        let new_l = self.loops.len() as u32;
        self.loops.push(LoopRec {
            head: short_head,
            len: short_len,
            alive: true,
        });
        self.journal.push(Change::NewLoop);
        let mut fv = short_head;
        loop {
            self.save(fv);
            self.occ[fv as usize].lp = new_l;
            fv = self.occ[fv as usize].next;
            if fv == short_head {
                break;
            }
        }
        self.save_loop(l);
        self.loops[l as usize].len = total - short_len;
        self.loops[l as usize].head = long_head;
        let mut out = Vec::new();
        for lp in [l, new_l] {
            if self.loops[lp as usize].len == 2 {
                let h = self.loops[lp as usize].head;
                let n = self.occ[h as usize].next;
                self.kill_loop(lp, &[h, n]);
            } else {
                out.push(lp);
            }
        }
        out
    }

    /// Joins two loops that touch: `u` and `v` are occurrences of the same
    /// node on different loops; afterwards one loop runs through both.
    /// Returns the loop that remains.
    pub fn join_pinch(&mut self, u: Fv, v: Fv) -> u32 {
        let (lu, lv) = (self.occ[u as usize].lp, self.occ[v as usize].lp);
        self.swap_next(u, v);
        let mut fv = v;
        loop {
            self.save(fv);
            self.occ[fv as usize].lp = lu;
            fv = self.occ[fv as usize].next;
            if fv == v {
                break;
            }
        }
        self.save_loop(lu);
        self.save_loop(lv);
        self.loops[lu as usize].len += self.loops[lv as usize].len;
        self.loops[lv as usize].alive = false;
        self.loops[lv as usize].len = 0;
        lu
    }

    /// Removes a loop from the front (closed by elements).
    pub fn close_loop(&mut self, l: u32) {
        let fvs = self.loop_fvs(l);
        self.kill_loop(l, &fvs);
    }

    fn kill_loop(&mut self, l: u32, fvs: &[Fv]) {
        for &fv in fvs {
            self.save(fv);
            self.occ[fv as usize].alive = false;
        }
        self.save_loop(l);
        self.loops[l as usize].alive = false;
        self.loops[l as usize].len = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_front() -> (Front, Vec<DVec2>) {
        let pos = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let mut f = Front::new(&[0, 1, 2, 3, 4, 5], 1.0);
        f.index_all(&pos);
        (f, pos)
    }

    #[test]
    fn a_cell_is_the_floor_of_the_coordinate() {
        for v in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999,
            -2.999,
            1e9,
            -1e9,
            3e9,
            -3e9,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            123456.75,
            -123456.75,
        ] {
            assert_eq!(floor_clamped(v), v.floor().clamp(-1e9, 1e9) as i32, "{v}");
        }
    }

    #[test]
    fn corner_of_ccw_rectangle_is_ninety_degrees() {
        let (f, pos) = square_front();
        assert!((f.angle(0, &pos) - 90.0).abs() < 1e-9);
        assert!((f.angle(1, &pos) - 180.0).abs() < 1e-9);
    }

    #[test]
    fn linking_across_splits_a_loop_in_two() {
        let (mut f, _) = square_front();
        f.begin();
        // Link node 1 to node 4 through a new occurrence of 4 after 1.
        let made = f.replace_path(1, 2, &[4], 0);
        assert_eq!(f.loop_len(0), 7);
        let v = f.occurrences(4).find(|&x| x != made[0]).unwrap();
        let loops = f.split_pinch(made[0], v);
        let mut lens: Vec<usize> = loops.iter().map(|&l| f.loop_len(l)).collect();
        lens.sort();
        assert_eq!(lens, vec![3, 4]);
    }

    #[test]
    fn rollback_restores_the_loop() {
        let (mut f, _) = square_front();
        f.begin();
        f.replace_path(0, 2, &[], 0);
        assert_eq!(f.loop_len(0), 5);
        f.rollback();
        assert_eq!(f.loop_len(0), 6);
        assert_eq!(f.loop_fvs(0), vec![0, 1, 2, 3, 4, 5]);
    }
}
