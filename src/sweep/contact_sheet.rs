//! Runs side by side: a labelled grid of one frame per run (`contact_sheet.png`) and, frame by frame, the tiled comparison video.
//!
//! Layout ([`TileGrid`]): `n` runs in `columns = ⌈√n⌉` columns and
//! `rows = ⌈n / columns⌉` rows of equal cells, in run order, left to right
//! then top to bottom. A cell is the run's frame, scaled down (never up) so
//! the whole image fits in the given bound, above a white label band: the
//! run's index on one line, then one `key=value` line per varied key
//! (shortened with `..` when too wide). A run without the frame (failed, or
//! not rendered) gets a grey tile. There are no gaps, so cell `i` starts at
//! `(i mod columns · cell_width, ⌊i / columns⌋ · cell_height)`.

use super::label_text::fit_text;
use crate::render::{draw_text, text_width};
use image::{Rgba, RgbaImage, imageops};
use std::path::{Path, PathBuf};

/// The largest contact sheet, in pixels per side.
pub const MAX_SHEET_SIZE: (u32, u32) = (3840, 3840);

/// The largest frame of the comparison video, in pixels per side.
pub const MAX_COMPARISON_SIZE: (u32, u32) = (1920, 1080);

const INK: [u8; 3] = [30, 30, 36];
const LABEL_BACKGROUND: Rgba<u8> = Rgba([255, 255, 255, 255]);
const MISSING: Rgba<u8> = Rgba([150, 150, 150, 255]);

/// The geometry of a grid of labelled tiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TileGrid {
    /// Tiles per row.
    pub columns: u32,
    /// Rows of tiles.
    pub rows: u32,
    /// Size of each (scaled) frame, in pixels.
    pub tile: (u32, u32),
    /// Height of the label band under each frame, in pixels.
    pub label_height: u32,
    /// Label text size, in pixels.
    font_px: u32,
}

impl TileGrid {
    /// The grid for `count` tiles of frames `frame_size` pixels large, each
    /// with `label_lines` lines of label, fitting in `bound`.
    pub fn new(
        count: usize,
        frame_size: (u32, u32),
        label_lines: usize,
        bound: (u32, u32),
    ) -> Self {
        let count = count.max(1) as u32;
        let columns = (count as f64).sqrt().ceil() as u32;
        let rows = count.div_ceil(columns);
        let (w, h) = (frame_size.0.max(1), frame_size.1.max(1));
        let lines = label_lines.max(1) as u32;
        // Font size from the tile width, then the tile from what is left.
        let mut tile_w = w.min(bound.0 / columns).max(8);
        let mut font_px = (tile_w / 14).clamp(9, 16);
        let mut label_height = lines * (font_px * 5 / 4) + font_px / 2;
        let height_left = (bound.1 / rows).saturating_sub(label_height).max(8);
        let by_height = ((height_left as u64 * w as u64) / h as u64) as u32;
        if by_height < tile_w {
            tile_w = by_height.max(8);
            font_px = (tile_w / 14).clamp(9, 16);
            label_height = lines * (font_px * 5 / 4) + font_px / 2;
        }
        let tile_h = ((tile_w as u64 * h as u64) / w as u64).max(1) as u32;
        Self {
            columns,
            rows,
            tile: (tile_w, tile_h),
            label_height,
            font_px,
        }
    }

    /// The size of one cell (frame and label band).
    pub fn cell(&self) -> (u32, u32) {
        (self.tile.0, self.tile.1 + self.label_height)
    }

    /// The size of the whole image.
    pub fn size(&self) -> (u32, u32) {
        let (w, h) = self.cell();
        (self.columns * w, self.rows * h)
    }

    /// Draws the grid: `tiles[i]` (scaled to the tile size; `None`: grey)
    /// with the label lines `labels[i]` under it.
    pub fn compose(&self, tiles: &[Option<RgbaImage>], labels: &[Vec<String>]) -> RgbaImage {
        let (width, height) = self.size();
        let mut sheet = RgbaImage::from_pixel(width, height, LABEL_BACKGROUND);
        let (cell_w, cell_h) = self.cell();
        for (i, (tile, lines)) in tiles.iter().zip(labels).enumerate() {
            let (column, row) = (i as u32 % self.columns, i as u32 / self.columns);
            let (x0, y0) = (column * cell_w, row * cell_h);
            match tile {
                Some(frame) => {
                    let scaled;
                    let frame = if frame.dimensions() == self.tile {
                        frame
                    } else {
                        scaled = imageops::resize(
                            frame,
                            self.tile.0,
                            self.tile.1,
                            imageops::FilterType::Triangle,
                        );
                        &scaled
                    };
                    imageops::replace(&mut sheet, frame, x0 as i64, y0 as i64);
                }
                None => {
                    let grey = RgbaImage::from_pixel(self.tile.0, self.tile.1, MISSING);
                    imageops::replace(&mut sheet, &grey, x0 as i64, y0 as i64);
                }
            }
            let px = self.font_px as f32;
            let line_h = (self.font_px * 5 / 4) as f32;
            let margin = (px / 3.0).max(2.0);
            for (k, line) in lines.iter().enumerate() {
                let text = fit_label(line, px, cell_w as f32 - 2.0 * margin);
                let baseline = (y0 + self.tile.1) as f32 + line_h * (k as f32 + 1.0);
                draw_text(&mut sheet, &text, x0 as f32 + margin, baseline, px, INK);
            }
        }
        sheet
    }
}

