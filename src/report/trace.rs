//! The inference trace: one record per element made (and per fallback
//! split), written as JSON Lines.

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
    /// The redesign rules that fired, in order.
    pub redesign: Vec<String>,
    /// The element's four node ids (counter-clockwise); empty for a split.
    pub element: Vec<i64>,
}

impl TraceStep {
    /// One line of text, as the REPL prints it and the snapshot tests
    /// keep it: step, edge, feature -> action, the angles seen (whole
    /// degrees), the redesign rules that fired, the element.
    pub fn to_text(&self) -> String {
        let angles: Vec<String> = self
            .angles
            .iter()
            .map(|(k, v)| format!("{k}={v:.0}"))
            .collect();
        let redesign = if self.redesign.is_empty() {
            String::new()
        } else {
            format!(" redesign {}", self.redesign.join(","))
        };
        format!(
            "{:>3} {:?} {} -> {} {}{} {:?}",
            self.step,
            self.edge,
            self.feature,
            self.action,
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
