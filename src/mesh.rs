//! The mesh being built: nodes, quadrilaterals and the boundary edges with
//! their physical groups.

use glam::DVec2;

/// What a node is, for smoothing: input boundary nodes stay where they are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// On an input loop or inner line: never moved.
    Boundary,
    /// Inside the domain (including the nodes of cutting lines): smoothing
    /// may move it.
    Interior,
}

/// A boundary edge of the input, with the physical group it belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoundaryEdge {
    /// First node.
    pub a: u32,
    /// Second node.
    pub b: u32,
    /// Index into `Mesh::groups`.
    pub group: u32,
}

/// An all-quadrilateral mesh (under construction or finished).
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates.
    pub nodes: Vec<DVec2>,
    /// What each node is.
    pub kinds: Vec<NodeKind>,
    /// Quadrilaterals, counter-clockwise node ids.
    pub quads: Vec<[u32; 4]>,
    /// Edges of the input loops and inner lines.
    pub boundary: Vec<BoundaryEdge>,
    /// Names of the physical groups: `outer`, `hole 1`, `line 1`, ...
    pub groups: Vec<String>,
}

impl Mesh {
    /// Adds a node, returning its id.
    pub fn add_node(&mut self, p: DVec2, kind: NodeKind) -> u32 {
        self.nodes.push(p);
        self.kinds.push(kind);
        (self.nodes.len() - 1) as u32
    }

    /// The corner positions of quad `q`.
    pub fn quad_points(&self, q: usize) -> [DVec2; 4] {
        self.quads[q].map(|n| self.nodes[n as usize])
    }

    /// Total area of the quads.
    pub fn area(&self) -> f64 {
        (0..self.quads.len()).map(|q| crate::geometry::polygon_area(&self.quad_points(q))).sum()
    }
}
