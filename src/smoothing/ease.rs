//! Easing: where an element is still past the bounds after smoothing and
//! clean-up (a corner outside the window, or its size against a
//! neighbour, its aspect or taper), the free nodes within two rings of it
//! move, a few rounds over: first to bring the corners round them nearer
//! the window, then the sizes and shapes nearer their bounds, then to
//! lower how far the corners come near the window's edges (the squared
//! degrees past a margin inside it). The neighbours make room that the
//! bad element's own nodes then take; a node moving alone cannot, since
//! its own worst corner decides (untangle.rs). A boundary node inside an
//! input edge slides along it, straight or along the arc's circle (never
//! an input vertex, and never nearer than a fifth of the way to a
//! neighbour): in a spike or a slot, where the elements' nodes are nearly
//! all on the boundary, that is the only room there is. No move makes the worst corner round a node
//! worse, nor the sizes and shapes past their bounds.

use crate::element_quality::{badness_of, fixed_tips, quad_area, size_shape_excess, worst_around};
use crate::geometry::quad_angles;
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::smoothing::compass::compass_search;
use crate::smoothing::strips::{element_neighbours, node_elements};
use glam::DVec2;

/// How far inside the window (degrees) a corner starts to count.
const MARGIN: f64 = 6.0;
/// The share of the size and shape bounds easing aims within (at the
/// bound itself, rounding would leave an element either side of it).
const SHAPE_AIM: f64 = 0.99;
/// Rounds over the nodes round the bad elements.
const ROUNDS: usize = 8;

/// Eases the nodes round the elements with a corner outside the window;
/// returns the moves kept and how many of them slid a boundary node
/// (0, and the mesh untouched, when there is none).
pub fn ease_bad_corners(mesh: &mut Mesh, bounds: &ElementBounds) -> (usize, usize) {
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    let bad: Vec<u32> = (0..mesh.quads.len() as u32)
        .filter(|&q| {
            badness_of(mesh, q as usize, bounds) > 0.0
                || size_shape_excess(
                    mesh,
                    q,
                    &neighbours[q as usize],
                    &|e| quad_area(mesh, e),
                    bounds,
                ) > 1.0
        })
        .collect();
    if bad.is_empty() {
        return (0, 0);
    }
    // the free nodes within two rings of the bad elements
    let mut near = vec![false; mesh.nodes.len()];
    let mut quads = bad;
    for ring in 0..3 {
        let mut next = Vec::new();
        for &q in &quads {
            for n in mesh.quads[q as usize] {
                if !near[n as usize] {
                    near[n as usize] = true;
                    if ring < 2 {
                        next.extend(around[n as usize].iter().map(|&(e, _)| e));
                    }
                }
            }
        }
        next.sort_unstable();
        next.dedup();
        quads = next;
    }
    let rails = slide_rails(mesh, bounds);
    let nodes: Vec<usize> = (0..mesh.nodes.len())
        .filter(|&n| {
            near[n]
                && !around[n].is_empty()
                && (mesh.kinds[n] == NodeKind::Interior || rails[n].is_some())
        })
        .collect();
    let (mut moved, mut slid) = (0, 0);
    for _ in 0..ROUNDS {
        let mut any = false;
        for &n in &nodes {
            let elements: Vec<u32> = around[n].iter().map(|&(q, _)| q).collect();
            // the elements whose size against a neighbour the move changes
            let mut judged = elements.clone();
            for &q in &elements {
                judged.extend(neighbours[q as usize].iter().flatten());
            }
            judged.sort_unstable();
            judged.dedup();
            let shape = |m: &Mesh| {
                judged
                    .iter()
                    .map(|&q| {
                        size_shape_excess(
                            m,
                            q,
                            &neighbours[q as usize],
                            &|e| quad_area(m, e),
                            bounds,
                        )
                    })
                    .fold(0.0, f64::max)
            };
            // past the size and shape bounds: how far, as a share of them
            let past = |m: &Mesh| (shape(m) - SHAPE_AIM).max(0.0);
            let (worst, _) = worst_around(mesh, &around[n], bounds);
            let start = (worst, past(mesh), strain(mesh, &around[n], bounds));
            let old = mesh.nodes[n];
            // an element round the node within the window stays so: the
            // worst corner eased at the price of another leaving it is no gain
            let outside = |m: &Mesh| {
                around[n]
                    .iter()
                    .filter(|&&(q, _)| badness_of(m, q as usize, bounds) > 0.0)
                    .count()
            };
            let outside_before = outside(mesh);
            let score = |m: &Mesh, best: (f64, f64, f64)| {
                let (w, _) = worst_around(m, &around[n], bounds);
                if !w.is_finite() || w > best.0 + 1e-9 || outside(m) > outside_before {
                    return None;
                }
                let p = past(m);
                if p > best.1 + 1e-12 {
                    return None;
                }
                Some((w, p, strain(m, &around[n], bounds)))
            };
            // corners first, then size and shape, then room
            let better = |w: (f64, f64, f64), best: (f64, f64, f64)| {
                w.0 < best.0 - 1e-9
                    || (w.0 <= best.0 + 1e-9
                        && (w.1 < best.1 - 1e-12
                            || (w.1 <= best.1 + 1e-12 && w.2 < best.2 * (1.0 - 1e-6))))
            };
            let best = match rails[n] {
                Some(rail) => {
                    rail_search(mesh, n, rail, bounds.boundary_slide, start, score, better)
                }
                None => compass_search(mesh, n, &around[n], start, score, better),
            };
            if best != old {
                mesh.nodes[n] = best;
                moved += 1;
                slid += usize::from(rails[n].is_some());
                any = true;
            }
        }
        if !any {
            break;
        }
    }
    (moved, slid)
}

