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

mod entities;
mod joining;
#[cfg(test)]
mod tests;

use std::path::Path;

use glam::DVec2;
use serde::Serialize;

use entities::drawn_geometry;
pub use joining::outline_of;

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
