//! The varied parameters of a sweep: `--vary KEY=V1,V2,…` and ranges, expanded into runs.
//!
//! A varied key takes a list of TOML values, written like `--set` values and
//! separated by commas at the top level only: a comma inside `[…]`, `{…}` or
//! a quoted string does not split, so
//! `mesh.velocity=[0,-1],[0,-5]` is two vectors and
//! `material.model="a,b","c"` two strings. Two ranges are spelled out:
//!
//! * `linspace(A, B, N)`: `N` evenly spaced values `A + (B − A)·i/(N − 1)`,
//!   `i = 0 … N − 1` (`N = 1` gives `A`);
//! * `logspace(A, B, N)`: `N` values evenly spaced on a log scale *between
//!   the endpoints* `A` and `B` (both `> 0`), `A·(B/A)^(i/(N − 1))`, like
//!   numpy's `geomspace` (not numpy's `logspace`, whose ends are exponents).
//!
//! When both ends are written as integers and every value is a whole number
//! (`linspace(1, 10, 4)` = 1, 4, 7, 10), the values are TOML integers, so
//! integer keys such as `time.substeps` accept them; otherwise they are
//! floats, rounded to 12 significant digits.
//!
//! [`expand`] turns the axes into runs: the cartesian product (the first
//! axis varies slowest, like nested loops written in the order given) or,
//! with `zip`, the i-th value of every axis together (all lists the same
//! length). Each [`RunSpec`] knows its folder name
//! (`0003_material.young=300_time.substeps=10`) and its scene overrides.

use super::SweepError;
use crate::scene::{SceneError, SceneOverride};
use std::path::{Path, PathBuf};

/// The largest number of runs one sweep may have.
pub const MAX_RUNS: usize = 10_000;

/// The longest folder name of a run, in bytes (the values are shortened to fit).
pub const MAX_FOLDER_NAME_BYTES: usize = 120;

/// One value of a varied key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VaryValue {
    /// The value as TOML text, as given to the scene (like a `--set` value).
    pub toml: String,
    /// The value for people: the TOML text without spaces and without the
    /// quotes of a string (e.g. `[0,-1]`, `300`, `neo-hookean`).
    pub label: String,
}

impl VaryValue {
    /// A value from its TOML text (trimmed).
    pub fn from_toml(text: &str) -> Self {
        let toml = text.trim().to_owned();
        let label = label_of(&toml);
        Self { toml, label }
    }
}

/// Where a varied key was given, for messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AxisOrigin {
    /// On the command line, as `--vary KEY=…`.
    Flag,
    /// In the `[vary]` table of this sweep file.
    File(PathBuf),
}

/// One varied key and its list of values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VaryAxis {
    /// The dotted scene key, e.g. `material.young`.
    pub key: String,
    /// Its values, in order (at least one).
    pub values: Vec<VaryValue>,
    /// Where it was given.
    pub origin: AxisOrigin,
}

impl VaryAxis {
    /// The flag or file entry that set `value`, for messages:
    /// `--vary material.young=300` or `sweep.toml: [vary] material.young = 300`.
    pub fn describe(&self, value: &VaryValue) -> String {
        describe(&self.origin, &self.key, value)
    }
}

fn describe(origin: &AxisOrigin, key: &str, value: &VaryValue) -> String {
    match origin {
        AxisOrigin::Flag => format!("--vary {key}={}", value.toml),
        AxisOrigin::File(path) => format!("{}: [vary] {key} = {}", path.display(), value.toml),
    }
}

/// Parses the argument of `--vary`: `KEY=V1,V2,…`, `KEY=linspace(A,B,N)` or
/// `KEY=logspace(A,B,N)`.
pub fn parse_vary(argument: &str) -> Result<VaryAxis, SweepError> {
    let flag = format!("--vary {argument}");
    let bad = |reason: String| SweepError::BadVary {
        flag: flag.clone(),
        reason,
    };
    let (key, list) = argument
        .split_once('=')
        .ok_or_else(|| bad("expected `KEY=V1,V2,…` (e.g. `material.young=100,300`)".into()))?;
    let key = checked_key(key.trim()).map_err(bad)?;
    let values = parse_values(list.trim()).map_err(bad)?;
    Ok(VaryAxis {
        key,
        values,
        origin: AxisOrigin::Flag,
    })
}

