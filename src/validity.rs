//! Validity before anything: every element is checked against the front
//! before it is committed. It must be convex with every corner in
//! [4, 176] degrees (the KB's `bound(valid_corner, 4)`, as each number
//! here), no edge a sliver, no front edge crossing it, no
//! front node inside it and, for a designed element, no new corner or
//! edge so close to the front that a sliver is left between them. An
//! element that takes a tip (a front corner below `bound(tip_corner, _)`)
//! whole may have its corner there as sharp as the tip, and its sides
//! across the tip as short as the tip's wedge makes them.
//! Orientation and crossing tests use robust predicates (geometry.rs).

use glam::DVec2;

use crate::front::Front;
use crate::geometry::{
    orient2d, point_segment_distance, quad_angles, segments_intersect, SegmentRelation,
};
use crate::initial_design::{qnode_id, qpos, QNode};
use crate::partial_mesh::PartialMesh;

/// Why the validity check refused an element (recorded in the trace as a
/// veto, see report/trace.rs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Vetoed {
    /// Not convex, or two corners at one node.
    NotConvex,
    /// A corner outside [4, 176] degrees (`bound(valid_corner, _)`).
    Corner,
    /// An edge shorter than a quarter of the base edge
    /// (`bound(valid_edge, _)`) or the run's minimum.
    ShortEdge,
    /// A front edge crosses it, a front node is inside it, or a new
    /// corner or edge comes too close to the front
    /// (`bound(valid_clearance, _)`).
    Front,
    /// Committing it would leave a loop odd or degenerate, or the
    /// remaining domain a spike (`bound(min_front_angle, _)`).
    Loop,
    /// An action the host cannot place as an element here.
    NotPlaceable,
    /// A transition whose new edge would be longer than
    /// `bound(coarsest_edge, _)` times the run's `max_size`.
    AboveCoarsestEdge,
}

impl Vetoed {
    /// Its name in the trace.
    pub fn reason(self) -> &'static str {
        match self {
            Vetoed::NotConvex => "not_convex",
            Vetoed::Corner => "corner_outside_valid_corner",
            Vetoed::ShortEdge => "short_edge",
            Vetoed::Front => "front_crossed_or_too_close",
            Vetoed::Loop => "odd_loop_or_spike",
            Vetoed::NotPlaceable => "not_placeable",
            Vetoed::AboveCoarsestEdge => "above_coarsest_edge",
        }
    }
}

/// Counter-clockwise corner positions of an element.
fn ccw(front: &Front, nodes: &[DVec2], q: &[QNode; 4], mirrored: bool) -> [DVec2; 4] {
    let p = q.map(|x| qpos(front, nodes, x));
    if mirrored {
        [p[3], p[2], p[1], p[0]]
    } else {
        p
    }
}

/// Hard validity of a designed element (corners in labelled order,
/// `mirrored` for the reading against the loop), by the KB's thresholds
/// (`pm.host`; built in: a convex element with corners in [4, 176]
/// degrees, every edge at least a quarter of the base edge and the run's
/// minimum, and clear of the front, see `quad_clear`, with a gap of 0.15
/// of the base edge). Err says why not.
pub fn element_valid(pm: &mut PartialMesh, q: &[QNode; 4], mirrored: bool) -> Result<(), Vetoed> {
    let p = ccw(&pm.front, &pm.mesh.nodes, q, mirrored);
    let ids: Vec<Option<u32>> = {
        let v = q.map(|x| qnode_id(&pm.front, x));
        if mirrored {
            vec![v[3], v[2], v[1], v[0]]
        } else {
            v.to_vec()
        }
    };
    for i in 0..4 {
        if orient2d(p[i], p[(i + 1) % 4], p[(i + 2) % 4]) <= 0.0 {
            return Err(Vetoed::NotConvex);
        }
        if let (Some(a), Some(b)) = (ids[i], ids[(i + 1) % 4]) {
            if a == b {
                return Err(Vetoed::NotConvex);
            }
        }
    }
    // a tip (a front corner sharper than `tip_corner`) taken whole: its
    // corner may be as sharp as the front's, and its sides across the tip
    // as short as the tip's wedge makes them
    let h = pm.host;
    let tip = whole_tip(pm, q, h.tip_corner);
    let clearly_open = (0..4).all(|i| {
        let a = p[(i + 1) % 4] - p[i];
        let b = p[(i + 3) % 4] - p[i];
        let d = a.dot(b);
        d * d < h.cos2_valid_corner * (1.0 - 1e-9) * a.length_squared() * b.length_squared()
    });
    let corners = h.valid_corner..=180.0 - h.valid_corner;
    let tip_ok = |a: f64| tip.is_some_and(|(t, _)| a > 0.0 && a <= t + 1e-9);
    if !clearly_open
        && quad_angles(p)
            .iter()
            .any(|&a| !corners.contains(&a) && !tip_ok(a))
    {
        return Err(Vetoed::Corner);
    }
    // No sliver: every edge at least a quarter of the base edge, so a
    // rule that keeps shrinking an element cannot run away. Beside a tip
    // of angle t the sides across it are shorter (`whole_tip`).
    let pos = |x| qpos(&pm.front, &pm.mesh.nodes, x);
    let base = (pos(q[1]) - pos(q[0])).length();
    let scale = tip.map_or(1.0, |(_, s)| s);
    let shortest = (h.valid_edge * base).max(pm.min_edge) * scale;
    if (0..4).any(|i| (p[(i + 1) % 4] - p[i]).length() < shortest) {
        return Err(Vetoed::ShortEdge);
    }
    if quad_clear(pm, p, &ids, h.valid_clearance * base) {
        Ok(())
    } else {
        Err(Vetoed::Front)
    }
}

