//! Checks a reader's trust in the figures rests on, run on every SVG an output folder holds
//! (xtask's test runs them on the default `--quick` run's): every text's box lies inside the
//! canvas and overlaps no other text (a title on a tick label), every band lies inside its
//! metric's range, no two methods of one figure share a colour, and a method has one colour in
//! every figure of its experiment (its folder).
//!
//! SVGs are parsed with `roxmltree`. A text's box is estimated conservatively from its font
//! size and characters ([`crate::chart::text_width`]), anchored as `text-anchor` says,
//! rotated by a `rotate(-90 x y)` transform, and placed through nested `<svg>` viewports. A
//! band's data values are read back from its polygon's pixels through the `data-*` axis
//! attributes of its plot (`data-left`, `data-y0`, …), so a band drawn outside its metric's
//! range fails whatever the code that computed it believed.

use std::collections::BTreeMap;

use crate::chart::text_width;

/// A problem found in one figure.
pub type Problem = String;

/// The translation and scale from a nested viewport's units to the canvas.
#[derive(Debug, Clone, Copy)]
struct Place {
    dx: f64,
    dy: f64,
    scale: f64,
}

fn number(node: roxmltree::Node<'_, '_>, name: &str) -> Option<f64> {
    node.attribute(name)?.trim_end_matches("px").parse().ok()
}

/// An attribute of `node` or of its nearest ancestor that has it.
fn inherited<'a>(node: roxmltree::Node<'a, '_>, name: &str) -> Option<&'a str> {
    node.ancestors().find_map(|n| n.attribute(name))
}

/// The problems of a set of figures (file name, SVG text), checked together so that a
/// method's colour can be compared between figures.
pub fn check_figures(figures: &[(String, String)]) -> Vec<Problem> {
    let mut problems = Vec::new();
    // folder/method → (colour, first figure drawing it)
    let mut colours: BTreeMap<String, (String, String)> = BTreeMap::new();
    for (name, text) in figures {
        let document = match roxmltree::Document::parse(text) {
            Ok(document) => document,
            Err(error) => {
                problems.push(format!("{name}: not well-formed XML: {error}"));
                continue;
            }
        };
        let root = document.root_element();
        let (Some(width), Some(height)) = (number(root, "width"), number(root, "height")) else {
            problems.push(format!(
                "{name}: the root <svg> has no numeric width and height"
            ));
            continue;
        };
        check_texts(name, root, width, height, &mut problems);
        check_bands(name, root, &mut problems);
        check_looks(name, root, &mut colours, &mut problems);
    }
    problems
}

/// Where a node's coordinates land on the canvas: through every nested `<svg>` above it.
fn place_of(node: roxmltree::Node<'_, '_>) -> Place {
    let mut viewports: Vec<roxmltree::Node<'_, '_>> = node
        .ancestors()
        .filter(|n| n.has_tag_name("svg") && n.parent_element().is_some())
        .collect();
    viewports.reverse();
    let mut place = Place {
        dx: 0.0,
        dy: 0.0,
        scale: 1.0,
    };
    for viewport in viewports {
        let (x, y) = (
            number(viewport, "x").unwrap_or(0.0),
            number(viewport, "y").unwrap_or(0.0),
        );
        let (mut min_x, mut min_y, mut scale) = (0.0, 0.0, 1.0);
        if let Some(view_box) = viewport.attribute("viewBox") {
            let v: Vec<f64> = view_box
                .split([' ', ','])
                .filter_map(|s| s.parse().ok())
                .collect();
            if let (4, Some(w)) = (v.len(), number(viewport, "width")) {
                min_x = v[0];
                min_y = v[1];
                scale = w / v[2];
            }
        }
        // inner point p ↦ x + (p − min)·scale, then the outer place.
        place = Place {
            dx: place.dx + place.scale * (x - min_x * scale),
            dy: place.dy + place.scale * (y - min_y * scale),
            scale: place.scale * scale,
        };
    }
    place
}