/// A varied key of a sweep file's `[vary]` table: an array of values, or a
/// string holding a range (`"linspace(1, 10, 4)"`).
pub fn axis_from_toml(key: &str, value: &toml::Value, file: &Path) -> Result<VaryAxis, SweepError> {
    let bad = |reason: String| SweepError::BadFile {
        path: file.to_owned(),
        reason: format!("`vary.{key}`: {reason}"),
    };
    let key = checked_key(key).map_err(bad)?;
    let values = match value {
        toml::Value::Array(items) if items.is_empty() => {
            return Err(bad("the list of values is empty".into()));
        }
        toml::Value::Array(items) => items
            .iter()
            .map(|v| VaryValue::from_toml(&inline_toml(v)))
            .collect(),
        toml::Value::String(text) if range_call(text).is_some() => {
            parse_values(text).map_err(bad)?
        }
        other => {
            return Err(bad(format!(
                "expected an array of values (e.g. [100, 300]) or a range string \
                 (\"linspace(A, B, N)\" or \"logspace(A, B, N)\"), got `{}`",
                inline_toml(other)
            )));
        }
    };
    Ok(VaryAxis {
        key,
        values,
        origin: AxisOrigin::File(file.to_owned()),
    })
}

/// A TOML value as inline TOML text.
fn inline_toml(value: &toml::Value) -> String {
    value.to_string()
}

/// Checks a dotted key the way `--set` does.
fn checked_key(key: &str) -> Result<String, String> {
    SceneOverride::set(key, "0", String::new())
        .map(|o| o.key())
        .map_err(|e| match e {
            SceneError::BadOverride { reason, .. } => reason,
            other => other.to_string(),
        })
}

/// The values of a list or a range.
fn parse_values(list: &str) -> Result<Vec<VaryValue>, String> {
    if let Some((kind, args)) = range_call(list) {
        return range(kind, args);
    }
    let items = split_top_level(list)?;
    let mut values = Vec::with_capacity(items.len());
    for item in items {
        let item = item.trim();
        if item.is_empty() {
            return Err(if list.is_empty() {
                "the list of values is empty".into()
            } else {
                format!("an empty value in `{list}` (two commas in a row, or one at an end)")
            });
        }
        values.push(VaryValue::from_toml(item));
    }
    Ok(values)
}

