//! Laplace smoothing (Eq. 4), guarded so that it never spoils an element.
//!
//! Each free node moves to the mean, over the elements round it, of its two
//! neighbours in each element: X_i = 1/(2 N_i) Σ (X_nj + X_ni). A move is
//! kept only if every element round the node stays convex and its worst
//! corner gets no worse than a bound; input boundary nodes never move.

use glam::DVec2;

use crate::geometry::{interior_angle, orient2d};
use crate::mesh::{Mesh, NodeKind};

/// For each node, the elements that use it and the node's corner index.
pub fn node_elements(mesh: &Mesh) -> Vec<Vec<(u32, u8)>> {
    let mut out = vec![Vec::new(); mesh.nodes.len()];
    for (qi, q) in mesh.quads.iter().enumerate() {
        for (c, &n) in q.iter().enumerate() {
            out[n as usize].push((qi as u32, c as u8));
        }
    }
    out
}

/// How far an element's worst corner is from the [45, 135] window
/// (degrees; 0 inside it), or infinity if the element is not convex.
fn badness(q: [DVec2; 4]) -> f64 {
    for i in 0..4 {
        if orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) <= 0.0 {
            return f64::INFINITY;
        }
    }
    // Most elements have every corner inside the window: |cos| <= cos 45
    // at each, tested without trigonometry.
    let inside = (0..4).all(|i| {
        let a = q[(i + 1) % 4] - q[i];
        let b = q[(i + 3) % 4] - q[i];
        let d = a.dot(b);
        2.0 * d * d <= a.length_squared() * b.length_squared()
    });
    if inside {
        return 0.0;
    }
    worst_excess(q)
}

/// The angle of corner `i` of an element in degrees, as `quad_angles`
/// measures it, or None when the corner is clearly inside [45, 135]:
/// told without trigonometry, with a margin so that the answer is the
/// same as measuring it.
fn angle_unless_inside(q: &[DVec2; 4], i: usize) -> Option<f64> {
    let a = q[(i + 1) % 4] - q[i];
    let b = q[(i + 3) % 4] - q[i];
    let d = a.dot(b);
    if a.perp_dot(b) > 0.0 && 2.0 * d * d < (1.0 - 1e-9) * a.length_squared() * b.length_squared() {
        return None;
    }
    Some(interior_angle(q[(i + 3) % 4], q[i], q[(i + 1) % 4]).to_degrees())
}

/// How far the worst corner of an element is past [45, 135] (degrees).
fn worst_excess(q: [DVec2; 4]) -> f64 {
    (0..4)
        .filter_map(|i| angle_unless_inside(&q, i))
        .map(|a| (45.0 - a).max(a - 135.0).max(0.0))
        .fold(0.0, f64::max)
}

/// Whether a sweep looks at node `n`: a free node of some element, marked
/// dirty since it was last looked at (the mark is taken). A node none of
/// whose elements changed since then would come out the same.
fn take_free_dirty(mesh: &Mesh, nodes: &Nodes, dirty: &mut [bool], n: usize) -> bool {
    std::mem::take(&mut dirty[n])
        && mesh.kinds[n] == NodeKind::Interior
        && !nodes.around[n].is_empty()
}

/// What a sweep works on: each node's elements, and the nodes it visits
/// (in ascending order; it moves no other).
struct Nodes<'a> {
    around: &'a [Vec<(u32, u8)>],
    visit: &'a [u32],
}

/// Meshes with fewer nodes are smoothed on one thread.
const SPLIT_FROM_NODES: usize = 20_000;

/// A large mesh is cut into this many strips across x.
const STRIPS: usize = 8;

/// How many rings of elements either side of a seam its sweep may move.
const SEAM_BAND: usize = 3;

/// Runs a sweep over every free node; a large mesh on several threads.
///
/// The nodes are cut into strips by x. A strip is swept without its nodes
/// at a seam (those sharing an element with another strip), so no strip
/// moves a node another one reads; the threads take strips in turn, each
/// on its own copy of the mesh, every strip from the mesh as it was. Then
/// the seams are swept, within a band of a few elements, the bands far
/// enough apart that neither reads the other's moves side by side. The
/// strips and bands depend on the mesh alone, and each comes out the same
/// whichever thread sweeps it, so the result is the same on any machine.
/// Returns the moves kept.
fn sweep_in_strips(
    mesh: &mut Mesh,
    around: Vec<Vec<(u32, u8)>>,
    sweep: impl Fn(&mut Mesh, &Nodes, &mut [bool]) -> usize + Sync,
) -> usize {
    let threads = std::thread::available_parallelism()
        .map_or(1, |c| c.get())
        .clamp(1, 4);
    sweep_in_strips_on(mesh, around, threads, sweep)
}