fn check_texts(
    name: &str,
    root: roxmltree::Node<'_, '_>,
    width: f64,
    height: f64,
    problems: &mut Vec<Problem>,
) {
    // Each text's ink box on the canvas: x0, x1, y0, y1.
    let mut boxes: Vec<(String, (f64, f64, f64, f64))> = Vec::new();
    for text in root.descendants().filter(|n| n.has_tag_name("text")) {
        let content: String = text
            .descendants()
            .filter(roxmltree::Node::is_text)
            .filter_map(|n| n.text())
            .collect();
        let content = content.trim();
        if content.is_empty() {
            continue;
        }
        let font = inherited(text, "font-size")
            .and_then(|s| s.trim_end_matches("px").parse().ok())
            .unwrap_or(16.0);
        let (x, y) = (
            number(text, "x").unwrap_or(0.0),
            number(text, "y").unwrap_or(0.0),
        );
        let w = text_width(content, font);
        let before = match inherited(text, "text-anchor") {
            Some("middle") => 0.5,
            Some("end") => 1.0,
            _ => 0.0,
        };
        // Along the text: [−w·before, w·(1 − before)]; across: ascent 1 em, descent 0.3 em.
        let (mut x0, mut x1, mut y0, mut y1) = (
            x - w * before,
            x + w * (1.0 - before),
            y - font,
            y + 0.3 * font,
        );
        if text
            .attribute("transform")
            .is_some_and(|t| t.starts_with("rotate(-90"))
        {
            // (x + dx, y + dy) ↦ (x + dy, y − dx)
            (x0, x1, y0, y1) = (
                x - font,
                x + 0.3 * font,
                y - w * (1.0 - before),
                y + w * before,
            );
        }
        let place = place_of(text);
        let (x0, x1) = (place.dx + place.scale * x0, place.dx + place.scale * x1);
        let (y0, y1) = (place.dy + place.scale * y0, place.dy + place.scale * y1);
        if x0 < -0.5 || y0 < -0.5 || x1 > width + 0.5 || y1 > height + 0.5 {
            problems.push(format!(
                "{name}: text {content:?} spans x {x0:.0}..{x1:.0}, y {y0:.0}..{y1:.0}, \
                 outside the {width}×{height} canvas"
            ));
        }
        // For overlaps, the glyphs' own extent: cap height above the baseline, descenders
        // below (the canvas check above keeps a full em of room).
        let inset = 0.25 * font * place.scale;
        let descent = 0.1 * font * place.scale;
        let ink = if text
            .attribute("transform")
            .is_some_and(|t| t.starts_with("rotate(-90"))
        {
            (x0 + inset, x1 - descent, y0, y1)
        } else {
            (x0, x1, y0 + inset, y1 - descent)
        };
        boxes.push((content.to_owned(), ink));
    }
    // No two texts overlap: a title on a tick label, a label on another.
    for (i, (a, (ax0, ax1, ay0, ay1))) in boxes.iter().enumerate() {
        for (b, (bx0, bx1, by0, by1)) in &boxes[i + 1..] {
            let across = ax0.max(*bx0) < ax1.min(*bx1) - 0.5;
            let along = ay0.max(*by0) < ay1.min(*by1) - 0.5;
            if across && along {
                problems.push(format!(
                    "{name}: text {a:?} overlaps text {b:?} (x {ax0:.0}..{ax1:.0}, y \
                     {ay0:.0}..{ay1:.0} against x {bx0:.0}..{bx1:.0}, y {by0:.0}..{by1:.0})"
                ));
            }
        }
    }
}

