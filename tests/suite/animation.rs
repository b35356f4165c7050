//! The compare report's animations: `animation.gif` of every case has the
//! documented number of frames (every output up to 60, evenly spaced from
//! the first to the last), one panel per completed formulation within the
//! documented pixel sizes, frames that change where the floes move and only
//! the time stamp where they do not; the page shows and links it; bad
//! inputs write no file.

use crate::common::{case_path, case_text, load, scenario, tempdir};
use floebench::compare::{self, CompareOptions};
use floebench::model::Scenario;
use floebench::report::figures::{animation_outputs, ANIMATION_FRAMES, ANIMATION_POLYGONS};
use floebench::report::plot::{
    self, AnimationFrame, Panel, PlotError, FRAME_DELAY_CS, LAST_FRAME_DELAY_CS, PANEL_MAX,
    TITLE_HEIGHT, WIDTH_MAX,
};
use std::path::{Path, PathBuf};

/// A decoded GIF: its size, every frame composited over the ones before
/// (RGBA), the delays (centiseconds) and whether it loops.
struct Gif {
    width: usize,
    height: usize,
    frames: Vec<Vec<u8>>,
    delays: Vec<u16>,
    loops: bool,
}

fn decode(path: &Path) -> Gif {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts
        .read_info(file)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (width, height) = (usize::from(d.width()), usize::from(d.height()));
    let loops = d.repeat() == gif::Repeat::Infinite;
    let mut canvas = vec![255u8; 4 * width * height];
    let (mut frames, mut delays) = (Vec::new(), Vec::new());
    while let Some(f) = d
        .read_next_frame()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    {
        let (l, t, w) = (
            usize::from(f.left),
            usize::from(f.top),
            usize::from(f.width),
        );
        for (k, px) in f.buffer.chunks_exact(4).enumerate() {
            if px[3] == 0 {
                continue; // transparent: the frame before shows
            }
            let (x, y) = (l + k % w, t + k / w);
            assert!(
                x < width && y < height,
                "{}: frame outside the image",
                path.display()
            );
            canvas[4 * (y * width + x)..4 * (y * width + x) + 4].copy_from_slice(px);
        }
        delays.push(f.delay);
        frames.push(canvas.clone());
    }
    Gif {
        width,
        height,
        frames,
        delays,
        loops,
    }
}

impl Gif {
    /// The pixels of frame `k` below the title strip (the panels).
    fn panels(&self, k: usize) -> &[u8] {
        &self.frames[k][4 * TITLE_HEIGHT as usize * self.width..]
    }

    /// The title strip of frame `k` (the time stamp).
    fn title(&self, k: usize) -> &[u8] {
        &self.frames[k][..4 * TITLE_HEIGHT as usize * self.width]
    }
}

/// Compares `cases` with `formulations` and writes the report into `out`;
/// returns index.md and index.html.
fn report(cases: Vec<(PathBuf, Scenario)>, formulations: &[&str], out: &Path) -> (String, String) {
    let opts = CompareOptions {
        formulations: formulations.iter().map(|f| f.to_string()).collect(),
        progress: false,
        chaos_probe: false,
        ..CompareOptions::default()
    };
    let comps = compare::compare(cases, &opts).unwrap_or_else(|e| panic!("{e}"));
    floebench::report::compare::write_report(&comps, out, "test").unwrap_or_else(|e| panic!("{e}"));
    let read = |f: &str| std::fs::read_to_string(out.join(f)).unwrap();
    (read("index.md"), read("index.html"))
}

/// The output times of a run written by `compare` (its trajectory.csv).
fn outputs(run_dir: &Path) -> usize {
    let text = std::fs::read_to_string(run_dir.join("trajectory.csv")).unwrap();
    let mut times: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    times.dedup();
    times.len()
}

/// Width of an animation of `cols` panels by the documented rule (the
/// README: panels at most 320 px wide, the image at most 1280 px, at least
/// 600 for its title).
fn expected_width(cols: u32) -> usize {
    assert_eq!((PANEL_MAX, WIDTH_MAX), (320, 1280), "the README's sizes");
    (cols * (1280 / cols).min(320)).max(600) as usize
}