/// `sweep_in_strips` on this many threads.
fn sweep_in_strips_on(
    mesh: &mut Mesh,
    around: Vec<Vec<(u32, u8)>>,
    threads: usize,
    sweep: impl Fn(&mut Mesh, &Nodes, &mut [bool]) -> usize + Sync,
) -> usize {
    let n = mesh.nodes.len();
    if n < SPLIT_FROM_NODES {
        let all: Vec<u32> = (0..n as u32).collect();
        let mut dirty = vec![true; n];
        let nodes = Nodes {
            around: &around,
            visit: &all,
        };
        return sweep(mesh, &nodes, &mut dirty);
    }
    let mut by_x: Vec<u32> = (0..n as u32).collect();
    by_x.sort_by(|&a, &b| {
        mesh.nodes[a as usize]
            .x
            .total_cmp(&mesh.nodes[b as usize].x)
            .then(a.cmp(&b))
    });
    let mut strip = vec![0usize; n];
    for (rank, &i) in by_x.iter().enumerate() {
        strip[i as usize] = rank * STRIPS / n;
    }
    let at_seam = |i: usize| {
        around[i].iter().any(|&(q, _)| {
            mesh.quads[q as usize]
                .iter()
                .any(|&m| strip[m as usize] != strip[i])
        })
    };
    let seam: Vec<bool> = (0..n).map(at_seam).collect();
    let mut inner: Vec<Vec<u32>> = vec![Vec::new(); STRIPS];
    for i in (0..n).filter(|&i| !seam[i]) {
        inner[strip[i]].push(i as u32);
    }
    let all_dirty = vec![true; n];
    let moved = sweep_groups(mesh, &around, &inner, &all_dirty, threads, &sweep);
    // the seams are left, swept within a band of a few elements either
    // side (a settling move there need not ripple across the mesh)
    let mut band = seam.clone();
    for _ in 0..SEAM_BAND {
        band = (0..n)
            .map(|i| {
                band[i]
                    || around[i]
                        .iter()
                        .any(|&(q, _)| mesh.quads[q as usize].iter().any(|&m| band[m as usize]))
            })
            .collect();
    }
    // bands far apart cannot read each other's moves: swept side by side,
    // they come out as swept together
    let bands = apart_groups(mesh, &around, &band, BANDS_APART);
    moved + sweep_groups(mesh, &around, &bands, &seam, threads, &sweep)
}

/// How many node steps from a band a sweep there may read or mark (the
/// size evening reads areas two elements out, three steps): bands more
/// than twice this apart are swept apart.
const BANDS_APART: usize = 4;

/// The nodes marked in `marked`, in ascending order, grouped so that two
/// nodes at most `2 * reach` steps apart (a step: to a corner of an
/// element at the node) are in one group; the groups ordered by their
/// first node.
fn apart_groups(
    mesh: &Mesh,
    around: &[Vec<(u32, u8)>],
    marked: &[bool],
    reach: usize,
) -> Vec<Vec<u32>> {
    let n = marked.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    // every node reached within `reach` steps of a marked one takes the
    // group of the first to reach it; two groups meeting are joined
    let mut owner: Vec<u32> = (0..n as u32)
        .map(|i| if marked[i as usize] { i } else { u32::MAX })
        .collect();
    let mut frontier: Vec<u32> = (0..n as u32).filter(|&i| marked[i as usize]).collect();
    for _ in 0..reach {
        let mut next = Vec::new();
        for &u in &frontier {
            for &(q, _) in &around[u as usize] {
                for v in mesh.quads[q as usize] {
                    let o = owner[v as usize];
                    if o == u32::MAX {
                        owner[v as usize] = owner[u as usize];
                        next.push(v);
                    } else {
                        let (a, b) = (root(&mut parent, o), root(&mut parent, owner[u as usize]));
                        parent[a.max(b) as usize] = a.min(b);
                    }
                }
            }
        }
        frontier = next;
    }
    let mut groups: Vec<Vec<u32>> = Vec::new();
    let mut index: rustc_hash::FxHashMap<u32, usize> = Default::default();
    for i in (0..n as u32).filter(|&i| marked[i as usize]) {
        let r = root(&mut parent, i);
        let g = *index.entry(r).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(i);
    }
    groups
}

/// Sweeps each group of nodes, the threads taking groups in turn, each
/// group from the mesh as it was and from the dirty marks of
/// `dirty_at_start`; the groups' nodes are then written back. Returns
/// the moves kept.
fn sweep_groups(
    mesh: &mut Mesh,
    around: &[Vec<(u32, u8)>],
    groups: &[Vec<u32>],
    dirty_at_start: &[bool],
    threads: usize,
    sweep: &(impl Fn(&mut Mesh, &Nodes, &mut [bool]) -> usize + Sync),
) -> usize {
    let n = mesh.nodes.len();
    if groups.is_empty() {
        return 0;
    }
    if groups.len() == 1 {
        let mut dirty = dirty_at_start.to_vec();
        let nodes = Nodes {
            around,
            visit: &groups[0],
        };
        return sweep(mesh, &nodes, &mut dirty);
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    // sweeps groups as they come, each from the mesh as it was (so that
    // what a group reads outside it is the same whichever groups the
    // thread swept before); the places its nodes went, and the moves kept
    let original = &*mesh;
    let work = || {
        let mut m = original.clone();
        let mut dirty = vec![false; n];
        let mut placed: Vec<(u32, DVec2)> = Vec::new();
        let mut moved = 0;
        loop {
            let s = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let Some(visit) = groups.get(s) else {
                return (placed, moved);
            };
            for &i in visit {
                dirty[i as usize] = dirty_at_start[i as usize];
            }
            moved += sweep(&mut m, &Nodes { around, visit }, &mut dirty);
            for &i in visit {
                placed.push((i, m.nodes[i as usize]));
                m.nodes[i as usize] = original.nodes[i as usize];
            }
        }
    };
    let results: Vec<(Vec<(u32, DVec2)>, usize)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (1..threads.min(groups.len()))
            .map(|_| scope.spawn(work))
            .collect();
        let mine = work();
        // a sweep that panicked is a defect: let it surface as one
        std::iter::once(mine)
            .chain(
                handles
                    .into_iter()
                    .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))),
            )
            .collect()
    });
    let mut moved = 0;
    for (placed, m) in results {
        moved += m;
        for (i, p) in placed {
            mesh.nodes[i as usize] = p;
        }
    }
    moved
}

/// Marks every node of these elements dirty: a sweep looks at them again.
fn mark_nodes(mesh: &Mesh, quads: impl Iterator<Item = u32>, dirty: &mut [bool]) {
    for q in quads {
        for m in mesh.quads[q as usize] {
            dirty[m as usize] = true;
        }
    }
}

