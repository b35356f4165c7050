//! Animated GIFs of snapshot panels: every frame is a one-row [`Grid`]
//! (the snapshot grid's drawing, bounds shared by every panel of every
//! frame), drawn into an RGB buffer, reduced to one global palette and
//! encoded as the difference from the frame before.
//!
//! - **Palette**: the 63 most frequent colours of the first, middle and
//!   last frame (ties by colour value, so the file is deterministic); a
//!   colour outside it takes its nearest entry (squared RGB distance). The
//!   charts use few colours (white, black, the floe fill and outline,
//!   obstacle greys, and the shades of anti-aliased text and outlines), so
//!   only rare shades move.
//! - **Frames**: the first is whole; each later one is the bounding box of
//!   the pixels whose palette index changed, the unchanged ones inside it
//!   transparent, drawn over the frame before (disposal "keep"). A frame
//!   with no change is one transparent pixel, so the frame count stays the
//!   number of times shown.
//! - **File**: encoded in memory and written atomically
//!   ([`crate::fsio::write_atomic`]): an interrupted run leaves no
//!   partial GIF.

use super::glyphs::Glyphs;
use super::grid::{shared_bounds, Grid};
use super::render::{ensure_font, Figure};
use super::{AnimationFrame, PlotError};
use crate::fsio::write_atomic;
use plotters::prelude::*;
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

/// Largest panel of an animation, width and height (pixels).
pub const PANEL_MAX: u32 = 320;

/// Largest width of an animation (pixels): a row of more than four panels
/// gets narrower ones.
pub const WIDTH_MAX: u32 = 1280;

/// Time each frame is shown (centiseconds: 10 frames per second).
pub const FRAME_DELAY_CS: u16 = 10;

/// Time the last frame is shown before the animation starts over
/// (centiseconds).
pub const LAST_FRAME_DELAY_CS: u16 = 100;

/// Colours of the palette (then the transparent index: a 64-entry table,
/// 6-bit codes). 63 keep the chart colours and enough greys of the
/// anti-aliased text; 255 make the files about 10 % larger for no visible
/// difference.
const PALETTE_COLORS: usize = 63;

/// The global palette: at most [`PALETTE_COLORS`] colours, then the
/// transparent index.
struct Palette {
    colors: Vec<[u8; 3]>,
    index: HashMap<[u8; 3], u8>,
}

impl Palette {
    /// The [`PALETTE_COLORS`] most frequent colours of the RGB buffers `samples`.
    fn of(samples: &[&[u8]]) -> Palette {
        let mut count: HashMap<[u8; 3], usize> = HashMap::new();
        for s in samples {
            for px in s.chunks_exact(3) {
                *count.entry([px[0], px[1], px[2]]).or_default() += 1;
            }
        }
        let mut by_count: Vec<([u8; 3], usize)> = count.into_iter().collect();
        by_count.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let colors: Vec<[u8; 3]> = by_count
            .into_iter()
            .take(PALETTE_COLORS)
            .map(|(c, _)| c)
            .collect();
        let index = colors
            .iter()
            .enumerate()
            .map(|(i, c)| (*c, i as u8))
            .collect();
        Palette { colors, index }
    }

    /// The index that shows no change (one past the colours).
    fn transparent(&self) -> u8 {
        self.colors.len() as u8
    }

    /// The palette index of `c`: its own, else its nearest colour's.
    fn of_color(&mut self, c: [u8; 3]) -> u8 {
        if let Some(&i) = self.index.get(&c) {
            return i;
        }
        let d = |p: &[u8; 3]| -> i32 {
            (0..3)
                .map(|k| (i32::from(p[k]) - i32::from(c[k])).pow(2))
                .sum()
        };
        let i = (0..self.colors.len())
            .min_by_key(|&i| d(&self.colors[i]))
            .unwrap_or(0) as u8;
        self.index.insert(c, i);
        i
    }

    /// The colour table as the encoder takes it: the colours, then a
    /// white entry for the transparent index.
    fn table(&self) -> Vec<u8> {
        self.colors
            .iter()
            .chain(std::iter::once(&[255, 255, 255]))
            .flatten()
            .copied()
            .collect()
    }
}

