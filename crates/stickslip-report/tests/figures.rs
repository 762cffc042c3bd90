//! Every committed report figure (`reports/*.svg`) keeps its text on its canvas: titles,
//! legends, axis and point labels, by the plotting layer's own width estimate
//! (`plot::svg_check`), so that no browser clips a legend or a title.

mod common;

use stickslip_report::plot::svg_check::text_outside;

#[test]
fn every_report_figure_keeps_its_text_on_the_canvas() {
    let figures = common::report_figures();
    let mut clipped = Vec::new();
    for p in &figures {
        let svg = std::fs::read_to_string(p).expect("readable figure");
        match text_outside(&svg) {
            Ok(out) if out.is_empty() => {}
            Ok(out) => clipped.push(format!("{}: {}", p.display(), out.join("; "))),
            Err(e) => clipped.push(format!("{}: {e}", p.display())),
        }
    }
    assert!(
        clipped.is_empty(),
        "text outside the canvas:\n{}",
        clipped.join("\n")
    );
}
