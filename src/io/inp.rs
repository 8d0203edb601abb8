//! Abaqus input decks (`.inp`), which CalculiX reads too: the nodes, the
//! elements in one element set `EALL` (and one set a region, `region_1`,
//! ..., where lines part the domain), and for each boundary group of the
//! mesh (`outer`, `hole 1`, `line 1`, a tag...) a node set, an element set
//! (the elements with a face on it) and an element-face surface, so that
//! boundary conditions and loads can be put on it.
//!
//! Element types: CPS4 (4-node plane stress), CPS8 (8-node plane stress)
//! for second-order serendipity quads. Abaqus has no 9-node plane stress
//! element and CalculiX no 9-node element at all (2.20 refuses S9R5 as
//! unknown): 9-node quads are written as S9R5, Abaqus' 9-node thin shell,
//! which meshio reads as `quad9`.
//!
//! Abaqus names are letters, digits and underscores, starting with a
//! letter, at most 80 characters, and case does not tell them apart: each
//! group's name is made so (`hole 1` -> `hole_1`), kept apart from the
//! others, and the original written in a comment beside it.

use std::collections::HashSet;
use std::fmt::Write as _;

use crate::mesh::Mesh;
use crate::second_order::{ElementKind, SecondOrder};

/// The Abaqus element type of an element kind.
pub fn element_type(kind: ElementKind) -> &'static str {
    match kind {
        ElementKind::Quad4 => "CPS4",
        ElementKind::Quad8 => "CPS8",
        ElementKind::Quad9 => "S9R5",
    }
}

/// A group name made into an Abaqus label: letters, digits and `_`,
/// starting with a letter (`G_` put before one that does not), at most 70
/// characters (room for a suffix).
pub fn abaqus_label(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .take(70)
        .collect();
    if !s.starts_with(|c: char| c.is_ascii_alphabetic()) {
        s.insert_str(0, "G_");
        s.truncate(70);
    }
    s
}

/// Labels for the groups, each unique whatever the case and apart from
/// `EALL`, `NALL` and the surfaces' `_S` names.
fn unique_labels(groups: &[String]) -> Vec<String> {
    let mut taken: HashSet<String> = ["EALL", "NALL"].iter().map(|s| s.to_string()).collect();
    groups
        .iter()
        .map(|g| {
            let base = abaqus_label(g);
            let mut label = base.clone();
            let mut k = 2;
            while taken.contains(&label.to_ascii_uppercase())
                || taken.contains(&format!("{}_S", label.to_ascii_uppercase()))
            {
                label = format!("{base}_{k}");
                k += 1;
            }
            taken.insert(label.to_ascii_uppercase());
            taken.insert(format!("{}_S", label.to_ascii_uppercase()));
            label
        })
        .collect()
}

/// Writes ids 16 to a line (Abaqus' limit), 1-based.
fn write_ids(s: &mut String, ids: &[u32]) {
    for chunk in ids.chunks(16) {
        let line: Vec<String> = chunk.iter().map(|i| (i + 1).to_string()).collect();
        let _ = writeln!(s, "{}", line.join(", "));
    }
}

