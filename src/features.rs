//! Feature recognition: how the host reads the front round an edge for
//! the KB. The front reads N7, N4, N1, N2, N5 along the edge N1N2 with the
//! remaining domain on the element's side (kb/features.pl); the context
//! is the angles there and the neighbouring edges' lengths, and the KB
//! names the feature (b1..b5) the edge shows.

use crate::front::{Front, Fv};
use crate::kb::{Context, FrontFacts, KbError, KnowledgeBase};
use crate::partial_mesh::PartialMesh;
use crate::report::trace::Angles;

/// The labelled occurrences around an oriented edge.
#[derive(Debug, Clone, Copy)]
pub struct Labels {
    /// N7, two before N1.
    pub n7: Fv,
    /// N4, before N1.
    pub n4: Fv,
    /// N1.
    pub n1: Fv,
    /// N2.
    pub n2: Fv,
    /// N5, after N2.
    pub n5: Fv,
    /// Read against the loop's direction (the element on the right).
    pub mirrored: bool,
}

/// An angle in whole degrees, as the KB sees it.
pub fn deg_round(x: f64) -> f64 {
    x.round()
}

/// The occurrence after `fv` in the reading's direction.
pub fn along(front: &Front, fv: Fv, mirrored: bool) -> Fv {
    if mirrored {
        front.prev(fv)
    } else {
        front.next(fv)
    }
}

fn back(front: &Front, fv: Fv, mirrored: bool) -> Fv {
    along(front, fv, !mirrored)
}

/// The labels of the edge from occurrence `fv` to the next, read along
/// the loop or (`mirrored`) against it.
pub fn labels(front: &Front, fv: Fv, mirrored: bool) -> Labels {
    let (n1, n2) = if mirrored {
        (front.next(fv), fv)
    } else {
        (fv, front.next(fv))
    };
    let n4 = back(front, n1, mirrored);
    let n7 = back(front, n4, mirrored);
    let n5 = along(front, n2, mirrored);
    Labels {
        n7,
        n4,
        n1,
        n2,
        n5,
        mirrored,
    }
}

/// The labels of the next edge along (redesign rules Rd10, Rd12).
pub fn labels_shifted(front: &Front, lab: &Labels) -> Labels {
    Labels {
        n7: lab.n4,
        n4: lab.n1,
        n1: lab.n2,
        n2: lab.n5,
        n5: along(front, lab.n5, lab.mirrored),
        mirrored: lab.mirrored,
    }
}

/// The context of a labelled edge of the run `pm` with its five angles
/// measured.
pub fn context(pm: &PartialMesh, lab: &Labels) -> Context {
    let (front, nodes) = (&pm.front, &pm.mesh.nodes);
    let t = |fv| deg_round(front.angle(fv, nodes));
    context_given(
        pm,
        lab,
        [t(lab.n7), t(lab.n4), t(lab.n1), t(lab.n2), t(lab.n5)],
    )
}

/// The context of a labelled edge with the five angles given: the
/// neighbouring edges l5, l6 relative to N1N2 (two decimals) and the
/// grading ratio (`PartialMesh::grading_ratio`).
pub fn context_given(pm: &PartialMesh, lab: &Labels, t: [f64; 5]) -> Context {
    let (front, nodes) = (&pm.front, &pm.mesh.nodes);
    let pos = |fv: Fv| nodes[front.node(fv) as usize];
    let l1 = (pos(lab.n2) - pos(lab.n1)).length().max(1e-300);
    let r = |x: f64| ((x / l1) * 100.0).round() / 100.0;
    Context([
        t[0],
        t[1],
        t[2],
        t[3],
        t[4],
        r((pos(lab.n1) - pos(lab.n4)).length()),
        r((pos(lab.n5) - pos(lab.n2)).length()),
        pm.grading_ratio(pos(lab.n1), pos(lab.n2)),
    ])
}

/// The trace's record of the angles a design saw, and of the grading
/// ratio where it is not 1 (graded runs, and edges of a uniform run far
/// from its size: `PartialMesh::grading_ratio`).
pub fn angle_map(angles: &[f64; 5], ratio: f64) -> Angles {
    let names = ["theta7", "theta4", "theta1", "theta2", "theta5"];
    let mut named: Vec<(&'static str, f64)> =
        names.into_iter().zip(angles.iter().copied()).collect();
    if ratio != 1.0 {
        named.push(("ratio", ratio));
    }
    Angles::new(named)
}

/// A front node as the feature recognition sees it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct NodeFeature {
    /// Node id.
    pub node: u32,
    /// Coordinates.
    pub x: f64,
    /// Coordinates.
    pub y: f64,
    /// Interior angle of the remaining domain (deg, rounded).
    pub angle: f64,
    /// Whether the KB calls it a concave point.
    pub concave: bool,
}

/// A front edge read from N1 to N2, with the KB's feature and action.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EdgeFeature {
    /// N1.
    pub n1: u32,
    /// N2.
    pub n2: u32,
    /// The context term the KB was asked with.
    pub ctx: String,
    /// The feature, if any.
    pub feature: Option<String>,
    /// The action the KB would take.
    pub action: Option<String>,
}

/// The features of a front.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct FrontFeatures {
    /// Nodes in loop order.
    pub nodes: Vec<NodeFeature>,
    /// Edges, each in both readings.
    pub edges: Vec<EdgeFeature>,
}

/// The boundary features of a front, as the KB sees them: every node
/// with its angle and whether it is concave, every edge in both readings
/// with its feature and action (None: no feature).
pub fn front_features(pm: &PartialMesh, kb: &mut KnowledgeBase) -> Result<FrontFeatures, KbError> {
    let (front, nodes) = (&pm.front, &pm.mesh.nodes);
    let mut out = FrontFeatures::default();
    for l in front.live_loops() {
        for fv in front.loop_fvs(l) {
            let n = front.node(fv);
            let angle = deg_round(front.angle(fv, nodes));
            let concave = kb.is_concave(angle)?;
            out.nodes.push(NodeFeature {
                node: n,
                x: nodes[n as usize].x,
                y: nodes[n as usize].y,
                angle,
                concave,
            });
            for mirrored in [false, true] {
                let lab = labels(front, fv, mirrored);
                let ctx = context(pm, &lab);
                let (feature, action) = kb.design_text(&ctx)?;
                out.edges.push(EdgeFeature {
                    n1: front.node(lab.n1),
                    n2: front.node(lab.n2),
                    ctx: ctx.to_string(),
                    feature,
                    action,
                });
            }
        }
    }
    Ok(out)
}

/// The front as facts for the KB (kb/front.pl): node_xy/3, front_edge/2,
/// node_angle/2 and edge_context/3 for both readings of every edge.
pub fn front_facts(pm: &PartialMesh) -> FrontFacts {
    let (front, nodes) = (&pm.front, &pm.mesh.nodes);
    let mut facts = FrontFacts::default();
    let mut seen = rustc_hash::FxHashSet::default();
    for l in front.live_loops() {
        for fv in front.loop_fvs(l) {
            let n = front.node(fv);
            if seen.insert(n) {
                facts.nodes.push((n, nodes[n as usize]));
            }
            facts.edges.push((n, front.node(front.next(fv))));
            facts.angles.push((n, deg_round(front.angle(fv, nodes))));
            // the edge as the front has it, read from either end
            let next = front.node(front.next(fv));
            for mirrored in [false, true] {
                let lab = labels(front, fv, mirrored);
                let from = front.node(lab.n1);
                facts.contexts.push((n, next, from, context(pm, &lab)));
            }
        }
    }
    facts
}
