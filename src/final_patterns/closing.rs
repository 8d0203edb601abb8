//! Closing a small loop whole, where the rules are stuck on it: every
//! way the KB's `closing_way/2` allows is tried (one element, a quad
//! inset in a four-segment loop, a hub node linked to every other node,
//! a chord into two smaller loops, a two-segment path through a new node
//! into two smaller loops; the smaller loops closed the same way), the
//! new nodes placed by a compass search, and the way whose worst element
//! is best wins.
//!
//! An element's score is its worst corner's distance from 90 degrees,
//! plus a penalty where its size is more than twice off the loop's edges
//! (so an inset quad does not shrink to nothing): at most 45 with every
//! corner in [45, 135] and the size in range; above `NOT_CONVEX` when
//! the element is not convex.

use glam::DVec2;
use std::collections::HashMap;

use crate::geometry::{interior_angle, segments_intersect, SegmentRelation};

/// The ways a loop may be closed (the KB's `closing_way/2` answers).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Ways {
    /// A four-segment loop as one element.
    pub quad: bool,
    /// A four-segment loop as a quad inset in it and four round it.
    pub inset: bool,
    /// A new node linked to every other node of the loop.
    pub hub: bool,
    /// A chord between two nodes: two smaller loops.
    pub chord: bool,
    /// A path of two segments through a new node: two smaller loops.
    pub path: bool,
}

/// How a loop was closed: elements over the loop's nodes (`0..n`) and the
/// new nodes (`n..`), the new nodes' places, the way in words and the
/// worst element's score.
#[derive(Debug, Clone)]
pub struct Closed {
    pub quads: Vec<[usize; 4]>,
    pub new_points: Vec<DVec2>,
    pub text: String,
    pub score: f64,
}

/// The score of an element (see the module's comment); `size` is the
/// loop's mean edge.
fn element_score(q: [DVec2; 4], size: f64) -> f64 {
    let corners = worst_corner_off_right(q);
    if corners >= 89.0 {
        // not convex (or a corner within a degree of flat, as
        // validity.rs's convex_ok): worse than any convex element
        return NOT_CONVEX + corners;
    }
    let area = 0.5
        * ((q[2] - q[0]).perp_dot(q[3] - q[1]))
            .abs()
            .max(f64::MIN_POSITIVE);
    // the penalty starts where the size is more than twice off (the
    // element's area more than four times off the square of the size):
    // the logarithm only past that
    let ratio = area / (size * size);
    if (0.25..=4.0).contains(&ratio) {
        return corners;
    }
    let off = (0.5 * ratio.log2()).abs();
    corners + 45.0 * (off - 1.0).max(0.0)
}

/// The largest distance of a corner of `q` from 90 degrees. The scoring
/// is the closer's hot loop: for a convex element the corner furthest
/// from a right angle is the one with the largest |cos| / sin, so one
/// arctangent serves all four corners.
fn worst_corner_off_right(q: [DVec2; 4]) -> f64 {
    let mut worst_ratio: f64 = 0.0;
    let mut reflex: Option<f64> = None;
    for i in 0..4 {
        let (prev, here, next) = (q[(i + 3) % 4], q[i], q[(i + 1) % 4]);
        match off_right_ratio(prev, here, next) {
            Some(ratio) => worst_ratio = worst_ratio.max(ratio),
            None => {
                // a corner of 180 degrees or more is at least 90 off,
                // more than any convex corner: these alone are measured
                let off = interior_angle(prev, here, next).to_degrees() - 90.0;
                reflex = Some(reflex.map_or(off, |r| r.max(off)));
            }
        }
    }
    match reflex {
        Some(off) => off,
        None => worst_ratio.atan().to_degrees(),
    }
}

/// |cos| / sin of the corner at `here` (counter-clockwise from `next`
/// round to `prev`), the tangent of its distance from 90 degrees; None
/// where the corner is 180 degrees or more.
fn off_right_ratio(prev: DVec2, here: DVec2, next: DVec2) -> Option<f64> {
    let (a, b) = (next - here, prev - here);
    let sine = a.perp_dot(b);
    (sine > 0.0).then(|| a.dot(b).abs() / sine)
}

/// The finest step of the compass search, in loop edges: coarse while
/// the ways are compared, fine when the chosen way's nodes are placed
/// again together at the end.
const SEARCH_STEP: f64 = 2e-2;
const FINAL_STEP: f64 = 1e-3;

