//! Second-order elements: the quads of a finished mesh with a node in the
//! middle of each edge (8 nodes, serendipity) and, for 9-node elements, one
//! in the middle of the element.
//!
//! A mid-edge node of an edge that lies on an input arc or circle is put on
//! the curve, halfway between the edge's ends in the curve's parameter
//! (its angle); every other mid-edge node is the middle of the edge. A
//! centre node is where the element's 8-node map puts the centre:
//! −¼ Σ corners + ½ Σ mid-edge nodes (the corners' mean where the edges
//! are straight). The corner quads are the mesh: checks and quality
//! measure them.

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::DVec2;

use crate::input::domain::{Curve, Domain};
use crate::mesh::Mesh;

/// The kind of element a mesh is written with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ElementKind {
    /// 4-node bilinear quads.
    #[default]
    Quad4,
    /// 8-node serendipity quads: corners, then the middles of edges 0-1,
    /// 1-2, 2-3, 3-0.
    Quad8,
    /// 9-node Lagrange quads: the 8 nodes, then the centre.
    Quad9,
}

impl ElementKind {
    /// The kind for an order (1 or 2) and, for order 2, whether the
    /// element is serendipity (8 nodes) or not (9).
    pub fn from_order(order: u8, serendipity: bool) -> Option<ElementKind> {
        match (order, serendipity) {
            (1, _) => Some(ElementKind::Quad4),
            (2, true) => Some(ElementKind::Quad8),
            (2, false) => Some(ElementKind::Quad9),
            _ => None,
        }
    }

    /// Nodes per element.
    pub fn nodes(self) -> usize {
        match self {
            ElementKind::Quad4 => 4,
            ElementKind::Quad8 => 8,
            ElementKind::Quad9 => 9,
        }
    }
}

/// A mesh's elements with their higher-order nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct SecondOrder {
    /// 8 or 9 nodes an element.
    pub(crate) kind: ElementKind,
    /// The added nodes, numbered after the mesh's own: the mid-edge nodes
    /// in the order the elements first reach them, then the centres.
    pub(crate) nodes: Vec<DVec2>,
    /// Each element's nodes, `kind.nodes()` a row, in the mesh's element
    /// order: its 4 corners, the middles of edges 0-1, 1-2, 2-3, 3-0, the
    /// centre.
    pub(crate) elements: Vec<u32>,
    /// The mid-edge node of each element edge, by its corner nodes (the
    /// smaller id first).
    middles: HashMap<(u32, u32), u32>,
}

impl SecondOrder {
    /// 8 or 9 nodes an element.
    pub fn kind(&self) -> ElementKind {
        self.kind
    }

    /// The added nodes, numbered after the mesh's own.
    pub fn nodes(&self) -> &[DVec2] {
        &self.nodes
    }

    /// The element nodes of quad `q`.
    pub fn element(&self, q: usize) -> &[u32] {
        let n = self.kind.nodes();
        &self.elements[q * n..(q + 1) * n]
    }

    /// The mid-edge node of the edge between corner nodes `a` and `b`, if
    /// that is an element edge.
    pub fn middle(&self, a: u32, b: u32) -> Option<u32> {
        self.middles.get(&(a.min(b), a.max(b))).copied()
    }

    /// Adds the mid-edge (and for `Quad9` centre) nodes to the quads of
    /// `mesh`, whose boundary follows `domain`'s curves.
    ///
    /// # Panics
    /// If `kind` is `Quad4` (nothing to add).
    pub fn build(mesh: &Mesh, domain: &Domain, kind: ElementKind) -> SecondOrder {
        assert_ne!(kind, ElementKind::Quad4, "a linear mesh has no added nodes");
        let curves = CurveIndex::new(domain);
        // the point of each boundary edge's middle on its curve
        let mut on_curve: HashMap<(u32, u32), DVec2> = HashMap::new();
        for e in &mesh.boundary {
            let (a, b) = (mesh.nodes[e.a as usize], mesh.nodes[e.b as usize]);
            if let Some(m) = curves.curved_middle(a, b) {
                on_curve.insert((e.a.min(e.b), e.a.max(e.b)), m);
            }
        }
        let base = mesh.nodes.len() as u32;
        let mut nodes = Vec::new();
        let mut mid_of: HashMap<(u32, u32), u32> = HashMap::with_capacity(2 * mesh.quads.len());
        let mut elements = Vec::with_capacity(kind.nodes() * mesh.quads.len());
        for q in &mesh.quads {
            elements.extend_from_slice(q);
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                let key = (a.min(b), a.max(b));
                let id = *mid_of.entry(key).or_insert_with(|| {
                    let p = on_curve
                        .get(&key)
                        .copied()
                        .unwrap_or_else(|| (mesh.nodes[a as usize] + mesh.nodes[b as usize]) / 2.0);
                    nodes.push(p);
                    base + nodes.len() as u32 - 1
                });
                elements.push(id);
            }
        }
        if kind == ElementKind::Quad9 {
            let mut with_centres = Vec::with_capacity(9 * mesh.quads.len());
            for row in elements.chunks_exact(8) {
                let at = |n: u32| {
                    if n < base {
                        mesh.nodes[n as usize]
                    } else {
                        nodes[(n - base) as usize]
                    }
                };
                let corners: DVec2 = row[..4].iter().map(|&n| at(n)).sum();
                let middles: DVec2 = row[4..].iter().map(|&n| at(n)).sum();
                with_centres.extend_from_slice(row);
                with_centres.push(base + nodes.len() as u32);
                nodes.push(-0.25 * corners + 0.5 * middles);
            }
            elements = with_centres;
        }
        SecondOrder {
            kind,
            nodes,
            elements,
            middles: mid_of,
        }
    }
}

