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

/// One edge of a loop or line: a straight segment or a circular arc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curve {
    /// Straight edge from `a` to `b`.
    Line {
        /// Start point.
        a: DVec2,
        /// End point.
        b: DVec2,
    },
    /// Circular arc from `a` to `b` with the DXF bulge tan(sweep/4),
    /// positive counter-clockwise.
    Arc {
        /// Start point.
        a: DVec2,
        /// End point.
        b: DVec2,
        /// tan(sweep / 4), signed.
        bulge: f64,
    },
    /// A full circle (a loop by itself), traversed counter-clockwise from
    /// angle 0.
    Circle {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
    },
}

impl Curve {
    /// Centre, radius, start angle and signed sweep of an arc.
    fn arc_frame(a: DVec2, b: DVec2, bulge: f64) -> (DVec2, f64, f64, f64) {
        let sweep = 4.0 * bulge.atan();
        let half = (b - a).length() / 2.0;
        let d = (b - a) / (2.0 * half);
        let left = DVec2::new(-d.y, d.x);
        let c = (a + b) / 2.0 + left * half * (1.0 - bulge * bulge) / (2.0 * bulge);
        let r = (a - c).length();
        let a0 = (a.y - c.y).atan2(a.x - c.x);
        (c, r, a0, sweep)
    }

    /// Length of the curve.
    pub fn length(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => (b - a).length(),
            Curve::Arc { a, b, bulge } => {
                let (_, r, _, sweep) = Self::arc_frame(a, b, bulge);
                r * sweep.abs()
            }
            Curve::Circle { radius, .. } => 2.0 * PI * radius,
        }
    }

    /// The point at parameter `t` in [0, 1] (uniform in arc length).
    pub fn point_at(&self, t: f64) -> DVec2 {
        match *self {
            Curve::Line { a, b } => a + (b - a) * t,
            Curve::Arc { a, b, bulge } => {
                if t <= 0.0 {
                    return a;
                }
                if t >= 1.0 {
                    return b;
                }
                let (c, r, a0, sweep) = Self::arc_frame(a, b, bulge);
                let ang = a0 + sweep * t;
                c + r * DVec2::new(ang.cos(), ang.sin())
            }
            Curve::Circle { center, radius } => {
                let ang = 2.0 * PI * t;
                center + radius * DVec2::new(ang.cos(), ang.sin())
            }
        }
    }

    /// Projects `p` onto the curve: the closest point on it.
    pub fn project(&self, p: DVec2) -> DVec2 {
        match *self {
            Curve::Line { a, b } => {
                let d = b - a;
                let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
                a + d * t
            }
            Curve::Circle { center, radius } => {
                let v = p - center;
                if v.length() < 1e-300 {
                    return center + DVec2::new(radius, 0.0);
                }
                center + v.normalize() * radius
            }
            Curve::Arc { a, b, bulge } => {
                let (c, r, a0, sweep) = Self::arc_frame(a, b, bulge);
                let ang = (p.y - c.y).atan2(p.x - c.x);
                let mut rel = (ang - a0) * sweep.signum();
                rel = rel.rem_euclid(2.0 * PI);
                if rel <= sweep.abs() {
                    let t = a0 + rel * sweep.signum();
                    c + r * DVec2::new(t.cos(), t.sin())
                } else if (p - a).length() < (p - b).length() {
                    a
                } else {
                    b
                }
            }
        }
    }

    /// `n` segments of (about) equal length: n+1 points, ends included
    /// (a circle: n points, the first not repeated).
    pub fn divide(&self, n: usize) -> Vec<DVec2> {
        match self {
            Curve::Circle { .. } => (0..n).map(|k| self.point_at(k as f64 / n as f64)).collect(),
            _ => (0..=n)
                .map(|k| self.point_at(k as f64 / n as f64))
                .collect(),
        }
    }

    /// The signed area contribution (shoelace term plus the arc's segment).
    pub fn signed_area_term(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => 0.5 * a.perp_dot(b),
            Curve::Arc { a, b, bulge } => {
                let (_, r, _, sweep) = Self::arc_frame(a, b, bulge);
                0.5 * a.perp_dot(b)
                    + 0.5 * r * r * (sweep.abs() - sweep.abs().sin()) * sweep.signum()
            }
            Curve::Circle { radius, .. } => PI * radius * radius,
        }
    }
}

