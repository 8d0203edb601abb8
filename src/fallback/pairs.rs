//! Open loops closed by pairs of triangles: the loop (an even number of
//! edges) triangulated with interior points on a lattice of about the
//! element size, and its triangles paired across their shared edges into
//! quads, a maximum matching of the triangles' neighbour graph (Gabow's
//! algorithm, petgraph). No node is put on the loop's edges, so the rules'
//! elements round the loop stay as they are: splitting triangles in three
//! halves every loop edge, and the halving runs along the rows of the
//! rules' elements to the boundary (a slot's whole length of elements
//! split in two).
//!
//! The pairs are chosen in tiers of their quads' corners (all within 45
//! to 135 degrees first, then wider windows, at last 5 to 175): the
//! strictest tier whose matching is as large as the widest's gives the
//! quads, so poor pairs are used only where the good ones cannot cover
//! as much of the loop. The triangles left over (where no perfect
//! matching exists) are split in three by the caller, which halves
//! their edges only. The smoothing and the clean-up then work on the
//! quads as on the rules'.

use glam::DVec2;
use petgraph::algo::maximum_matching;
use petgraph::graph::{NodeIndex, UnGraph};
use std::collections::{HashMap, HashSet};

use super::open_region::{
    after_halving, halving, key, triangulate_region, EdgeQuads, Spacing, Triangulated,
};
use super::triangles::FallbackError;
use crate::geometry::{quad_angles, quad_is_convex};

/// The corner windows (degrees from 90) of the tiers, the last any quad
/// with corners within 5 and 175 degrees: a pair whose corner is nearly
/// straight (three nodes of a straight input edge, as at a spike's tip)
/// is a triangle, and boundary nodes cannot be moved to mend it.
const TIERS: [f64; 4] = [45.0, 60.0, 75.0, 85.0];

/// Two triangles sharing an edge, as the quad they make
/// (counter-clockwise) and how far its worst corner is from 90 degrees.
struct Pair {
    tris: (usize, usize),
    quad: [u32; 4],
    off_square: f64,
}

/// `tris` (counter-clockwise node ids into `nodes`) paired into as many
/// quads as a matching can, never across an edge of `fixed` (the loop's
/// edges and the lines inside it): the quads, and the triangles left
/// over (none where the matching is perfect). Of the tiers that pair as
/// many, the strictest.
pub(super) fn pair_up(
    nodes: &[DVec2],
    tris: &[[u32; 3]],
    fixed: &HashSet<(u32, u32)>,
) -> (Vec<[u32; 4]>, Vec<[u32; 3]>) {
    // each directed edge's triangle and the corner opposite it
    let mut by_edge: HashMap<(u32, u32), (usize, u32)> = HashMap::new();
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            by_edge.insert((tri[i], tri[(i + 1) % 3]), (t, tri[(i + 2) % 3]));
        }
    }
    let mut pairs: Vec<Pair> = Vec::new();
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            let (u, v, w) = (tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]);
            if fixed.contains(&key(u, v)) {
                continue;
            }
            // the triangle across (u, v) runs v -> u
            let Some(&(s, x)) = by_edge.get(&(v, u)) else {
                continue;
            };
            if s <= t {
                continue; // each pair once
            }
            let quad = [w, u, x, v];
            let points = quad.map(|n| nodes[n as usize]);
            if !quad_is_convex(points) {
                continue;
            }
            let off_square = quad_angles(points)
                .iter()
                .map(|a| (a - 90.0).abs())
                .fold(0.0, f64::max);
            pairs.push(Pair {
                tris: (t, s),
                quad,
                off_square,
            });
        }
    }
    // each tier's matching, as the pairs it takes
    let matched = |window: f64| -> Vec<usize> {
        let mut graph: UnGraph<(), usize> = UnGraph::with_capacity(tris.len(), pairs.len());
        let ids: Vec<NodeIndex> = (0..tris.len()).map(|_| graph.add_node(())).collect();
        let mut which: HashMap<(usize, usize), usize> = HashMap::new();
        for (p, pair) in pairs.iter().enumerate() {
            if pair.off_square < window {
                graph.add_edge(ids[pair.tris.0], ids[pair.tris.1], p);
                which.insert(pair.tris, p);
            }
        }
        let mut taken: Vec<usize> = maximum_matching(&graph)
            .edges()
            .map(|(a, b)| {
                let (a, b) = (a.index(), b.index());
                which[&(a.min(b), a.max(b))]
            })
            .collect();
        taken.sort_unstable(); // the same mesh whatever the matching's order
        taken
    };
    let widest = matched(TIERS[TIERS.len() - 1]);
    let taken = TIERS[..TIERS.len() - 1]
        .iter()
        .map(|&w| matched(w))
        .find(|t| t.len() == widest.len())
        .unwrap_or(widest);
    let mut paired = vec![false; tris.len()];
    for &p in &taken {
        paired[pairs[p].tris.0] = true;
        paired[pairs[p].tris.1] = true;
    }
    let quads = taken.iter().map(|&p| pairs[p].quad).collect();
    let left_over = tris
        .iter()
        .zip(&paired)
        .filter(|(_, &p)| !p)
        .map(|(t, _)| *t)
        .collect();
    (quads, left_over)
}

