//! The mesh being built: nodes, quadrilaterals and the boundary edges with
//! their physical groups.

use glam::DVec2;

/// What a node is, for smoothing: input boundary nodes stay where they are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// On an input loop or inner line: never moved off it (easing may
    /// slide one inside a straight input edge along that edge).
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
    /// The input loop or line it lies on, as an index into `Mesh::groups`
    /// (the first groups are the chains': `outer`, `hole 1`, ..., `line
    /// 1`, ..., in the order of `Domain::chains`).
    pub group: u32,
    /// The named group the edge is written in instead of its chain's: its
    /// tag's, or a crack face's (an index into `Mesh::groups`).
    pub tag: Option<u32>,
}

impl BoundaryEdge {
    /// The group the edge is written in: its tag's if it has one, else
    /// its loop's or line's.
    pub fn output_group(&self) -> u32 {
        self.tag.unwrap_or(self.group)
    }
}

/// An all-quadrilateral mesh (under construction or finished).
///
/// Its parts are read through accessors and cannot be set from outside
/// the crate, so every mesh a user holds has its node ids in range
/// (`Mesh::default()`, the empty mesh, is valid too):
///
/// ```compile_fail
/// let mut mesh = freemesh::Mesh::default();
/// mesh.quads.push([0, 1, 2, 99]);
/// ```
///
/// ```compile_fail
/// let mesh = freemesh::Mesh { quads: vec![[0, 1, 2, 99]], ..Default::default() };
/// ```
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates.
    pub(crate) nodes: Vec<DVec2>,
    /// What each node is.
    pub(crate) kinds: Vec<NodeKind>,
    /// Quadrilaterals, counter-clockwise node ids.
    pub(crate) quads: Vec<[u32; 4]>,
    /// Edges of the input loops and inner lines.
    pub(crate) boundary: Vec<BoundaryEdge>,
    /// Names of the physical groups of boundary edges: `outer`, `hole 1`,
    /// `line 1`, ..., then the tags and crack faces (`crack 1 +`, ...).
    pub(crate) groups: Vec<String>,
    /// The region of each quad (0-based; `region 1` in the outputs): the
    /// parts of the domain the loops and lines enclose, found by a flood
    /// fill across element edges that are on no line. Empty until the
    /// mesh is finished.
    pub(crate) regions: Vec<u32>,
    /// The groups of the lines that are cracks (`"crack": true`): the
    /// mesh is cut open along them when it is finished.
    pub(crate) crack_lines: Vec<u32>,
    /// With `--blocks`, the block of each quad (0-based; `block 1` in the
    /// outputs); empty otherwise.
    pub(crate) blocks: Vec<u32>,
    /// Where the input's vertices are (their coordinates' bits, sorted):
    /// the boundary nodes that are none of them lie inside an input edge
    /// and may slide along it. None: not known, so none slides.
    pub(crate) input_vertices: Option<Vec<[u64; 2]>>,
}

impl Mesh {
    /// Whether node `n` is (or may be) at a vertex of the input.
    pub(crate) fn is_input_vertex(&self, n: usize) -> bool {
        let p = self.nodes[n];
        self.input_vertices
            .as_ref()
            .is_none_or(|v| v.binary_search(&[p.x.to_bits(), p.y.to_bits()]).is_ok())
    }

    /// The area the boundary segments of the loops enclose (those of the
    /// inner lines left out).
    pub(crate) fn loops_area(&self) -> f64 {
        self.boundary
            .iter()
            .filter(|e| (self.groups.get(e.group as usize)).is_none_or(|g| !g.starts_with("line ")))
            .map(|e| self.nodes[e.a as usize].perp_dot(self.nodes[e.b as usize]) / 2.0)
            .sum()
    }

    /// The area inside the loops' boundary edges (groups below `loops`).
    pub(crate) fn boundary_area(&self, loops: u32) -> f64 {
        self.boundary
            .iter()
            .filter(|e| e.group < loops)
            .map(|e| self.nodes[e.a as usize].perp_dot(self.nodes[e.b as usize]) / 2.0)
            .sum()
    }

    /// Node coordinates.
    pub fn nodes(&self) -> &[DVec2] {
        &self.nodes
    }

    /// What each node is, in the order of `nodes()`.
    pub fn kinds(&self) -> &[NodeKind] {
        &self.kinds
    }

    /// Quadrilaterals, counter-clockwise node ids (each below `nodes().len()`).
    pub fn quads(&self) -> &[[u32; 4]] {
        &self.quads
    }

    /// Edges of the input loops and inner lines.
    pub fn boundary(&self) -> &[BoundaryEdge] {
        &self.boundary
    }

    /// Names of the physical groups of boundary edges (see `BoundaryEdge::group`).
    pub fn groups(&self) -> &[String] {
        &self.groups
    }

    /// The region of each quad (0-based), empty until the mesh is finished.
    pub fn regions(&self) -> &[u32] {
        &self.regions
    }

    /// The groups of the lines that are cracks.
    pub fn crack_lines(&self) -> &[u32] {
        &self.crack_lines
    }

    /// Adds a node, returning its id.
    pub fn add_node(&mut self, p: DVec2, kind: NodeKind) -> u32 {
        self.nodes.push(p);
        self.kinds.push(kind);
        (self.nodes.len() - 1) as u32
    }

    /// The corner positions of quad `q` (`q` below `quads().len()`, as
    /// for indexing a slice).
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

    /// The boundary edges of each group, in the order of `groups`.
    pub fn group_edges(&self) -> Vec<Vec<(u32, u32)>> {
        let mut out = vec![Vec::new(); self.groups.len()];
        for e in &self.boundary {
            out[e.output_group() as usize].push((e.a, e.b));
        }
        out
    }

    /// The index of the group named `name`, added if there is none.
    pub fn group_named(&mut self, name: &str) -> u32 {
        match self.groups.iter().position(|g| g == name) {
            Some(i) => i as u32,
            None => {
                self.groups.push(name.to_string());
                (self.groups.len() - 1) as u32
            }
        }
    }

    /// The number of regions (at least one once the mesh is finished).
    pub fn region_count(&self) -> u32 {
        self.regions.iter().max().map_or(0, |&r| r + 1)
    }

    /// The block of each quad, when the mesh was made in blocks
    /// (`--blocks`), else empty.
    pub fn blocks(&self) -> &[u32] {
        &self.blocks
    }

    /// How many blocks (0 unless the mesh was made in blocks).
    pub fn block_count(&self) -> u32 {
        self.blocks.iter().max().map_or(0, |&b| b + 1)
    }

    /// Total area of the quads.
    pub fn area(&self) -> f64 {
        (0..self.quads.len())
            .map(|q| crate::geometry::polygon_area(&self.quad_points(q)))
            .sum()
    }
}

/// Three by three unit squares (nodes 0..16 by rows, the four inner ones
/// free), each element counter-clockwise from its lower left node.
#[cfg(test)]
pub(crate) fn three_by_three() -> Mesh {
    let mut m = Mesh::default();
    for y in 0..4 {
        for x in 0..4 {
            let inner = (1..3).contains(&x) && (1..3).contains(&y);
            let kind = if inner {
                NodeKind::Interior
            } else {
                NodeKind::Boundary
            };
            m.add_node(DVec2::new(x as f64, y as f64), kind);
        }
    }
    let id = |x: u32, y: u32| y * 4 + x;
    for y in 0..3 {
        for x in 0..3 {
            m.quads
                .push([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    m
}
