//! DXF outlines in: the LINE, ARC, CIRCLE, LWPOLYLINE and POLYLINE
//! entities of an ASCII DXF drawing joined by their end points into the
//! loops and lines of a domain (`domain-format.md`, version 1.1).
//!
//! How a drawing becomes a domain:
//!
//! - End points closer than [`JOIN_TOLERANCE`] times the drawing's extent
//!   (the larger side of the box round every entity) are one point. Where
//!   they differ, the point typed in the file (a polyline vertex, a line's
//!   end) wins over one computed (an arc's end, from its angles).
//! - Chains hanging free (an end that meets nothing) and chains joining
//!   two loops, or running across the inside of a loop, are inner
//!   `lines`; the closed rest are loops. The loop that contains the others
//!   is the outer boundary, every other loop a hole. A CIRCLE is a loop by
//!   itself.
//! - Each entity's layer is the `tags` entry of its edges; the default
//!   layer `0` stands for no tag.
//! - An outline with no closed loop round the rest does not close: the
//!   error names the gap (the two nearest free ends).
//!
//! Entities in paper space, blocks and annotations (TEXT, DIMENSION, ...)
//! are skipped, each kind named in a warning. Arcs are kept exact as
//! bulges, in the DXF polyline convention the domain format uses.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;

use glam::DVec2;
use serde::Serialize;

use crate::domain::Curve;
use crate::geometry::point_in_polygon;

/// End points closer than this times the drawing's extent are one point.
pub const JOIN_TOLERANCE: f64 = 1e-6;

/// What is wrong with a drawing.
#[derive(Debug, thiserror::Error)]
pub enum DxfError {
    /// The file cannot be read as DXF.
    #[error("{path}: cannot read as DXF: {message}")]
    Read {
        /// The file.
        path: String,
        /// What the DXF reader said.
        message: String,
    },
    /// An entity the reader cannot use as it stands.
    #[error("{path}: {message}")]
    Entity {
        /// The file.
        path: String,
        /// Which entity and why.
        message: String,
    },
    /// Nothing to make a domain of.
    #[error("{path}: no outline: the drawing has no LINE, ARC, CIRCLE, LWPOLYLINE or POLYLINE in model space")]
    Empty {
        /// The file.
        path: String,
    },
    /// The outline is open.
    #[error("{path}: the outline does not close: a gap between ({}, {}) and ({}, {}), {distance:.6e} apart (end points join within {tolerance:.3e}){more}", .from.x, .from.y, .to.x, .to.y)]
    Gap {
        /// The file.
        path: String,
        /// One side of the gap.
        from: DVec2,
        /// The other side.
        to: DVec2,
        /// Their distance.
        distance: f64,
        /// The joining tolerance.
        tolerance: f64,
        /// A note on further gaps, or empty.
        more: String,
    },
    /// The loops do not make one domain.
    #[error("{path}: {message}")]
    Shape {
        /// The file.
        path: String,
        /// What is wrong, with a point.
        message: String,
    },
}

/// One polyline of a domain (a loop or an inner line): points, a bulge
/// and a tag per edge.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Polyline {
    /// The corners (a loop's first point not repeated at its end).
    pub points: Vec<[f64; 2]>,
    /// tan(sweep / 4) of each edge; left out when every edge is straight.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bulges: Option<Vec<f64>>,
    /// The layer of each edge (`""`: the default layer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tags: Option<Vec<String>>,
}

/// A full circle of a domain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Circle {
    /// Centre.
    pub center: [f64; 2],
    /// Radius.
    pub radius: f64,
    /// Its layer, if not the default one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tag: Option<String>,
}

/// A loop of a domain file: a polyline or a circle.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Loop {
    /// Edges and arcs.
    Polyline(Polyline),
    /// A full circle.
    Circle {
        /// The circle.
        circle: Circle,
    },
}

/// A domain file (format 1.1) made from a drawing, keys in the format's
/// order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DomainFile {
    /// Free text: the drawing's file name.
    pub name: String,
    /// Target boundary segment length.
    pub size: f64,
    /// Largest interior element edge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_size: Option<f64>,
    /// The outer loop.
    pub outer: Loop,
    /// The holes.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Loop>,
    /// The inner lines.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub lines: Vec<Polyline>,
}

impl DomainFile {
    /// The domain as a JSON value, for `Domain::from_json`.
    pub fn to_json_value(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    /// The domain file's text: pretty JSON, keys in the format's order,
    /// each point and each list of numbers or tags on one line.
    pub fn to_pretty_json(&self) -> String {
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        let mut out = one_line_flat_arrays(&text);
        out.push('\n');
        out
    }
}

/// Puts every array of pretty JSON that holds no array or object on one
/// line (`[\n  1.0,\n  2.0\n]` becomes `[1.0, 2.0]`).
fn one_line_flat_arrays(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '"' {
            // a string, escapes and all
            let start = i;
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            out.extend(&chars[start..=i.min(chars.len() - 1)]);
            i += 1;
            continue;
        }
        if c == '[' {
            // find the end if nothing nested comes first
            let (mut j, mut in_string, mut flat) = (i + 1, false, true);
            while j < chars.len() {
                match chars[j] {
                    '\\' if in_string => j += 1,
                    '"' => in_string = !in_string,
                    '[' | '{' if !in_string => {
                        flat = false;
                        break;
                    }
                    ']' if !in_string => break,
                    _ => {}
                }
                j += 1;
            }
            if flat && j < chars.len() {
                // the items, whitespace outside strings dropped
                let mut item = String::new();
                let mut items = Vec::new();
                let mut in_string = false;
                let mut k = i + 1;
                while k < j {
                    let d = chars[k];
                    if in_string {
                        item.push(d);
                        if d == '\\' {
                            k += 1;
                            item.push(chars[k]);
                        } else if d == '"' {
                            in_string = false;
                        }
                    } else if d == '"' {
                        in_string = true;
                        item.push(d);
                    } else if d == ',' {
                        items.push(std::mem::take(&mut item));
                    } else if !d.is_whitespace() {
                        item.push(d);
                    }
                    k += 1;
                }
                if !item.is_empty() {
                    items.push(item);
                }
                out.push('[');
                out.push_str(&items.join(", "));
                out.push(']');
                i = j + 1;
                continue;
            }
        }
        out.push(c);
        i += 1;
    }
    out
}

