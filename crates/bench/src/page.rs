//! Performance pages: a Markdown page made from a `--json` report, so that the figures in
//! `docs/performance/` are what a run printed, stamped with its machine and commit, and never
//! kept by hand.
//!
//! A report is one JSON object per line: the [`Stamp`] first, then the benchmark's records.
//! Records with the same fields (and the same `measurement`, where they have one) make one
//! table, columns in the order the benchmark wrote them, nested objects flattened to dotted
//! names. Where a table's records come from several `system`s (raystage, Embree, Mitsuba), a
//! second table gives the first system's figures over each other's, row by row: rows are
//! matched on their text fields and `threads`, and every fractional figure is divided.

use std::fmt::Write;

use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::stamp::{Stamp, StampLine};

/// Numeric fields that say which case a record measures, as its text fields do: rows of two
/// systems are compared only where these agree (`target`: the error a path tracer is timed to).
const CASE_COUNTS: [&str; 3] = ["threads", "spp", "target"];

/// Why a report cannot make a page.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum PageError {
    /// The first line is not a stamp.
    #[error("line 1 is not a stamp ({0}): make the report with `raystage-bench <benchmark> --json`")]
    NoStamp(String),
    /// A line is not a JSON object.
    #[error("line {line} is not a JSON object: {message}")]
    NotAnObject {
        /// 1-based.
        line: usize,
        /// What the parser said.
        message: String,
    },
}

/// The page of `report` (the text of a `--json` run), titled after its benchmark.
pub fn render(report: &str) -> Result<String, PageError> {
    let mut lines = report.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let stamp = match lines.next() {
        Some((_, first)) => serde_json::from_str::<StampLine>(first).map_err(|e| PageError::NoStamp(e.to_string()))?.stamp,
        None => return Err(PageError::NoStamp("the report is empty".into())),
    };
    let mut tables: Vec<Table> = Vec::new();
    for (k, line) in lines {
        let value: Value = serde_json::from_str(line).map_err(|e| PageError::NotAnObject { line: k + 1, message: e.to_string() })?;
        let Value::Object(fields) = value else {
            return Err(PageError::NotAnObject { line: k + 1, message: "a record must be an object".into() });
        };
        let mut row = Vec::new();
        flatten("", fields, &mut row);
        let (columns, cells): (Vec<String>, Vec<Value>) = row.into_iter().unzip();
        let measurement = cells.iter().zip(&columns).find(|(_, c)| *c == "measurement").map(|(v, _)| v.text());
        match tables.iter_mut().find(|t| t.columns == columns && t.measurement == measurement) {
            Some(table) => table.rows.push(cells),
            None => tables.push(Table { measurement, columns, rows: vec![cells] }),
        }
    }
    let mut page = header(&stamp);
    for table in &tables {
        table.write(&mut page);
    }
    Ok(page)
}

/// The page's title and the stamp as a table.
fn header(stamp: &Stamp) -> String {
    let mut out = String::new();
    let benchmark = stamp.command.split_whitespace().next().unwrap_or("benchmark");
    let _ = writeln!(out, "# `{benchmark}` benchmark\n");
    let _ = writeln!(out, "<!-- Made by `raystage-bench page` from a `--json` report (scripts/performance.sh): do not edit. -->\n");
    let _ = writeln!(out, "| run | |\n|---|---|");
    let _ = writeln!(out, "| command | `raystage-bench {}` |", stamp.command);
    let _ = writeln!(out, "| date | {} |", stamp.date);
    let _ = writeln!(out, "| commit | `{}` |", stamp.commit);
    let _ = writeln!(out, "| CPU | {}, {} logical cores |", stamp.cpu, stamp.cores);
    let _ = writeln!(out, "| SIMD | {} (raystage's kernels: {}) |", stamp.simd.join(", "), stamp.kernel_isa);
    let _ = writeln!(out, "| Embree | {} |", stamp.embree.as_deref().unwrap_or("not measured (built without the `embree` feature)"));
    let load = stamp.load_average.map_or("unknown".to_string(), |l| format!("{l:.2}"));
    let _ = writeln!(out, "| load average at start | {load} (on a shared machine, compare ratios within this page only) |");
    let _ = writeln!(out, "| build | {} |", if stamp.release { "release" } else { "debug: the figures mean little" });
    out
}

/// Records with the same fields.
struct Table {
    measurement: Option<String>,
    columns: Vec<String>,
    rows: Vec<Vec<Value>>,
}

