//! Element quality: one home for every measure of an element the stages
//! judge by. Angles against the KB's corner window (badness; [45, 135]
//! unless `bound/2` says otherwise, see settings.rs), the scaled
//! Jacobian (smallest sine of a corner), aspect ratio and taper, and the
//! size jump between neighbours; each also for the elements round a node.

use glam::DVec2;

use crate::geometry::{interior_angle, orient2d};
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;

/// How far an element's worst corner is from the corner window
/// (degrees; 0 inside it), or infinity if the element is not convex.
pub(crate) fn badness(q: [DVec2; 4], bounds: &ElementBounds) -> f64 {
    for i in 0..4 {
        if orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) <= 0.0 {
            return f64::INFINITY;
        }
    }
    // Most elements have every corner inside the window: cos against the
    // window's at each, tested without trigonometry.
    let inside = (0..4).all(|i| {
        let a = q[(i + 1) % 4] - q[i];
        let b = q[(i + 3) % 4] - q[i];
        bounds.corner_inside(a.dot(b), a.length_squared(), b.length_squared())
    });
    if inside {
        return 0.0;
    }
    worst_excess(q, bounds)
}

/// The angle of corner `i` of an element in degrees, as `quad_angles`
/// measures it, or None when the corner is clearly inside the window:
/// told without trigonometry, with a margin so that the answer is the
/// same as measuring it.
pub(crate) fn angle_unless_inside(q: &[DVec2; 4], i: usize, bounds: &ElementBounds) -> Option<f64> {
    let a = q[(i + 1) % 4] - q[i];
    let b = q[(i + 3) % 4] - q[i];
    if a.perp_dot(b) > 0.0
        && bounds.corner_clearly_inside(a.dot(b), a.length_squared(), b.length_squared())
    {
        return None;
    }
    Some(interior_angle(q[(i + 3) % 4], q[i], q[(i + 1) % 4]).to_degrees())
}

/// How far the worst corner of an element is past the window (degrees).
pub(crate) fn worst_excess(q: [DVec2; 4], bounds: &ElementBounds) -> f64 {
    worst_excess_but(q, bounds, NO_TIPS)
}

/// `worst_excess` over the corners not marked in `skip`.
fn worst_excess_but(q: [DVec2; 4], bounds: &ElementBounds, skip: [bool; 4]) -> f64 {
    (0..4)
        .filter(|&i| !skip[i])
        .filter_map(|i| angle_unless_inside(&q, i, bounds))
        .map(|a| bounds.corner_excess(a))
        .fold(0.0, f64::max)
}

const NO_TIPS: [bool; 4] = [false; 4];

/// The corners of element `q` that are tips of the input taken whole:
/// the corner and both its neighbours input nodes (which never move) and
/// the corner sharper than the window's lower corner. No move changes
/// such a corner, so the measures over a mesh (`badness_of`,
/// `worst_around`, `sine_worst_around`) leave it out: else the tip's own
/// excess would hide what a move does to the element's other corners.
pub(crate) fn fixed_tips(mesh: &Mesh, q: usize, bounds: &ElementBounds) -> [bool; 4] {
    let quad = mesh.quads[q];
    let fixed = |i: usize| mesh.kinds[quad[i % 4] as usize] == NodeKind::Boundary;
    if !(0..4).any(|i| fixed(i) && fixed(i + 1) && fixed(i + 3)) {
        return NO_TIPS;
    }
    let p = mesh.quad_points(q);
    std::array::from_fn(|i| fixed(i) && fixed(i + 1) && fixed(i + 3) && under_window(&p, i, bounds))
}

/// Whether corner `i` of an element is sharper than the window's lower
/// corner (told without trigonometry).
fn under_window(p: &[DVec2; 4], i: usize, bounds: &ElementBounds) -> bool {
    let a = p[(i + 1) % 4] - p[i];
    let b = p[(i + 3) % 4] - p[i];
    let d = a.dot(b);
    d > 0.0 && d * d > bounds.cos2_lower * a.length_squared() * b.length_squared()
}

/// `badness` of element `q` of a mesh, its fixed tips left out.
pub(crate) fn badness_of(mesh: &Mesh, q: usize, bounds: &ElementBounds) -> f64 {
    let p = mesh.quad_points(q);
    let skip = fixed_tips(mesh, q, bounds);
    if skip == NO_TIPS {
        return badness(p, bounds);
    }
    for i in 0..4 {
        if orient2d(p[i], p[(i + 1) % 4], p[(i + 2) % 4]) <= 0.0 {
            return f64::INFINITY;
        }
    }
    worst_excess_but(p, bounds, skip)
}

