//! The rasteriser against analytic projections: silhouettes of boxes seen along an axis, the
//! pinhole model, the z-buffer, Lambert shading, PNG round trip and typed camera errors.

use opengrasp_core::model::{Geometry, Shape};
use opengrasp_core::nalgebra::{Isometry3, Point3, Vector3};
use opengrasp_core::scene::{Scene, StaticBody};
use opengrasp_viewer::drawing::{Drawing, Kind, BACKGROUND};
use opengrasp_viewer::raster::{Camera, Canvas, Projection};
use opengrasp_viewer::ViewerError;

fn box_scene(boxes: &[(&str, [f64; 3], [f64; 3])]) -> Scene {
    let mut scene = Scene::new("boxes");
    for (name, centre, half) in boxes {
        let shape = Shape::at_origin(Geometry::Box { half_extents: Vector3::from(*half) });
        let pose = Isometry3::translation(centre[0], centre[1], centre[2]);
        scene.add_body(StaticBody::new(*name, pose, vec![shape])).unwrap();
    }
    scene
}

fn drawing_of(scene: &Scene) -> Drawing {
    let mut d = Drawing::new();
    d.add_scene(scene, Kind::Robot).unwrap();
    d
}

/// Pixels (x, y) that are not background.
fn covered(canvas: &Canvas) -> Vec<(u32, u32)> {
    let cam = canvas.camera();
    let mut out = Vec::new();
    for y in 0..cam.height {
        for x in 0..cam.width {
            if canvas.pixel(x, y) != Some(BACKGROUND) {
                out.push((x, y));
            }
        }
    }
    out
}

fn top_view(width: u32, height: u32, half_height: f64) -> Camera {
    let ortho = Projection::Orthographic { half_height };
    Camera::look_at(Point3::new(0.0, 0.0, 5.0), Point3::origin(), Vector3::y(), ortho, width, height).unwrap()
}

#[test]
fn orthographic_box_covers_exactly_its_projected_rectangle() {
    // 200 × 100 px showing 4 m × 2 m: x_px = 50 (x + 2), y_px = 50 (1 − y).
    // Box x ∈ [−0.3, 0.5], y ∈ [−0.5, −0.1] → x_px ∈ [85, 125], y_px ∈ [55, 75].
    let scene = box_scene(&[("b", [0.1, -0.3, 0.0], [0.4, 0.2, 0.3])]);
    let canvas = drawing_of(&scene).render(top_view(200, 100, 1.0));
    let px = covered(&canvas);
    assert_eq!(px.len(), 40 * 20);
    assert!(px.iter().all(|&(x, y)| (85..125).contains(&x) && (55..75).contains(&y)));
    // Depth of the top face (z = 0.3) from the eye at z = 5.
    let d = canvas.depth(100, 60).unwrap();
    assert!((d - 4.7).abs() < 1e-9, "depth {d}");
    assert_eq!(canvas.depth(10, 10), None);
}

#[test]
fn top_face_is_lambert_shaded() {
    // Light direction: normalise(−forward + 0.6 up − 0.3 right) = (−0.3, 0.6, 1)/√1.45 for this
    // camera; the top face's normal is +z, so the factor is 0.35 + 0.65/√1.45.
    let scene = box_scene(&[("b", [0.0, 0.0, 0.0], [0.5, 0.5, 0.5])]);
    let canvas = drawing_of(&scene).render(top_view(100, 100, 1.0));
    let f = 0.35 + 0.65 / 1.45f64.sqrt();
    let expected = Kind::Environment.colour().map(|c| (f64::from(c) * f).round() as u8);
    assert_eq!(canvas.pixel(50, 50), Some(expected));
}

#[test]
fn perspective_square_follows_the_pinhole_model() {
    // 90° field of view, 100 × 100 px: x_px = 50 (x / z + 1). A 0.48 m square 2 m in front
    // spans x/z ∈ [−0.12, 0.12] → pixels with centres in (44, 56): 12 × 12.
    let scene = box_scene(&[("b", [0.0, 0.0, 0.0], [0.24, 0.24, 0.001])]);
    let persp = Projection::Perspective { fov_y: std::f64::consts::FRAC_PI_2 };
    let eye = Point3::new(0.0, 0.0, 2.001);
    let camera = Camera::look_at(eye, Point3::origin(), Vector3::y(), persp, 100, 100).unwrap();
    let canvas = drawing_of(&scene).render(camera);
    let px = covered(&canvas);
    assert_eq!(px.len(), 12 * 12);
    assert!(px.iter().all(|&(x, y)| (44..56).contains(&x) && (44..56).contains(&y)));
    let d = canvas.depth(50, 50).unwrap();
    assert!((d - 2.0).abs() < 1e-9, "depth {d}");
}

