//! Rings: a small loop no chord splits well gets a ring of elements round
//! a new convex loop inside it, which the final patterns or a chord close.
//!
//! Of the rings whose smallest corner is near the best a search finds,
//! the one whose sizes fit best is kept: its elements against each other,
//! against the elements outside the loop and against those that will
//! close the inner loop. A ring judged by its corners alone may put tiny
//! elements in the middle of large ones (size jumps past the bound that
//! smoothing, held by the corner window, cannot even out).

use glam::DVec2;

use crate::geometry::{orient2d, polygon_area};
use crate::mesh::NodeKind;
use crate::partial_mesh::{Closing, PartialMesh};
use crate::report::trace::{Angles, By};
use crate::validity::{convex_angles, distinct, quad_clear};

/// What a ring's search weighs: the shortest edge it may make, the size
/// jump aimed for (`bound(max_size_jump, _)`) and how many degrees of its
/// smallest corner it gives for sizes within it (`bound(ring_corner_give,
/// _)`).
pub struct RingAims {
    pub min_edge: f64,
    pub max_size_jump: f64,
    pub corner_give: f64,
}

/// The last resort for a loop the rules and chords cannot mesh: a
/// ring of n elements round a new convex loop of n nodes on a circle
/// about a centre that sees every node of the loop. The inner loop is
/// convex whatever the loop's shape, so the final patterns or a chord
/// close it.
/// With `sizes_fit`, only a ring whose size jumps are within the bound:
/// else a loop far smaller than the elements round it gets tiny elements
/// (taking back the elements round it may give it room instead).
pub fn close_ring(
    pm: &mut PartialMesh,
    l: u32,
    max_size_jump: f64,
    sizes_fit: bool,
) -> Option<u32> {
    let fvs = pm.front.loop_fvs(l);
    let n = fvs.len();
    let ids: Vec<u32> = fvs.iter().map(|&f| pm.front.node(f)).collect();
    if !distinct(&ids) || n > 12 {
        return None;
    }
    let p: Vec<DVec2> = ids.iter().map(|&i| pm.mesh.nodes[i as usize]).collect();
    // the element outside each edge of the loop (None on the boundary):
    // it runs the edge the other way
    let owners = pm.edge_owners();
    let outside_of: Vec<Option<u32>> = (0..n)
        .map(|i| owners.get(&(ids[(i + 1) % n], ids[i])).copied())
        .collect();
    let outside: Vec<Option<f64>> = outside_of
        .iter()
        .map(|o| o.map(|q| polygon_area(&pm.mesh.quad_points(q as usize)).abs()))
        .collect();
    let aims = RingAims {
        // a quarter of the rules' minimum: a ring may be finer than the
        // elements round it, but rings in rings cannot shrink for ever
        // (a loop of four gets a ring round a convex four, closed at once:
        // no nesting, so its ring may go finer)
        min_edge: pm.min_edge / if n == 4 { 32.0 } else { 4.0 },
        max_size_jump,
        corner_give: pm.host.ring_corner_give,
    };
    let (inner, jump) = best_ring(&p, &outside, &aims)?;
    if sizes_fit && jump > max_size_jump {
        return None;
    }
    for i in 0..n {
        let q = [p[i], p[(i + 1) % n], inner[(i + 1) % n], inner[i]];
        if !quad_clear(
            pm,
            q,
            &[Some(ids[i]), Some(ids[(i + 1) % n]), None, None],
            0.0,
        ) {
            return None;
        }
    }
    let base = pm.mesh.nodes.len() as u32;
    for &x in &inner {
        pm.mesh.add_node(x, NodeKind::Interior);
    }
    let qs: Vec<[u32; 4]> = (0..n)
        .map(|i| {
            [
                ids[i],
                ids[(i + 1) % n],
                base + ((i + 1) % n) as u32,
                base + i as u32,
            ]
        })
        .collect();
    let inner_ids: Vec<u32> = (0..n as u32).map(|i| base + i).collect();
    pm.stats.fallback_splits += 1;
    pm.stats.rings += 1;
    let layer = pm.front.layer(fvs[0]) + 1;
    pm.close_with(
        l,
        qs,
        &[],
        Closing {
            feature: "stuck",
            action: "ring".into(),
            angles: Angles::default(),
            by: By::Ring,
        },
    );
    pm.front.begin();
    let nl = pm.front.add_loop(&inner_ids, &vec![layer; n]);
    pm.front.commit(&pm.mesh.nodes);
    Some(nl)
}

/// A ring the search tried: its smallest corner (degrees from 0 or 180),
/// its largest size jump and its inner nodes.
struct Tried {
    corner: f64,
    jump: f64,
    inner: Vec<DVec2>,
}

