//! `report`: figures are real files with real content (PNG header and size, SVG text,
//! drawn pixels), and `flexflight report` reads run and map directories, diagnoses bad
//! input with line numbers, and never touches the run's own files.

use std::path::Path;
use std::process::Command;

use flexflight::report::map::{OverlayCurve, StabilityMap};
use flexflight::report::mesh::{DeformationFrame, MeshGeometry};
use flexflight::report::plot::{FIGURE_SIZE, Figure, PALETTE, Series, TimePlot, save_svg_png};
use plotters::prelude::*;

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |s: &[u8]| u32::from_be_bytes([s[0], s[1], s[2], s[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

/// Draw into an RGB buffer; returns the pixels.
fn render<F: Figure>(f: &F, size: (u32, u32)) -> Vec<u8> {
    let mut buf = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        f.draw(&root).unwrap();
    }
    buf
}

/// The text of every `<text>` element of an SVG, trimmed.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|chunk| {
            let body = chunk.split_once('>')?.1;
            Some(body.split_once("</text>")?.0.trim().to_string())
        })
        .collect()
}

fn count_colour(buf: &[u8], c: RGBColor) -> usize {
    buf.chunks(3).filter(|p| p == &[c.0, c.1, c.2]).count()
}

fn sine_plot() -> TimePlot {
    let t: Vec<f64> = (0..500).map(|k| k as f64 * 0.01).collect();
    TimePlot {
        title: "Angle of attack".into(),
        x_label: "t (s)".into(),
        y_label: "angle (deg)".into(),
        series: vec![
            Series {
                label: "alpha".into(),
                xs: t.clone(),
                ys: t.iter().map(|x| (3.0 * x).sin()).collect(),
            },
            Series {
                label: "beta".into(),
                xs: t.clone(),
                ys: t.iter().map(|x| 0.5 * (2.0 * x).cos()).collect(),
            },
        ],
        markers: vec![],
    }
}

fn test_map() -> StabilityMap {
    let xs: Vec<f64> = (0..11).map(|i| 0.4 + 0.1 * i as f64).collect();
    let ys: Vec<f64> = (0..9).map(|j| 0.5 + 0.25 * j as f64).collect();
    let values = ys
        .iter()
        .flat_map(|y| xs.iter().map(move |x| 20.0 * (y - 0.5 - 1.5 * x)))
        .collect();
    StabilityMap {
        xs,
        ys,
        values,
        x_label: "fin thickness (mm)".into(),
        y_label: "Mach".into(),
        value_label: "sigma_d (1/s)".into(),
        title: "sigma_d, planar pinned model".into(),
        overlays: vec![OverlayCurve {
            label: "NACA TN 4197".into(),
            points: vec![[0.4, 1.0], [1.4, 2.4]],
        }],
    }
}

#[test]
fn time_plot_writes_a_real_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let files = save_svg_png(&sine_plot(), &dir.path().join("alpha"), FIGURE_SIZE).unwrap();
    assert_eq!(files.len(), 2);
    let svg = std::fs::read_to_string(&files[0]).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
    let texts = svg_texts(&svg);
    for text in ["t (s)", "angle (deg)", "Angle of attack", "alpha", "beta"] {
        assert!(
            texts.iter().any(|t| t == text),
            "SVG lacks the text `{text}`: {texts:?}"
        );
    }
    let png = std::fs::read(&files[1]).unwrap();
    assert_eq!(png_size(&png), FIGURE_SIZE);
    assert!(png.len() > 10_000, "PNG of {} bytes", png.len());

    // The pixels: lines in the first two palette colours, dark text, mostly white.
    let buf = render(&sine_plot(), FIGURE_SIZE);
    let n = (FIGURE_SIZE.0 * FIGURE_SIZE.1) as usize;
    let white = count_colour(&buf, WHITE);
    assert!(
        white > n / 2 && white < n - 5_000,
        "white pixels {white} of {n}"
    );
    assert!(count_colour(&buf, PALETTE[0]) > 1_000);
    assert!(count_colour(&buf, PALETTE[1]) > 1_000);
}

