//! A domain of four sides whose opposite sides have different segment
//! counts (the paper's Fig. 18), meshed in mapped patches instead of by
//! free elements: a patch whose opposite sides differ by the same amount
//! e both ways takes one pair of irregular nodes (O of valence 3 near the
//! corner between its two longer sides, F of valence 5 inside), six
//! mapped patches round them, two of them strips e elements wide along
//! the longer sides; any other patch is cut by a chord into two such
//! patches (or a grid and one). So the irregular nodes of the mesh are
//! the pairs, at most `bound(four_sided_pairs, K)` of them.
//!
//! With the longer sides s0 (corner A to B) and s3 (D to A), n0 = n2 + e
//! and n3 = n1 + e; the shorter sides are shared p1 + q2 = n2 (CD) and
//! p2 + q3 = n1 (BC). O has lines to P2 on AB and P1 on DA, F to Q1 on AB,
//! Q2 on BC, Q3 on CD and Q4 on DA, and O to F:
//!
//! ```text
//!   D ---p1--- Q3 ----q2---- C
//!   |          |             |
//!   q3  (D)    |     (C)     q3
//!   |          |             |
//!   Q4 ------- F ----------- Q2
//!   e  strip / |    (B)      p2
//!   P1 ---- O  |             |
//!   p2 (A)  |e strip         |
//!   A --p1-- P2 --e-- Q1 -q2- B
//! ```
//!
//! round A a p1 x p2 grid, round B q2 x p2, round C q2 x q3, round D
//! p1 x q3, the strips e x p2 along AB and e x p1 along DA.

use glam::DVec2;

use super::mapping::coons_grid;
use crate::input::domain::Domain;
use crate::mesh::{Mesh, NodeKind};
use crate::partial_mesh::MeshStats;
use crate::pipeline::discretise_for_run;
use crate::recursion::Outcome;
use crate::settings::ElementBounds;

/// How many plans are meshed on a copy to choose from.
const PLANS_TRIED: usize = 16;

/// Past this many elements meshed on copies, no further plan is tried.
const TRIAL_QUADS: usize = 20_000;

/// How many of the plans ranked best after plain Laplace are smoothed as
/// a run smooths, to choose from.
const SMOOTHED_TRIALS: usize = 4;

/// `passes` sweeps of plain Laplace over the inner nodes (each to the
/// mean of its neighbours along element edges): enough to compare plans.
fn plain_laplace(mesh: &mut Mesh, passes: usize) {
    let mut next: Vec<Vec<u32>> = vec![Vec::new(); mesh.nodes.len()];
    for q in &mesh.quads {
        for i in 0..4 {
            let (a, b) = (q[i], q[(i + 1) % 4]);
            if !next[a as usize].contains(&b) {
                next[a as usize].push(b);
                next[b as usize].push(a);
            }
        }
    }
    for _ in 0..passes {
        for (n, around) in next.iter().enumerate() {
            if mesh.kinds[n] == NodeKind::Interior && !around.is_empty() {
                let sum: DVec2 = around.iter().map(|&m| mesh.nodes[m as usize]).sum();
                mesh.nodes[n] = sum / around.len() as f64;
            }
        }
    }
}

/// How many elements of `mesh` have a corner outside the window or an
/// aspect ratio or taper above the bounds, and the worst of those two
/// ratios over all elements.
fn shape(mesh: &Mesh, bounds: &ElementBounds) -> (usize, f64) {
    let mut outside = 0;
    let mut worst: f64 = 1.0;
    for q in &mesh.quads {
        let p = q.map(|i| mesh.nodes[i as usize]);
        let (aspect, taper) = crate::element_quality::aspect_taper(p);
        let bad = crate::element_quality::badness(p, bounds) > 0.0
            || aspect > bounds.max_aspect
            || taper > bounds.max_taper;
        outside += usize::from(bad);
        worst = worst.max(aspect).max(taper);
    }
    (outside, worst)
}