/// An arc or circle of the domain: centre, radius, start angle and signed
/// sweep (2π for a circle).
#[derive(Debug, Clone, Copy)]
struct Round {
    center: DVec2,
    radius: f64,
    start: f64,
    sweep: f64,
    circle: bool,
}

impl Round {
    fn of(c: &Curve) -> Option<Round> {
        match *c {
            Curve::Line { .. } => None,
            Curve::Circle { center, radius } => Some(Round {
                center,
                radius,
                start: 0.0,
                sweep: 2.0 * PI,
                circle: true,
            }),
            Curve::Arc { a, b, bulge } => {
                // the frame of Curve::point_at
                let sweep = 4.0 * bulge.atan();
                let half = (b - a).length() / 2.0;
                let d = (b - a) / (2.0 * half);
                let left = DVec2::new(-d.y, d.x);
                let center = (a + b) / 2.0 + left * half * (1.0 - bulge * bulge) / (2.0 * bulge);
                Some(Round {
                    center,
                    radius: (a - center).length(),
                    start: (a.y - center.y).atan2(a.x - center.x),
                    sweep,
                    circle: false,
                })
            }
        }
    }

    fn tolerance(&self) -> f64 {
        1e-9 * (self.radius + self.center.abs().max_element())
    }

    /// The parameter (angle from the start, along the sweep) of a point
    /// on the curve, or None if the point is off it.
    fn parameter(&self, p: DVec2) -> Option<f64> {
        let v = p - self.center;
        if (v.length() - self.radius).abs() > self.tolerance() {
            return None;
        }
        let rel = ((v.y.atan2(v.x) - self.start) * self.sweep.signum()).rem_euclid(2.0 * PI);
        if self.circle {
            return Some(rel);
        }
        let slack = self.tolerance() / self.radius;
        if rel <= self.sweep.abs() + slack {
            Some(rel)
        } else if rel >= 2.0 * PI - slack {
            Some(0.0)
        } else {
            None
        }
    }

    /// The point halfway between two points of the curve, in its
    /// parameter: on a circle, along the shorter way.
    fn middle(&self, a: DVec2, b: DVec2) -> Option<DVec2> {
        let (ta, tb) = (self.parameter(a)?, self.parameter(b)?);
        let mut t = (ta + tb) / 2.0;
        if self.circle && (ta - tb).abs() > PI {
            t += PI;
        }
        let ang = self.start + self.sweep.signum() * t;
        Some(self.center + self.radius * DVec2::new(ang.cos(), ang.sin()))
    }
}

/// The domain's curves by where they run: a grid of cells, each listing
/// the curves that pass near it.
struct CurveIndex {
    rounds: Vec<Round>,
    lines: Vec<(DVec2, DVec2)>,
    cell: f64,
    /// cell -> (is a round, index)
    grid: HashMap<(i64, i64), Vec<(bool, usize)>>,
}

impl CurveIndex {
    fn new(domain: &Domain) -> CurveIndex {
        let curves: Vec<Curve> = domain
            .chains()
            .flat_map(|c| c.edges.iter().map(|e| e.curve))
            .collect();
        let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
        for c in &curves {
            for p in c.divide(8) {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        let cell = ((hi - lo).max_element() / 256.0).max(1e-300);
        let mut index = CurveIndex {
            rounds: Vec::new(),
            lines: Vec::new(),
            cell,
            grid: HashMap::new(),
        };
        for c in &curves {
            let entry = match Round::of(c) {
                Some(r) => {
                    index.rounds.push(r);
                    (true, index.rounds.len() - 1)
                }
                None => {
                    let (Curve::Line { a, b } | Curve::Arc { a, b, .. }) = *c else {
                        continue;
                    };
                    index.lines.push((a, b));
                    (false, index.lines.len() - 1)
                }
            };
            // samples half a cell apart, each marking its cell and those round it
            let n = (c.length() / (cell / 2.0)).ceil().max(1.0) as usize;
            let mut cells = std::collections::BTreeSet::new();
            for k in 0..=n {
                let p = c.point_at(k as f64 / n as f64);
                let (cx, cy) = index.cell_of(p);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        cells.insert((cx + dx, cy + dy));
                    }
                }
            }
            for key in cells {
                index.grid.entry(key).or_default().push(entry);
            }
        }
        index
    }