/// How many rounds of flips `pair_with_flips` tries at most.
const FLIP_ROUNDS: usize = 8;

/// `tris` paired (see `pair_up`), then, while triangles are left over,
/// the triangulation changed where that leaves fewer: an edge of a
/// triangle left over (not one of `fixed`) flipped to the other diagonal
/// of the convex quad of its two triangles, kept where the matching then
/// leaves fewer triangles over (the first such flip, in the triangles'
/// and their edges' order, each round).
fn pair_with_flips(
    nodes: &[DVec2],
    mut tris: Vec<[u32; 3]>,
    fixed: &HashSet<(u32, u32)>,
) -> (Vec<[u32; 4]>, Vec<[u32; 3]>) {
    let mut best = pair_up(nodes, &tris, fixed);
    for _ in 0..FLIP_ROUNDS {
        if best.1.is_empty() {
            break;
        }
        let index: HashMap<[u32; 3], usize> =
            tris.iter().enumerate().map(|(i, &t)| (t, i)).collect();
        let mut by_edge: HashMap<(u32, u32), usize> = HashMap::new();
        for (i, t) in tris.iter().enumerate() {
            for k in 0..3 {
                by_edge.insert((t[k], t[(k + 1) % 3]), i);
            }
        }
        let mut improved = None;
        'search: for left in &best.1 {
            let ti = index[left];
            for k in 0..3 {
                let (u, v, w) = (left[k], left[(k + 1) % 3], left[(k + 2) % 3]);
                if fixed.contains(&key(u, v)) {
                    continue;
                }
                let Some(&si) = by_edge.get(&(v, u)) else {
                    continue;
                };
                let s = tris[si];
                let x = s[(0..3).find(|&j| s[j] != u && s[j] != v).unwrap_or(0)];
                // the flip is sound only in a strictly convex quad
                if !quad_is_convex([w, u, x, v].map(|n| nodes[n as usize])) {
                    continue;
                }
                let mut flipped = tris.clone();
                flipped[ti] = [w, u, x];
                flipped[si] = [x, v, w];
                let paired = pair_up(nodes, &flipped, fixed);
                if paired.1.len() < best.1.len() {
                    improved = Some((flipped, paired));
                    break 'search;
                }
            }
        }
        match improved {
            Some((flipped, paired)) => {
                tris = flipped;
                best = paired;
            }
            None => break,
        }
    }
    best
}

/// The lattice spacings the pairing tries, as shares of its own.
const PAIRS_DENSER: [f64; 4] = [1.0, 0.85, 0.7, 0.55];

/// An open region triangulated and its triangles paired: the points (the
/// loop's nodes first, `ids` their mesh ids), the pairs' quads and the
/// triangles left over, in the points' numbering.
pub(super) struct PairedRegion {
    pub points: Vec<DVec2>,
    pub ids: Vec<u32>,
    pub pairs: Vec<[u32; 4]>,
    pub left_over: Vec<[u32; 3]>,
}

