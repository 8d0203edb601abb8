//! The input domain: loops of straight edges and arcs, circles, holes and
//! inner lines, read from the JSON format of `domain-format.md` and
//! validated before anything is meshed.

use glam::DVec2;
use serde_json::Value;
use std::f64::consts::PI;

use crate::geometry::{segments_intersect, SegmentRelation};

/// Largest |bulge| accepted: beyond it an arc is a numerical circle of
/// almost infinite radius (domain format, "Errors").
pub const MAX_BULGE: f64 = 1e6;
/// Largest fixed segment count on one edge, and the largest number of
/// boundary segments a domain may have, so that absurd inputs are refused
/// instead of exhausting memory.
pub const MAX_BOUNDARY_SEGMENTS: usize = 2_000_000;

/// The most elements a run may be asked for: a domain whose area over
/// size squared (its element count at that size) is larger is refused
/// before meshing, with the estimate.
pub const MAX_ELEMENTS: usize = 5_000_000;

/// An error in a domain file: names the key, loop, edge or point at fault.
#[derive(Debug, thiserror::Error)]
pub enum DomainError {
    /// The file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What the system said (as text: an error chain would repeat it).
        message: String,
    },
    /// The text is not JSON.
    #[error("{path}: not valid JSON: {message}")]
    Json {
        /// The file.
        path: String,
        /// What the JSON parser said, with line and column.
        message: String,
    },
    /// A key is missing, has the wrong type or an invalid value.
    #[error("{key}: {message}")]
    Key {
        /// The key path, e.g. `holes[1].points[2]`.
        key: String,
        /// What is wrong with it.
        message: String,
    },
    /// The geometry is not a valid domain (crossing loops, odd total...).
    #[error("{0}")]
    Geometry(String),
    /// Keys the format does not know, each with where it is and the key
    /// probably meant: refused, since a misspelt `holes` would silently
    /// drop the holes.
    #[error("unknown {}: {}", if .0.len() == 1 { "key" } else { "keys" }, .0.join(", "))]
    UnknownKeys(Vec<String>),
}

fn key_err(key: &str, message: impl Into<String>) -> DomainError {
    DomainError::Key {
        key: key.to_string(),
        message: message.into(),
    }
}

use super::curves::{
    chain_vertices, input_decimals, line_end, meeting_point, point_text, second_meeting,
    set_line_end, split_curve,
};
pub use super::curves::{Chain, Curve, Edge};
use super::keys::unknown_keys;

/// A validated domain: the only ways to make one are the constructors,
/// [`Domain::from_file`], [`Domain::from_json_str`] and
/// [`Domain::from_json`], which check it as the domain format says (keys
/// and values, loops of at least three points, nothing crossing, holes and
/// lines inside), so every `Domain` the mesher sees has passed them. The
/// fixed segment counts' parity is checked where the boundary is
/// discretised, at the run's size. Its parts are read through accessors.
///
/// ```compile_fail
/// // a hand-built domain does not compile: the fields are private
/// let d = freemesh::Domain { name: "x".into(), size: 1.0, max_size: None,
///     outer: todo!(), holes: vec![], lines: vec![], tags: vec![] };
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    /// Free text name.
    pub(crate) name: String,
    /// Target boundary segment length.
    pub(crate) size: f64,
    /// Largest interior element edge, if bounded.
    pub(crate) max_size: Option<f64>,
    /// The outer loop.
    pub(crate) outer: Chain,
    /// Holes.
    pub(crate) holes: Vec<Chain>,
    /// Inner lines (open). A line may start or end on a loop or on another
    /// line (format 1.1): such a point is a vertex of both (an edge it
    /// lands in the middle of is split there when the domain is read).
    pub(crate) lines: Vec<Chain>,
    /// The edge tags' names, in order of first appearance (outer, holes,
    /// lines, edge by edge); `Edge::tag` indexes this.
    pub(crate) tags: Vec<String>,
}

