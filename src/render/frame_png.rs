//! PNG files of frames, written so that a frame over its run's fixed base
//! costs what its patch costs, not what the image costs.
//!
//! A whole image goes through the `png` crate (adaptive filters, fdeflate).
//! For a frame over a base ([`FrameImage`]) the image data is assembled from
//! pieces instead. A PNG's image data is one zlib stream of the filtered
//! rows, each row a filter-type byte and its `3W` RGB bytes:
//!
//! ```text
//! IDAT = 78 01 · deflate(r_0 ‖ r_1 ‖ … ‖ r_{H−1}) · Adler-32(r_0 ‖ … ‖ r_{H−1})
//! ```
//!
//! Deflate data is a sequence of blocks, and a *sync flush* ends the blocks
//! so far on a byte boundary (with an empty stored block, `00 00 FF FF`). So
//! pieces compressed separately, each from an empty history, concatenate
//! into one valid stream closed by an empty final block (`03 00`, fixed
//! codes):
//!
//! ```text
//! deflate(a ‖ b ‖ c) = sync(a) · sync(b) · sync(c) · 03 00
//! ```
//!
//! Every row is filtered with *Sub* (each byte minus the byte one pixel to
//! its left), which reads nothing of other rows, so a row of the base
//! filters to the same bytes in every frame. Each base row is therefore
//! filtered and compressed once per run, with its Adler-32
//! ([`CompressedRows`]), and a frame whose patch covers rows `[y0, y1)` is
//!
//! ```text
//! 78 01 · base rows [0, y0) · sync(rows [y0, y1) with the patch, compressed now) · base rows [y1, H) · 03 00 · Adler-32
//! ```
//!
//! with the checksum of the whole combined from those of the pieces
//! (`adler32_combine`: the Adler-32 of `a ‖ b` from those of `a` and `b` and
//! the length of `b`). The patch's rows are compressed at level 1, the base's
//! at level 6 (once). Both kinds of file decode to the same pixels; the tests
//! decode them with the `png` crate and compare every pixel.

use super::RenderError;
use super::frame_image::{FrameImage, PixelRect, push_rgb};
use super::image_file::png_error;
use super::partial_file::PartialFile;
use image::RgbaImage;
use rayon::prelude::*;
use std::io::Write;
use std::path::Path;
use zlib_rs::adler32::{adler32, adler32_combine};
use zlib_rs::{Deflate, DeflateFlush, compress_bound};

/// The zlib header of the assembled streams: deflate, 32 KiB window, the
/// fastest level, no dictionary (`0x7801` is a multiple of 31).
const ZLIB_HEADER: [u8; 2] = [0x78, 0x01];
/// An empty final deflate block with fixed codes: `BFINAL = 1`,
/// `BTYPE = 01`, then the end-of-block code, seven zero bits.
const FINAL_EMPTY_BLOCK: [u8; 2] = [0x03, 0x00];
/// PNG's *Sub* filter type.
const SUB_FILTER: u8 = 1;
/// Bytes per RGB pixel, the distance *Sub* looks back.
const PIXEL_BYTES: usize = 3;
/// Compression levels: the base's rows are compressed once per run, the
/// patch's rows once per frame.
const BASE_LEVEL: i32 = 6;
const PATCH_LEVEL: i32 = 1;
/// IDAT chunks are at most this long (PNG allows 2³¹ − 1 bytes).
const MAX_IDAT_BYTES: usize = 1 << 30;

/// A PNG encoder set up as every frame and video of a run is written: RGB,
/// 8 bits, fast compression, an sRGB chunk.
pub(crate) fn png_encoder<W: Write>(
    writer: W,
    width: u32,
    height: u32,
) -> png::Encoder<'static, W> {
    let mut encoder = png::Encoder::new(writer, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    encoder
}

/// The rows of a base image as a PNG holds them: each filtered with *Sub*
/// and compressed on its own up to a sync flush.
pub(crate) struct CompressedRows {
    /// Every row filtered: the filter type and `3W` bytes, one after the other.
    filtered: Vec<u8>,
    /// Every row's compressed bytes, one after the other.
    deflated: Vec<u8>,
    /// Where each row's compressed bytes start in `deflated`, and the end
    /// of the last (`H + 1` offsets): rows `a..b` are `offsets[a]..offsets[b]`.
    offsets: Vec<usize>,
    /// Per row: the Adler-32 of its filtered bytes.
    adlers: Vec<u32>,
    /// Filtered bytes per row: the filter type and `3W`.
    row_len: usize,
}