/// An edge of a loop or line with its optional fixed segment count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// The geometry of the edge.
    pub curve: Curve,
    /// Exact segment count, if the file fixes it.
    pub segments: Option<usize>,
}

/// A closed loop (outer boundary or hole) or an open inner line.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// Its edges in order.
    pub edges: Vec<Edge>,
    /// Where it came from in the file, e.g. `holes[1]`, for messages.
    pub label: String,
}

impl Chain {
    /// Signed area enclosed (counter-clockwise positive); closed loops only.
    pub fn signed_area(&self) -> f64 {
        self.edges.iter().map(|e| e.curve.signed_area_term()).sum()
    }
}

/// A validated domain.
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    /// Free text name.
    pub name: String,
    /// Target boundary segment length.
    pub size: f64,
    /// Largest interior element edge, if bounded.
    pub max_size: Option<f64>,
    /// The outer loop.
    pub outer: Chain,
    /// Holes.
    pub holes: Vec<Chain>,
    /// Inner lines (open).
    pub lines: Vec<Chain>,
}

/// The keys of each object of the format (domain-format.md, 1.1: `tags`,
/// a circle's `tag` and a line's `crack` are known keys).
const TOP_KEYS: &[&str] = &["name", "size", "max_size", "outer", "holes", "lines"];
const CHAIN_KEYS: &[&str] = &["points", "bulges", "segments", "tags", "crack", "circle"];
const CIRCLE_KEYS: &[&str] = &["center", "radius", "segments", "tag"];

/// Every key of the domain's objects that the format does not know, as
/// "where: key (did you mean ...?)".
fn unknown_keys(v: &Value) -> Vec<String> {
    fn check(v: &Value, at: &str, known: &[&str], out: &mut Vec<String>) {
        let Some(obj) = v.as_object() else { return };
        for k in obj.keys() {
            if known.contains(&k.as_str()) {
                continue;
            }
            let near = known
                .iter()
                .min_by_key(|c| edit_distance(k, c))
                .filter(|c| edit_distance(k, c) <= 2);
            let at = if at.is_empty() {
                String::new()
            } else {
                format!("{at}.")
            };
            out.push(match near {
                Some(c) => format!("{at}{k} (did you mean {c}?)"),
                None => format!("{at}{k}"),
            });
        }
    }
    let mut out = Vec::new();
    check(v, "", TOP_KEYS, &mut out);
    let chain = |c: &Value, at: String, out: &mut Vec<String>| {
        check(c, &at, CHAIN_KEYS, out);
        if let Some(circle) = c.get("circle") {
            check(circle, &format!("{at}.circle"), CIRCLE_KEYS, out);
        }
    };
    if let Some(o) = v.get("outer") {
        chain(o, "outer".into(), &mut out);
    }
    for list in ["holes", "lines"] {
        if let Some(items) = v.get(list).and_then(Value::as_array) {
            for (i, c) in items.iter().enumerate() {
                chain(c, format!("{list}[{i}]"), &mut out);
            }
        }
    }
    out
}

/// Levenshtein distance, for suggesting the key meant.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
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