fn num(v: &Value, key: &str) -> Result<f64, DomainError> {
    let x = v
        .as_f64()
        .ok_or_else(|| key_err(key, "expected a number"))?;
    if !x.is_finite() {
        return Err(key_err(key, "must be finite"));
    }
    Ok(x)
}

fn positive(v: &Value, key: &str) -> Result<f64, DomainError> {
    let x = num(v, key)?;
    if x <= 0.0 {
        return Err(key_err(key, format!("must be positive, got {x}")));
    }
    Ok(x)
}

fn point(v: &Value, key: &str) -> Result<DVec2, DomainError> {
    let arr = v
        .as_array()
        .ok_or_else(|| key_err(key, "expected a point [x, y]"))?;
    if arr.len() != 2 {
        return Err(key_err(
            key,
            format!("expected a point [x, y], got {} numbers", arr.len()),
        ));
    }
    Ok(DVec2::new(
        num(&arr[0], &format!("{key}[0]"))?,
        num(&arr[1], &format!("{key}[1]"))?,
    ))
}

fn segment_count(v: &Value, key: &str) -> Result<Option<usize>, DomainError> {
    if v.is_null() {
        return Ok(None);
    }
    let n = v
        .as_f64()
        .ok_or_else(|| key_err(key, "expected a whole number"))?;
    if !n.is_finite() || n < 0.0 || n.fract() != 0.0 {
        return Err(key_err(
            key,
            format!("expected a whole number >= 0, got {n}"),
        ));
    }
    if n > MAX_BOUNDARY_SEGMENTS as f64 {
        return Err(key_err(
            key,
            format!("{n} segments is above the limit of {MAX_BOUNDARY_SEGMENTS}"),
        ));
    }
    Ok(if n == 0.0 { None } else { Some(n as usize) })
}

/// An edge's tag: a string (`""` or null: none), interned in `tags`.
fn tag(v: &Value, key: &str, tags: &mut Vec<String>) -> Result<Option<u32>, DomainError> {
    match v {
        Value::Null => Ok(None),
        Value::String(s) if s.is_empty() => Ok(None),
        Value::String(s) => Ok(Some(match tags.iter().position(|t| t == s) {
            Some(i) => i as u32,
            None => {
                tags.push(s.clone());
                (tags.len() - 1) as u32
            }
        })),
        _ => Err(key_err(key, "expected a string (the edge's tag)")),
    }
}