/// A domain that is one loop of four input edges (no holes, no lines)
/// meshed so: the outcome and its pairs of irregular nodes. None where the
/// domain is not of four sides; Err says why no plan of at most
/// `max_pairs` pairs fits its counts.
pub fn outcome(
    domain: &Domain,
    size: f64,
    max_pairs: usize,
    bounds: &ElementBounds,
) -> Option<Result<(Outcome, usize), String>> {
    if !domain.holes.is_empty() || !domain.lines.is_empty() || domain.outer.edges.len() != 4 {
        return None;
    }
    // (discretised with the built-in thin_wall and max_size_jump bounds:
    // a KB that sets others changes the layouts' runs, not these counts)
    let boundary = discretise_for_run(domain, Some(size)).ok()?;
    let (disc, loops) = boundary.parts();
    let [ring] = loops else { return None };
    // the loop's corners: the nodes at the input edges' starts, in the
    // loop's order (domain on the left)
    let nearest = |p: DVec2| {
        (0..ring.len()).min_by(|&i, &j| {
            let d = |k: usize| (disc.nodes[ring[k] as usize] - p).length_squared();
            d(i).total_cmp(&d(j))
        })
    };
    let mut at: Vec<usize> = domain
        .outer
        .edges
        .iter()
        .map(|e| nearest(e.curve.point_at(0.0)))
        .collect::<Option<_>>()?;
    at.sort_unstable();
    at.dedup();
    if at.len() != 4 {
        return None;
    }
    // a corner is one element's corner: one past the window (a side
    // that bends on, as a slot's round end) is no patch corner
    let m = ring.len();
    let turn = |i: usize| {
        let p = |k: usize| disc.nodes[ring[k % m] as usize];
        let (a, b) = (p(i + 1) - p(i), p(i + m - 1) - p(i));
        a.perp_dot(b).atan2(a.dot(b)).to_degrees().rem_euclid(360.0)
    };
    if at.iter().any(|&i| turn(i) > bounds.upper_corner) {
        return None;
    }
    let sides: [Vec<u32>; 4] = std::array::from_fn(|i| {
        let (from, to) = (
            at[i],
            if i == 3 {
                at[0] + ring.len()
            } else {
                at[i + 1]
            },
        );
        (from..=to).map(|k| ring[k % ring.len()]).collect()
    });
    let n = sides.clone().map(|s| s.len() - 1);
    let corner = std::array::from_fn(|i| disc.nodes[sides[i][0] as usize]);
    // each plan meshed with each split on a copy and ranked after plain
    // Laplace (cheap): fewest elements out of bounds, fewer pairs, the
    // better worst shape; the first few smoothed as a run smooths and the
    // best of those kept
    // (elements out of bounds, pairs, worst aspect or taper): less is better
    type Key = (usize, usize, f64);
    type Trial = (Key, Mesh, Vec<Patch>, usize);
    let key_of = |m: &Mesh, pairs: usize| {
        let (outside, worst) = shape(m, bounds);
        (outside, pairs, worst)
    };
    let order = |a: &Key, b: &Key| (a.0, a.1).cmp(&(b.0, b.1)).then(a.2.total_cmp(&b.2));
    // each trial's mesh is the boundary with the patches' inner nodes; its
    // quads are the patches'
    let with_quads = |mesh: &Mesh, patches: &[Patch]| {
        let mut m = mesh.clone();
        m.quads = patches
            .iter()
            .flat_map(|p| p.quads.iter().copied())
            .collect();
        m
    };
    let mut ranked: Vec<Trial> = Vec::new();
    let mut meshed = 0;
    for (plan, pairs) in plans(n, corner, size, max_pairs, PLANS_TRIED) {
        if meshed > TRIAL_QUADS {
            break;
        }
        for split in SHARES
            .iter()
            .flat_map(|&a| SHARES.iter().map(move |&b| [a, b]))
        {
            let mut mesh = disc.clone();
            let patches = mesh_plan(&mut mesh, sides.clone(), plan, split);
            let mut trial = with_quads(&mesh, &patches);
            plain_laplace(&mut trial, 20);
            meshed += trial.quads.len();
            ranked.push((key_of(&trial, pairs), mesh, patches, pairs));
            if matches!(plan, Plan::Whole) && pairs == 0 {
                break; // a grid has no split
            }
        }
    }
    // (a stable sort: equals stay in the order they were tried)
    ranked.sort_by(|a, b| order(&a.0, &b.0));
    let best = ranked
        .into_iter()
        .take(SMOOTHED_TRIALS)
        .map(|(_, mesh, patches, pairs)| {
            let mut trial = with_quads(&mesh, &patches);
            crate::smoothing::smooth(&mut trial, 20, bounds, None);
            (key_of(&trial, pairs), mesh, patches, pairs)
        })
        // the first of equals, as before
        .reduce(|best, t| {
            if order(&t.0, &best.0).is_lt() {
                t
            } else {
                best
            }
        });
    let Some(((outside, ..), mut mesh, patches, pairs)) = best else {
        return Some(Err(format!(
            "four sides of {}, {}, {} and {} segments: no patches round at most {max_pairs} pairs of irregular nodes",
            n[0], n[1], n[2], n[3]
        )));
    };
    // (the clean-up could mend some, at the cost of irregular nodes the
    // layouts may do without)
    if outside > 0 {
        return Some(Err(format!(
            "four sides of {}, {}, {} and {} segments: patches round {pairs} pairs leave {outside} elements out of bounds",
            n[0], n[1], n[2], n[3]
        )));
    }
    let mut trace = Vec::new();
    for (b, p) in patches.iter().enumerate() {
        mesh.quads.extend(&p.quads);
        mesh.blocks
            .extend(std::iter::repeat_n(b as u32, p.quads.len()));
        trace.push(super::map_step(p.quads[0], p.counts));
    }
    super::renumber(&mut trace);
    let stats = MeshStats {
        blocks: patches.len(),
        ..MeshStats::default()
    };
    Some(Ok((
        Outcome {
            area: mesh.boundary_area(1),
            mesh,
            trace,
            vetoes: Vec::new(),
            stats,
            grading: None,
        },
        pairs,
    )))
}