/// The smoothing stage: `laplace_passes` sweeps of guarded Laplace, then
/// the angle clean-up and the evening out of sizes, 10 sweeps each; a
/// large mesh strip by strip (see `sweep_in_strips`), all three on a strip
/// before the next. Returns the moves kept.
pub fn smooth(mesh: &mut Mesh, laplace_passes: usize) -> usize {
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    sweep_in_strips(mesh, around, |mesh, nodes, dirty| {
        all_sweeps(mesh, [laplace_passes, 10], nodes, &neighbours, dirty)
    })
}

/// The smoothing stage again, on the nodes within a few elements of
/// `near` only: after a change there, the rest is as it was.
pub fn smooth_near(mesh: &mut Mesh, laplace_passes: usize, near: &[u32]) -> usize {
    let around = node_elements(mesh);
    let mut band = vec![false; mesh.nodes.len()];
    let mut visit: Vec<u32> = near.to_vec();
    for &n in near {
        band[n as usize] = true;
    }
    for _ in 0..2 {
        let ring: Vec<u32> = visit
            .iter()
            .flat_map(|&n| {
                around[n as usize]
                    .iter()
                    .flat_map(|&(q, _)| mesh.quads[q as usize])
            })
            .filter(|&m| !band[m as usize])
            .collect();
        for &m in &ring {
            band[m as usize] = true;
        }
        visit.extend(ring);
    }
    visit.sort_unstable();
    visit.dedup();
    // the neighbours of the elements the sweeps look at, and of theirs
    let mut neighbours = vec![[None; 4]; mesh.quads.len()];
    let mut quads: Vec<u32> = visit
        .iter()
        .flat_map(|&n| around[n as usize].iter().map(|&(q, _)| q))
        .collect();
    for _ in 0..2 {
        let mut more = Vec::new();
        for &q in &quads {
            let quad = mesh.quads[q as usize];
            let nb: [Option<u32>; 4] =
                std::array::from_fn(|i| across(mesh, &around, quad[i], quad[(i + 1) % 4]));
            more.extend(nb.iter().flatten());
            neighbours[q as usize] = nb;
        }
        quads = more;
    }
    let nodes = Nodes {
        around: &around,
        visit: &visit,
    };
    let mut dirty = band;
    all_sweeps(mesh, [laplace_passes, 4], &nodes, &neighbours, &mut dirty)
}

/// The three sweeps of the stage in turn over `nodes`, each from the
/// nodes marked dirty at the start: `passes` of Laplace, then of each of
/// the others.
fn all_sweeps(
    mesh: &mut Mesh,
    [laplace_passes, passes]: [usize; 2],
    nodes: &Nodes,
    neighbours: &[[Option<u32>; 4]],
    dirty: &mut [bool],
) -> usize {
    let start: Vec<bool> = nodes.visit.iter().map(|&i| dirty[i as usize]).collect();
    let restart = |dirty: &mut [bool]| {
        for (&i, &d) in nodes.visit.iter().zip(&start) {
            dirty[i as usize] = d;
        }
    };
    let mut moved = laplace_sweeps(mesh, laplace_passes, nodes, dirty);
    restart(dirty);
    moved += untangle_sweeps(mesh, passes, nodes, dirty);
    restart(dirty);
    moved + even_out_sweeps(mesh, passes, nodes, neighbours, dirty)
}

/// `passes` sweeps of guarded Laplace smoothing; returns how many moves
/// were kept in the last sweep.
pub fn laplace(mesh: &mut Mesh, passes: usize) -> usize {
    sweep_in_strips(mesh, node_elements(mesh), |mesh, nodes, dirty| {
        laplace_sweeps(mesh, passes, nodes, dirty)
    })
}

fn laplace_sweeps(mesh: &mut Mesh, passes: usize, nodes: &Nodes, dirty: &mut [bool]) -> usize {
    let around = nodes.around;
    // only dirty nodes are looked at: the same mesh as looking at all
    let mut kept = 0;
    for _ in 0..passes {
        kept = 0;
        for &n in nodes.visit {
            let n = n as usize;
            if !take_free_dirty(mesh, nodes, dirty, n) {
                continue;
            }
            // Eq. 4: the two neighbours of n in each of its elements
            let mut sum = DVec2::ZERO;
            for &(q, c) in &around[n] {
                let quad = mesh.quads[q as usize];
                sum += mesh.nodes[quad[(c as usize + 1) % 4] as usize]
                    + mesh.nodes[quad[(c as usize + 3) % 4] as usize];
            }
            let target = sum / (2.0 * around[n].len() as f64);
            let old = mesh.nodes[n];
            // settled: a move under a thousandth of an element's edge is
            // not worth the checks (and sweeps stop where all are settled)
            let (q0, c0) = around[n][0];
            let edge = mesh.nodes[mesh.quads[q0 as usize][(c0 as usize + 1) % 4] as usize] - old;
            if (target - old).length_squared() <= 1e-6 * edge.length_squared() {
                continue;
            }
            let before = around[n]
                .iter()
                .map(|&(q, _)| badness(mesh.quad_points(q as usize)))
                .fold(0.0, f64::max);
            // try the full move, then half of it
            for t in [1.0, 0.5] {
                mesh.nodes[n] = old + (target - old) * t;
                let after = around[n]
                    .iter()
                    .map(|&(q, _)| badness(mesh.quad_points(q as usize)))
                    .fold(0.0, f64::max);
                if after.is_finite() && after <= before.max(0.0) + 1e-9 {
                    kept += 1;
                    mark_nodes(mesh, around[n].iter().map(|&(q, _)| q), dirty);
                    // after half a move the target is still ahead
                    dirty[n] = t < 1.0;
                    break;
                }
                mesh.nodes[n] = old;
            }
        }
    }
    kept
}