/// Rows per piece of a base compressed on its own thread.
const ROWS_PER_PIECE: usize = 32;

impl CompressedRows {
    /// Filters and compresses every row of `image`. Each row is compressed
    /// from an empty history, so pieces of rows are compressed in parallel
    /// and joined: the same bytes whatever the number of threads.
    pub fn new(image: &RgbaImage) -> Result<Self, String> {
        let width = image.width() as usize;
        let height = image.height() as usize;
        let row_len = 1 + width * PIXEL_BYTES;
        let pieces: Vec<Result<CompressedRows, String>> = image
            .as_raw()
            .par_chunks((width * 4 * ROWS_PER_PIECE).max(1))
            .map(|rows| Self::of_rows(rows, width, row_len))
            .collect();
        let mut whole = Self::empty(height, row_len);
        for piece in pieces {
            let piece = piece?;
            let start = whole.deflated.len();
            whole.filtered.extend_from_slice(&piece.filtered);
            whole.deflated.extend_from_slice(&piece.deflated);
            whole
                .offsets
                .extend(piece.offsets[1..].iter().map(|&o| start + o));
            whole.adlers.extend_from_slice(&piece.adlers);
        }
        Ok(whole)
    }

    /// The rows of RGBA pixels `rows`, `width` pixels each.
    fn of_rows(rows: &[u8], width: usize, row_len: usize) -> Result<Self, String> {
        let mut deflate = Deflate::new(BASE_LEVEL, false, 15);
        let mut rgb = Vec::new();
        let mut piece = Self::empty(rows.len() / (width * 4).max(1), row_len);
        let mut output = Vec::new();
        for row in rows.chunks_exact(width * 4) {
            rgb.clear();
            push_rgb(row, &mut rgb);
            let start = piece.filtered.len();
            push_sub_filtered(&rgb, &mut piece.filtered);
            let filtered = &piece.filtered[start..];
            piece.adlers.push(adler32(1, filtered));
            let compressed = deflate_segment(&mut deflate, filtered, &mut output)?;
            piece.deflated.extend_from_slice(compressed);
            piece.offsets.push(piece.deflated.len());
        }
        Ok(piece)
    }

    /// No rows yet, with room for `rows` of `row_len` filtered bytes.
    fn empty(rows: usize, row_len: usize) -> Self {
        let mut offsets = Vec::with_capacity(rows + 1);
        offsets.push(0);
        CompressedRows {
            filtered: Vec::with_capacity(rows * row_len),
            deflated: Vec::new(),
            offsets,
            adlers: Vec::with_capacity(rows),
            row_len,
        }
    }

    /// Row `y` filtered.
    fn filtered_row(&self, y: usize) -> &[u8] {
        &self.filtered[y * self.row_len..(y + 1) * self.row_len]
    }

    /// The compressed bytes of `rows`, one after the other.
    fn segment(&self, rows: std::ops::Range<usize>) -> &[u8] {
        &self.deflated[self.offsets[rows.start]..self.offsets[rows.end]]
    }
}

/// Writes frames as PNG files, reusing its buffers from frame to frame.
#[derive(Default)]
pub(crate) struct FramePngWriter {
    rgb: Vec<u8>,
    filtered: Vec<u8>,
    /// The compressor's output, kept at its largest size.
    deflated: Vec<u8>,
    idat: Vec<u8>,
    /// The whole file, encoded before it is written.
    file: Vec<u8>,
    deflate: Option<Deflate>,
}

impl FramePngWriter {
    /// Writes `frame` to `path`: encoded in memory, then written under a
    /// hidden temporary name, renamed once complete.
    pub fn write(&mut self, path: &Path, frame: &FrameImage) -> Result<(), RenderError> {
        // Dropped on an error, the partial file removes itself.
        let partial = PartialFile::new(path)?;
        let mut file = std::mem::take(&mut self.file);
        file.clear();
        let encoded = self.encode(path, frame, &mut file);
        let written = encoded.and_then(|()| partial.write_whole(&file));
        self.file = file;
        written?;
        partial.publish()
    }