/// The outline of a drawing: loops and lines, with what was learnt on
/// the way.
#[derive(Debug, Clone, PartialEq)]
pub struct Outline {
    /// The outer loop (counter-clockwise).
    pub outer: Loop,
    /// The holes (clockwise).
    pub holes: Vec<Loop>,
    /// The inner lines.
    pub lines: Vec<Polyline>,
    /// The distance within which end points were joined.
    pub tolerance: f64,
    /// Entities skipped, as one line each.
    pub warnings: Vec<String>,
}

impl Outline {
    /// The domain file of this outline with boundary size `size`.
    pub fn domain_file(&self, name: &str, size: f64, max_size: Option<f64>) -> DomainFile {
        DomainFile {
            name: name.to_string(),
            size,
            max_size,
            outer: self.outer.clone(),
            holes: self.holes.clone(),
            lines: self.lines.clone(),
        }
    }

    /// One line saying what the outline holds.
    pub fn summary(&self) -> String {
        let edges = |l: &Loop| match l {
            Loop::Polyline(p) => p.points.len(),
            Loop::Circle { .. } => 1,
        };
        format!(
            "outer loop of {} edges, {} holes, {} lines; end points joined within {:.3e}",
            edges(&self.outer),
            self.holes.len(),
            self.lines.len(),
            self.tolerance
        )
    }
}

/// One edge drawn in the file: a straight edge or an arc (bulge), with
/// its layer and whether each end was typed (not computed).
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnEdge {
    /// Start.
    pub a: DVec2,
    /// End.
    pub b: DVec2,
    /// tan(sweep / 4), counter-clockwise positive; 0 for straight.
    pub bulge: f64,
    /// The layer (`""` for the default layer).
    pub layer: String,
    /// Whether the ends are typed in the file (polyline vertices, line
    /// ends) rather than computed (an arc's ends).
    pub typed: bool,
}

/// A circle drawn in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnCircle {
    /// Centre.
    pub center: DVec2,
    /// Radius.
    pub radius: f64,
    /// The layer (`""` for the default layer).
    pub layer: String,
}

/// Reads a DXF file's outline.
pub fn read_dxf(path: &Path) -> Result<Outline, DxfError> {
    let p = path.display().to_string();
    let drawing = ::dxf::Drawing::load_file(path).map_err(|e| DxfError::Read {
        path: p.clone(),
        message: e.to_string(),
    })?;
    let (edges, circles, warnings) = drawn_geometry(&drawing, &p)?;
    let mut outline = outline_of(&edges, &circles, &p)?;
    outline.warnings = warnings;
    Ok(outline)
}

/// The layer name as a tag: the default layer `0` is none.
fn layer_tag(layer: &str) -> String {
    if layer == "0" {
        String::new()
    } else {
        layer.to_string()
    }
}

/// A drawing's edges, circles and warnings.
type DrawnGeometry = (Vec<DrawnEdge>, Vec<DrawnCircle>, Vec<String>);

