//! Every committed report figure (`reports/*.svg`) parses and renders with resvg (the
//! renderer librsvg-based viewers and browsers agree with on these plain SVGs), and every
//! text it lays out with a real font stays on the canvas: a clipped legend, title or label
//! fails here. resvg lays the text out with the system's DejaVu Sans (`.ci/run` installs
//! `fonts-dejavu-core` where it is missing), the face the figures' `sans-serif` resolves to
//! on Debian.

use resvg::tiny_skia::{Pixmap, Transform};
use resvg::usvg::{Group, Node, Options, Tree};
mod common;

/// How far (px) a glyph's box may pass the canvas's edge: anti-aliasing, not clipping.
const SLACK_PX: f32 = 0.5;

fn options() -> Options<'static> {
    let mut opt = Options::default();
    let db = opt.fontdb_mut();
    db.load_system_fonts();
    assert!(
        db.faces()
            .any(|f| f.families.iter().any(|(name, _)| name == "DejaVu Sans")),
        "no DejaVu Sans among the system fonts: install fonts-dejavu-core (.ci/run does)"
    );
    db.set_sans_serif_family("DejaVu Sans");
    opt
}

/// Every text node under `g`, with its box in canvas coordinates.
fn texts(g: &Group, out: &mut Vec<(String, resvg::usvg::Rect)>) {
    for node in g.children() {
        match node {
            Node::Group(inner) => texts(inner, out),
            Node::Text(t) => {
                let words: String = t.chunks().iter().map(|c| c.text()).collect();
                out.push((words, node.abs_bounding_box()));
            }
            _ => {}
        }
    }
}

/// What is wrong with the figure `svg`: a parse error, an empty rendering, a text no font lays
/// out, a text leaving the canvas.
fn faults_of(name: &str, svg: &str, opt: &Options<'_>) -> Vec<String> {
    let mut faults = Vec::new();
    let tree = match Tree::from_str(svg, opt) {
        Ok(t) => t,
        Err(e) => return vec![format!("{name}: does not parse: {e}")],
    };
    let size = tree.size();
    let Some(mut pixmap) = Pixmap::new(size.width().ceil() as u32, size.height().ceil() as u32)
    else {
        return vec![format!("{name}: empty canvas")];
    };
    resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
    if pixmap.data().iter().all(|&b| b == 0) {
        faults.push(format!("{name}: renders nothing"));
    }
    let mut laid_out = Vec::new();
    texts(tree.root(), &mut laid_out);
    // A text element without a face to lay it out is dropped by the parser: count them.
    let written = svg.matches("<text").count();
    if laid_out.len() < written {
        faults.push(format!(
            "{name}: {} of {written} texts laid out (a font is missing)",
            laid_out.len()
        ));
    }
    for (words, r) in laid_out {
        if r.left() < -SLACK_PX
            || r.top() < -SLACK_PX
            || r.right() > size.width() + SLACK_PX
            || r.bottom() > size.height() + SLACK_PX
        {
            faults.push(format!(
                "{name}: \"{words}\" at x {:.0}–{:.0}, y {:.0}–{:.0} leaves the {:.0} × {:.0} canvas",
                r.left(),
                r.right(),
                r.top(),
                r.bottom(),
                size.width(),
                size.height()
            ));
        }
    }
    faults
}

#[test]
fn a_clipped_label_and_a_broken_file_are_found() {
    let opt = options();
    let head = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50">"#;
    let inside = format!(
        r#"{head}<rect width="100" height="50" fill="white"/><text x="5" y="20" font-family="sans-serif" font-size="12">ok</text></svg>"#
    );
    assert!(faults_of("inside", &inside, &opt).is_empty());
    let clipped = format!(
        r#"{head}<rect width="100" height="50" fill="white"/><text x="70" y="20" font-family="sans-serif" font-size="12">a long legend</text></svg>"#
    );
    let f = faults_of("clipped", &clipped, &opt);
    assert!(f.len() == 1 && f[0].contains("a long legend"), "{f:?}");
    let broken = format!("{head}<text x=\"5\" y=\"20\">unclosed</svg>");
    assert!(faults_of("broken", &broken, &opt)[0].contains("does not parse"));
}

#[test]
fn every_report_figure_renders_with_its_text_on_the_canvas() {
    let figures = common::report_figures();
    let opt = options();
    let mut faults = Vec::new();
    let mut texts_checked = 0;
    for p in &figures {
        let name = p
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into());
        let svg = std::fs::read_to_string(p).expect("readable figure");
        texts_checked += svg.matches("<text").count();
        faults.extend(faults_of(&name, &svg, &opt));
    }
    assert!(texts_checked > 1000, "{texts_checked} texts");
    assert!(
        faults.is_empty(),
        "{} faults:\n{}",
        faults.len(),
        faults.join("\n")
    );
}