/// Indexes the RGB buffer `rgb` into `indexed` (the previous frame's
/// indices, updated in place where the colour changed from `before`, the
/// previous frame's RGB buffer; `None`: the first frame); returns the
/// sub-frame to encode, `(left, top, width, height, indices)`: the
/// bounding box of the pixels whose index changed, the others in it
/// transparent (the first frame: all of it).
fn difference(
    palette: &mut Palette,
    rgb: &[u8],
    before: Option<&[u8]>,
    indexed: &mut [u8],
    width: usize,
) -> (usize, usize, usize, usize, Vec<u8>) {
    let old = before.map(|_| indexed.to_vec());
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    let mut last: Option<([u8; 3], u8)> = None;
    let line = 3 * width;
    for (y, row) in rgb.chunks_exact(line).enumerate() {
        let prev = before.map(|b| &b[y * line..(y + 1) * line]);
        if prev == Some(row) {
            continue;
        }
        for (x, px) in row.chunks_exact(3).enumerate() {
            if prev.is_some_and(|p| p[3 * x..3 * x + 3] == *px) {
                continue;
            }
            let c = [px[0], px[1], px[2]];
            let i = match last {
                Some((lc, li)) if lc == c => li,
                _ => {
                    let i = palette.of_color(c);
                    last = Some((c, i));
                    i
                }
            };
            let k = y * width + x;
            if old.is_some() && indexed[k] == i {
                continue;
            }
            indexed[k] = i;
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    let Some(old) = old else {
        let height = indexed.len() / width.max(1);
        return (0, 0, width, height, indexed.to_vec());
    };
    if x0 > x1 {
        return (0, 0, 1, 1, vec![palette.transparent()]);
    }
    let (w, h) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut sub = Vec::with_capacity(w * h);
    for y in y0..=y1 {
        let span = y * width + x0..=y * width + x1;
        sub.extend(indexed[span.clone()].iter().zip(&old[span]).map(|(n, o)| {
            if n == o {
                palette.transparent()
            } else {
                *n
            }
        }));
    }
    (x0, y0, w, h, sub)
}

/// Draws `frames` (each one row of at most `cols` panels) and writes them
/// as a looping GIF at `path`; returns the image size (pixels).
pub(super) fn write_gif<'a>(
    cols: usize,
    frames: &'a [AnimationFrame],
    path: &Path,
) -> Result<(u32, u32), PlotError> {
    ensure_font()?;
    if frames.is_empty() {
        return Err(PlotError::Input("an animation needs a frame".into()));
    }
    let cols = cols.max(1);
    if let Some(f) = frames.iter().find(|f| f.panels.len() > cols) {
        return Err(PlotError::Input(format!(
            "frame `{}` has {} panels for {cols} columns",
            f.title,
            f.panels.len()
        )));
    }
    let bounds = shared_bounds(frames.iter().flat_map(|f| f.panels.iter()));
    let panel_w = (WIDTH_MAX / cols as u32).min(PANEL_MAX);
    let grid = |f: &'a AnimationFrame| Grid {
        title: &f.title,
        rows: 1,
        cols,
        panels: &f.panels,
        bounds: bounds.clone(),
        panel_w,
        square: true,
    };
    let size = grid(&frames[0]).size();
    let draw = |f: &'a AnimationFrame| -> Result<Vec<u8>, PlotError> {
        let mut buf = vec![0u8; 3 * size.0 as usize * size.1 as usize];
        {
            let root = Glyphs(BitMapBackend::with_buffer(&mut buf, size)).into_drawing_area();
            grid(f).draw(&root)?;
            root.present()?;
        }
        Ok(buf)
    };
    let last = frames.len() - 1;
    let sampled = [0, last / 2, last];
    let mut kept: Vec<(usize, Vec<u8>)> = Vec::new();
    for k in sampled {
        if kept.iter().all(|(j, _)| *j != k) {
            kept.push((k, draw(&frames[k])?));
        }
    }
    let mut palette = {
        let samples: Vec<&[u8]> = kept.iter().map(|(_, b)| b.as_slice()).collect();
        Palette::of(&samples)
    };
    let gif_err = |e: gif::EncodingError| PlotError::Draw(format!("GIF encoding: {e}"));
    let (w, h) = (
        u16::try_from(size.0).map_err(|_| PlotError::Input("image too wide".into()))?,
        u16::try_from(size.1).map_err(|_| PlotError::Input("image too tall".into()))?,
    );
    let mut enc = gif::Encoder::new(Vec::new(), w, h, &palette.table()).map_err(gif_err)?;
    enc.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
    let mut indexed = vec![0u8; size.0 as usize * size.1 as usize];
    let mut before: Option<Vec<u8>> = None;
    for (k, f) in frames.iter().enumerate() {
        let rgb = match kept.iter().position(|(j, _)| *j == k) {
            Some(p) => kept.swap_remove(p).1,
            None => draw(f)?,
        };

        let (left, top, fw, fh, sub) = difference(
            &mut palette,
            &rgb,
            before.as_deref(),
            &mut indexed,
            size.0 as usize,
        );
        let frame = gif::Frame {
            delay: if k == last {
                LAST_FRAME_DELAY_CS
            } else {
                FRAME_DELAY_CS
            },
            dispose: gif::DisposalMethod::Keep,
            transparent: before.as_ref().map(|_| palette.transparent()),
            left: left as u16,
            top: top as u16,
            width: fw as u16,
            height: fh as u16,
            buffer: Cow::Owned(sub),
            ..gif::Frame::default()
        };
        enc.write_frame(&frame).map_err(gif_err)?;

        before = Some(rgb);
    }
    let bytes = enc.into_inner().map_err(gif_err)?;

    write_atomic(path, &bytes).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(size)
}
