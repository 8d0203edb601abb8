//! Gmsh's binary MSH 4.1 (`$MeshFormat` `4.1 1 8`), read for
//! `freemesh quality`: the `$Nodes` and `$Elements` sections in their
//! binary layout (Gmsh reference manual, "MSH file format version 4.1":
//! `size_t` of 8 bytes, `int` of 4, `double` of 8, in the byte order the
//! header's integer 1 gives). Other sections are skipped.

use std::collections::HashMap;

/// A mesh's nodes (tag, x, y) and cells (type, node tags), as read.
#[derive(Debug, Default, PartialEq)]
pub struct MshCells {
    /// Each node's tag and coordinates.
    pub nodes: Vec<(u64, f64, f64)>,
    /// Each element's Gmsh type (3: the 4-node quad) and node tags.
    pub cells: Vec<(u32, Vec<u64>)>,
}

/// True when the text starts as a binary MSH file (format flag 1).
pub fn is_binary_msh(bytes: &[u8]) -> bool {
    header(bytes).is_some_and(|(_, binary, _)| binary)
}

/// The version, the binary flag and where the header line ends.
fn header(bytes: &[u8]) -> Option<(String, bool, usize)> {
    let start = find(bytes, b"$MeshFormat", 0)? + b"$MeshFormat".len();
    let line_start = start
        + bytes[start..]
            .iter()
            .take_while(|b| b.is_ascii_whitespace())
            .count();
    let line_end = line_start + bytes[line_start..].iter().position(|&b| b == b'\n')?;
    let line = std::str::from_utf8(&bytes[line_start..line_end]).ok()?;
    let mut words = line.split_ascii_whitespace();
    let version = words.next()?.to_string();
    let binary = words.next()? == "1";
    Some((version, binary, line_end + 1))
}

fn find(bytes: &[u8], what: &[u8], from: usize) -> Option<usize> {
    bytes
        .get(from..)?
        .windows(what.len())
        .position(|w| w == what)
        .map(|i| i + from)
}

/// Reads numbers of the binary layout in order.
struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
    little_endian: bool,
    section: &'static str,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let chunk = self
            .bytes
            .get(self.at..self.at + N)
            .ok_or(format!("${} ends too early", self.section))?;
        self.at += N;
        let mut out = [0; N];
        out.copy_from_slice(chunk);
        Ok(out)
    }
    fn int(&mut self) -> Result<i32, String> {
        let b = self.take::<4>()?;
        Ok(if self.little_endian {
            i32::from_le_bytes(b)
        } else {
            i32::from_be_bytes(b)
        })
    }
    fn size(&mut self) -> Result<u64, String> {
        let b = self.take::<8>()?;
        Ok(if self.little_endian {
            u64::from_le_bytes(b)
        } else {
            u64::from_be_bytes(b)
        })
    }
    fn double(&mut self) -> Result<f64, String> {
        let b = self.take::<8>()?;
        Ok(if self.little_endian {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }
    /// A count, checked against the bytes left (`each` bytes an item at
    /// least), so that a corrupt count is an error, not a huge allocation.
    fn count(&mut self, each: usize) -> Result<usize, String> {
        let n = self.size()?;
        let left = (self.bytes.len() - self.at) as u64;
        if n.saturating_mul(each as u64) > left {
            return Err(format!(
                "${}: a count of {n} runs past the file's end",
                self.section
            ));
        }
        Ok(n as usize)
    }
}

/// Nodes of each element type this reader knows (Gmsh's numbering).
fn nodes_per_element(kind: i32) -> Result<usize, String> {
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
}

/// Reads a binary MSH 4.1 file.
pub fn read(bytes: &[u8]) -> Result<MshCells, String> {
    let (version, binary, mut at) = header(bytes).ok_or("no $MeshFormat header")?;
    if !binary {
        return Err("not a binary MSH file".into());
    }
    if version != "4.1" {
        return Err(format!(
            "binary MSH {version} is not read (binary 4.1 and ASCII 4.1 and 2.2 are)"
        ));
    }
    let one = bytes.get(at..at + 4).ok_or("$MeshFormat ends too early")?;
    let little_endian = match one {
        [1, 0, 0, 0] => true,
        [0, 0, 0, 1] => false,
        _ => return Err("$MeshFormat: no integer 1 after the header".into()),
    };
    at = find(bytes, b"$EndMeshFormat", at + 4).ok_or("$MeshFormat is not closed")?
        + b"$EndMeshFormat".len();
    let mut out = MshCells::default();
    let (mut nodes_seen, mut elements_seen) = (false, false);
    while let Some(start) = find(bytes, b"$", at) {
        let name_end = start
            + bytes[start..]
                .iter()
                .position(|b| b.is_ascii_whitespace())
                .ok_or("a section name runs to the file's end")?;
        let name = String::from_utf8_lossy(&bytes[start + 1..name_end]).into_owned();
        let body = name_end + 1;
        let reader = |section: &'static str| Reader {
            bytes,
            at: body,
            little_endian,
            section,
        };
        let end_at = match name.as_str() {
            "Nodes" => {
                let mut r = reader("Nodes");
                read_nodes(&mut r, &mut out)?;
                nodes_seen = true;
                r.at
            }
            "Elements" => {
                let mut r = reader("Elements");
                read_elements(&mut r, &mut out)?;
                elements_seen = true;
                r.at
            }
            _ => body,
        };
        let end_tag = format!("$End{name}");
        let end =
            find(bytes, end_tag.as_bytes(), end_at).ok_or(format!("${name} is not closed"))?;
        if matches!(name.as_str(), "Nodes" | "Elements")
            && bytes[end_at..end].iter().any(|b| !b.is_ascii_whitespace())
        {
            return Err(format!("${name}: more data than its counts say"));
        }
        at = end + end_tag.len();
    }
    if !nodes_seen {
        return Err("no $Nodes section".into());
    }
    if !elements_seen {
        return Err("no $Elements section".into());
    }
    Ok(out)
}