/// The edges and circles of a drawing's model space, and a warning for
/// each kind of entity skipped.
fn drawn_geometry(drawing: &::dxf::Drawing, path: &str) -> Result<DrawnGeometry, DxfError> {
    use ::dxf::entities::EntityType;
    let mut edges = Vec::new();
    let mut circles = Vec::new();
    let mut skipped: std::collections::BTreeMap<String, usize> = Default::default();
    for (k, entity) in drawing.entities().enumerate() {
        let layer = layer_tag(&entity.common.layer);
        if entity.common.is_in_paper_space {
            *skipped.entry("in paper space".into()).or_default() += 1;
            continue;
        }
        // Entities drawn seen from below (extrusion 0,0,-1, as mirrored
        // parts often are) have their x axis reversed; any other plane is
        // not a plane outline.
        let plane = |normal: &::dxf::Vector, what: &str| -> Result<f64, DxfError> {
            if normal.x.abs() > 1e-9 || normal.y.abs() > 1e-9 || normal.z == 0.0 {
                return Err(DxfError::Entity {
                    path: path.to_string(),
                    message: format!(
                        "entity {k} ({what} on layer {:?}) is not in the XY plane (extrusion {}, {}, {})",
                        entity.common.layer, normal.x, normal.y, normal.z
                    ),
                });
            }
            Ok(normal.z.signum())
        };
        match &entity.specific {
            EntityType::Line(l) => {
                // a LINE's points are in world coordinates
                edges.push(DrawnEdge {
                    a: DVec2::new(l.p1.x, l.p1.y),
                    b: DVec2::new(l.p2.x, l.p2.y),
                    bulge: 0.0,
                    layer,
                    typed: true,
                });
            }
            EntityType::Arc(a) => {
                let s = plane(&a.normal, "ARC")?;
                let (t0, t1) = (a.start_angle.to_radians(), a.end_angle.to_radians());
                let mut sweep = (t1 - t0).rem_euclid(2.0 * PI);
                if sweep == 0.0 {
                    sweep = 2.0 * PI;
                }
                let c = DVec2::new(a.center.x, a.center.y);
                let at =
                    |t: f64| DVec2::new(s * (c.x + a.radius * t.cos()), c.y + a.radius * t.sin());
                if sweep >= 2.0 * PI - 1e-12 {
                    circles.push(DrawnCircle {
                        center: DVec2::new(s * c.x, c.y),
                        radius: a.radius,
                        layer,
                    });
                    continue;
                }
                edges.push(DrawnEdge {
                    a: at(t0),
                    b: at(t1),
                    bulge: s * (sweep / 4.0).tan(),
                    layer,
                    typed: false,
                });
            }
            EntityType::Circle(c) => {
                let s = plane(&c.normal, "CIRCLE")?;
                circles.push(DrawnCircle {
                    center: DVec2::new(s * c.center.x, c.center.y),
                    radius: c.radius,
                    layer,
                });
            }
            EntityType::LwPolyline(pl) => {
                let s = plane(&pl.extrusion_direction, "LWPOLYLINE")?;
                let pts: Vec<(DVec2, f64)> = pl
                    .vertices
                    .iter()
                    .map(|v| (DVec2::new(s * v.x, v.y), s * v.bulge))
                    .collect();
                polyline_edges(&pts, pl.is_closed(), &layer, &mut edges);
            }
            EntityType::Polyline(pl) => {
                let s = plane(&pl.normal, "POLYLINE")?;
                if pl.is_polyface_mesh() || pl.is_3d_polygon_mesh() {
                    *skipped.entry("POLYLINE mesh".into()).or_default() += 1;
                    continue;
                }
                let pts: Vec<(DVec2, f64)> = pl
                    .vertices()
                    .map(|v| (DVec2::new(s * v.location.x, v.location.y), s * v.bulge))
                    .collect();
                polyline_edges(&pts, pl.is_closed(), &layer, &mut edges);
            }
            other => {
                let kind = format!("{other:?}");
                let kind = kind
                    .split(|c: char| !c.is_alphanumeric())
                    .next()
                    .unwrap_or("entity")
                    .to_uppercase();
                *skipped.entry(kind).or_default() += 1;
            }
        }
    }
    for (i, e) in edges.iter().enumerate() {
        if !(e.a.is_finite() && e.b.is_finite() && e.bulge.is_finite()) {
            return Err(DxfError::Entity {
                path: path.to_string(),
                message: format!("edge {i} has a coordinate or bulge that is not a finite number"),
            });
        }
    }
    for c in &circles {
        if !(c.center.is_finite() && c.radius.is_finite() && c.radius > 0.0) {
            return Err(DxfError::Entity {
                path: path.to_string(),
                message: format!(
                    "a CIRCLE at ({}, {}) has radius {}: not a positive number",
                    c.center.x, c.center.y, c.radius
                ),
            });
        }
    }
    let warnings = skipped
        .into_iter()
        .map(|(kind, n)| format!("{path}: skipped {n} {kind} (not an outline entity)"))
        .collect();
    Ok((edges, circles, warnings))
}

/// The edges of a polyline's vertices (each with the bulge of the edge
/// that leaves it).
fn polyline_edges(pts: &[(DVec2, f64)], closed: bool, layer: &str, out: &mut Vec<DrawnEdge>) {
    let n = pts.len();
    let m = if closed { n } else { n.saturating_sub(1) };
    for i in 0..m {
        let (a, bulge) = pts[i];
        let (b, _) = pts[(i + 1) % n];
        out.push(DrawnEdge {
            a,
            b,
            bulge,
            layer: layer.to_string(),
            typed: true,
        });
    }
}

/// An edge of the joined drawing between two joined points.
#[derive(Debug, Clone)]
struct GraphEdge {
    ends: [usize; 2],
    /// From `ends[0]` to `ends[1]`.
    bulge: f64,
    layer: String,
}

/// An edge walked one way: (edge, forward).
type HalfEdge = (usize, bool);

/// The drawing's edges joined at their end points.
struct Graph {
    points: Vec<DVec2>,
    edges: Vec<GraphEdge>,
    /// The edges at each point.
    at: Vec<Vec<usize>>,
}

