//! The interval assignment of a block layout: how many elements each
//! block edge gets. A block is meshed as a mapping element, so its
//! opposite sides get the same count; the edges tied together that way
//! (a chord of the layout, running through the blocks from one side of
//! the domain to another, or round in a ring) share one count. Each
//! chord aims at its edges' mean length over the element size; where the
//! file fixes an input edge's count, the chords of its block edges add
//! up to it exactly.

use rustc_hash::FxHashMap as HashMap;

/// One edge of the layout: its two block corners (lower id first).
pub type LayoutEdge = (u32, u32);

/// The chords of a layout: for each block, the edge of each of its four
/// sides, and each edge's chord.
#[derive(Debug, Clone, PartialEq)]
pub struct Chords {
    /// The layout's edges, in order of first appearance.
    pub edges: Vec<LayoutEdge>,
    /// Each block's four sides (indices into `edges`), side k from its
    /// corner k to corner k + 1.
    pub sides: Vec<[usize; 4]>,
    /// Each edge's chord (0-based, numbered in order of first edge).
    pub chord_of: Vec<usize>,
    /// How many chords.
    pub count: usize,
}

/// Ties the opposite sides of every block: sides 0 and 2, 1 and 3.
pub fn chords(blocks: &[[u32; 4]]) -> Chords {
    let mut index: HashMap<LayoutEdge, usize> = HashMap::default();
    let mut edges = Vec::new();
    let mut sides = Vec::with_capacity(blocks.len());
    for q in blocks {
        let mut s = [0; 4];
        for (k, side) in s.iter_mut().enumerate() {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let key = (a.min(b), a.max(b));
            *side = *index.entry(key).or_insert_with(|| {
                edges.push(key);
                edges.len() - 1
            });
        }
        sides.push(s);
    }
    let mut parent: Vec<usize> = (0..edges.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for s in &sides {
        for (x, y) in [(s[0], s[2]), (s[1], s[3])] {
            let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
            if rx != ry {
                parent[rx.max(ry)] = rx.min(ry);
            }
        }
    }
    let mut number: HashMap<usize, usize> = HashMap::default();
    let chord_of: Vec<usize> = (0..edges.len())
        .map(|e| {
            let r = root(&mut parent, e);
            let next = number.len();
            *number.entry(r).or_insert(next)
        })
        .collect();
    Chords {
        count: number.len(),
        edges,
        sides,
        chord_of,
    }
}

/// An input edge whose segment count the file fixes: the layout edges on
/// it and the count they must add up to.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedCount {
    /// The layout edges along the input edge.
    pub edges: Vec<usize>,
    /// The count the file gives.
    pub count: usize,
}

/// Why no assignment exists.
#[derive(Debug, Clone, PartialEq)]
pub struct Disagreement {
    /// The fixed count that cannot be met.
    pub count: usize,
    /// What the chords it crosses already add up to, or need at least.
    pub chords_give: usize,
}

/// Each chord's count, and the block edges whose counts are apart from
/// their chords' (edge, count); see `assign`.
pub type Assignment = (Vec<usize>, Vec<(usize, usize)>);

