//! A parsed scene file with its overrides merged in, keeping every key's position.
//!
//! The file is parsed into toml's spanned tree (`DeTable`); each override is
//! parsed on its own and grafted in with *virtual* spans past the end of the
//! file text: override `k` owns the range starting at
//! `len + 1 + k * OVERRIDE_SPAN`, its key part at depth `d` gets offset `d`
//! and its value the offset after the last key part. Every later error
//! carries a span, so it can say whether the bad value came from the file
//! (then with its line and column) or from which flag, and which key it is.

use super::raw_scene::{RawScene, choices};
use super::scene_error::{Diagnostic, Origin, SceneError, num};
use super::scene_override::{KeyPart, dotted};
use super::{SceneOverride, SceneSource};
use serde::Deserialize;
use std::borrow::Cow;
use std::ops::Range;
use toml::Spanned;
use toml::de::{DeArray, DeTable, DeValue};

/// Width of the virtual span range of one override (more than any key depth).
const OVERRIDE_SPAN: usize = 1 << 16;

/// The merged tree and what is needed to explain a span.
pub(crate) struct SceneDocument<'a> {
    source: &'a SceneSource,
    overrides: &'a [SceneOverride],
    root: Spanned<DeTable<'a>>,
}

impl<'a> SceneDocument<'a> {
    /// Parses the source and applies the overrides in order.
    pub fn parse(
        source: &'a SceneSource,
        overrides: &'a [SceneOverride],
    ) -> Result<Self, SceneError> {
        let mut root = DeTable::parse(&source.text).map_err(|e| {
            let mut reason = format!("invalid TOML: {}", e.message().trim_end());
            if reason.ends_with(':') {
                reason.pop();
            }
            let mut key = None;
            if let Some(span) = e
                .span()
                .filter(|_| e.message().starts_with("duplicate key"))
            {
                key = duplicate_key(&source.text, span);
                reason = "is given more than once (invalid TOML: duplicate key)".to_owned();
            }
            let origin = e
                .span()
                .map(|s| file_position(&source.text, s.start))
                .unwrap_or(Origin::Scene);
            SceneError::Invalid(Box::new(Diagnostic {
                source: source.label.clone(),
                origin,
                key,
                reason,
            }))
        })?;
        let base = source.text.len() + 1;
        for (k, o) in overrides.iter().enumerate() {
            apply(root.get_mut(), o, base + k * OVERRIDE_SPAN).map_err(|reason| {
                SceneError::Invalid(Box::new(Diagnostic {
                    source: source.label.clone(),
                    origin: Origin::Flag(o.flag.clone()),
                    key: Some(o.key()),
                    reason,
                }))
            })?;
        }
        Ok(Self {
            source,
            overrides,
            root,
        })
    }

    /// Deserialises the merged tree; serde errors are located by their span.
    pub fn deserialize(&self) -> Result<RawScene, SceneError> {
        let deserializer = toml::de::Deserializer::from(self.root.clone());
        RawScene::deserialize(deserializer).map_err(|e| {
            let span = e.span();
            let key = span
                .as_ref()
                .and_then(|s| path_at(self.root.get_ref(), s, &mut Vec::new()));
            let origin = span.map(|s| self.origin_of(&s)).unwrap_or(Origin::Scene);
            SceneError::Invalid(Box::new(Diagnostic {
                source: self.source.label.clone(),
                origin,
                reason: plain_reason(key.as_deref(), e.message().trim_end()),
                key,
            }))
        })
    }

    /// A diagnostic for `key` (dotted): located at the key's value when it is
    /// present, else at the nearest present parent table.
    pub fn error(&self, key: &str, reason: impl Into<String>) -> SceneError {
        let parts: Vec<&str> = key.split('.').collect();
        let mut table = self.root.get_ref();
        let mut span = None;
        for (i, part) in parts.iter().enumerate() {
            // `bodies[1]`: item 1 of the array `bodies`.
            let (name, index) = match part.strip_suffix(']').and_then(|p| p.split_once('[')) {
                Some((name, index)) => (name, index.parse::<usize>().ok()),
                None => (*part, None),
            };
            let Some(mut value) = table.get(name) else {
                break;
            };
            if let (Some(index), DeValue::Array(items)) = (index, value.get_ref()) {
                span = Some(value.span());
                let Some(item) = items.get(index) else { break };
                value = item;
            }
            span = Some(value.span());
            match value.get_ref() {
                DeValue::Table(t) if i + 1 < parts.len() => table = t,
                _ => break,
            }
        }
        let origin = span.map(|s| self.origin_of(&s)).unwrap_or(Origin::Scene);
        SceneError::Invalid(Box::new(Diagnostic {
            source: self.source.label.clone(),
            origin,
            key: Some(key.to_owned()),
            reason: reason.into(),
        }))
    }

