//! Writers: Gmsh MSH 4.1 ASCII, legacy VTK, SVG, JSON and Abaqus `.inp`,
//! chosen by the file extension; second-order elements in all but SVG. Every file is written to a temporary name beside it and
//! renamed only when all outputs of the run are written, so a failed run
//! leaves no output; an interrupted one removes its temporaries
//! (`interrupt`).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::geometry::quad_angles;
use crate::mesh::Mesh;
use crate::second_order::{ElementKind, SecondOrder};

/// An output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Gmsh MSH 4.1, ASCII.
    Msh,
    /// Legacy VTK unstructured grid.
    Vtk,
    /// A picture.
    Svg,
    /// Nodes, quads and boundary edges as JSON.
    Json,
    /// Abaqus / CalculiX input deck.
    Inp,
}

/// An error writing outputs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The extension names no known format.
    #[error("{0}: unknown output format (use .msh, .vtk, .svg, .json or .inp)")]
    UnknownFormat(String),
    /// The run was interrupted (Ctrl-C, a termination request) before
    /// its outputs were all in place: none is.
    #[error("interrupted: no output written")]
    Interrupted,
    /// The file could not be written.
    #[error("{path}: cannot write: {reason}")]
    Io {
        /// The file.
        path: String,
        /// Why (as text: an error chain would repeat the system's reason).
        reason: String,
    },
}

/// Set by the signal handler itself (`interrupted_flag`) the moment an
/// interruption comes, before any thread runs on: the renames look at it,
/// so that a run interrupted while its temporaries are there never puts
/// them in place, whichever thread the handler's work runs on.
static INTERRUPTED: std::sync::OnceLock<std::sync::Arc<std::sync::atomic::AtomicBool>> =
    std::sync::OnceLock::new();

/// The flag an interruption sets (for `signal_hook::flag::register`).
pub fn interrupted_flag() -> std::sync::Arc<std::sync::atomic::AtomicBool> {
    INTERRUPTED.get_or_init(Default::default).clone()
}

/// Whether an interruption came.
pub fn was_interrupted() -> bool {
    INTERRUPTED
        .get()
        .is_some_and(|f| f.load(std::sync::atomic::Ordering::SeqCst))
}

/// The temporaries being written, so that an interrupted run can remove
/// them (`interrupt`).
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temporaries() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Makes the file `tmp` and lists it among the temporaries, both while
/// the list is held: `interrupt` then finds every temporary made.
fn make_temporary(tmp: &Path) -> std::io::Result<std::fs::File> {
    let mut list = temporaries();
    list.push(tmp.to_path_buf());
    std::fs::File::create(tmp)
}

fn forget_temporary(tmp: &Path) {
    temporaries().retain(|t| t != tmp);
}

/// For a signal handler, just before the process exits: removes the
/// temporaries of the writes under way and keeps the list held, so that
/// no other one is made and no temporary is renamed into place.
pub fn interrupt() {
    let list = temporaries();
    for t in list.iter() {
        let _ = std::fs::remove_file(t);
    }
    std::mem::forget(list);
}

/// Checks before a run that `path` can be written: its folder is there
/// and a file can be made in it (the temporary the run will write, made
/// and removed at once).
pub fn check_writable(path: &Path) -> Result<(), OutputError> {
    let fail = |reason: String| OutputError::Io {
        path: path.display().to_string(),
        reason,
    };
    let folder = match path.parent() {
        Some(f) if !f.as_os_str().is_empty() => f,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(fail(if folder.exists() {
            format!("{} is not a folder", folder.display())
        } else {
            format!("the folder {} does not exist", folder.display())
        }));
    }
    if path.is_dir() || path.file_name().is_none() {
        return Err(fail("it is a folder, not a file name".into()));
    }
    let tmp = tmp_name(path);
    let made = make_temporary(&tmp);
    if made.is_ok() {
        let _ = std::fs::remove_file(&tmp);
    }
    forget_temporary(&tmp);
    made.map(|_| ()).map_err(|e| fail(e.to_string()))
}