impl Table {
    fn write(&self, out: &mut String) {
        let title = self.measurement.clone().unwrap_or_else(|| "results".into());
        let _ = writeln!(out, "\n## {title}\n");
        markdown(out, &self.columns, self.rows.iter().map(|r| r.iter().map(Value::text).collect()));
        let Some(system) = self.columns.iter().position(|c| c == "system") else { return };
        let mut systems: Vec<String> = Vec::new();
        for row in &self.rows {
            let name = row[system].text();
            if !systems.contains(&name) {
                systems.push(name);
            }
        }
        // Rows of two systems describe the same case when their text fields and the case's
        // counts (threads, samples per pixel) agree; the figures compared are the fractional
        // ones (times, rates, ratios).
        let identity: Vec<usize> = (0..self.columns.len())
            .filter(|&c| c != system && (matches!(self.rows[0][c], Value::String(_)) || CASE_COUNTS.contains(&self.columns[c].as_str())))
            .collect();
        let figures: Vec<usize> = (0..self.columns.len()).filter(|&c| !identity.contains(&c) && self.rows.iter().any(|r| r[c].is_fraction())).collect();
        if figures.is_empty() {
            return;
        }
        // raystage's figures over each other system's, wherever raystage is in the table.
        if let Some(at) = systems.iter().position(|s| s == "raystage") {
            systems[..=at].rotate_right(1);
        }
        let ours = &systems[0];
        for theirs in &systems[1..] {
            let mut rows = Vec::new();
            for a in self.rows.iter().filter(|r| r[system].text() == *ours) {
                let Some(b) = self.rows.iter().find(|b| b[system].text() == *theirs && identity.iter().all(|&c| a[c] == b[c])) else { continue };
                let mut row: Vec<String> = identity.iter().map(|&c| a[c].text()).collect();
                row.extend(figures.iter().map(|&c| match (a[c].number(), b[c].number()) {
                    (Some(x), Some(y)) if y != 0.0 => format!("{:.2}×", x / y),
                    _ => "–".into(),
                }));
                rows.push(row);
            }
            if rows.is_empty() {
                continue;
            }
            let _ = writeln!(out, "\n{ours} ÷ {theirs}, case by case (a time below 1× is faster, a rate above 1× is faster):\n");
            let columns: Vec<String> = identity.iter().chain(&figures).map(|&c| self.columns[c].clone()).collect();
            markdown(out, &columns, rows.into_iter());
        }
    }
}

/// A Markdown table.
fn markdown(out: &mut String, columns: &[String], rows: impl Iterator<Item = Vec<String>>) {
    let _ = writeln!(out, "| {} |", columns.join(" | "));
    let _ = writeln!(out, "|{}", "---|".repeat(columns.len()));
    for row in rows {
        let _ = writeln!(out, "| {} |", row.join(" | "));
    }
}

/// Appends `fields` to `row`, nested objects as `parent.child` columns.
fn flatten(prefix: &str, fields: Vec<(String, Value)>, row: &mut Vec<(String, Value)>) {
    for (name, value) in fields {
        let name = if prefix.is_empty() { name } else { format!("{prefix}.{name}") };
        match value {
            Value::Object(inner) => flatten(&name, inner, row),
            value => row.push((name, value)),
        }
    }
}

/// A JSON value whose objects keep their fields in the order they were written (the order the
/// benchmark's report structs declare them, which is the order a reader wants the columns in).
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Null,
    Bool(bool),
    Number(serde_json::Number),
    String(String),
    Array(Vec<Value>),
    Object(Vec<(String, Value)>),
}

impl Value {
    /// The value as a table cell: fractions to four significant digits.
    fn text(&self) -> String {
        match self {
            Value::Null => "–".into(),
            Value::Bool(b) => b.to_string(),
            Value::Number(n) if n.is_f64() => significant(n.as_f64().unwrap_or(f64::NAN)),
            Value::Number(n) => n.to_string(),
            Value::String(s) => s.replace('|', "\\|"),
            Value::Array(items) => items.iter().map(Value::text).collect::<Vec<_>>().join(", "),
            Value::Object(fields) => fields.iter().map(|(k, v)| format!("{k}: {}", v.text())).collect::<Vec<_>>().join(", "),
        }
    }

    fn number(&self) -> Option<f64> {
        match self {
            Value::Number(n) => n.as_f64(),
            _ => None,
        }
    }

    fn is_fraction(&self) -> bool {
        matches!(self, Value::Number(n) if n.is_f64())
    }
}

/// `x` to four significant digits, without an exponent for everyday magnitudes.
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let digits = (3 - x.abs().log10().floor() as i32).clamp(0, 9) as usize;
    format!("{x:.digits$}")
}

impl<'de> Deserialize<'de> for Value {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Value, D::Error> {
        deserializer.deserialize_any(ValueVisitor)
    }
}

struct ValueVisitor;