#[test]
fn nearer_surface_wins_whatever_the_drawing_order() {
    // A high box (top at z = 1) over a low wide one (top at z = 0.2).
    let high = ("high", [0.0, 0.0, 0.5], [0.2, 0.2, 0.5]);
    let low = ("low", [0.0, 0.0, 0.0], [0.6, 0.6, 0.2]);
    for order in [[high, low], [low, high]] {
        let mut d = drawing_of(&box_scene(&order));
        for m in &mut d.meshes {
            m.colour = if m.name == "high" { [255, 0, 0] } else { [0, 0, 255] };
        }
        let canvas = d.render(top_view(100, 100, 1.0));
        let centre = canvas.pixel(50, 50).unwrap();
        let side = canvas.pixel(75, 50).unwrap();
        assert!(centre[0] > 0 && centre[2] == 0, "centre {centre:?}");
        assert!(side[2] > 0 && side[0] == 0, "side {side:?}");
        assert!((canvas.depth(50, 50).unwrap() - 4.0).abs() < 1e-9);
        assert!((canvas.depth(75, 50).unwrap() - 4.8).abs() < 1e-9);
    }
}

#[test]
fn lines_hidden_behind_a_box_are_faint_and_visible_ones_full() {
    // A segment along x at y = 0, z = −1 (under a box covering x ∈ [−0.2, 0.2]).
    let mut d = drawing_of(&box_scene(&[("b", [0.0, 0.0, 0.0], [0.2, 0.2, 0.2])]));
    d.lines.push(opengrasp_viewer::drawing::Polyline {
        name: "path".into(),
        colour: [0, 0, 0],
        points: vec![Point3::new(-0.9, 0.0, -1.0), Point3::new(0.9, 0.0, -1.0)],
    });
    let canvas = d.render(top_view(100, 100, 1.0));
    // Outside the box the line is drawn at full colour; over it only faintly.
    assert_eq!(canvas.pixel(20, 50), Some([0, 0, 0]));
    let over = canvas.pixel(50, 50).unwrap();
    assert_eq!(over, [170, 170, 170]);
}

#[test]
fn png_round_trip_gives_the_canvas_bytes() {
    let scene = box_scene(&[("b", [0.1, -0.3, 0.0], [0.4, 0.2, 0.3])]);
    let canvas = drawing_of(&scene).render(top_view(64, 48, 1.0));
    let bytes = canvas.to_png().unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height, info.color_type), (64, 48, png::ColorType::Rgb));
    assert_eq!(&buf[..info.buffer_size()], canvas.rgb());
}

#[test]
fn bad_cameras_are_typed_errors() {
    let ortho = Projection::Orthographic { half_height: 1.0 };
    let p = Point3::new(1.0, 2.0, 3.0);
    let cases = [
        Camera::look_at(p, p, Vector3::z(), ortho, 10, 10),
        Camera::look_at(p, Point3::origin(), p.coords, ortho, 10, 10),
        Camera::look_at(p, Point3::origin(), Vector3::z(), ortho, 0, 10),
        Camera::look_at(p, Point3::origin(), Vector3::z(), Projection::Orthographic { half_height: -1.0 }, 10, 10),
        Camera::look_at(p, Point3::origin(), Vector3::z(), Projection::Perspective { fov_y: 4.0 }, 10, 10),
        Camera::look_at(Point3::new(f64::NAN, 0.0, 0.0), Point3::origin(), Vector3::z(), ortho, 10, 10),
    ];
    for c in cases {
        assert!(matches!(c, Err(ViewerError::InvalidCamera { .. })), "{c:?}");
    }
    assert!(matches!(Drawing::new().render_framed(10, 10), Err(ViewerError::InvalidCamera { .. })));
}

#[test]
fn framing_keeps_the_whole_scene_in_the_image() {
    let scene = box_scene(&[("a", [3.0, -2.0, 0.5], [1.0, 0.5, 0.5]), ("b", [-1.0, 4.0, 1.0], [0.3, 0.3, 1.0])]);
    let d = drawing_of(&scene);
    let canvas = d.render_framed(160, 120).unwrap();
    let cam = canvas.camera();
    for m in &d.meshes {
        for v in m.mesh.vertices() {
            let (x, y, _) = cam.project(v).unwrap();
            assert!(x > 0.0 && x < 160.0 && y > 0.0 && y < 120.0, "{v} at ({x}, {y})");
        }
    }
    // Nothing touches the border.
    let px = covered(&canvas);
    assert!(!px.is_empty());
    assert!(px.iter().all(|&(x, y)| x > 0 && x < 159 && y > 0 && y < 119));
}
