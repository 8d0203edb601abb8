//! Redesign: the host measures how a candidate element sits in the
//! remaining domain (the relations: corners it leaves, front nodes and
//! segments its new corners and edges come near), and the KB's redesign
//! rules (kb/redesign.pl, Rd1-Rd13) say which constraint is broken and
//! how to correct the action: new parameters, the action on the next
//! edge, or a new corner merged with a front node (fronts that meet).

use glam::DVec2;

use crate::features::{context, deg_round, labels_shifted, Labels};
use crate::front::Fv;
use crate::geometry::point_segment_distances;
use crate::initial_design::{apply_merges, element, qnode_id, qpos, QNode};
use crate::kb::{
    Action, Corner, ElementEdge, ElementNode, KbError, KnowledgeBase, Redesigned, Relation,
};
use crate::partial_mesh::PartialMesh;

/// What the redesign rules made of a design.
pub struct Redesign {
    /// The element to check and commit (merges applied), None when the
    /// action cannot be placed.
    pub element: Option<[QNode; 4]>,
    /// The action in the end.
    pub action: Action,
    /// The edge it acts on in the end.
    pub labels: Labels,
    /// The front occurrences the new corners N3, N4 merge with.
    pub merges: [Option<Fv>; 2],
    /// The rules that fired, in order.
    pub fired: Vec<String>,
}

/// Lets the redesign rules correct `action` over `lab`, at most `rounds`
/// times: each round places the element, measures its relations and asks
/// the KB, until no rule fires (or a merge fixes a corner).
pub fn redesign(
    pm: &mut PartialMesh,
    kb: &mut KnowledgeBase,
    rounds: usize,
    mut action: Action,
    mut lab: Labels,
) -> Result<Redesign, KbError> {
    let mut fired = Vec::new();
    let mut merges: [Option<Fv>; 2] = [None, None];
    let mut q = None;
    for round in 0..=rounds {
        let Some(el) = element(&pm.front, &pm.mesh.nodes, &action, &lab) else {
            break;
        };
        let (rel, targets) = relations(pm, &el, &lab, &action);
        q = Some(el);
        if round == rounds || rel.is_empty() {
            break;
        }
        let ctx = context(pm, &lab);
        let Some(Redesigned { rule, action: new }) = kb.redesign(&ctx, &action, &rel)? else {
            break;
        };
        fired.push(rule);
        pm.stats.redesigns += 1;
        match new {
            Action::Shift(a) => {
                lab = labels_shifted(&pm.front, &lab);
                action = *a;
                merges = [None, None];
            }
            Action::Merge(c, a) => {
                let slot = if c == Corner::N3 { 0 } else { 1 };
                if targets[slot].is_none() {
                    break;
                }
                merges[slot] = targets[slot];
                let merge = Action::Merge(c, a.clone());
                action = *a;
                // the merged corner is fixed now: judge the rest
                q = element(&pm.front, &pm.mesh.nodes, &action, &lab)
                    .map(|e| apply_merges(e, &merges));
                // the merged element's own corners shown to the KB: a rule
                // may undo the merge (fronts that met at an open node the
                // element would take whole), the element placed as designed
                if let Some(merged) = q {
                    let wide = wide_corners(pm, &merged);
                    if !wide.is_empty() {
                        let ctx = context(pm, &lab);
                        if let Some(Redesigned { rule, action: new }) =
                            kb.redesign(&ctx, &merge, &wide)?
                        {
                            fired.push(rule);
                            pm.stats.redesigns += 1;
                            merges = [None, None];
                            action = new;
                            q = None;
                        }
                    }
                }
                break;
            }
            a => action = a,
        }
        q = None;
    }
    let element = q
        .or_else(|| element(&pm.front, &pm.mesh.nodes, &action, &lab))
        .map(|el| apply_merges(el, &merges));
    Ok(Redesign {
        element,
        action,
        labels: lab,
        merges,
        fired,
    })
}

