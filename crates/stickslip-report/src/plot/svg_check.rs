//! A check of a rendered SVG without fonts: every `<text>` element's extent, estimated at
//! 0.55 em per character (the plotting layer's own estimate, generous for sans-serif), must
//! lie inside the canvas. It finds clipped titles, legends and labels, which a browser would
//! cut off at the canvas's edge.

/// The value of attribute `name` in a tag's attribute text.
fn attr<'a>(attrs: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = attrs.find(&key)? + key.len();
    let end = attrs[start..].find('"')? + start;
    Some(&attrs[start..end])
}

/// Undoes the XML escapes plotters writes.
fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&#39;", "'")
        .replace("&amp;", "&")
}

/// The texts of `svg` whose estimated extent leaves the canvas (with 1 px of slack), each
/// with its extent; an error when the SVG has no width and height.
///
/// # Errors
/// The document has no `<svg width=… height=…>`.
pub fn text_outside(svg: &str) -> Result<Vec<String>, String> {
    let head = svg.find("<svg").ok_or("no <svg> element")?;
    let head_end = svg[head..].find('>').ok_or("unterminated <svg>")? + head;
    let head_attrs = &svg[head + 4..head_end];
    let num = |name: &str| -> Result<f64, String> {
        attr(head_attrs, name)
            .and_then(|v| v.trim_end_matches("px").parse().ok())
            .ok_or_else(|| format!("<svg> has no numeric {name}"))
    };
    let (w, h) = (num("width")?, num("height")?);
    let mut out = Vec::new();
    let mut rest = &svg[head_end..];
    while let Some(i) = rest.find("<text") {
        let tag_end = rest[i..].find('>').ok_or("unterminated <text>")? + i;
        let attrs = &rest[i + 5..tag_end];
        let close = rest[tag_end..].find("</text>").ok_or("unclosed <text>")? + tag_end;
        let text = unescape(rest[tag_end + 1..close].trim());
        rest = &rest[close + 7..];
        let f = |name: &str| attr(attrs, name).and_then(|v| v.parse::<f64>().ok());
        let (Some(x), Some(y), Some(size)) = (f("x"), f("y"), f("font-size")) else {
            continue;
        };
        let width = super::draw::text_width_px(&text, size);
        let (lo, hi) = match attr(attrs, "text-anchor") {
            Some("middle") => (-width / 2.0, width / 2.0),
            Some("end") => (-width, 0.0),
            _ => (0.0, width),
        };
        // The offset across the text's direction, from its dy.
        let (a, b) = match attr(attrs, "dy") {
            Some("0.76em") => (0.0, size),
            Some("0.5ex") => (-size / 2.0, size / 2.0),
            Some("-0.5ex") => (-size, 0.0),
            _ => (-size, 0.25 * size),
        };
        let rotated = attr(attrs, "transform").is_some_and(|t| t.starts_with("rotate(270"));
        let ((x0, x1), (y0, y1)) = if rotated {
            // Read upwards: along the text is −y, across it (dy) is +x.
            ((x + a, x + b), (y - hi, y - lo))
        } else {
            ((x + lo, x + hi), (y + a, y + b))
        };
        if x0 < -1.0 || x1 > w + 1.0 || y0 < -1.0 || y1 > h + 1.0 {
            out.push(format!(
                "`{text}` spans x {x0:.0}…{x1:.0}, y {y0:.0}…{y1:.0} on a {w:.0} × {h:.0} canvas"
            ));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::palette::PALETTE;
    use crate::plot::{Panel, Series, render_svg};

    #[test]
    fn long_legends_and_titles_stay_on_the_canvas() {
        let long = "a legend label far longer than the strip of 170 px would hold";
        let p = Panel::new(
            "a title far too long for a panel of this width, which must shrink to fit it",
            "x (s)",
            "y (m)",
        )
        .with(vec![Series::new(
            long,
            vec![(0.0, 1.0), (1.0, 2.0)],
            PALETTE[0],
        )])
        .legend_outside();
        let svg = render_svg(&[p], 1, 640, 360).unwrap();
        assert_eq!(text_outside(&svg).unwrap(), Vec::<String>::new());
    }

    #[test]
    fn a_text_past_the_edge_is_found() {
        let svg = r#"<svg width="100" height="50"><text x="90" y="10" font-size="10">too long here</text><text x="5" y="20" font-size="10">ok</text></svg>"#;
        let out = text_outside(svg).unwrap();
        assert_eq!(out.len(), 1, "{out:?}");
        assert!(out[0].contains("too long here"));
        assert!(text_outside("<html/>").is_err());
    }
}