/// Splits at commas that are outside brackets, braces and quoted strings.
fn split_top_level(list: &str) -> Result<Vec<&str>, String> {
    let mut items = Vec::new();
    let mut depth: Vec<char> = Vec::new();
    let mut quote: Option<char> = None;
    let mut escaped = false;
    let mut start = 0;
    for (i, c) in list.char_indices() {
        if let Some(q) = quote {
            if escaped {
                escaped = false;
            } else if c == '\\' && q == '"' {
                escaped = true;
            } else if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            '"' | '\'' => quote = Some(c),
            '[' => depth.push(']'),
            '{' => depth.push('}'),
            ']' | '}' if depth.pop() != Some(c) => {
                return Err(format!("unbalanced `{c}` in `{list}`"));
            }
            ',' if depth.is_empty() => {
                items.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    if quote.is_some() {
        return Err(format!("unterminated string in `{list}`"));
    }
    if let Some(close) = depth.last() {
        return Err(format!("missing `{close}` in `{list}`"));
    }
    items.push(&list[start..]);
    Ok(items)
}

/// Which range function a value list calls, and its argument text.
fn range_call(list: &str) -> Option<(RangeKind, &str)> {
    let list = list.trim();
    for (name, kind) in [
        ("linspace", RangeKind::Linear),
        ("logspace", RangeKind::Log),
    ] {
        if let Some(rest) = list.strip_prefix(name) {
            let rest = rest.trim_start();
            if let Some(args) = rest.strip_prefix('(') {
                return Some((kind, args));
            }
        }
    }
    None
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RangeKind {
    Linear,
    Log,
}

impl RangeKind {
    fn name(self) -> &'static str {
        match self {
            RangeKind::Linear => "linspace",
            RangeKind::Log => "logspace",
        }
    }
}

/// The values of `linspace(A, B, N)` / `logspace(A, B, N)`; `args` is the
/// text after the opening parenthesis.
fn range(kind: RangeKind, args: &str) -> Result<Vec<VaryValue>, String> {
    let name = kind.name();
    let usage = format!("expected `{name}(A, B, N)` with numbers A, B and a count N ≥ 1");
    let inner = args
        .trim_end()
        .strip_suffix(')')
        .ok_or_else(|| format!("`{name}(` is not closed: {usage}"))?;
    let parts: Vec<&str> = inner.split(',').map(str::trim).collect();
    let [a, b, n] = parts[..] else {
        return Err(format!(
            "`{name}({inner})` has {} arguments: {usage}",
            parts.len()
        ));
    };
    let number = |text: &str| -> Result<f64, String> {
        match text.replace('_', "").parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!(
                "`{name}({inner})`: `{text}` is not a finite number"
            )),
        }
    };
    let (start, end) = (number(a)?, number(b)?);
    let count = match n.parse::<u64>() {
        Ok(count) if count >= 1 => count as usize,
        _ => {
            return Err(format!(
                "`{name}({inner})`: the count `{n}` must be a whole number ≥ 1"
            ));
        }
    };
    if count > MAX_RUNS {
        return Err(format!(
            "`{name}({inner})`: the count {count} is more than the {MAX_RUNS} runs a sweep may have"
        ));
    }
    if kind == RangeKind::Log && !(start > 0.0 && end > 0.0) {
        return Err(format!(
            "`{name}({inner})`: both ends must be positive (the values are spaced \
             evenly on a log scale between them)"
        ));
    }
    let at = |i: usize| -> f64 {
        if count == 1 || i == 0 {
            return start;
        }
        if i == count - 1 {
            return end;
        }
        let t = i as f64 / (count - 1) as f64;
        match kind {
            RangeKind::Linear => start + (end - start) * t,
            RangeKind::Log => start * (end / start).powf(t),
        }
    };
    let raw: Vec<f64> = (0..count).map(at).collect();
    let integer_ends = is_integer_text(a) && is_integer_text(b);
    let whole = |x: f64| (x - x.round()).abs() <= 1e-9 * x.abs().max(1.0);
    let as_integers = integer_ends && raw.iter().all(|&x| whole(x) && x.abs() < 9e15);
    Ok(raw
        .into_iter()
        .map(|x| {
            let text = if as_integers {
                format!("{}", x.round() as i64)
            } else {
                float_text(x)
            };
            VaryValue::from_toml(&text)
        })
        .collect())
}

fn is_integer_text(text: &str) -> bool {
    let digits = text
        .strip_prefix(['-', '+'])
        .unwrap_or(text)
        .replace('_', "");
    !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit())
}

/// A float as TOML float text, rounded to 12 significant digits (`0.1`,
/// `3.0`, `1e20`, `3.16227766017`).
fn float_text(x: f64) -> String {
    let rounded: f64 = format!("{x:.11e}")
        .parse()
        .expect("a formatted float parses");
    // `Debug` always writes a float form: `3.0`, `1e20`, `1e-7`.
    format!("{rounded:?}")
}

/// The label of a TOML value text: spaces outside strings dropped, string
/// quotes dropped.
fn label_of(toml: &str) -> String {
    let mut label = String::with_capacity(toml.len());
    let mut quote: Option<char> = None;
    let mut escaped = false;
    for c in toml.chars() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                    label.push(c);
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                } else {
                    label.push(c);
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                c if c.is_whitespace() => {}
                c => label.push(c),
            },
        }
    }
    label
}

/// One run of a sweep: its index and the value of every varied key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunSpec {
    /// Position in the sweep, from 0 (the order of [`expand`]).
    pub index: usize,
    /// Each varied key with its value in this run, in the order of the axes.
    pub values: Vec<(String, VaryValue)>,
    /// Where each value was given (parallel to `values`), for messages.
    origins: Vec<AxisOrigin>,
}

impl RunSpec {
    /// A run with these values, all given on the command line.
    pub fn new(index: usize, values: Vec<(String, VaryValue)>) -> Self {
        let origins = vec![AxisOrigin::Flag; values.len()];
        Self {
            index,
            values,
            origins,
        }
    }