    /// The label of the source, for messages.
    pub fn source(&self) -> &SceneSource {
        self.source
    }

    /// The overrides applied, in order.
    pub fn overrides(&self) -> &[SceneOverride] {
        self.overrides
    }

    fn origin_of(&self, span: &Range<usize>) -> Origin {
        let base = self.source.text.len() + 1;
        if span.start >= base {
            match self.overrides.get((span.start - base) / OVERRIDE_SPAN) {
                Some(o) => Origin::Flag(o.flag.clone()),
                None => Origin::Scene,
            }
        } else {
            file_position(&self.source.text, span.start)
        }
    }
}

/// A serde message in the words of the scene file: TOML types instead of
/// Rust ones, and the accepted names where a name is expected.
fn plain_reason(key: Option<&str>, message: &str) -> String {
    if message.contains("wanted string or table") {
        return match key.and_then(choices) {
            Some(names) => format!("expected one of {names}"),
            None if key.is_some_and(|k| TABLES.contains(&k)) => "expected a table".to_owned(),
            None => "expected a string".to_owned(),
        };
    }
    let mut reason = message.to_owned();
    for (rust, toml) in [
        ("expected i64", "expected a whole number"),
        ("expected u64", "expected a whole number"),
        ("expected f64", "expected a number"),
        ("expected a sequence", "expected an array"),
        ("invalid type: sequence", "invalid type: array"),
        ("invalid type: map", "invalid type: table"),
        ("floating point", "number"),
    ] {
        reason = reason.replace(rust, toml);
    }
    // serde spells floats out in full (`1e300` as 301 digits).
    if let Some(start) = reason.find("number `").map(|i| i + "number `".len())
        && let Some(len) = reason[start..].find('`')
        && let Ok(x) = reason[start..start + len].parse::<f64>()
    {
        reason.replace_range(start..start + len, &num(x));
    }
    reason
}

/// The keys that hold tables.
const TABLES: &[&str] = &[
    "mesh",
    "material",
    "time",
    "solver",
    "effects",
    "effects.gravity",
    "effects.ground",
    "effects.pinned",
    "render",
    "render.camera",
];

/// The dotted key of a duplicate-key error at `span`: the key text there,
/// inside the table whose header comes last before it.
fn duplicate_key(text: &str, span: Range<usize>) -> Option<String> {
    let token = text.get(span.clone())?.trim().trim_matches('"');
    if token.is_empty() || token.contains('\n') {
        return None;
    }
    let line_start = text[..span.start].rfind('\n').map_or(0, |i| i + 1);
    if text[line_start..span.start].trim_start().starts_with('[') {
        // The header itself is repeated: `[material]` twice.
        return Some(token.to_owned());
    }
    let table = text[..line_start].lines().rev().find_map(|line| {
        let line = line.trim();
        line.starts_with('[').then(|| {
            line.trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_owned()
        })
    });
    Some(match table {
        Some(table) if !table.is_empty() => format!("{table}.{token}"),
        _ => token.to_owned(),
    })
}

/// 1-based line and column (in characters) of a byte offset.
fn file_position(text: &str, offset: usize) -> Origin {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = text[line_start..offset].chars().count() + 1;
    Origin::File { line, column }
}

/// Grafts one override into the tree; its virtual spans start at `start`.
/// A key part with an index (`bodies[1]`) steps into that item of an
/// existing array; a key part without one must not name an array of tables
/// (the message says how to index it).
fn apply<'a>(root: &mut DeTable<'a>, o: &'a SceneOverride, start: usize) -> Result<(), String> {
    let (last, parents) = o
        .path
        .split_last()
        .expect("an override key has at least one part");
    let at = |depth: usize| start + depth..start + depth + 1;
    let mut table = root;
    for (depth, part) in parents.iter().enumerate() {
        let walked = dotted(&o.path[..=depth]);
        let entry = match part.index {
            Some(index) => item_mut(table, part, index, &walked)?,
            None => {
                let entry = table
                    .entry(Spanned::new(at(depth), Cow::Borrowed(part.name.as_str())))
                    .or_insert_with(|| Spanned::new(at(depth), DeValue::Table(DeTable::new())));
                if let DeValue::Array(items) = entry.get_ref() {
                    return Err(array_without_index(&walked, items, &o.path[depth + 1..]));
                }
                entry
            }
        };
        match entry.get_mut() {
            DeValue::Table(t) => table = t,
            other => {
                return Err(format!("`{walked}` is a {}, not a table", other.type_str()));
            }
        }
    }
    let span = at(o.path.len());
    let value = o.value.as_ref().map(|text| match DeValue::parse(text) {
        Ok(v) => respan(v.into_inner(), &span),
        // Not a TOML value: take the text as a string, so that
        // `--set material.model=neo-hookean` needs no quotes.
        Err(_) => Spanned::new(span, DeValue::String(Cow::Borrowed(text.as_str()))),
    });
    match (last.index, value) {
        (Some(index), Some(value)) => {
            *item_mut(table, last, index, &o.key())? = value;
        }
        (Some(_), None) => {
            return Err(format!(
                "`{}`: one item of an array cannot be removed",
                o.key()
            ));
        }
        (None, value) => {
            table.remove(last.name.as_str());
            if let Some(value) = value {
                table.insert(
                    Spanned::new(at(parents.len()), Cow::Borrowed(last.name.as_str())),
                    value,
                );
            }
        }
    }
    Ok(())
}

