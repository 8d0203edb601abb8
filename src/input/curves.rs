//! The geometry of a domain's boundary: an edge is a straight segment or
//! a circular arc (`Curve`); edges make loops and lines (`Chain`).

use glam::DVec2;

use crate::geometry::SegmentRelation;
use std::f64::consts::PI;

/// One edge of a loop or line: a straight segment or a circular arc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curve {
    /// Straight edge from `a` to `b`.
    Line {
        /// Start point.
        a: DVec2,
        /// End point.
        b: DVec2,
    },
    /// Circular arc from `a` to `b` with the DXF bulge tan(sweep/4),
    /// positive counter-clockwise.
    Arc {
        /// Start point.
        a: DVec2,
        /// End point.
        b: DVec2,
        /// tan(sweep / 4), signed.
        bulge: f64,
    },
    /// A full circle (a loop by itself), traversed counter-clockwise from
    /// angle 0.
    Circle {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
    },
}

impl Curve {
    /// Centre, radius, start angle and signed sweep of an arc.
    pub(crate) fn arc_frame(a: DVec2, b: DVec2, bulge: f64) -> (DVec2, f64, f64, f64) {
        let sweep = 4.0 * bulge.atan();
        let half = (b - a).length() / 2.0;
        let d = (b - a) / (2.0 * half);
        let left = DVec2::new(-d.y, d.x);
        let c = (a + b) / 2.0 + left * half * (1.0 - bulge * bulge) / (2.0 * bulge);
        let r = (a - c).length();
        let a0 = (a.y - c.y).atan2(a.x - c.x);
        (c, r, a0, sweep)
    }