/// The relations the redesign rules judge, and the nearest front
/// occurrence to each new corner (a merge target).
pub fn relations(
    pm: &mut PartialMesh,
    q: &[QNode; 4],
    lab: &Labels,
    action: &Action,
) -> (Vec<Relation>, [Option<Fv>; 2]) {
    let pos: Vec<DVec2> = q
        .iter()
        .map(|&x| qpos(&pm.front, &pm.mesh.nodes, x))
        .collect();
    let s = (0..4)
        .map(|i| (pos[(i + 1) % 4] - pos[i]).length())
        .sum::<f64>()
        / 4.0;
    let mut rel = Vec::new();
    let mut targets = [None, None];
    let ids: Vec<Option<u32>> = q.iter().map(|&x| qnode_id(&pm.front, x)).collect();
    let is_quad_node = |n: u32| ids.contains(&Some(n));
    let r3 = |x: f64| (x * 1000.0).round() / 1000.0;
    // the element's corners in labelled order (unsigned: it is convex
    // when it matters), and what the remaining domain keeps
    let qa: [f64; 4] =
        std::array::from_fn(|i| corner_angle(pos[(i + 3) % 4], pos[i], pos[(i + 1) % 4]));
    let th = |fv: Fv| pm.front.angle(fv, &pm.mesh.nodes);
    // the thresholds of what redesign is shown (bound/2, settings.rs)
    let h = pm.host;
    let outer = |rel: &mut Vec<Relation>, node: ElementNode, deg: f64| {
        if deg < h.relation_corner {
            rel.push(Relation::OuterCorner {
                node,
                deg: deg_round(deg),
            });
        }
    };
    match action {
        Action::A1 { .. } => {
            outer(&mut rel, ElementNode::N1, th(lab.n1) - qa[0]);
            outer(&mut rel, ElementNode::N2, th(lab.n2) - qa[1]);
        }
        Action::A2 { .. } | Action::A4 => {
            outer(&mut rel, ElementNode::N2, th(lab.n2) - qa[1]);
            outer(&mut rel, ElementNode::N4, th(lab.n4) - qa[3]);
        }
        Action::A3 => {
            for (node, i, fv) in [
                (ElementNode::N3, 2usize, lab.n5),
                (ElementNode::N4, 3, lab.n4),
            ] {
                if qa[i] < h.relation_corner || qa[i] > h.relation_inner_above {
                    rel.push(Relation::InnerCorner {
                        node,
                        deg: deg_round(qa[i]),
                    });
                }
                let left = th(fv) - qa[i];
                if left < h.relation_corner {
                    rel.push(Relation::RemainingCorner {
                        node,
                        deg: deg_round(left),
                    });
                }
            }
        }
        _ => {}
    }
    // new corners near front nodes and segments
    for (ci, &qi) in [2usize, 3].iter().enumerate() {
        let QNode::New(c) = q[qi] else { continue };
        let corner = if qi == 2 {
            ElementNode::N3
        } else {
            ElementNode::N4
        };
        let r = s * h.relation_reach;
        let mut near = std::mem::take(&mut pm.scratch);
        pm.front
            .edges_near(c - DVec2::splat(r), c + DVec2::splat(r), &mut near);
        let mut best: Option<(f64, Fv)> = None;
        let mut worst_seg: Option<(f64, f64, f64)> = None;
        for &e in &near {
            let (na, nb) = (pm.front.node(e), pm.front.node(pm.front.next(e)));
            if !is_quad_node(na) && pm.front.loop_of(e) == pm.front.loop_of(lab.n1) {
                let d = (pm.mesh.nodes[na as usize] - c).length();
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, e));
                }
            }
            if is_quad_node(na) || is_quad_node(nb) {
                continue;
            }
            let (v, h) =
                point_segment_distances(c, pm.mesh.nodes[na as usize], pm.mesh.nodes[nb as usize]);
            if worst_seg.is_none_or(|w| v + h < w.0 + w.1) {
                worst_seg = Some((v, h, v + h));
            }
        }
        pm.scratch = near;
        if let Some((d, e)) = best {
            if d < s {
                rel.insert(
                    0,
                    Relation::CornerNode {
                        corner,
                        distance: r3(d / s),
                    },
                );
                targets[ci] = Some(e);
            }
        }
        if let Some((v, h, _)) = worst_seg.filter(|w| w.0 < s && w.1 < s) {
            rel.push(Relation::CornerSegment {
                corner,
                vertical: r3(v / s),
                horizontal: r3(h / s),
            });
        }
    }
    // element edges near concave front nodes
    for (edge, i, j) in [
        (ElementEdge::E23, 1usize, 2usize),
        (ElementEdge::E34, 2, 3),
        (ElementEdge::E41, 3, 0),
    ] {
        if !matches!(q[i], QNode::New(_)) && !matches!(q[j], QNode::New(_)) {
            continue;
        }
        let (a, b) = (pos[i], pos[j]);
        let lo = a.min(b) - DVec2::splat(s * 0.5);
        let hi = a.max(b) + DVec2::splat(s * 0.5);
        let mut near = std::mem::take(&mut pm.scratch);
        pm.front.edges_near(lo, hi, &mut near);
        let mut worst: Option<(f64, f64, f64)> = None;
        for &e in &near {
            let n = pm.front.node(e);
            if is_quad_node(n) {
                continue;
            }
            let t = pm.front.angle(e, &pm.mesh.nodes);
            if t <= 180.0 {
                continue;
            }
            let (v, h) = point_segment_distances(pm.mesh.nodes[n as usize], a, b);
            if worst.is_none_or(|w| v + h < w.0 + w.1) {
                worst = Some((v, h, t));
            }
        }
        pm.scratch = near;
        if let Some((v, h, t)) = worst.filter(|w| w.0 < s && w.1 < s) {
            rel.push(Relation::EdgePoint {
                edge,
                vertical: r3(v / s),
                horizontal: r3(h / s),
                angle: deg_round(t),
            });
        }
    }
    (rel, targets)
}

/// The unsigned angle at `v` between the directions to `a` and `b` (deg).
/// The corners of element `q` above `bound(relation_inner_above, _)`, as
/// inner_corner relations (labelled N1..N4 in the element's order).
fn wide_corners(pm: &PartialMesh, q: &[QNode; 4]) -> Vec<Relation> {
    let pos: Vec<DVec2> = q
        .iter()
        .map(|&x| qpos(&pm.front, &pm.mesh.nodes, x))
        .collect();
    let names = [
        ElementNode::N1,
        ElementNode::N2,
        ElementNode::N3,
        ElementNode::N4,
    ];
    (0..4)
        .filter_map(|i| {
            let deg = corner_angle(pos[(i + 3) % 4], pos[i], pos[(i + 1) % 4]);
            (deg > pm.host.relation_inner_above).then(|| Relation::InnerCorner {
                node: names[i],
                deg: deg_round(deg),
            })
        })
        .collect()
}

fn corner_angle(a: DVec2, v: DVec2, b: DVec2) -> f64 {
    let (x, y) = (a - v, b - v);
    x.perp_dot(y).abs().atan2(x.dot(y)).to_degrees()
}