#[test]
fn stability_map_has_both_signs_a_bold_zero_contour_and_the_overlay() {
    let map = test_map();
    let dir = tempfile::tempdir().unwrap();
    let files = save_svg_png(&map, &dir.path().join("map"), FIGURE_SIZE).unwrap();
    let svg = std::fs::read_to_string(&files[0]).unwrap();
    let texts = svg_texts(&svg);
    for text in [
        "fin thickness (mm)",
        "Mach",
        "sigma_d (1/s)",
        "NACA TN 4197",
    ] {
        assert!(
            texts.iter().any(|t| t == text),
            "SVG lacks `{text}`: {texts:?}"
        );
    }
    assert!(svg.contains("stroke-width=\"4\""), "bold zero contour");
    assert_eq!(png_size(&std::fs::read(&files[1]).unwrap()), FIGURE_SIZE);

    let buf = render(&map, FIGURE_SIZE);
    let reddish = buf.chunks(3).filter(|p| p[0] > 150 && p[2] < 120).count();
    let bluish = buf.chunks(3).filter(|p| p[2] > 150 && p[0] < 120).count();
    assert!(
        reddish > 10_000 && bluish > 10_000,
        "red {reddish} blue {bluish}"
    );
    assert!(count_colour(&buf, BLACK) > 1_500, "zero contour and text");
    assert!(count_colour(&buf, PALETTE[3]) > 300, "overlay curve");
}

#[test]
fn deformation_frame_draws_both_views() {
    // A cross of four one-element "fins" on a two-node body; one mode lifts fin tips in z.
    let positions = vec![
        [0.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-1.0, 0.3, 0.0],
        [-1.0, 0.0, 0.3],
        [-1.0, -0.3, 0.0],
        [-1.0, 0.0, -0.3],
    ];
    let mut shapes = vec![0.0; 6 * positions.len()];
    shapes[6 * 2 + 2] = 1.0;
    shapes[6 * 4 + 2] = -1.0;
    let geometry = MeshGeometry {
        positions,
        components: vec![-1, -1, 0, 1, 2, 3],
        edges: vec![[0, 1], [1, 2], [1, 3], [1, 4], [1, 5]],
        shapes,
        mode_names: vec!["fin_flap".into()],
    };
    let frame = DeformationFrame {
        geometry: &geometry,
        eta: vec![0.1],
        t: 0.5,
        magnify: 1.0,
        title: "frame".into(),
    };
    let buf = render(&frame, (1200, 600));
    for (fin, colour) in PALETTE.iter().take(4).enumerate() {
        assert!(count_colour(&buf, *colour) > 50, "fin {fin}");
    }
    let dir = tempfile::tempdir().unwrap();
    let files = save_svg_png(&frame, &dir.path().join("frame_01"), (1200, 600)).unwrap();
    assert!(files[0].ends_with("frame_01.svg") && files[1].ends_with("frame_01.png"));
    let svg = std::fs::read_to_string(&files[0]).unwrap();
    assert!(
        svg_texts(&svg)
            .iter()
            .any(|t| t == "front view (looking aft)")
    );
}

fn flexflight(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(args)
        .output()
        .unwrap()
}

fn write_history(dir: &Path) -> String {
    let mut s = String::from(
        "t,v_body_x,alpha,beta,mach,eta_fin1_flap,eta_fin1_twist,eta_dot_fin1_flap,energy_total\n",
    );
    for k in 0..200 {
        let t = k as f64 * 0.01;
        s.push_str(&format!(
            "{t},{},{},{},0.8,{},{},{},100\n",
            250.0 - t,
            (5.0 * t).sin(),
            0.1 * t,
            1e-3 * (40.0 * t).sin(),
            1e-4 * (90.0 * t).cos(),
            4e-2 * (40.0 * t).cos()
        ));
    }
    std::fs::write(dir.join("history.csv"), &s).unwrap();
    s
}

#[test]
fn report_of_a_run_directory() {
    let dir = tempfile::tempdir().unwrap();
    let history = write_history(dir.path());
    let out = flexflight(&["report", dir.path().to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("no summary.json"), "{stderr}");
    let report = dir.path().join("report");
    for stem in [
        "alpha",
        "mach",
        "velocity_axial",
        "fin_flap",
        "fin_twist",
        "energy",
    ] {
        for ext in ["svg", "png"] {
            assert!(
                report.join(format!("{stem}.{ext}")).is_file(),
                "{stem}.{ext}"
            );
        }
    }
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("<img src=\"fin_flap.svg\""));
    assert!(html.contains("href=\"fin_flap.png\""));
    assert!(
        html.contains("Skipped: Body bending modal coordinates"),
        "no bending column"
    );
    assert!(html.contains("Skipped: Deformation frames"));
    assert!(!report.join("body_bending.svg").exists());
    // The run's own file is untouched.
    assert_eq!(
        std::fs::read_to_string(dir.path().join("history.csv")).unwrap(),
        history
    );
}

