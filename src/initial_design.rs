//! Initial design: the design actions a1-a4 as the KB states them, and the
//! builtins that place the nodes of the element N1N2N3N4 over an edge.
//!
//! Labelling (see `kb/features.pl`): the front reads N7, N4, N1, N2, N5
//! along the edge N1N2 with the remaining domain on the side the element
//! goes to. Lengths in actions are relative to |N1N2|; angles in degrees.

use glam::DVec2;

use crate::features::Labels;
use crate::front::{Front, Fv};
use crate::kb::Action;

/// Positions of the labelled front nodes around an edge.
#[derive(Debug, Clone, Copy)]
pub struct Neighbourhood {
    /// N7, N4, N1, N2, N5.
    pub p7: DVec2,
    /// N4 (front node before N1).
    pub p4: DVec2,
    /// N1.
    pub p1: DVec2,
    /// N2.
    pub p2: DVec2,
    /// N5 (front node after N2).
    pub p5: DVec2,
    /// +1 when the domain is left of N1→N2, -1 when right (mirrored reading).
    pub side: f64,
}

fn rotate(v: DVec2, deg: f64) -> DVec2 {
    let (s, c) = deg.to_radians().sin_cos();
    DVec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Where the two rays `a + s u` and `b + t v` (s, t > 0) meet.
fn ray_meet(a: DVec2, u: DVec2, b: DVec2, v: DVec2) -> Option<DVec2> {
    let den = u.perp_dot(v);
    if den.abs() < 1e-12 * u.length() * v.length() {
        return None;
    }
    let s = (b - a).perp_dot(v) / den;
    let t = (b - a).perp_dot(u) / den;
    (s > 0.0 && t > 0.0).then(|| a + u * s)
}

/// The new node positions of an action: (N3, N4) where each is `None` when
/// that corner is an existing front node (N4 in a2/a4, both in a3).
/// `None` overall when the action cannot be placed (rays that never meet).
pub fn place(action: &Action, nb: &Neighbourhood) -> Option<(Option<DVec2>, Option<DVec2>)> {
    let l1 = (nb.p2 - nb.p1).length();
    let u = (nb.p2 - nb.p1) / l1;
    match action {
        Action::A1 { phi1, phi2, l2, l4 } => {
            let n4 = nb.p1 + rotate(u, nb.side * phi1) * (l4 * l1);
            let n3 = nb.p2 + rotate(-u, -nb.side * phi2) * (l2 * l1);
            Some((Some(n3), Some(n4)))
        }
        Action::A2 { phi2, phi4 } => {
            let from2 = rotate(-u, -nb.side * phi2);
            let w = (nb.p1 - nb.p4).normalize_or_zero();
            let from4 = rotate(w, nb.side * phi4);
            ray_meet(nb.p2, from2, nb.p4, from4).map(|n3| (Some(n3), None))
        }
        Action::A3 => Some((None, None)),
        Action::A4 => {
            let p6 = nb.p5 + nb.p7 - nb.p1;
            Some((Some((nb.p2 + nb.p4 + p6) / 3.0), None))
        }
        // t3 and r3 place four elements (recursion/mesher/coarsen.rs)
        Action::T3 { .. } | Action::R3 { .. } | Action::Shift(_) | Action::Merge(_, _) => None,
    }
}

/// A corner of a candidate element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum QNode {
    /// An occurrence on the front.
    Front(Fv),
    /// A new node.
    New(DVec2),
    /// A new corner replaced by this front occurrence.
    Merged(Fv),
}

impl Neighbourhood {
    /// The positions round a labelled edge.
    pub fn of(front: &Front, nodes: &[DVec2], lab: &Labels) -> Neighbourhood {
        let pos = |fv: Fv| nodes[front.node(fv) as usize];
        Neighbourhood {
            p7: pos(lab.n7),
            p4: pos(lab.n4),
            p1: pos(lab.n1),
            p2: pos(lab.n2),
            p5: pos(lab.n5),
            side: if lab.mirrored { -1.0 } else { 1.0 },
        }
    }
}

