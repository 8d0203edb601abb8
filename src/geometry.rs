//! Plane geometry with robust predicates: orient2d, segment relations,
//! interior angles and the point-segment relation of the paper (Fig. 10).
//!
//! Signs near zero are decided by Shewchuk's adaptive-precision `orient2d`
//! (the `robust` crate), never by a plain floating-point product.

use glam::DVec2;

fn coord(p: DVec2) -> robust::Coord<f64> {
    robust::Coord { x: p.x, y: p.y }
}

/// Twice the signed area of triangle `abc`, computed exactly enough that its
/// sign is right (Shewchuk's orient2d).
pub fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// How two closed segments meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentRelation {
    /// No common point.
    Disjoint,
    /// They share exactly one point that is an end of at least one of them.
    Touch,
    /// They cross at one point interior to both.
    Cross,
    /// They are collinear and share more than one point.
    Overlap,
}

fn on_segment(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// The relation of segments `p1p2` and `q1q2`.
///
/// Degenerate (zero-length) segments are treated as points.
pub fn segments_intersect(p1: DVec2, p2: DVec2, q1: DVec2, q2: DVec2) -> SegmentRelation {
    let d1 = orient2d(q1, q2, p1);
    let d2 = orient2d(q1, q2, p2);
    let d3 = orient2d(p1, p2, q1);
    let d4 = orient2d(p1, p2, q2);
    if d1 == 0.0 && d2 == 0.0 && d3 == 0.0 && d4 == 0.0 {
        // Collinear: compare the projections on the longer direction.
        let dir = if (p2 - p1).length_squared() >= (q2 - q1).length_squared() {
            p2 - p1
        } else {
            q2 - q1
        };
        if dir == DVec2::ZERO {
            return if p1 == q1 {
                SegmentRelation::Touch
            } else {
                SegmentRelation::Disjoint
            };
        }
        let (a0, a1) = {
            let (s, t) = (p1.dot(dir), p2.dot(dir));
            (s.min(t), s.max(t))
        };
        let (b0, b1) = {
            let (s, t) = (q1.dot(dir), q2.dot(dir));
            (s.min(t), s.max(t))
        };
        let lo = a0.max(b0);
        let hi = a1.min(b1);
        return if lo > hi {
            SegmentRelation::Disjoint
        } else if lo == hi {
            SegmentRelation::Touch
        } else {
            SegmentRelation::Overlap
        };
    }
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return SegmentRelation::Cross;
    }
    if (d1 == 0.0 && on_segment(q1, q2, p1))
        || (d2 == 0.0 && on_segment(q1, q2, p2))
        || (d3 == 0.0 && on_segment(p1, p2, q1))
        || (d4 == 0.0 && on_segment(p1, p2, q2))
    {
        return SegmentRelation::Touch;
    }
    SegmentRelation::Disjoint
}

/// True iff `p` lies inside the closed polygon `poly` (even-odd rule;
/// points on the boundary may go either way).
pub fn point_in_polygon(p: DVec2, poly: &[DVec2]) -> bool {
    let mut inside = false;
    let n = poly.len();
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// Signed area of a polygon (counter-clockwise positive).
pub fn polygon_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| poly[i].perp_dot(poly[(i + 1) % n]))
        .sum::<f64>()
        / 2.0
}

/// The interior angle (radians, in (0, 2π]) at `v` of a boundary walked
/// `prev` → `v` → `next` with the domain on the left: the counter-clockwise
/// turn from the direction to `next` round to the direction to `prev`.
///
/// A slit tip (`prev == next`) gives 2π; a straight run gives π.
pub fn interior_angle(prev: DVec2, v: DVec2, next: DVec2) -> f64 {
    let a = next - v;
    let b = prev - v;
    let ang = a.perp_dot(b).atan2(a.dot(b));
    if ang <= 0.0 {
        ang + 2.0 * std::f64::consts::PI
    } else {
        ang
    }
}