fn chain(v: &Value, key: &str, closed: bool, tags: &mut Vec<String>) -> Result<Chain, DomainError> {
    let obj = v
        .as_object()
        .ok_or_else(|| key_err(key, "expected an object with \"points\" or \"circle\""))?;
    let crack = match obj.get("crack") {
        None | Some(Value::Null) | Some(Value::Bool(false)) => false,
        Some(Value::Bool(true)) if !closed => true,
        Some(Value::Bool(true)) => {
            return Err(key_err(
                &format!("{key}.crack"),
                "only an inner line can be a crack",
            ))
        }
        Some(_) => return Err(key_err(&format!("{key}.crack"), "expected true or false")),
    };
    if let Some(c) = obj.get("circle") {
        if !closed {
            return Err(key_err(key, "an inner line cannot be a circle"));
        }
        if obj.get("tags").is_some_and(|t| !t.is_null()) {
            return Err(key_err(
                &format!("{key}.tags"),
                "a circle takes its tag as circle.tag",
            ));
        }
        let ck = format!("{key}.circle");
        let co = c
            .as_object()
            .ok_or_else(|| key_err(&ck, "expected an object"))?;
        let center = point(
            co.get("center")
                .ok_or_else(|| key_err(&ck, "missing key \"center\""))?,
            &format!("{ck}.center"),
        )?;
        let radius = positive(
            co.get("radius")
                .ok_or_else(|| key_err(&ck, "missing key \"radius\""))?,
            &format!("{ck}.radius"),
        )?;
        let segments = match co.get("segments") {
            Some(s) => segment_count(s, &format!("{ck}.segments"))?,
            None => None,
        };
        if segments.is_some_and(|n| n < 3) {
            return Err(key_err(
                &format!("{ck}.segments"),
                "a circle needs at least 3 segments",
            ));
        }
        let tag = match co.get("tag") {
            Some(t) => tag(t, &format!("{ck}.tag"), tags)?,
            None => None,
        };
        return Ok(Chain {
            edges: vec![Edge {
                curve: Curve::Circle { center, radius },
                segments,
                tag,
            }],
            label: key.to_string(),
            crack: false,
        });
    }
    let pk = format!("{key}.points");
    let pts = obj
        .get("points")
        .ok_or_else(|| key_err(key, "missing key \"points\" (or \"circle\")"))?
        .as_array()
        .ok_or_else(|| key_err(&pk, "expected an array of points"))?;
    let min = if closed { 3 } else { 2 };
    if pts.len() < min {
        return Err(key_err(
            &pk,
            format!("needs at least {min} points, got {}", pts.len()),
        ));
    }
    let points: Vec<DVec2> = pts
        .iter()
        .enumerate()
        .map(|(i, p)| point(p, &format!("{pk}[{i}]")))
        .collect::<Result<_, _>>()?;
    let m = if closed {
        points.len()
    } else {
        points.len() - 1
    };
    let per_edge = |name: &str| -> Result<Vec<Value>, DomainError> {
        match obj.get(name) {
            None | Some(Value::Null) => Ok(vec![Value::Null; m]),
            Some(Value::Array(a)) => {
                if a.len() != m {
                    return Err(key_err(
                        &format!("{key}.{name}"),
                        format!("expected {m} entries (one per edge), got {}", a.len()),
                    ));
                }
                Ok(a.clone())
            }
            Some(_) => Err(key_err(&format!("{key}.{name}"), "expected an array")),
        }
    };
    let bulges = per_edge("bulges")?;
    let counts = per_edge("segments")?;
    let edge_tags = per_edge("tags")?;
    let mut edges = Vec::with_capacity(m);
    for i in 0..m {
        let a = points[i];
        let b = points[(i + 1) % points.len()];
        if (b - a).length() <= 1e-12 * (1.0 + a.length()) {
            return Err(key_err(
                &format!("{key} edge {i}"),
                format!("zero-length edge from point {i} ({}, {})", a.x, a.y),
            ));
        }
        let bk = format!("{key}.bulges[{i}]");
        let bulge = if bulges[i].is_null() {
            0.0
        } else {
            num(&bulges[i], &bk)?
        };
        if bulge.abs() > MAX_BULGE {
            return Err(key_err(
                &bk,
                format!("|bulge| {bulge} is above {MAX_BULGE}"),
            ));
        }
        let curve = if bulge == 0.0 {
            Curve::Line { a, b }
        } else {
            Curve::Arc { a, b, bulge }
        };
        let segments = segment_count(&counts[i], &format!("{key}.segments[{i}]"))?;
        let tag = tag(&edge_tags[i], &format!("{key}.tags[{i}]"), tags)?;
        edges.push(Edge {
            curve,
            segments,
            tag,
        });
    }
    Ok(Chain {
        edges,
        label: key.to_string(),
        crack,
    })
}

/// The JSON of a domain file's text (`path` names it in an error), a
/// byte-order mark first read past (editors on Windows write one).
fn json_of(text: &str, path: &str) -> Result<Value, DomainError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).map_err(|e| DomainError::Json {
        path: path.to_string(),
        message: e.to_string(),
    })
}

impl Domain {
    /// Reads and validates a domain file.
    pub fn from_file(path: &str) -> Result<Domain, DomainError> {
        let text = std::fs::read_to_string(path).map_err(|e| DomainError::Io {
            path: path.to_string(),
            message: e.to_string(),
        })?;
        Domain::from_json(&json_of(&text, path)?)
    }

