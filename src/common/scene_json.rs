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