/// An element's `badness` and its scaled Jacobian (smallest sine of a
/// corner) together, the edge vectors worked out once: the same numbers
/// as the two functions apart. None if the element is not convex.
fn badness_and_sine(q: [DVec2; 4]) -> Option<(f64, f64)> {
    for i in 0..4 {
        if orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) <= 0.0 {
            return None;
        }
    }
    let e: [DVec2; 4] = std::array::from_fn(|i| q[(i + 1) % 4] - q[i]);
    let unit = e.map(DVec2::normalize_or_zero);
    let mut inside = true;
    let mut min_sin = f64::INFINITY;
    for i in 0..4 {
        // corner i between e[i] and the reversed e[i - 1]
        let (a, b) = (e[i], -e[(i + 3) % 4]);
        let d = a.dot(b);
        inside &= 2.0 * d * d <= a.length_squared() * b.length_squared();
        min_sin = min_sin.min(unit[i].perp_dot(-unit[(i + 3) % 4]));
    }
    let bad = if inside { 0.0 } else { worst_excess(q) };
    Some((bad, min_sin))
}

/// Minus the smallest sine of a corner of the elements round a node
/// (infinite if one is not convex): the same order as `worst_around`
/// (the corner farthest from a right angle has the smallest sine), for
/// a fraction of its cost.
pub(crate) fn sine_worst_around(mesh: &Mesh, around: &[(u32, u8)]) -> f64 {
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        match convex_scaled_jacobian(mesh.quad_points(q as usize)) {
            Some(s) => min_sin = min_sin.min(s),
            None => return f64::INFINITY,
        }
    }
    -min_sin
}

/// The smallest sine of a corner of a convex element, None if it is not
/// convex (plain arithmetic: for comparing places, not for the check).
fn convex_scaled_jacobian(q: [DVec2; 4]) -> Option<f64> {
    let e: [DVec2; 4] = std::array::from_fn(|i| q[(i + 1) % 4] - q[i]);
    let inv = e.map(|v| 1.0 / v.length());
    let mut min_sin = f64::INFINITY;
    for i in 0..4 {
        let j = (i + 3) % 4;
        // corner i, between e[i] and e[j] reversed
        let cross = e[j].perp_dot(e[i]);
        if !(cross > 0.0) {
            return None;
        }
        min_sin = min_sin.min(cross * inv[i] * inv[j]);
    }
    Some(min_sin)
}

/// The worst corner of the elements round a node: (badness, -smallest
/// sine of a corner), smaller is better; infinite if one is not convex.
pub(crate) fn worst_around(mesh: &Mesh, around: &[(u32, u8)]) -> (f64, f64) {
    let mut bad: f64 = 0.0;
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        let Some((b, s)) = badness_and_sine(mesh.quad_points(q as usize)) else {
            return (f64::INFINITY, f64::INFINITY);
        };
        bad = bad.max(b);
        min_sin = min_sin.min(s);
    }
    (bad, -min_sin)
}

/// `worst_around` if it is better (smaller) than `best`, else None: the
/// elements are judged one by one and the search gives up on a place at
/// the first that shows it no better (both parts only grow).
pub(crate) fn worst_around_under(
    mesh: &Mesh,
    around: &[(u32, u8)],
    best: (f64, f64),
) -> Option<(f64, f64)> {
    let mut bad: f64 = 0.0;
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        let (b, s) = badness_and_sine(mesh.quad_points(q as usize))?;
        bad = bad.max(b);
        min_sin = min_sin.min(s);
        if !((bad, -min_sin) < best) {
            return None;
        }
    }
    Some((bad, -min_sin))
}

/// `sine_worst_around` if it is smaller than `best`, else None (judged
/// element by element, as `worst_around_under`).
pub(crate) fn sine_worst_around_under(mesh: &Mesh, around: &[(u32, u8)], best: f64) -> Option<f64> {
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        min_sin = min_sin.min(convex_scaled_jacobian(mesh.quad_points(q as usize))?);
        if !(-min_sin < best) {
            return None;
        }
    }
    Some(-min_sin)
}

/// True when every corner of the elements round a node has a sine above
/// 0.8 (between 53 and 127 degrees, so convex and inside [45, 135]):
/// the common case, told without trigonometry.
fn corners_fine(mesh: &Mesh, around: &[(u32, u8)]) -> bool {
    around.iter().all(|&(q, _)| {
        let p = mesh.quad_points(q as usize);
        (0..4).all(|i| {
            let a = p[(i + 1) % 4] - p[i];
            let b = p[(i + 3) % 4] - p[i];
            let d = a.dot(b);
            a.perp_dot(b) > 0.0 && d * d < 0.36 * a.length_squared() * b.length_squared()
        })
    })
}

/// Moves each free node next to an element with a corner outside
/// [45, 135] to the place, found by a compass search, where the worst
/// corner round it is best; `passes` sweeps. Never makes an element worse
/// than it was, never inverts one. Returns the moves kept.
pub fn untangle_angles(mesh: &mut Mesh, passes: usize) -> usize {
    sweep_in_strips(mesh, node_elements(mesh), |mesh, nodes, dirty| {
        untangle_sweeps(mesh, passes, nodes, dirty)
    })
}

fn untangle_sweeps(mesh: &mut Mesh, passes: usize, nodes: &Nodes, dirty: &mut [bool]) -> usize {
    let around = nodes.around;
    let mut moved = 0;
    for _ in 0..passes {
        let mut any = false;
        for &n in nodes.visit {
            let n = n as usize;
            if !take_free_dirty(mesh, nodes, dirty, n) {
                continue;
            }
            if corners_fine(mesh, &around[n]) {
                continue;
            }
            let start = worst_around(mesh, &around[n]);
            if start.0 == 0.0 && start.1 < -0.8 {
                continue; // every corner round it is fine
            }
            let old = mesh.nodes[n];
            let best = compass_search(
                mesh,
                n,
                &around[n],
                start,
                |m, best| worst_around_under(m, &around[n], best),
                |w, best| w < best,
            );
            mesh.nodes[n] = best;
            if best != old {
                moved += 1;
                any = true;
                mark_nodes(mesh, around[n].iter().map(|&(q, _)| q), dirty);
            }
        }
        if !any {
            break;
        }
    }
    moved
}