/// Each chord's count: the rounded mean of `targets` (an edge's length
/// over the element size) over its edges, at least 1; a chord that
/// crosses an input edge with a fixed count takes its share of that
/// count (in proportion to the targets, largest remainders first). The
/// fixed counts are met in the order given; one whose chords were all
/// set by an earlier one and add up to another count, or that has fewer
/// segments than chords, is a disagreement; unless `free_blocks`, where
/// it is shared out over its own block edges instead (in proportion to
/// their targets) and those edges' counts, apart from their chords',
/// come back beside the chords' (the blocks along them cannot be
/// mapping elements: the paper's Fig. 18, meshed free). A count below
/// its edges' number is a disagreement either way.
pub fn assign(
    chords: &Chords,
    targets: &[f64],
    fixed: &[FixedCount],
    free_blocks: bool,
) -> Result<Assignment, Disagreement> {
    let mut apart: Vec<(usize, usize)> = Vec::new();
    let mut sum = vec![0.0; chords.count];
    let mut n = vec![0usize; chords.count];
    for (e, &t) in targets.iter().enumerate() {
        sum[chords.chord_of[e]] += t;
        n[chords.chord_of[e]] += 1;
    }
    let mean: Vec<f64> = sum
        .iter()
        .zip(&n)
        .map(|(s, &k)| s / k.max(1) as f64)
        .collect();
    let mut count: Vec<Option<usize>> = vec![None; chords.count];
    for f in fixed {
        // a chord may cross the same input edge more than once
        let mut crossings: Vec<(usize, usize)> = Vec::new();
        for &e in &f.edges {
            let c = chords.chord_of[e];
            match crossings.iter_mut().find(|(x, _)| *x == c) {
                Some((_, k)) => *k += 1,
                None => crossings.push((c, 1)),
            }
        }
        let set: usize = crossings
            .iter()
            .filter_map(|&(c, k)| count[c].map(|n| n * k))
            .sum();
        let open: Vec<(usize, usize)> = crossings
            .iter()
            .copied()
            .filter(|&(c, _)| count[c].is_none())
            .collect();
        let least: usize = set + open.iter().map(|&(_, k)| k).sum::<usize>();
        if (open.is_empty() && set != f.count) || least > f.count {
            if free_blocks && f.count >= f.edges.len() {
                let own: Vec<(usize, usize)> = f.edges.iter().map(|&e| (e, 1)).collect();
                let shares = share_out(f.count, &own, targets);
                apart.extend(f.edges.iter().copied().zip(shares));
                continue;
            }
            return Err(Disagreement {
                count: f.count,
                chords_give: least,
            });
        }
        if open.is_empty() {
            continue;
        }
        let shares = share_out(f.count - set, &open, &mean);
        for (&(c, _), s) in open.iter().zip(shares) {
            count[c] = Some(s);
        }
        let total: usize = crossings
            .iter()
            .map(|&(c, k)| count[c].unwrap_or(0) * k)
            .sum();
        if total != f.count {
            return Err(Disagreement {
                count: f.count,
                chords_give: total,
            });
        }
    }
    let counts = count
        .iter()
        .zip(&mean)
        .map(|(c, m)| c.unwrap_or_else(|| (m.round() as usize).max(1)))
        .collect();
    Ok((counts, apart))
}

