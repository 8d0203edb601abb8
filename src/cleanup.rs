//! Topological clean-up: where smoothing cannot bring an element's corners
//! into the window of `bound/2` ([45, 135] built in; the way the elements meet there is wrong, not where
//! the nodes are), the elements are joined up anew.
//!
//! Two operations, both keeping the mesh all-quad and conforming and the
//! input boundary and inner lines as they are:
//!
//! - flip: two elements sharing an edge make a hexagon; it is split into
//!   two elements along one of its other two diagonals;
//! - collapse: an element is removed by joining two opposite corners
//!   (the free one moves onto the other), its neighbours closing the gap;
//! - merge: the elements round a few free nodes, when their outline is a
//!   loop of four or six nodes, are replaced by one element or two (what
//!   a ring closing a small loop leaves is such a patch: once smoothing
//!   made the loop good, its small middle element and the slanted ones
//!   round it give the worst corners and size jumps of the mesh);
//! - split: two elements sharing an edge make a hexagon; it is split into
//!   three round a new node in its middle. A node of the hexagon that has
//!   one element too few gets one more: a lone element at a boundary node
//!   bent more than the window allows (on a tight arc, where a row ended)
//!   keeps that corner whatever the smoothing does, and no flip or
//!   collapse gives the node a second element without taking one from the
//!   next node along the boundary. Where a lone element spans two edges
//!   of a tight arc, its node between them gets a second element from a
//!   split of the hexagon into four round two new nodes (no split into
//!   three gives it one without taking one from a neighbour along the
//!   arc): see `hexagon.rs`.
//!
//! Each element with a corner outside the window, worst first, is tried
//! with every flip of its edges and every collapse; the region round each
//! result is smoothed locally, and the best result is kept if it makes the
//! region's worst corner clearly better. Then each element past the shape
//! and size bounds (built in: aspect ratio or taper above 10, size above
//! twice a neighbour's) gets the change that brings its region furthest within
//! them, if no corner of the region gets worse. Last, each element still
//! with a corner outside the window gets the split that makes its
//! region's worst corner clearly better without taking the region past
//! the shape and size bounds.

use glam::DVec2;

use crate::mesh::Mesh;
use crate::settings::ElementBounds;

use crate::element_quality::sine_worst_around_every_corner;

mod changes;
mod coarsen;
mod hexagon;
mod unfold;

pub use coarsen::coarsen_to_field;

use changes::{changes, Change, Op, Working, Worst};

/// What the clean-up did.
#[derive(Debug, Default, Clone, Copy)]
pub struct CleanupStats {
    /// Flips kept.
    pub flips: usize,
    /// Collapses kept.
    pub collapses: usize,
    /// Hexagons split into three (an element more each).
    pub splits: usize,
}

/// How many of an element's changes, best first as they are made, are
/// smoothed and judged in full; the rest are judged only if none of these
/// is good.
const JUDGED: usize = 2;

/// How far round the last changes a later clean-up looks (elements): the
/// smoothing after them moved nodes two rings out.
const NEAR_RINGS: usize = 4;

/// A whole mesh of this many elements or more is cleaned up with a copy
/// to judge changes on beside it (see `first_good`).
const SIDE_BY_SIDE_FROM: usize = 20_000;

/// The operations tried on every bad element.
const OPS: [Op; 9] = [
    Op::Flip(0),
    Op::Flip(1),
    Op::Flip(2),
    Op::Flip(3),
    Op::Collapse(0),
    Op::Collapse(1),
    Op::Collapse(2),
    Op::Collapse(3),
    Op::Merge,
];