/// An element's `badness` and its scaled Jacobian (smallest sine of a
/// corner) together, over the corners not marked in `skip` (convexity
/// over all four), the edge vectors worked out once: the same numbers as
/// the two measures apart. None if the element is not convex.
fn badness_and_sine_but(
    q: [DVec2; 4],
    bounds: &ElementBounds,
    skip: [bool; 4],
) -> Option<(f64, f64)> {
    for i in 0..4 {
        if orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) <= 0.0 {
            return None;
        }
    }
    let e: [DVec2; 4] = std::array::from_fn(|i| q[(i + 1) % 4] - q[i]);
    let unit = e.map(DVec2::normalize_or_zero);
    let mut inside = true;
    let mut min_sin = f64::INFINITY;
    for i in (0..4).filter(|&i| !skip[i]) {
        // corner i between e[i] and the reversed e[i - 1]
        let (a, b) = (e[i], -e[(i + 3) % 4]);
        inside &= bounds.corner_inside(a.dot(b), a.length_squared(), b.length_squared());
        min_sin = min_sin.min(unit[i].perp_dot(-unit[(i + 3) % 4]));
    }
    let bad = if inside {
        0.0
    } else {
        worst_excess_but(q, bounds, skip)
    };
    Some((bad, min_sin))
}

/// Minus the smallest sine of a corner of the elements round a node
/// (infinite if one is not convex): the same order as `worst_around`
/// (the corner farthest from a right angle has the smallest sine), for
/// a fraction of its cost.
pub(crate) fn sine_worst_around(mesh: &Mesh, around: &[(u32, u8)], bounds: &ElementBounds) -> f64 {
    sine_worst_around_of(mesh, around, Some(bounds))
}

/// `sine_worst_around` with every corner counted, fixed tips too (see
/// `worst_around_every_corner`).
pub(crate) fn sine_worst_around_every_corner(mesh: &Mesh, around: &[(u32, u8)]) -> f64 {
    sine_worst_around_of(mesh, around, None)
}

fn sine_worst_around_of(mesh: &Mesh, around: &[(u32, u8)], tips: Option<&ElementBounds>) -> f64 {
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        let skip = tips.map_or(NO_TIPS, |b| fixed_tips(mesh, q as usize, b));
        match convex_sine_but(mesh.quad_points(q as usize), skip) {
            Some(s) => min_sin = min_sin.min(s),
            None => return f64::INFINITY,
        }
    }
    -min_sin
}

/// The smallest sine of a corner of element `q` of a mesh (its scaled
/// Jacobian), its fixed tips left out; None if it is not convex (plain
/// arithmetic: for comparing places, not for the check).
fn convex_sine_of(mesh: &Mesh, q: usize, bounds: &ElementBounds) -> Option<f64> {
    convex_sine_but(mesh.quad_points(q), fixed_tips(mesh, q, bounds))
}

fn convex_sine_but(q: [DVec2; 4], skip: [bool; 4]) -> Option<f64> {
    let e: [DVec2; 4] = std::array::from_fn(|i| q[(i + 1) % 4] - q[i]);
    let inv = e.map(|v| 1.0 / v.length());
    let mut min_sin = f64::INFINITY;
    for i in 0..4 {
        let j = (i + 3) % 4;
        // corner i, between e[i] and e[j] reversed
        let cross = e[j].perp_dot(e[i]);
        if !(cross > 0.0) {
            return None;
        }
        if !skip[i] {
            min_sin = min_sin.min(cross * inv[i] * inv[j]);
        }
    }
    Some(min_sin)
}

/// The worst corner of the elements round a node: (badness, -smallest
/// sine of a corner), smaller is better; infinite if one is not convex.
pub(crate) fn worst_around(
    mesh: &Mesh,
    around: &[(u32, u8)],
    bounds: &ElementBounds,
) -> (f64, f64) {
    worst_around_of(mesh, around, bounds, true)
}

/// `worst_around` with every corner counted, fixed tips too: for
/// comparing elements before and after a change of topology (a flip or a
/// collapse makes and unmakes corners, fixed ones too).
pub(crate) fn worst_around_every_corner(
    mesh: &Mesh,
    around: &[(u32, u8)],
    bounds: &ElementBounds,
) -> (f64, f64) {
    worst_around_of(mesh, around, bounds, false)
}