/// `total` shared among chords (or edges) crossing `k` times each, at
/// least 1 each, in proportion to their `mean` targets; what rounding leaves goes
/// to the largest remainders. Where the crossings make `total`
/// unreachable (a chord crossing twice takes an even part), the shares
/// come back short and the caller says so.
fn share_out(total: usize, open: &[(usize, usize)], mean: &[f64]) -> Vec<usize> {
    let weight: f64 = open
        .iter()
        .map(|&(c, k)| mean[c].max(1e-9) * k as f64)
        .sum();
    let spare = total - open.iter().map(|&(_, k)| k).sum::<usize>();
    let mut shares: Vec<(usize, f64)> = open
        .iter()
        .map(|&(c, _)| {
            let exact = spare as f64 * mean[c].max(1e-9) / weight;
            let whole = exact.floor() as usize;
            (1 + whole, exact - whole as f64)
        })
        .collect();
    let mut left = total
        - shares
            .iter()
            .zip(open)
            .map(|(s, &(_, k))| s.0 * k)
            .sum::<usize>();
    let mut order: Vec<usize> = (0..open.len()).collect();
    order.sort_by(|&a, &b| shares[b].1.total_cmp(&shares[a].1).then(a.cmp(&b)));
    for &i in order.iter().cycle().take(4 * open.len()) {
        let k = open[i].1;
        if left >= k {
            shares[i].0 += 1;
            left -= k;
        }
        if left == 0 {
            break;
        }
    }
    shares.into_iter().map(|s| s.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The layout edge between two corners.
    fn edge(c: &Chords, a: u32, b: u32) -> usize {
        c.edges
            .iter()
            .position(|&x| x == (a.min(b), a.max(b)))
            .expect("an edge of the layout")
    }

    /// Two blocks side by side: 0-1-4-3 and 1-2-5-4.
    fn two_blocks() -> Vec<[u32; 4]> {
        vec![[0, 1, 4, 3], [1, 2, 5, 4]]
    }

    #[test]
    fn two_blocks_side_by_side_have_three_chords() {
        let c = chords(&two_blocks());
        // across both: the bottoms and tops (one chord each block, tied
        // side 0 to side 2) and the three verticals tied into one chord
        assert_eq!(c.count, 3);
        let vertical = |a: u32, b: u32| c.chord_of[edge(&c, a, b)];
        assert_eq!(vertical(0, 3), vertical(1, 4));
        assert_eq!(vertical(1, 4), vertical(2, 5));
        assert_ne!(vertical(0, 1), vertical(1, 2));
        assert_eq!(vertical(0, 1), vertical(3, 4));
    }

    #[test]
    fn a_chord_aims_at_its_mean_target_and_a_fixed_count_is_shared() {
        let c = chords(&two_blocks());
        let e = |a: u32, b: u32| edge(&c, a, b);
        let mut targets = vec![0.0; c.edges.len()];
        for (a, b, t) in [
            (0, 1, 3.2),
            (3, 4, 2.8),
            (1, 2, 1.0),
            (4, 5, 1.0),
            (0, 3, 2.0),
            (1, 4, 2.2),
            (2, 5, 2.4),
        ] {
            targets[e(a, b)] = t;
        }
        let (n, _) = assign(&c, &targets, &[], false).unwrap();
        assert_eq!(n[c.chord_of[e(0, 1)]], 3);
        assert_eq!(n[c.chord_of[e(1, 2)]], 1);
        assert_eq!(n[c.chord_of[e(0, 3)]], 2);
        // the bottom fixed at 8: shared 3 to 1 as the targets say (6, 2)
        let fixed = [FixedCount {
            edges: vec![e(0, 1), e(1, 2)],
            count: 8,
        }];
        let (n, _) = assign(&c, &targets, &fixed, false).unwrap();
        assert_eq!(n[c.chord_of[e(0, 1)]] + n[c.chord_of[e(1, 2)]], 8);
        assert_eq!(n[c.chord_of[e(0, 1)]], 6);
    }

    #[test]
    fn a_disagreeing_fixed_count_can_be_kept_apart_for_a_free_block() {
        let c = chords(&[[0, 1, 2, 3]]);
        let e = |a: u32, b: u32| edge(&c, a, b);
        let fixed = [
            FixedCount {
                edges: vec![e(0, 1)],
                count: 12,
            },
            FixedCount {
                edges: vec![e(2, 3)],
                count: 6,
            },
        ];
        let (counts, apart) = assign(&c, &[4.0; 4], &fixed, true).unwrap();
        assert_eq!(counts[c.chord_of[e(0, 1)]], 12);
        assert_eq!(apart, vec![(e(2, 3), 6)]);
    }

    #[test]
    fn opposite_sides_fixed_at_different_counts_disagree() {
        let c = chords(&[[0, 1, 2, 3]]);
        let e = |a: u32, b: u32| edge(&c, a, b);
        let targets = vec![4.0; 4];
        let fixed = [
            FixedCount {
                edges: vec![e(0, 1)],
                count: 12,
            },
            FixedCount {
                edges: vec![e(2, 3)],
                count: 6,
            },
        ];
        assert_eq!(
            assign(&c, &targets, &fixed, false).map(|_| ()),
            Err(Disagreement {
                count: 6,
                chords_give: 12
            })
        );
    }
}
