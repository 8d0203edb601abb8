//! The host's words in the protocol with the KB: what it hands in (a
//! context, the relations it measured, the front as facts) and what it
//! gets back (a design action, a redesign, final patterns). Their Prolog text is
//! in `terms.rs`.

use glam::DVec2;

/// Which of the element's new corners.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    /// N3.
    N3,
    /// N4.
    N4,
}

/// A design action, as the KB answers it (its Prolog text is read and
/// written in kb/terms.rs).
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
    /// t3: three flat front edges N4N1, N1N2, N2N5 become one over two
    /// rows (four elements; paving's row adjustment for a coarser
    /// interior): new nodes above N1 and N2 at `height` times the edges'
    /// mean length, above N4 and N5 at twice that.
    T3 {
        /// The first row's height over the edges' mean length.
        height: f64,
    },
    /// r3: the mirror of t3, one front edge N1N2 far coarser than the
    /// place asks for becomes three over two rows (four elements): new
    /// nodes at its thirds, `height` times a third of it inside, three
    /// above them and N1 and N2 at twice that.
    R3 {
        /// The first row's height over a third of the edge.
        height: f64,
    },
    /// The action applied on the next edge along (redesign rules Rd10, Rd12).
    Shift(Box<Action>),
    /// The action with a new corner replaced by the nearest front node.
    Merge(Corner, Box<Action>),
}

impl Action {
    /// The paper's name of the action kind: a1, a2, a3, a4.
    pub fn kind(&self) -> &'static str {
        match self {
            Action::A1 { .. } => "a1",
            Action::A2 { .. } => "a2",
            Action::A3 => "a3",
            Action::A4 => "a4",
            Action::T3 { .. } => "t3",
            Action::R3 { .. } => "r3",
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
            Action::T3 { height } | Action::R3 { height } => height.is_finite() && *height > 0.0,
            Action::Shift(a) | Action::Merge(_, a) => a.is_sound(),
        }
    }
}

/// The context of an oriented front edge as the KB sees it (Fig. 4's
/// labelling, kb/features.pl): the angles theta7, theta4, theta1, theta2,
/// theta5 at N7, N4, N1, N2, N5 in whole degrees, and the neighbouring
/// edges l5 = |N4N1| and l6 = |N2N5| over |N1N2| in hundredths, and the
/// grading ratio r: the size field's target at the edge over |N1N2|, in
/// tenths (1 where the run is not graded).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Context(pub [f64; 8]);

/// What the design rules make of a context: the first feature of the
/// strategy the edge shows, and its action.
#[derive(Debug, Clone, PartialEq)]
pub struct Designed {
    /// The feature (b1..b5, or one a user's file adds).
    pub feature: String,
    /// Its action, checked sound.
    pub action: Action,
}

/// A redesign rule that fired, and the action it gives instead.
#[derive(Debug, Clone, PartialEq)]
pub struct Redesigned {
    /// The rule's name (rd1..rd13, or a user's).
    pub rule: String,
    /// The corrected action, checked sound.
    pub action: Action,
}

/// A corner of the element N1N2N3N4 in the redesign relations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementNode {
    /// N1.
    N1,
    /// N2.
    N2,
    /// N3.
    N3,
    /// N4.
    N4,
}

/// An edge of the element with a new end, in the redesign relations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementEdge {
    /// N2N3.
    E23,
    /// N3N4.
    E34,
    /// N4N1.
    E41,
}

/// A relation between a candidate element and the remaining domain, the
/// facts the redesign constraints judge (kb/redesign.pl). Lengths are
/// relative to the element's mean edge; angles in whole degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Relation {
    /// The remaining domain keeps a corner under 90 degrees beside the
    /// element at a front node.
    OuterCorner {
        /// Where.
        node: ElementNode,
        /// The corner left (deg).
        deg: f64,
    },
    /// a3: the corner the remaining domain keeps at N3 or N4.
    RemainingCorner {
        /// Where.
        node: ElementNode,
        /// The corner left (deg).
        deg: f64,
    },
    /// a3: an inner corner of the element outside [90, 120].
    InnerCorner {
        /// Where.
        node: ElementNode,
        /// The element's corner (deg).
        deg: f64,
    },
    /// A new corner near a front node (fronts that meet).
    CornerNode {
        /// The new corner, N3 or N4.
        corner: ElementNode,
        /// Its distance to the nearest front node.
        distance: f64,
    },
    /// A new corner near a front segment (Fig. 10's distances).
    CornerSegment {
        /// The new corner, N3 or N4.
        corner: ElementNode,
        /// Vertical distance.
        vertical: f64,
        /// Horizontal distance.
        horizontal: f64,
    },
    /// A new element edge near a concave front node.
    EdgePoint {
        /// The edge.
        edge: ElementEdge,
        /// Vertical distance.
        vertical: f64,
        /// Horizontal distance.
        horizontal: f64,
        /// The front's angle at the node (deg).
        angle: f64,
    },
}

/// The final patterns of a six-segment loop (kb/patterns.pl).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatternKind {
    /// Pattern 1: three elements round a node at Eq. 5's centre.
    One,
    /// Pattern 2: three elements round a node at Eq. 6's point.
    Two,
    /// Pattern 3: two elements split along a diagonal.
    Three,
}

/// A final pattern the KB gives a six-segment loop.
#[derive(Debug, Clone, PartialEq)]
pub struct Pattern {
    /// Which pattern.
    pub kind: PatternKind,
    /// The loop node it starts at (the paper's N1), 0..6.
    pub start: usize,
    /// Its term, for the trace.
    pub text: String,
}

/// The live front stated to the KB as facts (kb/front.pl).
#[derive(Debug, Clone, Default)]
pub struct FrontFacts {
    /// Each front node once, with its position.
    pub nodes: Vec<(u32, DVec2)>,
    /// Each front edge, the remaining domain on its left.
    pub edges: Vec<(u32, u32)>,
    /// The interior angle at each occurrence (whole degrees).
    pub angles: Vec<(u32, f64)>,
    /// Both readings of every edge: the edge as the front has it, the
    /// node the reading starts from (N1) and the context.
    pub contexts: Vec<(u32, u32, u32, Context)>,
}