    /// Appends the PNG file of `frame` (to be written at `path`) to `file`.
    fn encode(
        &mut self,
        path: &Path,
        frame: &FrameImage,
        file: &mut Vec<u8>,
    ) -> Result<(), RenderError> {
        let (width, height) = frame.dimensions();
        let encode_error = |e: png::EncodingError| png_error(path, e);
        let mut writer = png_encoder(file, width, height)
            .write_header()
            .map_err(encode_error)?;
        match frame.over_base() {
            Some((base, changed)) => {
                let rows = base
                    .png_rows()
                    .as_ref()
                    .map_err(|message| RenderError::Encode {
                        path: path.to_owned(),
                        message: message.clone(),
                    })?;
                self.assemble_idat(frame, rows, changed)
                    .map_err(|message| RenderError::Encode {
                        path: path.to_owned(),
                        message,
                    })?;
                for chunk in self.idat.chunks(MAX_IDAT_BYTES) {
                    writer
                        .write_chunk(png::chunk::IDAT, chunk)
                        .map_err(encode_error)?;
                }
            }
            None => {
                self.rgb.clear();
                frame.push_rgb_rect(PixelRect::new(0, 0, width, height), &mut self.rgb);
                writer.write_image_data(&self.rgb).map_err(encode_error)?;
            }
        }
        writer.finish().map_err(encode_error)
    }

    /// The zlib stream of a frame over a base whose rows are `rows`, which
    /// differs from the base in `changed` (see the module documentation).
    fn assemble_idat(
        &mut self,
        frame: &FrameImage,
        rows: &CompressedRows,
        changed: Option<PixelRect>,
    ) -> Result<(), String> {
        let height = rows.adlers.len();
        let band = changed.map_or(height..height, |rect| {
            rect.y as usize..(rect.y + rect.height) as usize
        });
        let row_len = rows.row_len as u64;
        let base_adler = |range: std::ops::Range<usize>, adler: u32| {
            rows.adlers[range]
                .iter()
                .fold(adler, |adler, &row| adler32_combine(adler, row, row_len))
        };

        self.idat.clear();
        self.idat.extend_from_slice(&ZLIB_HEADER);
        self.idat.extend_from_slice(rows.segment(0..band.start));
        let mut adler = base_adler(0..band.start, 1);
        if let Some(patch) = changed {
            // The base's filtered rows, with the patch's pixels filtered
            // again, and the pixel right of it (Sub reads the patch's last);
            // the pixel left of the patch is read for the first.
            let width = frame.dimensions().0;
            let first = patch.x.saturating_sub(1);
            let end = (patch.x + patch.width + 1).min(width);
            let skip = (patch.x - first) as usize * PIXEL_BYTES;
            let refiltered = 1 + patch.x as usize * PIXEL_BYTES;
            self.filtered.clear();
            for y in band.clone() {
                let row_start = self.filtered.len();
                self.filtered.extend_from_slice(rows.filtered_row(y));
                self.rgb.clear();
                frame.push_rgb_row(y as u32, first..end, &mut self.rgb);
                let span = &mut self.filtered[row_start + refiltered..][..self.rgb.len() - skip];
                sub_filter_span(&self.rgb, skip, span);
            }
            let deflate = self
                .deflate
                .get_or_insert_with(|| Deflate::new(PATCH_LEVEL, false, 15));
            let compressed = deflate_segment(deflate, &self.filtered, &mut self.deflated)?;
            self.idat.extend_from_slice(compressed);
            adler = adler32_combine(
                adler,
                adler32(1, &self.filtered),
                self.filtered.len() as u64,
            );
        }
        self.idat.extend_from_slice(rows.segment(band.end..height));
        adler = base_adler(band.end..height, adler);
        self.idat.extend_from_slice(&FINAL_EMPTY_BLOCK);
        self.idat.extend_from_slice(&adler.to_be_bytes());
        Ok(())
    }
}