fn worst_around_of(
    mesh: &Mesh,
    around: &[(u32, u8)],
    bounds: &ElementBounds,
    leave_out_tips: bool,
) -> (f64, f64) {
    let mut bad: f64 = 0.0;
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        let skip = if leave_out_tips {
            fixed_tips(mesh, q as usize, bounds)
        } else {
            NO_TIPS
        };
        let Some((b, s)) = badness_and_sine_but(mesh.quad_points(q as usize), bounds, skip) else {
            return (f64::INFINITY, f64::INFINITY);
        };
        bad = bad.max(b);
        min_sin = min_sin.min(s);
    }
    (bad, -min_sin)
}

/// `worst_around` if it is better (smaller) than `best`, else None: the
/// elements are judged one by one and the search gives up on a place at
/// the first that shows it no better (both parts only grow).
pub(crate) fn worst_around_under(
    mesh: &Mesh,
    around: &[(u32, u8)],
    best: (f64, f64),
    bounds: &ElementBounds,
) -> Option<(f64, f64)> {
    let mut bad: f64 = 0.0;
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        let skip = fixed_tips(mesh, q as usize, bounds);
        let (b, s) = badness_and_sine_but(mesh.quad_points(q as usize), bounds, skip)?;
        bad = bad.max(b);
        min_sin = min_sin.min(s);
        if !((bad, -min_sin) < best) {
            return None;
        }
    }
    Some((bad, -min_sin))
}

/// `sine_worst_around` if it is smaller than `best`, else None (judged
/// element by element, as `worst_around_under`); a search uses `Star`,
/// which gives the same numbers.
#[cfg(test)]
pub(crate) fn sine_worst_around_under(
    mesh: &Mesh,
    around: &[(u32, u8)],
    best: f64,
    bounds: &ElementBounds,
) -> Option<f64> {
    let mut min_sin = f64::INFINITY;
    for &(q, _) in around {
        min_sin = min_sin.min(convex_sine_of(mesh, q as usize, bounds)?);
        if !(-min_sin < best) {
            return None;
        }
    }
    Some(-min_sin)
}

/// The elements round a node as a search moves it, for
/// `sine_worst_around_under`'s measure: what does not change with the
/// node's place (the two edges away from it, the corner opposite it, the
/// fixed tips) worked out once, the same numbers as measuring afresh.
pub(crate) struct Star {
    node: usize,
    elements: Vec<StarElement>,
}

struct StarElement {
    /// The element's corners, the moving node's among them (at `at`).
    p: [DVec2; 4],
    at: usize,
    /// The edges away from the node, `e[at + 1]` and `e[at + 2]`, and
    /// their inverse lengths.
    far: [DVec2; 2],
    far_inv: [f64; 2],
    skip: [bool; 4],
    /// The opposite corner: convex or not, and its sine.
    opposite: Option<f64>,
    /// Where the node is at more than one corner: measured afresh.
    whole: Option<u32>,
}

impl Star {
    /// The elements `around` node `n` (each with the node's corner).
    pub(crate) fn new(mesh: &Mesh, n: u32, around: &[(u32, u8)], bounds: &ElementBounds) -> Star {
        let elements = around
            .iter()
            .map(|&(q, c)| {
                let quad = mesh.quads[q as usize];
                let at = c as usize;
                let p = mesh.quad_points(q as usize);
                let skip = fixed_tips(mesh, q as usize, bounds);
                let e = |i: usize| p[(i + 1) % 4] - p[i % 4];
                let far = [e(at + 1), e(at + 2)];
                let far_inv = far.map(|v| 1.0 / v.length());
                let cross = far[0].perp_dot(far[1]);
                let opposite = (cross > 0.0).then(|| {
                    if skip[(at + 2) % 4] {
                        f64::INFINITY
                    } else {
                        cross * far_inv[1] * far_inv[0]
                    }
                });
                let twice = quad.iter().filter(|&&m| m == n).count() != 1 || quad[at] != n;
                StarElement {
                    p,
                    at,
                    far,
                    far_inv,
                    skip,
                    opposite,
                    whole: twice.then_some(q),
                }
            })
            .collect();
        Star {
            node: n as usize,
            elements,
        }
    }

    /// `sine_worst_around_under` with the node at its place in `mesh`.
    pub(crate) fn sine_worst_under(
        &self,
        mesh: &Mesh,
        best: f64,
        bounds: &ElementBounds,
    ) -> Option<f64> {
        let mut min_sin = f64::INFINITY;
        for el in &self.elements {
            let s = match el.whole {
                Some(q) => convex_sine_of(mesh, q as usize, bounds)?,
                None => el.sine(mesh.nodes[self.node])?,
            };
            min_sin = min_sin.min(s);
            if !(-min_sin < best) {
                return None;
            }
        }
        Some(-min_sin)
    }
}