    /// The run's folder name: the index padded to 4 digits, then
    /// `_key=value` for every varied key, e.g.
    /// `0003_material.young=300_time.substeps=10`. Only ASCII letters,
    /// digits and `. , = + - _` appear (brackets, quotes and spaces are
    /// dropped, other characters become `_`), and the name is at most
    /// [`MAX_FOLDER_NAME_BYTES`] long (values are cut, the index keeps
    /// names unique).
    pub fn folder_name(&self) -> String {
        let mut name = format!("{:04}", self.index);
        for (key, value) in &self.values {
            name.push('_');
            name.push_str(&filesystem_safe(key));
            name.push('=');
            name.push_str(&filesystem_safe(&value.label));
        }
        if name.len() > MAX_FOLDER_NAME_BYTES {
            name.truncate(MAX_FOLDER_NAME_BYTES);
        }
        name
    }

    /// A label for people: `material.young=300, time.substeps=10` (`(no
    /// varied keys)` for a sweep of one run without `--vary`).
    pub fn label(&self) -> String {
        if self.values.is_empty() {
            return "(no varied keys)".into();
        }
        self.values
            .iter()
            .map(|(key, value)| format!("{key}={}", value.label))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The scene overrides that make this run (apply them after the
    /// sweep's `--set` overrides); each names its `--vary` flag or sweep file
    /// entry in messages.
    pub fn overrides(&self) -> Result<Vec<SceneOverride>, SceneError> {
        self.values
            .iter()
            .zip(&self.origins)
            .map(|((key, value), origin)| {
                SceneOverride::set(key, &value.toml, describe(origin, key, value))
            })
            .collect()
    }
}

/// Keeps ASCII letters, digits and `.,=+-_`; drops brackets, braces, quotes
/// and whitespace; replaces anything else with `_`.
fn filesystem_safe(text: &str) -> String {
    text.chars()
        .filter(|c| !matches!(c, '[' | ']' | '{' | '}' | '"' | '\'') && !c.is_whitespace())
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | ',' | '=' | '+' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The runs of a sweep: the cartesian product of the axes (first axis
/// slowest) or, with `zip`, their values taken together position by
/// position. No axes give one run with no varied key.
pub fn expand(axes: &[VaryAxis], zip: bool) -> Result<Vec<RunSpec>, SweepError> {
    for (i, axis) in axes.iter().enumerate() {
        if axes[..i].iter().any(|other| other.key == axis.key) {
            return Err(SweepError::DuplicateKey {
                key: axis.key.clone(),
            });
        }
        if axis.values.is_empty() {
            return Err(SweepError::BadVary {
                flag: format!("--vary {}=", axis.key),
                reason: "the list of values is empty".into(),
            });
        }
    }
    let origins: Vec<AxisOrigin> = axes.iter().map(|a| a.origin.clone()).collect();
    let run = |index: usize, picks: &[usize]| RunSpec {
        index,
        values: axes
            .iter()
            .zip(picks)
            .map(|(axis, &p)| (axis.key.clone(), axis.values[p].clone()))
            .collect(),
        origins: origins.clone(),
    };
    if zip {
        let len = axes.first().map_or(1, |a| a.values.len());
        if axes.iter().any(|a| a.values.len() != len) {
            let lengths = axes
                .iter()
                .map(|a| format!("{}: {}", a.key, a.values.len()))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(SweepError::ZipLengths { lengths });
        }
        if len > MAX_RUNS {
            return Err(SweepError::TooManyRuns {
                runs: len as u128,
                max: MAX_RUNS,
            });
        }
        return Ok((0..len).map(|i| run(i, &vec![i; axes.len()])).collect());
    }
    let total: u128 = axes.iter().map(|a| a.values.len() as u128).product();
    if total > MAX_RUNS as u128 {
        return Err(SweepError::TooManyRuns {
            runs: total,
            max: MAX_RUNS,
        });
    }
    let mut runs = Vec::with_capacity(total as usize);
    let mut picks = vec![0usize; axes.len()];
    for index in 0..total as usize {
        runs.push(run(index, &picks));
        // Odometer: the last axis turns fastest.
        for (pick, axis) in picks.iter_mut().zip(axes).rev() {
            *pick += 1;
            if *pick < axis.values.len() {
                break;
            }
            *pick = 0;
        }
    }
    Ok(runs)
}

#[cfg(test)]
mod tests;