impl<'de> Visitor<'de> for ValueVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_bool<E>(self, b: bool) -> Result<Value, E> {
        Ok(Value::Bool(b))
    }
    fn visit_i64<E>(self, n: i64) -> Result<Value, E> {
        Ok(Value::Number(n.into()))
    }
    fn visit_u64<E>(self, n: u64) -> Result<Value, E> {
        Ok(Value::Number(n.into()))
    }
    fn visit_f64<E>(self, x: f64) -> Result<Value, E> {
        Ok(serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number))
    }
    fn visit_str<E>(self, s: &str) -> Result<Value, E> {
        Ok(Value::String(s.to_string()))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(Value::Array(items))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut fields = Vec::new();
        while let Some((key, value)) = map.next_entry::<String, Value>()? {
            fields.push((key, value));
        }
        Ok(Value::Object(fields))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stamp() -> String {
        let stamp = Stamp {
            command: "kernel --scene sphere".into(),
            date: "2026-12-06T12:00:00Z".into(),
            commit: "abc1234".into(),
            cpu: "Test CPU".into(),
            cores: 2,
            simd: vec!["avx2".into()],
            kernel_isa: "avx2".into(),
            embree: Some("3.13.5".into()),
            load_average: Some(1.5),
            release: true,
        };
        serde_json::to_string(&StampLine { stamp }).unwrap()
    }

    #[test]
    fn a_page_has_the_stamp_the_records_in_their_order_and_ratios_between_systems() {
        let report = [
            stamp(),
            r#"{"system":"raystage","scene":"sphere","threads":1,"build_s":0.5,"hits":10}"#.into(),
            r#"{"system":"embree","scene":"sphere","threads":1,"build_s":1.0,"hits":10}"#.into(),
            r#"{"system":"raystage","scene":"sphere","threads":2,"build_s":0.3,"hits":10}"#.into(),
            r#"{"system":"embree","scene":"sphere","threads":2,"build_s":0.4,"hits":10}"#.into(),
            r#"{"measurement":"specialisation","threads":2,"ms":{"general":12.5,"special":10.0}}"#.into(),
        ]
        .join("\n");
        let page = render(&report).unwrap();
        assert!(page.starts_with("# `kernel` benchmark"), "{page}");
        for expected in [
            "| commit | `abc1234` |",
            "| CPU | Test CPU, 2 logical cores |",
            "| Embree | 3.13.5 |",
            // Columns in the order written, not alphabetical.
            "| system | scene | threads | build_s | hits |",
            "| raystage | sphere | 1 | 0.5000 | 10 |",
            "raystage ÷ embree",
            "| scene | threads | build_s |",
            "| sphere | 1 | 0.50× |",
            "| sphere | 2 | 0.75× |",
            "## specialisation",
            "| measurement | threads | ms.general | ms.special |",
            "| specialisation | 2 | 12.50 | 10.00 |",
        ] {
            assert!(page.contains(expected), "missing {expected:?} in\n{page}");
        }
    }

    #[test]
    fn rows_are_compared_at_equal_sample_counts_raystage_over_the_others() {
        let report = [
            stamp(),
            r#"{"system":"mitsuba","spp":16,"seconds":2.0}"#.into(),
            r#"{"system":"raystage","spp":16,"seconds":1.0}"#.into(),
            r#"{"system":"raystage","spp":64,"seconds":3.0}"#.into(),
            r#"{"system":"mitsuba","spp":64,"seconds":12.0}"#.into(),
        ]
        .join("\n");
        let page = render(&report).unwrap();
        for expected in ["raystage ÷ mitsuba", "| spp | seconds |", "| 16 | 0.50× |", "| 64 | 0.25× |"] {
            assert!(page.contains(expected), "missing {expected:?} in\n{page}");
        }
        assert!(!page.contains("mitsuba ÷ raystage"), "{page}");
    }

    #[test]
    fn a_report_without_its_stamp_or_with_a_broken_line_is_refused() {
        assert!(matches!(render(r#"{"system":"raystage"}"#), Err(PageError::NoStamp(_))));
        assert!(matches!(render(""), Err(PageError::NoStamp(_))));
        let broken = format!("{}\n{{\"a\": 1}}\nnot json", stamp());
        assert!(matches!(render(&broken), Err(PageError::NotAnObject { line: 3, .. })));
        let array = format!("{}\n[1, 2]", stamp());
        assert!(matches!(render(&array), Err(PageError::NotAnObject { line: 2, .. })));
    }

    #[test]
    fn figures_keep_four_significant_digits() {
        assert_eq!(significant(1234.567), "1235");
        assert_eq!(significant(0.012345), "0.01235");
        assert_eq!(significant(5.0), "5.000");
        assert_eq!(significant(0.0), "0");
    }
}
