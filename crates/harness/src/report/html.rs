//! `index.html`: `report.md` as a page that reads offline (no scripts, no external files): its
//! headings, paragraphs, tables, images and link lines, with a little CSS.

/// Escapes text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Inline Markdown of the report: `code` and images.
fn inline(s: &str) -> String {
    let mut out = String::new();
    let mut code = false;
    for (i, part) in esc(s).split('`').enumerate() {
        if i > 0 {
            out.push_str(if code { "</code>" } else { "<code>" });
            code = !code;
        }
        out.push_str(part);
    }
    out
}

/// An image line `![alt](src)` as `<img>`, if it is one.
fn image(line: &str) -> Option<String> {
    let rest = line.strip_prefix("![")?;
    let (alt, rest) = rest.split_once("](")?;
    let src = rest.strip_suffix(')')?;
    Some(format!(
        "<p><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a></p>",
        esc(src),
        esc(alt)
    ))
}

/// A link line `[text](href)` as a paragraph holding the link, if it is one.
fn link(line: &str) -> Option<String> {
    let rest = line.strip_prefix('[')?;
    let (text, rest) = rest.split_once("](")?;
    let href = rest.strip_suffix(')')?;
    Some(format!(
        "<p><a href=\"{}\">{}</a></p>",
        esc(href),
        inline(text)
    ))
}

/// Renders the report's Markdown as a self-contained HTML page.
pub fn render(markdown: &str) -> String {
    let mut body = String::new();
    let mut table: Vec<Vec<String>> = Vec::new();
    let flush = |table: &mut Vec<Vec<String>>, body: &mut String| {
        if table.is_empty() {
            return;
        }
        body.push_str("<table>\n");
        for (i, row) in table.iter().enumerate() {
            let tag = if i == 0 { "th" } else { "td" };
            body.push_str("<tr>");
            for c in row {
                body.push_str(&format!("<{tag}>{}</{tag}>", inline(c)));
            }
            body.push_str("</tr>\n");
        }
        body.push_str("</table>\n");
        table.clear();
    };
    for line in markdown.lines() {
        let t = line.trim();
        if let Some(row) = t.strip_prefix('|') {
            let cells: Vec<String> = row
                .trim_end_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect();
            if !cells
                .iter()
                .all(|c| c.chars().all(|ch| matches!(ch, '-' | ':')))
            {
                table.push(cells);
            }
            continue;
        }
        flush(&mut table, &mut body);
        if t.is_empty() {
            continue;
        }
        let level = t.chars().take_while(|c| *c == '#').count();
        if level > 0 && t[level..].starts_with(' ') {
            body.push_str(&format!(
                "<h{level}>{}</h{level}>\n",
                inline(t[level..].trim())
            ));
        } else if let Some(img) = image(t).or_else(|| link(t)) {
            body.push_str(&img);
            body.push('\n');
        } else {
            body.push_str(&format!("<p>{}</p>\n", inline(t)));
        }
    }
    flush(&mut table, &mut body);
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Soft-shadow report</title>\n<style>\nbody {{ font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; }}\ntable {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\nth, td {{ border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }}\nth:first-child, td:first-child {{ text-align: left; }}\ntr:nth-child(even) td {{ background: #f6f6f6; }}\nimg {{ max-width: 100%; }}\ncode {{ background: #eee; padding: 0 0.2em; }}\n</style></head>\n<body>\n{body}</body></html>\n"
    )
}