/// The two distances of the paper's point-segment relation (Fig. 10): the
/// vertical one, from `p` to the line through `a`,`b`, and the horizontal
/// one, how far the foot of `p` falls outside the segment along it (0 when
/// it falls between `a` and `b`).
pub fn point_segment_distances(p: DVec2, a: DVec2, b: DVec2) -> (f64, f64) {
    let d = b - a;
    let len = d.length();
    if len == 0.0 {
        let dist = (p - a).length();
        return (dist, dist);
    }
    let u = d / len;
    let t = (p - a).dot(u);
    let vertical = (p - a).perp_dot(u).abs();
    let horizontal = if t < 0.0 {
        -t
    } else if t > len {
        t - len
    } else {
        0.0
    };
    (vertical, horizontal)
}

/// Euclidean distance from `p` to the segment `ab`.
pub fn point_segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let (v, h) = point_segment_distances(p, a, b);
    (v * v + h * h).sqrt()
}

/// True iff the quadrilateral `q` (counter-clockwise) is strictly convex:
/// every corner turns left.
pub fn quad_is_convex(q: [DVec2; 4]) -> bool {
    (0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) > 0.0)
}

/// The four interior angles of a quad in degrees (corner `i` at `q[i]`).
pub fn quad_angles(q: [DVec2; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for i in 0..4 {
        let prev = q[(i + 3) % 4];
        let next = q[(i + 1) % 4];
        out[i] = interior_angle(prev, q[i], next).to_degrees();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_segments_cross() {
        let r = segments_intersect(
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(1.0, 0.0),
        );
        assert_eq!(r, SegmentRelation::Cross);
    }

    #[test]
    fn segments_sharing_an_end_touch() {
        let r = segments_intersect(DVec2::ZERO, DVec2::X, DVec2::X, DVec2::new(2.0, 1.0));
        assert_eq!(r, SegmentRelation::Touch);
    }

    #[test]
    fn collinear_segments_overlap() {
        let r = segments_intersect(
            DVec2::ZERO,
            DVec2::new(2.0, 0.0),
            DVec2::X,
            DVec2::new(3.0, 0.0),
        );
        assert_eq!(r, SegmentRelation::Overlap);
    }

    #[test]
    fn parallel_segments_are_disjoint() {
        let r = segments_intersect(DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::new(1.0, 1.0));
        assert_eq!(r, SegmentRelation::Disjoint);
    }

    #[test]
    fn straight_run_has_interior_angle_pi() {
        let a = interior_angle(DVec2::new(-1.0, 0.0), DVec2::ZERO, DVec2::X);
        assert!((a - std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn square_corner_of_ccw_loop_is_90_degrees() {
        // A counter-clockwise square visits (0,0) between (0,1) and (1,0).
        let a = interior_angle(DVec2::new(0.0, 1.0), DVec2::ZERO, DVec2::X);
        assert!((a.to_degrees() - 90.0).abs() < 1e-9);
    }

    #[test]
    fn slit_tip_has_interior_angle_two_pi() {
        let a = interior_angle(DVec2::X, DVec2::ZERO, DVec2::X);
        assert!((a - 2.0 * std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn point_beyond_segment_end_has_horizontal_distance() {
        let (v, h) =
            point_segment_distances(DVec2::new(3.0, 1.0), DVec2::ZERO, DVec2::new(2.0, 0.0));
        assert_eq!((v, h), (1.0, 1.0));
    }

    #[test]
    fn reversed_square_is_not_convex() {
        let q = [DVec2::ZERO, DVec2::Y, DVec2::new(1.0, 1.0), DVec2::X];
        assert!(!quad_is_convex(q));
        let q = [DVec2::ZERO, DVec2::X, DVec2::new(1.0, 1.0), DVec2::Y];
        assert!(quad_is_convex(q));
    }
}

/// A fixed sequence of numbers in [0, 1) from `seed`, for tests that
/// perturb shapes the same way on every machine.
#[cfg(test)]
pub(crate) fn test_noise(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}
