//! Command-line overrides of scene keys: `--set key.path=value` and the shortcut flags.

use super::SceneError;
use std::str::FromStr;

/// One part of a dotted key: a key, with the index of one item when the
/// key holds an array (`bodies[1]`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyPart {
    /// The key.
    pub name: String,
    /// The item of the array the key holds, from 0.
    pub index: Option<usize>,
}

impl std::fmt::Display for KeyPart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.index {
            Some(index) => write!(f, "{}[{index}]", self.name),
            None => write!(f, "{}", self.name),
        }
    }
}

/// The dotted text of key parts: `bodies[1].material.young`.
pub(crate) fn dotted(parts: &[KeyPart]) -> String {
    parts
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(".")
}

/// One change to the parsed scene table, applied before validation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneOverride {
    /// The dotted key, split: `material`, `young`; `bodies[1]`, `material`,
    /// `young` for one item of an array of tables.
    pub path: Vec<KeyPart>,
    /// The new value as TOML text (a bare word that is not TOML is taken as a
    /// string); `None` removes the key.
    pub value: Option<String>,
    /// The flag as the user typed it, for messages (e.g. `--set time.frames=0`).
    pub flag: String,
}

impl SceneOverride {
    /// Sets `key` (dotted) to the TOML value `value`, reported as `flag`.
    pub fn set(key: &str, value: &str, flag: impl Into<String>) -> Result<Self, SceneError> {
        Self::new(key, Some(value.to_owned()), flag.into())
    }

    /// Removes `key` (dotted) if present, reported as `flag`.
    pub fn remove(key: &str, flag: impl Into<String>) -> Result<Self, SceneError> {
        Self::new(key, None, flag.into())
    }

    fn new(key: &str, value: Option<String>, flag: String) -> Result<Self, SceneError> {
        let path = parse_key(key).map_err(|reason| SceneError::BadOverride {
            flag: flag.clone(),
            reason,
        })?;
        Ok(Self { path, value, flag })
    }

    /// The dotted key.
    pub fn key(&self) -> String {
        dotted(&self.path)
    }
}

impl FromStr for SceneOverride {
    type Err = SceneError;

    /// Parses the argument of `--set`: `key.path=value`.
    fn from_str(argument: &str) -> Result<Self, SceneError> {
        let flag = format!("--set {argument}");
        let Some((key, value)) = argument.split_once('=') else {
            return Err(SceneError::BadOverride {
                flag,
                reason: "expected `key.path=value`".into(),
            });
        };
        Self::set(key.trim(), value.trim(), flag)
    }
}

/// Splits a dotted key into its parts; a part may end in `[N]`, the index
/// of one item of an array (`bodies[1].material.young`).
fn parse_key(key: &str) -> Result<Vec<KeyPart>, String> {
    if key.is_empty() {
        return Err("the key is empty (expected e.g. `material.young`)".into());
    }
    key.split('.')
        .map(|part| {
            let (name, index) = match part.split_once('[') {
                Some((name, rest)) => {
                    let digits = rest.strip_suffix(']').ok_or_else(|| {
                        format!("`{key}`: `{part}` has an index without its closing `]`")
                    })?;
                    let index = digits
                        .parse::<usize>()
                        .ok()
                        .filter(|_| digits.bytes().all(|b| b.is_ascii_digit()))
                        .ok_or_else(|| {
                            format!(
                                "`{key}`: the index in `{part}` must be a whole number from 0, \
                                 e.g. `{name}[0]`"
                            )
                        })?;
                    (name, Some(index))
                }
                None => (part, None),
            };
            if name.is_empty() {
                Err(format!("`{key}` has an empty component"))
            } else if !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                Err(format!(
                    "`{key}`: `{part}` is not a plain key (letters, digits, `_`, `-`, and an \
                     index such as `bodies[1]`)"
                ))
            } else {
                Ok(KeyPart {
                    name: name.to_owned(),
                    index,
                })
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_key_and_value() {
        let o: SceneOverride = "material.young=1e3".parse().unwrap();
        assert_eq!(o.key(), "material.young");
        assert_eq!(o.path.len(), 2);
        assert_eq!(o.value.as_deref(), Some("1e3"));
        assert_eq!(o.flag, "--set material.young=1e3");
        let o: SceneOverride = "effects.gravity.acceleration = [0, -2]".parse().unwrap();
        assert_eq!(o.key(), "effects.gravity.acceleration");
        assert_eq!(o.value.as_deref(), Some("[0, -2]"));
    }

    #[test]
    fn an_item_of_an_array_is_addressed_by_its_index() {
        let o: SceneOverride = "bodies[1].material.young=3".parse().unwrap();
        assert_eq!(
            o.path[0],
            KeyPart {
                name: "bodies".into(),
                index: Some(1)
            }
        );
        assert_eq!(o.path[1].index, None);
        assert_eq!(o.key(), "bodies[1].material.young");
        let o: SceneOverride = "effects.pinned[0].release=0.5".parse().unwrap();
        assert_eq!(o.key(), "effects.pinned[0].release");
        assert_eq!(o.path[2].index, None);
        assert_eq!(o.path[1].index, Some(0));
    }

    #[test]
    fn rejects_malformed_arguments() {
        for bad in [
            "material.young",
            "=3",
            "material..young=3",
            "mat rial=2",
            ".x=1",
            "bodies[1.material.young=3",
            "bodies[-1].material.young=3",
            "bodies[x].material.young=3",
            "bodies[+1].material.young=3",
            "[0].x=3",
            "bodies[1][2].x=3",
        ] {
            let err = bad.parse::<SceneOverride>().unwrap_err();
            assert!(
                matches!(err, SceneError::BadOverride { .. }),
                "{bad}: {err}"
            );
            assert!(err.to_string().contains(bad), "{err}");
        }
    }
}