/// A patch side: its node ids from one corner to the next,
/// counter-clockwise.
type Side = Vec<u32>;

/// Where a pair patch's shorter sides are shared: p1 = n2 split[0] and
/// p2 = n1 split[1] (rounded, at least 1 and at most n - 1).
pub type Split = [f64; 2];

/// The shares tried for each.
const SHARES: [f64; 3] = [0.5, 1.0 / 3.0, 2.0 / 3.0];

/// A mapped patch made: its quads (counter-clockwise) and its grid's
/// counts.
pub struct Patch {
    /// The quads.
    pub quads: Vec<[u32; 4]>,
    /// Segments along its first side and along its second.
    pub counts: [usize; 2],
}

/// How a patch with side counts `n` is meshed alone: Some(0) a grid,
/// Some(1) one pair of irregular nodes, None neither.
fn pairs_alone(n: [usize; 4]) -> Option<usize> {
    if n[0] == n[2] && n[1] == n[3] {
        return Some(0);
    }
    let (d02, d13) = (n[0] as i64 - n[2] as i64, n[1] as i64 - n[3] as i64);
    // the shorter sides hold both patches beside the strips
    let shorter_ok = n[0].min(n[2]) >= 2 && n[1].min(n[3]) >= 2;
    (d02.abs() == d13.abs() && shorter_ok).then_some(1)
}

/// The patches a four-sided domain with side counts `n` is cut into: one
/// (no chord), or two by a chord from side `k` (at `x` segments from its
/// start) to side `k + 2` (at `t` segments from its start) with `l`
/// segments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plan {
    /// One patch: a grid or one pair.
    Whole,
    /// Two patches either side of a chord.
    Cut {
        k: usize,
        x: usize,
        t: usize,
        l: usize,
    },
}

/// The plans of at most `max_pairs` pairs for a patch with side counts
/// `n`, fewest pairs first, then the chords whose count best fits their
/// length at `size` and that run most nearly across (their ends at the
/// same share of the two sides); `corner` gives the four corners'
/// positions. At most `keep` of them.
pub fn plans(
    n: [usize; 4],
    corner: [DVec2; 4],
    size: f64,
    max_pairs: usize,
    keep: usize,
) -> Vec<(Plan, usize)> {
    if let Some(p) = pairs_alone(n).filter(|&p| p <= max_pairs) {
        return vec![(Plan::Whole, p)];
    }
    let mut found: Vec<(usize, f64, Plan)> = Vec::new();
    if max_pairs < 2 {
        return Vec::new();
    }
    for k in 0..2 {
        let (a, b, c, d) = (n[k], n[k + 1], n[k + 2], n[(k + 3) % 4]);
        for x in 1..a {
            for t in 1..c {
                // side k from its start A to B, side k+2 from C to D: the
                // patch beyond the chord [a - x, b, t, l], before it
                // [x, l, c - t, d]
                let share = (x as f64 / a as f64 - (c - t) as f64 / c as f64).abs();
                let ends = |s: usize, f: f64| corner[s].lerp(corner[(s + 1) % 4], f);
                let length =
                    (ends(k, x as f64 / a as f64) - ends(k + 2, t as f64 / c as f64)).length();
                // a grid or a pair beyond takes l = b or b -+ |a - x - t|,
                // before it l = d or d -+ |x - c + t|
                let (u, v) = ((a - x).abs_diff(t), x.abs_diff(c - t));
                let mut ls = [b, b + u, b.saturating_sub(u), d, d + v, d.saturating_sub(v)];
                ls.sort_unstable();
                for (i, &l) in ls.iter().enumerate() {
                    if l == 0 || (i > 0 && ls[i - 1] == l) {
                        continue;
                    }
                    let (Some(p1), Some(p2)) =
                        (pairs_alone([a - x, b, t, l]), pairs_alone([x, l, c - t, d]))
                    else {
                        continue;
                    };
                    if p1 + p2 <= max_pairs {
                        let cost = (length / (l as f64 * size)).ln().abs() + share;
                        found.push((p1 + p2, cost, Plan::Cut { k, x, t, l }));
                    }
                }
            }
        }
    }
    // (a stable sort: equal plans stay in the order they were found)
    found.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    found
        .into_iter()
        .take(keep)
        .map(|(p, _, plan)| (plan, p))
        .collect()
}