    /// Length of the curve.
    pub fn length(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => (b - a).length(),
            Curve::Arc { a, b, bulge } => {
                let (_, r, _, sweep) = Self::arc_frame(a, b, bulge);
                r * sweep.abs()
            }
            Curve::Circle { radius, .. } => 2.0 * PI * radius,
        }
    }

    /// The point at parameter `t` in [0, 1] (uniform in arc length).
    pub fn point_at(&self, t: f64) -> DVec2 {
        match *self {
            // the end itself, not a + (b - a) * 1 (which may be off by an
            // ulp): a line that ends where another begins meets it exactly
            Curve::Line { b, .. } if t >= 1.0 => b,
            Curve::Line { a, b } => a + (b - a) * t,
            Curve::Arc { a, b, bulge } => {
                if t <= 0.0 {
                    return a;
                }
                if t >= 1.0 {
                    return b;
                }
                let (c, r, a0, sweep) = Self::arc_frame(a, b, bulge);
                let ang = a0 + sweep * t;
                c + r * DVec2::new(ang.cos(), ang.sin())
            }
            Curve::Circle { center, radius } => {
                let ang = 2.0 * PI * t;
                center + radius * DVec2::new(ang.cos(), ang.sin())
            }
        }
    }

    /// The parameter (as `point_at`'s) of the point of the curve closest
    /// to `p`.
    pub fn param_of(&self, p: DVec2) -> f64 {
        match *self {
            Curve::Line { a, b } => {
                let d = b - a;
                ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            }
            Curve::Arc { a, b, bulge } => {
                let (c, _, a0, sweep) = Self::arc_frame(a, b, bulge);
                let ang = (p.y - c.y).atan2(p.x - c.x);
                let rel = ((ang - a0) * sweep.signum()).rem_euclid(2.0 * PI);
                // past the end: the nearer end
                if rel <= sweep.abs() {
                    rel / sweep.abs()
                } else if rel - sweep.abs() < 2.0 * PI - rel {
                    1.0
                } else {
                    0.0
                }
            }
            Curve::Circle { center, .. } => {
                let v = p - center;
                (v.y.atan2(v.x) / (2.0 * PI)).rem_euclid(1.0)
            }
        }
    }

    /// The angle the curve turns through, unsigned (radians; 0 for a
    /// line, a full turn for a circle).
    pub fn sweep(&self) -> f64 {
        match *self {
            Curve::Line { .. } => 0.0,
            Curve::Arc { bulge, .. } => (4.0 * bulge.atan()).abs(),
            Curve::Circle { .. } => 2.0 * PI,
        }
    }

    /// The unit tangent at `p` on the curve, the way it runs (a to b;
    /// a circle counter-clockwise).
    pub fn tangent_at(&self, p: DVec2) -> DVec2 {
        match *self {
            Curve::Line { a, b } => (b - a).normalize_or_zero(),
            Curve::Arc { a, b, bulge } => {
                let (centre, ..) = Self::arc_frame(a, b, bulge);
                (p - centre).perp().normalize_or_zero() * bulge.signum()
            }
            Curve::Circle { center, .. } => (p - center).perp().normalize_or_zero(),
        }
    }

    /// Distance from `p` to the curve.
    pub fn distance(&self, p: DVec2) -> f64 {
        (self.project(p) - p).length()
    }

    /// Projects `p` onto the curve: the closest point on it.
    pub fn project(&self, p: DVec2) -> DVec2 {
        match *self {
            Curve::Line { a, b } => {
                let d = b - a;
                let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
                a + d * t
            }
            Curve::Circle { center, radius } => {
                let v = p - center;
                if v.length() < 1e-300 {
                    return center + DVec2::new(radius, 0.0);
                }
                center + v.normalize() * radius
            }
            Curve::Arc { a, b, bulge } => {
                let (c, r, a0, sweep) = Self::arc_frame(a, b, bulge);
                let ang = (p.y - c.y).atan2(p.x - c.x);
                let mut rel = (ang - a0) * sweep.signum();
                rel = rel.rem_euclid(2.0 * PI);
                if rel <= sweep.abs() {
                    let t = a0 + rel * sweep.signum();
                    c + r * DVec2::new(t.cos(), t.sin())
                } else if (p - a).length() < (p - b).length() {
                    a
                } else {
                    b
                }
            }
        }
    }

    /// `n` segments of (about) equal length: n+1 points, ends included
    /// (a circle: n points, the first not repeated).
    pub fn divide(&self, n: usize) -> Vec<DVec2> {
        match self {
            Curve::Circle { .. } => (0..n).map(|k| self.point_at(k as f64 / n as f64)).collect(),
            _ => (0..=n)
                .map(|k| self.point_at(k as f64 / n as f64))
                .collect(),
        }
    }

    /// The box round eight segments' points along the curve, grown by
    /// `by` on every side: lower and upper corners (for pairing edges
    /// that may come within `by` of each other).
    pub(crate) fn box_grown_by(&self, by: f64) -> (DVec2, DVec2) {
        let pts = self.divide(8);
        let lo = pts.iter().fold(DVec2::splat(f64::MAX), |m, p| m.min(*p));
        let hi = pts.iter().fold(DVec2::splat(f64::MIN), |m, p| m.max(*p));
        (lo - by, hi + by)
    }

    /// The signed area contribution (shoelace term plus the arc's segment).
    pub fn signed_area_term(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => 0.5 * a.perp_dot(b),
            Curve::Arc { a, b, bulge } => {
                let (_, r, _, sweep) = Self::arc_frame(a, b, bulge);
                0.5 * a.perp_dot(b)
                    + 0.5 * r * r * (sweep.abs() - sweep.abs().sin()) * sweep.signum()
            }
            Curve::Circle { radius, .. } => PI * radius * radius,
        }
    }
}

/// The fewest segments a curve may have: one per 60 deg of arc.
pub(crate) fn min_arc_segments(c: &Curve) -> usize {
    (c.sweep() / (PI / 3.0) - 1e-9).ceil().max(1.0) as usize
}

/// The fewest segments a curve of a domain of `area` may have: a circle
/// whose square of chords loses at most `SQUARE_CIRCLE_LOSS` of that
/// area takes four (a small hole: six chords there only ask for rings
/// of smaller elements round it), else `min_arc_segments`.
pub(crate) fn fewest_segments(c: &Curve, area: f64) -> usize {
    match *c {
        Curve::Circle { radius, .. }
            if (PI - 2.0) * radius * radius <= SQUARE_CIRCLE_LOSS * area =>
        {
            4
        }
        _ => min_arc_segments(c),
    }
}

