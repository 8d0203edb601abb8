//! Thin walls: two edges of the boundary that face each other across less
//! than a few element sizes (a tube's two circles, a channel's flanges, a
//! web) get the same segment count, so that the rules lay one structured
//! row of elements between them instead of a transition squeezed into the
//! wall (which leaves 45/135-degree parallelograms and slivers).
//!
//! The threshold is `bound(thin_wall, K)` in kb/strategy.pl: edges facing
//! each other closer than K element sizes over most of their length.

use glam::DVec2;

use crate::input::curves::min_arc_segments;
use crate::input::domain::{Curve, Domain};

/// Samples along an edge to tell how much of it faces another.
const SAMPLES: usize = 16;

/// Share of an edge's samples that must face the other edge.
const FACING_SHARE: f64 = 0.8;

/// The share of `e`'s samples from which `f` is within `gap`, across (the
/// way to it within 30 degrees of `e`'s normal) and running along `e`
/// (their tangents within 30 degrees, either way round).
fn facing_share(e: &Curve, f: &Curve, gap: f64) -> f64 {
    let facing = (0..SAMPLES)
        .filter(|&k| {
            let t = (k as f64 + 0.5) / SAMPLES as f64;
            let p = e.point_at(t);
            let q = f.project(p);
            let d = (q - p).length();
            if d == 0.0 || d > gap {
                return false;
            }
            let te = e.tangent_at(p);
            ((q - p) / d).dot(te).abs() < 0.5 && te.dot(f.tangent_at(q)).abs() > 0.866
        })
        .count();
    facing as f64 / SAMPLES as f64
}

/// Gives the edges of the domain's loops that face each other across a
/// thin wall (closer than `wall` element sizes over most of both) one
/// segment count per group of facing edges: a count fixed by the file if
/// one has it, else the group's mean length over `size`. `fixed[c][e]`
/// says whether the file fixes an edge's count. Returns, for each edge,
/// whether it is in such a group.
pub(crate) fn match_facing_counts(
    domain: &Domain,
    size: f64,
    wall: f64,
    fixed: &[Vec<bool>],
    counts: &mut [Vec<usize>],
) -> Vec<Vec<bool>> {
    let mut in_wall: Vec<Vec<bool>> = counts.iter().map(|r| vec![false; r.len()]).collect();
    if wall <= 0.0 {
        return in_wall;
    }
    let gap = wall * size;
    let loops = 1 + domain.holes.len();
    // the loops' edges with their bounding boxes grown by the gap
    let mut edges: Vec<(usize, usize, Curve, DVec2, DVec2)> = Vec::new();
    for (ci, chain) in domain.chains().enumerate().take(loops) {
        for (ei, e) in chain.edges.iter().enumerate() {
            let (lo, hi) = e.curve.box_grown_by(gap);
            edges.push((ci, ei, e.curve, lo, hi));
        }
    }
    // pairs by a sweep over the boxes' left sides: near linear for the
    // long boundaries of drawings
    let mut order: Vec<usize> = (0..edges.len()).collect();
    order.sort_by(|&i, &j| edges[i].3.x.total_cmp(&edges[j].3.x).then(i.cmp(&j)));
    let mut parent: Vec<usize> = (0..edges.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut paired = vec![false; edges.len()];
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if edges[j].3.x > edges[i].4.x {
                break;
            }
            let (a, b) = (&edges[i], &edges[j]);
            if b.3.y > a.4.y || a.3.y > b.4.y {
                continue;
            }
            // edges that meet at a corner face each other only there
            let n = domain.chains().nth(a.0).map_or(0, |c| c.edges.len());
            let adjacent = (a.1 + 1) % n == b.1 || (b.1 + 1) % n == a.1;
            if a.0 == b.0 && adjacent {
                continue;
            }
            if facing_share(&a.2, &b.2, gap) >= FACING_SHARE
                && facing_share(&b.2, &a.2, gap) >= FACING_SHARE
            {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
                paired[i] = true;
                paired[j] = true;
            }
        }
    }
    // one count per group
    let mut groups: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for i in (0..edges.len()).filter(|&i| paired[i]) {
        groups.entry(root(&mut parent, i)).or_default().push(i);
    }
    for members in groups.values() {
        let fixed_count = members
            .iter()
            .find(|&&i| fixed[edges[i].0][edges[i].1])
            .map(|&i| counts[edges[i].0][edges[i].1]);
        let target = fixed_count.unwrap_or_else(|| {
            let mean =
                members.iter().map(|&i| edges[i].2.length()).sum::<f64>() / members.len() as f64;
            // no arc gets fewer chords than it needs to follow its curve
            let fewest = members.iter().map(|&i| min_arc_segments(&edges[i].2)).max();
            ((mean / size).round() as usize)
                .max(fewest.unwrap_or(1))
                .max(1)
        });
        for &i in members {
            let (ci, ei) = (edges[i].0, edges[i].1);
            if !fixed[ci][ei] {
                counts[ci][ei] = target;
            }
            in_wall[ci][ei] = true;
        }
    }
    in_wall
}
