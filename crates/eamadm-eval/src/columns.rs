//! What every column of the evaluation's tables means, as data: one [`Column`] per column, kept
//! beside the code that writes it ([`scores::COLUMNS`](crate::scores::COLUMNS) for
//! `final-scores.csv`, [`claims::CLAIM_COLUMNS`](crate::claims::CLAIM_COLUMNS) for
//! `claims.csv`), and from those tables a [Frictionless Data
//! Package](https://specs.frictionlessdata.io/data-package/) (`datapackage.json`, which
//! `frictionless`, pandas and R read to type the columns) and a Markdown page for people.
//!
//! Each table's tests write a row and check that the CSV header equals the table's names, so a
//! column cannot be added, renamed or moved without its documentation.
//!
//! # Example
//!
//! ```
//! use eamadm_eval::columns::{Resource, data_package};
//! use eamadm_eval::scores;
//!
//! let package = data_package(
//!     "example",
//!     &[Resource {
//!         name: "final-scores",
//!         path: "final-scores.csv",
//!         title: "Final scores",
//!         description: "One row per run.",
//!         columns: scores::COLUMNS,
//!     }],
//! );
//! let fields = &package["resources"][0]["schema"]["fields"];
//! assert_eq!(fields[0]["name"], "task");
//! assert_eq!(fields[8]["name"], "final_steps");
//! assert_eq!(fields[8]["type"], "number");
//! assert_eq!(fields[8]["unit"], "steps");
//! ```

use serde_json::{Value, json};

/// A column's type, by the Frictionless Table Schema's names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldType {
    /// Text.
    String,
    /// A whole number (written without a decimal point).
    Integer,
    /// A real number (written so that it reads back bit for bit; `NaN` and `inf` never
    /// occur in these tables).
    Number,
    /// `true` or `false`.
    Boolean,
}

impl FieldType {
    /// The Table Schema name: `string`, `integer`, `number` or `boolean`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::String => "string",
            Self::Integer => "integer",
            Self::Number => "number",
            Self::Boolean => "boolean",
        }
    }
}

/// One column of a CSV table, documented.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Column {
    /// The header name.
    pub name: &'static str,
    /// Its type.
    pub field_type: FieldType,
    /// Its unit (`steps`, `s`, …), when it has one.
    pub unit: Option<&'static str>,
    /// What it holds and how it is computed.
    pub description: &'static str,
    /// When the cell is blank and why; `None` for a column that is always filled.
    pub blank_when: Option<&'static str>,
    /// The values a text column can take, when they are a fixed set.
    pub values: Option<&'static [&'static str]>,
}

impl Column {
    /// A column that is always filled, with no unit and no fixed set of values.
    #[must_use]
    pub const fn new(name: &'static str, field_type: FieldType, description: &'static str) -> Self {
        Self {
            name,
            field_type,
            unit: None,
            description,
            blank_when: None,
            values: None,
        }
    }

    /// This column, measured in `unit`.
    #[must_use]
    pub const fn unit(self, unit: &'static str) -> Self {
        Self {
            unit: Some(unit),
            ..self
        }
    }

    /// This column, blank when `when`.
    #[must_use]
    pub const fn blank_when(self, when: &'static str) -> Self {
        Self {
            blank_when: Some(when),
            ..self
        }
    }

    /// This column, taking only `values`.
    #[must_use]
    pub const fn values(self, values: &'static [&'static str]) -> Self {
        Self {
            values: Some(values),
            ..self
        }
    }

    /// The Table Schema field descriptor: `name`, `type`, `description` (with the blank rule
    /// appended), `unit` when there is one, and `constraints` (`required` for an always-filled
    /// column, `enum` for a fixed set of values).
    #[must_use]
    pub fn field(&self) -> Value {
        let mut field = json!({
            "name": self.name,
            "type": self.field_type.name(),
            "description": self.full_description(),
        });
        if let Some(unit) = self.unit {
            field["unit"] = json!(unit);
        }
        let mut constraints = serde_json::Map::new();
        if self.blank_when.is_none() {
            constraints.insert("required".to_owned(), json!(true));
        }
        if let Some(values) = self.values {
            constraints.insert("enum".to_owned(), json!(values));
        }
        if !constraints.is_empty() {
            field["constraints"] = Value::Object(constraints);
        }
        field
    }

    /// The description followed by "Blank when …" for a column that can be blank.
    #[must_use]
    pub fn full_description(&self) -> String {
        match self.blank_when {
            Some(when) => format!("{} Blank when {when}.", self.description),
            None => self.description.to_owned(),
        }
    }
}

