//! The messages of the TOML and serde errors of a case file, made to say
//! where they are as the value errors of `build.rs` do: the table
//! (`[[floe]] #1`, `[contact]`), the key, a misspelled table called a table,
//! and the closest known name when it is a likely typo (`did you mean`).

use super::Ctx;

/// The largest edit distance at which a known name is offered for an
/// unknown one (`thikness` → `thickness`: 1; `obstacles` → `obstacle`: 1).
const TYPO_DISTANCE: usize = 2;

/// A table header of the file: `[name]` or `[[name]]`.
struct Header {
    /// Its name, dotted, spaces removed (`floe`, `formulation.moreau`).
    name: String,
    /// `[[name]]`: an element of an array of tables.
    array: bool,
    /// Its index among the headers `[[name]]` before it (from 0).
    index: usize,
}

impl Header {
    /// `[[floe]] #1` or `[contact]`, as the value errors name a table.
    fn label(&self) -> String {
        if self.array {
            format!("[[{}]] #{}", self.name, self.index)
        } else {
            format!("[{}]", self.name)
        }
    }
}

/// `Some((name, array))` when `line` is a table header.
fn parse_header(line: &str) -> Option<(String, bool)> {
    let t = line.trim();
    let (array, inner) = match t.strip_prefix("[[") {
        Some(rest) => (true, rest.split_once("]]")?),
        None => (false, t.strip_prefix('[')?.split_once(']')?),
    };
    let (name, rest) = inner;
    let rest = rest.trim_start();
    if !(rest.is_empty() || rest.starts_with('#')) {
        return None;
    }
    let name: String = name.split('.').map(str::trim).collect::<Vec<_>>().join(".");
    let bare = name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '"')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-.\"".contains(c));
    bare.then_some((name, array))
}

/// The edit distance (Levenshtein) between `a` and `b`.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let here = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(here + 1);
            prev = here;
        }
    }
    row[b.len()]
}

/// The known name closest to `unknown`, when within [`TYPO_DISTANCE`] and
/// shorter than the name itself.
pub(crate) fn closest<'a>(unknown: &str, known: &[&'a str]) -> Option<&'a str> {
    known
        .iter()
        .map(|k| (distance(unknown, k), *k))
        .filter(|(d, k)| *d <= TYPO_DISTANCE && *d < k.len())
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// serde's `unknown field `x`, expected one of `a`, `b``: the field and the
/// known names.
fn unknown_field(message: &str) -> Option<(&str, Vec<&str>)> {
    let rest = message.strip_prefix("unknown field `")?;
    let (field, tail) = rest.split_once('`')?;
    let known = tail.split('`').skip(1).step_by(2).collect();
    Some((field, known))
}

impl Ctx<'_> {
    /// The header of the table holding `offset`, and whether the line at
    /// `offset` is that header.
    fn header_at(&self, offset: usize) -> Option<(Header, bool)> {
        let offset = offset.min(self.text.len());
        let mut seen: Vec<(String, usize)> = Vec::new();
        let mut current = None;
        let mut start = 0;
        for line in self.text.split_inclusive('\n') {
            if start > offset {
                break;
            }
            if let Some((name, array)) = parse_header(line) {
                let index = if array {
                    match seen.iter_mut().find(|(n, _)| *n == name) {
                        Some((_, k)) => {
                            *k += 1;
                            *k
                        }
                        None => {
                            seen.push((name.clone(), 0));
                            0
                        }
                    }
                } else {
                    0
                };
                let on_it = offset < start + line.len();
                current = Some((Header { name, array, index }, on_it));
            } else if current.is_some() {
                current = current.map(|(h, _)| (h, false));
            }
            start += line.len();
        }
        current
    }

    /// The key whose value starts at `offset` (`velocity` in
    /// `air = { …, velocity = 15.0 }`), if the value follows its `=`.
    fn key_of_value(&self, offset: usize) -> Option<&str> {
        let offset = offset.min(self.text.len());
        let start = self.text[..offset].rfind('\n').map_or(0, |i| i + 1);
        let before = self.text[start..offset].trim_end();
        let named = before.strip_suffix('=').map(|b| {
            let b = b.trim_end();
            let from = b
                .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'))
                .map_or(0, |i| i + 1);
            &b[from..]
        });
        named.filter(|k| !k.is_empty())
    }

    /// serde's `message` for an error at `offset`, saying where it is: the
    /// table, the key, an unknown table as such, the closest known name.
    pub(super) fn explain(&self, offset: Option<usize>, message: &str) -> String {
        let Some(offset) = offset else {
            return message.to_string();
        };
        let header = self.header_at(offset);
        if let Some((field, known)) = unknown_field(message) {
            let hint = closest(field, &known);
            if let Some((h, true)) = &header {
                // A header names a table, not a key: `[[obstacles]]`.
                let (open, close) = if h.array { ("[[", "]]") } else { ("[", "]") };
                let hint = hint.map_or(String::new(), |k| {
                    let parent = h.name.strip_suffix(field).unwrap_or("");
                    format!(" (did you mean `{open}{parent}{k}{close}`?)")
                });
                let tail = message.split_once(", ").map_or("", |(_, t)| t);
                return format!("unknown table `{open}{}{close}`{hint}, {tail}", h.name);
            }
            let hint = hint.map_or(String::new(), |k| format!(" (did you mean `{k}`?)"));
            let message = message.replacen(&format!("`{field}`"), &format!("`{field}`{hint}"), 1);
            // A key of an inline table: the key holding it (`air`).
            let inline = self.key_at(offset).filter(|k| *k != field);
            return match (&header, inline) {
                (Some((h, _)), Some(k)) => format!("{} `{k}`: {message}", h.label()),
                (Some((h, _)), None) => format!("{}: {message}", h.label()),
                (None, _) => message,
            };
        }
        // Name the keys serde's message does not (`invalid length 3`): the
        // line's first (`air`), and the value's inside it after the message
        // (`velocity` in `air = { …, velocity = 15.0 }`).
        let unnamed = |k: &&str| !message.contains(&format!("`{k}`"));
        let line_key = self.key_at(offset);
        let named = match line_key.filter(unnamed) {
            Some(k) => format!("`{k}`: {message}"),
            None => message.to_string(),
        };
        let named = match self.key_of_value(offset).filter(unnamed) {
            Some(k) if Some(k) != line_key => format!("{named} (the value of `{k}`)"),
            _ => named,
        };
        match header {
            Some((h, _)) if h.array => format!("{}: {named}", h.label()),
            _ => named,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_typos_and_fields_are_read() {
        assert_eq!(
            parse_header("[[ floe ]] # a floe"),
            Some(("floe".into(), true))
        );
        assert_eq!(
            parse_header("[formulation.moreau]"),
            Some(("formulation.moreau".into(), false))
        );
        assert_eq!(parse_header("  [0.0, 1.0],"), None);
        assert_eq!(parse_header("[[0.0, 0.0], [1.0, 0.0]]"), None);
        assert_eq!(distance("thikness", "thickness"), 1);
        assert_eq!(distance("obstacles", "obstacle"), 1);
        assert_eq!(closest("wnd", &["coriolis", "air", "water"]), None);
        assert_eq!(
            closest("frcition", &["restitution", "friction"]),
            Some("friction")
        );
        let (f, known) = unknown_field("unknown field `x`, expected one of `a`, `bc`").unwrap();
        assert_eq!((f, known), ("x", vec!["a", "bc"]));
        let (f, known) = unknown_field("unknown field `x`, expected `a`").unwrap();
        assert_eq!((f, known), ("x", vec!["a"]));
    }
}