impl StarElement {
    /// `convex_sine_but` of the element with the node at `x`: the same
    /// products in the same order.
    fn sine(&self, x: DVec2) -> Option<f64> {
        let at = self.at;
        let (next, prev) = ((at + 1) % 4, (at + 3) % 4);
        let near = self.p[next] - x;
        let before = x - self.p[prev];
        let (near_inv, before_inv) = (1.0 / near.length(), 1.0 / before.length());
        let mut min_sin = self.opposite?;
        // corner at: e[at] after e[prev]
        let cross = before.perp_dot(near);
        if !(cross > 0.0) {
            return None;
        }
        if !self.skip[at] {
            min_sin = min_sin.min(cross * near_inv * before_inv);
        }
        // corner next: e[next] after e[at]
        let cross = near.perp_dot(self.far[0]);
        if !(cross > 0.0) {
            return None;
        }
        if !self.skip[next] {
            min_sin = min_sin.min(cross * self.far_inv[0] * near_inv);
        }
        // corner prev: e[prev] after e[at + 2]
        let cross = self.far[1].perp_dot(before);
        if !(cross > 0.0) {
            return None;
        }
        if !self.skip[prev] {
            min_sin = min_sin.min(cross * before_inv * self.far_inv[1]);
        }
        Some(min_sin)
    }
}

/// True when every corner of the elements round a node has a sine above
/// 0.8 (between 53 and 127 degrees) and is inside the window, so convex
/// and good: the common case, told without trigonometry.
pub(crate) fn corners_fine(mesh: &Mesh, around: &[(u32, u8)], bounds: &ElementBounds) -> bool {
    // cos² below 0.36 and below the window's on both sides
    let fine = 0.36f64.min(bounds.cos2_lower).min(bounds.cos2_upper);
    around.iter().all(|&(q, _)| {
        let p = mesh.quad_points(q as usize);
        (0..4).all(|i| {
            let a = p[(i + 1) % 4] - p[i];
            let b = p[(i + 3) % 4] - p[i];
            let d = a.dot(b);
            a.perp_dot(b) > 0.0 && d * d < fine * a.length_squared() * b.length_squared()
        })
    })
}

/// How many corners of the elements round a node are outside the window.
pub(crate) fn corners_outside(mesh: &Mesh, around: &[(u32, u8)], bounds: &ElementBounds) -> usize {
    around
        .iter()
        .map(|&(q, _)| {
            let p = mesh.quad_points(q as usize);
            (0..4)
                .filter_map(|i| angle_unless_inside(&p, i, bounds))
                .filter(|&a| !bounds.corner_in_window(a))
                .count()
        })
        .sum()
}

/// How far an element is past the paper's bounds on size and shape, as a
/// share of each bound: its size against each neighbour's (the square
/// root of the area ratio), its taper and aspect ratio. At most 1 when
/// within them. `area` gives each element's area.
pub(crate) fn size_shape_excess(
    mesh: &Mesh,
    q: u32,
    neighbours: &[Option<u32>; 4],
    area: &dyn Fn(u32) -> f64,
    bounds: &ElementBounds,
) -> f64 {
    let (aspect, taper) = aspect_taper(mesh.quad_points(q as usize));
    let mut worst = (aspect / bounds.max_aspect).max(taper / bounds.max_taper);
    let mine = area(q).max(1e-300);
    for f in neighbours.iter().flatten() {
        let other = area(*f).max(1e-300);
        worst = worst.max((mine / other).max(other / mine).sqrt() / bounds.max_size_jump);
    }
    worst
}

/// Whether every element round a node is clearly within the aspect and
/// taper bounds (a thousandth inside them), told from squared lengths:
/// the cheap test before `shape_worst_around`.
pub(crate) fn shapes_clearly_within(
    mesh: &Mesh,
    around: &[(u32, u8)],
    bounds: &ElementBounds,
) -> bool {
    let t2 = (bounds.max_taper * (1.0 - 1e-3)).powi(2);
    let a2 = (bounds.max_aspect * (1.0 - 1e-3)).powi(2);
    around.iter().all(|&(q, _)| {
        let p = mesh.quad_points(q as usize);
        let e: [f64; 4] = std::array::from_fn(|i| (p[(i + 1) % 4] - p[i]).length_squared());
        let m02 = ((p[0] + p[1]) - (p[2] + p[3])).length_squared();
        let m13 = ((p[1] + p[2]) - (p[3] + p[0])).length_squared();
        let within = |x: f64, y: f64, k2: f64| x <= k2 * y && y <= k2 * x;
        within(e[0], e[2], t2) && within(e[1], e[3], t2) && within(m02, m13, a2)
    })
}