impl Graph {
    /// Joins end points within `tol`: typed points first, so that a
    /// computed end snaps onto a typed one.
    fn join(drawn: &[DrawnEdge], tol: f64) -> Graph {
        let mut ends: Vec<(DVec2, bool, usize, usize)> = Vec::new();
        for (i, e) in drawn.iter().enumerate() {
            ends.push((e.a, e.typed, i, 0));
            ends.push((e.b, e.typed, i, 1));
        }
        // typed first, then in file order: a stable sort keeps the order
        ends.sort_by_key(|e| !e.1);
        let cell = |p: DVec2| ((p.x / tol).floor() as i64, (p.y / tol).floor() as i64);
        let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        let mut points: Vec<DVec2> = Vec::new();
        let mut end_point = vec![[usize::MAX; 2]; drawn.len()];
        for &(p, _, i, side) in &ends {
            let (cx, cy) = cell(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for &q in grid.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                        if (points[q] - p).length() <= tol {
                            found = Some(q);
                            break 'search;
                        }
                    }
                }
            }
            let q = found.unwrap_or_else(|| {
                points.push(p);
                grid.entry((cx, cy)).or_default().push(points.len() - 1);
                points.len() - 1
            });
            end_point[i][side] = q;
        }
        let mut edges = Vec::new();
        // an edge drawn twice (CAD drawings often hold copies) counts once
        let mut seen = std::collections::HashSet::new();
        for (i, e) in drawn.iter().enumerate() {
            let ends = end_point[i];
            if ends[0] == ends[1] {
                continue; // shorter than the tolerance: a point
            }
            let key = if ends[0] < ends[1] {
                (ends[0], ends[1], (e.bulge + 0.0).to_bits())
            } else {
                (ends[1], ends[0], (0.0 - e.bulge).to_bits())
            };
            if !seen.insert(key) {
                continue;
            }
            edges.push(GraphEdge {
                ends,
                bulge: e.bulge,
                layer: e.layer.clone(),
            });
        }
        let mut at = vec![Vec::new(); points.len()];
        for (k, e) in edges.iter().enumerate() {
            at[e.ends[0]].push(k);
            at[e.ends[1]].push(k);
        }
        Graph { points, edges, at }
    }

    fn start(&self, h: HalfEdge) -> usize {
        self.edges[h.0].ends[if h.1 { 0 } else { 1 }]
    }

    fn end(&self, h: HalfEdge) -> usize {
        self.edges[h.0].ends[if h.1 { 1 } else { 0 }]
    }

    fn bulge(&self, h: HalfEdge) -> f64 {
        if h.1 {
            self.edges[h.0].bulge
        } else {
            // 0 - b, not -b: a straight edge stays 0, not -0
            0.0 - self.edges[h.0].bulge
        }
    }

    fn curve(&self, h: HalfEdge) -> Curve {
        let (a, b) = (self.points[self.start(h)], self.points[self.end(h)]);
        let bulge = self.bulge(h);
        if bulge == 0.0 {
            Curve::Line { a, b }
        } else {
            Curve::Arc { a, b, bulge }
        }
    }

    /// The direction in which a half-edge leaves its start (an arc's
    /// tangent: the chord turned by half the sweep, away from the bulge).
    fn leaving_angle(&self, h: HalfEdge) -> f64 {
        let d = self.points[self.end(h)] - self.points[self.start(h)];
        d.y.atan2(d.x) - 2.0 * self.bulge(h).atan()
    }

    /// Removes the chains that hang free (repeatedly, the edges at a
    /// point met by one active edge); returns them.
    fn prune_hanging(&self, active: &mut [bool]) -> Vec<usize> {
        let mut degree = vec![0usize; self.points.len()];
        for (k, e) in self.edges.iter().enumerate() {
            if active[k] {
                degree[e.ends[0]] += 1;
                degree[e.ends[1]] += 1;
            }
        }
        let mut queue: Vec<usize> = (0..self.points.len()).filter(|&p| degree[p] == 1).collect();
        let mut pruned = Vec::new();
        while let Some(p) = queue.pop() {
            if degree[p] != 1 {
                continue;
            }
            let Some(&k) = self.at[p].iter().find(|&&k| active[k]) else {
                continue;
            };
            active[k] = false;
            pruned.push(k);
            for &q in &self.edges[k].ends {
                degree[q] -= 1;
                if degree[q] == 1 {
                    queue.push(q);
                }
            }
        }
        pruned
    }

    /// The active edges in connected pieces, each in ascending order.
    fn components(&self, active: &[bool]) -> Vec<Vec<usize>> {
        let mut seen = vec![false; self.edges.len()];
        let mut out = Vec::new();
        for k0 in 0..self.edges.len() {
            if !active[k0] || seen[k0] {
                continue;
            }
            let mut comp = Vec::new();
            let mut stack = vec![k0];
            seen[k0] = true;
            while let Some(k) = stack.pop() {
                comp.push(k);
                for &p in &self.edges[k].ends {
                    for &j in &self.at[p] {
                        if active[j] && !seen[j] {
                            seen[j] = true;
                            stack.push(j);
                        }
                    }
                }
            }
            comp.sort_unstable();
            out.push(comp);
        }
        out
    }

    /// The walk round the outside of a connected piece (its unbounded
    /// face, clockwise): at each point the walk takes the sharpest left
    /// turn, which keeps the face on its left; of all the faces so
    /// walked, the outside is the one of negative area.
    fn outside_walk(&self, comp: &[usize], active: &[bool]) -> Vec<HalfEdge> {
        // the half-edges leaving each point, counter-clockwise by angle
        let mut leaving: HashMap<usize, Vec<(f64, HalfEdge)>> = HashMap::new();
        for &k in comp {
            for h in [(k, true), (k, false)] {
                leaving
                    .entry(self.start(h))
                    .or_default()
                    .push((self.leaving_angle(h), h));
            }
        }
        for v in leaving.values_mut() {
            v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        }
        let next = |h: HalfEdge| -> HalfEdge {
            let around = &leaving[&self.end(h)];
            let back = (h.0, !h.1);
            let i = around
                .iter()
                .position(|x| x.1 == back)
                .expect("the reverse half-edge leaves the end point");
            // the first one clockwise from the way back
            around[(i + around.len() - 1) % around.len()].1
        };
        let mut walked: std::collections::HashSet<HalfEdge> = Default::default();
        let mut best: Option<(f64, Vec<HalfEdge>)> = None;
        for &k in comp {
            debug_assert!(active[k]);
            for h0 in [(k, true), (k, false)] {
                if walked.contains(&h0) {
                    continue;
                }
                let mut face = Vec::new();
                let mut h = h0;
                loop {
                    walked.insert(h);
                    face.push(h);
                    h = next(h);
                    if h == h0 || face.len() > 2 * comp.len() {
                        break;
                    }
                }
                let area: f64 = face.iter().map(|&h| self.curve(h).signed_area_term()).sum();
                if best.as_ref().is_none_or(|b| area < b.0) {
                    best = Some((area, face));
                }
            }
        }
        best.map(|b| b.1).unwrap_or_default()
    }
}