/// Cleans up the elements with a corner outside the window of `bounds`
/// or past its shape and size bounds: all of them, or (`near`) those within a few
/// elements of these nodes (round the last clean-up's changes: elsewhere
/// nothing changed since). Returns what it did and the nodes round the
/// changes (to be smoothed again).
pub fn clean_up(
    mesh: &mut Mesh,
    near: Option<&[u32]>,
    bounds: &ElementBounds,
) -> (CleanupStats, Vec<u32>) {
    // a second copy to judge changes on beside the first: for a whole
    // large mesh, where many elements have all their changes judged
    let threads = std::thread::available_parallelism().map_or(1, |c| c.get());
    let side_by_side = near.is_none() && threads > 1 && mesh.quads.len() >= SIDE_BY_SIDE_FROM;
    clean_up_on(mesh, near, side_by_side, bounds)
}

/// `clean_up`, judging changes on a copy beside the mesh or not.
fn clean_up_on(
    mesh: &mut Mesh,
    near: Option<&[u32]>,
    side_by_side: bool,
    bounds: &ElementBounds,
) -> (CleanupStats, Vec<u32>) {
    let mut stats = CleanupStats::default();
    let mut touched: Vec<u32> = Vec::new();
    let mut copy = side_by_side.then(|| mesh.clone());
    let mut w = Working::new(mesh, *bounds);
    let mut helper = copy.as_mut().map(|m| Working::new(m, *bounds));
    let look_at: Vec<u32> = match near {
        None => (0..w.mesh.quads.len() as u32).collect(),
        Some(nodes) => w.elements_near(nodes, NEAR_RINGS),
    };
    rounds(
        &mut w,
        &mut helper,
        look_at.clone(),
        &mut stats,
        &mut touched,
    );
    // flips and collapses first; a split adds elements, so it comes only
    // where they could not mend the shape
    shape_round(
        &OPS,
        &mut w,
        &mut helper,
        &look_at,
        &mut stats,
        &mut touched,
    );
    shape_round(
        &SPLITS,
        &mut w,
        &mut helper,
        &look_at,
        &mut stats,
        &mut touched,
    );
    split_round(&mut w, &mut helper, &look_at, &mut stats, &mut touched);
    finish(w, stats, touched)
}

/// Ends a clean-up: the collapsed elements' slots go; what it did and
/// the nodes round its changes, each once.
fn finish(w: Working, stats: CleanupStats, mut touched: Vec<u32>) -> (CleanupStats, Vec<u32>) {
    let Working { mesh, alive, .. } = w;
    keep_alive(&mut mesh.quads, &alive);
    if !mesh.blocks.is_empty() {
        keep_alive(&mut mesh.blocks, &alive);
    }
    touched.sort_unstable();
    touched.dedup();
    (stats, touched)
}

/// Keeps the items (one an element) whose element is alive.
fn keep_alive<T>(items: &mut Vec<T>, alive: &[bool]) {
    let mut k = 0;
    items.retain(|_| {
        k += 1;
        alive[k - 1]
    });
}

/// Up to three rounds over the bad elements among `look_at`, worst first
/// (the next rounds look near the changes made): each gets the best
/// change, if one is clearly better.
fn rounds(
    w: &mut Working,
    helper: &mut Option<Working>,
    mut look_at: Vec<u32>,
    stats: &mut CleanupStats,
    touched: &mut Vec<u32>,
) {
    for _round in 0..3 {
        let mut next: Vec<u32> = Vec::new();
        for q in worst_first(w, &look_at, corner_past) {
            if !w.alive[q as usize] || corner_past(w, q) <= 0.0 {
                continue;
            }
            let candidates: Vec<Change> = OPS.iter().flat_map(|&op| changes(w, q, op)).collect();
            // ranked by the changed elements' smallest sine; kept if the
            // region's worst corner gets clearly better
            let done = best_change(
                w,
                helper,
                candidates,
                sine_rank,
                |w, region| w.worst_of(region),
                |before, after| clearly_better(after, before).then_some(after),
            );
            if let Some(done) = done {
                let nodes = record(w, &done, stats, touched);
                next.extend(
                    nodes
                        .iter()
                        .flat_map(|&n| w.around[n as usize].iter().copied()),
                );
            }
        }
        if next.is_empty() {
            break;
        }
        next.sort_unstable();
        next.dedup();
        look_at = next;
    }
}