#[test]
fn report_of_a_map_directory() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("map.csv"), test_map().to_csv()).unwrap();
    std::fs::write(
        dir.path().join("overlay_TN_4197.csv"),
        "thickness_mm,mach\n0.4,1.0\n1.4,2.4\n",
    )
    .unwrap();
    let out = flexflight(&["report", dir.path().to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(dir.path().join("report/map.svg")).unwrap();
    let texts = svg_texts(&svg);
    assert!(texts.iter().any(|t| t == "sigma_d (1/s)"));
    assert!(
        texts.iter().any(|t| t == "TN 4197"),
        "overlay legend: {texts:?}"
    );
    assert!(dir.path().join("report/map.png").is_file());
}

#[test]
fn bad_input_is_diagnosed() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("history.csv"), "t,alpha\n0,1\n0.1,one\n").unwrap();
    let out = flexflight(&["report", dir.path().to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("history.csv:3:"), "{stderr}");
    assert!(stderr.contains("report::csv"), "{stderr}");
    assert!(
        !dir.path().join("report").exists(),
        "nothing written on bad input"
    );

    let maps = tempfile::tempdir().unwrap();
    std::fs::write(maps.path().join("map.csv"), "x,y,sigma_d\n0,0,1\n1,0\n").unwrap();
    let out = flexflight(&["report", maps.path().to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("map.csv:3:"), "{stderr}");

    let missing = dir.path().join("no-such-run");
    let out = flexflight(&["report", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a directory"));

    let empty = tempfile::tempdir().unwrap();
    let out = flexflight(&["report", empty.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nothing to report"));

    write_history(dir.path());
    let out = flexflight(&["report", dir.path().to_str().unwrap(), "--magnify", "big"]);
    assert_eq!(out.status.code(), Some(2));
}

/// A short real run of the thesis example, then its report with deformation frames: the
/// artifact recorded in summary.json is found, the mesh is rebuilt from the vehicle file
/// with its element edges, and the run's files stay as they were.
#[test]
fn report_of_a_real_run_draws_frames() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = root.join("examples/thesis/section_6_5.vdl");
    let tmp = tempfile::tempdir().unwrap();
    let (run, cache) = (tmp.path().join("run"), tmp.path().join("cache"));
    let out = flexflight(&[
        "run",
        file.to_str().unwrap(),
        "--scenario",
        "supersonic_t10",
        "--set",
        "run.stop_time=0.02 s",
        "--out",
        run.to_str().unwrap(),
        "--cache-dir",
        cache.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = std::fs::read(run.join("summary.json")).unwrap();
    let history = std::fs::read(run.join("history.csv")).unwrap();
    let out = flexflight(&[
        "report",
        run.to_str().unwrap(),
        "--frames",
        "0.01,0.02",
        "--vehicle-file",
        file.to_str().unwrap(),
        "--cache-dir",
        cache.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    let report = run.join("report");
    for stem in [
        "frame_01",
        "frame_02",
        "fin_flap",
        "fin_twist",
        "body_bending",
    ] {
        let png = std::fs::read(report.join(format!("{stem}.png"))).unwrap();
        assert!(png_size(&png).0 > 0, "{stem}");
        assert!(report.join(format!("{stem}.svg")).is_file(), "{stem}");
    }
    assert!(!report.join("frame_03.svg").exists());
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("Deformed FE mesh at t = 0.0100 s"), "{html}");
    assert!(html.contains("supersonic_t10"));
    assert!(!html.contains("no element topology"));
    assert_eq!(std::fs::read(run.join("summary.json")).unwrap(), summary);
    assert_eq!(std::fs::read(run.join("history.csv")).unwrap(), history);

    // A second report with one frame removes the first report's second frame.
    let out = flexflight(&[
        "report",
        run.to_str().unwrap(),
        "--frames",
        "0.015",
        "--cache-dir",
        cache.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(report.join("frame_01.svg").is_file());
    assert!(!report.join("frame_02.svg").exists() && !report.join("frame_02.png").exists());
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        html.contains("no element topology"),
        "no --vehicle-file this time"
    );
    assert_eq!(std::fs::read(run.join("history.csv")).unwrap(), history);
}
