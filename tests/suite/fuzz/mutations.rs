//! The mutator: numbers replaced by extremes, lines deleted, duplicated or
//! swapped, the keys of two lines swapped, vectors made longer or shorter;
//! and a test of the mutator itself.

use crate::common::cases_dir;
use floebench::rng::SplitMix64;

/// The byte ranges of the numbers of `line` (outside a `#` comment when
/// `comments`).
fn number_spans(line: &str, comments: bool) -> Vec<(usize, usize)> {
    let code = if comments {
        line.split('#').next().unwrap_or("")
    } else {
        line
    };
    let b = code.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            || ((b[i] == b'-' || b[i] == b'+') && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        let inside_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if starts && !inside_word {
            let start = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit()
                    || b[i] == b'.'
                    || b[i] == b'e'
                    || b[i] == b'E'
                    || b[i] == b'_'
                    || ((b[i] == b'-' || b[i] == b'+') && matches!(b[i - 1], b'e' | b'E')))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

/// A replacement for the number `x` (as written): extremes, special
/// values, strings, and changes of scale and type. `json` picks the
/// spellings of the dumps (`NaN`, `Infinity`, `null`).
fn extreme(rng: &mut SplitMix64, x: &str, json: bool) -> String {
    let v: f64 = x.replace('_', "").parse().unwrap_or(1.0);
    // Half the time a change a physicist might make (within the limits,
    // mostly): the runs see those.
    if rng.int_range(0, 1) == 0 {
        let factor = [0.5, 0.9, 1.1, 2.0, 3.0, -1.0, 0.0, 10.0, 0.1, 1.0001][rng.int_range(0, 9)];
        let w = v * factor;
        return if x.contains(['.', 'e', 'E']) || factor.fract() != 0.0 {
            format!("{w:?}")
        } else {
            format!("{}", w as i64)
        };
    }
    let choices: [&dyn Fn() -> String; 24] = [
        &|| "0".into(),
        &|| "0.0".into(),
        &|| format!("-{}", x.trim_start_matches('-')),
        &|| "1e300".into(),
        &|| "-1e308".into(),
        &|| "5e-324".into(),
        &|| "1e-12".into(),
        &|| if json { "NaN" } else { "nan" }.into(),
        &|| if json { "Infinity" } else { "inf" }.into(),
        &|| if json { "-Infinity" } else { "-inf" }.into(),
        &|| if json { "null" } else { "\"nan\"" }.into(),
        &|| format!("\"{x}\""),
        &|| "9223372036854775807".into(),
        &|| "4294967296".into(),
        &|| "-1".into(),
        &|| "1e15".into(),
        &|| format!("{:?}", v * 1000.0),
        &|| format!("{:?}", v / 1000.0),
        &|| format!("{:?}", v * 10.0),
        &|| format!("{:?}", v + 1.0),
        &|| format!("{}", v as i64),
        &|| format!("{:?}", v.trunc()),
        &|| "3e8".into(),
        &|| "1e9".into(),
    ];
    choices[rng.int_range(0, choices.len() - 1)]()
}

/// The key of a `key = value` (TOML) or `"key": value` (JSON) line, as a
/// byte range.
fn key_span(line: &str) -> Option<(usize, usize)> {
    let t = line.trim_start();
    let start = line.len() - t.len();
    if let Some(rest) = t.strip_prefix('"') {
        let end = rest.find('"')?;
        rest[end..]
            .contains(':')
            .then_some((start, start + end + 2))
    } else {
        let eq = t.find('=')?;
        let key = t[..eq].trim_end();
        let bare = !key.is_empty()
            && key
                .bytes()
                .all(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'-');
        bare.then_some((start, start + key.len()))
    }
}

/// `text` with one to three mutations.
pub(super) fn mutate(rng: &mut SplitMix64, text: &str, json: bool) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    // One mutation most often, up to three.
    let rounds = [1, 1, 1, 2, 2, 3][rng.int_range(0, 5)];
    for _ in 0..rounds {
        if lines.is_empty() {
            break;
        }
        let k = rng.int_range(0, lines.len() - 1);
        match rng.int_range(0, 12) {
            // Numbers most often: they carry the physics.
            0..=7 => {
                let spans = number_spans(&lines[k], !json);
                let with: Vec<usize> = (0..lines.len())
                    .filter(|&i| !number_spans(&lines[i], !json).is_empty())
                    .collect();
                let k = if spans.is_empty() && !with.is_empty() {
                    with[rng.int_range(0, with.len() - 1)]
                } else {
                    k
                };
                let spans = number_spans(&lines[k], !json);
                if let Some(&(a, b)) = spans.get(rng.int_range(0, spans.len().max(1) - 1)) {
                    let new = extreme(rng, &lines[k][a..b], json);
                    lines[k].replace_range(a..b, &new);
                }
            }
            8 => {
                lines.remove(k);
            }
            9 => {
                let copy = lines[k].clone();
                lines.insert(k, copy);
            }
            10 => {
                let j = rng.int_range(0, lines.len() - 1);
                lines.swap(k, j);
            }
            11 => {
                // Swap the keys of two lines.
                let keyed: Vec<usize> = (0..lines.len())
                    .filter(|&i| key_span(&lines[i]).is_some())
                    .collect();
                if keyed.len() >= 2 {
                    let a = keyed[rng.int_range(0, keyed.len() - 1)];
                    let b = keyed[rng.int_range(0, keyed.len() - 1)];
                    if let (Some((a0, a1)), Some((b0, b1))) =
                        (key_span(&lines[a]), key_span(&lines[b]))
                    {
                        let (ka, kb) = (lines[a][a0..a1].to_string(), lines[b][b0..b1].to_string());
                        lines[a].replace_range(a0..a1, &kb);
                        let (b0, b1) = key_span(&lines[b]).unwrap_or((b0, b1));
                        lines[b].replace_range(b0..b1, &ka);
                    }
                }
            }
            _ => {
                // A vector one longer or one shorter.
                let line = &mut lines[k];
                let closes: Vec<usize> = line.match_indices(']').map(|(i, _)| i).collect();
                if let Some(&c) = closes.get(rng.int_range(0, closes.len().max(1) - 1)) {
                    if rng.int_range(0, 1) == 0 {
                        line.insert_str(c, ", 1.0");
                    } else if let Some(comma) = line[..c].rfind(',') {
                        if !line[comma..c].contains('[') && !line[comma..c].contains(']') {
                            line.replace_range(comma..c, "");
                        }
                    }
                }
            }
        }
    }
    let mut out = lines.join("\n");
    out.push('\n');
    out
}

#[test]
fn mutations_change_the_text_and_keep_it_mostly_readable() {
    // The mutator itself: each mutant differs from its source; numbers are
    // found outside comments only.
    assert_eq!(
        number_spans("a = [1.5, -2e-3] # 7", true),
        vec![(5, 8), (10, 15)]
    );
    assert_eq!(number_spans("x1 = 3", true), vec![(5, 6)]);
    assert_eq!(key_span("  friction = 0.3"), Some((2, 10)));
    assert_eq!(key_span("  \"q\": [1.0]"), Some((2, 5)));
    let text = std::fs::read_to_string(cases_dir().join("head_on.toml")).unwrap();
    let mut rng = SplitMix64::new(1);
    let changed = (0..200)
        .filter(|_| mutate(&mut rng, &text, false) != text)
        .count();
    assert!(changed > 150, "only {changed} of 200 mutants differ");
}