impl Format {
    /// The format of a path, by its extension.
    pub fn from_path(path: &Path) -> Result<Format, OutputError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("msh") => Ok(Format::Msh),
            Some("vtk") => Ok(Format::Vtk),
            Some("svg") => Ok(Format::Svg),
            Some("json") => Ok(Format::Json),
            Some("inp") => Ok(Format::Inp),
            _ => Err(OutputError::UnknownFormat(path.display().to_string())),
        }
    }
}

/// Renders a mesh in a format, with its second-order nodes if given (the
/// picture draws the corner quads).
pub fn render(mesh: &Mesh, second: Option<&SecondOrder>, name: &str, format: Format) -> String {
    match format {
        Format::Msh => to_msh(mesh, second),
        Format::Vtk => to_vtk(mesh, second, name),
        Format::Svg => to_svg(mesh, &[], name),
        Format::Json => to_json(mesh, second, name),
        Format::Inp => super::inp::to_inp(mesh, second, name),
    }
}

/// The nodes of element `q`: its corners, or its second-order row.
fn element_nodes<'a>(mesh: &'a Mesh, second: Option<&'a SecondOrder>, q: usize) -> &'a [u32] {
    match second {
        Some(so) => so.element(q),
        None => &mesh.quads[q],
    }
}

/// Writes several files all or nothing: temporaries first, then renames.
pub fn write_all(files: &[(PathBuf, String)]) -> Result<(), OutputError> {
    let temps: Vec<PathBuf> = files.iter().map(|(path, _)| tmp_name(path)).collect();
    let remove_all = || {
        for t in &temps {
            let _ = std::fs::remove_file(t);
            forget_temporary(t);
        }
    };
    for ((path, text), tmp) in files.iter().zip(&temps) {
        let written = make_temporary(tmp).and_then(|mut f| f.write_all(text.as_bytes()));
        if let Err(e) = written {
            remove_all();
            return Err(OutputError::Io {
                path: path.display().to_string(),
                reason: e.to_string(),
            });
        }
    }
    for ((path, _), tmp) in files.iter().zip(&temps) {
        // renamed while the list is held: an interruption removes the
        // temporary or finds it renamed, never half of each
        let mut list = temporaries();
        if was_interrupted() {
            drop(list);
            remove_all();
            return Err(OutputError::Interrupted);
        }
        let renamed = std::fs::rename(tmp, path);
        list.retain(|t| t != tmp);
        drop(list);
        if let Err(e) = renamed {
            remove_all();
            return Err(OutputError::Io {
                path: path.display().to_string(),
                reason: e.to_string(),
            });
        }
    }
    Ok(())
}

fn tmp_name(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(format!(".tmp-{}", std::process::id()));
    path.with_file_name(name)
}

fn bbox(mesh: &Mesh) -> (f64, f64, f64, f64) {
    let mut b = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for p in &mesh.nodes {
        b = (b.0.min(p.x), b.1.min(p.y), b.2.max(p.x), b.3.max(p.y));
    }
    b
}