/// The inner nodes of the best ring inside the loop `p` (counter-
/// clockwise; `outside[i]`: the area of the element across edge i, if
/// any): the best of a grid of centres over the loop's box and of rings
/// along the corners' bisectors. Of the rings whose smallest corner is
/// within `aims.corner_give` of the best, the one with the smallest size
/// jump (any within the bound as good as another), then the best corner.
/// Returns its inner nodes and its largest size jump.
pub fn best_ring(
    p: &[DVec2],
    outside: &[Option<f64>],
    aims: &RingAims,
) -> Option<(Vec<DVec2>, f64)> {
    let n = p.len();
    // the elements closing the inner loop: a loop of n nodes and no
    // inner one is closed by (n - 2) / 2 elements
    let closing = ((n as f64 - 2.0) / 2.0).max(1.0);
    let jump = |a: f64, b: f64| (a / b).max(b / a).sqrt();
    // the ring's elements, judged by their smallest angle and their size
    // jumps; None too once its corner is sure to be below `floor`
    let judge = |inner: Vec<DVec2>, floor: f64| -> Option<Tried> {
        if (0..n).any(|i| orient2d(inner[i], inner[(i + 1) % n], inner[(i + 2) % n]) <= 0.0) {
            return None;
        }
        // no edge below the run's minimum: rings inside rings would
        // otherwise shrink without end
        if (0..n).any(|i| {
            (inner[(i + 1) % n] - inner[i]).length() < aims.min_edge
                || (inner[i] - p[i]).length() < aims.min_edge
        }) {
            return None;
        }
        // most rings of the search fail `floor`: the sines of their
        // corners say so without an arc tangent (the same rings refused)
        if let Some(least) = least_sine_squared(floor) {
            if (0..n)
                .any(|i| surely_below(&[p[i], p[(i + 1) % n], inner[(i + 1) % n], inner[i]], least))
            {
                return None;
            }
        }
        let mut corner = f64::MAX;
        let mut areas = Vec::with_capacity(n);
        for i in 0..n {
            let q = [p[i], p[(i + 1) % n], inner[(i + 1) % n], inner[i]];
            let angles = convex_angles(&q)?;
            corner = corner.min(
                angles
                    .iter()
                    .map(|&x| x.min(180.0 - x))
                    .fold(f64::MAX, f64::min),
            );
            if corner < floor {
                return None;
            }
            areas.push(polygon_area(&q));
        }
        let middle = polygon_area(&inner) / closing;
        let mut worst = 1.0f64;
        for i in 0..n {
            worst = worst
                .max(jump(areas[i], areas[(i + 1) % n]))
                .max(jump(areas[i], middle));
            if let Some(o) = outside[i] {
                worst = worst.max(jump(areas[i], o.max(1e-300)));
            }
        }
        Some(Tried {
            corner,
            jump: worst,
            inner,
        })
    };
    // inner nodes on a circle round a centre c
    let ring = |c: DVec2, t: f64, floor: f64| -> Option<Tried> {
        let rmax = p.iter().map(|&x| (x - c).length()).fold(f64::MAX, f64::min);
        if rmax <= 0.0 {
            return None;
        }
        judge(
            p.iter()
                .map(|&x| c + (x - c).normalize_or_zero() * rmax * t)
                .collect(),
            floor,
        )
    };
    // or each inner node in from its loop node along the bisector of
    // the loop's corner there: a loop with a reflex or flat corner
    // (no centre sees it well) gets its ring this way
    let bisector_ring = |t: f64, floor: f64| -> Option<Tried> {
        judge(
            (0..n)
                .map(|i| {
                    let (prev, v, next) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
                    let half = crate::geometry::interior_angle(prev, v, next) / 2.0;
                    let dir = DVec2::from_angle(half).rotate((next - v).normalize_or_zero());
                    v + dir * t * (next - v).length().min((prev - v).length())
                })
                .collect(),
            floor,
        )
    };
    let lo = p.iter().fold(DVec2::splat(f64::MAX), |a, &b| a.min(b));
    let hi = p.iter().fold(DVec2::splat(f64::MIN), |a, &b| a.max(b));
    // every ring near the best corner so far
    let mut tried: Vec<Tried> = Vec::new();
    let mut best_corner = f64::NEG_INFINITY;
    let mut keep = |r: Option<Tried>, best_corner: &mut f64| {
        if let Some(r) = r {
            *best_corner = best_corner.max(r.corner);
            tried.push(r);
        }
    };
    let steps = 48;
    for ix in 1..steps {
        for iy in 1..steps {
            let c = lo + (hi - lo) * DVec2::new(ix as f64 / steps as f64, iy as f64 / steps as f64);
            for t in [0.25, 0.5, 0.75] {
                let r = ring(c, t, best_corner - aims.corner_give);
                keep(r, &mut best_corner);
            }
        }
    }
    for t in [0.2, 0.35, 0.5] {
        let r = bisector_ring(t, best_corner - aims.corner_give);
        keep(r, &mut best_corner);
    }
    let within = |j: f64| j.max(aims.max_size_jump);
    tried
        .into_iter()
        .filter(|r| r.corner >= best_corner - aims.corner_give)
        .reduce(|a, b| {
            let better = within(b.jump) < within(a.jump)
                || (within(b.jump) == within(a.jump) && b.corner > a.corner);
            if better {
                b
            } else {
                a
            }
        })
        .map(|r| (r.inner, r.jump))
}

