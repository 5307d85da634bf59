//! Command-line overrides of scene keys: `--set key.path=value` and the shortcut flags.

use super::SceneError;
use std::str::FromStr;

/// One change to the parsed scene table, applied before validation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneOverride {
    /// The dotted key, split: `["material", "young"]`.
    pub path: Vec<String>,
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
        self.path.join(".")
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

fn parse_key(key: &str) -> Result<Vec<String>, String> {
    if key.is_empty() {
        return Err("the key is empty (expected e.g. `material.young`)".into());
    }
    key.split('.')
        .map(|part| {
            if part.is_empty() {
                Err(format!("`{key}` has an empty component"))
            } else if !part
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                Err(format!(
                    "`{key}`: `{part}` is not a plain key (letters, digits, `_`, `-`)"
                ))
            } else {
                Ok(part.to_owned())
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
        assert_eq!(o.path, vec!["material", "young"]);
        assert_eq!(o.value.as_deref(), Some("1e3"));
        assert_eq!(o.flag, "--set material.young=1e3");
        let o: SceneOverride = "effects.gravity.acceleration = [0, -2]".parse().unwrap();
        assert_eq!(o.key(), "effects.gravity.acceleration");
        assert_eq!(o.value.as_deref(), Some("[0, -2]"));
    }

    #[test]
    fn rejects_malformed_arguments() {
        for bad in [
            "material.young",
            "=3",
            "material..young=3",
            "mat rial=2",
            ".x=1",
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