/// The names of `columns`, in order: a CSV header.
#[must_use]
pub fn names(columns: &[Column]) -> Vec<&'static str> {
    columns.iter().map(|c| c.name).collect()
}

/// One CSV file of a data package.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resource {
    /// The resource's name (lower case, `-` and `_` only).
    pub name: &'static str,
    /// The file, relative to the package.
    pub path: &'static str,
    /// A title for people.
    pub title: &'static str,
    /// What one row is.
    pub description: &'static str,
    /// Its columns, in order.
    pub columns: &'static [Column],
}

/// The Frictionless Data Package of `resources` (CSV files, comma-separated, UTF-8, a header
/// row; an empty cell is a missing value), named `name`.
#[must_use]
pub fn data_package(name: &str, resources: &[Resource]) -> Value {
    let resources: Vec<Value> = resources
        .iter()
        .map(|resource| {
            json!({
                "name": resource.name,
                "path": resource.path,
                "profile": "tabular-data-resource",
                "title": resource.title,
                "description": resource.description,
                "format": "csv",
                "mediatype": "text/csv",
                "encoding": "utf-8",
                "schema": {
                    "fields": resource.columns.iter().map(Column::field).collect::<Vec<_>>(),
                    "missingValues": [""],
                },
            })
        })
        .collect();
    json!({
        "name": name,
        "profile": "tabular-data-package",
        "resources": resources,
    })
}

/// `package` as the text of `datapackage.json`: pretty-printed, keys in the order written,
/// ending with a newline.
#[must_use]
pub fn to_json_text(package: &Value) -> String {
    // Serialising a `Value` cannot fail.
    let mut text = serde_json::to_string_pretty(package).unwrap_or_default();
    text.push('\n');
    text
}

/// A Markdown section per resource: its title, file and description, then a table of its
/// columns (name, type, unit, meaning and when blank).
#[must_use]
pub fn markdown(resources: &[Resource]) -> String {
    let mut text = String::new();
    for (i, resource) in resources.iter().enumerate() {
        if i > 0 {
            text.push('\n');
        }
        text.push_str(&format!(
            "### `{}`: {}\n\n{}\n\n| column | type | unit | meaning | blank when |\n|---|---|---|---|---|\n",
            resource.path, resource.title, resource.description
        ));
        for column in resource.columns {
            let mut meaning = column.description.to_owned();
            if let Some(values) = column.values {
                let values: Vec<String> = values.iter().map(|v| format!("`{v}`")).collect();
                meaning.push_str(&format!(" One of {}.", values.join(", ")));
            }
            text.push_str(&format!(
                "| `{}` | {} | {} | {} | {} |\n",
                column.name,
                column.field_type.name(),
                column.unit.unwrap_or(""),
                meaning.replace('|', "\\|"),
                column.blank_when.unwrap_or("never").replace('|', "\\|"),
            ));
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_carries_its_unit_constraints_and_blank_rule() {
        let column = Column::new("x", FieldType::Number, "The x.")
            .unit("s")
            .blank_when("there is no x");
        assert_eq!(
            column.field(),
            json!({"name": "x", "type": "number", "unit": "s",
                   "description": "The x. Blank when there is no x."})
        );
        let column = Column::new("k", FieldType::String, "A kind.").values(&["a", "b"]);
        assert_eq!(
            column.field()["constraints"],
            json!({"required": true, "enum": ["a", "b"]})
        );
    }
}
