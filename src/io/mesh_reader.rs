//! Reading a quadrilateral mesh written by freemesh or another program, so
//! that `freemesh quality` can measure it: Gmsh's MSH (ASCII, versions 4.1
//! and 2.2; binary 4.1) and freemesh's JSON. 8- and 9-node quads are read
//! as their corners; cells other than quads (points, lines, triangles) are
//! counted, not kept.

use glam::DVec2;
use std::collections::HashMap;

use crate::mesh::{Mesh, NodeKind};

/// A mesh read from a file.
#[derive(Debug)]
pub struct ReadMesh {
    /// The nodes and the quads (counter-clockwise).
    pub mesh: Mesh,
    /// Triangles and other 2D cells that are not quads.
    pub other_faces: usize,
}

/// Why a mesh file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The system's reason.
        message: String,
    },
    /// The text is not a mesh this reader knows.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: String,
        /// What is wrong, and where.
        message: String,
    },
}

/// Reads a mesh file, by its extension: `.msh` or `.json`.
pub fn read_mesh(path: &str) -> Result<ReadMesh, ReadError> {
    let bytes = std::fs::read(path).map_err(|e| ReadError::Io {
        path: path.into(),
        message: e.to_string(),
    })?;
    let bad = |message: String| ReadError::Format {
        path: path.into(),
        message,
    };
    let mut read = if super::msh_binary::is_binary_msh(&bytes) {
        from_binary_msh(&bytes).map_err(bad)?
    } else {
        let text = String::from_utf8(bytes).map_err(|_| {
            bad("not a text file, nor a binary MSH 4.1 file: give ASCII MSH 4.1 or 2.2, binary MSH 4.1 or freemesh's JSON".into())
        })?;
        read_text(path, &text).map_err(bad)?
    };
    if read.mesh.quads.is_empty() {
        return Err(ReadError::Format {
            path: path.into(),
            message: "no quadrilaterals in the file".into(),
        });
    }
    orient_counter_clockwise(&mut read.mesh);
    Ok(read)
}

/// A text mesh file, by its extension.
fn read_text(path: &str, text: &str) -> Result<ReadMesh, String> {
    if path.ends_with(".json") {
        from_json(text)
    } else if path.ends_with(".msh") {
        from_msh(text)
    } else {
        Err("unknown mesh format: give a .msh or .json file".into())
    }
}

/// Gmsh's binary MSH 4.1: the quads kept, other faces counted.
fn from_binary_msh(bytes: &[u8]) -> Result<ReadMesh, String> {
    let cells = super::msh_binary::read(bytes)?;
    let index = super::msh_binary::node_index(&cells);
    let mut mesh = Mesh::default();
    for &(_, x, y) in &cells.nodes {
        mesh.add_node(DVec2::new(x, y), NodeKind::Interior);
    }
    let mut other_faces = 0;
    for (kind, tags) in &cells.cells {
        match kind {
            3 => {
                let ids: Option<Vec<u32>> = tags.iter().map(|t| index.get(t).copied()).collect();
                let ids = ids.ok_or("a quad names a node the file does not have")?;
                mesh.quads.push([ids[0], ids[1], ids[2], ids[3]]);
            }
            2 | 9 | 10 | 16 => other_faces += 1,
            _ => {}
        }
    }
    Ok(ReadMesh { mesh, other_faces })
}

/// Turns every quad counter-clockwise when most are clockwise (a mesh
/// written with its normal along -z).
fn orient_counter_clockwise(mesh: &mut Mesh) {
    let clockwise = (0..mesh.quads.len())
        .filter(|&q| crate::geometry::polygon_area(&mesh.quad_points(q)) < 0.0)
        .count();
    if 2 * clockwise > mesh.quads.len() {
        for q in &mut mesh.quads {
            q.reverse();
        }
    }
}