    /// Reads and validates a domain from the text of a domain file (the
    /// JSON format of `domain-format.md`).
    ///
    /// ```
    /// let d = freemesh::Domain::from_json_str(
    ///     r#"{"size": 0.5, "outer": {"points": [[0,0],[2,0],[2,1],[0,1]]}}"#,
    /// ).unwrap();
    /// assert_eq!(d.size(), 0.5);
    /// assert_eq!(d.area(), 2.0);
    /// // a domain that fails a check is an error, never a Domain
    /// assert!(freemesh::Domain::from_json_str(r#"{"size": -1}"#).is_err());
    /// // a byte-order mark first is read past
    /// assert!(freemesh::Domain::from_json_str(
    ///     "\u{feff}{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[2,0],[2,1],[0,1]]}}",
    /// )
    /// .is_ok());
    /// ```
    pub fn from_json_str(text: &str) -> Result<Domain, DomainError> {
        Domain::from_json(&json_of(text, "(text)")?)
    }

    /// Builds and validates a domain from parsed JSON.
    pub fn from_json(v: &Value) -> Result<Domain, DomainError> {
        let obj = v
            .as_object()
            .ok_or_else(|| key_err("(top level)", "expected a JSON object"))?;
        // first: a misspelt key explains the missing one better than
        // "size: missing key" would
        let unknown = unknown_keys(v);
        if !unknown.is_empty() {
            return Err(DomainError::UnknownKeys(unknown));
        }
        let name = match obj.get("name") {
            None | Some(Value::Null) => "domain".to_string(),
            Some(Value::String(s)) => s.clone(),
            Some(_) => return Err(key_err("name", "expected a string")),
        };
        let size = positive(
            obj.get("size")
                .ok_or_else(|| key_err("size", "missing key"))?,
            "size",
        )?;
        let max_size = match obj.get("max_size") {
            None | Some(Value::Null) => None,
            Some(x) => Some(positive(x, "max_size")?),
        };
        if let Some(max_size) = max_size.filter(|&m| m < size) {
            return Err(key_err(
                "max_size",
                format!("{max_size} is below size {size}"),
            ));
        }
        let mut tags = Vec::new();
        let outer = chain(
            obj.get("outer")
                .ok_or_else(|| key_err("outer", "missing key"))?,
            "outer",
            true,
            &mut tags,
        )?;
        let list = |k: &str| -> Result<Vec<Value>, DomainError> {
            match obj.get(k) {
                None | Some(Value::Null) => Ok(vec![]),
                Some(Value::Array(a)) => Ok(a.clone()),
                Some(_) => Err(key_err(k, "expected an array")),
            }
        };
        let holes = list("holes")?
            .iter()
            .enumerate()
            .map(|(i, h)| chain(h, &format!("holes[{i}]"), true, &mut tags))
            .collect::<Result<Vec<_>, _>>()?;
        let lines = list("lines")?
            .iter()
            .enumerate()
            .map(|(i, l)| chain(l, &format!("lines[{i}]"), false, &mut tags))
            .collect::<Result<Vec<_>, _>>()?;
        let mut d = Domain {
            name,
            size,
            max_size,
            outer,
            holes,
            lines,
            tags,
        };
        d.attach_line_ends()?;
        d.check_geometry()?;
        Ok(d)
    }

    /// Its name (`"domain"` when the file gives none).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The target boundary segment length.
    pub fn size(&self) -> f64 {
        self.size
    }

    /// The largest interior element edge, if the file bounds it.
    pub fn max_size(&self) -> Option<f64> {
        self.max_size
    }

    /// The number of holes.
    pub fn hole_count(&self) -> usize {
        self.holes.len()
    }

    /// The area meshed: inside the outer loop, outside the holes (arcs
    /// exactly, not their chords).
    pub fn area(&self) -> f64 {
        self.outer.signed_area().abs()
            - self
                .holes
                .iter()
                .map(|h| h.signed_area().abs())
                .sum::<f64>()
    }