/// One round over the elements of `look_at` past the shape and size
/// bounds (aspect ratio or taper above 10, size above twice a
/// neighbour's), worst first: each gets the change of `ops` that brings
/// its region furthest within them, if it does so clearly and no corner
/// of the region gets worse.
fn shape_round(
    ops: &[Op],
    w: &mut Working,
    helper: &mut Option<Working>,
    look_at: &[u32],
    stats: &mut CleanupStats,
    touched: &mut Vec<u32>,
) {
    let past = |w: &Working, q: u32| w.shape_excess(&[q]) - 1.0;
    for q in worst_first(w, look_at, past) {
        if !w.alive[q as usize] || past(w, q) <= 0.0 {
            continue;
        }
        let candidates: Vec<Change> = ops.iter().flat_map(|&op| changes(w, q, op)).collect();
        // ranked by the changed elements' excess; kept if the region's
        // gets clearly smaller with no corner worse
        let done = best_change(
            w,
            helper,
            candidates,
            |w, changed| w.shape_excess(changed),
            |w, region| (w.worst_of(region), w.shape_excess(region)),
            |(before, shape_before), (after, shape_after)| {
                (after.0.is_finite() && after.0 <= before.0 && shape_after < shape_before - 0.01)
                    .then_some(shape_after)
            },
        );
        if let Some(done) = done {
            record(w, &done, stats, touched);
        }
    }
}

/// The splits of the hexagons of an element and its neighbours.
const SPLITS: [Op; 4] = [Op::Split(0), Op::Split(1), Op::Split(2), Op::Split(3)];

/// One round over the elements of `look_at` (and the elements the round
/// adds) with a corner still outside the window, worst first: each gets
/// the split that makes its region's worst corner clearly better, if the
/// region stays within the shape and size bounds (or gets no further
/// past them).
fn split_round(
    w: &mut Working,
    helper: &mut Option<Working>,
    look_at: &[u32],
    stats: &mut CleanupStats,
    touched: &mut Vec<u32>,
) {
    for q in worst_first(w, look_at, corner_past) {
        if !w.alive[q as usize] || corner_past(w, q) <= 0.0 {
            continue;
        }
        let candidates: Vec<Change> = SPLITS.iter().flat_map(|&op| changes(w, q, op)).collect();
        let done = best_change(
            w,
            helper,
            candidates,
            sine_rank,
            |w, region| (w.worst_of(region), w.shape_excess(region)),
            |(before, shape_before): (Worst, f64), (after, shape_after): (Worst, f64)| {
                (clearly_better(after, before) && shape_after <= shape_before.max(1.0))
                    .then_some(after)
            },
        );
        if let Some(done) = done {
            record(w, &done, stats, touched);
        }
    }
}

/// The live elements of `look_at` that `past` puts past a bound (above
/// 0), worst first.
fn worst_first(w: &Working, look_at: &[u32], past: impl Fn(&Working, u32) -> f64) -> Vec<u32> {
    let mut bad: Vec<(f64, u32)> = look_at
        .iter()
        .copied()
        .filter(|&q| w.alive[q as usize])
        .map(|q| (past(w, q), q))
        .filter(|&(x, _)| x > 0.0)
        .collect();
    bad.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    bad.into_iter().map(|(_, q)| q).collect()
}

/// How far element q's worst corner is outside the window (degrees).
fn corner_past(w: &Working, q: u32) -> f64 {
    w.worst_of(&[q]).0
}

/// A change's rank by the smallest sine of the elements it changed
/// (smaller first).
fn sine_rank(w: &Working, changed: &[u32]) -> f64 {
    let pairs: Vec<(u32, u8)> = changed.iter().map(|&q| (q, 0)).collect();
    sine_worst_around_every_corner(w.mesh, &pairs)
}