/// Item `index` of the array `part.name` of `table` (`walked`: the key up to
/// and with it, for messages).
fn item_mut<'t, 'a>(
    table: &'t mut DeTable<'a>,
    part: &KeyPart,
    index: usize,
    walked: &str,
) -> Result<&'t mut Spanned<DeValue<'a>>, String> {
    let name = &part.name;
    let Some(value) = table.get_mut(name.as_str()) else {
        return Err(format!(
            "the scene has no `{name}`, so `{walked}` names no item (an index addresses one \
             item of an array that is there)"
        ));
    };
    let items = match value.get_mut() {
        DeValue::Array(items) => items,
        other => {
            let whole = walked.strip_suffix(&format!("[{index}]")).unwrap_or(walked);
            return Err(format!(
                "`{whole}` is a {}, not an array: drop the index `[{index}]`",
                other.type_str()
            ));
        }
    };
    let count = items.len();
    items.get_mut(index).ok_or_else(|| match count {
        0 => format!("index {index} of `{walked}` is out of range: `{name}` is empty"),
        1 => format!("index {index} of `{walked}` is out of range: `{name}` has 1 item, `[0]`"),
        n => format!(
            "index {index} of `{walked}` is out of range: `{name}` has {n} items, `[0]` to \
             `[{}]`",
            n - 1
        ),
    })
}

/// The message for a key that steps through an array without an index.
fn array_without_index(walked: &str, items: &DeArray<'_>, rest: &[KeyPart]) -> String {
    let tables = items
        .iter()
        .all(|item| matches!(item.get_ref(), DeValue::Table(_)));
    if !tables || items.is_empty() {
        return format!(
            "`{walked}` is an array of {} values, not a table",
            items.len()
        );
    }
    let example = format!("{walked}[0].{}", dotted(rest));
    match items.len() {
        1 => format!("`{walked}` is an array of 1 table: address it by its index, `{example}`"),
        n => format!(
            "`{walked}` is an array of {n} tables: address one by its index, `{walked}[0]` to \
             `{walked}[{}]`, e.g. `{example}`",
            n - 1
        ),
    }
}

/// Gives a value and everything inside it the override's virtual span.
fn respan<'a>(value: DeValue<'a>, span: &Range<usize>) -> Spanned<DeValue<'a>> {
    let value = match value {
        DeValue::Array(items) => DeValue::Array(
            items
                .into_iter()
                .map(|v| respan(v.into_inner(), span))
                .collect::<DeArray<'a>>(),
        ),
        DeValue::Table(t) => {
            let mut out = DeTable::new();
            for (k, v) in t {
                out.insert(
                    Spanned::new(span.clone(), k.into_inner()),
                    respan(v.into_inner(), span),
                );
            }
            DeValue::Table(out)
        }
        other => other,
    };
    Spanned::new(span.clone(), value)
}

/// The dotted path of the entry whose key span equals `span` or whose value
/// span contains it, searching depth first (the deepest match wins).
fn path_at(table: &DeTable<'_>, span: &Range<usize>, prefix: &mut Vec<String>) -> Option<String> {
    for (key, value) in table.iter() {
        prefix.push(key.get_ref().to_string());
        let inner = match value.get_ref() {
            DeValue::Table(inner) => path_at(inner, span, prefix),
            // `[[effects.pinned]]`: item `i` is `effects.pinned[i]`.
            DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| {
                let DeValue::Table(inner) = item.get_ref() else {
                    return None;
                };
                let name = format!("{}[{i}]", key.get_ref());
                let last = prefix.len() - 1;
                let whole = std::mem::replace(&mut prefix[last], name);
                let found = path_at(inner, span, prefix).or_else(|| {
                    let s = item.span();
                    (s.start <= span.start && span.end <= s.end && s != (0..0))
                        .then(|| prefix.join("."))
                });
                prefix[last] = whole;
                found
            }),
            _ => None,
        };
        if inner.is_some() {
            return inner;
        }
        let value_span = value.span();
        if key.span() == *span || (value_span.start <= span.start && span.end <= value_span.end) {
            let found = prefix.join(".");
            prefix.pop();
            return Some(found);
        }
        prefix.pop();
    }
    None
}