    /// All chains: outer first, then holes, then lines.
    pub fn chains(&self) -> impl Iterator<Item = &Chain> {
        std::iter::once(&self.outer)
            .chain(self.holes.iter())
            .chain(self.lines.iter())
    }

    /// A fine polyline of each chain, for the geometric checks: arcs are cut
    /// into short chords whose sagitta is far below the model scale.
    fn fine_polyline(c: &Chain, closed: bool) -> Vec<DVec2> {
        let mut pts = Vec::new();
        for e in &c.edges {
            let n = match e.curve {
                Curve::Line { .. } => 1,
                Curve::Arc { bulge, .. } => {
                    ((4.0 * bulge.atan()).abs() / (PI / 64.0)).ceil().max(2.0) as usize
                }
                Curve::Circle { .. } => 128,
            };
            let p = e.curve.divide(n);
            match e.curve {
                Curve::Circle { .. } => pts.extend(p),
                _ => pts.extend(&p[..n]),
            }
        }
        if !closed {
            if let Some(last) = c.edges.last() {
                pts.push(last.curve.point_at(1.0));
            }
        }
        pts
    }

    /// The size of the outer loop's bounding box: the model's scale.
    pub fn scale(&self) -> f64 {
        let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
        for p in Self::fine_polyline(&self.outer, true) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (hi - lo).max_element()
    }

    /// How near a line's end must come to a loop or another line to end
    /// on it: a millionth of the model's scale (coordinates written with
    /// six decimals end on a slanted edge).
    pub fn tolerance(&self) -> f64 {
        1e-6 * self.scale()
    }

    /// The end points of the lines that end on a loop or another line
    /// (partitions, edge cracks, T-junctions): each is a vertex of both.
    pub fn junctions(&self) -> Vec<DVec2> {
        let vertices: Vec<(usize, DVec2)> = self
            .chains()
            .enumerate()
            .flat_map(|(ci, c)| chain_vertices(c).into_iter().map(move |v| (ci, v)))
            .collect();
        let first_line = 1 + self.holes.len();
        let mut out: Vec<DVec2> = Vec::new();
        for (li, l) in self.lines.iter().enumerate() {
            let ends = chain_vertices(l);
            for end in [ends[0], ends[ends.len() - 1]] {
                let shared = vertices
                    .iter()
                    .any(|&(ci, v)| ci != first_line + li && v == end);
                if shared && !out.contains(&end) {
                    out.push(end);
                }
            }
        }
        out
    }

    /// Whether two touching segments of different chains meet only at a
    /// common end that is a junction (a line's end on a loop or line).
    fn meet_at_a_line_end(&self, p1: DVec2, p2: DVec2, q1: DVec2, q2: DVec2) -> bool {
        let shared = [p1, p2].into_iter().find(|&p| p == q1 || p == q2);
        let Some(s) = shared else { return false };
        self.lines.iter().any(|l| {
            let ends = chain_vertices(l);
            s == ends[0] || s == ends[ends.len() - 1]
        })
    }