/// Appends the *Sub*-filtered row of the RGB pixels `rgb`: the filter type,
/// then each byte minus the byte one pixel to its left (0 left of the row).
fn push_sub_filtered(rgb: &[u8], filtered: &mut Vec<u8>) {
    filtered.push(SUB_FILTER);
    let first_pixel = rgb.len().min(PIXEL_BYTES);
    filtered.extend_from_slice(&rgb[..first_pixel]);
    filtered.extend(
        rgb[first_pixel..]
            .iter()
            .zip(rgb)
            .map(|(&byte, &left)| byte.wrapping_sub(left)),
    );
}

/// Fills `span` with the *Sub*-filtered bytes `skip..` of the RGB pixels
/// `rgb` (a piece of a row starting at the row's start, or one pixel before
/// the span: `skip` is 0 or one pixel).
fn sub_filter_span(rgb: &[u8], skip: usize, span: &mut [u8]) {
    for (i, byte) in span.iter_mut().enumerate() {
        let j = skip + i;
        *byte = match j.checked_sub(PIXEL_BYTES) {
            Some(left) => rgb[j].wrapping_sub(rgb[left]),
            None => rgb[j],
        };
    }
}

/// Compresses `input` from an empty history up to a sync flush: raw
/// deflate blocks ending on a byte boundary, none final. `output` is the
/// compressor's buffer, grown as needed and kept; the compressed bytes are
/// its start.
fn deflate_segment<'a>(
    deflate: &mut Deflate,
    input: &[u8],
    output: &'a mut Vec<u8>,
) -> Result<&'a [u8], String> {
    deflate.reset();
    // The bound holds the whole input; the flush marker adds a few bytes.
    let needed = compress_bound(input.len()) + 16;
    if output.len() < needed {
        output.resize(needed, 0);
    }
    let result = deflate.compress(input, output, DeflateFlush::SyncFlush);
    result.map_err(|e| format!("deflate failed: {}", e.as_str()))?;
    let written = deflate.total_out() as usize;
    // The flush is complete when the input is used up with room to spare.
    if deflate.total_in() as usize != input.len() || written == output.len() {
        return Err(format!(
            "deflate wrote {written} bytes for {} of {} bytes into {} bytes of room",
            deflate.total_in(),
            input.len(),
            output.len()
        ));
    }
    Ok(&output[..written])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::frame_image::{FrameBase, Patch, noise};

    /// A base like a 2D backdrop: flat colour, a hatched band, noise in a corner.
    fn backdrop(width: u32, height: u32) -> RgbaImage {
        let grain = noise(width, height, 9);
        RgbaImage::from_fn(width, height, |x, y| {
            if x < 6 && y < 5 {
                *grain.get_pixel(x, y)
            } else if y > height * 2 / 3 && (x + y) % 4 == 0 {
                image::Rgba([90, 88, 80, 255])
            } else {
                image::Rgba([242, 242, 240, 255])
            }
        })
    }

    fn decode(path: &Path) -> (png::OutputInfo, Vec<u8>) {
        let file = std::fs::File::open(path).unwrap();
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut pixels).unwrap();
        pixels.truncate(info.buffer_size());
        (info, pixels)
    }

    fn rgb(image: &RgbaImage) -> Vec<u8> {
        let mut rgb = Vec::new();
        push_rgb(image.as_raw(), &mut rgb);
        rgb
    }

    #[test]
    fn frames_over_a_base_decode_to_their_pixels() {
        let (width, height) = (61, 47);
        let base = FrameBase::new(backdrop(width, height));
        let body = noise(width, height, 4);
        let dir = tempfile::tempdir().unwrap();
        let mut writer = FramePngWriter::default();
        let patches = [
            None,
            Some(PixelRect::new(10, 12, 20, 9)),
            Some(PixelRect::new(0, 0, width, 1)),
            Some(PixelRect::new(60, 46, 1, 1)),
            Some(PixelRect::new(0, 0, width, height)),
            Some(PixelRect::new(30, 20, 31, 27)),
        ];
        for (i, rect) in patches.into_iter().enumerate() {
            let patch = rect.map(|rect| Patch::cut(&body, rect));
            let frame = FrameImage::patched(base.clone(), patch);
            let path = dir.path().join(format!("frame_{i}.png"));
            writer.write(&path, &frame).unwrap();
            let (info, pixels) = decode(&path);
            assert_eq!((info.width, info.height), (width, height));
            assert_eq!(info.color_type, png::ColorType::Rgb);
            assert!(
                pixels == rgb(&frame.to_rgba()),
                "frame {i} ({rect:?}) decodes differently"
            );
        }
        // The writer's buffers carry nothing from one frame to the next:
        // the first frame again gives the same file.
        let again = dir.path().join("again.png");
        writer
            .write(&again, &FrameImage::patched(base, None))
            .unwrap();
        assert_eq!(
            std::fs::read(&again).unwrap(),
            std::fs::read(dir.path().join("frame_0.png")).unwrap()
        );
    }

    #[test]
    fn whole_frames_decode_to_their_pixels() {
        let image = noise(33, 20, 5);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("whole.png");
        FramePngWriter::default()
            .write(&path, &FrameImage::from(image.clone()))
            .unwrap();
        let (info, pixels) = decode(&path);
        assert_eq!((info.width, info.height), (33, 20));
        assert_eq!(pixels, rgb(&image));
    }

    #[test]
    fn a_mostly_flat_frame_is_small() {
        // Each base row compressed alone still shrinks a flat image a lot.
        let (width, height) = (640, 360);
        let base = FrameBase::new(backdrop(width, height));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flat.png");
        FramePngWriter::default()
            .write(&path, &FrameImage::patched(base, None))
            .unwrap();
        let size = std::fs::metadata(&path).unwrap().len();
        let raw = u64::from(width * height * 3);
        assert!(size * 50 < raw, "{size} bytes for {raw} bytes of pixels");
    }

    #[test]
    fn sub_filtering_subtracts_the_pixel_to_the_left() {
        let rgb = [10, 20, 30, 15, 5, 40, 15, 5, 40];
        let mut filtered = vec![7];
        push_sub_filtered(&rgb, &mut filtered);
        assert_eq!(filtered, [7, SUB_FILTER, 10, 20, 30, 5, 241, 10, 0, 0, 0]);
        // A span from the row's start, and one from the second pixel on.
        let mut span = [0; 6];
        sub_filter_span(&rgb, 0, &mut span);
        assert_eq!(span, [10, 20, 30, 5, 241, 10]);
        sub_filter_span(&rgb, 3, &mut span);
        assert_eq!(span, [5, 241, 10, 0, 0, 0]);
    }

    #[test]
    fn segments_concatenate_into_one_stream() {
        // Three pieces compressed apart, closed by the empty final block,
        // inflate to the three pieces in order.
        let pieces: [Vec<u8>; 3] = [
            (0..5000u32).map(|i| (i % 7) as u8).collect(),
            Vec::new(),
            noise(50, 40, 2).into_raw(),
        ];
        let mut deflate = Deflate::new(PATCH_LEVEL, false, 15);
        let mut stream = ZLIB_HEADER.to_vec();
        let mut output = Vec::new();
        let mut adler = 1;
        for piece in &pieces {
            stream.extend_from_slice(deflate_segment(&mut deflate, piece, &mut output).unwrap());
            adler = adler32_combine(adler, adler32(1, piece), piece.len() as u64);
        }
        stream.extend_from_slice(&FINAL_EMPTY_BLOCK);
        stream.extend_from_slice(&adler.to_be_bytes());
        let mut inflated = Vec::new();
        std::io::Read::read_to_end(
            &mut flate2::read::ZlibDecoder::new(&stream[..]),
            &mut inflated,
        )
        .unwrap();
        assert_eq!(inflated, pieces.concat());
        assert_eq!(adler, adler32(1, &pieces.concat()));
    }

    #[test]
    fn a_base_compressed_in_pieces_is_the_base_compressed_whole() {
        // 3.5 pieces of rows, and a piece of a few rows.
        for height in [7 * ROWS_PER_PIECE as u32 / 2, 5] {
            let image = noise(37, height, 3);
            let pieces = CompressedRows::new(&image).unwrap();
            let row_len = 1 + 37 * PIXEL_BYTES;
            let whole = CompressedRows::of_rows(image.as_raw(), 37, row_len).unwrap();
            assert_eq!(pieces.filtered, whole.filtered);
            assert_eq!(pieces.deflated, whole.deflated);
            assert_eq!(pieces.offsets, whole.offsets);
            assert_eq!(pieces.adlers, whole.adlers);
            assert_eq!(pieces.offsets.len(), height as usize + 1);
        }
    }
}