fn check_bands(name: &str, root: roxmltree::Node<'_, '_>, problems: &mut Vec<Problem>) {
    let plots = root.descendants().filter(|n| {
        n.has_tag_name("g")
            && n.attribute("class")
                .is_some_and(|c| c.split(' ').any(|c| c == "plot"))
    });
    for plot in plots {
        let get = |a: &str| number(plot, a);
        let (Some(top), Some(bottom), Some(y0), Some(y1)) = (
            get("data-top"),
            get("data-bottom"),
            get("data-y0"),
            get("data-y1"),
        ) else {
            problems.push(format!("{name}: a plot without its axis attributes"));
            continue;
        };
        let (low, high) = (get("data-metric-min"), get("data-metric-max"));
        // Coordinates are written to a tenth of a pixel.
        let tolerance = 0.06 * (y1 - y0).abs() / (bottom - top).abs().max(1.0);
        for band in plot
            .descendants()
            .filter(|n| n.attribute("class") == Some("band"))
        {
            let method = band.attribute("data-method").unwrap_or("?");
            let values = band
                .attribute("points")
                .unwrap_or("")
                .split_whitespace()
                .filter_map(|p| p.split(',').nth(1)?.parse::<f64>().ok())
                .map(|py| y0 + (bottom - py) / (bottom - top) * (y1 - y0));
            for value in values {
                let below = low.is_some_and(|low| value < low - tolerance);
                let above = high.is_some_and(|high| value > high + tolerance);
                if below || above {
                    problems.push(format!(
                        "{name}: the band of {method} reaches {value:.3}, outside the metric's \
                         range [{}, {}]",
                        low.map_or("−∞".to_owned(), |v| v.to_string()),
                        high.map_or("∞".to_owned(), |v| v.to_string())
                    ));
                    break;
                }
            }
        }
    }
}

