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

    /// Drops nodes no element uses (left when a stuck region was taken
    /// back) and renumbers the rest; returns the new id of each old node.
    pub fn compact(&mut self) -> Vec<Option<u32>> {
        let mut used = vec![false; self.nodes.len()];
        for q in &self.quads {
            for &n in q {
                used[n as usize] = true;
            }
        }
        let mut map = vec![None; self.nodes.len()];
        let mut next = 0u32;
        for (i, u) in used.iter().enumerate() {
            if *u {
                map[i] = Some(next);
                self.nodes[next as usize] = self.nodes[i];
                self.kinds[next as usize] = self.kinds[i];
                next += 1;
            }
        }
        self.nodes.truncate(next as usize);
        self.kinds.truncate(next as usize);
        for q in &mut self.quads {
            for n in q.iter_mut() {
                *n = map[*n as usize].expect("a node of an element is used");
            }
        }
        self.boundary
            .retain(|e| map[e.a as usize].is_some() && map[e.b as usize].is_some());
        for e in &mut self.boundary {
            e.a = map[e.a as usize].expect("kept");
            e.b = map[e.b as usize].expect("kept");
        }
        map
    }

    /// Total area of the quads.
    pub fn area(&self) -> f64 {
        (0..self.quads.len())
            .map(|q| crate::geometry::polygon_area(&self.quad_points(q)))
            .sum()
    }
}
