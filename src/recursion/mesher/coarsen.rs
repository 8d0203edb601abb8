//! The transitions: to a coarser interior, the action t3 (kb/design.pl,
//! feature coarsen), and its mirror to a finer one, r3 (feature refine).
//! In t3 three flat front edges b0b1, b1b2, b2b3 (N4N1, N1N2, N2N5)
//! become one, t0t1, over two rows of four elements:
//!
//! ```text
//!   t0 ------------------ t1
//!   |  \               /  |
//!   |   m1 --------- m2   |
//!   |   |            |    |
//!   b0--b1 --------- b2--b3
//! ```
//!
//! b0 b1 m1 t0, b1 b2 m2 m1, b2 b3 t1 m2 and m1 m2 t1 t0; the front then
//! reads b0 t0 t1 b3 (as many edges as before, so every loop stays even).
//! The elements are committed one by one, as a1, a2, a2 and a3 would make
//! them, each traced with the t3 that placed it.
//!
//! Beside an earlier transition (the KB's coarsen admits a right angle
//! at b0 or b3, a step), the step's top node is where t0 (or t1) would
//! go: the template takes that node instead of making one, so that
//! transitions sit side by side and the coarser front they leave is flat
//! and even, ready for the next one. The first element is then made as
//! a2 would make it, the third as a3; each step taken removes two more
//! front edges.
//!
//! r3 is the same template upside down: one front edge t0t1 far coarser
//! than the place asks for (a fixed segment count coarser than the size)
//! becomes three, b0b1, b1b2, b2b3, over two rows: t0 t1 m2 m1 (the cap),
//! t0 m1 b1 b0, m1 m2 b2 b1 and m2 t1 b3 b2; the front then reads t0 b0
//! b1 b2 b3 t1 (four edges more, every loop stays even). Beside an earlier
//! refinement, b0 (or b3) is that one's step top, N4 (or N5), taken as t3
//! takes its own.

use glam::DVec2;

use super::Mesher;
use crate::features::{along, labels, Labels};
use crate::front::Fv;
use crate::initial_design::{qpos, QNode};
use crate::kb::Action;
use crate::recursion::MeshError;
use crate::report::trace::{Angles, By, TraceStep, Veto};
use crate::validity::{element_valid, Vetoed};

/// Where the four new nodes go: m1, m2 above b1, b2 at `height` times
/// the edges' mean length, t0, t1 above b0, b3 at twice that (each along
/// the normal of its side's edge, toward the domain).
fn template_nodes(b: [DVec2; 4], side: f64, height: f64) -> [DVec2; 4] {
    let normal = |a: DVec2, c: DVec2| {
        let d = (c - a).normalize_or_zero();
        DVec2::new(-d.y, d.x) * side
    };
    let (n01, n12, n23) = (normal(b[0], b[1]), normal(b[1], b[2]), normal(b[2], b[3]));
    let mean = ((b[1] - b[0]).length() + (b[2] - b[1]).length() + (b[3] - b[2]).length()) / 3.0;
    let h = height * mean;
    let m1 = b[1] + (n01 + n12).normalize_or_zero() * h;
    let m2 = b[2] + (n12 + n23).normalize_or_zero() * h;
    [m1, m2, b[0] + n01 * 2.0 * h, b[3] + n23 * 2.0 * h]
}

/// The actions a transition's elements are committed as (the template
/// has placed their nodes; these say which of them are new).
const SQUARE_A1: Action = Action::A1 {
    phi1: 90.0,
    phi2: 90.0,
    l2: 1.0,
    l4: 1.0,
};
const SQUARE_A2: Action = Action::A2 {
    phi2: 90.0,
    phi4: 90.0,
};

/// The labels of the edge from occurrence `first` to the next in the
/// reading's direction (against the loop's where `mirrored`).
fn reading_labels(front: &crate::front::Front, first: Fv, mirrored: bool) -> Labels {
    let fv = if mirrored {
        along(front, first, true)
    } else {
        first
    };
    labels(front, fv, mirrored)
}

/// Where r3's six new nodes go over the edge t0t1: m1, m2 at its thirds,
/// `height` times a third of it inside; b1, b2 above them and b0, b3
/// above t0, t1, at twice that.
fn refine_nodes(t0: DVec2, t1: DVec2, side: f64, height: f64) -> [DVec2; 6] {
    let d = t1 - t0;
    let u = d.normalize_or_zero();
    let h = DVec2::new(-u.y, u.x) * side * height * d.length() / 3.0;
    let (m1, m2) = (t0 + d / 3.0 + h, t0 + d * (2.0 / 3.0) + h);
    [m1, m2, t0 + h * 2.0, m1 + h, m2 + h, t1 + h * 2.0]
}