fn check_looks(
    name: &str,
    root: roxmltree::Node<'_, '_>,
    colours: &mut BTreeMap<String, (String, String)>,
    problems: &mut Vec<Problem>,
) {
    // method → (colour, dash) in this figure
    let mut looks: BTreeMap<String, (String, String)> = BTreeMap::new();
    let drawn = root.descendants().filter(|n| {
        n.attribute("data-method").is_some()
            && matches!(
                n.attribute("class"),
                Some("line" | "sample" | "path" | "seed" | "band" | "strip" | "collapse")
            )
    });
    for node in drawn {
        let method = node.attribute("data-method").unwrap_or("").to_owned();
        let colour = node
            .attribute("stroke")
            .or_else(|| node.attribute("fill"))
            .unwrap_or("none")
            .to_ascii_uppercase();
        let dash = node
            .attribute("stroke-dasharray")
            .unwrap_or("solid")
            .to_owned();
        let class = node.attribute("class").unwrap_or("");
        // A method keeps its colour in every figure of its experiment (its folder).
        let folder = name.rsplit_once('/').map_or("", |(folder, _)| folder);
        let key = format!("{folder}/{method}");
        match colours.get(&key) {
            Some((known, figure)) if *known != colour => problems.push(format!(
                "{name}: {method} is drawn in {colour} but in {known} in {figure}"
            )),
            Some(_) => {}
            None => {
                colours.insert(key, (colour.clone(), name.to_owned()));
            }
        }
        // Seeds, bands and collapse marks carry the colour only; the dash is the line's, the
        // sample's and the strip's.
        if matches!(class, "seed" | "band" | "collapse") {
            continue;
        }
        match looks.get(&method) {
            Some(look) if *look != (colour.clone(), dash.clone()) => problems.push(format!(
                "{name}: {method} is drawn both as {look:?} and as ({colour}, {dash})"
            )),
            Some(_) => {}
            None => {
                looks.insert(method, (colour, dash));
            }
        }
    }
    // One colour per method in a figure: a reader tells methods apart by colour first, the
    // dash is the second channel.
    let mut by_colour: BTreeMap<&String, &String> = BTreeMap::new();
    for (method, (colour, _)) in &looks {
        if let Some(other) = by_colour.insert(colour, method) {
            problems.push(format!(
                "{name}: {other} and {method} share colour {colour}"
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svg(body: &str) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"400\" height=\"300\" \
             viewBox=\"0 0 400 300\">{body}</svg>"
        )
    }

    fn problems(figures: &[(&str, String)]) -> Vec<Problem> {
        let figures: Vec<(String, String)> = figures
            .iter()
            .map(|(n, t)| ((*n).to_owned(), t.clone()))
            .collect();
        check_figures(&figures)
    }

    #[test]
    fn a_text_leaving_the_canvas_fails() {
        let fits =
            svg("<text x=\"200\" y=\"20\" font-size=\"12\" text-anchor=\"middle\">title</text>");
        assert!(problems(&[("a.svg", fits)]).is_empty());
        let long = "a very long title that cannot fit on a canvas this narrow";
        let wide = svg(&format!(
            "<text x=\"200\" y=\"20\" font-size=\"18\" text-anchor=\"middle\">{long}</text>"
        ));
        let found = problems(&[("a.svg", wide)]);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].contains("outside the 400×300 canvas"));
        // Rotated: the long side runs vertically.
        let rotated = svg(&format!(
            "<text x=\"20\" y=\"150\" font-size=\"14\" text-anchor=\"middle\" \
             transform=\"rotate(-90 20 150)\">{long}</text>"
        ));
        assert_eq!(problems(&[("a.svg", rotated)]).len(), 1);
        // In a nested viewport moved right, a text near its right edge leaves the canvas.
        let nested = svg(
            "<svg x=\"300\" y=\"0\" width=\"200\" height=\"100\" viewBox=\"0 0 200 100\">\
             <text x=\"50\" y=\"50\" font-size=\"12\">label here</text></svg>",
        );
        assert_eq!(problems(&[("a.svg", nested)]).len(), 1);
    }

    #[test]
    fn a_text_over_another_fails() {
        let text = |x: u32, y: u32, words: &str| {
            format!("<text x=\"{x}\" y=\"{y}\" font-size=\"12\">{words}</text>")
        };
        // Two lines of a wrapped title, 15 px apart: no overlap.
        let lines = svg(&(text(10, 50, "a title") + &text(10, 65, "wrapped")));
        assert!(problems(&[("a.svg", lines)]).is_empty());
        // A title over a tick label.
        let over = svg(&(text(10, 50, "final 40 episodes") + &text(40, 53, "2000")));
        let found = problems(&[("a.svg", over)]);
        assert!(
            found[0].contains("text \"final 40 episodes\" overlaps text \"2000\""),
            "{found:?}"
        );
    }

    #[test]
    fn a_band_outside_its_metric_fails() {
        // Plot: pixels 10 (top) to 110 (bottom) show values 0 to 100.
        let plot = |points: &str| {
            svg(&format!(
                "<g class=\"plot\" data-left=\"0\" data-right=\"100\" data-top=\"10\" \
                 data-bottom=\"110\" data-x0=\"1\" data-x1=\"10\" data-y0=\"0\" \
                 data-y1=\"100\" data-metric-min=\"0\" data-metric-max=\"50\">\
                 <polygon class=\"band\" data-method=\"m\" fill=\"#0072B2\" points=\"{points}\"/></g>"
            ))
        };
        assert!(problems(&[("a.svg", plot("0,60 10,70 10,110"))]).is_empty());
        let below = problems(&[("a.svg", plot("0,60 10,115"))]);
        assert!(below[0].contains("reaches -5.000"), "{below:?}");
        assert_eq!(problems(&[("a.svg", plot("0,40 10,70"))]).len(), 1);
    }

    #[test]
    fn shared_looks_and_changing_colours_fail() {
        let line = |method: &str, colour: &str, dash: Option<&str>| {
            format!(
                "<polyline class=\"line\" data-method=\"{method}\" stroke=\"{colour}\"{} points=\"0,0 1,1\"/>",
                dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""))
            )
        };
        let distinct = svg(&(line("a", "#0072B2", None) + &line("b", "#D55E00", Some("2 4"))));
        assert!(problems(&[("one.svg", distinct.clone())]).is_empty());
        // One colour per method in a figure: another dash does not tell them apart enough.
        let shared = svg(&(line("a", "#0072B2", None) + &line("b", "#0072b2", Some("2 4"))));
        let found = problems(&[("one.svg", shared)]);
        assert!(
            found[0].contains("a and b share colour #0072B2"),
            "{found:?}"
        );
        let other = svg(&line("a", "#D55E00", None));
        let found = problems(&[
            ("x/one.svg", distinct.clone()),
            ("x/two.svg", other.clone()),
        ]);
        assert_eq!(
            found,
            ["x/two.svg: a is drawn in #D55E00 but in #0072B2 in x/one.svg"]
        );
        // Another experiment's figures may colour it otherwise.
        assert!(problems(&[("x/one.svg", distinct), ("y/two.svg", other)]).is_empty());
    }
}