/// Loops and line edges of a set of edges: hanging chains and chains
/// inside a loop are line edges, the outsides of the rest loops, and
/// what lies inside a loop is sorted the same way in turn.
fn loops_and_lines(
    g: &Graph,
    mut active: Vec<bool>,
    loops: &mut Vec<Vec<HalfEdge>>,
    lines: &mut Vec<usize>,
) {
    lines.extend(g.prune_hanging(&mut active));
    for comp in g.components(&active) {
        let walk = g.outside_walk(&comp, &active);
        let mut count: HashMap<usize, usize> = HashMap::new();
        for h in &walk {
            *count.entry(h.0).or_default() += 1;
        }
        // an edge walked both ways joins two loops: a line; the runs of
        // the walk between such edges are loops
        let once = |h: &HalfEdge| count[&h.0] == 1;
        let mut runs: Vec<Vec<HalfEdge>> = Vec::new();
        match walk.iter().position(|h| !once(h)) {
            None => runs.push(walk.clone()),
            Some(s) => {
                let mut run = Vec::new();
                for i in 0..walk.len() {
                    let h = walk[(s + i) % walk.len()];
                    if once(&h) {
                        run.push(h);
                    } else if !run.is_empty() {
                        runs.push(std::mem::take(&mut run));
                    }
                }
                if !run.is_empty() {
                    runs.push(run);
                }
            }
        }
        let mut inner = vec![false; g.edges.len()];
        for &k in &comp {
            inner[k] = true;
        }
        for h in &walk {
            if once(h) {
                inner[h.0] = false;
            }
        }
        loops.extend(runs);
        if inner.iter().any(|&x| x) {
            loops_and_lines(g, inner, loops, lines);
        }
    }
}

/// A fine polygon of a loop, for inside tests.
fn fine_polygon(curves: &[Curve]) -> Vec<DVec2> {
    let mut pts = Vec::new();
    for c in curves {
        let n = match *c {
            Curve::Line { .. } => 1,
            Curve::Arc { bulge, .. } => {
                ((4.0 * bulge.atan()).abs() / (PI / 64.0)).ceil().max(2.0) as usize
            }
            Curve::Circle { .. } => 128,
        };
        let p = c.divide(n);
        match c {
            Curve::Circle { .. } => pts.extend(p),
            _ => pts.extend(&p[..n]),
        }
    }
    pts
}

