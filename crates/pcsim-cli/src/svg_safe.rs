//! A figure for the report, rebuilt from a whitelist: `report.html` inlines every SVG figure of an
//! output directory, and a figure on disk may have been replaced or edited since pcsim drew it.
//! Nothing of it is copied verbatim: it is read as XML and written again with only the elements
//! and attributes that pcsim's figures use (drawing primitives and text), attribute values of a
//! plain character set, and text escaped again. Scripts, event attributes (`on…`),
//! `foreignObject`, links, styles, `<use>`, `<image>`, comments, processing instructions, a
//! DOCTYPE and every outside reference (`url(…)`, `href`) do not survive. The page also forbids
//! scripts by its Content-Security-Policy (`cmd/report.rs`).

use anyhow::{bail, Result};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::fmt::Write as _;

/// The elements a figure may hold (what plotters' SVG backend writes, and plain shapes).
const ELEMENTS: [&str; 11] = [
    "svg", "g", "rect", "line", "polyline", "polygon", "path", "circle", "ellipse", "text", "tspan",
];

/// The attributes an element may carry.
const ATTRIBUTES: [&str; 31] = [
    "width",
    "height",
    "viewBox",
    "x",
    "y",
    "dx",
    "dy",
    "x1",
    "y1",
    "x2",
    "y2",
    "cx",
    "cy",
    "r",
    "rx",
    "ry",
    "points",
    "d",
    "fill",
    "stroke",
    "stroke-width",
    "stroke-dasharray",
    "stroke-opacity",
    "fill-opacity",
    "opacity",
    "font-family",
    "font-size",
    "font-weight",
    "font-style",
    "text-anchor",
    "transform",
];

/// The SVG namespace, the one value `xmlns` may take.
const SVG_NS: &str = "http://www.w3.org/2000/svg";

/// Whether an attribute value is plain: numbers, names, colours, lists and transforms, with no
/// reference to anything outside the figure.
fn plain_value(v: &str) -> bool {
    let lower = v.to_ascii_lowercase();
    v.len() <= 1 << 20
        && v.chars()
            .all(|c| c.is_ascii_alphanumeric() || " #.,()%+-\n\t".contains(c))
        && !lower.contains("url(")
        && !lower.contains("javascript")
        && !lower.contains("expression")
}

