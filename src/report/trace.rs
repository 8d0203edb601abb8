//! The inference trace: one record per element made (and per fallback
//! split), each saying who made it, and one per design the host's
//! validity check vetoed; written as JSON Lines.

use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

/// The angles a step saw, by name, kept in name order (a short list: a
/// trace of a million steps keeps a million of them).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Angles(Vec<(&'static str, f64)>);

impl Angles {
    /// The angles, put in name order.
    pub fn new(mut named: Vec<(&'static str, f64)>) -> Angles {
        named.sort_by(|a, b| a.0.cmp(b.0));
        Angles(named)
    }

    /// Name and value, in name order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        self.0.iter().copied()
    }
}

impl Serialize for Angles {
    /// As a JSON object, name to degrees.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

/// Who made an element (or, for `Chord` and `Unmesh`, changed the
/// front without one): the KB's rules, or one of the host's fallbacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum By {
    /// A design rule of the KB (with its redesign rules).
    Rule,
    /// A final pattern of the KB (a 4- or 6-segment loop closed).
    Pattern,
    /// The fallback's loop subdivision: a loop split by a chord.
    Chord,
    /// The fallback's ring of elements round a convex inner loop.
    Ring,
    /// The fallback that takes elements back to give a stuck loop room.
    Unmesh,
    /// The last resort: the whole domain by triangles split into quads.
    Triangles,
    /// With `--blocks`: a block of the layout meshed as a mapping
    /// element (its elements, a step for the block).
    Block,
}

impl By {
    /// Its name in the trace.
    pub fn name(self) -> &'static str {
        match self {
            By::Rule => "rule",
            By::Pattern => "pattern",
            By::Chord => "chord",
            By::Ring => "ring",
            By::Unmesh => "unmesh",
            By::Triangles => "triangles",
            By::Block => "block",
        }
    }
}

/// A design the host's validity check refused before commit.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Veto {
    /// The number of the step that came next (the vetoes before step n
    /// are written before it).
    pub before_step: usize,
    /// The front edge the design was for (node ids of the output mesh).
    pub edge: [i64; 2],
    /// The feature the KB recognised there.
    pub feature: String,
    /// The action (after redesign) that was refused.
    pub action: String,
    /// Why (see validity.rs).
    pub reason: &'static str,
    /// What the host did instead: `nothing` (the edge waits for another
    /// design), or `placed_unmerged` (a merge vetoed, the element placed
    /// without it: the step's redesign list still names the merge rule).
    pub outcome: &'static str,
}

impl Veto {
    /// One line of JSON, `{"veto": {...}}`.
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(&serde_json::json!({ "veto": self })).unwrap_or_default()
    }
}

/// A run's trace as JSON Lines: each step after the vetoes that came
/// before it, the vetoes after the last step at the end.
pub fn json_lines(steps: &[TraceStep], vetoes: &[Veto]) -> String {
    {
        let mut text = String::new();
        let mut vetoes = vetoes.iter().peekable();
        for step in steps {
            while let Some(v) = vetoes.next_if(|v| v.before_step <= step.step) {
                text.push_str(&v.to_json_line());
                text.push('\n');
            }
            text.push_str(&step.to_json_line());
            text.push('\n');
        }
        for v in vetoes {
            text.push_str(&v.to_json_line());
            text.push('\n');
        }
        text
    }
}

/// One step of the inference.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TraceStep {
    /// Step number, from 1.
    pub step: usize,
    /// The front edge acted on (N1, N2), node ids of the output mesh (-1:
    /// a node no element kept, after a stuck region was taken back).
    pub edge: [i64; 2],
    /// Interior angles seen (degrees, rounded as the KB saw them):
    /// theta7, theta4, theta1, theta2, theta5; for final patterns a1..a6.
    pub angles: Angles,
    /// The feature the KB recognised (b1..b5, a user's feature, `final4`,
    /// `final6`, or `stuck` for a fallback split).
    pub feature: String,
    /// The action, as the KB stated it (after redesign).
    pub action: String,
    /// Who made the element.
    pub by: By,
    /// The redesign rules that fired, in order.
    pub redesign: Vec<String>,
    /// The element's four node ids (counter-clockwise); empty for a split.
    pub element: Vec<i64>,
}

impl TraceStep {
    /// One line of text, as the REPL prints it and the snapshot tests
    /// keep it: step, edge, feature -> action, the angles seen (whole
    /// degrees) and in a graded run the grading ratio (tenths), the
    /// redesign rules that fired, the element.
    pub fn to_text(&self) -> String {
        let angles: Vec<String> = self
            .angles
            .iter()
            .map(|(k, v)| {
                if k == "ratio" {
                    format!("{k}={v:.1}")
                } else {
                    format!("{k}={v:.0}")
                }
            })
            .collect();
        let redesign = if self.redesign.is_empty() {
            String::new()
        } else {
            format!(" redesign {}", self.redesign.join(","))
        };
        format!(
            "{:>3} {:?} {} -> {} by {} {}{} {:?}",
            self.step,
            self.edge,
            self.feature,
            self.action,
            self.by.name(),
            angles.join(" "),
            redesign,
            self.element
        )
    }

    /// One line of JSON.
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}