/// The outline of drawn edges and circles: `path` names the file in
/// messages.
pub fn outline_of(
    drawn: &[DrawnEdge],
    circles: &[DrawnCircle],
    path: &str,
) -> Result<Outline, DxfError> {
    let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
    for e in drawn {
        lo = lo.min(e.a).min(e.b);
        hi = hi.max(e.a).max(e.b);
    }
    for c in circles {
        lo = lo.min(c.center - c.radius);
        hi = hi.max(c.center + c.radius);
    }
    if drawn.is_empty() && circles.is_empty() {
        return Err(DxfError::Empty { path: path.into() });
    }
    let extent = (hi - lo)
        .max_element()
        .max(lo.abs().max_element() * 1e-9)
        .max(1e-300);
    let tol = JOIN_TOLERANCE * extent;
    let g = Graph::join(drawn, tol);
    let mut walks = Vec::new();
    let mut line_edges = Vec::new();
    loops_and_lines(&g, vec![true; g.edges.len()], &mut walks, &mut line_edges);

    // every loop, as curves, with its walk or circle
    enum Found {
        Walk(Vec<HalfEdge>),
        Circle(usize),
    }
    let mut found: Vec<(Vec<Curve>, Found)> = walks
        .into_iter()
        .map(|w| (w.iter().map(|&h| g.curve(h)).collect(), Found::Walk(w)))
        .collect();
    for (i, c) in circles.iter().enumerate() {
        found.push((
            vec![Curve::Circle {
                center: c.center,
                radius: c.radius,
            }],
            Found::Circle(i),
        ));
    }
    let lines = line_paths(
        &g,
        &line_edges,
        &found
            .iter()
            .filter_map(|f| match &f.1 {
                Found::Walk(w) => Some(w.as_slice()),
                Found::Circle(_) => None,
            })
            .collect::<Vec<_>>(),
    );

    let free_ends: Vec<usize> = (0..g.points.len())
        .filter(|&p| g.at[p].len() == 1)
        .collect();
    // the two nearest free ends, or (no two) a chain that is no loop
    let gap = |more: usize| -> DxfError {
        let mut best: Option<(f64, usize, usize)> = None;
        for (i, &p) in free_ends.iter().enumerate() {
            for &q in &free_ends[i + 1..] {
                let d = (g.points[p] - g.points[q]).length();
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, p, q));
                }
            }
        }
        match best {
            Some((distance, p, q)) => DxfError::Gap {
                path: path.into(),
                from: g.points[p],
                to: g.points[q],
                distance,
                tolerance: tol,
                more: if more > 1 {
                    format!(" ({more} open chains in all)")
                } else {
                    String::new()
                },
            },
            None => DxfError::Shape {
                path: path.into(),
                message: "no closed loop round the drawing".into(),
            },
        }
    };
    if found.is_empty() {
        return Err(gap(lines.len()));
    }
    let areas: Vec<f64> = found
        .iter()
        .map(|(c, _)| c.iter().map(Curve::signed_area_term).sum::<f64>())
        .collect();
    let outer = (0..found.len())
        .max_by(|&a, &b| areas[a].abs().total_cmp(&areas[b].abs()).then(b.cmp(&a)))
        .expect("a loop");
    let polygon = fine_polygon(&found[outer].0);
    for (i, (curves, _)) in found.iter().enumerate() {
        if i != outer && !point_in_polygon(curves[0].point_at(0.0), &polygon) {
            let p = curves[0].point_at(0.0);
            let q = found[outer].0[0].point_at(0.0);
            return Err(DxfError::Shape {
                path: path.into(),
                message: format!(
                    "two outlines side by side: the loop through ({}, {}) lies outside the loop through ({}, {})",
                    p.x, p.y, q.x, q.y
                ),
            });
        }
    }
    let outside = lines
        .iter()
        .filter(|l| {
            // a line lies inside when a point of it does: take the middle
            // of its first edge (its ends may lie on the loop)
            let a = DVec2::new(l.points[0][0], l.points[0][1]);
            let b = DVec2::new(l.points[1][0], l.points[1][1]);
            let bulge = l.bulges.as_ref().map_or(0.0, |b| b[0]);
            let first = if bulge == 0.0 {
                Curve::Line { a, b }
            } else {
                Curve::Arc { a, b, bulge }
            };
            !point_in_polygon(first.point_at(0.5), &polygon)
        })
        .count();
    if outside > 0 {
        return Err(gap(outside));
    }

    let to_loop = |i: usize, ccw: bool| -> Loop {
        match &found[i].1 {
            Found::Circle(c) => {
                let c = &circles[*c];
                Loop::Circle {
                    circle: Circle {
                        center: [c.center.x, c.center.y],
                        radius: c.radius,
                        tag: (!c.layer.is_empty()).then(|| c.layer.clone()),
                    },
                }
            }
            Found::Walk(w) => {
                let mut w = w.clone();
                if (areas[i] > 0.0) != ccw {
                    w = w.iter().rev().map(|&(k, f)| (k, !f)).collect();
                }
                // start at the lowest point (then leftmost)
                let s = (0..w.len())
                    .min_by(|&a, &b| {
                        let (p, q) = (g.points[g.start(w[a])], g.points[g.start(w[b])]);
                        p.y.total_cmp(&q.y).then(p.x.total_cmp(&q.x))
                    })
                    .unwrap_or(0);
                w.rotate_left(s);
                Loop::Polyline(polyline_of(&g, &w, false))
            }
        }
    };
    let holes = (0..found.len())
        .filter(|&i| i != outer)
        .map(|i| to_loop(i, false))
        .collect();
    Ok(Outline {
        outer: to_loop(outer, true),
        holes,
        lines,
        tolerance: tol,
        warnings: Vec::new(),
    })
}

/// The polyline of a walk; `open` adds the last end point.
fn polyline_of(g: &Graph, walk: &[HalfEdge], open: bool) -> Polyline {
    let mut points: Vec<[f64; 2]> = walk
        .iter()
        .map(|&h| g.points[g.start(h)].to_array())
        .collect();
    if open {
        if let Some(&h) = walk.last() {
            points.push(g.points[g.end(h)].to_array());
        }
    }
    let bulges: Vec<f64> = walk.iter().map(|&h| g.bulge(h)).collect();
    let tags: Vec<String> = walk.iter().map(|&h| g.edges[h.0].layer.clone()).collect();
    Polyline {
        points,
        bulges: bulges.iter().any(|&b| b != 0.0).then_some(bulges),
        tags: tags.iter().any(|t| !t.is_empty()).then_some(tags),
    }
}