/// Meshes the patch bounded by `sides` as `plan` says: its mapped
/// patches.
pub fn mesh_plan(mesh: &mut Mesh, sides: [Side; 4], plan: Plan, split: Split) -> Vec<Patch> {
    let mut out = Vec::new();
    match plan {
        Plan::Whole => mesh_patch(mesh, sides, split, &mut out),
        Plan::Cut { k, x, t, l } => {
            let s = |i: usize| sides[(k + i) % 4].clone();
            let (a, c) = (s(0), s(2));
            let chord = line(mesh, a[x], c[t], l); // X to Y
            let mut back = chord.clone();
            back.reverse();
            let beyond = [a[x..].to_vec(), s(1), c[..=t].to_vec(), back];
            let before = [a[..=x].to_vec(), chord, c[t..].to_vec(), s(3)];
            mesh_patch(mesh, beyond, split, &mut out);
            mesh_patch(mesh, before, split, &mut out);
        }
    }
    out
}

/// A patch that is a grid or takes one pair (`pairs_alone` says which).
fn mesh_patch(mesh: &mut Mesh, sides: [Side; 4], split: Split, out: &mut Vec<Patch>) {
    let n = sides.clone().map(|s| s.len() - 1);
    if n[0] == n[2] && n[1] == n[3] {
        return grid(mesh, &sides, out);
    }
    // turn the patch so that its two longer sides meet at corner 0
    let long02 = n[0] > n[2];
    let long13 = n[1] > n[3];
    let r = match (long02, long13) {
        (true, false) => 0,  // s0 and s3 longer: corner 0
        (true, true) => 1,   // s0 and s1: corner 1
        (false, true) => 2,  // s1 and s2: corner 2
        (false, false) => 3, // s2 and s3: corner 3
    };
    let s: [Side; 4] = std::array::from_fn(|i| sides[(i + r) % 4].clone());
    pair(mesh, s, split, out)
}

/// A grid patch.
fn grid(mesh: &mut Mesh, s: &[Side; 4], out: &mut Vec<Patch>) {
    let (mut top, mut left) = (s[2].clone(), s[3].clone());
    top.reverse();
    left.reverse();
    out.push(Patch {
        quads: coons_grid(mesh, &s[0], &s[1], &top, &left),
        counts: [s[0].len() - 1, s[1].len() - 1],
    });
}