#[test]
fn compare_writes_a_gif_of_the_documented_frames_and_size_and_links_it() {
    let dir = tempdir();
    let out = dir.path().join("r");
    // head_on: 41 outputs, all shown; cradle_gaps: 101 outputs, 60 shown.
    let names = ["head_on", "cradle_gaps"];
    let forms = ["event-driven", "moreau", "rapier"];
    let cases = names.iter().map(|n| (case_path(n), load(n))).collect();
    let (md, html) = report(cases, &forms, &out);
    for name in names {
        let case = out.join(name);
        let n = outputs(&case.join("event-driven"));
        // The README's bound: at most 60 frames.
        let want = n.min(60);
        let gif = decode(&case.join("animation.gif"));
        assert_eq!(gif.frames.len(), want, "{name}: {n} outputs");
        assert_eq!(gif.width, expected_width(forms.len() as u32), "{name}");
        assert!(gif.width <= WIDTH_MAX as usize);
        assert!(
            gif.height > TITLE_HEIGHT as usize && gif.height <= (TITLE_HEIGHT + PANEL_MAX) as usize,
            "{name}: height {}",
            gif.height
        );
        assert!(gif.loops, "{name}: does not loop");
        let mut delays = vec![FRAME_DELAY_CS; want - 1];
        delays.push(LAST_FRAME_DELAY_CS);
        assert_eq!(gif.delays, delays, "{name}");
        // The time stamp changes on every frame.
        for k in 1..want {
            assert_ne!(gif.title(k - 1), gif.title(k), "{name}: same title at {k}");
        }
        // The floes move: the first and the last frame differ in the panels.
        assert_ne!(gif.panels(0), gif.panels(want - 1), "{name}");
        // Shown and linked from the page, with the frame count and sizes.
        let path = format!("{name}/animation.gif");
        assert!(
            md.contains(&format!("]({path})]({path})")),
            "index.md does not show and link {path}"
        );
        assert!(
            html.contains(&format!(
                "<a href=\"{path}\"><img class=\"anim\" src=\"{path}\""
            )),
            "index.html does not show and link {path}"
        );
        for text in [
            format!("{want} of the {n} output times"),
            format!("{}×{} px", gif.width, gif.height),
            format!("{PANEL_MAX}×{PANEL_MAX} px"),
        ] {
            assert!(md.contains(&text), "index.md lacks {text:?}");
        }
        // Nothing temporary left in the case folder.
        for e in std::fs::read_dir(&case).unwrap() {
            let f = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!f.starts_with('.'), "{name}: left {f}");
        }
    }
    // head_on before the impact (t < 8.3 s): floe 0 moves 0.25 m per
    // output, more than a pixel: every frame differs from the one before.
    let gif = decode(&out.join("head_on/animation.gif"));
    for k in 1..16 {
        assert_ne!(
            gif.panels(k - 1),
            gif.panels(k),
            "head_on: frame {k} as {}",
            k - 1
        );
    }
}

#[test]
fn still_floes_give_frames_that_differ_only_in_the_time_stamp() {
    let text = case_text("head_on")
        .replace("name = \"head_on\"", "name = \"still\"")
        .replace("velocity = [0.5, 0.0]", "velocity = [0.0, 0.0]")
        .replace("velocity = [-0.1, 0.0]", "velocity = [0.0, 0.0]");
    assert_eq!(text.matches("velocity = [0.0, 0.0]").count(), 2);
    let dir = tempdir();
    let out = dir.path().join("r");
    let forms = ["event-driven", "moreau"];
    report(vec![(case_path("head_on"), scenario(&text))], &forms, &out);
    let gif = decode(&out.join("still/animation.gif"));
    assert_eq!(gif.frames.len(), outputs(&out.join("still/moreau")).min(60));
    assert_eq!(gif.width, expected_width(2));
    for k in 1..gif.frames.len() {
        assert_eq!(
            gif.panels(k - 1),
            gif.panels(k),
            "still: panels of frame {k} changed"
        );
        assert_ne!(
            gif.title(k - 1),
            gif.title(k),
            "still: same time stamp at {k}"
        );
    }
}

#[test]
fn the_outputs_shown_are_evenly_spaced_from_the_first_to_the_last_and_capped() {
    assert!(animation_outputs(0, 10).is_empty());
    assert_eq!(animation_outputs(1, 10), [0]);
    assert_eq!(animation_outputs(41, 8), (0..41).collect::<Vec<_>>());
    for (n, per_frame) in [(401, 80), (101, 5), (61, 1), (100_000, 4), (1000, 80_000)] {
        let k = animation_outputs(n, per_frame);
        let want = n
            .min(ANIMATION_FRAMES)
            .min((ANIMATION_POLYGONS / per_frame).max(2));
        assert_eq!(k.len(), want, "{n} outputs, {per_frame} polygons a frame");
        assert_eq!((k[0], k[want - 1]), (0, n - 1));
        // Evenly spaced: each gap is the mean gap rounded down or up.
        let mean = (n - 1) as f64 / (want - 1) as f64;
        for w in k.windows(2) {
            let gap = (w[1] - w[0]) as f64;
            assert!(
                gap >= mean.floor() && gap <= mean.ceil(),
                "{n}: gap {gap}, mean {mean}"
            );
        }
    }
    // A field beyond the polygon budget: 2 frames, never fewer.
    assert_eq!(animation_outputs(500, 4 * 20_000 * 10), [0, 499]);
}