/// The share of a domain's area a circle's square of chords may lose.
const SQUARE_CIRCLE_LOSS: f64 = 0.002;

/// An edge of a loop or line with its optional fixed segment count and tag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// The geometry of the edge.
    pub curve: Curve,
    /// Exact segment count, if the file fixes it.
    pub segments: Option<usize>,
    /// The edge's tag, an index into `Domain::tags` (format 1.1).
    pub tag: Option<u32>,
}

/// A closed loop (outer boundary or hole) or an open inner line.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// Its edges in order.
    pub edges: Vec<Edge>,
    /// Where it came from in the file, e.g. `holes[1]`, for messages.
    pub label: String,
    /// A line with `"crack": true`: the mesh is cut open along it.
    pub crack: bool,
}

impl Chain {
    /// Signed area enclosed (counter-clockwise positive); closed loops only.
    pub fn signed_area(&self) -> f64 {
        self.edges.iter().map(|e| e.curve.signed_area_term()).sum()
    }
}

/// The vertices of a chain: each edge's start, and a line's last point
/// (a circle has none).
pub(crate) fn chain_vertices(c: &Chain) -> Vec<DVec2> {
    let mut out: Vec<DVec2> = c
        .edges
        .iter()
        .filter_map(|e| match e.curve {
            Curve::Line { a, .. } | Curve::Arc { a, .. } => Some(a),
            Curve::Circle { .. } => None,
        })
        .collect();
    if let Some(Curve::Line { b, .. } | Curve::Arc { b, .. }) = c.edges.last().map(|e| e.curve) {
        // a loop's last edge ends where its first starts
        if out.first() != Some(&b) {
            out.push(b);
        }
    }
    out
}

/// The first (or, `at_end`, the last) point of a line.
pub(crate) fn line_end(line: &Chain, at_end: bool) -> DVec2 {
    let e = if at_end {
        line.edges.last()
    } else {
        line.edges.first()
    };
    match e.map(|e| e.curve) {
        Some(Curve::Line { a, b } | Curve::Arc { a, b, .. }) => {
            if at_end {
                b
            } else {
                a
            }
        }
        _ => DVec2::ZERO,
    }
}

/// Moves the first (or last) point of a line to `p`.
pub(crate) fn set_line_end(line: &mut Chain, at_end: bool, p: DVec2) {
    let e = if at_end {
        line.edges.last_mut()
    } else {
        line.edges.first_mut()
    };
    if let Some(Edge {
        curve: Curve::Line { a, b } | Curve::Arc { a, b, .. },
        ..
    }) = e
    {
        if at_end {
            *b = p;
        } else {
            *a = p;
        }
    }
}

/// A curve cut in two at a point `p` on it (or within the tolerance of
/// it); a circle becomes two half circles from `p` and back.
pub(crate) fn split_curve(c: Curve, p: DVec2) -> (Curve, Curve) {
    match c {
        Curve::Line { a, b } => (Curve::Line { a, b: p }, Curve::Line { a: p, b }),
        Curve::Arc { a, b, bulge } => {
            let (centre, _, a0, sweep) = Curve::arc_frame(a, b, bulge);
            let ang = (p.y - centre.y).atan2(p.x - centre.x);
            let first = ((ang - a0) * sweep.signum()).rem_euclid(2.0 * PI) * sweep.signum();
            (
                Curve::Arc {
                    a,
                    b: p,
                    bulge: (first / 4.0).tan(),
                },
                Curve::Arc {
                    a: p,
                    b,
                    bulge: ((sweep - first) / 4.0).tan(),
                },
            )
        }
        Curve::Circle { center, .. } => {
            let opposite = 2.0 * center - p;
            (
                Curve::Arc {
                    a: p,
                    b: opposite,
                    bulge: 1.0,
                },
                Curve::Arc {
                    a: opposite,
                    b: p,
                    bulge: 1.0,
                },
            )
        }
    }
}