impl Mesher<'_> {
    /// Carries out r3 over the labelled edge N1N2: checks the four
    /// elements against the front, then commits them (the cap as a1
    /// makes it, the others as a1, a2 and a2 or a3 would). False (a veto
    /// in the trace) when they do not fit.
    pub(super) fn try_refine(
        &mut self,
        lab: Labels,
        action: &Action,
        feature: &str,
        angles: Angles,
    ) -> Result<bool, MeshError> {
        let Action::R3 { height } = *action else {
            return Ok(false);
        };
        let (t0, t1) = (self.pm.pos(lab.n1), self.pm.pos(lab.n2));
        let side = if lab.mirrored { -1.0 } else { 1.0 };
        let [m1, m2, b0, b1, b2, b3] = refine_nodes(t0, t1, side, height);
        // a step's top beside the edge is taken for b0 (N4) or b3 (N5):
        // within a third of the template's height of it
        let near = 0.3 * (b0 - t0).length();
        let left = self.node_near(lab.n4, b0, near);
        let right = self.node_near(lab.n5, b3, near);
        if left.is_some() && left == right {
            return Ok(false);
        }
        let (f, n) = (QNode::Front, QNode::New);
        let top0 = left.map_or(n(b0), f);
        let top3 = right.map_or(n(b3), f);
        let quads = [
            [f(lab.n1), f(lab.n2), n(m2), n(m1)],
            [f(lab.n1), n(m1), n(b1), top0],
            [n(m1), n(m2), n(b2), n(b1)],
            [n(m2), f(lab.n2), top3, n(b2)],
        ];
        let edge = [
            self.pm.front.node(lab.n1) as i64,
            self.pm.front.node(lab.n2) as i64,
        ];
        if !self.template_fits(&quads, lab.mirrored, None, edge, feature, action) {
            return Ok(false);
        }
        let mir = lab.mirrored;
        let edge_labels = |m: &Self, first: Fv| reading_labels(&m.pm.front, first, mir);
        // the cap over N1N2
        let l = edge_labels(self, lab.n1);
        if l.n2 != lab.n2 {
            return Ok(false);
        }
        let cap = [f(l.n1), f(l.n2), n(m2), n(m1)];
        if !self.commit_part(&cap, &l, &SQUARE_A1, edge, feature, action, &angles)? {
            return Ok(false);
        }
        // from here on the refinement has begun: true whatever follows
        // t0 m1 b1 b0 over N1 m1 (b0 the step's top N4, as a2 takes N4)
        let l = edge_labels(self, lab.n1);
        let (m1_fv, m2_fv) = (l.n2, along(&self.pm.front, l.n2, mir));
        let (left_el, act) = match left {
            Some(top) if top == l.n4 => ([f(l.n1), f(l.n2), n(b1), f(top)], &SQUARE_A2),
            Some(_) => return Ok(true),
            None => ([f(l.n1), f(l.n2), n(b1), n(b0)], &SQUARE_A1),
        };
        if !self.commit_part(&left_el, &l, act, edge, feature, action, &angles)? {
            return Ok(true);
        }
        // m1 m2 b2 b1 over m1 m2, then m2 t1 b3 b2 over m2 N2 (b3 the
        // step's top N5, linked as a3 links N4 and N5)
        for k in 0..2 {
            let first = if k == 0 { m1_fv } else { m2_fv };
            if !self.pm.front.alive(first) {
                break;
            }
            let l = edge_labels(self, first);
            let (el, act) = match (k, right) {
                (0, _) => ([f(l.n1), f(l.n2), n(b2), f(l.n4)], &SQUARE_A2),
                (_, Some(top)) if top == l.n5 && l.n2 == lab.n2 => {
                    ([f(l.n1), f(l.n2), f(top), f(l.n4)], &Action::A3)
                }
                (_, Some(_)) => break,
                (_, None) => ([f(l.n1), f(l.n2), n(b3), f(l.n4)], &SQUARE_A2),
            };
            if !self.commit_part(&el, &l, act, edge, feature, action, &angles)? {
                break;
            }
        }
        Ok(true)
    }

    /// Carries out t3 over the labelled edge (N1N2 the middle one of the
    /// three): checks the four elements against the front, then commits
    /// them. False (a veto in the trace) when they do not fit.
    pub(super) fn try_coarsen(
        &mut self,
        lab: Labels,
        action: &Action,
        feature: &str,
        angles: Angles,
    ) -> Result<bool, MeshError> {
        let Action::T3 { height } = *action else {
            return Ok(false);
        };
        let b_fv = [lab.n4, lab.n1, lab.n2, lab.n5];
        let b_id = b_fv.map(|fv| self.pm.front.node(fv));
        let b = b_id.map(|n| self.pm.mesh.nodes[n as usize]);
        let side = if lab.mirrored { -1.0 } else { 1.0 };
        let [m1, m2, t0, t1] = template_nodes(b, side, height);
        // a step's top node near t0 (before b0) or t1 (after b3) is taken
        // instead: within a third of the template's height of it
        let near = 0.3 * (t0 - b[0]).length().min((t1 - b[3]).length());
        let step_top =
            |fv: Fv, at: DVec2| self.node_near(fv, at, near).filter(|fv| !b_fv.contains(fv));
        let left = step_top(lab.n7, t0);
        let right = step_top(along(&self.pm.front, lab.n5, lab.mirrored), t1);
        if left.is_some() && left == right {
            return Ok(false);
        }
        // each of the four judged as any designed element is (labelled
        // order, the reading's orientation)
        let (f, n) = (QNode::Front, QNode::New);
        let top0 = left.map_or(n(t0), f);
        let top1 = right.map_or(n(t1), f);
        let quads = [
            [f(b_fv[0]), f(b_fv[1]), n(m1), top0],
            [f(b_fv[1]), f(b_fv[2]), n(m2), n(m1)],
            [f(b_fv[2]), f(b_fv[3]), top1, n(m2)],
            [n(m1), n(m2), top1, top0],
        ];
        let edge = [b_id[1] as i64, b_id[2] as i64];
        // the new edge t0t1 no longer than the KB's coarsest edge allows
        let at = |q: QNode| qpos(&self.pm.front, &self.pm.mesh.nodes, q);
        let too_coarse = self.pm.size_field.as_ref().is_some_and(|f| {
            (at(top1) - at(top0)).length() > self.pm.host.coarsest_edge * f.max_size()
        });
        let refused = too_coarse.then_some(Vetoed::AboveCoarsestEdge);
        if !self.template_fits(&quads, lab.mirrored, refused, edge, feature, action) {
            return Ok(false);
        }
        // the four elements one by one, each over its own edge in the
        // reading's direction, as a1, a2, a2, a3 commit them
        let mir = lab.mirrored;
        let edge_labels = |m: &Self, first: Fv| reading_labels(&m.pm.front, first, mir);
        let steps: [(usize, QNode, QNode, Action); 3] = [
            (0, QNode::New(m1), QNode::New(t0), SQUARE_A1),
            (1, QNode::New(m2), QNode::New(m1), SQUARE_A2),
            (2, QNode::New(t1), QNode::New(m2), SQUARE_A2),
        ];
        let mut made = 0;
        let mut m1_fv = None;
        for (k, n3, n4, act) in steps {
            let first = b_fv[k];
            if !self.pm.front.alive(first) || !self.pm.front.alive(b_fv[k + 1]) {
                break;
            }
            let l = edge_labels(self, first);
            if l.n2 != b_fv[k + 1] {
                break;
            }
            // beside a step, the first element takes the step's top as a2
            // takes N4, the third links N4 to it (N5) as a3 does
            let step = match k {
                0 => left.map(|top| (top, l.n4)),
                2 => right.map(|top| (top, l.n5)),
                _ => None,
            };
            if step.is_some_and(|(top, at)| top != at) {
                break;
            }
            // the corner before N1 is the node the last element made (or
            // the step's top)
            let n4 = if k == 0 && step.is_none() {
                n4
            } else {
                QNode::Front(l.n4)
            };
            if k == 1 {
                m1_fv = Some(l.n4);
            }
            let (n3, act) = match (k, step) {
                (0, Some(_)) => (n3, SQUARE_A2),
                (2, Some(_)) => (QNode::Front(l.n5), Action::A3),
                _ => (n3, act),
            };
            let el = [QNode::Front(l.n1), QNode::Front(l.n2), n3, n4];
            if !self.commit_part(&el, &l, &act, edge, feature, action, &angles)? {
                break;
            }
            made += 1;
        }
        // the cap over the two middle nodes: m1 m2 t1 t0, as a3 links N4
        // and N5
        if let (3, Some(m1_fv)) = (made, m1_fv) {
            if self.pm.front.alive(m1_fv) {
                let l = edge_labels(self, m1_fv);
                let el = [
                    QNode::Front(l.n1),
                    QNode::Front(l.n2),
                    QNode::Front(l.n5),
                    QNode::Front(l.n4),
                ];
                if self.commit_part(&el, &l, &Action::A3, edge, feature, action, &angles)? {
                    made += 1;
                }
            }
        }
        Ok(made > 0)
    }

    /// The occurrence `fv` if its node is within `near` of `at` (a step's
    /// top where a template would put its own corner).
    fn node_near(&self, fv: Fv, at: DVec2, near: f64) -> Option<Fv> {
        ((self.pm.pos(fv) - at).length() <= near).then_some(fv)
    }

    /// Whether a transition's four elements all pass the validity check
    /// (each judged as any designed element is, in labelled order) and
    /// nothing refused it before (`refused`); else the veto is traced.
    fn template_fits(
        &mut self,
        quads: &[[QNode; 4]; 4],
        mirrored: bool,
        refused: Option<Vetoed>,
        edge: [i64; 2],
        feature: &str,
        action: &Action,
    ) -> bool {
        let why = refused.or_else(|| {
            quads
                .iter()
                .find_map(|q| element_valid(&mut self.pm, q, mirrored).err())
        });
        let Some(why) = why else {
            return true;
        };
        self.pm.note_veto(|before_step| Veto {
            before_step,
            edge,
            feature: feature.to_string(),
            action: action.to_string(),
            reason: why.reason(),
            outcome: "nothing",
        });
        false
    }

    /// Commits one element of a t3 or r3 and traces it; false when the front
    /// refuses it (a loop left odd or degenerate).
    #[allow(clippy::too_many_arguments)]
    fn commit_part(
        &mut self,
        el: &[QNode; 4],
        lab: &Labels,
        as_action: &Action,
        edge: [i64; 2],
        feature: &str,
        action: &Action,
        angles: &Angles,
    ) -> Result<bool, MeshError> {
        let ids = match self.commit_element(el, lab, as_action)? {
            Ok(ids) => ids,
            Err(_) => return Ok(false),
        };
        self.pm.stats.designed += 1;
        self.pm.note_step(|step| TraceStep {
            step,
            edge,
            angles: angles.clone(),
            feature: feature.to_string(),
            action: action.to_string(),
            by: By::Rule,
            redesign: Vec::new(),
            element: ids.iter().map(|&x| x as i64).collect(),
        });
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn on_a_straight_front_the_template_is_two_rows_high() {
        let b = [0.0, 1.0, 2.0, 3.0].map(|x| DVec2::new(x, 0.0));
        let [m1, m2, t0, t1] = template_nodes(b, 1.0, 1.0);
        assert!((m1 - DVec2::new(1.0, 1.0)).length() < 1e-12);
        assert!((m2 - DVec2::new(2.0, 1.0)).length() < 1e-12);
        assert!((t0 - DVec2::new(0.0, 2.0)).length() < 1e-12);
        assert!((t1 - DVec2::new(3.0, 2.0)).length() < 1e-12);
        // mirrored: the other side
        let [m1, ..] = template_nodes(b, -1.0, 1.0);
        assert!((m1 - DVec2::new(1.0, -1.0)).length() < 1e-12);
    }

    #[test]
    fn refinement_is_the_template_upside_down() {
        let [m1, m2, b0, b1, b2, b3] = refine_nodes(DVec2::ZERO, DVec2::new(3.0, 0.0), 1.0, 1.0);
        let want = [
            (1.0, 1.0),
            (2.0, 1.0),
            (0.0, 2.0),
            (1.0, 2.0),
            (2.0, 2.0),
            (3.0, 2.0),
        ];
        for (p, (x, y)) in [m1, m2, b0, b1, b2, b3].into_iter().zip(want) {
            assert!(
                (p - DVec2::new(x, y)).length() < 1e-12,
                "{p} is not ({x}, {y})"
            );
        }
    }
}
