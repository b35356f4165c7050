//! Drawing a chart on both backends: the [`Figure`] trait every chart
//! implements, the font registration, and the atomic writing of
//! `<stem>.svg` and `<stem>.png`.

use super::glyphs::Glyphs;
use super::style::{FONT, SIZE};
use super::PlotError;
use crate::fsio::write_atomic;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// A chart that can be drawn on any backend.
pub(super) trait Figure {
    /// Image size in pixels.
    fn size(&self) -> (u32, u32) {
        SIZE
    }
    /// Draws the chart on `root` (the whole image).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// Registers the DejaVu Sans font (regular and bold) once.
pub(super) fn ensure_font() -> Result<(), PlotError> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK.get_or_init(|| {
        register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    });
    ok.then_some(()).ok_or(PlotError::Font)
}

/// `stem` with `.ext` appended (not replacing a dot already in the name).
fn with_ext(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Draws `fig` with the SVG and the bitmap backend and writes both files atomically.
pub(super) fn render<F: Figure>(fig: &F, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    ensure_font()?;
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PlotError::Io { path, source }
    };
    let (png, svg) = (with_ext(stem, "png"), with_ext(stem, "svg"));
    let dir = match stem.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    let size = fig.size();

    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        fig.draw(&root)?;
        root.present()?;
    }
    write_atomic(&svg, text.as_bytes()).map_err(io(&svg))?;

    render_png(fig, &png)?;
    Ok([png, svg])
}

/// Draws `fig` with the bitmap backend into the PNG file `png`, atomically
/// (a hidden temporary `.png` next to it, then renamed); returns `png`.
pub(super) fn render_png<F: Figure>(fig: &F, png: &Path) -> Result<PathBuf, PlotError> {
    ensure_font()?;
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PlotError::Io { path, source }
    };
    let dir = match png.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    // The bitmap backend encodes by file extension: draw into a hidden
    // temporary `.png` next to the target, then rename.
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let name = png.file_name().map(|n| n.to_string_lossy().into_owned());
    let tmp = dir.join(format!(
        ".{}.{}-{}.tmp.png",
        name.unwrap_or_default(),
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    ));
    let drawn = (|| {
        let root = Glyphs(BitMapBackend::new(&tmp, fig.size())).into_drawing_area();
        fig.draw(&root)?;
        root.present()?;
        Ok::<(), PlotError>(())
    })();
    let done = drawn.and_then(|()| std::fs::rename(&tmp, png).map_err(io(png)));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done.map(|()| png.to_path_buf())
}
