//! How many segments each edge of the domain gets: its length over the
//! size (or the count the input fixes), at least one per 60 degrees of
//! arc, one count for edges facing each other across a thin wall, an
//! inner line's edge near another chain in segments of the gap, and an
//! even total.

use crate::input::curves::fewest_segments;
use crate::input::domain::{Domain, DomainError, MAX_BOUNDARY_SEGMENTS};
use crate::input::line_gaps::refine_lines_near_others;
use crate::input::thin_walls::match_facing_counts;
use crate::settings::HostBounds;

/// The knowledge base's bounds the segment counts follow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CountBounds {
    /// `bound(thin_wall, K)` (see thin_walls.rs); 0: never.
    pub thin_wall: f64,
    /// `bound(line_gap, F)` (see line_gaps.rs); 0: never.
    pub line_gap: f64,
    /// `bound(line_gap_floor, G)` (see line_gaps.rs).
    pub line_gap_floor: f64,
}

impl CountBounds {
    /// The counts' bounds of a knowledge base's host bounds.
    pub fn of(host: &HostBounds) -> CountBounds {
        CountBounds {
            thin_wall: host.thin_wall,
            line_gap: host.line_gap,
            line_gap_floor: host.line_gap_floor,
        }
    }

    /// Every edge its length over the size: no walls matched, no line
    /// refined.
    #[cfg(test)]
    pub const PLAIN: CountBounds = CountBounds {
        thin_wall: 0.0,
        line_gap: 0.0,
        line_gap_floor: 1.0,
    };
}

/// What the counts' bounds changed: the edges given one count across a
/// thin wall, and the inner lines' edges given segments of a gap.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CountsChanged {
    /// Edges in a thin wall's group.
    pub walled: usize,
    /// Inner lines' edges given more segments near another chain.
    pub near_lines: usize,
}

/// The segment count of every edge of every chain (outer, holes, lines in
/// that order), with an even total: edges facing each other across a wall
/// thinner than `bounds.thin_wall` element sizes get one count (see
/// thin_walls.rs), an inner line's edge near another chain segments of
/// the gap (line_gaps.rs); where the total of the derived counts is odd,
/// the free edge of a loop with the longest segments gets one more,
/// outside the walls where it can. Returns the counts and what the
/// bounds changed.
pub(crate) fn segment_counts(
    domain: &Domain,
    size: f64,
    bounds: CountBounds,
) -> Result<(Vec<Vec<usize>>, CountsChanged), DomainError> {
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
    let near_lines = refine_lines_near_others(
        domain,
        size,
        (bounds.line_gap, bounds.line_gap_floor),
        &fixed,
        &mut counts,
    );
    let in_wall = match_facing_counts(domain, size, bounds.thin_wall, &fixed, &mut counts);
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
    Ok((counts, CountsChanged { walled, near_lines }))
}