/// The deck of a mesh (with its second-order nodes, if any) named `name`.
pub fn to_inp(mesh: &Mesh, second: Option<&SecondOrder>, name: &str) -> String {
    let kind = second.map_or(ElementKind::Quad4, |s| s.kind);
    let extra: &[glam::DVec2] = second.map_or(&[], |s| &s.nodes);
    let mut s = String::with_capacity(48 * (mesh.nodes.len() + extra.len() + mesh.quads.len()));
    let title: String = name.chars().filter(|c| !c.is_control()).take(200).collect();
    let _ = writeln!(s, "** Abaqus / CalculiX input deck written by freemesh");
    let _ = writeln!(
        s,
        "** {} nodes, {} {} elements (plane, z = 0)",
        mesh.nodes.len() + extra.len(),
        mesh.quads.len(),
        element_type(kind)
    );
    if kind == ElementKind::Quad9 {
        s.push_str(
            "** S9R5: Abaqus has no 9-node plane stress element; CalculiX no 9-node element\n",
        );
    }
    let _ = writeln!(s, "*HEADING\n{title}");
    s.push_str("*NODE, NSET=NALL\n");
    for (i, p) in mesh.nodes.iter().chain(extra).enumerate() {
        let _ = writeln!(s, "{}, {:?}, {:?}", i + 1, p.x, p.y);
    }
    let _ = writeln!(s, "*ELEMENT, TYPE={}, ELSET=EALL", element_type(kind));
    for q in 0..mesh.quads.len() {
        let nodes: &[u32] = match second {
            Some(so) => so.element(q),
            None => &mesh.quads[q],
        };
        let _ = write!(s, "{}", q + 1);
        for n in nodes {
            let _ = write!(s, ", {}", n + 1);
        }
        s.push('\n');
    }
    // the element and face of each edge: face k joins corners k and k+1
    let mut face_of: std::collections::HashMap<(u32, u32), Vec<(u32, u8)>> = Default::default();
    for (e, q) in mesh.quads.iter().enumerate() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            face_of
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((e as u32, k as u8 + 1));
        }
    }
    // the regions that lines part the domain into, after the groups
    let regions = mesh.region_count() as usize;
    let regions = if regions > 1 { regions } else { 0 };
    let mut names = mesh.groups.clone();
    names.extend((1..=regions).map(|r| format!("region {r}")));
    let labels = unique_labels(&names);
    for r in 0..regions {
        let label = &labels[mesh.groups.len() + r];
        let elements: Vec<u32> = (0..mesh.quads.len() as u32)
            .filter(|&q| mesh.regions[q as usize] as usize == r)
            .collect();
        let _ = writeln!(s, "** region {}: element set {label}", r + 1);
        let _ = writeln!(s, "*ELSET, ELSET={label}");
        write_ids(&mut s, &elements);
    }
    let by_group = mesh.group_edges();
    for (g, group) in mesh.groups.iter().enumerate() {
        let edges: Vec<(u32, u32)> = by_group[g].clone();
        if edges.is_empty() {
            continue;
        }
        let label = &labels[g];
        let mut nodes: Vec<u32> = Vec::with_capacity(3 * edges.len());
        let mut faces: Vec<(u32, u8)> = Vec::with_capacity(edges.len());
        for &(a, b) in &edges {
            nodes.push(a);
            nodes.push(b);
            if let Some(m) = second.and_then(|so| so.middle(a, b)) {
                nodes.push(m);
            }
            faces.extend(face_of.get(&(a.min(b), a.max(b))).into_iter().flatten());
        }
        nodes.sort_unstable();
        nodes.dedup();
        faces.sort_unstable();
        faces.dedup();
        let mut elements: Vec<u32> = faces.iter().map(|f| f.0).collect();
        elements.dedup();
        let _ = writeln!(
            s,
            "** group {:?}: node set and element set {label}, surface {label}_S",
            group
        );
        let _ = writeln!(s, "*NSET, NSET={label}");
        write_ids(&mut s, &nodes);
        let _ = writeln!(s, "*ELSET, ELSET={label}");
        write_ids(&mut s, &elements);
        let _ = writeln!(s, "*SURFACE, NAME={label}_S, TYPE=ELEMENT");
        for (e, k) in faces {
            let _ = writeln!(s, "{}, S{k}", e + 1);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_become_abaqus_labels() {
        assert_eq!(abaqus_label("hole 1"), "hole_1");
        assert_eq!(abaqus_label("outer"), "outer");
        assert_eq!(abaqus_label("2nd-face"), "G_2nd_face");
        assert_eq!(abaqus_label("é"), "G__");
        assert_eq!(abaqus_label(&"x".repeat(100)).len(), 70);
    }

    #[test]
    fn labels_that_differ_only_in_case_or_punctuation_are_kept_apart() {
        let groups: Vec<String> = ["hole 1", "hole_1", "HOLE-1", "eall"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_eq!(
            unique_labels(&groups),
            vec!["hole_1", "hole_1_2", "HOLE_1_3", "eall_2"]
        );
    }
}
