//! Inner lines near another part of the boundary: an edge of an inner
//! line that comes nearer another loop or line than `bound(line_gap, F)`
//! element sizes (one it does not touch) gets segments as long as that
//! gap, not under `bound(line_gap_floor, G)` sizes. A line's end a fifth
//! of the size from a small hole, in one segment, leaves the fronts a
//! gap they can only bridge with a sliver; in segments of the gap the
//! elements between grow from it.

use glam::DVec2;

use crate::input::domain::{Curve, Domain};

/// Samples along a line's edge where the gap is measured (ends included).
const SAMPLES: usize = 32;

/// The segment counts of the inner lines' edges near another chain,
/// raised to the edge's length over the gap (`counts` and `fixed` by
/// chain: loops, then lines). Returns how many edges were given more.
pub(crate) fn refine_lines_near_others(
    domain: &Domain,
    size: f64,
    (line_gap, floor): (f64, f64),
    fixed: &[Vec<bool>],
    counts: &mut [Vec<usize>],
) -> usize {
    if line_gap <= 0.0 || domain.lines.is_empty() {
        return 0;
    }
    let reach = line_gap * size;
    let loops = 1 + domain.holes.len();
    let chains: Vec<Vec<(Curve, DVec2, DVec2)>> = domain
        .chains()
        .map(|c| {
            c.edges
                .iter()
                .map(|e| {
                    let (lo, hi) = e.curve.box_grown_by(reach);
                    (e.curve, lo, hi)
                })
                .collect()
        })
        .collect();
    let mut refined = 0;
    for (li, line) in domain.lines.iter().enumerate() {
        let ci = loops + li;
        let ends: Vec<DVec2> = line
            .edges
            .iter()
            .flat_map(|e| [e.curve.point_at(0.0), e.curve.point_at(1.0)])
            .collect();
        // the chains this line touches (ends on them) are not gaps
        let apart: Vec<usize> = (0..chains.len())
            .filter(|&cj| cj != ci)
            .filter(|&cj| {
                !chains[cj].iter().any(|(c, _, _)| {
                    ends.iter()
                        .any(|&p| c.distance(p) <= 1e-9 * size.max(p.abs().max_element()))
                })
            })
            .collect();
        for (ei, e) in line.edges.iter().enumerate() {
            if fixed[ci][ei] {
                continue;
            }
            let (lo, hi) = e.curve.box_grown_by(0.0);
            let samples: Vec<DVec2> = (0..=SAMPLES)
                .map(|k| e.curve.point_at(k as f64 / SAMPLES as f64))
                .collect();
            let gap = apart
                .iter()
                .flat_map(|&cj| &chains[cj])
                .filter(|(_, clo, chi)| clo.cmplt(hi).all() && lo.cmplt(*chi).all())
                .flat_map(|(c, _, _)| samples.iter().map(move |&p| c.distance(p)))
                .fold(f64::INFINITY, f64::min);
            if gap >= reach {
                continue;
            }
            let step = gap.max(floor * size);
            let n = (e.curve.length() / step).round() as usize;
            if n > counts[ci][ei] {
                counts[ci][ei] = n;
                refined += 1;
            }
        }
    }
    refined
}

#[cfg(test)]
mod tests {
    use super::refine_lines_near_others;
    use crate::input::domain::Domain;

    /// The counts of the domain's one inner line once refined (loops and
    /// line one segment an edge before), and how many edges were.
    fn line_counts(text: &str, line_gap: f64) -> (Vec<usize>, usize) {
        let domain = Domain::from_json_str(text).unwrap();
        let mut counts: Vec<Vec<usize>> = domain.chains().map(|c| vec![1; c.edges.len()]).collect();
        let fixed: Vec<Vec<bool>> = counts.iter().map(|r| vec![false; r.len()]).collect();
        let refined = refine_lines_near_others(&domain, 1.0, (line_gap, 0.25), &fixed, &mut counts);
        (counts.last().unwrap().clone(), refined)
    }

    /// A line of 1.2 sizes whose end is 0.4 from a small hole is divided
    /// in segments of about 0.4 (3); 0.1 from it, in segments of the
    /// floor, a quarter of the size (5); with `bound(line_gap, 0)`, or
    /// with the hole away, it keeps its one.
    #[test]
    fn a_line_near_a_hole_is_divided_in_segments_of_the_gap() {
        let with_gap = |gap: f64| {
            format!(
                r#"{{"size": 1, "outer": {{"points": [[-5, -5], [5, -5], [5, 5], [-5, 5]]}},
                    "holes": [{{"circle": {{"center": [{}, 0], "radius": 0.3}}}}],
                    "lines": [{{"points": [[-1.2, 0], [0, 0]]}}]}}"#,
                0.3 + gap
            )
        };
        assert_eq!(line_counts(&with_gap(0.4), 1.0), (vec![3], 1));
        assert_eq!(line_counts(&with_gap(0.1), 1.0), (vec![5], 1));
        assert_eq!(line_counts(&with_gap(0.1), 0.0), (vec![1], 0));
        assert_eq!(line_counts(&with_gap(3.0), 1.0), (vec![1], 0));
    }

    /// A loop the line ends on is no gap: a line from the outer loop
    /// into the domain keeps its count.
    #[test]
    fn a_line_ending_on_a_loop_keeps_its_count() {
        let (counts, refined) = line_counts(
            r#"{"size": 1, "outer": {"points": [[0, 0], [6, 0], [6, 6], [0, 6]]},
                "lines": [{"points": [[0, 3], [2.2, 3]]}]}"#,
            1.0,
        );
        assert_eq!((counts, refined), (vec![1], 0));
    }
}