/// The sharpest tip (a front corner below `tip_corner` degrees) the
/// element takes whole, its two sides there being the front's edges: the
/// corner (degrees) and the share sqrt(2) sin(t/2) of the usual shortest
/// edge its sides across the tip may come down to (a kite over the tip
/// with a right angle opposite, kb/design.pl, has sides that short).
fn whole_tip(pm: &PartialMesh, q: &[QNode; 4], tip_corner: f64) -> Option<(f64, f64)> {
    let front = &pm.front;
    let mut out: Option<(f64, f64)> = None;
    for k in 0..4 {
        let QNode::Front(fv) = q[k] else { continue };
        let (a, b) = (
            qnode_id(front, q[(k + 1) % 4]),
            qnode_id(front, q[(k + 3) % 4]),
        );
        let (p, n) = (front.node(front.prev(fv)), front.node(front.next(fv)));
        let whole = (a == Some(p) && b == Some(n)) || (a == Some(n) && b == Some(p));
        if !whole {
            continue;
        }
        let t = front.angle(fv, &pm.mesh.nodes);
        if t < tip_corner && out.map_or(true, |(o, _)| t < o) {
            // the kite's sides across a tip of t: sqrt 2 sin(t/2) of its
            // sides along the front
            let s = (std::f64::consts::SQRT_2 * (t / 2.0).to_radians().sin()).min(1.0);
            out = Some((t, s));
        }
    }
    out
}

/// True iff no front edge crosses the element `p` (counter-clockwise;
/// `ids` the node ids of its corners, None for new ones), no front node
/// lies inside it, and, with `gap` > 0, no new corner comes closer than
/// `gap` to a front edge nor a front node to a new edge.
pub fn quad_clear(pm: &mut PartialMesh, p: [DVec2; 4], ids: &[Option<u32>], gap: f64) -> bool {
    let pad = DVec2::splat(gap);
    let lo = p.iter().fold(DVec2::splat(f64::MAX), |a, &b| a.min(b)) - pad;
    let hi = p.iter().fold(DVec2::splat(f64::MIN), |a, &b| a.max(b)) + pad;
    let mut near = std::mem::take(&mut pm.scratch);
    pm.front.edges_near(lo, hi, &mut near);
    let is_quad_node = |n: u32| ids.contains(&Some(n));
    let mut ok = true;
    'edges: for &e in &near {
        let (na, nb) = (pm.front.node(e), pm.front.node(pm.front.next(e)));
        let (a, b) = (pm.mesh.nodes[na as usize], pm.mesh.nodes[nb as usize]);
        // a front node strictly inside the element
        if !is_quad_node(na) && (0..4).all(|i| orient2d(p[i], p[(i + 1) % 4], a) > 0.0) {
            ok = false;
            break;
        }
        // no sliver left between the element and the front: a new
        // corner keeps off front edges, a front node off new edges
        if gap > 0.0 && !is_quad_node(na) && !is_quad_node(nb) {
            for i in 0..4 {
                if ids[i].is_none() && point_segment_distance(p[i], a, b) < gap {
                    ok = false;
                    break 'edges;
                }
            }
        }
        if gap > 0.0 && !is_quad_node(na) {
            for i in 0..4 {
                let new_edge = ids[i].is_none() || ids[(i + 1) % 4].is_none();
                if new_edge && point_segment_distance(a, p[i], p[(i + 1) % 4]) < gap {
                    ok = false;
                    break 'edges;
                }
            }
        }
        for i in 0..4 {
            let (qa, qb) = (ids[i], ids[(i + 1) % 4]);
            if let (Some(x), Some(y)) = (qa, qb) {
                if (x == na && y == nb) || (x == nb && y == na) {
                    continue; // the front edge is this element edge
                }
            }
            match segments_intersect(p[i], p[(i + 1) % 4], a, b) {
                SegmentRelation::Disjoint => {}
                SegmentRelation::Touch => {
                    // only at a node the two share
                    let shared = [qa, qb]
                        .iter()
                        .any(|q| q.is_some_and(|q| q == na || q == nb));
                    if !shared {
                        ok = false;
                        break 'edges;
                    }
                }
                _ => {
                    ok = false;
                    break 'edges;
                }
            }
        }
    }
    pm.scratch = near;
    ok
}

/// Whether `q` (counter-clockwise) is convex with every corner in
/// [1, 179] degrees: good enough to close a loop with.
pub fn convex_ok(q: &[DVec2; 4]) -> bool {
    convex_angles(q).is_some()
}

/// The corner angles of `q` if it passes `convex_ok`.
pub fn convex_angles(q: &[DVec2; 4]) -> Option<[f64; 4]> {
    if !(0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) > 0.0) {
        return None;
    }
    let a = quad_angles(*q);
    a.iter().all(|&a| (1.0..=179.0).contains(&a)).then_some(a)
}

/// Whether the node ids are all different (a loop that does not touch
/// itself).
pub fn distinct(ids: &[u32]) -> bool {
    let mut v = ids.to_vec();
    v.sort_unstable();
    v.windows(2).all(|w| w[0] != w[1])
}
