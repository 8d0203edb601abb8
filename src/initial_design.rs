//! Initial design: the design actions a1-a4 as the KB states them, and the
//! builtins that place the nodes of the element N1N2N3N4 over an edge.
//!
//! Labelling (see `kb/features.pl`): the front reads N7, N4, N1, N2, N5
//! along the edge N1N2 with the remaining domain on the side the element
//! goes to. Lengths in actions are relative to |N1N2|; angles in degrees.

use glam::DVec2;
use scryer_prolog::Term;
use std::fmt;

use crate::kb::{fmt_float, term_number, term_text};

/// Which of the element's new corners.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    /// N3.
    N3,
    /// N4.
    N4,
}

/// A design action, as the KB answers it.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// a1: add three lines; new N4 at angle phi1 from N1 and distance l4,
    /// new N3 at angle phi2 from N2 and distance l2.
    A1 {
        /// Inner corner at N1 (deg).
        phi1: f64,
        /// Inner corner at N2 (deg).
        phi2: f64,
        /// |N2N3| / |N1N2|.
        l2: f64,
        /// |N1N4| / |N1N2|.
        l4: f64,
    },
    /// a2: add two lines from N2 and N4 at phi2 and phi4; they meet at N3.
    A2 {
        /// Inner corner at N2 (deg).
        phi2: f64,
        /// Inner corner at N4 (deg).
        phi4: f64,
    },
    /// a3: link N3 and N4 (both on the front).
    A3,
    /// a4: N3 at the centre of the block, (N2 + N4 + N6)/3.
    A4,
    /// The action applied on the next edge along (redesign rules Rd10, Rd12).
    Shift(Box<Action>),
    /// The action with a new corner replaced by the nearest front node.
    Merge(Corner, Box<Action>),
}

impl Action {
    /// Reads an action term (`a1(P1, P2, L2, L4)`, `a2(P2, P4)`, `a3`, `a4`,
    /// `shift(1, A)`, `merge(n3, A)`).
    pub fn from_term(t: &Term) -> Option<Action> {
        let nums = |args: &[Term]| -> Option<Vec<f64>> { args.iter().map(term_number).collect() };
        match t {
            Term::Atom(a) if a == "a3" => Some(Action::A3),
            Term::Atom(a) if a == "a4" => Some(Action::A4),
            Term::Compound(f, args) => match (f.as_str(), args.len()) {
                ("a1", 4) => {
                    let v = nums(args)?;
                    Some(Action::A1 {
                        phi1: v[0],
                        phi2: v[1],
                        l2: v[2],
                        l4: v[3],
                    })
                }
                ("a2", 2) => {
                    let v = nums(args)?;
                    Some(Action::A2 {
                        phi2: v[0],
                        phi4: v[1],
                    })
                }
                ("shift", 2) if term_number(&args[0]) == Some(1.0) => {
                    Some(Action::Shift(Box::new(Action::from_term(&args[1])?)))
                }
                ("merge", 2) => {
                    let c = match &args[0] {
                        Term::Atom(a) if a == "n3" => Corner::N3,
                        Term::Atom(a) if a == "n4" => Corner::N4,
                        _ => return None,
                    };
                    Some(Action::Merge(c, Box::new(Action::from_term(&args[1])?)))
                }
                _ => None,
            },
            _ => None,
        }
    }

    /// The paper's name of the action kind: a1, a2, a3, a4.
    pub fn kind(&self) -> &'static str {
        match self {
            Action::A1 { .. } => "a1",
            Action::A2 { .. } => "a2",
            Action::A3 => "a3",
            Action::A4 => "a4",
            Action::Shift(a) | Action::Merge(_, a) => a.kind(),
        }
    }

    /// Checks the parameters are usable (finite, angles in (0, 180)).
    pub fn is_sound(&self) -> bool {
        let ang = |x: f64| x.is_finite() && x > 0.0 && x < 180.0;
        match self {
            Action::A1 { phi1, phi2, l2, l4 } => {
                ang(*phi1)
                    && ang(*phi2)
                    && l2.is_finite()
                    && *l2 > 0.0
                    && l4.is_finite()
                    && *l4 > 0.0
            }
            Action::A2 { phi2, phi4 } => ang(*phi2) && ang(*phi4),
            Action::A3 | Action::A4 => true,
            Action::Shift(a) | Action::Merge(_, a) => a.is_sound(),
        }
    }
}

fn r2(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

impl fmt::Display for Action {
    /// Prolog text of the action (parameters rounded to 0.01 for the trace
    /// and for queries).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Action::A1 { phi1, phi2, l2, l4 } => {
                write!(
                    f,
                    "a1({}, {}, {}, {})",
                    fmt_float(r2(*phi1)),
                    fmt_float(r2(*phi2)),
                    fmt_float(r2(*l2)),
                    fmt_float(r2(*l4))
                )
            }
            Action::A2 { phi2, phi4 } => {
                write!(f, "a2({}, {})", fmt_float(r2(*phi2)), fmt_float(r2(*phi4)))
            }
            Action::A3 => write!(f, "a3"),
            Action::A4 => write!(f, "a4"),
            Action::Shift(a) => write!(f, "shift(1, {a})"),
            Action::Merge(c, a) => write!(
                f,
                "merge({}, {a})",
                if *c == Corner::N3 { "n3" } else { "n4" }
            ),
        }
    }
}

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
        Action::Shift(_) | Action::Merge(_, _) => None,
    }
}

/// The action's term text for the trace.
pub fn describe(t: &Term) -> String {
    term_text(t)
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

    #[test]
    fn action_terms_round_trip_through_text() {
        let a = Action::Merge(
            Corner::N3,
            Box::new(Action::A2 {
                phi2: 90.0,
                phi4: 85.5,
            }),
        );
        assert_eq!(a.to_string(), "merge(n3, a2(90.0, 85.5))");
    }
}
