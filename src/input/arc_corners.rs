//! The first segments of an arc at an input corner. The element at a
//! corner has the chords' angle there, not the curves': an arc bulging
//! out of the domain makes it sharper by half its first segment's sweep
//! (a 37.8-degree tip is 36.7 at a segment of the size), one bulging in
//! makes it wider. Where the chords would take the corner more than
//! `bound(corner_slack, D)` degrees below the lower of the corner itself
//! and the window's lower corner (or above the window's upper corner,
//! the corner being inside it), the arc's segments grow from a shorter
//! first one, the edge keeping its segment count, until the chords are
//! within `bound(arc_corner_chord, D)` of it. A tip sharper than
//! `bound(arc_corner_from, D)` keeps its segments: there the element is
//! long and thin whatever its chords, its taper the bound that binds.

use glam::DVec2;

use crate::geometry::interior_angle;
use crate::input::domain::{Chain, Curve, Domain};
use crate::settings::{ElementBounds, HostBounds};

/// What the chords at a corner are held to (degrees), and how fast the
/// segments of an arc may grow from a shorter first one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerAim {
    /// The window's lower corner.
    pub lower: f64,
    /// The window's upper corner.
    pub upper: f64,
    /// `bound(corner_slack, D)`: how far past the aim a chord may be
    /// before the segments are shortened (the corner counts as within).
    pub slack: f64,
    /// `bound(arc_corner_chord, D)`: how far past the aim a chord may be
    /// once they are.
    pub chord: f64,
    /// `bound(arc_corner_from, D)`: a corner sharper keeps its segments.
    pub from: f64,
    /// The largest ratio of two neighbouring segments of an arc (the
    /// square root of `max_size_jump`: their elements' sizes).
    pub growth: f64,
}

impl CornerAim {
    /// From the KB's bounds: its window, `arc_corner_chord`, and growth
    /// the square root of `max_size_jump`.
    pub fn of(host: &HostBounds, element: &ElementBounds) -> CornerAim {
        CornerAim {
            lower: element.lower_corner,
            upper: element.upper_corner,
            slack: host.corner_slack,
            chord: host.arc_corner_chord,
            from: host.arc_corner_from,
            growth: element.max_size_jump.sqrt(),
        }
    }

    /// The paper's window, the built-in chord bound and a size jump of 2:
    /// for tests that discretise by hand.
    #[cfg(test)]
    pub(crate) fn paper() -> CornerAim {
        CornerAim {
            lower: 45.0,
            upper: 135.0,
            slack: 0.5,
            chord: 0.2,
            from: 15.0,
            growth: std::f64::consts::SQRT_2,
        }
    }
}

/// The shortest first segment tried, as a share of the uniform one.
const SHORTEST_SHARE: f64 = 0.3;

/// Each step of the search for the first segment's share.
const SHARE_STEP: f64 = 0.8;

/// The longest an arc's middle segments may grow (times the uniform
/// segment) to make room for shorter ones at its ends.
const LONGEST_MIDDLE: f64 = 1.5;

/// For each edge of a loop (`closed`; a line has the domain on both sides
/// and keeps its uniform segments), the first and last segments' shares
/// of the edge's uniform segment: 1 where the chords keep the corner.
/// `domain_left`: whether the domain lies left of the chain as written.
pub(crate) fn end_shares(
    chain: &Chain,
    counts: &[usize],
    closed: bool,
    domain_left: bool,
    aim: &CornerAim,
) -> Vec<[f64; 2]> {
    let m = chain.edges.len();
    let mut shares = vec![[1.0, 1.0]; m];
    if !closed || m < 2 || aim.chord <= 0.0 {
        return shares;
    }
    for k in 0..m {
        let (before, after) = ((k + m - 1) % m, k);
        let (ep, en) = (&chain.edges[before].curve, &chain.edges[after].curve);
        let (is_arc_p, is_arc_n) = (is_arc(ep), is_arc(en));
        if !is_arc_p && !is_arc_n {
            continue;
        }
        let (np, nn) = (counts[before], counts[after]);
        let v = en.point_at(0.0);
        let angle = |prev: DVec2, next: DVec2| side_angle(prev, v, next, domain_left);
        let t_in = travel_tangent(ep, v, v - ep.point_at(1.0 - 1.0 / np as f64));
        let t_out = travel_tangent(en, v, en.point_at(1.0 / nn as f64) - v);
        let corner = angle(v - t_in, v + t_out);
        if corner < aim.from {
            continue;
        }
        let window = |past: f64| {
            let high = if corner <= aim.upper {
                aim.upper + past
            } else {
                f64::INFINITY
            };
            (corner.min(aim.lower) - past, high)
        };
        // the arcs' first segments shortened to `f`, a line's beside them
        // as near `f` as its segments allow, so that the element at the
        // corner has sides of about one length (an edge of one segment
        // keeps it)
        let fits_before =
            |f: f64| np >= 2 && graded_params(np, shares[before][0], f, aim.growth).is_some();
        let fits_after =
            |f: f64| nn >= 2 && graded_params(nn, f, shares[after][1], aim.growth).is_some();
        let share = |f: f64, arc: bool, fits: &dyn Fn(f64) -> bool| {
            let mut g = f;
            while !arc && !fits(g) && g < 1.0 {
                g = (g / SHARE_STEP).min(1.0);
            }
            g
        };
        let shares_at = |f: f64| {
            (
                share(f, is_arc_p, &fits_before),
                share(f, is_arc_n, &fits_after),
            )
        };
        let chord_at = |f: f64| {
            let (fp, fnx) = shares_at(f);
            angle(
                ep.point_at(1.0 - fp / np as f64),
                en.point_at(fnx / nn as f64),
            )
        };
        let within = |a: f64, (low, high): (f64, f64)| a >= low && a <= high;
        if within(chord_at(1.0), window(aim.slack)) {
            continue;
        }
        let arcs_fit = |f: f64| (!is_arc_p || fits_before(f)) && (!is_arc_n || fits_after(f));
        let mut chosen = None;
        let mut f = SHARE_STEP;
        while f >= SHORTEST_SHARE && arcs_fit(f) {
            chosen = Some(f);
            if within(chord_at(f), window(aim.chord)) {
                break;
            }
            f *= SHARE_STEP;
        }
        if let Some(f) = chosen {
            let (fp, fnx) = shares_at(f);
            if np > 1 {
                shares[before][1] = fp;
            }
            if nn > 1 {
                shares[after][0] = fnx;
            }
        }
    }
    shares
}