/// Counts a change made and notes the nodes round it; returns them.
fn record(
    w: &Working,
    done: &Change,
    stats: &mut CleanupStats,
    touched: &mut Vec<u32>,
) -> Vec<u32> {
    match done {
        Change::Flip { .. } => stats.flips += 1,
        Change::Collapse { .. } => stats.collapses += 1,
        // the elements that go count as collapsed
        Change::Merge { gone, .. } => stats.collapses += gone.len(),
        Change::Add { .. } => stats.splits += 1,
    }
    let nodes = done.nodes(w);
    touched.extend(&nodes);
    nodes
}

/// Makes the best of `candidates` by `accept`, if any: each is ranked
/// as made by `quick` on the elements it changes (cheap, smaller first),
/// the best few made again with smoothing round them and their region
/// measured before and after; `accept` gives the score of a good one
/// (smaller is better). Where none of the few is good, the first good
/// one of the rest; with a `helper` (a copy of the mesh) two threads
/// look for it, the answer the same. The change is made on both.
fn best_change<M, K: PartialOrd + Copy + Send>(
    w: &mut Working,
    helper: &mut Option<Working>,
    candidates: Vec<Change>,
    quick: impl Fn(&Working, &[u32]) -> f64,
    measure: impl Fn(&Working, &[u32]) -> M + Sync,
    accept: impl Fn(M, M) -> Option<K> + Sync,
) -> Option<Change> {
    let mut raw: Vec<(f64, usize)> = Vec::new();
    for (i, c) in candidates.iter().enumerate() {
        c.apply(w);
        raw.push((quick(w, &c.changed()), i));
        c.revert(w);
    }
    raw.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let ranked: Vec<usize> = raw.iter().map(|&(_, i)| i).collect();
    let judge = |w: &mut Working, i: usize| judge_change(w, &candidates[i], &measure, &accept);
    let mut best: Option<(K, usize, Vec<(u32, DVec2)>)> = None;
    for &i in ranked.iter().take(JUDGED) {
        if let Some((score, moved)) = judge(w, i) {
            if best.as_ref().is_none_or(|b| score < b.0) {
                best = Some((score, i, moved));
            }
        }
    }
    let rest = ranked.get(JUDGED..).unwrap_or(&[]);
    let (i, moved) = match best {
        Some((_, i, moved)) => (i, moved),
        None => first_good(w, helper, rest, &judge)?,
    };
    let c = candidates[i].clone();
    c.apply(w);
    w.restore(&moved);
    if let Some(h) = helper {
        c.apply(h);
        h.restore(&moved);
    }
    Some(c)
}

/// Makes change `c`, smooths round it and measures its region before
/// and after; the score `accept` gives it and where the nodes went, if
/// it is good. The mesh is left as it was.
fn judge_change<M, K>(
    w: &mut Working,
    c: &Change,
    measure: &impl Fn(&Working, &[u32]) -> M,
    accept: &impl Fn(M, M) -> Option<K>,
) -> Option<(K, Vec<(u32, DVec2)>)> {
    let region = c.region(w);
    let mut after_region = region.clone();
    match c {
        Change::Collapse { q, .. } => after_region.retain(|r| r != q),
        Change::Merge { gone, .. } => after_region.retain(|r| !gone.contains(r)),
        Change::Add { first, added, .. } => {
            after_region.extend(*first..*first + added.len() as u32)
        }
        Change::Flip { .. } => {}
    }
    let saved = w.snapshot(&region);
    let before = measure(w, &region);
    // (`bound(unfold_crowded_corners, 1)`)
    let crowded = if w.bounds.unfold_crowded_corners >= 1.0 {
        w.crowded_corners(&c.changed())
    } else {
        Vec::new()
    };
    c.apply(w);
    let nodes = c.nodes(w);
    match c {
        // new nodes start far from where they go
        Change::Add { .. } => w.smooth_sweeps(&nodes, 6),
        _ => w.smooth_locally(&nodes),
    }
    // a change that takes an element from a crowded corner, folded over
    // by the smoothing: smoothed again from the mean of each free node's
    // neighbours (the other element must move well away)
    let relieves = crowded
        .iter()
        .any(|&(n, count)| w.around[n as usize].len() < count);
    if relieves && !w.worst_of(&after_region).0.is_finite() {
        w.place_at_neighbours_mean(&nodes);
        w.smooth_sweeps(&nodes, 4);
    }
    let good = accept(before, measure(w, &after_region)).map(|k| (k, w.snapshot(&after_region)));
    c.revert(w);
    w.restore(&saved);
    good
}