/// The pair pattern (see the module's comment) with the longer sides s0
/// and s3 meeting at corner 0: six grids.
fn pair(mesh: &mut Mesh, s: [Side; 4], split: Split, out: &mut Vec<Patch>) {
    let n = s.clone().map(|x| x.len() - 1);
    let e = n[0] - n[2];
    let share = |n: usize, f: f64| ((n as f64 * f).round() as usize).clamp(1, n - 1);
    let (p1, p2) = (share(n[2], split[0]), share(n[1], split[1]));
    let (q2, q3) = (n[2] - p1, n[1] - p2);
    let (a, b, c, d) = (&s[0], &s[1], &s[2], &s[3]);
    let (pp2, qq1) = (a[p1], a[p1 + e]);
    let qq2 = b[p2];
    let qq3 = c[q2];
    let (qq4, pp1) = (d[q3], d[q3 + e]);
    // O and F where the layout's edges would have their counts' lengths:
    // each a mean of its neighbours weighted by one over the count between
    let at = |i: u32| mesh.nodes[i as usize];
    let mut o = (at(a[0]) + at(b[0]) + at(c[0]) + at(d[0])) / 4.0;
    let mut f = o;
    let w = |k: usize| 1.0 / k as f64;
    for _ in 0..200 {
        o = (at(pp2) * w(p2) + at(pp1) * w(p1) + f * w(e)) / (w(p2) + w(p1) + w(e));
        f = (at(qq1) * w(p2) + at(qq2) * w(q2) + at(qq3) * w(q3) + at(qq4) * w(p1) + o * w(e))
            / (w(p2) + w(q2) + w(q3) + w(p1) + w(e));
    }
    let on = mesh.add_node(o, NodeKind::Interior);
    let fnode = mesh.add_node(f, NodeKind::Interior);
    let rev = |mut v: Vec<u32>| {
        v.reverse();
        v
    };
    let p2_o = line(mesh, pp2, on, p2);
    let o_p1 = line(mesh, on, pp1, p1);
    let o_f = line(mesh, on, fnode, e);
    let f_q1 = line(mesh, fnode, qq1, p2);
    let f_q2 = line(mesh, fnode, qq2, q2);
    let f_q3 = line(mesh, fnode, qq3, q3);
    let f_q4 = line(mesh, fnode, qq4, p1);
    let faces: [[Side; 4]; 6] = [
        // round A: A, P2, O, P1
        [
            a[..=p1].to_vec(),
            p2_o.clone(),
            o_p1.clone(),
            d[q3 + e..].to_vec(),
        ],
        // the strip along AB: P2, Q1, F, O
        [
            a[p1..=p1 + e].to_vec(),
            rev(f_q1.clone()),
            rev(o_f.clone()),
            rev(p2_o),
        ],
        // round B: Q1, B, Q2, F
        [
            a[p1 + e..].to_vec(),
            b[..=p2].to_vec(),
            rev(f_q2.clone()),
            f_q1,
        ],
        // round C: F, Q2, C, Q3
        [f_q2, b[p2..].to_vec(), c[..=q2].to_vec(), rev(f_q3.clone())],
        // round D: F, Q3, D, Q4
        [f_q3, c[q2..].to_vec(), d[..=q3].to_vec(), rev(f_q4.clone())],
        // the strip along DA: Q4, P1, O, F
        [d[q3..=q3 + e].to_vec(), rev(o_p1), o_f, f_q4],
    ];
    for face in &faces {
        grid(mesh, face, out);
    }
}

/// A straight line of `n` segments from node `a` to node `b`: its node
/// ids, the inner ones new.
fn line(mesh: &mut Mesh, a: u32, b: u32, n: usize) -> Vec<u32> {
    let (pa, pb) = (mesh.nodes[a as usize], mesh.nodes[b as usize]);
    let mut ids = vec![a];
    for k in 1..n {
        ids.push(mesh.add_node(pa.lerp(pb, k as f64 / n as f64), NodeKind::Interior));
    }
    ids.push(b);
    ids
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_opposite_sides_are_a_grid_and_equal_differences_one_pair() {
        assert_eq!(pairs_alone([6, 3, 6, 3]), Some(0));
        // 8 - 4 = 6 - 2 (s0 and s3 longer)
        assert_eq!(pairs_alone([8, 2, 4, 6]), Some(1));
        assert_eq!(pairs_alone([12, 4, 6, 2]), None);
        // a shorter side of one segment leaves no room beside the strip
        assert_eq!(pairs_alone([5, 1, 3, 3]), None);
    }

    #[test]
    fn sides_of_12_4_6_and_2_are_cut_into_two_patches_of_one_pair_each() {
        let corner = [
            DVec2::new(0.0, 0.0),
            DVec2::new(8.0, 0.0),
            DVec2::new(8.0, 4.0),
            DVec2::new(0.0, 4.0),
        ];
        let all = plans([12, 4, 6, 2], corner, 0.5, 2, 100);
        assert!(!all.is_empty() && all.iter().all(|&(_, pairs)| pairs == 2));
        let (p, _) = all[0];
        let Plan::Cut { k, x, t, l } = p else {
            panic!("{p:?}")
        };
        let n = [12, 4, 6, 2];
        let (a, b, c, d) = (n[k], n[k + 1], n[k + 2], n[(k + 3) % 4]);
        assert!(pairs_alone([a - x, b, t, l]).is_some());
        assert!(pairs_alone([x, l, c - t, d]).is_some());
        assert!(plans([12, 4, 6, 2], corner, 0.5, 1, 100).is_empty());
        assert_eq!(
            plans([6, 3, 6, 3], corner, 0.5, 0, 100),
            vec![(Plan::Whole, 0)]
        );
    }
}