/// freemesh's JSON: `{"nodes": [[x, y], ...], "quads": [[a, b, c, d], ...]}`.
fn from_json(text: &str) -> Result<ReadMesh, String> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let mut mesh = Mesh::default();
    let nodes = v["nodes"].as_array().ok_or("no \"nodes\" list")?;
    for (i, p) in nodes.iter().enumerate() {
        let xy = |k: usize| p.get(k).and_then(|c| c.as_f64());
        let (Some(x), Some(y)) = (xy(0), xy(1)) else {
            return Err(format!("node {i} is not [x, y]"));
        };
        mesh.add_node(DVec2::new(x, y), NodeKind::Interior);
    }
    for (i, q) in v["quads"]
        .as_array()
        .ok_or("no \"quads\" list")?
        .iter()
        .enumerate()
    {
        let ids: Vec<u32> = q
            .as_array()
            .map(|a| {
                a.iter()
                    .filter_map(|x| x.as_u64().and_then(|x| u32::try_from(x).ok()))
                    .collect()
            })
            .unwrap_or_default();
        if ids.len() != 4 || ids.iter().any(|&n| n as usize >= mesh.nodes.len()) {
            return Err(format!("quad {i} is not four node ids"));
        }
        mesh.quads.push([ids[0], ids[1], ids[2], ids[3]]);
    }
    Ok(ReadMesh {
        mesh,
        other_faces: 0,
    })
}

/// The text of a `$Name ... $EndName` section.
fn section<'t>(text: &'t str, name: &str) -> Result<&'t str, String> {
    let start = text
        .find(&format!("${name}"))
        .ok_or(format!("no ${name} section"))?
        + name.len()
        + 1;
    let end = text[start..]
        .find(&format!("$End{name}"))
        .ok_or(format!("${name} is not closed"))?;
    Ok(&text[start..start + end])
}

/// Numbers of a section, read in order.
struct Numbers<'t> {
    words: std::str::SplitAsciiWhitespace<'t>,
    section: &'static str,
}

impl Numbers<'_> {
    fn next<T: std::str::FromStr>(&mut self) -> Result<T, String> {
        let w = self
            .words
            .next()
            .ok_or(format!("${} ends too early", self.section))?;
        w.parse()
            .map_err(|_| format!("${}: {w:?} is not a number", self.section))
    }
}