/// The first of `ranked` that `judge` finds good (its index and where its
/// nodes went). With a helper, one thread judges every other one on it:
/// each stops at its first good one, or once the other found one ranked
/// before; the earlier of the two is the one judging in turn finds.
fn first_good<K: Send>(
    w: &mut Working,
    helper: &mut Option<Working>,
    ranked: &[usize],
    judge: &(impl Fn(&mut Working, usize) -> Option<(K, Vec<(u32, DVec2)>)> + Sync),
) -> Option<(usize, Vec<(u32, DVec2)>)> {
    let Some(h) = helper.as_mut().filter(|_| ranked.len() > 1) else {
        return ranked
            .iter()
            .find_map(|&i| judge(w, i).map(|(_, moved)| (i, moved)));
    };
    let found = std::sync::atomic::AtomicUsize::new(usize::MAX);
    let search = |w: &mut Working, first: usize| {
        for rank in (first..ranked.len()).step_by(2) {
            if rank > found.load(std::sync::atomic::Ordering::SeqCst) {
                return None;
            }
            if let Some((_, moved)) = judge(w, ranked[rank]) {
                found.fetch_min(rank, std::sync::atomic::Ordering::SeqCst);
                return Some((rank, moved));
            }
        }
        None
    };
    let (mine, theirs) = std::thread::scope(|scope| {
        let other = scope.spawn(|| search(h, 1));
        let mine = search(w, 0);
        // a judging that panicked is a defect: let it surface as one
        let theirs = other
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        (mine, theirs)
    });
    let (rank, moved) = mine.into_iter().chain(theirs).min_by_key(|r| r.0)?;
    Some((ranked[rank], moved))
}