/// The least score of an element that is not convex.
pub const NOT_CONVEX: f64 = 1e6;

fn worst(quads: &[[usize; 4]], pt: &dyn Fn(usize) -> DVec2, size: f64) -> f64 {
    quads
        .iter()
        .map(|q| element_score(q.map(pt), size))
        .fold(0.0, f64::max)
}

/// Moves the `free` points (indices into `pts`) by a compass search that
/// lowers the worst score of `quads`, down to steps of `finest` times
/// `size`; returns the score reached. Each element's score is kept, and a
/// trial move scores again only the elements round the moved point.
fn place(pts: &mut [DVec2], free: &[usize], quads: &[[usize; 4]], size: f64, finest: f64) -> f64 {
    let score_of = |pts: &[DVec2], q: &[usize; 4]| element_score(q.map(|i| pts[i]), size);
    let mut scores: Vec<f64> = quads.iter().map(|q| score_of(pts, q)).collect();
    let mut best = scores.iter().copied().fold(0.0, f64::max);
    let round: Vec<Vec<usize>> = free
        .iter()
        .map(|f| (0..quads.len()).filter(|&k| quads[k].contains(f)).collect())
        .collect();
    let mut step = 0.25 * size;
    let dirs = [DVec2::X, DVec2::NEG_X, DVec2::Y, DVec2::NEG_Y];
    let mut trial = Vec::new();
    while step > finest * size && !free.is_empty() {
        let mut moved = false;
        for (&f, round) in free.iter().zip(&round) {
            for d in dirs {
                let old = pts[f];
                pts[f] = old + d * step;
                trial.clear();
                trial.extend(round.iter().map(|&k| score_of(pts, &quads[k])));
                let s = (0..quads.len())
                    .filter(|k| !round.contains(k))
                    .map(|k| scores[k])
                    .chain(trial.iter().copied())
                    .fold(0.0, f64::max);
                if s < best - 1e-9 {
                    best = s;
                    moved = true;
                    for (&k, &t) in round.iter().zip(&trial) {
                        scores[k] = t;
                    }
                } else {
                    pts[f] = old;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    best
}

/// Whether the chord `a`-`b` (positions in `poly`, a counter-clockwise
/// loop) runs inside the loop.
fn chord_inside(pts: &[DVec2], poly: &[usize], a: usize, b: usize) -> bool {
    let n = poly.len();
    let (pa, pb) = (pts[poly[a]], pts[poly[b]]);
    // it leaves each end into the loop's interior angle
    for (v, w) in [(a, pb), (b, pa)] {
        let (prev, here, next) = (
            pts[poly[(v + n - 1) % n]],
            pts[poly[v]],
            pts[poly[(v + 1) % n]],
        );
        let open = interior_angle(prev, here, next);
        let to = interior_angle(w, here, next);
        if !(to > 1e-6 && to < open - 1e-6) {
            return false;
        }
    }
    // and crosses no edge of the loop
    (0..n).all(|i| {
        let j = (i + 1) % n;
        if [i, j].contains(&a) || [i, j].contains(&b) {
            return true;
        }
        segments_intersect(pa, pb, pts[poly[i]], pts[poly[j]]) == SegmentRelation::Disjoint
    })
}

/// The search over the ways: loops are lists of point indices, the new
/// nodes of paths and the inner nodes of each way appended to `pts`.
struct Search {
    pts: Vec<DVec2>,
    /// The ways allowed, by the loop's number of segments.
    ways: Vec<Ways>,
    size: f64,
    /// A path's middle node for each pair of ends, so a loop reached twice
    /// is the same loop.
    middles: HashMap<(usize, usize), usize>,
    memo: HashMap<Vec<usize>, Option<Closed>>,
    /// Splits scoring this or worse are not followed (`NOT_CONVEX`: no
    /// cap).
    cap: f64,
}

impl Search {
    fn close(&mut self, poly: &[usize]) -> Option<Closed> {
        if let Some(done) = self.memo.get(poly) {
            return done.clone();
        }
        let best = self.close_fresh(poly);
        self.memo.insert(poly.to_vec(), best.clone());
        best
    }

    /// Elements are over global point indices here; `Closed::new_points`
    /// stays empty until the end (every new node is in `pts`).
    fn close_fresh(&mut self, poly: &[usize]) -> Option<Closed> {
        let n = poly.len();
        let ways = self.ways.get(n).copied().unwrap_or_default();
        let mut best: Option<Closed> = None;
        let keep = |best: &mut Option<Closed>, c: Closed| {
            if c.score < NOT_CONVEX && best.as_ref().is_none_or(|b| c.score < b.score) {
                *best = Some(c);
            }
        };
        // what a split must beat: its first loop's score alone can rule it
        // out before the second is closed (a split's score is the larger)
        let cap = self.cap;
        let beat = |best: &Option<Closed>| best.as_ref().map_or(cap, |b| b.score.min(cap));
        if n == 4 && ways.quad {
            let q = [poly[0], poly[1], poly[2], poly[3]];
            let score = worst(&[q], &|i| self.pts[i], self.size);
            keep(
                &mut best,
                Closed {
                    quads: vec![q],
                    new_points: vec![],
                    text: "quad".into(),
                    score,
                },
            );
        }
        // no other way can score below a loop's sharpest corner
        if best
            .as_ref()
            .is_some_and(|b| b.score <= self.least_score(poly))
        {
            return best;
        }
        if n == 4 && ways.inset {
            keep(&mut best, self.inset(poly));
        }
        if n >= 6 && ways.hub {
            for parity in 0..2 {
                keep(&mut best, self.hub(poly, parity));
            }
        }
        if n >= 6 && ways.chord {
            for a in 0..n {
                for b in (a + 3..n).step_by(2) {
                    if n - (b - a) < 3 || !chord_inside(&self.pts, poly, a, b) {
                        continue;
                    }
                    let left: Vec<usize> = poly[a..=b].to_vec();
                    let right: Vec<usize> = poly[b..].iter().chain(&poly[..=a]).copied().collect();
                    let how = format!("chord({a}, {b}");
                    if let Some(c) = self.both(&left, &right, how, beat(&best)) {
                        keep(&mut best, c);
                    }
                }
            }
        }
        if n >= 8 && ways.path {
            for a in 0..n {
                for b in (a + 4..n).step_by(2) {
                    if n - (b - a) < 4 || !chord_inside(&self.pts, poly, a, b) {
                        continue;
                    }
                    let m = self.middle(poly[a], poly[b]);
                    let mut left: Vec<usize> = poly[a..=b].to_vec();
                    left.push(m);
                    let mut right: Vec<usize> =
                        poly[b..].iter().chain(&poly[..=a]).copied().collect();
                    right.push(m);
                    let how = format!("path({a}, {b}");
                    if let Some(c) = self.both(&left, &right, how, beat(&best)) {
                        keep(&mut best, c);
                    }
                }
            }
        }
        best
    }

    /// The split into loops `left` and `right`, or None where either
    /// cannot be closed or either alone scores `beat` or worse.
    fn both(&mut self, left: &[usize], right: &[usize], how: String, beat: f64) -> Option<Closed> {
        if self.least_score(left) >= beat || self.least_score(right) >= beat {
            return None;
        }
        let l = self.close(left)?;
        if l.score >= beat {
            return None;
        }
        let r = self.close(right)?;
        Some(Closed {
            quads: l.quads.iter().chain(&r.quads).copied().collect(),
            new_points: vec![],
            text: format!("{how}, {}, {})", l.text, r.text),
            score: l.score.max(r.score),
        })
    }

    /// A score no closing of `poly` can beat: an element at a corner of
    /// the loop sharper than 90 degrees has a corner at least that sharp
    /// (the elements there share the loop's corner). Measured as
    /// `element_score` measures corners (`off_right_ratio`), so a
    /// four-segment loop whose quad's worst corner is the sharp one scores
    /// exactly this.
    fn least_score(&self, poly: &[usize]) -> f64 {
        let n = poly.len();
        let mut worst_ratio: f64 = 0.0;
        for i in 0..n {
            let (prev, here, next) = (
                self.pts[poly[(i + n - 1) % n]],
                self.pts[poly[i]],
                self.pts[poly[(i + 1) % n]],
            );
            // only the corners sharper than 90 degrees bind
            if (next - here).dot(prev - here) > 0.0 {
                if let Some(ratio) = off_right_ratio(prev, here, next) {
                    worst_ratio = worst_ratio.max(ratio);
                }
            }
        }
        worst_ratio.atan().to_degrees()
    }

    /// The middle node of a path between points `a` and `b`.
    fn middle(&mut self, a: usize, b: usize) -> usize {
        if let Some(&m) = self.middles.get(&(a, b)) {
            return m;
        }
        self.pts.push((self.pts[a] + self.pts[b]) * 0.5);
        let m = self.pts.len() - 1;
        self.middles.insert((a, b), m);
        m
    }

    fn centroid(&self, poly: &[usize]) -> DVec2 {
        poly.iter().map(|&i| self.pts[i]).sum::<DVec2>() / poly.len() as f64
    }

    fn hub(&mut self, poly: &[usize], parity: usize) -> Closed {
        let n = poly.len();
        let linked: Vec<usize> = (0..n / 2).map(|k| poly[(2 * k + parity) % n]).collect();
        self.pts.push(self.centroid(&linked));
        let h = self.pts.len() - 1;
        let quads: Vec<[usize; 4]> = (0..n / 2)
            .map(|k| {
                let at = |i: usize| poly[(2 * k + parity + i) % n];
                [at(0), at(1), at(2), h]
            })
            .collect();
        let score = place(&mut self.pts, &[h], &quads, self.size, SEARCH_STEP);
        Closed {
            quads,
            new_points: vec![],
            text: format!("hub({parity})"),
            score,
        }
    }

    fn inset(&mut self, poly: &[usize]) -> Closed {
        let c = self.centroid(poly);
        let inner: Vec<usize> = poly
            .iter()
            .map(|&i| {
                self.pts.push(self.pts[i].lerp(c, 0.45));
                self.pts.len() - 1
            })
            .collect();
        let mut quads: Vec<[usize; 4]> = (0..4)
            .map(|k| [poly[k], poly[(k + 1) % 4], inner[(k + 1) % 4], inner[k]])
            .collect();
        quads.push([inner[0], inner[1], inner[2], inner[3]]);
        let score = place(&mut self.pts, &inner, &quads, self.size, SEARCH_STEP);
        Closed {
            quads,
            new_points: vec![],
            text: "inset".into(),
            score,
        }
    }
}

/// The closings searched so far in a run, by the loop's points (exactly),
/// the ways allowed and the cap: the search is a function of those alone.
#[derive(Default)]
pub struct Memo {
    done: HashMap<MemoKey, Option<Closed>>,
}

/// A loop's points (their bits), the ways allowed and the cap (its bits).
type MemoKey = (Vec<[u64; 2]>, Vec<Ways>, u64);

impl Memo {
    /// `close_loop`, answered from the memo where the same loop was
    /// searched before.
    pub fn close_loop(&mut self, points: &[DVec2], ways: &[Ways], cap: f64) -> Option<Closed> {
        let key = (
            points
                .iter()
                .map(|p| [p.x.to_bits(), p.y.to_bits()])
                .collect(),
            ways.to_vec(),
            cap.to_bits(),
        );
        self.done
            .entry(key)
            .or_insert_with(|| close_loop(points, ways, cap))
            .clone()
    }
}

/// The best way to close the loop through `points` (counter-clockwise,
/// the region on the left) with the `ways` allowed, or None if no way
/// gives convex elements. `ways[k]` are the ways for a loop of `k`
/// segments. The new nodes of the chosen way are placed
/// again, all together, at the end.
/// A way that splits the loop is followed only while its parts score
/// below `cap` (`NOT_CONVEX`: always): a caller that takes only elements
/// with every corner within `cap` degrees of a right angle (less the gain
/// of the last placement) loses nothing by it, and the search ends sooner.
pub fn close_loop(points: &[DVec2], ways: &[Ways], cap: f64) -> Option<Closed> {
    let n = points.len();
    if n < 4 || n % 2 == 1 {
        return None;
    }
    let size = (0..n)
        .map(|i| (points[(i + 1) % n] - points[i]).length())
        .sum::<f64>()
        / n as f64;
    let mut search = Search {
        pts: points.to_vec(),
        ways: ways.to_vec(),
        size,
        middles: HashMap::new(),
        memo: HashMap::new(),
        cap,
    };
    let loop_: Vec<usize> = (0..n).collect();
    let mut best = search.close(&loop_)?;
    // renumber the new nodes the way uses, in order of first use
    let mut renumber: HashMap<usize, usize> = HashMap::new();
    let mut new_points = Vec::new();
    for q in &mut best.quads {
        for i in q.iter_mut() {
            if *i >= n {
                let next = n + renumber.len();
                *i = *renumber.entry(*i).or_insert_with(|| {
                    new_points.push(search.pts[*i]);
                    next
                });
            }
        }
    }
    let mut pts: Vec<DVec2> = points.iter().copied().chain(new_points).collect();
    let free: Vec<usize> = (n..pts.len()).collect();
    best.score = place(&mut pts, &free, &best.quads, size, FINAL_STEP);
    best.new_points = pts[n..].to_vec();
    Some(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EVERY: Ways = Ways {
        quad: true,
        inset: true,
        hub: true,
        chord: true,
        path: true,
    };
    const ALL: &[Ways] = &[EVERY; 13];

    fn rect(w: usize, h: usize) -> Vec<DVec2> {
        let mut p = Vec::new();
        for i in 0..w {
            p.push(DVec2::new(i as f64, 0.0));
        }
        for j in 0..h {
            p.push(DVec2::new(w as f64, j as f64));
        }
        for i in (1..=w).rev() {
            p.push(DVec2::new(i as f64, h as f64));
        }
        for j in (1..=h).rev() {
            p.push(DVec2::new(0.0, j as f64));
        }
        p
    }

    #[test]
    fn a_two_by_three_block_closes_as_its_grid() {
        let c = close_loop(&rect(3, 2), ALL, NOT_CONVEX).expect("closed");
        assert_eq!(c.quads.len(), 6, "{}", c.text);
        assert!(c.score < 1.0, "score {} by {}", c.score, c.text);
    }

    #[test]
    fn a_triangle_with_a_node_on_one_side_is_an_inset_quad() {
        // a four-segment loop that is no element: one node straight
        let p = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 1.6),
        ];
        let c = close_loop(&p, ALL, NOT_CONVEX).expect("closed");
        assert_eq!(c.text, "inset");
        assert_eq!(c.quads.len(), 5);
        // convex (the triangle's corners split in two cannot all be in
        // the window)
        assert!(c.score < NOT_CONVEX, "score {}", c.score);
        let without = [Ways {
            inset: false,
            ..EVERY
        }; 5];
        assert!(close_loop(&p, &without, NOT_CONVEX).is_none());
    }

    #[test]
    fn no_closing_beats_the_loops_sharpest_corner() {
        // an eight-segment loop with a 30-degree corner at the origin:
        // whatever way wins, an element there has a corner of 30 or less
        let t = 30f64.to_radians();
        let p = [
            DVec2::ZERO,
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(3.0, 0.0),
            DVec2::new(3.0, 1.0),
            DVec2::new(2.0, 1.5),
            DVec2::new(1.5, 1.5),
            DVec2::new(t.cos(), t.sin()) * 1.2,
        ];
        let search = Search {
            pts: p.to_vec(),
            ways: ALL.to_vec(),
            size: 1.0,
            middles: HashMap::new(),
            memo: HashMap::new(),
            cap: NOT_CONVEX,
        };
        let least = search.least_score(&(0..8).collect::<Vec<_>>());
        assert!((least - 60.0).abs() < 1e-9, "least {least}");
        let c = close_loop(&p, ALL, NOT_CONVEX).expect("closed");
        assert!(c.score >= least - 1e-9, "{} scores {}", c.text, c.score);
        // uncapped, a split wins here; under a cap of 50 no split is
        // followed: one of its parts has the 30-degree corner
        assert!(c.text.starts_with("path"), "{}", c.text);
        let capped = close_loop(&p, ALL, 50.0);
        assert!(
            capped
                .as_ref()
                .is_none_or(|c| !c.text.starts_with("chord") && !c.text.starts_with("path")),
            "{:?}",
            capped.map(|c| c.text)
        );
        // the run's memo answers as the search does
        let mut memo = Memo::default();
        let again = memo.close_loop(&p, ALL, NOT_CONVEX).expect("closed");
        assert_eq!((again.text, again.score), (c.text, c.score));
    }

    #[test]
    fn an_odd_loop_is_not_closed() {
        let p = [DVec2::ZERO, DVec2::X, DVec2::ONE];
        assert!(close_loop(&p, ALL, NOT_CONVEX).is_none());
    }

    #[test]
    fn the_kb_names_the_ways_for_each_loop() {
        let mut kb = crate::kb::KnowledgeBase::builtin().unwrap();
        assert_eq!(kb.closing_ways(4).unwrap(), ["quad", "inset"]);
        assert_eq!(kb.closing_ways(6).unwrap(), ["hub", "chord"]);
        assert_eq!(kb.closing_ways(10).unwrap(), ["hub", "chord", "path"]);
    }
}