/// The eight directions of the compass search, a unit step each.
const COMPASS: [DVec2; 8] = {
    let d = std::f64::consts::FRAC_1_SQRT_2;
    [
        DVec2::new(1.0, 0.0),
        DVec2::new(d, d),
        DVec2::new(0.0, 1.0),
        DVec2::new(-d, d),
        DVec2::new(-1.0, 0.0),
        DVec2::new(-d, -d),
        DVec2::new(0.0, -1.0),
        DVec2::new(d, -d),
    ]
};

/// The best place for node `n` by a compass search: the eight directions
/// round the best place so far, six times over, the step halving from a
/// quarter of the shortest edge at the node. `score` judges the node where
/// it is put, given the best score so far (None: not allowed there, or
/// sure to be no better); a place is taken when `better` than the best so
/// far. The node is left where it was.
pub(crate) fn compass_search<S: Copy>(
    mesh: &mut Mesh,
    n: usize,
    around: &[(u32, u8)],
    start: S,
    score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
) -> DVec2 {
    compass_search_steps(mesh, n, around, start, score, better, 6)
}

/// `compass_search` with `steps` halvings of the step instead of six.
pub(crate) fn compass_search_steps<S: Copy>(
    mesh: &mut Mesh,
    n: usize,
    around: &[(u32, u8)],
    start: S,
    score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
    steps: usize,
) -> DVec2 {
    compass_search_together(mesh, &[n], around, start, score, better, steps)
}

/// `compass_search_steps` moving the nodes `ns` together, each by the
/// same displacement; `around` holds their elements. Returns the best
/// place of the first; the others keep their offsets from it.
fn compass_search_together<S: Copy>(
    mesh: &mut Mesh,
    ns: &[usize],
    around: &[(u32, u8)],
    start: S,
    mut score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
    steps: usize,
) -> DVec2 {
    let olds: Vec<DVec2> = ns.iter().map(|&n| mesh.nodes[n]).collect();
    let (first, old) = (ns[0], olds[0]);
    let h = around
        .iter()
        .map(|&(q, c)| {
            let quad = mesh.quads[q as usize];
            let at = mesh.nodes[quad[c as usize] as usize];
            (mesh.nodes[quad[(c as usize + 1) % 4] as usize] - at).length()
        })
        .fold(f64::INFINITY, f64::min);
    let mut best = (start, old);
    let mut step = 0.25 * h;
    for _ in 0..steps {
        let centre = best.1;
        for dir in COMPASS {
            mesh.nodes[first] = centre + dir * step;
            let shift = mesh.nodes[first] - old;
            for (&n, &o) in ns.iter().zip(&olds).skip(1) {
                mesh.nodes[n] = o + shift;
            }
            if let Some(w) = score(mesh, best.0) {
                if better(w, best.0) {
                    best = (w, mesh.nodes[first]);
                }
            }
        }
        step *= 0.5;
    }
    for (&n, &o) in ns.iter().zip(&olds) {
        mesh.nodes[n] = o;
    }
    best.1
}

/// How many corners of the elements round a node are outside [45, 135].
fn corners_outside(mesh: &Mesh, around: &[(u32, u8)]) -> usize {
    around
        .iter()
        .map(|&(q, _)| {
            let p = mesh.quad_points(q as usize);
            (0..4)
                .filter_map(|i| angle_unless_inside(&p, i))
                .filter(|a| !(45.0..=135.0).contains(a))
                .count()
        })
        .sum()
}

/// For each element, the elements across its four edges.
fn element_neighbours(mesh: &Mesh, around: &[Vec<(u32, u8)>]) -> Vec<[Option<u32>; 4]> {
    mesh.quads
        .iter()
        .map(|q| std::array::from_fn(|i| across(mesh, around, q[i], q[(i + 1) % 4])))
        .collect()
}

/// The element with the edge b -> a (the other side of the edge a -> b).
fn across(mesh: &Mesh, around: &[Vec<(u32, u8)>], a: u32, b: u32) -> Option<u32> {
    around[b as usize]
        .iter()
        .find(|&&(o, c)| mesh.quads[o as usize][(c as usize + 1) % 4] == a)
        .map(|&(o, _)| o)
}

/// How far an element is past the paper's bounds on size and shape, as a
/// share of each bound: its size against each neighbour's (factor 2, the
/// square root of the area ratio), its taper and aspect ratio (10). At
/// most 1 when within them. `area` gives each element's area.
fn size_shape_excess(
    mesh: &Mesh,
    q: u32,
    neighbours: &[Option<u32>; 4],
    area: &dyn Fn(u32) -> f64,
) -> f64 {
    let (aspect, taper) = crate::quality::aspect_taper(mesh.quad_points(q as usize));
    let mut worst = (aspect / 10.0).max(taper / 10.0);
    let mine = area(q).max(1e-300);
    for f in neighbours.iter().flatten() {
        let other = area(*f).max(1e-300);
        worst = worst.max((mine / other).max(other / mine).sqrt() / 2.0);
    }
    worst
}

/// Evens out sizes and shapes where they break the paper's bounds: each
/// free node round an element past them moves, by a compass search, to
/// where the worst excess round it is least, without a corner round it
/// leaving [45, 135] further or getting much sharper than it was. Where
/// that leaves an element past a bound, the node moves together with a
/// neighbour (a corner at the window's edge can hold one node, not the
/// edge between two). `passes` sweeps; returns the moves kept.
pub fn even_out_sizes(mesh: &mut Mesh, passes: usize) -> usize {
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    sweep_in_strips(mesh, around, |mesh, nodes, dirty| {
        even_out_sweeps(mesh, passes, nodes, &neighbours, dirty)
    })
}