/// The squared sine of `floor` (degrees), a hair under it so that a
/// corner near `floor` is left to the judge's own measure; None where
/// the sines cannot tell (`floor` outside (0, 90]). Once for a ring,
/// not for each of its elements.
fn least_sine_squared(floor: f64) -> Option<f64> {
    (floor > 0.0 && floor <= 90.0).then(|| (floor.to_radians().sin() * (1.0 - 1e-9)).powi(2))
}

/// Whether `q` surely fails the ring's judge at a floor whose squared
/// sine (`least_sine_squared`) is `least`: it turns the wrong way at a
/// corner, or a corner's sine puts it nearer than the floor to 0 or 180
/// degrees.
fn surely_below(q: &[DVec2; 4], least: f64) -> bool {
    // squared: no square roots on the search's hot path
    (0..4).any(|i| {
        let (a, b) = (q[(i + 1) % 4] - q[i], q[(i + 3) % 4] - q[i]);
        let cross = a.perp_dot(b);
        cross <= 0.0 || cross * cross < least * a.length_squared() * b.length_squared()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::geometry::test_noise as noise;

    fn jump_of(p: &[DVec2], outside: &[Option<f64>], give: f64) -> f64 {
        let aims = RingAims {
            min_edge: 1e-3,
            max_size_jump: 2.0,
            corner_give: give,
        };
        best_ring(p, outside, &aims).expect("a ring").1
    }

    /// The sines' shortcut refuses only what the judge's own measure
    /// refuses (a corner nearer than the floor to 0 or 180 degrees, or
    /// no convex element), and refuses most of those.
    #[test]
    fn the_sines_refuse_only_elements_the_corners_refuse() {
        let mut next = noise(7);
        let (mut refused, mut below) = (0, 0);
        for _ in 0..20_000 {
            let q: [DVec2; 4] = std::array::from_fn(|i| {
                let a = std::f64::consts::TAU * (i as f64 + 0.9 * next() - 0.45) / 4.0;
                DVec2::from_angle(a) * (0.3 + next())
            });
            let floor = 90.0 * next();
            let exact = convex_angles(&q)
                .map(|a| a.iter().map(|&x| x.min(180.0 - x)).fold(f64::MAX, f64::min));
            let judged_below = exact.is_none_or(|c| c < floor);
            if least_sine_squared(floor).is_some_and(|least| surely_below(&q, least)) {
                refused += 1;
                assert!(judged_below, "{q:?} at {floor}: {exact:?}");
            }
            below += usize::from(judged_below);
        }
        assert!(refused * 10 >= below * 9, "{refused} of {below}");
    }

    #[test]
    fn a_ring_gives_a_few_degrees_for_sizes_that_fit_its_neighbours() {
        // uneven hexagons (one side on the boundary), the elements round
        // them as large as half the loop: the ring judged by its corners
        // alone puts elements too small among them
        let mut next = noise(11);
        let (mut fitted, mut tried) = (0, 0);
        for _ in 0..60 {
            let p: Vec<DVec2> = (0..6)
                .map(|i| {
                    let a = std::f64::consts::TAU * (i as f64 + 0.6 * next() - 0.3) / 6.0;
                    DVec2::from_angle(a) * (0.6 + 0.8 * next())
                })
                .collect();
            let area = polygon_area(&p);
            let outside: Vec<Option<f64>> =
                (0..6).map(|i| (i != 0).then_some(area / 2.0)).collect();
            let (by_corner, by_size) = (jump_of(&p, &outside, 0.0), jump_of(&p, &outside, 10.0));
            tried += 1;
            // never further past the bound than the corners' choice
            assert!(by_size.max(2.0) <= by_corner.max(2.0) + 1e-12);
            fitted += usize::from(by_corner > 2.0 && by_size <= 2.0);
        }
        assert!(fitted >= 3, "{fitted} of {tried} brought within the bound");
    }
}