/// Half a degree better, or every corner brought into the bounds, or
/// (with none worse) a smallest sine clearly larger.
fn clearly_better(after: Worst, before: Worst) -> bool {
    after.0.is_finite()
        && (after.0 < before.0 - 0.5
            || (after.0 == 0.0 && before.0 > 0.0)
            || (after.0 <= before.0 && after.1 < before.1 - 0.05))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::quad_angles;
    use crate::mesh::BoundaryEdge;
    use crate::mesh::NodeKind;

    /// A fixed sequence of numbers in [-0.5, 0.5) from `seed`.
    fn noise(seed: u64) -> impl FnMut() -> f64 {
        let mut unit = crate::geometry::test_noise(seed);
        move || unit() - 0.5
    }

    /// How far the worst corner of the mesh is past [45, 135] (degrees).
    fn worst_corner(m: &Mesh) -> f64 {
        (0..m.quads.len())
            .flat_map(|q| quad_angles(m.quad_points(q)))
            .map(|a| (45.0 - a).max(a - 135.0))
            .fold(f64::MIN, f64::max)
    }

    /// A hexagon of fixed nodes (its sides input edges) split into the
    /// two elements `quads`.
    fn fixed_hexagon(corners: [(f64, f64); 6], quads: [[u32; 4]; 2]) -> Mesh {
        let mut m = Mesh::default();
        for (x, y) in corners {
            m.add_node(DVec2::new(x, y), NodeKind::Boundary);
        }
        m.quads = quads.to_vec();
        for k in 0..6u32 {
            m.boundary.push(BoundaryEdge {
                a: k,
                b: (k + 1) % 6,
                group: 0,
                tag: None,
            });
        }
        m
    }

    /// A hexagon of fixed nodes split into two elements along its diagonal
    /// 0-3 (corners of 34 degrees), which the split 2-5 would not have
    /// (59 to 121 degrees); the hexagon's sides are input edges.
    fn badly_split_hexagon() -> Mesh {
        let corners = [
            (0.0, 0.0),
            (3.0, 0.0),
            (3.6, 1.0),
            (3.0, 2.0),
            (0.0, 2.0),
            (-0.6, 1.0),
        ];
        fixed_hexagon(corners, [[0, 1, 2, 3], [3, 4, 5, 0]])
    }

    /// A hexagon of fixed nodes, corners of 150 degrees at nodes 1 and 5
    /// and of 105 at the others, split into two elements along its
    /// diagonal 2-5: node 1 has one element and a corner of 150 there. A
    /// flip gives it a second element but takes one from node 5 (150
    /// again there); only a split into three round a new middle node
    /// gives node 1 an element more and takes none from node 5.
    fn hexagon_with_a_lone_bent_corner() -> Mesh {
        let corners = [
            (0.0, 0.0),
            (0.783953, 0.0),
            (1.559733, 0.447894),
            (1.245008, 1.622507),
            (0.028906, 1.622507),
            (-0.202903, 0.757225),
        ];
        fixed_hexagon(corners, [[0, 1, 2, 5], [2, 3, 4, 5]])
    }

    /// A hexagon of fixed nodes and unit sides, corners of 80 degrees at
    /// nodes 0 and 3 and of 140 at the others, split into two elements
    /// along its diagonal 2-5: nodes 1 and 4 have one element each and a
    /// corner of 140 there (a lone element spanning two edges of a tight
    /// arc). A flip gives them a second but takes one from nodes 2 and 5
    /// (140 again there); a split into three gives only one of 1 and 4
    /// a second.
    fn hexagon_with_two_lone_bent_corners() -> Mesh {
        let (c, s) = (40f64.to_radians().cos(), 40f64.to_radians().sin());
        let corners = [
            (0.0, 0.0),
            (c, -s),
            (c + 1.0, -s),
            (2.0 * c + 1.0, 0.0),
            (c + 1.0, s),
            (c, s),
        ];
        fixed_hexagon(corners, [[0, 1, 2, 5], [2, 3, 4, 5]])
    }

    /// Two elements sharing the boundary corner at node 0, of `corner`
    /// degrees, its free node 3 on the bisector.
    fn two_elements_at_a_corner(corner: f64) -> Mesh {
        let dir = |deg: f64| DVec2::new(deg.to_radians().cos(), deg.to_radians().sin());
        let mut m = Mesh::default();
        let kinds = [
            NodeKind::Boundary,
            NodeKind::Boundary,
            NodeKind::Boundary,
            NodeKind::Interior,
            NodeKind::Boundary,
            NodeKind::Boundary,
        ];
        let points = [
            DVec2::ZERO,
            2.0 * dir(0.0),
            2.0 * dir(corner),
            1.5 * dir(corner / 2.0),
            2.0 * dir(0.0) + dir(corner / 2.0),
            2.0 * dir(corner) + dir(corner / 2.0),
        ];
        for (p, k) in points.into_iter().zip(kinds) {
            m.add_node(p, k);
        }
        m.quads = vec![[0, 1, 4, 3], [0, 3, 5, 2]];
        m
    }

    #[test]
    fn a_corner_under_twice_the_lower_corner_is_crowded_by_two_elements() {
        for (corner, crowded) in [(80.0, vec![(0, 2)]), (100.0, vec![])] {
            let mut m = two_elements_at_a_corner(corner);
            let w = Working::new(&mut m, ElementBounds::default());
            assert_eq!(w.crowded_corners(&[0, 1]), crowded, "a corner of {corner}");
        }
    }

    #[test]
    fn a_lone_element_at_a_bent_boundary_node_gets_a_neighbour_by_a_split() {
        let mut m = hexagon_with_a_lone_bent_corner();
        let area = m.area();
        assert!(worst_corner(&m) >= 14.9, "{}", worst_corner(&m));
        let (stats, touched) = clean_up(&mut m, None, &ElementBounds::default());
        assert_eq!((stats.flips, stats.collapses, stats.splits), (0, 0, 1));
        assert!(!touched.is_empty());
        assert_eq!((m.quads.len(), m.nodes.len()), (3, 7));
        assert_eq!(m.kinds[6], NodeKind::Interior);
        // nodes 1 and 5 have two elements each, the new node three
        let at = |n: u32| m.quads.iter().filter(|q| q.contains(&n)).count();
        assert_eq!((at(1), at(5), at(6)), (2, 2, 3));
        assert!(worst_corner(&m) <= 0.0, "{}", worst_corner(&m));
        assert!((m.area() - area).abs() < 1e-9);
        crate::report::check::check_mesh(&m, area).unwrap();
    }

    #[test]
    fn two_lone_elements_at_bent_boundary_nodes_get_neighbours_by_a_split_into_four() {
        let mut m = hexagon_with_two_lone_bent_corners();
        let area = m.area();
        assert!(worst_corner(&m) >= 4.9, "{}", worst_corner(&m));
        let (stats, _) = clean_up(&mut m, None, &ElementBounds::default());
        assert_eq!((stats.flips, stats.collapses, stats.splits), (0, 0, 1));
        assert_eq!((m.quads.len(), m.nodes.len()), (4, 8));
        // nodes 1, 2, 4 and 5 have two elements each, the new nodes three
        let at = |n: u32| m.quads.iter().filter(|q| q.contains(&n)).count();
        let counts: Vec<usize> = (0..8).map(at).collect();
        assert_eq!(counts, [1, 2, 2, 1, 2, 2, 3, 3]);
        assert!(worst_corner(&m) <= 0.0, "{}", worst_corner(&m));
        assert!((m.area() - area).abs() < 1e-9);
        crate::report::check::check_mesh(&m, area).unwrap();
        // never with bound(split_into_four, 0): the corner of 140 stays
        let mut m = hexagon_with_two_lone_bent_corners();
        let never = ElementBounds::default().with_split_into_four(0.0).unwrap();
        let (stats, _) = clean_up(&mut m, None, &never);
        assert_eq!((stats.splits, m.quads.len()), (0, 2));
        assert!(worst_corner(&m) >= 4.9, "{}", worst_corner(&m));
    }

    #[test]
    fn changes_judged_on_two_threads_are_the_changes_judged_on_one() {
        // a 30 x 30 grid, its inner nodes pushed hard: many bad elements,
        // some of them with every change judged
        let (m, _) = crate::smoothing::tests::pushed_grid(30, 0.45);
        let (mut one, mut two) = (m.clone(), m.clone());
        let (s1, t1) = clean_up_on(&mut one, None, false, &ElementBounds::default());
        let (s2, t2) = clean_up_on(&mut two, None, true, &ElementBounds::default());
        assert!(s1.flips + s1.collapses > 0);
        assert_eq!((s1.flips, s1.collapses, t1), (s2.flips, s2.collapses, t2));
        assert_eq!(one.quads, two.quads);
        assert_eq!(one.nodes, two.nodes);
    }

    #[test]
    fn a_bad_split_is_flipped_unless_its_edge_is_an_input_line() {
        let mut m = badly_split_hexagon();
        let area = m.area();
        assert!(worst_corner(&m) > 10.0);
        let (stats, _) = clean_up(&mut m, None, &ElementBounds::default());
        assert_eq!((stats.flips, stats.collapses), (1, 0));
        assert!(worst_corner(&m) <= 0.0, "{}", worst_corner(&m));
        assert!((m.area() - area).abs() < 1e-12);
        let mut diagonals: Vec<(u32, u32)> = m
            .quads
            .iter()
            .flat_map(|q| (0..4).map(move |i| (q[i].min(q[(i + 1) % 4]), q[i].max(q[(i + 1) % 4]))))
            .filter(|&(a, b)| b - a == 3)
            .collect();
        diagonals.dedup();
        assert_eq!(diagonals, vec![(2, 5)]);
        // the same with the diagonal 0-3 an inner line: it stays
        let mut m = badly_split_hexagon();
        m.boundary.push(BoundaryEdge {
            a: 0,
            b: 3,
            group: 1,
            tag: None,
        });
        let (stats, _) = clean_up(&mut m, None, &ElementBounds::default());
        assert_eq!(stats.flips, 0);
        assert_eq!(m.quads, vec![[0, 1, 2, 3], [3, 4, 5, 0]]);
    }

    /// Three by three unit squares (nodes 0..16), the middle element made
    /// a sliver by pulling two of its free corners together.
    fn grid_with_sliver() -> Mesh {
        let mut m = crate::mesh::three_by_three();
        // the middle element: corners 5, 6, 10, 9; 5 and 10 pulled together
        m.nodes[5] = DVec2::new(1.45, 1.45);
        m.nodes[10] = DVec2::new(1.55, 1.55);
        m
    }

    #[test]
    fn the_clean_up_never_makes_a_corner_worse_nor_breaks_the_mesh() {
        // the grid's four free nodes pushed about, a fixed sequence
        let mut next = noise(7);
        let (mut tried, mut changed) = (0, 0);
        for _ in 0..40 {
            let mut m = grid_with_sliver();
            for n in [5usize, 6, 9, 10] {
                let home = DVec2::new((n % 4) as f64, (n / 4) as f64);
                m.nodes[n] = home + DVec2::new(next(), next()) * 0.8;
            }
            let convex = |q: usize| {
                let p = m.quad_points(q);
                (0..4)
                    .all(|i| crate::geometry::orient2d(p[i], p[(i + 1) % 4], p[(i + 2) % 4]) > 0.0)
            };
            if !(0..m.quads.len()).all(convex) {
                continue;
            }
            let area = m.area();
            let corner_before = worst_corner(&m).max(0.0);
            let (stats, _) = clean_up(&mut m, None, &ElementBounds::default());
            tried += 1;
            changed += usize::from(stats.flips + stats.collapses > 0);
            crate::report::check::check_mesh(&m, area).unwrap();
            assert!(worst_corner(&m).max(0.0) <= corner_before + 1e-9);
        }
        // the cases are varied enough to make it work
        assert!(
            tried >= 20 && changed >= 3,
            "{tried} tried, {changed} changed"
        );
    }

    #[test]
    fn a_sliver_is_cleaned_up_keeping_the_area_and_the_boundary() {
        let mut m = grid_with_sliver();
        let area = m.area();
        let before = worst_corner(&m);
        assert!(before > 30.0, "a sliver: {before}");
        let boundary: Vec<DVec2> = (0..16)
            .filter(|&i| m.kinds[i] == NodeKind::Boundary)
            .map(|i| m.nodes[i])
            .collect();
        let (stats, touched) = clean_up(&mut m, None, &ElementBounds::default());
        assert!(stats.flips + stats.collapses > 0);
        assert!(!touched.is_empty());
        assert!(worst_corner(&m) < before - 0.5);
        assert!((m.area() - area).abs() < 1e-9);
        let after: Vec<DVec2> = (0..16)
            .filter(|&i| m.kinds[i] == NodeKind::Boundary)
            .map(|i| m.nodes[i])
            .collect();
        assert_eq!(after, boundary);
        crate::report::check::check_mesh(&m, area).unwrap();
    }
}