/// For each node, the two boundary neighbours it may slide between
/// (`boundary_rails`; none with `bound(boundary_slide, 0)`): an element
/// at a tip of the input takes its corner from the nodes either side (the
/// first segments' chords), so one of those on an arc stays, lest a slide
/// along it make the tip sharper than the input's.
pub(super) fn slide_rails(mesh: &Mesh, bounds: &ElementBounds) -> Vec<Option<(u32, u32)>> {
    let mut rails = if bounds.boundary_slide > 0.0 {
        boundary_rails(mesh)
    } else {
        vec![None; mesh.nodes.len()]
    };
    for (q, quad) in mesh.quads.iter().enumerate() {
        for (k, tip) in fixed_tips(mesh, q, bounds).into_iter().enumerate() {
            let tip = tip && mesh.is_input_vertex(quad[k] as usize);
            for side in [quad[(k + 1) % 4] as usize, quad[(k + 3) % 4] as usize] {
                if tip && rails[side].is_some_and(|r| on_an_arc(mesh, side, r)) {
                    rails[side] = None;
                }
            }
        }
    }
    rails
}

/// The squared degrees the corners round a node come within `MARGIN` of
/// the window's edges or past them (fixed tips left out).
fn strain(mesh: &Mesh, around: &[(u32, u8)], bounds: &ElementBounds) -> f64 {
    let (lo, hi) = (bounds.lower_corner + MARGIN, bounds.upper_corner - MARGIN);
    around
        .iter()
        .map(|&(q, _)| {
            let skip = fixed_tips(mesh, q as usize, bounds);
            let a = quad_angles(mesh.quad_points(q as usize));
            (0..4)
                .filter(|&i| !skip[i])
                .map(|i| {
                    let over = (a[i] - hi).max(0.0) + (lo - a[i]).max(0.0);
                    over * over
                })
                .sum::<f64>()
        })
        .sum()
}

/// Whether a boundary node's rail is an arc's circle.
fn on_an_arc(mesh: &Mesh, n: usize, (a, b): (u32, u32)) -> bool {
    let at = |i: u32| mesh.nodes[i as usize];
    matches!(
        rail_through(at(a), mesh.nodes[n], at(b)),
        Some((Rail::Arc(..), _))
    )
}

/// The curve a boundary node may slide along, between its two boundary
/// neighbours: the straight input edge they lie on, or the circle of the
/// input arc (or circle) they lie on.
#[derive(Debug, Clone, Copy)]
pub(super) enum Rail {
    Line(DVec2, DVec2),
    /// Centre, radius, the angle at the first neighbour and the signed
    /// sweep to the second.
    Arc(DVec2, f64, f64, f64),
}

impl Rail {
    /// The point a share `t` of the way from the first neighbour.
    fn at(&self, t: f64) -> DVec2 {
        match *self {
            Rail::Line(a, b) => a + (b - a) * t,
            Rail::Arc(c, r, from, sweep) => {
                let (sin, cos) = (from + sweep * t).sin_cos();
                c + DVec2::new(cos, sin) * r
            }
        }
    }
}

