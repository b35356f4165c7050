//! The plotting module: every chart kind writes a PNG and an SVG, degenerate
//! inputs still give files, bad paths give errors. `demo_images` (ignored)
//! writes realistic demo charts to `target/tmp/plotdemo/` for looking at.

use std::path::{Path, PathBuf};

use crate::common::tempdir;
use floebench::report::plot::{
    bar_chart, line_chart, plan_view, snapshot_grid, LineChart, Panel, PlanView, PlotError, Scale,
    Series, StackedBars,
};

/// Checks both files and that the SVG contains `title`.
fn check(paths: [PathBuf; 2], title: &str) {
    let [png, svg] = paths;
    assert_eq!(png.extension().and_then(|e| e.to_str()), Some("png"));
    let bytes = std::fs::read(&png).unwrap();
    assert!(
        bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
        "{png:?} is not a PNG"
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.starts_with("<svg") || text.starts_with("<?xml"),
        "{svg:?}"
    );
    assert!(text.contains(title), "{svg:?} lacks the title {title:?}");
    // No temporary file left behind.
    for e in std::fs::read_dir(png.parent().unwrap()).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        assert!(!name.contains(".tmp"), "left over {name}");
    }
}

fn series(label: &str, color: usize, points: Vec<(f64, f64)>) -> Series {
    Series::new(label, color, points)
}

/// A regular hexagon of radius `r` around `(x, y)`.
fn hexagon(x: f64, y: f64, r: f64, phase: f64) -> Vec<(f64, f64)> {
    (0..6)
        .map(|k| {
            let a = phase + k as f64 * std::f64::consts::PI / 3.0;
            (x + r * a.cos(), y + r * a.sin())
        })
        .collect()
}

fn line(dir: &Path, name: &str, s: &[Series], y_scale: Scale) -> Result<[PathBuf; 2], PlotError> {
    let chart = LineChart {
        title: name,
        x_label: "t (s)",
        y_label: "kinetic energy (J)",
        series: s,
        x_scale: Scale::Linear,
        y_scale,
        marks: &[(10.0, "t1".into()), (50.0, "rest".into())],
    };
    line_chart(&chart, &dir.join(name))
}

#[test]
fn line_charts_including_degenerate_ones() {
    let dir = tempdir();
    let d = dir.path();
    let ramp: Vec<_> = (0..100).map(|i| (i as f64, (i * i) as f64)).collect();
    let s = [series("a", 0, ramp.clone()), series("b", 1, ramp)];
    check(line(d, "normal", &s, Scale::Linear).unwrap(), "normal");
    check(line(d, "log", &s, Scale::Log).unwrap(), "log");
    check(line(d, "auto", &s, Scale::Auto).unwrap(), "auto");
    check(line(d, "none", &[], Scale::Linear).unwrap(), "none");
    check(
        line(d, "empty", &[series("e", 2, vec![])], Scale::Log).unwrap(),
        "empty",
    );
    let one = [series("one", 3, vec![(5.0, 7.0)])];
    check(line(d, "single", &one, Scale::Linear).unwrap(), "single");
    let nan = [series(
        "nan",
        4,
        vec![
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
            (2.0, 3.0),
            (3.0, f64::NAN),
        ],
    )];
    check(line(d, "nan", &nan, Scale::Auto).unwrap(), "nan");
    let all_nan = [series("all nan", 4, vec![(f64::NAN, f64::NAN)])];
    check(
        line(d, "allnan", &all_nan, Scale::Linear).unwrap(),
        "allnan",
    );
    let flat = [series("flat", 5, vec![(1.0, 2.0), (1.0, 2.0)])];
    check(line(d, "flat", &flat, Scale::Linear).unwrap(), "flat");
    let zeros = [series("zero", 6, vec![(0.0, 0.0), (1.0, 0.0)])];
    check(line(d, "zeros", &zeros, Scale::Log).unwrap(), "zeros");
    let tiny = [series("tiny", 7, vec![(0.0, -1.234e-5), (1.0, 2.0e-6)])];
    check(line(d, "tiny", &tiny, Scale::Linear).unwrap(), "tiny");
}

