//! The one reader of scene files, for both systems: serde errors become
//! `file:line:column: key.path: message` and unknown keys become warnings.

use serde::Deserialize;

/// Keys the starter's user interface reads that do not affect the simulation; accepted silently.
const UI_ONLY_KEYS: &[&str] = &["show_contacts", "is_running"];

/// A scene that cannot be loaded; the message is one line naming the file.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct SceneError(pub String);

/// Deserialises `text`, naming `source` in errors and warning about keys nobody reads.
pub fn from_str<T: for<'de> Deserialize<'de>>(
    text: &str,
    source: &str,
    warnings: &mut Vec<String>,
) -> Result<T, SceneError> {
    let mut unknown = Vec::new();
    let mut de = serde_json::Deserializer::from_str(text);
    let mut record_unknown = |path: serde_ignored::Path<'_>| unknown.push(path.to_string());
    let ignored = serde_ignored::Deserializer::new(&mut de, &mut record_unknown);
    let value: T = serde_path_to_error::deserialize(ignored).map_err(|e| {
        // serde_path_to_error writes "?" for a segment it could not name (inside a syntax error).
        let path = e
            .path()
            .to_string()
            .trim_end_matches(".?")
            .trim_end_matches('?')
            .to_string();
        let inner = e.into_inner();
        let message = inner.to_string();
        // serde_json appends " at line L column C"; we put the position in front instead.
        let message = message.split(" at line ").next().unwrap_or(&message);
        let location = if inner.line() > 0 {
            format!("{source}:{}:{}", inner.line(), inner.column())
        } else {
            source.to_string()
        };
        if path.is_empty() || path == "." {
            SceneError(format!("{location}: {message}"))
        } else {
            SceneError(format!("{location}: {path}: {message}"))
        }
    })?;
    de.end().map_err(|e| {
        SceneError(format!(
            "{source}:{}:{}: trailing characters after the JSON value",
            e.line(),
            e.column()
        ))
    })?;
    for key in unknown {
        if !UI_ONLY_KEYS.iter().any(|k| key.ends_with(k)) {
            warnings.push(format!("{source}: unknown key `{key}` ignored"));
        }
    }
    Ok(value)
}

/// Scene parameters given on the command line, `--set KEY=VALUE`, in order. A value is read as
/// JSON (`50`, `0.3`, `true`, `[0, -9.8, 0]`), else as a string (`integrator=body`), and is
/// checked by the same reader as a file's value of that key.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides(pub Vec<(String, serde_json::Value)>);

impl Overrides {
    /// Parses `KEY=VALUE` texts; a malformed one is an error naming it.
    pub fn parse(texts: &[String]) -> Result<Overrides, String> {
        let mut out = Vec::new();
        for text in texts {
            let Some((key, value)) = text.split_once('=') else {
                return Err(format!("--set {text:?}: expected KEY=VALUE"));
            };
            let key = key.trim();
            if key.is_empty() {
                return Err(format!("--set {text:?}: the key is empty"));
            }
            if out.iter().any(|(k, _): &(String, _)| k == key) {
                return Err(format!("--set {key}: given twice"));
            }
            let value = serde_json::from_str(value.trim())
                .unwrap_or_else(|_| serde_json::Value::String(value.trim().to_string()));
            out.push((key.to_string(), value));
        }
        Ok(Overrides(out))
    }

    /// Whether none is given.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// `KEY=VALUE` for each, as given (for the summary and the trace header).
    pub fn describe(&self) -> Vec<String> {
        self.0
            .iter()
            .map(|(k, v)| match v {
                serde_json::Value::String(s) => format!("{k}={s}"),
                v => format!("{k}={v}"),
            })
            .collect()
    }

    /// Checks each override alone as a value of `T` (the JSON shape of the parameters it
    /// overrides, named `what` in messages): an unknown key or a bad value is an error naming the
    /// key, with the reader's message.
    pub fn check<T: for<'de> Deserialize<'de>>(&self, what: &str) -> Result<(), SceneError> {
        for (key, value) in &self.0 {
            let one =
                serde_json::Value::Object([(key.clone(), value.clone())].into_iter().collect());
            let mut unknown = false;
            let mut record_unknown = |_: serde_ignored::Path<'_>| unknown = true;
            let ignored = serde_ignored::Deserializer::new(one, &mut record_unknown);
            let checked: Result<T, _> = serde_path_to_error::deserialize(ignored);
            if let Err(e) = checked {
                return Err(SceneError(format!(
                    "--set {key}={value}: {}",
                    e.into_inner()
                )));
            }
            if unknown {
                let hint = other_systems_name(key)
                    .map(|(system, name)| format!(" (its {system} name is `{name}`)"))
                    .unwrap_or_default();
                return Err(SceneError(format!(
                    "--set {key}: not a key of {what}{hint}"
                )));
            }
        }
        Ok(())
    }

    /// Writes every override into `target` (a JSON object), replacing what is there.
    pub fn apply(&self, target: &mut serde_json::Map<String, serde_json::Value>) {
        for (key, value) in &self.0 {
            target.insert(key.clone(), value.clone());
        }
    }
}

/// The keys the two systems name differently for the same setting, 3D first, 2D second: so that
/// `--set pgs_order=…` on a 2D scene, or `--set order=…` on a 3D one, says what to write
/// instead.
const NAMES_3D_2D: [(&str, &str); 5] = [
    ("pgs_order", "order"),
    ("pgs_seed", "seed"),
    ("pgs_iterations", "iterations"),
    ("dt", "step"),
    ("stabilization_slop", "slop"),
];

/// For a key of one system, the system and name of the same setting in the other.
fn other_systems_name(key: &str) -> Option<(&'static str, &'static str)> {
    NAMES_3D_2D.iter().find_map(|&(three, two)| {
        if key == three {
            Some(("2D", two))
        } else if key == two {
            Some(("3D", three))
        } else {
            None
        }
    })
}