/// For each node, the two boundary neighbours it may slide between: an
/// input boundary node inside one input edge (its two boundary edges in
/// one group, the node not an input vertex), straight or an arc (the
/// circle through it and its two neighbours is the arc's).
fn boundary_rails(mesh: &Mesh) -> Vec<Option<(u32, u32)>> {
    let mut next: Vec<Vec<(u32, u32)>> = vec![Vec::new(); mesh.nodes.len()];
    for e in &mesh.boundary {
        next[e.a as usize].push((e.b, e.output_group()));
        next[e.b as usize].push((e.a, e.output_group()));
    }
    (0..mesh.nodes.len())
        .map(|n| {
            let [(a, ga), (b, gb)] = next[n][..] else {
                return None;
            };
            if ga != gb || mesh.is_input_vertex(n) {
                return None;
            }
            let (pa, p, pb) = (
                mesh.nodes[a as usize],
                mesh.nodes[n],
                mesh.nodes[b as usize],
            );
            rail_through(pa, p, pb).map(|_| (a, b))
        })
        .collect()
}

/// The rail from `pa` to `pb` through `p`, and the share of the way `p`
/// is at: the line where the three are in line, else their circle (None
/// where `p` is not between the two, or is off their line by a millionth
/// of its length or less: a straight edge's node rounded off it).
pub(super) fn rail_through(pa: DVec2, p: DVec2, pb: DVec2) -> Option<(Rail, f64)> {
    let ab = pb - pa;
    if (p - pa).perp_dot(ab).abs() <= 1e-12 * ab.length_squared() {
        let between = (p - pa).dot(ab) > 0.0 && (p - pb).dot(ab) < 0.0;
        let len = ab.length();
        let t = (p - pa).dot(ab / len) / len;
        return between.then_some((Rail::Line(pa, pb), t));
    }
    // the circumcentre, from p (the nearest of the three)
    let (u, v) = (pa - p, pb - p);
    let d = 2.0 * u.perp_dot(v);
    let centre = p + DVec2::new(
        v.y * u.length_squared() - u.y * v.length_squared(),
        u.x * v.length_squared() - v.x * u.length_squared(),
    ) / d;
    let r = (p - centre).length();
    // a straight edge's node a rounding off its line is no arc's
    let sagitta = (p - pa).perp_dot(ab).abs() / ab.length();
    if !(r.is_finite() && sagitta > 1e-6 * ab.length()) {
        return None;
    }
    let angle = |x: DVec2| (x - centre).y.atan2((x - centre).x);
    let wrap = |x: f64| {
        let t = std::f64::consts::TAU;
        x - t * ((x + t / 2.0) / t).floor()
    };
    let (to_p, p_to_b) = (wrap(angle(p) - angle(pa)), wrap(angle(pb) - angle(p)));
    if to_p * p_to_b <= 0.0 {
        return None;
    }
    let sweep = to_p + p_to_b;
    Some((Rail::Arc(centre, r, angle(pa), sweep), to_p / sweep))
}

/// The best place for boundary node `n` on its rail between its
/// neighbours `a` and `b` (as they are now: they may have slid too), as
/// the compass search but along the rail, at least `keep` of the way from
/// either (`bound(boundary_slide, _)`).
fn rail_search<S: Copy>(
    mesh: &mut Mesh,
    n: usize,
    (a, b): (u32, u32),
    keep: f64,
    start: S,
    mut score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
) -> DVec2 {
    let old = mesh.nodes[n];
    let Some((rail, t0)) = rail_through(mesh.nodes[a as usize], old, mesh.nodes[b as usize]) else {
        return old;
    };
    let (lo, hi) = (keep.min(t0), (1.0 - keep).max(t0));
    let mut best = (start, t0);
    let mut step = 0.125;
    for _ in 0..6 {
        let centre = best.1;
        for t in [centre - step, centre + step] {
            if t < lo || t > hi {
                continue;
            }
            mesh.nodes[n] = rail.at(t);
            if let Some(w) = score(mesh, best.0) {
                if better(w, best.0) {
                    best = (w, t);
                }
            }
        }
        step *= 0.5;
    }
    mesh.nodes[n] = old;
    if best.1 == t0 {
        old
    } else {
        rail.at(best.1)
    }
}