fn chain(v: &Value, key: &str, closed: bool) -> Result<Chain, DomainError> {
    let obj = v
        .as_object()
        .ok_or_else(|| key_err(key, "expected an object with \"points\" or \"circle\""))?;
    if let Some(c) = obj.get("circle") {
        if !closed {
            return Err(key_err(key, "an inner line cannot be a circle"));
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
        return Ok(Chain {
            edges: vec![Edge {
                curve: Curve::Circle { center, radius },
                segments,
            }],
            label: key.to_string(),
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
        edges.push(Edge { curve, segments });
    }
    Ok(Chain {
        edges,
        label: key.to_string(),
    })
}

impl Domain {
    /// Reads and validates a domain file.
    pub fn from_file(path: &str) -> Result<Domain, DomainError> {
        let text = std::fs::read_to_string(path).map_err(|e| DomainError::Io {
            path: path.to_string(),
            message: e.to_string(),
        })?;
        let v: Value = serde_json::from_str(&text).map_err(|e| DomainError::Json {
            path: path.to_string(),
            message: e.to_string(),
        })?;
        Domain::from_json(&v)
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
        let outer = chain(
            obj.get("outer")
                .ok_or_else(|| key_err("outer", "missing key"))?,
            "outer",
            true,
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
            .map(|(i, h)| chain(h, &format!("holes[{i}]"), true))
            .collect::<Result<Vec<_>, _>>()?;
        let lines = list("lines")?
            .iter()
            .enumerate()
            .map(|(i, l)| chain(l, &format!("lines[{i}]"), false))
            .collect::<Result<Vec<_>, _>>()?;
        let d = Domain {
            name,
            size,
            max_size,
            outer,
            holes,
            lines,
        };
        d.check_geometry()?;
        Ok(d)
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

    /// The most decimals a coordinate or radius of the domain has, as the
    /// shortest text that reads back as the same number: a point quoted in
    /// a message gets no more digits than the input has.
    fn input_decimals(&self) -> usize {
        let decimals = |x: f64| {
            let text = x.to_string();
            text.split_once('.').map_or(0, |(_, fraction)| fraction.len())
        };
        let mut most = 0;
        for e in self.chains().flat_map(|c| &c.edges) {
            let numbers = match e.curve {
                Curve::Line { a, b } | Curve::Arc { a, b, .. } => [a.x, a.y, b.x, b.y],
                Curve::Circle { center, radius } => [center.x, center.y, radius, 0.0],
            };
            most = numbers.into_iter().map(decimals).fold(most, usize::max);
        }
        most
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
        let decimals = self.input_decimals();
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
        let outer = &polys[0].1;
        for (label, p, _) in &polys[1..] {
            if !crate::geometry::point_in_polygon(p[0], outer) {
                return Err(DomainError::Geometry(format!(
                    "{label} lies outside the outer loop"
                )));
            }
        }
        for (hi, h) in self.holes.iter().enumerate() {
            let hp = &polys[1 + hi].1;
            for (label, p, _) in &polys[1..] {
                if label != &h.label && crate::geometry::point_in_polygon(p[0], hp) {
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

/// Where two segments that are not disjoint meet: the point where they
/// cross, or for a touch or an overlap an end of one that lies on the other.
fn meeting_point(p1: DVec2, p2: DVec2, q1: DVec2, q2: DVec2, rel: SegmentRelation) -> DVec2 {
    let (dp, dq) = (p2 - p1, q2 - q1);
    let denominator = dp.perp_dot(dq);
    if rel == SegmentRelation::Cross && denominator != 0.0 {
        return p1 + dp * ((q1 - p1).perp_dot(dq) / denominator);
    }
    let on = |a: DVec2, b: DVec2, p: DVec2| {
        crate::geometry::orient2d(a, b, p) == 0.0
            && p.x >= a.x.min(b.x)
            && p.x <= a.x.max(b.x)
            && p.y >= a.y.min(b.y)
            && p.y <= a.y.max(b.y)
    };
    [(q1, p1, p2), (q2, p1, p2), (p1, q1, q2), (p2, q1, q2)]
        .into_iter()
        .find(|&(p, a, b)| on(a, b, p))
        .map_or(p1, |(p, _, _)| p)
}

/// `at (x, y)` with `decimals` decimals, or `near (x, y)` where that
/// rounds the point.
fn point_text(p: DVec2, decimals: usize) -> String {
    let number = |v: f64| {
        let text = format!("{v:.decimals$}");
        // -0 reads as a typo
        let text = if text.trim_start_matches(['-', '0', '.']).is_empty() {
            text.trim_start_matches('-').to_string()
        } else {
            text
        };
        let exact = text.parse::<f64>() == Ok(v);
        (text, exact)
    };
    let ((x, x_exact), (y, y_exact)) = (number(p.x), number(p.y));
    let word = if x_exact && y_exact { "at" } else { "near" };
    format!("{word} ({x}, {y})")
}