/// Escape text for HTML and XML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// An element's name if it is allowed.
fn allowed(e: &BytesStart<'_>) -> Option<&'static str> {
    let name = e.name();
    let n = std::str::from_utf8(name.as_ref()).ok()?;
    ELEMENTS.iter().copied().find(|&a| a == n)
}

/// Write an allowed element's start tag with its allowed attributes.
fn start_tag(out: &mut String, name: &str, e: &BytesStart<'_>, empty: bool) {
    out.push('<');
    out.push_str(name);
    for a in e.attributes().with_checks(false).flatten() {
        let Ok(key) = std::str::from_utf8(a.key.as_ref()) else {
            continue;
        };
        let Ok(value) = a.unescape_value() else {
            continue;
        };
        let keep = if key == "xmlns" {
            name == "svg" && value == SVG_NS
        } else {
            ATTRIBUTES.contains(&key) && plain_value(&value)
        };
        if keep {
            let _ = write!(out, " {key}=\"{}\"", esc(&value));
        }
    }
    out.push_str(if empty { "/>" } else { ">" });
}

/// The figure `text` rebuilt from the whitelist (see the module's documentation); an error when it
/// is not an SVG document at all (its root element is not `svg`, or it is not XML).
pub fn sanitize(text: &str) -> Result<String> {
    let mut r = Reader::from_str(text);
    r.config_mut().check_end_names = true;
    let mut out = String::with_capacity(text.len());
    // The open elements: Some(name) kept, None dropped (with everything inside it).
    let mut open: Vec<Option<&'static str>> = Vec::new();
    let mut root_seen = false;
    let dropping = |open: &[Option<&'static str>]| open.iter().any(Option::is_none);
    loop {
        let ev = match r.read_event() {
            Ok(ev) => ev,
            Err(e) => bail!("not a well-formed SVG figure ({e})"),
        };
        match ev {
            Event::Start(e) | Event::Empty(e)
                if open.is_empty() && (root_seen || allowed(&e) != Some("svg")) =>
            {
                bail!(
                    "not an SVG figure (its root element is `{}`)",
                    String::from_utf8_lossy(e.name().as_ref())
                );
            }
            Event::Start(e) => {
                root_seen = true;
                let keep = if dropping(&open) { None } else { allowed(&e) };
                if let Some(n) = keep {
                    start_tag(&mut out, n, &e, false);
                }
                open.push(keep);
            }
            Event::Empty(e) => {
                root_seen = true;
                if !dropping(&open) {
                    if let Some(n) = allowed(&e) {
                        start_tag(&mut out, n, &e, true);
                    }
                }
            }
            Event::End(_) => {
                if let Some(Some(n)) = open.pop() {
                    let _ = write!(out, "</{n}>");
                }
            }
            Event::Text(t) if !open.is_empty() && !dropping(&open) => {
                // Text only inside a kept element (a <text>'s label, or white space).
                if let Ok(s) = t.decode() {
                    out.push_str(&esc(&s));
                }
            }
            Event::GeneralRef(g) if !open.is_empty() && !dropping(&open) => {
                if let Ok(Some(c)) = g.resolve_char_ref() {
                    out.push_str(&esc(&c.to_string()));
                } else if let Ok(name) = g.decode() {
                    let c = match &*name {
                        "lt" => "<",
                        "gt" => ">",
                        "amp" => "&",
                        "quot" => "\"",
                        "apos" => "'",
                        _ => "",
                    };
                    out.push_str(&esc(c));
                }
            }
            Event::Eof => break,
            // CDATA, comments, processing instructions, the declaration, a DOCTYPE, text outside
            // the root: dropped.
            _ => {}
        }
    }
    if !root_seen || !open.is_empty() {
        bail!("not a complete SVG figure");
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::sanitize;

    #[test]
    fn a_figure_of_pcsim_keeps_its_drawing() {
        let svg = "<svg width=\"10\" height=\"5\" viewBox=\"0 0 10 5\" xmlns=\"http://www.w3.org/2000/svg\">\n<rect x=\"0\" y=\"0\" width=\"10\" height=\"5\" opacity=\"1\" fill=\"#FFFFFF\" stroke=\"none\"/>\n<text x=\"1\" y=\"2\" dy=\"0.76em\" text-anchor=\"middle\" font-family=\"sans-serif\" font-size=\"13.7\" opacity=\"1\" fill=\"#000000\" transform=\"rotate(270, 15, 313)\">\nσ &lt; 3 &amp; (780–1440)\n</text>\n<polyline fill=\"none\" opacity=\"1\" stroke=\"#1F77B4\" stroke-width=\"2\" points=\"1,2 3,4 \"/>\n</svg>\n";
        let s = sanitize(svg).unwrap();
        assert_eq!(s, svg.trim_end());
    }

    #[test]
    fn scripts_handlers_foreign_objects_and_references_do_not_survive() {
        let svg = r##"<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x "y">]>
<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" onload="alert(1)" width="10">
<script>alert(2)</script><script type="text/javascript"><![CDATA[alert(3)]]></script>
<rect onclick="alert(4)" fill="url(https://evil.example/x)" stroke="red" width="1" style="background:url(x)"/>
<foreignObject><body xmlns="http://www.w3.org/1999/xhtml"><script>alert(5)</script></body></foreignObject>
<a href="javascript:alert(6)"><text x="1">click</text></a>
<image href="https://evil.example/i.png"/><use xlink:href="#a"/>
<text x="1" fill="javascript:alert(7)">ok &x; &#60;b&#62;</text><!-- <script>alert(8)</script> -->
<set attributeName="onmouseover" to="alert(9)"/><animate attributeName="href" to="javascript:alert(10)"/>
</svg>"##;
        let s = sanitize(svg).unwrap();
        let lower = s.to_ascii_lowercase();
        for bad in [
            "script",
            "alert",
            "onload",
            "onclick",
            "foreignobject",
            "href",
            "url(",
            "javascript",
            "style",
            "<image",
            "<use",
            "<a",
            "<set",
            "<animate",
            "<!",
            "<?",
            "evil",
            "xlink",
        ] {
            assert!(!lower.contains(bad), "`{bad}` survived: {s}");
        }
        // What is drawing stays: the rect's stroke and width, the text, escaped.
        assert!(s.contains("<rect stroke=\"red\" width=\"1\"/>"), "{s}");
        assert!(s.contains("ok  &lt;b&gt;"), "{s}");
    }

    #[test]
    fn what_is_not_an_svg_is_refused() {
        assert!(sanitize("<html><script>alert(1)</script></html>").is_err());
        assert!(sanitize("just text").is_err());
        assert!(sanitize("<svg><rect></svg>").is_err());
        assert!(sanitize("<svg/><script>alert(1)</script>").is_err());
    }
}