/// The corner (deg, the domain's side) at each vertex of the loops, as
/// the curves' tangents make it there: what an element at the corner is
/// measured against.
pub(crate) fn loop_corners(domain: &Domain) -> Vec<(DVec2, f64)> {
    let mut corners = Vec::new();
    let loops =
        std::iter::once((&domain.outer, true)).chain(domain.holes.iter().map(|h| (h, false)));
    for (chain, outer) in loops {
        let domain_left = (chain.signed_area() > 0.0) == outer;
        let m = chain.edges.len();
        for k in 0..m {
            let (ep, en) = (&chain.edges[(k + m - 1) % m].curve, &chain.edges[k].curve);
            if matches!(en, Curve::Circle { .. }) {
                continue;
            }
            let v = en.point_at(0.0);
            let t_in = travel_tangent(ep, v, v - ep.point_at(0.5));
            let t_out = travel_tangent(en, v, en.point_at(0.5) - v);
            corners.push((v, side_angle(v - t_in, v, v + t_out, domain_left)));
        }
    }
    corners
}

/// The angle (deg) at `v` from `prev` to `next` on the domain's side.
fn side_angle(prev: DVec2, v: DVec2, next: DVec2, domain_left: bool) -> f64 {
    let a = if domain_left {
        interior_angle(prev, v, next)
    } else {
        interior_angle(next, v, prev)
    };
    a.to_degrees()
}

fn is_arc(c: &Curve) -> bool {
    matches!(c, Curve::Arc { .. })
}

/// The unit tangent of a curve at `p` on it, the way `along` runs.
fn travel_tangent(c: &Curve, p: DVec2, along: DVec2) -> DVec2 {
    let t = c.tangent_at(p);
    if t.dot(along) < 0.0 {
        -t
    } else {
        t
    }
}

/// The parameters of the `n + 1` points of a curve whose first and last
/// segments are `first` and `last` times the uniform one (1: as the
/// others) and the others grow from them by at most `growth` a segment
/// up to a common length (at most `LONGEST_MIDDLE` uniform ones); None
/// if `n` segments cannot.
pub(crate) fn graded_params(n: usize, first: f64, last: f64, growth: f64) -> Option<Vec<f64>> {
    // an end of share 1 is not held: its segments take the common length
    let from = |share: f64, k: usize| {
        if share >= 1.0 {
            f64::INFINITY
        } else {
            share * growth.powi(k as i32)
        }
    };
    let length = |j: usize, u: f64| from(first, j).min(from(last, n - 1 - j)).min(u);
    let total = |u: f64| (0..n).map(|j| length(j, u)).sum::<f64>();
    if total(LONGEST_MIDDLE) < n as f64 {
        return None;
    }
    // the common length u that makes the segments add up to the edge
    let (mut lo, mut hi) = (0.0, LONGEST_MIDDLE);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if total(mid) < n as f64 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut params = Vec::with_capacity(n + 1);
    let mut at = 0.0;
    params.push(0.0);
    for j in 0..n - 1 {
        at += length(j, hi) / n as f64;
        params.push(at);
    }
    params.push(1.0);
    Some(params)
}

/// `n` segments of a curve from the `end_shares` of its edge: uniform
/// where both are 1.
pub(crate) fn divide(curve: &Curve, n: usize, shares: [f64; 2], growth: f64) -> Vec<DVec2> {
    if shares == [1.0, 1.0] || n < 2 {
        return curve.divide(n);
    }
    match graded_params(n, shares[0], shares[1], growth) {
        Some(params) => params.into_iter().map(|t| curve.point_at(t)).collect(),
        None => curve.divide(n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_segments_add_up_and_grow_within_the_bound() {
        let p = graded_params(10, 0.3, 1.0, 1.4).unwrap();
        assert_eq!(p.len(), 11);
        let seg: Vec<f64> = p.windows(2).map(|w| w[1] - w[0]).collect();
        assert!((seg[0] - 0.3 / 10.0).abs() < 1e-12);
        for w in seg.windows(2) {
            assert!(w[1] / w[0] <= 1.4 + 1e-9, "{seg:?}");
            assert!(w[1] >= w[0] - 1e-12, "{seg:?}");
        }
        assert!(
            seg.iter().all(|&l| l <= LONGEST_MIDDLE / 10.0 + 1e-12),
            "{seg:?}"
        );
        assert_eq!(p[10], 1.0);
        // too few segments to grow from a tenth
        assert!(graded_params(2, 0.1, 1.0, 1.4).is_none());
    }
}