fn even_out_sweeps(
    mesh: &mut Mesh,
    passes: usize,
    nodes: &Nodes,
    neighbours: &[[Option<u32>; 4]],
    dirty: &mut [bool],
) -> usize {
    let around = nodes.around;
    let mut area: Vec<f64> = (0..mesh.quads.len() as u32)
        .map(|q| quad_area(mesh, q))
        .collect();
    let mut moved = 0;
    for _ in 0..passes {
        let mut any = false;
        for &n in nodes.visit {
            let n = n as usize;
            if !take_free_dirty(mesh, nodes, dirty, n) {
                continue;
            }
            let own = excess_round(mesh, &area, neighbours, &around[n]);
            if own <= 0.95 {
                continue; // moving n could only make its elements worse
            }
            let mut moved_nodes = Vec::new();
            let left = match even_out_move(mesh, &[n], &around[n], &area, neighbours) {
                Some(left) => {
                    moved_nodes.push(n);
                    left
                }
                None => own,
            };
            if left > 1.0 {
                // still past a bound: n is held by a corner at the edge
                // of the window; try it with a neighbour, both moving
                // together (an edge of the element shifted)
                if let Some(m) = even_out_pair(mesh, n, nodes, &area, neighbours) {
                    moved_nodes.extend([n, m]);
                }
            }
            for k in moved_nodes {
                moved += 1;
                any = true;
                // the neighbours' size ratios changed with these
                for &(q, _) in &around[k] {
                    area[q as usize] = quad_area(mesh, q);
                    let touched =
                        std::iter::once(q).chain(neighbours[q as usize].iter().flatten().copied());
                    mark_nodes(mesh, touched, dirty);
                }
            }
        }
        if !any {
            break;
        }
    }
    moved
}

fn quad_area(mesh: &Mesh, q: u32) -> f64 {
    crate::geometry::polygon_area(&mesh.quad_points(q as usize)).abs()
}

/// The size and shape excess of the elements of `region` (measured
/// afresh), against their neighbours too: all that moving the nodes the
/// region is round changes. `area` holds every other element's area.
fn excess_round(
    mesh: &Mesh,
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
    region: &[(u32, u8)],
) -> f64 {
    excess_round_under(mesh, area, neighbours, region, f64::INFINITY).unwrap_or(f64::INFINITY)
}

/// The region's areas measured once an evaluation (a region is rarely
/// larger; past this its areas are measured as they are asked for).
const REGION_AREAS: usize = 24;

/// `excess_round` if it is below `bound`, else None: the elements are
/// judged one by one and the first at or past the bound ends it (most
/// places a search tries are no better, and one element shows it).
fn excess_round_under(
    mesh: &Mesh,
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
    region: &[(u32, u8)],
    bound: f64,
) -> Option<f64> {
    let mut fresh = [0.0; REGION_AREAS];
    for (slot, &(q, _)) in fresh.iter_mut().zip(region) {
        *slot = quad_area(mesh, q);
    }
    let area_of = |q: u32| match region.iter().position(|x| x.0 == q) {
        Some(i) if i < REGION_AREAS => fresh[i],
        Some(_) => quad_area(mesh, q),
        None => area[q as usize],
    };
    let mut worst = 0.0;
    for &(q, _) in region {
        let e = size_shape_excess(mesh, q, &neighbours[q as usize], &area_of);
        if e >= bound {
            return None;
        }
        worst = f64::max(worst, e);
    }
    (worst < bound).then_some(worst)
}

/// Moves the nodes `ns` together to where the size and shape excess of
/// their elements (`region`) is least, without a corner there leaving
/// [45, 135] further or getting much sharper than it was. Returns the
/// excess left if they moved.
fn even_out_move(
    mesh: &mut Mesh,
    ns: &[usize],
    region: &[(u32, u8)],
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
) -> Option<f64> {
    let inside = |f: &u32| region.iter().any(|&(q, _)| q == *f);
    // what moving them cannot change: the shapes of the elements next to
    // the region, and their sizes against elements outside it
    let fixed = region
        .iter()
        .flat_map(|&(q, _)| neighbours[q as usize].iter().flatten().copied())
        .filter(|f| !inside(f))
        .map(|f| {
            let others = neighbours[f as usize].map(|g| g.filter(|g| !inside(g)));
            size_shape_excess(mesh, f, &others, &|q| area[q as usize])
        })
        .fold(0.0, f64::max);
    let start_excess = excess_round(mesh, area, neighbours, region).max(fixed);
    if fixed >= start_excess - 1e-6 {
        return None; // the worst is out of reach: no place does better
    }
    let start = worst_around(mesh, region);
    let start_outside = corners_outside(mesh, region);
    let min_sin = (-start.1).min(0.6);
    let olds: Vec<DVec2> = ns.iter().map(|&n| mesh.nodes[n]).collect();
    let best = compass_search_together(
        mesh,
        ns,
        region,
        start_excess,
        |m, best| {
            // the excess first: most places are no better, and the
            // corners need not be looked at there
            let e = excess_round_under(m, area, neighbours, region, best - 1e-6)?.max(fixed);
            if e >= best - 1e-6 {
                return None;
            }
            let w = worst_around(m, region);
            let allowed = w.0 <= start.0 + 1e-9
                && -w.1 >= min_sin
                && corners_outside(m, region) <= start_outside;
            allowed.then_some(e)
        },
        |e, best| e < best - 1e-6,
        6,
    );
    if best == olds[0] {
        return None;
    }
    for (&n, &o) in ns.iter().zip(&olds) {
        mesh.nodes[n] = o + (best - olds[0]);
    }
    Some(excess_round(mesh, area, neighbours, region))
}