#[test]
fn bar_charts_including_degenerate_ones() {
    let dir = tempdir();
    let d = dir.path();
    let cats: Vec<String> = ["event-driven", "moreau", "rapier"]
        .map(String::from)
        .to_vec();
    let segs = vec![
        ("detection".to_string(), vec![0.01, 1.0, 100.0]),
        ("solve".to_string(), vec![0.5, f64::NAN, 900.0]),
    ];
    for (name, scale) in [
        ("bars", Scale::Linear),
        ("logbars", Scale::Log),
        ("autobars", Scale::Auto),
    ] {
        let chart = StackedBars {
            title: name,
            y_label: "CPU time (s)",
            categories: &cats,
            segments: &segs,
            y_scale: scale,
            notes: &["1×".into(), "100×".into(), "1000×".into()],
        };
        check(bar_chart(&chart, &d.join(name)).unwrap(), name);
    }
    let zero = vec![("detection".to_string(), vec![0.0, -1.0, f64::NAN])];
    let chart = StackedBars {
        title: "zero bars",
        y_label: "CPU time (s)",
        categories: &cats,
        segments: &zero,
        y_scale: Scale::Auto,
        notes: &[],
    };
    check(bar_chart(&chart, &d.join("zero")).unwrap(), "zero bars");
    let chart = StackedBars {
        title: "no bars",
        y_label: "CPU time (s)",
        categories: &[],
        segments: &[],
        y_scale: Scale::Log,
        notes: &[],
    };
    check(bar_chart(&chart, &d.join("nobars")).unwrap(), "no bars");
    let bad = vec![("detection".to_string(), vec![1.0])];
    let chart = StackedBars {
        segments: &bad,
        categories: &cats,
        ..chart
    };
    assert!(matches!(
        bar_chart(&chart, &d.join("bad")),
        Err(PlotError::Input(_))
    ));
}

#[test]
fn plan_views_and_grids_including_degenerate_ones() {
    let dir = tempdir();
    let d = dir.path();
    let coast = vec![vec![(0.0, 0.0), (100.0, 0.0), (100.0, 20.0), (0.0, 10.0)]];
    let paths = [
        series(
            "floe 1",
            0,
            vec![(10.0, 50.0), (20.0, 55.0), (f64::NAN, 1.0), (30.0, 60.0)],
        ),
        series("floe 2", 1, vec![(50.0, 50.0)]),
        series("", 2, vec![]),
    ];
    let chart = PlanView {
        title: "paths",
        paths: &paths,
        obstacles: &coast,
        labels: &[("floe 1".into(), (30.0, 60.0))],
    };
    check(plan_view(&chart, &d.join("paths")).unwrap(), "paths");
    let chart = PlanView {
        title: "empty plan",
        paths: &[],
        obstacles: &[],
        labels: &[],
    };
    check(
        plan_view(&chart, &d.join("emptyplan")).unwrap(),
        "empty plan",
    );

    let panel = |t: &str, floes| Panel {
        title: t.into(),
        floes,
        labels: vec!["1".into()],
        obstacles: coast.clone(),
        ..Default::default()
    };
    let panels = [
        panel("a, t = 0 s", vec![hexagon(50.0, 50.0, 5.0, 0.0)]),
        panel("b, t = 0 s", vec![vec![(1.0, f64::NAN), (2.0, 2.0)]]),
        panel("c, t = 0 s", vec![]),
    ];
    check(
        snapshot_grid("grid", 2, 2, &panels, &d.join("grid")).unwrap(),
        "grid",
    );
    check(
        snapshot_grid("no panels", 0, 0, &[], &d.join("nogrid")).unwrap(),
        "no panels",
    );
    let point = [Panel {
        title: "point".into(),
        floes: vec![vec![(1.0, 1.0); 3]],
        labels: vec!["0".into()],
        obstacles: vec![],
        ..Default::default()
    }];
    check(
        snapshot_grid("point grid", 1, 1, &point, &d.join("point")).unwrap(),
        "point grid",
    );
    assert!(matches!(
        snapshot_grid("too many", 1, 2, &panels, &d.join("many")),
        Err(PlotError::Input(_))
    ));
}

#[test]
fn bad_path_is_an_error() {
    let dir = tempdir();
    let file = dir.path().join("file");
    std::fs::write(&file, b"x").unwrap();
    let s = [series("a", 0, vec![(0.0, 1.0), (1.0, 2.0)])];
    let err = line(&file.join("sub"), "x", &s, Scale::Linear).unwrap_err();
    assert!(matches!(err, PlotError::Io { .. }), "{err}");
}