/// Whether element `q` has a corner sharper than the window's lower
/// corner at an input node.
fn at_sharp_input_corner(mesh: &Mesh, q: usize, bounds: &ElementBounds) -> bool {
    let quad = mesh.quads[q];
    let p = mesh.quad_points(q);
    (0..4)
        .any(|i| mesh.kinds[quad[i] as usize] == NodeKind::Boundary && under_window(&p, i, bounds))
}

/// The worst of the elements round a node by aspect ratio and taper, as
/// a share of their bounds (at most 1 within them): the smoothing moves
/// refuse to take it past the bounds, since a node slid onto its
/// neighbour leaves an edge of nothing between two corners of 90, which
/// the corners alone would welcome.
pub(crate) fn shape_worst_around(mesh: &Mesh, around: &[(u32, u8)], bounds: &ElementBounds) -> f64 {
    around
        .iter()
        // an element at an input corner sharper than the window has the
        // taper the corner's wedge gives it
        .filter(|&&(q, _)| !at_sharp_input_corner(mesh, q as usize, bounds))
        .map(|&(q, _)| {
            let (aspect, taper) = aspect_taper(mesh.quad_points(q as usize));
            (aspect / bounds.max_aspect).max(taper / bounds.max_taper)
        })
        .fold(0.0, f64::max)
}

pub(crate) fn quad_area(mesh: &Mesh, q: u32) -> f64 {
    crate::geometry::polygon_area(&mesh.quad_points(q as usize)).abs()
}

/// Scaled Jacobian of a quad: the least, over its corners, of the sine of
/// the corner angle (cross product of the unit edge vectors).
pub fn scaled_jacobian(q: [DVec2; 4]) -> f64 {
    (0..4)
        .map(|i| {
            let a = (q[(i + 1) % 4] - q[i]).normalize_or_zero();
            let b = (q[(i + 3) % 4] - q[i]).normalize_or_zero();
            a.perp_dot(b)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Aspect ratio and taper of a quad (both >= 1).
pub fn aspect_taper(q: [DVec2; 4]) -> (f64, f64) {
    let e: [f64; 4] = std::array::from_fn(|i| (q[(i + 1) % 4] - q[i]).length());
    let ratio = |a: f64, b: f64| {
        if a.min(b) <= 0.0 {
            f64::INFINITY
        } else {
            a.max(b) / a.min(b)
        }
    };
    let taper = ratio(e[0], e[2]).max(ratio(e[1], e[3]));
    let m02 = ((q[0] + q[1]) / 2.0 - (q[2] + q[3]) / 2.0).length();
    let m13 = ((q[1] + q[2]) / 2.0 - (q[3] + q[0]) / 2.0).length();
    (ratio(m02, m13), taper)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The star's measure is the measure afresh, bit for bit, wherever the
    /// node goes (convex or not, the best so far met or not), with a
    /// sharp fixed tip among the elements.
    #[test]
    fn a_star_measures_as_the_elements_measured_afresh() {
        let mut m = crate::mesh::three_by_three();
        // a sharp tip at the corner node 0: its neighbours pulled close
        m.nodes[1] = DVec2::new(1.0, 0.5);
        m.nodes[4] = DVec2::new(0.5, 1.0);
        let bounds = ElementBounds::default();
        let n = 5u32;
        let pairs: Vec<(u32, u8)> = (0..m.quads.len() as u32)
            .filter_map(|q| {
                let at = m.quads[q as usize].iter().position(|&k| k == n)?;
                Some((q, at as u8))
            })
            .collect();
        assert_eq!(pairs.len(), 4);
        assert!(fixed_tips(&m, 0, &bounds).contains(&true));
        let star = Star::new(&m, n, &pairs, &bounds);
        let mut seen_none = 0;
        for k in 0..400 {
            let t = k as f64 * 0.37;
            m.nodes[n as usize] = DVec2::new(1.0 + 0.9 * t.sin(), 1.0 + 0.9 * (1.7 * t).cos());
            for best in [f64::INFINITY, -0.5, -0.9] {
                let afresh = sine_worst_around_under(&m, &pairs, best, &bounds);
                let by_star = star.sine_worst_under(&m, best, &bounds);
                assert_eq!(
                    afresh.map(f64::to_bits),
                    by_star.map(f64::to_bits),
                    "at {k}"
                );
                seen_none += usize::from(afresh.is_none());
            }
        }
        assert!(seen_none > 0 && seen_none < 1200);
    }
}