/// Makes the best joint move of node `n` with one of the free nodes it
/// shares an edge with (one the sweep may move), if one does better. The
/// first partner wins a tie. Returns the partner.
fn even_out_pair(
    mesh: &mut Mesh,
    n: usize,
    nodes: &Nodes,
    area: &[f64],
    neighbours: &[[Option<u32>; 4]],
) -> Option<usize> {
    let around = nodes.around;
    let mut partners: Vec<usize> = around[n]
        .iter()
        .map(|&(q, c)| mesh.quads[q as usize][(c as usize + 1) % 4] as usize)
        .filter(|&m| {
            mesh.kinds[m] == NodeKind::Interior && nodes.visit.binary_search(&(m as u32)).is_ok()
        })
        .collect();
    partners.sort_unstable();
    partners.dedup();
    let at_n = mesh.nodes[n];
    // (partner, excess left, where the two went)
    let mut best: Option<(usize, f64, [DVec2; 2])> = None;
    for m in partners {
        let at_m = mesh.nodes[m];
        let mut region = around[n].clone();
        region.extend(
            around[m]
                .iter()
                .filter(|x| !around[n].iter().any(|y| y.0 == x.0)),
        );
        if let Some(left) = even_out_move(mesh, &[n, m], &region, area, neighbours) {
            if best.is_none_or(|b| left < b.1 - 1e-6) {
                best = Some((m, left, [mesh.nodes[n], mesh.nodes[m]]));
            }
            mesh.nodes[n] = at_n;
            mesh.nodes[m] = at_m;
        }
    }
    let (m, _, [pn, pm]) = best?;
    mesh.nodes[n] = pn;
    mesh.nodes[m] = pm;
    Some(m)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::quad_angles;

    /// Four unit squares round one free centre node (id 4).
    fn two_by_two_block() -> Mesh {
        let mut m = Mesh::default();
        for y in 0..3 {
            for x in 0..3 {
                let kind = if x == 1 && y == 1 {
                    NodeKind::Interior
                } else {
                    NodeKind::Boundary
                };
                m.add_node(DVec2::new(x as f64, y as f64), kind);
            }
        }
        m.quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        m
    }

    #[test]
    fn centre_node_of_a_two_by_two_block_moves_to_the_middle() {
        let mut m = two_by_two_block();
        m.nodes[4] = DVec2::new(1.3, 0.8);
        laplace(&mut m, 20);
        assert!((m.nodes[4] - DVec2::new(1.0, 1.0)).length() < 1e-6);
    }

    #[test]
    fn compass_search_repairs_a_pinched_corner() {
        let mut m = two_by_two_block();
        m.nodes[4] = DVec2::new(0.6, 0.6); // a corner of 157 deg at the centre
        assert!(untangle_angles(&mut m, 5) > 0);
        let worst = (0..4)
            .flat_map(|q| quad_angles(m.quad_points(q)))
            .fold(0.0, f64::max);
        assert!(worst <= 135.0 + 1e-6, "worst corner {worst}");
    }

    #[test]
    fn a_size_jump_past_two_is_evened_out() {
        let mut m = two_by_two_block();
        m.nodes[4] = DVec2::new(0.2, 0.2); // areas 0.2 and 1.8: a jump of 3
        let jump = |m: &Mesh| {
            let a: Vec<f64> = (0..4)
                .map(|q| crate::geometry::polygon_area(&m.quad_points(q)).abs())
                .collect();
            (a[3] / a[0]).sqrt()
        };
        let worst_corner = |m: &Mesh| {
            (0..4)
                .map(|q| badness(m.quad_points(q)))
                .fold(0.0, f64::max)
        };
        let corner_before = worst_corner(&m);
        assert!(jump(&m) > 2.5);
        assert!(even_out_sizes(&mut m, 5) > 0);
        assert!(jump(&m) <= 2.0 * 0.95 + 1e-9, "jump {}", jump(&m));
        assert!(worst_corner(&m) <= corner_before + 1e-9);
    }

    /// A grid of n x n unit squares, its inner nodes pushed off the grid
    /// by up to `push` (a fixed pseudo-random sequence).
    pub(crate) fn pushed_grid(n: usize, push: f64) -> (Mesh, Vec<DVec2>) {
        let mut m = Mesh::default();
        let mut seed: u64 = 12345;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut grid = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                let p = DVec2::new(x as f64, y as f64);
                grid.push(p);
                let inner = x > 0 && y > 0 && x < n && y < n;
                let kind = if inner {
                    NodeKind::Interior
                } else {
                    NodeKind::Boundary
                };
                let off = if inner {
                    DVec2::new(next(), next()) * push
                } else {
                    DVec2::ZERO
                };
                m.add_node(p + off, kind);
            }
        }
        let id = |x: usize, y: usize| (y * (n + 1) + x) as u32;
        for y in 0..n {
            for x in 0..n {
                m.quads
                    .push([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
        (m, grid)
    }

    #[test]
    fn a_large_mesh_is_smoothed_in_strips_seams_included() {
        let (mut m, grid) = pushed_grid(150, 0.3);
        assert!(m.nodes.len() >= SPLIT_FROM_NODES);
        let off = |m: &Mesh, near_seam: bool| {
            let mid = 75.0;
            let (sum, count) = (0..m.nodes.len())
                .filter(|&i| m.kinds[i] == NodeKind::Interior)
                .filter(|&i| !near_seam || (grid[i].x - mid).abs() <= 2.0)
                .fold((0.0, 0), |(s, c), i| {
                    (s + (m.nodes[i] - grid[i]).length(), c + 1)
                });
            sum / count as f64
        };
        let (before, before_seam) = (off(&m, false), off(&m, true));
        let mut again = m.clone();
        laplace(&mut m, 30);
        laplace(&mut again, 30);
        assert_eq!(m.nodes, again.nodes, "the same mesh every time");
        assert!(
            off(&m, false) < 0.3 * before,
            "{} of {before}",
            off(&m, false)
        );
        assert!(
            off(&m, true) < 0.3 * before_seam,
            "at the seam {} of {before_seam}",
            off(&m, true)
        );
        for (i, p) in m.nodes.iter().enumerate() {
            if m.kinds[i] == NodeKind::Boundary {
                assert_eq!(*p, grid[i]);
            }
        }
        assert!((0..m.quads.len()).all(|q| badness(m.quad_points(q)).is_finite()));
    }

    /// The largest size jump between neighbours (the square root of
    /// their area ratio).
    fn largest_jump(m: &Mesh) -> f64 {
        let around = node_elements(m);
        let area = |q: usize| crate::geometry::polygon_area(&m.quad_points(q)).abs();
        let mut jump: f64 = 1.0;
        for (q, nb) in element_neighbours(m, &around).iter().enumerate() {
            for &f in nb.iter().flatten() {
                jump = jump.max((area(q) / area(f as usize)).sqrt());
            }
        }
        jump
    }

    #[test]
    fn a_size_jump_one_node_cannot_even_out_is_evened_out_by_two() {
        // a 4 x 4 grid graded hard in x and y, its inner nodes pushed: the
        // node between the two elements of the jump is held by a corner
        // at the window's edge (alone it gets the jump to 2.10 only)
        let (mut m, _) = pushed_grid(4, 0.0);
        for p in &mut m.nodes {
            *p = DVec2::new((p.x / 4.0).powi(3) * 4.0, (p.y / 4.0).powf(1.6) * 4.0);
        }
        let inner = [
            (6, 0.0333, 0.4637),
            (7, 0.3718, 0.2429),
            (8, 1.5747, 0.6143),
            (11, 0.2293, 1.0905),
            (12, 0.4863, 1.1262),
            (13, 1.8729, 1.2367),
            (16, 0.2734, 2.5611),
            (17, 0.5709, 2.5817),
            (18, 1.8180, 2.5270),
        ];
        for (i, x, y) in inner {
            assert_eq!(m.kinds[i], NodeKind::Interior);
            m.nodes[i] = DVec2::new(x, y);
        }
        let worst_corner = |m: &Mesh| {
            (0..m.quads.len())
                .map(|q| badness(m.quad_points(q)))
                .fold(0.0, f64::max)
        };
        let corner_before = worst_corner(&m);
        assert!(largest_jump(&m) > 2.4);
        assert!(even_out_sizes(&mut m, 10) > 0);
        assert!(largest_jump(&m) <= 2.0, "jump {}", largest_jump(&m));
        assert!(worst_corner(&m) <= corner_before + 1e-9);
    }

    #[test]
    fn a_strip_comes_out_the_same_whichever_thread_sweeps_it() {
        // pushed hard, so that every sweep of the stage has work near the
        // seams; one thread sweeps the strips one after another, three
        // share them
        let (m, _) = pushed_grid(150, 0.45);
        let around = node_elements(&m);
        let neighbours = element_neighbours(&m, &around);
        let stage = |mesh: &mut Mesh, nodes: &Nodes, dirty: &mut [bool]| {
            all_sweeps(mesh, [5, 5], nodes, &neighbours, dirty)
        };
        let mut alone = m.clone();
        let mut shared = m.clone();
        let moved = sweep_in_strips_on(&mut alone, around.clone(), 1, stage);
        assert!(moved > 0);
        sweep_in_strips_on(&mut shared, around, 3, stage);
        assert_eq!(alone.nodes, shared.nodes);
    }

    #[test]
    fn bands_far_enough_apart_come_out_as_swept_together() {
        // pushed hard, so that every sweep of the stage has work; columns
        // of a 60 x 60 grid marked, nine steps apart (apart) or eight (one)
        let (m, _) = pushed_grid(60, 0.45);
        let around = node_elements(&m);
        let neighbours = element_neighbours(&m, &around);
        let stage = |mesh: &mut Mesh, nodes: &Nodes, dirty: &mut [bool]| {
            all_sweeps(mesh, [5, 5], nodes, &neighbours, dirty)
        };
        let columns = |a: usize, b: usize| -> Vec<bool> {
            (0..m.nodes.len())
                .map(|i| (a..a + 5).contains(&(i % 61)) || (b..b + 5).contains(&(i % 61)))
                .collect()
        };
        assert_eq!(
            apart_groups(&m, &around, &columns(8, 20), BANDS_APART).len(),
            1
        );
        let marked = columns(8, 21);
        let groups = apart_groups(&m, &around, &marked, BANDS_APART);
        assert_eq!(groups.len(), 2);
        let all_dirty = vec![true; m.nodes.len()];
        let mut apart = m.clone();
        sweep_groups(&mut apart, &around, &groups, &all_dirty, 2, &stage);
        let mut together = m.clone();
        let visit: Vec<u32> = (0..m.nodes.len() as u32)
            .filter(|&i| marked[i as usize])
            .collect();
        let moved = stage(
            &mut together,
            &Nodes {
                around: &around,
                visit: &visit,
            },
            &mut all_dirty.clone(),
        );
        assert!(moved > 0);
        assert_eq!(apart.nodes, together.nodes);
    }

    #[test]
    fn boundary_nodes_never_move() {
        let mut m = Mesh::default();
        m.add_node(DVec2::ZERO, NodeKind::Boundary);
        m.add_node(DVec2::X, NodeKind::Boundary);
        m.add_node(DVec2::new(1.0, 1.0), NodeKind::Boundary);
        m.add_node(DVec2::new(0.2, 0.9), NodeKind::Boundary);
        m.quads = vec![[0, 1, 2, 3]];
        let before = m.nodes.clone();
        laplace(&mut m, 5);
        assert_eq!(m.nodes, before);
    }
}
