//! How many segments each edge of the domain gets: its length over the
//! size (or the count the input fixes), at least one per 60 degrees of
//! arc, one count for edges facing each other across a thin wall, and an
//! even total.

use crate::input::curves::fewest_segments;
use crate::input::domain::{Domain, DomainError, MAX_BOUNDARY_SEGMENTS};
use crate::input::thin_walls::match_facing_counts;

/// The segment count of every edge of every chain (outer, holes, lines in
/// that order), with an even total: edges facing each other across a wall
/// thinner than `wall` element sizes get one count (see thin_walls.rs);
/// where the total of the derived counts is odd, the free edge of a loop
/// with the longest segments gets one more, outside the walls where it can.
/// Returns the counts and how many edges a wall's matching covers.
pub(crate) fn segment_counts(
    domain: &Domain,
    size: f64,
    wall: f64,
) -> Result<(Vec<Vec<usize>>, usize), DomainError> {
    let mut counts = Vec::new();
    let mut fixed = Vec::new();
    let area = domain.area();
    for chain in domain.chains() {
        let mut row = Vec::new();
        for (ei, e) in chain.edges.iter().enumerate() {
            let n = match e.segments {
                Some(n) => n,
                None => {
                    let est = (e.curve.length() / size).round();
                    if !est.is_finite() || est > MAX_BOUNDARY_SEGMENTS as f64 {
                        return Err(DomainError::Geometry(format!(
                            "{} edge {ei}: size {size} gives about {est:.3e} segments, above the limit of {MAX_BOUNDARY_SEGMENTS}",
                            chain.label
                        )));
                    }
                    // No segment spans more than 60 deg of arc, so the
                    // chords stay close to the curve: a circle gets at
                    // least 6 (4 if it is small in the domain), a half
                    // circle 3.
                    (est as usize).max(1).max(fewest_segments(&e.curve, area))
                }
            };
            row.push(n);
        }
        fixed.push(
            chain
                .edges
                .iter()
                .map(|e| e.segments.is_some())
                .collect::<Vec<_>>(),
        );
        counts.push(row);
    }
    let in_wall = match_facing_counts(domain, size, wall, &fixed, &mut counts);
    let n_loops = 1 + domain.holes.len();
    let mut total: u128 = 0;
    // (outside the walls, segment length, chain, edge) of the free edges
    // of loops: the last is the one to get a segment more
    let mut best_free: Option<(bool, f64, usize, usize)> = None;
    for (ci, (chain, row)) in domain.chains().zip(&counts).enumerate() {
        for (ei, (e, &n)) in chain.edges.iter().zip(row).enumerate() {
            total += n as u128 * if ci >= n_loops { 2 } else { 1 };
            if ci < n_loops && !fixed[ci][ei] {
                let cand = (!in_wall[ci][ei], e.curve.length() / n as f64, ci, ei);
                if best_free.is_none_or(|b| cand >= b) {
                    best_free = Some(cand);
                }
            }
        }
    }
    if total > MAX_BOUNDARY_SEGMENTS as u128 {
        return Err(DomainError::Geometry(format!(
            "{total} boundary segments is above the limit of {MAX_BOUNDARY_SEGMENTS}"
        )));
    }
    if total % 2 == 1 {
        match best_free {
            Some((_, _, ci, ei)) => counts[ci][ei] += 1,
            None => {
                let per: Vec<String> = domain
                    .chains()
                    .zip(&counts)
                    .map(|(c, r)| format!("{} {}", c.label, r.iter().sum::<usize>()))
                    .collect();
                return Err(DomainError::Geometry(format!(
                    "the fixed segment counts total {total}, which is odd: no all-quad mesh exists ({})",
                    per.join(", ")
                )));
            }
        }
    }
    let walled = in_wall.iter().flatten().filter(|&&w| w).count();
    Ok((counts, walled))
}