/// Gmsh MSH 4.1 ASCII: the quads (type 3; second order: 16 with 8 nodes,
/// 10 with 9) in a surface entity with the physical group "domain" (one
/// entity a region, each also in the group `region K`, when lines part the
/// domain; with `--blocks`, one entity a block, in the group `block K`,
/// its region's and "domain"), and one curve entity a boundary group (each input loop and
/// inner line, each tag, each crack face) with its boundary edges (type 1;
/// second order: 8, the mid-edge node last) in a physical group of its
/// name.
pub fn to_msh(mesh: &Mesh, second: Option<&SecondOrder>) -> String {
    let extra: &[glam::DVec2] = second.map_or(&[], |so| &so.nodes);
    let (quad_type, line_type) = match second.map(|so| so.kind) {
        None | Some(ElementKind::Quad4) => (3, 1),
        Some(ElementKind::Quad8) => (16, 8),
        Some(ElementKind::Quad9) => (10, 8),
    };
    let mut s = String::with_capacity(64 * (mesh.nodes.len() + extra.len() + mesh.quads.len()));
    let ng = mesh.groups.len();
    let regions = mesh.region_count() as usize;
    // one surface a region when there are several: physical tags ng + 2...
    let region_groups = if regions > 1 { regions } else { 0 };
    // with blocks, one surface a block (tags after the regions'), each
    // also in its region's group and in "domain"
    let block_groups = mesh.block_count() as usize;
    let (x0, y0, x1, y1) = bbox(mesh);
    s.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    let _ = writeln!(
        s,
        "$PhysicalNames\n{}",
        ng + 1 + region_groups + block_groups
    );
    for (i, g) in mesh.groups.iter().enumerate() {
        let _ = writeln!(s, "1 {} \"{}\"", i + 1, g.replace('"', "'"));
    }
    let _ = writeln!(s, "2 {} \"domain\"", ng + 1);
    for r in 0..region_groups {
        let _ = writeln!(s, "2 {} \"region {}\"", ng + 2 + r, r + 1);
    }
    for b in 0..block_groups {
        let _ = writeln!(s, "2 {} \"block {}\"", ng + 2 + region_groups + b, b + 1);
    }
    s.push_str("$EndPhysicalNames\n");
    let surfaces = if block_groups > 0 {
        block_groups
    } else {
        regions.max(1)
    };
    let _ = writeln!(s, "$Entities\n0 {ng} {surfaces} 0");
    for i in 0..ng {
        let _ = writeln!(s, "{} {x0} {y0} 0 {x1} {y1} 0 1 {} 0", i + 1, i + 1);
    }
    if block_groups > 0 {
        // a block's region: that of its first quad
        let mut region_of = vec![0usize; block_groups];
        for (q, &b) in mesh.blocks.iter().enumerate().rev() {
            region_of[b as usize] = mesh.regions.get(q).map_or(0, |&r| r as usize);
        }
        for (b, r) in region_of.iter().enumerate() {
            let block_tag = ng + 2 + region_groups + b;
            if region_groups == 0 {
                let _ = writeln!(
                    s,
                    "{} {x0} {y0} 0 {x1} {y1} 0 2 {block_tag} {} 0",
                    b + 1,
                    ng + 1
                );
            } else {
                let _ = writeln!(
                    s,
                    "{} {x0} {y0} 0 {x1} {y1} 0 3 {block_tag} {} {} 0",
                    b + 1,
                    ng + 2 + r,
                    ng + 1
                );
            }
        }
    } else if region_groups == 0 {
        let _ = writeln!(s, "1 {x0} {y0} 0 {x1} {y1} 0 1 {} 0", ng + 1);
    } else {
        // the region's group first: a reader that keeps one physical
        // group an entity keeps that one
        for r in 0..regions {
            let _ = writeln!(
                s,
                "{} {x0} {y0} 0 {x1} {y1} 0 2 {} {} 0",
                r + 1,
                ng + 2 + r,
                ng + 1
            );
        }
    }
    s.push_str("$EndEntities\n");
    let n = mesh.nodes.len() + extra.len();
    let _ = writeln!(s, "$Nodes\n1 {n} 1 {n}\n2 1 0 {n}");
    for i in 0..n {
        let _ = writeln!(s, "{}", i + 1);
    }
    // the coordinates (most of the writing: the shortest exact form of
    // each float) in two halves side by side
    let all;
    let nodes: &[glam::DVec2] = if extra.is_empty() {
        &mesh.nodes
    } else {
        all = [mesh.nodes.as_slice(), extra].concat();
        &all
    };
    let (first, second_half) = nodes.split_at(n / 2);
    let coordinates = |half: &[glam::DVec2]| {
        let mut t = String::with_capacity(48 * half.len());
        for p in half {
            let _ = writeln!(t, "{:?} {:?} 0", p.x, p.y);
        }
        t
    };
    let (a, b) = std::thread::scope(|scope| {
        let b = scope.spawn(|| coordinates(second_half));
        let a = coordinates(first);
        (a, b.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
    });
    s.push_str(&a);
    s.push_str(&b);
    s.push_str("$EndNodes\n");
    let by_group = mesh.group_edges();
    let blocks = by_group.iter().filter(|v| !v.is_empty()).count() + surfaces;
    let total = mesh.boundary.len() + mesh.quads.len();
    let _ = writeln!(s, "$Elements\n{blocks} {total} 1 {total}");
    let mut tag = 1;
    for (g, edges) in by_group.iter().enumerate() {
        if edges.is_empty() {
            continue;
        }
        let _ = writeln!(s, "1 {} {line_type} {}", g + 1, edges.len());
        for &(a, b) in edges {
            let _ = write!(s, "{tag} {} {}", a + 1, b + 1);
            if let Some(m) = second.and_then(|so| so.middle(a, b)) {
                let _ = write!(s, " {}", m + 1);
            }
            s.push('\n');
            tag += 1;
        }
    }
    // each surface's quads, in their order (one pass: a mesh may have
    // hundreds of blocks)
    let mut by_surface: Vec<Vec<usize>> = vec![Vec::new(); surfaces];
    for q in 0..mesh.quads.len() {
        let r = if block_groups > 0 {
            mesh.blocks[q] as usize
        } else if region_groups > 0 {
            mesh.regions[q] as usize
        } else {
            0
        };
        by_surface[r].push(q);
    }
    for (r, quads) in by_surface.iter().enumerate() {
        let _ = writeln!(s, "2 {} {quad_type} {}", r + 1, quads.len());
        for &q in quads {
            let _ = write!(s, "{tag}");
            for n in element_nodes(mesh, second, q) {
                let _ = write!(s, " {}", n + 1);
            }
            s.push('\n');
            tag += 1;
        }
    }
    s.push_str("$EndElements\n");
    s
}

/// Legacy VTK (ASCII unstructured grid of quads, cell type 9; second
/// order: 23 with 8 nodes, 28 with 9). Where the domain has named
/// boundary groups (tags, crack faces) the boundary edges follow the quads
/// as line cells (type 3), with one cell-data array a named group (1 on
/// its edges, 0 elsewhere; spaces in the name written as `_`); where lines
/// part the domain, the cell-data array `region` numbers each quad's
/// region from 1 (0 on line cells); with `--blocks`, `block` its block.
pub fn to_vtk(mesh: &Mesh, second: Option<&SecondOrder>, name: &str) -> String {
    let extra: &[glam::DVec2] = second.map_or(&[], |so| &so.nodes);
    let (per, cell_type) = match second.map(|so| so.kind) {
        None | Some(ElementKind::Quad4) => (4, "9"),
        Some(ElementKind::Quad8) => (8, "23"),
        Some(ElementKind::Quad9) => (9, "28"),
    };
    let mut s = String::with_capacity(48 * (mesh.nodes.len() + extra.len() + mesh.quads.len()));
    let title: String = name.chars().filter(|c| *c != '\n').take(200).collect();
    let _ = writeln!(
        s,
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {} double",
        mesh.nodes.len() + extra.len()
    );
    for p in mesh.nodes.iter().chain(extra) {
        let _ = writeln!(s, "{:?} {:?} 0", p.x, p.y);
    }
    let named: Vec<u32> = named_groups(mesh);
    let lines = if named.is_empty() {
        &[][..]
    } else {
        &mesh.boundary[..]
    };
    let regions = mesh.region_count();
    let nq = mesh.quads.len();
    let cells = nq + lines.len();
    let _ = writeln!(s, "CELLS {cells} {}", nq * (per + 1) + lines.len() * 3);
    for q in 0..nq {
        let _ = write!(s, "{per}");
        for n in element_nodes(mesh, second, q) {
            let _ = write!(s, " {n}");
        }
        s.push('\n');
    }
    for e in lines {
        let _ = writeln!(s, "2 {} {}", e.a, e.b);
    }
    let _ = writeln!(s, "CELL_TYPES {cells}");
    for _ in 0..nq {
        s.push_str(cell_type);
        s.push('\n');
    }
    for _ in lines {
        s.push_str("3\n");
    }
    if named.is_empty() && regions <= 1 && mesh.blocks.is_empty() {
        return s;
    }
    let _ = writeln!(s, "CELL_DATA {cells}");
    if !mesh.blocks.is_empty() {
        s.push_str("SCALARS block int 1\nLOOKUP_TABLE default\n");
        for b in &mesh.blocks {
            let _ = writeln!(s, "{}", b + 1);
        }
        for _ in lines {
            s.push_str("0\n");
        }
    }
    if regions > 1 {
        s.push_str("SCALARS region int 1\nLOOKUP_TABLE default\n");
        for r in &mesh.regions {
            let _ = writeln!(s, "{}", r + 1);
        }
        for _ in lines {
            s.push_str("0\n");
        }
    }
    for g in named {
        let label = mesh.groups[g as usize].replace(char::is_whitespace, "_");
        let _ = writeln!(s, "SCALARS {label} int 1\nLOOKUP_TABLE default");
        for _ in 0..nq {
            s.push_str("0\n");
        }
        for e in lines {
            s.push_str(if e.output_group() == g { "1\n" } else { "0\n" });
        }
    }
    s
}

/// The element edges two blocks share, in order of their nodes.
fn block_edges(mesh: &Mesh) -> Vec<(u32, u32)> {
    let mut sides: Vec<((u32, u32), u32)> = Vec::with_capacity(4 * mesh.quads.len());
    for (q, quad) in mesh.quads.iter().enumerate() {
        for k in 0..4 {
            let (a, b) = (quad[k], quad[(k + 1) % 4]);
            sides.push(((a.min(b), a.max(b)), mesh.blocks[q]));
        }
    }
    sides.sort_unstable();
    sides
        .windows(2)
        .filter(|w| w[0].0 == w[1].0 && w[0].1 != w[1].1)
        .map(|w| w[0].0)
        .collect()
}

/// The groups that are not an input loop's or line's: tags and crack
/// faces, in the order of `Mesh::groups`, those with edges.
fn named_groups(mesh: &Mesh) -> Vec<u32> {
    let mut used: Vec<u32> = mesh.boundary.iter().filter_map(|e| e.tag).collect();
    used.sort_unstable();
    used.dedup();
    used
}

/// An SVG picture: quads outlined, those with a corner outside [45, 135]
/// filled red, input boundary drawn thick; `front` draws open loops (the
/// REPL's current state) in blue.
pub fn to_svg(mesh: &Mesh, front: &[Vec<u32>], title: &str) -> String {
    let (x0, y0, x1, y1) = bbox(mesh);
    let w = (x1 - x0).max(1e-12);
    let h = (y1 - y0).max(1e-12);
    let scale = 900.0 / w.max(h);
    let (pw, ph) = (w * scale + 40.0, h * scale + 70.0);
    let tx = |x: f64| (x - x0) * scale + 20.0;
    let ty = |y: f64| (y1 - y) * scale + 50.0;
    let stroke = (0.6f64).min(300.0 / (mesh.quads.len() as f64).sqrt().max(1.0));
    let mut s = String::new();
    let _ = writeln!(s, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{pw:.0}\" height=\"{ph:.0}\" viewBox=\"0 0 {pw:.1} {ph:.1}\">");
    let _ = writeln!(s, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
    let bad = (0..mesh.quads.len())
        .filter(|&i| {
            quad_angles(mesh.quad_points(i))
                .iter()
                .any(|a| !(45.0..=135.0).contains(a))
        })
        .count();
    let esc = |t: &str| {
        t.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let _ = writeln!(s, "<text x=\"20\" y=\"30\" font-family=\"sans-serif\" font-size=\"16\">{}: {} quads, {} outside [45, 135] deg (red)</text>", esc(title), mesh.quads.len(), bad);
    let _ = writeln!(
        s,
        "<g stroke=\"#222\" stroke-width=\"{stroke:.2}\" stroke-linejoin=\"round\">"
    );
    for i in 0..mesh.quads.len() {
        let p = mesh.quad_points(i);
        let fill = if quad_angles(p).iter().any(|a| !(45.0..=135.0).contains(a)) {
            "#f08080"
        } else {
            "#e8f0fa"
        };
        let pts: Vec<String> = p
            .iter()
            .map(|q| format!("{:.2},{:.2}", tx(q.x), ty(q.y)))
            .collect();
        let _ = writeln!(s, "<polygon points=\"{}\" fill=\"{fill}\"/>", pts.join(" "));
    }
    s.push_str("</g>\n");
    // the input boundary thick; the blocks' edges (element edges between
    // two blocks) in blue
    let segments = |s: &mut String, colour: &str, width: f64, edges: &[(u32, u32)]| {
        let _ = writeln!(
            s,
            "<g stroke=\"{colour}\" stroke-width=\"{width:.2}\" fill=\"none\">"
        );
        for &(a, b) in edges {
            let (a, b) = (mesh.nodes[a as usize], mesh.nodes[b as usize]);
            let _ = writeln!(
                s,
                "<line x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\"/>",
                tx(a.x),
                ty(a.y),
                tx(b.x),
                ty(b.y)
            );
        }
        s.push_str("</g>\n");
    };
    let boundary: Vec<(u32, u32)> = mesh.boundary.iter().map(|e| (e.a, e.b)).collect();
    segments(&mut s, "#000", stroke * 3.0, &boundary);
    if !mesh.blocks.is_empty() {
        segments(&mut s, "#1f5fbf", stroke * 2.5, &block_edges(mesh));
    }
    if !front.is_empty() {
        let _ = writeln!(
            s,
            "<g stroke=\"#1060e0\" stroke-width=\"{:.2}\" fill=\"none\">",
            stroke * 3.0
        );
        for lp in front {
            let pts: Vec<String> = lp
                .iter()
                .map(|&n| mesh.nodes[n as usize])
                .map(|q| format!("{:.2},{:.2}", tx(q.x), ty(q.y)))
                .collect();
            let _ = writeln!(s, "<polygon points=\"{}\"/>", pts.join(" "));
        }
        s.push_str("</g>\n");
    }
    s.push_str("</svg>\n");
    s
}

/// JSON: name, nodes, quads (0-based ids), boundary edges with their
/// groups (a tagged edge's group is its tag's, and it names its loop or
/// line as `on`), the group names; where lines part the domain,
/// `regions`: each quad's region, numbered from 1; with `--blocks`,
/// `blocks`: each quad's block, from 1; second order: `nodes`
/// holds the added nodes after the corners, and `elements` each element's
/// 8 or 9 nodes (`element_type` `quad8` or `quad9`), `quads` still the
/// corners.
pub fn to_json(mesh: &Mesh, second: Option<&SecondOrder>, name: &str) -> String {
    let extra: &[glam::DVec2] = second.map_or(&[], |so| &so.nodes);
    let boundary: Vec<serde_json::Value> = mesh
        .boundary
        .iter()
        .map(|e| {
            let group = &mesh.groups[e.output_group() as usize];
            match e.tag {
                None => serde_json::json!({"nodes": [e.a, e.b], "group": group}),
                Some(_) => serde_json::json!({"nodes": [e.a, e.b], "group": group, "on": mesh.groups[e.group as usize]}),
            }
        })
        .collect();
    let mut v = serde_json::json!({
        "name": name,
        "nodes": mesh.nodes.iter().chain(extra).map(|p| [p.x, p.y]).collect::<Vec<_>>(),
        "quads": mesh.quads,
        "boundary": boundary,
        "groups": mesh.groups,
    });
    if let Some(so) = second {
        let per = so.kind.nodes();
        v["element_type"] = format!("quad{per}").into();
        v["elements"] = so.elements.chunks_exact(per).collect::<Vec<_>>().into();
    }
    if !mesh.blocks.is_empty() {
        v["blocks"] = mesh.blocks.iter().map(|b| b + 1).collect::<Vec<_>>().into();
    }
    if mesh.region_count() > 1 {
        v["regions"] = mesh
            .regions
            .iter()
            .map(|r| r + 1)
            .collect::<Vec<_>>()
            .into();
    }
    serde_json::to_string(&v).unwrap_or_default()
}