/// The element of an action over the labelled edge: its corners
/// N1 N2 N3 N4 (labelled order), or None if it cannot be placed.
pub fn element(
    front: &Front,
    nodes: &[DVec2],
    action: &Action,
    lab: &Labels,
) -> Option<[QNode; 4]> {
    let nb = Neighbourhood::of(front, nodes, lab);
    let (p3, p4) = place(action, &nb)?;
    let n3 = match (action, p3) {
        (Action::A3, _) => QNode::Front(lab.n5),
        (_, Some(p)) => QNode::New(p),
        _ => return None,
    };
    let n4 = match p4 {
        Some(p) => QNode::New(p),
        None => QNode::Front(lab.n4),
    };
    Some([QNode::Front(lab.n1), QNode::Front(lab.n2), n3, n4])
}

/// Where a corner of a candidate element is.
pub fn qpos(front: &Front, nodes: &[DVec2], q: QNode) -> DVec2 {
    match q {
        QNode::Front(fv) | QNode::Merged(fv) => nodes[front.node(fv) as usize],
        QNode::New(p) => p,
    }
}

/// The node id of a corner of a candidate element (None: a new node).
pub fn qnode_id(front: &Front, q: QNode) -> Option<u32> {
    match q {
        QNode::Front(fv) | QNode::Merged(fv) => Some(front.node(fv)),
        QNode::New(_) => None,
    }
}

/// Replaces the new corners N3 (slot 0) and N4 (slot 1) by the front
/// occurrences they merge with.
pub fn apply_merges(mut el: [QNode; 4], merges: &[Option<Fv>; 2]) -> [QNode; 4] {
    for (slot, qi) in [(0usize, 2usize), (1, 3)] {
        if let (Some(t), QNode::New(_)) = (merges[slot], el[qi]) {
            el[qi] = QNode::Merged(t);
        }
    }
    el
}

/// Whether a corner of the element was merged with a front node.
pub fn is_merged(el: &[QNode; 4]) -> bool {
    el.iter().any(|q| matches!(q, QNode::Merged(_)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat() -> Neighbourhood {
        Neighbourhood {
            p7: DVec2::new(-2.0, 0.0),
            p4: DVec2::new(-1.0, 0.0),
            p1: DVec2::ZERO,
            p2: DVec2::X,
            p5: DVec2::new(2.0, 0.0),
            side: 1.0,
        }
    }

    #[test]
    fn a1_on_a_flat_edge_stands_a_unit_square_on_it() {
        let (n3, n4) = place(
            &Action::A1 {
                phi1: 90.0,
                phi2: 90.0,
                l2: 1.0,
                l4: 1.0,
            },
            &flat(),
        )
        .unwrap();
        assert!((n3.unwrap() - DVec2::new(1.0, 1.0)).length() < 1e-12);
        assert!((n4.unwrap() - DVec2::new(0.0, 1.0)).length() < 1e-12);
    }

    #[test]
    fn a2_with_supplementary_angles_completes_a_parallelogram() {
        // N1 is a right-angled corner: N4 above it.
        let nb = Neighbourhood {
            p4: DVec2::Y,
            ..flat()
        };
        let (n3, n4) = place(
            &Action::A2 {
                phi2: 90.0,
                phi4: 90.0,
            },
            &nb,
        )
        .unwrap();
        assert!((n3.unwrap() - DVec2::new(1.0, 1.0)).length() < 1e-12);
        assert!(n4.is_none());
    }

    #[test]
    fn mirrored_reading_places_on_the_other_side() {
        let nb = Neighbourhood {
            side: -1.0,
            ..flat()
        };
        let (n3, _) = place(
            &Action::A1 {
                phi1: 90.0,
                phi2: 90.0,
                l2: 1.0,
                l4: 1.0,
            },
            &nb,
        )
        .unwrap();
        assert!((n3.unwrap() - DVec2::new(1.0, -1.0)).length() < 1e-12);
    }

    #[test]
    fn a4_puts_n3_at_the_centre_of_a_two_by_two_block() {
        let nb = Neighbourhood {
            p7: DVec2::new(0.0, 2.0),
            p4: DVec2::Y,
            p1: DVec2::ZERO,
            p2: DVec2::X,
            p5: DVec2::new(2.0, 0.0),
            side: 1.0,
        };
        let (n3, _) = place(&Action::A4, &nb).unwrap();
        assert!((n3.unwrap() - DVec2::new(1.0, 1.0)).length() < 1e-12);
    }
}