/// Gmsh's MSH, ASCII, version 4.1 or 2.2.
fn from_msh(text: &str) -> Result<ReadMesh, String> {
    let version: f64 = section(text, "MeshFormat")?
        .split_ascii_whitespace()
        .next()
        .and_then(|v| v.parse().ok())
        .ok_or("no version in $MeshFormat")?;
    let format = section(text, "MeshFormat")?;
    if format.split_ascii_whitespace().nth(1) != Some("0") {
        return Err("binary MSH is not read: write it as ASCII".into());
    }
    let nums = |name: &'static str| -> Result<Numbers, String> {
        Ok(Numbers {
            words: section(text, name)?.split_ascii_whitespace(),
            section: name,
        })
    };
    let mut mesh = Mesh::default();
    let mut id_of: HashMap<u64, u32> = HashMap::new();
    let mut other_faces = 0;
    // element types: 3 is the 4-node quad, 16 and 10 the 8- and 9-node
    // ones (measured by their corners, the first four); 2 and 9 are other
    // faces
    let mut add_cell =
        |mesh: &mut Mesh, kind: u32, tags: &[u64], id_of: &HashMap<u64, u32>| match kind {
            3 | 10 | 16 => {
                let ids: Option<Vec<u32>> =
                    tags[..4].iter().map(|t| id_of.get(t).copied()).collect();
                let ids = ids.ok_or("a quad names a node the file does not have")?;
                mesh.quads.push([ids[0], ids[1], ids[2], ids[3]]);
                Ok::<(), String>(())
            }
            2 | 9 => {
                other_faces += 1;
                Ok(())
            }
            _ => Ok(()),
        };
    let nodes_per = |kind: u32| -> Result<usize, String> {
        Ok(match kind {
            15 => 1,
            1 => 2,
            2 => 3,
            3 => 4,
            8 => 3,
            9 => 6,
            10 => 9,
            16 => 8,
            _ => return Err(format!("element type {kind} is not read")),
        })
    };
    if (4.0..5.0).contains(&version) {
        let mut n = nums("Nodes")?;
        let (blocks, _, _, _): (usize, usize, u64, u64) =
            (n.next()?, n.next()?, n.next()?, n.next()?);
        for _ in 0..blocks {
            let (_dim, _tag, parametric, count): (u32, i64, u32, usize) =
                (n.next()?, n.next()?, n.next()?, n.next()?);
            if parametric != 0 {
                return Err("parametric nodes are not read".into());
            }
            let tags: Vec<u64> = (0..count).map(|_| n.next()).collect::<Result<_, _>>()?;
            for t in tags {
                let (x, y, _z): (f64, f64, f64) = (n.next()?, n.next()?, n.next()?);
                id_of.insert(t, mesh.add_node(DVec2::new(x, y), NodeKind::Interior));
            }
        }
        let mut e = nums("Elements")?;
        let (blocks, _, _, _): (usize, usize, u64, u64) =
            (e.next()?, e.next()?, e.next()?, e.next()?);
        for _ in 0..blocks {
            let (_dim, _tag, kind, count): (u32, i64, u32, usize) =
                (e.next()?, e.next()?, e.next()?, e.next()?);
            let per = nodes_per(kind)?;
            for _ in 0..count {
                let _id: u64 = e.next()?;
                let tags: Vec<u64> = (0..per).map(|_| e.next()).collect::<Result<_, _>>()?;
                add_cell(&mut mesh, kind, &tags, &id_of)?;
            }
        }
    } else if (2.0..3.0).contains(&version) {
        let mut n = nums("Nodes")?;
        let count: usize = n.next()?;
        for _ in 0..count {
            let (t, x, y, _z): (u64, f64, f64, f64) = (n.next()?, n.next()?, n.next()?, n.next()?);
            id_of.insert(t, mesh.add_node(DVec2::new(x, y), NodeKind::Interior));
        }
        let mut e = nums("Elements")?;
        let count: usize = e.next()?;
        for _ in 0..count {
            let (_id, kind, ntags): (u64, u32, usize) = (e.next()?, e.next()?, e.next()?);
            for _ in 0..ntags {
                let _: i64 = e.next()?;
            }
            let tags: Vec<u64> = (0..nodes_per(kind)?)
                .map(|_| e.next())
                .collect::<Result<_, _>>()?;
            add_cell(&mut mesh, kind, &tags, &id_of)?;
        }
    } else {
        return Err(format!(
            "MSH version {version} is not read (4.1 and 2.2 are)"
        ));
    }
    Ok(ReadMesh { mesh, other_faces })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE_41: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n$Elements\n1 1 1 1\n2 1 3 1\n1 1 2 3 4\n$EndElements\n";

    #[test]
    fn a_quad_in_msh_41_and_22_reads_the_same() {
        let a = from_msh(SQUARE_41).unwrap();
        let b = from_msh("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n2\n1 2 2 0 1 1 2 3\n2 3 2 0 1 1 2 3 4\n$EndElements\n").unwrap();
        assert_eq!(a.mesh.quads, vec![[0, 1, 2, 3]]);
        assert_eq!(a.mesh.quads, b.mesh.quads);
        assert_eq!(a.mesh.nodes, b.mesh.nodes);
        assert_eq!(b.other_faces, 1);
    }

    #[test]
    fn an_eight_node_quad_reads_as_its_corners() {
        let quad8 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 8 1 8\n2 1 0 8\n1\n2\n3\n4\n5\n6\n7\n8\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 0\n1 0.5 0\n0.5 1 0\n0 0.5 0\n$EndNodes\n$Elements\n1 1 1 1\n2 1 16 1\n1 1 2 3 4 5 6 7 8\n$EndElements\n";
        let a = from_msh(quad8).unwrap();
        assert_eq!(a.mesh.quads, vec![[0, 1, 2, 3]]);
        assert_eq!(a.other_faces, 0);
    }

    #[test]
    fn a_truncated_file_is_an_error_naming_the_section() {
        let cut = &SQUARE_41[..SQUARE_41.find("1 1 2 3 4").unwrap()];
        let e = from_msh(cut).unwrap_err();
        assert!(e.contains("$Elements"), "{e}");
    }
}