fn read_nodes(r: &mut Reader, out: &mut MshCells) -> Result<(), String> {
    let blocks = r.count(20)?;
    let (_nodes, _min, _max) = (r.size()?, r.size()?, r.size()?);
    for _ in 0..blocks {
        let (_dim, _tag, parametric) = (r.int()?, r.int()?, r.int()?);
        let count = r.count(32)?;
        if parametric != 0 {
            return Err("$Nodes: parametric nodes are not read".into());
        }
        let tags: Vec<u64> = (0..count).map(|_| r.size()).collect::<Result<_, _>>()?;
        for tag in tags {
            let (x, y, _z) = (r.double()?, r.double()?, r.double()?);
            out.nodes.push((tag, x, y));
        }
    }
    Ok(())
}

fn read_elements(r: &mut Reader, out: &mut MshCells) -> Result<(), String> {
    let blocks = r.count(20)?;
    let (_elements, _min, _max) = (r.size()?, r.size()?, r.size()?);
    for _ in 0..blocks {
        let (_dim, _tag, kind) = (r.int()?, r.int()?, r.int()?);
        let per = nodes_per_element(kind)?;
        let count = r.count(8 * (per + 1))?;
        for _ in 0..count {
            let _element_tag = r.size()?;
            let tags: Vec<u64> = (0..per).map(|_| r.size()).collect::<Result<_, _>>()?;
            out.cells.push((kind as u32, tags));
        }
    }
    Ok(())
}

/// The node tags of the cells mapped to node indices, in reading order.
pub fn node_index(cells: &MshCells) -> HashMap<u64, u32> {
    cells
        .nodes
        .iter()
        .enumerate()
        .map(|(i, &(tag, _, _))| (tag, i as u32))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square as one quad and one boundary line, written the way
    /// the manual lays binary 4.1 out (little-endian).
    fn square() -> Vec<u8> {
        let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
        b.extend(1i32.to_le_bytes());
        b.extend(b"\n$EndMeshFormat\n$Nodes\n");
        for n in [1u64, 4, 1, 4] {
            b.extend(n.to_le_bytes());
        }
        for i in [2i32, 1, 0] {
            b.extend(i.to_le_bytes());
        }
        b.extend(4u64.to_le_bytes());
        for t in 1u64..=4 {
            b.extend(t.to_le_bytes());
        }
        for (x, y) in [(0.0f64, 0.0f64), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            for c in [x, y, 0.0] {
                b.extend(c.to_le_bytes());
            }
        }
        b.extend(b"\n$EndNodes\n$Elements\n");
        for n in [2u64, 2, 1, 2] {
            b.extend(n.to_le_bytes());
        }
        for i in [1i32, 1, 1] {
            b.extend(i.to_le_bytes());
        }
        b.extend(1u64.to_le_bytes());
        for t in [1u64, 1, 2] {
            b.extend(t.to_le_bytes());
        }
        for i in [2i32, 1, 3] {
            b.extend(i.to_le_bytes());
        }
        b.extend(1u64.to_le_bytes());
        for t in [2u64, 1, 2, 3, 4] {
            b.extend(t.to_le_bytes());
        }
        b.extend(b"\n$EndElements\n");
        b
    }

    #[test]
    fn a_binary_square_reads_as_its_nodes_and_cells() {
        let bytes = square();
        assert!(is_binary_msh(&bytes));
        let m = read(&bytes).unwrap();
        assert_eq!(
            m.nodes,
            vec![(1, 0.0, 0.0), (2, 1.0, 0.0), (3, 1.0, 1.0), (4, 0.0, 1.0)]
        );
        assert_eq!(m.cells, vec![(1, vec![1, 2]), (3, vec![1, 2, 3, 4])]);
    }

    #[test]
    fn a_cut_binary_file_is_an_error_naming_the_section() {
        let bytes = square();
        let cut = &bytes[..bytes.len() - 30];
        let e = read(cut).unwrap_err();
        assert!(e.contains("$Elements"), "{e}");
    }

    #[test]
    fn an_ascii_file_is_not_taken_for_binary() {
        assert!(!is_binary_msh(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"));
    }
}