    /// Makes every line end that lies on a loop or on another line (within
    /// `tolerance`) a vertex of it: snapped to a vertex it is that near, or
    /// else the edge it lands on is split there (the line stays as it is
    /// written, the edge bends by at most the tolerance).
    fn attach_line_ends(&mut self) -> Result<(), DomainError> {
        if self.lines.is_empty() {
            return Ok(());
        }
        let tol = self.tolerance();
        let first_line = 1 + self.holes.len();
        let n_chains = first_line + self.lines.len();
        for li in 0..self.lines.len() {
            for at_end in [false, true] {
                let line = &self.lines[li];
                let mut p = line_end(line, at_end);
                for ci in 0..n_chains {
                    if ci == first_line + li {
                        continue;
                    }
                    let other = self.chain_mut(ci);
                    if let Some(v) = chain_vertices(other)
                        .into_iter()
                        .find(|v| (*v - p).length() <= tol)
                    {
                        p = v;
                        set_line_end(&mut self.lines[li], at_end, v);
                        continue;
                    }
                    let Some(ei) = other
                        .edges
                        .iter()
                        .position(|e| (e.curve.project(p) - p).length() <= tol)
                    else {
                        continue;
                    };
                    let label = other.label.clone();
                    let e = other.edges[ei];
                    let (c1, c2) = split_curve(e.curve, p);
                    let (n1, n2) = match e.segments {
                        None => (None, None),
                        Some(n) if n < 2 => {
                            return Err(DomainError::Geometry(format!(
                                "{} ends in the middle of {label} edge {ei}, whose one fixed segment leaves no node there",
                                self.lines[li].label
                            )))
                        }
                        Some(n) => {
                            let share = c1.length() / (c1.length() + c2.length());
                            let k = ((n as f64 * share).round() as usize).clamp(1, n - 1);
                            (Some(k), Some(n - k))
                        }
                    };
                    let other = self.chain_mut(ci);
                    other.edges[ei] = Edge {
                        curve: c1,
                        segments: n1,
                        tag: e.tag,
                    };
                    other.edges.insert(
                        ei + 1,
                        Edge {
                            curve: c2,
                            segments: n2,
                            tag: e.tag,
                        },
                    );
                }
            }
        }
        Ok(())
    }

    fn chain_mut(&mut self, ci: usize) -> &mut Chain {
        let first_line = 1 + self.holes.len();
        if ci == 0 {
            &mut self.outer
        } else if ci < first_line {
            &mut self.holes[ci - 1]
        } else {
            &mut self.lines[ci - first_line]
        }
    }

    /// Edges that follow each other meet only at their shared point: the
    /// exact test, since an arc may cross the edge before it within its
    /// first polyline chord.
    fn check_consecutive_edges(&self, tol: f64, decimals: usize) -> Result<(), DomainError> {
        let chains = std::iter::once((&self.outer, true))
            .chain(self.holes.iter().map(|h| (h, true)))
            .chain(self.lines.iter().map(|l| (l, false)));
        for (chain, closed) in chains {
            let n = chain.edges.len();
            let pairs = if closed { n } else { n.saturating_sub(1) };
            for i in 0..pairs {
                let (first, second) = (&chain.edges[i].curve, &chain.edges[(i + 1) % n].curve);
                let Some(p) = second_meeting(first, second, tol) else {
                    continue;
                };
                // a loop of two edges: they meet again at its other vertex
                if closed && n == 2 && (p - first.point_at(0.0)).length() <= tol {
                    continue;
                }
                let what = if closed {
                    "the loop intersects itself"
                } else {
                    "the line crosses itself"
                };
                // where: the two edges, and how far from the point they
                // share (a cusp drawn a little past its tip, most often)
                let (j, shared) = ((i + 1) % n, second.point_at(0.0));
                return Err(DomainError::Geometry(format!(
                    "{}: {what} {}: edges {i} and {j} meet again {:.decimals$} from point {j} {}, where they join",
                    chain.label,
                    point_text(p, decimals),
                    (p - shared).length(),
                    point_text(shared, decimals)
                )));
            }
        }
        Ok(())
    }