/// The open region paired as well as the lattice spacings of
/// `PAIRS_DENSER` allow: of their triangulations (a narrow loop gets
/// interior points at a denser one, and its triangles more ways to
/// pair), the one whose closing makes the fewest elements, the triangles
/// left over split in three and the halving carried along the chords of
/// `rules` (the rules' elements; the coarser spacing on a tie). With
/// pairing off, the triangles at the split spacing, none paired.
pub(super) fn pair_region(
    nodes: &[DVec2],
    rules: &EdgeQuads,
    loop_edges: &[(u32, u32)],
    times: &HashMap<(u32, u32), u32>,
    spacing: Spacing,
) -> Result<PairedRegion, FallbackError> {
    let unpaired = || -> Result<PairedRegion, FallbackError> {
        let Triangulated {
            points,
            ids,
            triangles,
        } = triangulate_region(nodes, loop_edges, times, spacing.split)?;
        Ok(PairedRegion {
            points,
            ids,
            pairs: Vec::new(),
            left_over: triangles,
        })
    };
    if spacing.pairs <= 0.0 {
        return unpaired();
    }
    // the lattice as fine as the loop's edges: the elements round a loop
    // the rules left open are often smaller than the size
    let mean_edge = loop_edges
        .iter()
        .map(|&(a, b)| (nodes[a as usize] - nodes[b as usize]).length())
        .sum::<f64>()
        / loop_edges.len() as f64;
    let lattice = spacing.pairs * mean_edge;
    let mut best: Option<(usize, PairedRegion)> = None;
    for step in PAIRS_DENSER {
        let Ok(Triangulated {
            points,
            ids,
            triangles,
        }) = triangulate_region(nodes, loop_edges, times, lattice * step)
        else {
            continue;
        };
        // the region's edges, in the triangulation's numbering
        let compact: HashMap<u32, u32> = ids
            .iter()
            .enumerate()
            .map(|(i, &n)| (n, i as u32))
            .collect();
        let fixed: HashSet<(u32, u32)> = loop_edges
            .iter()
            .map(|&(a, b)| key(compact[&a], compact[&b]))
            .collect();
        let (pairs, left_over) = pair_with_flips(&points, triangles, &fixed);
        // the elements its closing makes: each quad one, or two or four
        // where halved, each triangle left over three (the lattice points
        // numbered past the mesh's nodes, as they will be)
        let id = |n: u32| {
            ids.get(n as usize)
                .copied()
                .unwrap_or(nodes.len() as u32 + n - ids.len() as u32)
        };
        let quads: Vec<[u32; 4]> = pairs.iter().map(|q| q.map(id)).collect();
        let tris: Vec<[u32; 3]> = left_over.iter().map(|t| t.map(id)).collect();
        let halved = halving(rules, &quads, &tris);
        let elements = after_halving(rules, &quads, &halved) + 3 * tris.len();
        if best.as_ref().is_none_or(|(e, _)| elements < *e) {
            let done = left_over.is_empty();
            best = Some((
                elements,
                PairedRegion {
                    points,
                    ids,
                    pairs,
                    left_over,
                },
            ));
            if done {
                break;
            }
        }
    }
    match best {
        Some((_, b)) => Ok(b),
        None => unpaired(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square of side 2 with a node in the middle of each side and one
    /// in its centre, cut into 8 triangles: they pair into 4 squares.
    #[test]
    fn a_fan_of_eight_triangles_pairs_into_four_squares() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let nodes = vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 1.0),
            p(2.0, 2.0),
            p(1.0, 2.0),
            p(0.0, 2.0),
            p(0.0, 1.0),
            p(1.0, 1.0),
        ];
        let tris: Vec<[u32; 3]> = (0..8u32).map(|i| [8, i, (i + 1) % 8]).collect();
        let fixed: HashSet<(u32, u32)> = (0..8u32)
            .map(|i| (i.min((i + 1) % 8), i.max((i + 1) % 8)))
            .collect();
        let (quads, left_over) = pair_up(&nodes, &tris, &fixed);
        assert!(left_over.is_empty());
        assert_eq!(quads.len(), 4);
        for q in &quads {
            let a = quad_angles(q.map(|n| nodes[n as usize]));
            assert!(a.iter().all(|x| (x - 90.0).abs() < 1e-9), "{q:?}: {a:?}");
        }
    }

    /// Of three triangles in a row, two are paired and one left over.
    #[test]
    fn of_three_triangles_one_is_left_over() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        let nodes = vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(2.0, 0.0),
            p(0.5, 1.0),
            p(1.5, 1.0),
        ];
        let tris = vec![[0, 1, 3], [1, 4, 3], [1, 2, 4]];
        let (quads, left_over) = pair_up(&nodes, &tris, &HashSet::new());
        assert_eq!(quads.len(), 1);
        assert_eq!(left_over.len(), 1);
    }

    /// Two triangles whose union is not convex are not a pair.
    #[test]
    fn a_dart_is_not_a_pair() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        // the union of [0, 1, 2] and [0, 2, 3] is a dart: re-entrant at 2
        let nodes = vec![p(0.0, 0.0), p(2.0, 0.0), p(0.4, 0.4), p(0.0, 2.0)];
        let tris = vec![[0, 1, 2], [0, 2, 3]];
        let (quads, left_over) = pair_up(&nodes, &tris, &HashSet::new());
        assert!(quads.is_empty());
        assert_eq!(left_over, tris);
    }
}
