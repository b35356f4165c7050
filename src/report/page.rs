//! A minimal document model for the report page, written once and rendered
//! both as Markdown (`index.md`) and as self-contained HTML (`index.html`,
//! inline style, no script, no external resource: images are linked by
//! relative path).

use std::fmt::Write as _;

/// A block of the report page. Text may hold Markdown's `**bold**` and
/// `` `code` `` spans (rendered as `<b>` and `<code>` in HTML).
#[derive(Debug, Clone, PartialEq)]
pub enum Block {
    /// A heading of level 1 to 3.
    Heading(u8, String),
    /// A paragraph of plain text (`**bold**` spans allowed).
    Para(String),
    /// A bulleted list of plain-text items.
    List(Vec<String>),
    /// A table with a header row; cells are plain text.
    Table {
        /// Column titles.
        header: Vec<String>,
        /// Rows of cells.
        rows: Vec<Vec<String>>,
    },
    /// Images side by side: (alternative text, relative path of the PNG, relative path of the SVG).
    Figures(Vec<(String, String, String)>),
    /// An animation (GIF) shown at its own size and linked: (alternative
    /// text, relative path).
    Animation(String, String),
    /// Preformatted text.
    Pre(String),
}

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The page as Markdown.
pub fn markdown(blocks: &[Block]) -> String {
    let mut s = String::new();
    for b in blocks {
        match b {
            Block::Heading(level, text) => {
                let _ = writeln!(
                    s,
                    "{} {text}\n",
                    "#".repeat(usize::from(*level).clamp(1, 6))
                );
            }
            Block::Para(text) => {
                let _ = writeln!(s, "{text}\n");
            }
            Block::List(items) => {
                for i in items {
                    let _ = writeln!(s, "- {i}");
                }
                s.push('\n');
            }
            Block::Table { header, rows } => {
                let line = |cells: &[String]| {
                    let cells: Vec<String> = cells.iter().map(|c| md_cell(c)).collect();
                    format!("| {} |\n", cells.join(" | "))
                };
                s.push_str(&line(header));
                let _ = writeln!(s, "|{}", " --- |".repeat(header.len()));
                for r in rows {
                    s.push_str(&line(r));
                }
                s.push('\n');
            }
            Block::Figures(figs) => {
                for (alt, png, svg) in figs {
                    let _ = writeln!(s, "[![{alt}]({png})]({svg})");
                }
                s.push('\n');
            }
            Block::Animation(alt, path) => {
                let _ = writeln!(s, "[![{alt}]({path})]({path})\n");
            }
            Block::Pre(text) => {
                let _ = writeln!(s, "```text\n{}\n```\n", text.trim_end());
            }
        }
    }
    s
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Escapes `s` for HTML and renders its Markdown spans: `` `code` `` as
/// `<code>` (taken literally inside), `**bold**` as `<b>`.
fn inline(s: &str) -> String {
    let mut out = String::new();
    let mut bold = false;
    for (k, piece) in s.split('`').enumerate() {
        // An unmatched last backtick is literal text.
        let code = k % 2 == 1 && s.matches('`').count() > k;
        if code {
            let _ = write!(out, "<code>{}</code>", esc(piece));
            continue;
        }
        if k % 2 == 1 {
            out.push('`');
        }
        for (j, part) in esc(piece).split("**").enumerate() {
            if j > 0 {
                out.push_str(if bold { "</b>" } else { "<b>" });
                bold = !bold;
            }
            out.push_str(part);
        }
    }
    if bold {
        out.push_str("</b>");
    }
    out
}

const STYLE: &str =
    "body{font-family:sans-serif;max-width:1200px;margin:1em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:.5em 0 1.2em;font-size:.9em}\
th,td{border:1px solid #bbb;padding:.2em .5em;text-align:right}\
th{background:#eee}td:first-child,th:first-child{text-align:left}\
.figs{display:flex;flex-wrap:wrap;gap:8px}.figs img{width:580px;border:1px solid #ddd}\
img.anim{max-width:100%;border:1px solid #ddd}\
pre{background:#f6f6f6;padding:.5em;overflow-x:auto}\
code{background:#f3f3f3;padding:0 .2em;border-radius:3px;font-size:.92em}";

/// The page as one self-contained HTML document titled `title`.
pub fn html(title: &str, blocks: &[Block]) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{}</title><style>{STYLE}</style></head><body>\n",
        esc(title)
    );
    for b in blocks {
        match b {
            Block::Heading(level, text) => {
                let l = level.clamp(&1, &6);
                let id: String = text
                    .chars()
                    .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
                    .collect();
                let _ = writeln!(s, "<h{l} id=\"{}\">{}</h{l}>", esc(&id), inline(text));
            }
            Block::Para(text) => {
                let _ = writeln!(s, "<p>{}</p>", inline(text));
            }
            Block::List(items) => {
                s.push_str("<ul>");
                for i in items {
                    let _ = write!(s, "<li>{}</li>", inline(i));
                }
                s.push_str("</ul>\n");
            }
            Block::Table { header, rows } => {
                s.push_str("<table><tr>");
                for h in header {
                    let _ = write!(s, "<th>{}</th>", inline(h));
                }
                s.push_str("</tr>\n");
                for r in rows {
                    s.push_str("<tr>");
                    for c in r {
                        let _ = write!(s, "<td>{}</td>", inline(c));
                    }
                    s.push_str("</tr>\n");
                }
                s.push_str("</table>\n");
            }
            Block::Figures(figs) => {
                s.push_str("<div class=\"figs\">");
                for (alt, png, svg) in figs {
                    let _ = write!(
                        s,
                        "<a href=\"{}\"><img src=\"{}\" alt=\"{}\"></a>",
                        esc(svg),
                        esc(png),
                        esc(alt)
                    );
                }
                s.push_str("</div>\n");
            }
            Block::Animation(alt, path) => {
                let _ = writeln!(
                    s,
                    "<p><a href=\"{}\"><img class=\"anim\" src=\"{}\" alt=\"{}\"></a></p>",
                    esc(path),
                    esc(path),
                    esc(alt)
                );
            }
            Block::Pre(text) => {
                let _ = writeln!(s, "<pre>{}</pre>", esc(text.trim_end()));
            }
        }
    }
    s.push_str("</body></html>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::inline;

    #[test]
    fn code_and_bold_spans() {
        assert_eq!(
            inline("run `floebench check <x>` **now**"),
            "run <code>floebench check &lt;x&gt;</code> <b>now</b>"
        );
        assert_eq!(inline("`a**b`"), "<code>a**b</code>");
        assert_eq!(inline("odd ` tick"), "odd ` tick");
        assert_eq!(inline("**open"), "<b>open</b>");
    }
}