    fn check_geometry(&self) -> Result<(), DomainError> {
        let polys: Vec<(String, Vec<DVec2>, bool)> = std::iter::once((
            self.outer.label.clone(),
            Self::fine_polyline(&self.outer, true),
            true,
        ))
        .chain(
            self.holes
                .iter()
                .map(|h| (h.label.clone(), Self::fine_polyline(h, true), true)),
        )
        .chain(
            self.lines
                .iter()
                .map(|l| (l.label.clone(), Self::fine_polyline(l, false), false)),
        )
        .collect();
        let scale = {
            let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
            for p in &polys[0].1 {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
            (hi - lo).max_element()
        };
        // Segments of every chain, checked pairwise through a coarse grid so
        // that large inputs stay near linear.
        let mut segs: Vec<(usize, usize, DVec2, DVec2, bool)> = Vec::new();
        for (ci, (_, p, closed)) in polys.iter().enumerate() {
            let m = if *closed { p.len() } else { p.len() - 1 };
            for i in 0..m {
                segs.push((ci, i, p[i], p[(i + 1) % p.len()], *closed));
            }
        }
        let cell = (scale / (segs.len() as f64).sqrt().max(1.0)).max(1e-12);
        let mut grid: std::collections::BTreeMap<(i64, i64), Vec<usize>> =
            std::collections::BTreeMap::new();
        for (k, s) in segs.iter().enumerate() {
            let lo = s.2.min(s.3);
            let hi = s.2.max(s.3);
            for gx in (lo.x / cell).floor() as i64..=(hi.x / cell).floor() as i64 {
                for gy in (lo.y / cell).floor() as i64..=(hi.y / cell).floor() as i64 {
                    grid.entry((gx, gy)).or_default().push(k);
                }
            }
        }
        let decimals = input_decimals(self.chains());
        self.check_consecutive_edges(1e-6 * scale, decimals)?;
        let mut seen = std::collections::HashSet::new();
        for cellv in grid.values() {
            for (x, &i) in cellv.iter().enumerate() {
                for &j in &cellv[x + 1..] {
                    let (a, b) = if i < j { (i, j) } else { (j, i) };
                    if !seen.insert((a, b)) {
                        continue;
                    }
                    let (ci, si, p1, p2, closed_i) = segs[a];
                    let (cj, sj, q1, q2, _) = segs[b];
                    let rel = segments_intersect(p1, p2, q1, q2);
                    if rel == SegmentRelation::Disjoint {
                        continue;
                    }
                    if ci == cj {
                        let n = polys[ci].1.len();
                        let m = if closed_i { n } else { n - 1 };
                        let adjacent = sj == si + 1 || (closed_i && si == 0 && sj == m - 1);
                        if adjacent && rel == SegmentRelation::Touch {
                            continue;
                        }
                        return Err(DomainError::Geometry(format!(
                            "{}: the loop intersects itself {}",
                            polys[ci].0,
                            point_text(meeting_point(p1, p2, q1, q2, rel), decimals)
                        )));
                    }
                    if rel == SegmentRelation::Touch && self.meet_at_a_line_end(p1, p2, q1, q2) {
                        continue;
                    }
                    return Err(DomainError::Geometry(format!(
                        "{} and {} cross or touch {}",
                        polys[ci].0,
                        polys[cj].0,
                        point_text(meeting_point(p1, p2, q1, q2, rel), decimals)
                    )));
                }
            }
        }
        if self.outer.signed_area().abs() <= 0.0 {
            return Err(DomainError::Geometry(
                "outer: the loop encloses no area".into(),
            ));
        }
        // Every hole and line lies inside the outer loop (no crossings, so
        // one point of each decides), and outside every hole.
        // a line may end on a loop: its probe is the middle of its first
        // segment, never an end
        let probe = |p: &[DVec2], closed: bool| if closed { p[0] } else { (p[0] + p[1]) / 2.0 };
        let outer = &polys[0].1;
        for (label, p, closed) in &polys[1..] {
            if !crate::geometry::point_in_polygon(probe(p, *closed), outer) {
                return Err(DomainError::Geometry(format!(
                    "{label} lies outside the outer loop"
                )));
            }
        }
        for (hi, h) in self.holes.iter().enumerate() {
            let hp = &polys[1 + hi].1;
            for (label, p, closed) in &polys[1..] {
                if label != &h.label && crate::geometry::point_in_polygon(probe(p, *closed), hp) {
                    return Err(DomainError::Geometry(format!(
                        "{label} lies inside {}",
                        h.label
                    )));
                }
            }
        }
        Ok(())
    }
}