/// Writes realistic demo charts to `target/tmp/plotdemo/` (cargo's
/// `CARGO_TARGET_TMPDIR`, not the shared temp dir; run with `--ignored`,
/// then look at them).
#[test]
#[ignore]
fn demo_images() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plotdemo");
    let mut rng = 12345u64;
    let mut rand = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };

    // Kinetic energy of 4 formulations over 6 h; two coincide exactly.
    let t: Vec<f64> = (0..=10_000).map(|i| 2.16 * i as f64).collect();
    let ke = |decay: f64, wiggle: f64| -> Vec<(f64, f64)> {
        t.iter()
            .map(|&t| {
                (
                    t,
                    1.2e4 * (-t / decay).exp() * (1.0 + wiggle * (t / 600.0).sin()),
                )
            })
            .collect()
    };
    let s = [
        series("event-driven LCP", 0, ke(5000.0, 0.05)),
        series("Moreau-Jean", 1, ke(5000.0, 0.05)),
        series("rapier", 2, ke(7000.0, 0.1)),
        series("free drift", 3, ke(20000.0, 0.0)),
    ];
    let chart = LineChart {
        title: "Kinetic energy, case packed-ice",
        x_label: "t (s)",
        y_label: "kinetic energy (J)",
        series: &s,
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
        marks: &[(3000.0, "t1".into())],
    };
    println!("{:?}", line_chart(&chart, &out.join("energy")).unwrap());
    let chart = LineChart {
        y_scale: Scale::Log,
        title: "Kinetic energy (log scale)",
        ..chart
    };
    println!("{:?}", line_chart(&chart, &out.join("energy_log")).unwrap());
    let small: Vec<Series> = (0..10)
        .map(|k| {
            let pts = (0..10_000)
                .map(|i| {
                    (
                        i as f64 * 1e-3,
                        -1.234e-5 * (1.0 + 0.1 * k as f64) * (i as f64 * 1e-3 + rand()).sin(),
                    )
                })
                .collect();
            series(&format!("run {k}"), k, pts)
        })
        .collect();
    let chart = LineChart {
        title: "Energy error, 10 runs x 10000 points",
        x_label: "t (s)",
        y_label: "energy error (J)",
        series: &small,
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
        marks: &[],
    };
    println!("{:?}", line_chart(&chart, &out.join("many")).unwrap());

    // CPU time per stage, 5 formulations from 0.01 s to 1000 s.
    let cats: Vec<String> = [
        "event-driven",
        "Moreau-Jean",
        "rapier",
        "free drift",
        "penalty",
    ]
    .map(String::from)
    .to_vec();
    let segs = vec![
        ("detection".to_string(), vec![12.0, 8.0, 3.0, 0.004, 40.0]),
        ("solve".to_string(), vec![950.0, 60.0, 5.0, 0.0, 300.0]),
        ("integration".to_string(), vec![3.0, 2.0, 1.0, 0.005, 5.0]),
        ("other".to_string(), vec![1.0, 0.5, 0.4, 0.001, 2.0]),
    ];
    for (name, scale) in [("cpu", Scale::Linear), ("cpu_auto", Scale::Auto)] {
        let chart = StackedBars {
            title: "CPU time by stage, case packed-ice",
            y_label: "CPU time (s)",
            categories: &cats,
            segments: &segs,
            y_scale: scale,
            notes: &["1×", "0.07×", "0.01×", "1e-5×", "0.3×"].map(String::from),
        };
        println!("{:?}", bar_chart(&chart, &out.join(name)).unwrap());
    }

    // Three floe paths along a coast.
    let coast = vec![vec![
        (-2000.0, -500.0),
        (8000.0, -500.0),
        (8000.0, 300.0),
        (5000.0, 600.0),
        (2000.0, 200.0),
        (-2000.0, 400.0),
    ]];
    let path = |y0: f64, drift: f64, k: usize| {
        let pts = (0..500)
            .map(|i| {
                let s = i as f64;
                (s * 12.0, y0 + drift * s + 150.0 * (s / 40.0).sin())
            })
            .collect();
        series(&format!("floe {k}"), k, pts)
    };
    let paths = [
        path(2500.0, -2.0, 0),
        path(3000.0, -3.0, 1),
        path(1800.0, 0.5, 2),
    ];
    let chart = PlanView {
        title: "Floe paths, case coast-drift",
        paths: &paths,
        obstacles: &coast,
        labels: &[("floe 1".into(), (5988.0, 2000.0))],
    };
    println!("{:?}", plan_view(&chart, &out.join("plan")).unwrap());

    // 2 x 3 snapshots of 200 random hexagons.
    let land = vec![vec![
        (0.0, 0.0),
        (1000.0, 0.0),
        (1000.0, 60.0),
        (0.0, 120.0),
    ]];
    let mut panels = Vec::new();
    for t in [0.0, 3600.0] {
        for f in ["event-driven", "Moreau-Jean", "rapier"] {
            let floes: Vec<_> = (0..200)
                .map(|_| {
                    let (x, y) = (50.0 + 900.0 * rand(), 200.0 + 500.0 * rand() - t / 40.0);
                    hexagon(x, y, 10.0 + 15.0 * rand(), rand())
                })
                .collect();
            panels.push(Panel {
                title: format!("{f}, t = {t} s"),
                labels: (0..floes.len()).map(|k| k.to_string()).collect(),
                floes,
                obstacles: land.clone(),
                ..Default::default()
            });
        }
    }
    let r = snapshot_grid(
        "Floe snapshots, case packed-ice",
        2,
        3,
        &panels,
        &out.join("grid"),
    );
    println!("{:?}", r.unwrap());
    let big: Vec<Panel> = (0..15)
        .map(|k| Panel {
            title: format!("f{}, t = {} s", k % 5, 600 * (k / 5)),
            floes: (0..3000)
                .map(|_| hexagon(1000.0 * rand(), 800.0 * rand(), 5.0, rand()))
                .collect(),
            labels: (0..3000).map(|i| i.to_string()).collect(),
            obstacles: land.clone(),
            ..Default::default()
        })
        .collect();
    let start = std::time::Instant::now();
    let r = snapshot_grid(
        "3 x 5 panels of 3000 floes",
        3,
        5,
        &big,
        &out.join("biggrid"),
    );
    println!("{:?} in {:?}", r.unwrap(), start.elapsed());
}