/// The most decimals a coordinate or radius of the chains has, as the
/// shortest text that reads back as the same number: a point quoted in a
/// message gets no more digits than the input has.
pub(crate) fn input_decimals<'a>(chains: impl Iterator<Item = &'a Chain>) -> usize {
    let decimals = |x: f64| {
        let text = x.to_string();
        text.split_once('.')
            .map_or(0, |(_, fraction)| fraction.len())
    };
    let mut most = 0;
    for e in chains.flat_map(|c| &c.edges) {
        let numbers = match e.curve {
            Curve::Line { a, b } | Curve::Arc { a, b, .. } => [a.x, a.y, b.x, b.y],
            Curve::Circle { center, radius } => [center.x, center.y, radius, 0.0],
        };
        most = numbers.into_iter().map(decimals).fold(most, usize::max);
    }
    most
}

/// Where two segments that are not disjoint meet: the point where they
/// cross, or for a touch or an overlap an end of one that lies on the other.
pub(crate) fn meeting_point(
    p1: DVec2,
    p2: DVec2,
    q1: DVec2,
    q2: DVec2,
    rel: SegmentRelation,
) -> DVec2 {
    let (dp, dq) = (p2 - p1, q2 - q1);
    let denominator = dp.perp_dot(dq);
    if rel == SegmentRelation::Cross && denominator != 0.0 {
        return p1 + dp * ((q1 - p1).perp_dot(dq) / denominator);
    }
    let on = |a: DVec2, b: DVec2, p: DVec2| {
        crate::geometry::orient2d(a, b, p) == 0.0
            && p.x >= a.x.min(b.x)
            && p.x <= a.x.max(b.x)
            && p.y >= a.y.min(b.y)
            && p.y <= a.y.max(b.y)
    };
    [(q1, p1, p2), (q2, p1, p2), (p1, q1, q2), (p2, q1, q2)]
        .into_iter()
        .find(|&(p, a, b)| on(a, b, p))
        .map_or(p1, |(p, _, _)| p)
}

/// `at (x, y)` with `decimals` decimals, or `near (x, y)` where that
/// rounds the point.
pub(crate) fn point_text(p: DVec2, decimals: usize) -> String {
    let number = |v: f64| {
        let text = format!("{v:.decimals$}");
        // -0 reads as a typo
        let text = if text.trim_start_matches(['-', '0', '.']).is_empty() {
            text.trim_start_matches('-').to_string()
        } else {
            text
        };
        let exact = text.parse::<f64>() == Ok(v);
        (text, exact)
    };
    let ((x, x_exact), (y, y_exact)) = (number(p.x), number(p.y));
    let word = if x_exact && y_exact { "at" } else { "near" };
    format!("{word} ({x}, {y})")
}