    fn cell_of(&self, p: DVec2) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    /// Where the middle of edge a-b goes if the edge lies on an arc or a
    /// circle of the domain (and on no straight edge of it).
    fn curved_middle(&self, a: DVec2, b: DVec2) -> Option<DVec2> {
        let near = self.grid.get(&self.cell_of(a))?;
        let straight = near.iter().any(|&(round, i)| {
            if round {
                return false;
            }
            let (p, q) = self.lines[i];
            let on = |x: DVec2| {
                let d = q - p;
                let t = ((x - p).dot(d) / d.length_squared()).clamp(0.0, 1.0);
                (p + d * t - x).length() <= 1e-9 * (d.length() + p.abs().max_element())
            };
            on(a) && on(b)
        });
        if straight {
            return None;
        }
        near.iter()
            .filter(|e| e.0)
            .find_map(|&(_, i)| self.rounds[i].middle(a, b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BoundaryEdge, NodeKind};

    fn domain(json: &str) -> Domain {
        Domain::from_json(&serde_json::from_str(json).unwrap()).unwrap()
    }

    #[test]
    fn the_middle_of_an_arc_edge_is_halfway_in_angle() {
        // a half disc (the arc from (1, 0) round to (-1, 0)) over a triangle
        let d = domain(
            r#"{"size": 1, "outer": {"points": [[1, 0], [-1, 0], [0, -1]], "bulges": [1, 0, 0]}}"#,
        );
        let mut mesh = Mesh::default();
        let s = 0.5f64.sqrt();
        for p in [[1.0, 0.0], [s, s], [0.0, 0.0]] {
            mesh.add_node(DVec2::from(p), NodeKind::Boundary);
        }
        mesh.quads.push([0, 1, 2, 2]);
        mesh.boundary.push(BoundaryEdge {
            a: 0,
            b: 1,
            group: 0,
            tag: None,
        });
        let so = SecondOrder::build(&mesh, &d, ElementKind::Quad8);
        let m = so.nodes[0];
        let want = DVec2::new((PI / 8.0).cos(), (PI / 8.0).sin());
        assert!((m - want).length() < 1e-12, "{m}");
        // the edge 1-2 is inside: its middle is the chord's
        assert!((so.nodes[1] - DVec2::new(s / 2.0, s / 2.0)).length() < 1e-15);
    }

    #[test]
    fn an_edge_on_a_straight_line_between_two_points_of_a_circle_stays_straight() {
        // a disc with a chord from (1, 0) to (0, 1), built without the
        // checks of the format (a line ending on a loop is format 1.1)
        use crate::input::domain::{Chain, Edge};
        let chain = |curve| Chain {
            edges: vec![Edge {
                curve,
                segments: None,
                tag: None,
            }],
            label: String::new(),
            crack: false,
        };
        let d = Domain {
            name: String::new(),
            size: 1.0,
            max_size: None,
            outer: chain(Curve::Circle {
                center: DVec2::ZERO,
                radius: 1.0,
            }),
            holes: vec![],
            lines: vec![chain(Curve::Line {
                a: DVec2::X,
                b: DVec2::Y,
            })],
            tags: vec![],
        };
        let mut mesh = Mesh::default();
        for p in [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]] {
            mesh.add_node(DVec2::from(p), NodeKind::Boundary);
        }
        mesh.quads.push([0, 1, 2, 2]);
        mesh.boundary.push(BoundaryEdge {
            a: 0,
            b: 1,
            group: 1,
            tag: None,
        });
        let so = SecondOrder::build(&mesh, &d, ElementKind::Quad8);
        assert!(
            (so.nodes[0] - DVec2::new(0.5, 0.5)).length() < 1e-15,
            "{}",
            so.nodes[0]
        );
    }

    #[test]
    fn nine_node_elements_share_mid_edge_nodes_and_have_their_centre() {
        let d = domain(r#"{"size": 1, "outer": {"points": [[0, 0], [2, 0], [2, 1], [0, 1]]}}"#);
        let mut mesh = Mesh::default();
        for p in [
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [0.0, 1.0],
        ] {
            mesh.add_node(DVec2::from(p), NodeKind::Boundary);
        }
        mesh.quads.push([0, 1, 4, 5]);
        mesh.quads.push([1, 2, 3, 4]);
        let so = SecondOrder::build(&mesh, &d, ElementKind::Quad9);
        // 7 edges, 2 centres
        assert_eq!(so.nodes.len(), 9);
        // the shared edge 1-4 is edge 1 of the first quad, edge 3 of the second
        assert_eq!(so.element(0)[5], so.element(1)[7]);
        let centre = so.nodes[(so.element(1)[8] - 6) as usize];
        assert!((centre - DVec2::new(1.5, 0.5)).length() < 1e-15);
    }
}
