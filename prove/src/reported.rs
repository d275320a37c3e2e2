//! The reported effects as other tools read them: through the contract's JSON keys
//! (`docs/diagnosis-format.md`), not the diagnosis's types, so the proof scores any
//! report that follows the contract, keys added by its amendments included, and a key a report
//! lacks reads as not given.

use serde_json::Value;

/// One entry of OUT.json's `effects`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ReportedEffect {
    pub name: String,
    /// `material`, `transducer` or `electronics`; `None` where the report has no `stage`.
    pub stage: Option<String>,
    pub channels: Vec<String>,
    /// `Some(false)`: a term the catalogue lacks, described; absent: a catalogue entry.
    pub catalogue: Option<bool>,
    /// The quantities a described term is a function of; `None` where the report has none.
    pub depends_on: Option<Vec<String>>,
    pub form: Option<String>,
}

impl ReportedEffect {
    /// A catalogue entry (not `"catalogue": false`).
    pub fn is_catalogue(&self) -> bool {
        self.catalogue != Some(false)
    }

    /// Every effect of a report's JSON (none where it has no `effects` list).
    pub fn all(report: &Value) -> Vec<Self> {
        let Some(list) = report.get("effects").and_then(Value::as_array) else {
            return Vec::new();
        };
        list.iter().map(Self::from_json).collect()
    }

    fn from_json(e: &Value) -> Self {
        let text = |key: &str| e.get(key).and_then(Value::as_str).map(str::to_string);
        let texts = |key: &str| {
            e.get(key).and_then(Value::as_array).map(|a| {
                a.iter()
                    .filter_map(Value::as_str)
                    .map(str::to_string)
                    .collect::<Vec<_>>()
            })
        };
        Self {
            name: text("name").unwrap_or_default(),
            stage: text("stage"),
            channels: texts("channels").unwrap_or_default(),
            catalogue: e.get("catalogue").and_then(Value::as_bool),
            depends_on: texts("depends_on"),
            form: text("form"),
        }
    }

    /// The effect in a table cell: `name@stage[channels]{depends_on}`.
    pub fn short(&self) -> String {
        let mut s = self.name.clone();
        if let Some(stage) = &self.stage {
            s.push('@');
            s.push_str(stage);
        }
        s.push_str(&format!("[{}]", self.channels.join(",")));
        if let Some(d) = &self.depends_on {
            s.push_str(&format!("{{{}}}", d.join(",")));
        }
        if !self.is_catalogue() {
            s.push_str(" (described)");
        }
        s
    }
}