/// Where two curves that follow each other (`first` ends where `second`
/// starts) meet again, other than at their shared point: an arc that
/// leaves a corner almost backwards along the edge before it crosses it a
/// little further on, closer than any polyline check of the arc sees.
/// Points within `tol` of the shared point are a tangent touch, not a
/// crossing. Two lines meet again only by overlapping, which the segment
/// checks see.
pub(crate) fn second_meeting(first: &Curve, second: &Curve, tol: f64) -> Option<DVec2> {
    let on_arc = |c: &Curve, p: DVec2| match *c {
        Curve::Arc { a, b, bulge } => {
            let (centre, _, a0, sweep) = Curve::arc_frame(a, b, bulge);
            let ang = (p.y - centre.y).atan2(p.x - centre.x);
            let rel = ((ang - a0) * sweep.signum()).rem_euclid(2.0 * PI);
            rel <= sweep.abs() + 1e-12
        }
        _ => false,
    };
    let circle = |c: &Curve| match *c {
        Curve::Arc { a, b, bulge } => Some(Curve::arc_frame(a, b, bulge).0),
        _ => None,
    };
    let vertex = match *second {
        Curve::Line { a, .. } | Curve::Arc { a, .. } => a,
        Curve::Circle { .. } => return None,
    };
    let hit = match (circle(first), circle(second)) {
        (None, None) => return None,
        (Some(c1), Some(c2)) => {
            // two circles through V meet again at V mirrored in the line
            // of their centres
            let axis = c2 - c1;
            if axis.length_squared() == 0.0 {
                return None;
            }
            let foot = c1 + axis * ((vertex - c1).dot(axis) / axis.length_squared());
            2.0 * foot - vertex
        }
        (Some(c), None) | (None, Some(c)) => {
            // the line through V meets the circle again at s = -2 d.(V - c)
            let (line_from, line_to) = match (*first, *second) {
                (Curve::Line { a, b }, _) => (b, a),
                (_, Curve::Line { a, b }) => (a, b),
                _ => return None,
            };
            let len = (line_to - line_from).length();
            if len == 0.0 {
                return None;
            }
            let d = (line_to - line_from) / len;
            let s = -2.0 * d.dot(vertex - c);
            if s > len + tol {
                return None;
            }
            vertex + d * s
        }
    };
    let within = |c: &Curve| match *c {
        Curve::Line { a, b } => {
            let d = b - a;
            let t = (hit - a).dot(d) / d.length_squared();
            (-1e-12..=1.0 + 1e-12).contains(&t)
        }
        _ => on_arc(c, hit),
    };
    ((hit - vertex).length() > tol && within(first) && within(second)).then_some(hit)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(a: [f64; 2], b: [f64; 2], bulge: f64) -> Curve {
        Curve::Arc {
            a: DVec2::from(a),
            b: DVec2::from(b),
            bulge,
        }
    }
    fn line(a: [f64; 2], b: [f64; 2]) -> Curve {
        Curve::Line {
            a: DVec2::from(a),
            b: DVec2::from(b),
        }
    }

    #[test]
    fn a_small_circle_takes_four_chords_and_a_large_one_six() {
        let circle = |radius| Curve::Circle {
            center: DVec2::ZERO,
            radius,
        };
        // a square of chords loses (pi - 2) r^2: 0.1% of 100 here
        assert_eq!(fewest_segments(&circle(0.3), 100.0), 4);
        // 11% of 10: six chords, as any full turn of arc
        assert_eq!(fewest_segments(&circle(1.0), 10.0), 6);
        assert_eq!(min_arc_segments(&circle(0.3)), 6);
    }

    #[test]
    fn an_arc_leaving_a_corner_backwards_crosses_the_line_before_it() {
        // the arc starts 0.8 degrees off the line it came along and curves
        // back across it 0.087 from the corner
        let l = line([1.369494, 0.836582], [-0.801826, -1.23605]);
        let a = arc([-0.801826, -1.23605], [1.528682, -0.388674], -0.2173);
        let p = second_meeting(&l, &a, 1e-6).expect("a crossing");
        assert!((p - DVec2::new(-0.801826, -1.23605)).length() > 0.08);
        assert!((l.project(p) - p).length() < 1e-9 && (a.project(p) - p).length() < 1e-9);
        // the same arc curving the other way leaves the line for good
        let away = arc([-0.801826, -1.23605], [1.528682, -0.388674], 0.2173);
        assert_eq!(second_meeting(&l, &away, 1e-6), None);
    }

    #[test]
    fn edges_that_only_share_their_corner_do_not_meet_again() {
        // a rounded corner: an arc tangent to the line before it
        let l = line([0.0, 0.0], [1.0, 0.0]);
        let quarter = arc([1.0, 0.0], [2.0, 1.0], (PI / 8.0).tan());
        assert_eq!(second_meeting(&l, &quarter, 1e-9), None);
        // two arcs bulging apart from a common point
        let a1 = arc([0.0, 0.0], [1.0, 0.0], 0.3);
        let a2 = arc([1.0, 0.0], [2.0, 0.0], 0.3);
        assert_eq!(second_meeting(&a1, &a2, 1e-9), None);
        // a half disc: the line and the arc meet again at its other corner,
        // past the end of the line
        let half = arc([1.0, 0.0], [0.0, 0.0], 1.0);
        assert!(second_meeting(&l, &half, 1e-9).is_some_and(|p| p.length() < 1e-9));
    }

    #[test]
    fn two_arcs_that_cross_after_their_common_point_are_found() {
        // a small arc going out and curving back across a large one
        let big = arc([-1.0, 0.0], [0.0, 0.0], -0.05);
        let back = arc([0.0, 0.0], [-0.5, -0.05], 0.9);
        assert!(second_meeting(&big, &back, 1e-9).is_some());
    }
}
