//! `index.html`: `report.md` as a page that reads offline (no server, no network, nothing but
//! the report's own files): its headings, paragraphs, tables, images and link lines, with a
//! little CSS. In the report's page each scene's strip becomes a grid of labelled tiles (the
//! reference, then each configuration with its signed error under it, cut from the strip PNG),
//! a click enlarges a tile, and checkboxes filter the tiles by technique, resolution and
//! backend (a few lines of inline script).

use super::json::Strip;
use std::collections::BTreeSet;

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

/// The strip an image line `![alt](src)` shows, if it shows one.
fn strip_of<'a>(line: &str, strips: &'a [Strip]) -> Option<&'a Strip> {
    let src = line
        .strip_prefix("![")?
        .split_once("](")?
        .1
        .strip_suffix(')')?;
    strips.iter().find(|s| s.file == src && !s.tiles.is_empty())
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

/// Renders Markdown as a self-contained HTML page.
pub fn render(markdown: &str) -> String {
    render_report(markdown, &[])
}

/// Displayed side of a tile, pixels.
const TILE: u32 = 192;

/// One cell of a strip (column `col`, row `row`) as a CSS sprite of `TILE` pixels.
fn cell(strip: &Strip, col: usize, row: u32) -> String {
    let cols = strip.tiles.len() + 1;
    format!(
        "<div class=\"cell\" style=\"background-image:url('{}');background-size:{}px {}px;\
         background-position:-{}px -{}px\"></div>",
        esc(&strip.file),
        cols as u32 * TILE,
        super::images::STRIP_ROWS * TILE,
        col as u32 * TILE,
        row * TILE
    )
}

/// The grid of one strip: the reference tile, then one tile per configuration.
fn grid(strip: &Strip) -> String {
    let mut g = format!(
        "<div class=\"grid\">\n<figure class=\"tile\" data-ref=\"1\">{}{}<figcaption>reference</figcaption></figure>\n",
        cell(strip, 0, 0),
        cell(strip, 0, 1)
    );
    for (k, t) in strip.tiles.iter().enumerate() {
        g.push_str(&format!(
            "<figure class=\"tile\" data-technique=\"{}\" data-res=\"{}\" data-backend=\"{}\">{}{}{}\
             <figcaption><b>{}</b> {}<br>{} {}², image {:.2}, V {:.2}</figcaption></figure>\n",
            esc(&t.technique),
            t.resolution,
            esc(&t.backend),
            cell(strip, k + 1, 0),
            cell(strip, k + 1, 1),
            cell(strip, k + 1, 2),
            esc(&t.technique),
            esc(&t.variant),
            esc(&t.backend),
            t.resolution,
            t.image_rms_255,
            t.rms_255
        ));
    }
    g.push_str(&format!(
        "</div>\n<p><a href=\"{0}\">the whole strip ({0})</a></p>\n",
        esc(&strip.file)
    ));
    g
}

/// The filter bar: one checkbox per technique, resolution and backend in `strips`.
fn filters(strips: &[Strip]) -> String {
    let mut techniques = BTreeSet::new();
    let mut resolutions = BTreeSet::new();
    let mut backends = BTreeSet::new();
    for t in strips.iter().flat_map(|s| &s.tiles) {
        techniques.insert(t.technique.clone());
        resolutions.insert(t.resolution);
        backends.insert(t.backend.clone());
    }
    let boxes = |key: &str, values: Vec<String>| {
        values
            .iter()
            .map(|v| {
                format!(
                    "<label><input type=\"checkbox\" checked data-key=\"{key}\" value=\"{0}\"> {0}</label>",
                    esc(v)
                )
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    format!(
        "<div id=\"filters\"><p><b>Show</b> (tiles of every scene below; click a tile to enlarge it)</p>\n\
         <p>technique: {}</p>\n<p>map resolution: {}</p>\n<p>backend: {}</p></div>\n",
        boxes("technique", techniques.into_iter().collect()),
        boxes("res", resolutions.iter().map(|r| r.to_string()).collect()),
        boxes("backend", backends.into_iter().collect()),
    )
}

/// The page's script: the filters hide tiles, a click toggles a tile's enlarged size.
const SCRIPT: &str = "<script>\n\
function applyFilters() {\n\
  const on = {};\n\
  document.querySelectorAll('#filters input').forEach(i => {\n\
    on[i.dataset.key] = on[i.dataset.key] || new Set();\n\
    if (i.checked) on[i.dataset.key].add(i.value);\n\
  });\n\
  document.querySelectorAll('.tile[data-technique]').forEach(t => {\n\
    const show = ['technique', 'res', 'backend'].every(k => !on[k] || on[k].has(t.dataset[k]));\n\
    t.style.display = show ? '' : 'none';\n\
  });\n\
}\n\
document.querySelectorAll('#filters input').forEach(i => i.addEventListener('change', applyFilters));\n\
document.querySelectorAll('.tile').forEach(t => t.addEventListener('click', () => t.classList.toggle('big')));\n\
</script>\n";

/// Renders the report's Markdown as a self-contained HTML page, each strip image of `strips`
/// as a filterable grid of labelled tiles.
pub fn render_report(markdown: &str, strips: &[Strip]) -> String {
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
        } else if let Some(strip) = strip_of(t, strips) {
            body.push_str(&grid(strip));
        } else if let Some(img) = image(t).or_else(|| link(t)) {
            body.push_str(&img);
            body.push('\n');
        } else {
            body.push_str(&format!("<p>{}</p>\n", inline(t)));
        }
    }
    flush(&mut table, &mut body);
    let (bar, script) = if strips.iter().any(|s| !s.tiles.is_empty()) {
        (filters(strips), SCRIPT)
    } else {
        (String::new(), "")
    };
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Soft-shadow report</title>\n<style>\nbody {{ font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; }}\ntable {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\nth, td {{ border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }}\nth:first-child, td:first-child {{ text-align: left; }}\ntr:nth-child(even) td {{ background: #f6f6f6; }}\nimg {{ max-width: 100%; }}\ncode {{ background: #eee; padding: 0 0.2em; }}\n.grid {{ display: flex; flex-wrap: wrap; gap: 8px; }}\n.tile {{ margin: 0; width: {TILE}px; cursor: zoom-in; font-size: 0.8em; }}\n.tile .cell {{ width: {TILE}px; height: {TILE}px; image-rendering: pixelated; }}\n.tile.big {{ transform: scale(2.5); transform-origin: top left; position: relative; z-index: 2; background: #fff; box-shadow: 0 0 8px #000; cursor: zoom-out; }}\n#filters {{ position: sticky; top: 0; background: #fff; border-bottom: 1px solid #ccc; z-index: 1; }}\n#filters label {{ white-space: nowrap; margin-right: 0.6em; }}\n</style></head>\n<body>\n{bar}{body}{script}</body></html>\n"
    )
}