/// A `key.path=value` line that does not fit loses the key's leading
/// components (`young=300`), then is cut with `..`.
fn fit_label(line: &str, px: f32, width: f32) -> String {
    if text_width(line, px) <= width {
        return line.to_owned();
    }
    let shorter = match line.split_once('=') {
        Some((key, value)) => format!("{}={value}", key.rsplit('.').next().unwrap_or(key)),
        None => line.to_owned(),
    };
    fit_text(&shorter, px, width)
}

/// The PNG frames of a run folder's `frames/`, in frame order (empty when
/// there are none).
pub fn run_frames(run_dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(run_dir.join("frames")) else {
        return Vec::new();
    };
    let mut frames: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("frame_") && n.ends_with(".png"))
        })
        .collect();
    // frame_0009 < frame_0010 as text; past 10000 frames the names grow a
    // digit, so order by the number.
    frames.sort_by_key(|p| {
        let name = p.file_stem().and_then(|n| n.to_str()).unwrap_or("");
        name.trim_start_matches("frame_")
            .parse::<u64>()
            .unwrap_or(u64::MAX)
    });
    frames
}

/// Reads a PNG as RGBA; `None` when it cannot be read.
pub fn read_frame(path: &Path) -> Option<RgbaImage> {
    image::open(path).ok().map(|i| i.to_rgba8())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_hold_36_runs_within_the_bound() {
        for (count, frame) in [
            (1, (64, 48)),
            (4, (640, 360)),
            (36, (1920, 1080)),
            (100, (640, 480)),
        ] {
            let grid = TileGrid::new(count, frame, 3, MAX_SHEET_SIZE);
            assert!(grid.columns * grid.rows >= count as u32);
            let (w, h) = grid.size();
            assert!(
                w <= MAX_SHEET_SIZE.0 && h <= MAX_SHEET_SIZE.1,
                "{count}: {w}x{h}"
            );
            assert!(grid.tile.0 <= frame.0, "never scaled up");
            let aspect = grid.tile.0 as f64 / grid.tile.1 as f64;
            let expected = frame.0 as f64 / frame.1 as f64;
            assert!(
                (aspect / expected - 1.0).abs() < 0.05,
                "{aspect} vs {expected}"
            );
        }
        let grid = TileGrid::new(36, (1920, 1080), 3, MAX_SHEET_SIZE);
        assert_eq!((grid.columns, grid.rows), (6, 6));
        let grid = TileGrid::new(5, (64, 48), 2, MAX_SHEET_SIZE);
        assert_eq!((grid.columns, grid.rows, grid.tile), (3, 2, (64, 48)));
    }

    #[test]
    fn each_cell_holds_its_frame_and_its_label() {
        let grid = TileGrid::new(3, (40, 30), 2, MAX_SHEET_SIZE);
        let colours = [[200, 0, 0], [0, 200, 0], [0, 0, 200]];
        let tiles: Vec<Option<RgbaImage>> = colours
            .iter()
            .map(|&[r, g, b]| Some(RgbaImage::from_pixel(40, 30, Rgba([r, g, b, 255]))))
            .collect();
        let labels: Vec<Vec<String>> = (0..3)
            .map(|i| vec![format!("#{i}"), format!("k={i}")])
            .collect();
        let sheet = grid.compose(&tiles, &labels);
        assert_eq!(sheet.dimensions(), grid.size());
        let (cw, ch) = grid.cell();
        for (i, &[r, g, b]) in colours.iter().enumerate() {
            let (x0, y0) = (
                (i as u32 % grid.columns) * cw,
                (i as u32 / grid.columns) * ch,
            );
            assert_eq!(sheet.get_pixel(x0 + 20, y0 + 15).0, [r, g, b, 255]);
            let ink = (0..grid.label_height)
                .flat_map(|y| (0..cw).map(move |x| (x, y)))
                .filter(|&(x, y)| sheet.get_pixel(x0 + x, y0 + grid.tile.1 + y).0[0] < 128)
                .count();
            assert!(ink > 10, "cell {i} has a label ({ink} dark pixels)");
        }
    }
}
