//! Rendering tests: what the SVG says, and that the PNG decodes with the bundled font drawn.

use std::path::PathBuf;

use super::*;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("opengrasp-plots-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The contents of every `<text>` element of an SVG document.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..];
            Some(body[..body.find("</text>")?].trim().to_string())
        })
        .collect()
}

/// RRT-Connect: 20 values 10..=29 ms; PRM: a tight sample with one low and one high outlier;
/// IK-RRT: no values.
fn motion_series() -> Vec<(String, Vec<f64>)> {
    let rrt = (10..30).map(f64::from).collect();
    let prm = vec![6.96, 20.0, 20.5, 21.0, 21.5, 22.0, 80.0];
    vec![("RRT-Connect".into(), rrt), ("PRM".into(), prm), ("IK-RRT".into(), Vec::new())]
}

#[test]
fn box_plot_svg_has_counts_outliers_units_and_no_quotes() {
    let dir = temp_dir("box-svg");
    let path = dir.join("times.svg");
    box_plot(&path, "planning time: scene 1", "planning time [ms]", &motion_series()).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    let texts = svg_texts(&svg);
    for label in ["RRT-Connect (n=20)", "PRM (n=7)", "IK-RRT (n=0)", "no data", "planning time [ms]", "planner"] {
        assert!(texts.iter().any(|t| t == label), "{label} missing in {texts:?}");
    }
    assert!(texts.iter().any(|t| t == BOX_PLOT_SUBTITLE), "{texts:?}");
    // Issue 16: labels came out as "\"PRM\"".
    assert!(texts.iter().all(|t| !t.contains('"') && !t.contains("&quot;")), "{texts:?}");
    // PRM's two outliers are dots; RRT-Connect's uniform sample has none.
    assert_eq!(svg.matches("<circle").count(), 2, "{svg}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn grouped_bars_svg_shows_n_and_marks_empty_cells() {
    let dir = temp_dir("bars-svg");
    let path = dir.join("fc.svg");
    let groups = vec!["salt_can".to_string(), "mug".to_string()];
    let series = vec![
        ("medial-axis".to_string(), vec![Some(Bar { value: 50.0, n: Some(12) }), None]),
        (
            "surface-normals".to_string(),
            vec![Some(Bar { value: 0.0, n: Some(7) }), Some(Bar { value: 25.0, n: Some(4) })],
        ),
    ];
    grouped_bars_counted(&path, "force closure: barrett hand", "object", "force closure [%]", &groups, &series)
        .unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    let texts = svg_texts(&svg);
    for label in ["n=12", "n=7", "n=4", "salt_can", "mug", "object", "force closure [%]", BAR_CHART_SUBTITLE] {
        assert!(texts.iter().any(|t| t == label), "{label} missing in {texts:?}");
    }
    // Exactly one empty cell, marked; a real 0 % (n=7) is a bar with its count, not "no data".
    assert_eq!(texts.iter().filter(|t| *t == "no data").count(), 1, "{texts:?}");
    assert!(texts.iter().all(|t| !t.contains('"') && !t.contains("&quot;")), "{texts:?}");
    // The compatible form without counts still draws.
    let plain = dir.join("plain.svg");
    grouped_bars(&plain, "t", "force closure [%]", &groups, &[("a".into(), vec![Some(10.0), None])]).unwrap();
    assert!(svg_texts(&std::fs::read_to_string(plain).unwrap()).iter().any(|t| t == "no data"));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn box_plot_png_decodes_and_the_bundled_font_renders() {
    let dir = temp_dir("box-png");
    let path = dir.join("times.png");
    box_plot(&path, "planning time: scene 1", "planning time [ms]", &motion_series()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    // Three boxes: 170 * 3 + 200 = 710 px, at least 720 wide; 540 high.
    assert_eq!((be(16), be(20)), (720, 540));
    let img = image::load_from_memory(&bytes).unwrap().to_luma8();
    assert_eq!(img.dimensions(), (720, 540));
    // The title is centred in the top 30 px: dark pixels there, none in the left margin.
    let dark = |x0: u32, x1: u32, y0: u32, y1: u32| {
        (y0..y1).flat_map(|y| (x0..x1).map(move |x| (x, y))).filter(|&(x, y)| img.get_pixel(x, y)[0] < 128).count()
    };
    assert!(dark(200, 520, 5, 32) > 100, "title not rendered: {} dark pixels", dark(200, 520, 5, 32));
    assert_eq!(dark(0, 60, 0, 30), 0);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn plot_format_extensions() {
    assert_eq!(PlotFormat::default(), PlotFormat::Both);
    assert_eq!(PlotFormat::Both.extensions(), ["svg", "png"]);
    assert_eq!(PlotFormat::Png.extensions(), ["png"]);
    assert_eq!(PlotFormat::Svg.extensions(), ["svg"]);
}

#[test]
fn nothing_to_plot_is_an_error() {
    let dir = temp_dir("empty");
    let err = box_plot(&dir.join("e.svg"), "t", "y", &[("a".into(), vec![])]).unwrap_err();
    assert!(err.to_string().contains("no values"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}
