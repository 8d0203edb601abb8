//! The check every mesh passes before it is written: all quads, each
//! convex with positive area, conforming (no edge in more than two
//! elements, no hanging boundary), covering the domain's area.

use rustc_hash::{FxHashMap, FxHashSet};

use crate::geometry::orient2d;
use crate::mesh::Mesh;

/// What is wrong with a mesh.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshCheckError {
    /// No elements at all.
    #[error("the mesh has no elements")]
    Empty,
    /// An element that is inverted or not convex.
    #[error("element {0} is inverted or not convex")]
    NotConvex(usize),
    /// An edge shared by more than two elements.
    #[error("edge ({0}, {1}) is shared by more than two elements")]
    NonManifold(u32, u32),
    /// The elements do not cover the domain.
    #[error("the elements cover an area of {got:.6}, the domain {want:.6}")]
    Area {
        /// Area of the elements.
        got: f64,
        /// Area of the discretised domain.
        want: f64,
    },
    /// A boundary or inner-line segment that is no element's edge.
    #[error("boundary segment ({0}, {1}) is no element's edge")]
    BoundaryNotFollowed(u32, u32),
}

/// Checks that every boundary segment (loops and inner lines) is an edge
/// of an element. Run it before nodes no element keeps are dropped: they
/// take their segments with them.
pub fn check_boundary_followed(mesh: &Mesh) -> Result<(), MeshCheckError> {
    let edges = element_edges(mesh);
    match mesh
        .boundary
        .iter()
        .find(|e| !edges.contains(&(e.a.min(e.b), e.a.max(e.b))))
    {
        Some(e) => Err(MeshCheckError::BoundaryNotFollowed(e.a, e.b)),
        None => Ok(()),
    }
}

/// Every boundary or inner-line segment that is no element's edge (in
/// the mesh's order).
pub fn lost_segments(mesh: &Mesh) -> Vec<(u32, u32)> {
    let edges = element_edges(mesh);
    mesh.boundary
        .iter()
        .filter(|e| !edges.contains(&(e.a.min(e.b), e.a.max(e.b))))
        .map(|e| (e.a, e.b))
        .collect()
}

fn element_edges(mesh: &Mesh) -> FxHashSet<(u32, u32)> {
    let mut edges = FxHashSet::with_capacity_and_hasher(mesh.quads.len() * 2, Default::default());
    for q in &mesh.quads {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    edges
}

/// Checks a mesh against the area `want` of the discretised domain.
pub fn check_mesh(mesh: &Mesh, want: f64) -> Result<(), MeshCheckError> {
    if mesh.quads.is_empty() {
        return Err(MeshCheckError::Empty);
    }
    let mut count: FxHashMap<(u32, u32), u8> =
        FxHashMap::with_capacity_and_hasher(mesh.quads.len() * 2, Default::default());
    for (i, q) in mesh.quads.iter().enumerate() {
        let p = mesh.quad_points(i);
        if (0..4).any(|k| orient2d(p[k], p[(k + 1) % 4], p[(k + 2) % 4]) <= 0.0) {
            return Err(MeshCheckError::NotConvex(i));
        }
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let c = count.entry((a.min(b), a.max(b))).or_insert(0);
            *c += 1;
            if *c > 2 {
                return Err(MeshCheckError::NonManifold(a, b));
            }
        }
    }
    let got = mesh.area();
    if (got - want).abs() > 1e-6 * want.abs().max(1e-300) {
        return Err(MeshCheckError::Area { got, want });
    }
    Ok(())
}