/// A panel of one square floe at `x`.
fn square_at(x: f64) -> Panel {
    Panel {
        title: "f".into(),
        floes: vec![vec![(x, 0.0), (x + 1.0, 0.0), (x + 1.0, 1.0), (x, 1.0)]],
        labels: vec!["0".into()],
        obstacles: Vec::new(),
        ..Default::default()
    }
}

#[test]
fn a_bad_animation_writes_no_file() {
    let dir = tempdir();
    let path = dir.path().join("a.gif");
    assert!(matches!(
        plot::animation(2, &[], &path),
        Err(PlotError::Input(_))
    ));
    let three = AnimationFrame {
        title: "t = 0 s".into(),
        panels: vec![square_at(0.0), square_at(1.0), square_at(2.0)],
    };
    assert!(matches!(
        plot::animation(2, &[three], &path),
        Err(PlotError::Input(_))
    ));
    // A folder where the file should go: the write fails, no temporary left.
    std::fs::create_dir(&path).unwrap();
    let one = AnimationFrame {
        title: "t = 0 s".into(),
        panels: vec![square_at(0.0)],
    };
    assert!(matches!(
        plot::animation(1, std::slice::from_ref(&one), &path),
        Err(PlotError::Io { .. })
    ));
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["a.gif"], "left behind");
    // And a good one: one frame, decoded whole.
    let good = dir.path().join("b.gif");
    let size = plot::animation(1, &[one], &good).unwrap();
    let gif = decode(&good);
    assert_eq!((gif.width as u32, gif.height as u32), size);
    assert_eq!(gif.delays, [LAST_FRAME_DELAY_CS]);
}

#[test]
fn a_frame_decodes_the_same_whichever_frame_came_before() {
    // Frame differences and transparency: a composited frame is the same
    // whichever frame came before it.
    let dir = tempdir();
    let frame = |k: usize| AnimationFrame {
        title: format!("t = {k} s"),
        panels: vec![square_at(0.3 * k as f64), square_at(2.0 - 0.2 * k as f64)],
    };
    let frames: Vec<AnimationFrame> = (0..8).map(frame).collect();
    let all = dir.path().join("all.gif");
    plot::animation(2, &frames, &all).unwrap();
    let gif = decode(&all);
    assert_eq!(gif.frames.len(), 8);
    for k in [1, 3, 4, 7] {
        // Frame k after frame 0 and after frame 3; the palette is drawn
        // from the first, middle and last frames, here as in `all`.
        let alone = dir.path().join(format!("{k}.gif"));
        let five = [0, k, 3, k, 7].map(|j| frames[j].clone());
        plot::animation(2, &five, &alone).unwrap();
        let again = decode(&alone);
        for j in [1, 3] {
            assert!(
                again.frames[j] == gif.frames[k],
                "frame {k} after frame {} differs from frame {k} after {}",
                [0, k, 3][j - 1],
                k - 1
            );
        }
        assert!(
            gif.frames[k] != gif.frames[k - 1],
            "frame {k} did not change"
        );
    }
}

/// Draws the animation of a large synthetic field (4 panels of 20 000
/// floes: the polygon budget gives 15 frames) and prints the time and size:
/// `cargo test --release --test suite animation::demo -- --ignored --nocapture`.
#[test]
#[ignore]
fn demo_large_field() {
    let floes = 20_000;
    let frames: Vec<AnimationFrame> = animation_outputs(1000, 4 * floes)
        .iter()
        .map(|&k| AnimationFrame {
            title: format!("field: t = {k} s"),
            panels: (0..4)
                .map(|p| Panel {
                    title: format!("f{p}"),
                    floes: (0..floes)
                        .map(|i| {
                            let (x, y) = ((i % 141) as f64 * 7.0, (i / 141) as f64 * 7.0);
                            let d = 0.01 * k as f64 * (1 + p) as f64;
                            vec![
                                (x + d, y),
                                (x + d + 5.0, y),
                                (x + d + 5.0, y + 5.0),
                                (x + d, y + 5.0),
                            ]
                        })
                        .collect(),
                    labels: (0..floes).map(|i| i.to_string()).collect(),
                    obstacles: Vec::new(),
                    ..Default::default()
                })
                .collect(),
        })
        .collect();
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("field.gif");
    let start = std::time::Instant::now();
    let size = plot::animation(4, &frames, &path).unwrap();
    println!(
        "{} frames {size:?} in {:?}, {} bytes",
        frames.len(),
        start.elapsed(),
        std::fs::metadata(&path).unwrap().len()
    );
}