/// The line edges as paths: a path runs on through a point met by two
/// line edges and by no loop, and stops anywhere else.
fn line_paths(g: &Graph, line_edges: &[usize], loops: &[&[HalfEdge]]) -> Vec<Polyline> {
    let mut is_line = vec![false; g.edges.len()];
    for &k in line_edges {
        is_line[k] = true;
    }
    let mut on_loop = vec![false; g.points.len()];
    for w in loops {
        for &h in *w {
            on_loop[g.start(h)] = true;
        }
    }
    let line_degree = |p: usize| g.at[p].iter().filter(|&&k| is_line[k]).count();
    let through = |p: usize| !on_loop[p] && line_degree(p) == 2;
    let mut used = vec![false; g.edges.len()];
    let mut paths = Vec::new();
    let walk_from = |p0: usize, k0: usize, used: &mut Vec<bool>| -> Vec<HalfEdge> {
        let mut path = Vec::new();
        let (mut p, mut k) = (p0, k0);
        loop {
            used[k] = true;
            let h = (k, g.edges[k].ends[0] == p);
            path.push(h);
            p = g.end(h);
            if !through(p) {
                break;
            }
            match g.at[p].iter().find(|&&j| is_line[j] && !used[j]) {
                Some(&j) => k = j,
                None => break,
            }
        }
        path
    };
    // from the ends first (in point order), then what is left: rings of
    // line edges alone
    for p in 0..g.points.len() {
        if through(p) {
            continue;
        }
        for &k in &g.at[p] {
            if is_line[k] && !used[k] {
                paths.push(walk_from(p, k, &mut used));
            }
        }
    }
    for &k in line_edges {
        if !used[k] {
            paths.push(walk_from(g.edges[k].ends[0], k, &mut used));
        }
    }
    paths
        .into_iter()
        .map(|mut path| {
            // start at the lower (then left) end
            let (a, b) = (
                g.points[g.start(path[0])],
                g.points[g.end(path[path.len() - 1])],
            );
            if b.y.total_cmp(&a.y).then(b.x.total_cmp(&a.x)).is_lt() {
                path = path.iter().rev().map(|&(k, f)| (k, !f)).collect();
            }
            polyline_of(g, &path, true)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(a: [f64; 2], b: [f64; 2], layer: &str) -> DrawnEdge {
        DrawnEdge {
            a: DVec2::from(a),
            b: DVec2::from(b),
            bulge: 0.0,
            layer: layer.into(),
            typed: true,
        }
    }

    #[test]
    fn four_lines_in_any_order_and_direction_and_a_copy_make_one_counter_clockwise_loop() {
        let edges = [
            line([10.0, 5.0], [10.0, 0.0], "right"),
            line([0.0, 0.0], [10.0, 0.0], "bottom"),
            line([0.0, 5.0], [0.0, 0.0], ""),
            line([0.0, 5.0], [10.0, 5.0], "top"),
        ];
        let mut edges = edges.to_vec();
        // the bottom drawn again, the other way
        edges.push(line([10.0, 0.0], [0.0, 0.0], "bottom"));
        let o = outline_of(&edges, &[], "t.dxf").unwrap();
        assert_eq!(
            o.outer,
            Loop::Polyline(Polyline {
                points: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]],
                bulges: None,
                tags: Some(vec![
                    "bottom".into(),
                    "right".into(),
                    "top".into(),
                    "".into()
                ]),
            })
        );
        assert!(o.holes.is_empty() && o.lines.is_empty());
    }

    #[test]
    fn end_points_within_the_tolerance_join_and_a_typed_point_wins() {
        let mut arc = line([10.0 + 1e-7, 0.0], [10.0, 5.0], "");
        arc.typed = false;
        arc.bulge = 0.1;
        let edges = [
            line([0.0, 0.0], [10.0, 0.0], ""),
            arc,
            line([10.0, 5.0], [0.0, 0.0], ""),
        ];
        let o = outline_of(&edges, &[], "t.dxf").unwrap();
        let Loop::Polyline(p) = &o.outer else {
            panic!()
        };
        assert_eq!(p.points, vec![[0.0, 0.0], [10.0, 0.0], [10.0, 5.0]]);
        assert_eq!(p.bulges, Some(vec![0.0, 0.1, 0.0]));
    }

    #[test]
    fn an_outline_with_a_gap_names_the_gap() {
        let edges = [
            line([0.0, 0.0], [10.0, 0.0], ""),
            line([10.0, 0.0], [10.0, 5.0], ""),
            line([10.0, 5.0], [0.0, 5.0], ""),
            line([0.0, 5.0], [0.0, 0.01], ""),
        ];
        let e = outline_of(&edges, &[], "t.dxf").unwrap_err().to_string();
        assert!(
            e.starts_with("t.dxf: the outline does not close: a gap between (0, 0) and (0, 0.01), 1.000000e-2 apart"),
            "{e}"
        );
    }

    #[test]
    fn a_circle_inside_is_a_hole_and_a_hanging_chain_a_line() {
        let edges = [
            line([0.0, 0.0], [10.0, 0.0], ""),
            line([10.0, 0.0], [10.0, 5.0], ""),
            line([10.0, 5.0], [0.0, 5.0], ""),
            line([0.0, 5.0], [0.0, 0.0], ""),
            // an edge crack from the bottom edge's corner inward, in two
            line([0.0, 0.0], [1.0, 1.0], "crack"),
            line([1.0, 1.0], [2.0, 1.0], "crack"),
        ];
        let circles = [DrawnCircle {
            center: DVec2::new(6.0, 2.5),
            radius: 1.0,
            layer: "bore".into(),
        }];
        let o = outline_of(&edges, &circles, "t.dxf").unwrap();
        assert_eq!(o.holes.len(), 1);
        assert!(
            matches!(&o.holes[0], Loop::Circle { circle } if circle.tag.as_deref() == Some("bore"))
        );
        assert_eq!(o.lines.len(), 1);
        assert_eq!(o.lines[0].points, vec![[0.0, 0.0], [1.0, 1.0], [2.0, 1.0]]);
    }

    #[test]
    fn a_line_across_the_loop_is_a_line_and_a_loop_joined_by_a_line_a_hole() {
        let edges = [
            line([0.0, 0.0], [10.0, 0.0], ""),
            line([10.0, 0.0], [10.0, 5.0], ""),
            line([10.0, 5.0], [0.0, 5.0], ""),
            line([0.0, 5.0], [0.0, 0.0], ""),
            // a partition from the bottom to the top
            line([4.0, 0.0], [4.0, 5.0], "interface"),
            // a square hole joined to the right side by a line
            line([6.0, 2.0], [8.0, 2.0], ""),
            line([8.0, 2.0], [8.0, 3.0], ""),
            line([8.0, 3.0], [6.0, 3.0], ""),
            line([6.0, 3.0], [6.0, 2.0], ""),
            line([8.0, 2.0], [10.0, 2.0], "tie"),
        ];
        // the bottom and top edges are split where the partition meets them
        let mut edges = edges.to_vec();
        edges[0] = line([0.0, 0.0], [4.0, 0.0], "");
        edges.push(line([4.0, 0.0], [10.0, 0.0], ""));
        edges[2] = line([10.0, 5.0], [4.0, 5.0], "");
        edges.push(line([4.0, 5.0], [0.0, 5.0], ""));
        edges[1] = line([10.0, 0.0], [10.0, 2.0], "");
        edges.push(line([10.0, 2.0], [10.0, 5.0], ""));
        let o = outline_of(&edges, &[], "t.dxf").unwrap();
        let Loop::Polyline(outer) = &o.outer else {
            panic!()
        };
        assert_eq!(outer.points.len(), 7);
        assert_eq!(o.holes.len(), 1);
        let Loop::Polyline(hole) = &o.holes[0] else {
            panic!()
        };
        assert_eq!(
            hole.points,
            vec![[6.0, 2.0], [6.0, 3.0], [8.0, 3.0], [8.0, 2.0]]
        );
        let mut lines: Vec<_> = o.lines.iter().map(|l| l.points.clone()).collect();
        lines.sort_by(|a, b| a[0][0].total_cmp(&b[0][0]));
        assert_eq!(
            lines,
            vec![vec![[4.0, 0.0], [4.0, 5.0]], vec![[8.0, 2.0], [10.0, 2.0]]]
        );
    }

    #[test]
    fn an_arc_seen_from_below_is_mirrored_and_turns_the_other_way() {
        use ::dxf::entities::{Arc, Entity, EntityType};
        let mut drawing = ::dxf::Drawing::new();
        let mut arc = Arc::new(::dxf::Point::new(0.0, 0.0, 0.0), 1.0, 0.0, 90.0);
        arc.normal = ::dxf::Vector::new(0.0, 0.0, -1.0);
        drawing.add_entity(Entity::new(EntityType::Arc(arc)));
        let (edges, _, _) = drawn_geometry(&drawing, "t.dxf").unwrap();
        // from (-1, 0) clockwise (seen from above) to (0, 1)
        assert!((edges[0].a - DVec2::new(-1.0, 0.0)).length() < 1e-15);
        assert!((edges[0].b - DVec2::new(0.0, 1.0)).length() < 1e-15);
        assert!((edges[0].bulge + (PI / 8.0).tan()).abs() < 1e-15);
        assert!(!edges[0].typed);
    }

    #[test]
    fn flat_arrays_go_on_one_line_and_strings_are_left_alone() {
        let v = serde_json::json!({"a": [[0.0, 1.5], [2.0, 3.0]], "t": ["x, [y]", "\"q\""]});
        let text = serde_json::to_string_pretty(&v).unwrap();
        assert_eq!(
            one_line_flat_arrays(&text),
            "{\n  \"a\": [\n    [0.0, 1.5],\n    [2.0, 3.0]\n  ],\n  \"t\": [\"x, [y]\", \"\\\"q\\\"\"]\n}"
        );
    }

    #[test]
    fn a_drawing_of_points_only_has_no_loop() {
        let edges = [line([1.0, 1.0], [1.0, 1.0], "")];
        let e = outline_of(&edges, &[], "t.dxf").unwrap_err().to_string();
        assert_eq!(e, "t.dxf: no closed loop round the drawing");
    }

    #[test]
    fn two_loops_side_by_side_are_refused() {
        let sq = |x: f64| {
            vec![
                line([x, 0.0], [x + 1.0, 0.0], ""),
                line([x + 1.0, 0.0], [x + 1.0, 1.0], ""),
                line([x + 1.0, 1.0], [x, 1.0], ""),
                line([x, 1.0], [x, 0.0], ""),
            ]
        };
        let mut edges = sq(0.0);
        edges.extend(sq(3.0));
        let e = outline_of(&edges, &[], "t.dxf").unwrap_err().to_string();
        assert!(e.contains("two outlines side by side"), "{e}");
    }
}
