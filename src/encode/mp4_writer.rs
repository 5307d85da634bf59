//! [`Mp4Writer`]: H.264 MP4 encoded in the process, so `--video mp4` works
//! on every machine, a cluster node without ffmpeg included.
//!
//! **Why these crates.** Video used to go to an `ffmpeg` child process,
//! which a fresh machine does not have (and whose stalls needed timeouts,
//! process groups and a feeder thread). Now:
//!
//! - [`openh264`] encodes: Cisco's OpenH264 encoder (BSD-2-Clause), built
//!   from the source bundled in the `openh264-sys2` crate with the C++
//!   compiler that Rust's own linking already needs, so there is nothing to
//!   install and nothing loaded at run time. It writes the constrained
//!   baseline profile, which every player decodes. (Cisco's patent licence
//!   covers Cisco's own binaries, not builds from source; see the README.)
//! - [`mp4`] muxes: a small pure-Rust ISO-BMFF writer that streams the
//!   samples into `mdat` as they come and writes `moov` at the end, so a long
//!   run holds no more than one frame (the `muxide` crate, also considered,
//!   keeps every sample in memory until it finishes).
//!
//! **The frames.** `frame_yuv` converts each frame to YUV 4:2:0 with BT.709
//! colours in limited range, dimensions padded to even numbers with the
//! background colour (only the rows a frame changes are converted); the SPS
//! is tagged BT.709, limited range, so players invert exactly that. The
//! encoder runs on one thread, with frame skipping off, a key frame every
//! two seconds, and a bit rate of [`BITS_PER_PIXEL`] per pixel per frame:
//! the same frames give the same bytes, and every frame is one sample.
//!
//! **The file.** Samples are length-prefixed NAL units (`avc1`); the
//! parameter sets go into the `avcC` box, not into the samples. Sample
//! times are exact: the frame duration is the fraction of a second
//! closest to `1 / fps` (the APNG's [`frame_delay`]), in a track time scale
//! of at least 10000 ticks per second. The MP4 is written to the video's
//! hidden temporary file; the sequence writer publishes it only when the
//! whole run succeeded, and an interrupt removes it (`partial_file.rs`).

use super::RenderError;
use super::frame_yuv::{Yuv420Frames, padded_size};
use super::partial_file::PartialFile;
use super::video_writer::{VideoSpec, VideoWriter, frame_delay};
use image::RgbaImage;
use openh264::OpenH264API;
use openh264::encoder::{
    BitRate, EncodedBitStream, Encoder, EncoderConfig, FrameRate, IntraFramePeriod,
    RateControlMode, UsageType, VuiConfig,
};
use openh264::formats::YUVSlices;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The largest frame the encoder takes (either way up): OpenH264 stops at
/// H.264 level 5.2.
pub(crate) const MAX_SIZE: (u32, u32) = (3840, 2160);

/// The bit rate's share per pixel and frame. The frames are flat colours
/// with sharp edges and text; at 0.25 bit per pixel (1.7 Mbit/s for 640x360
/// at 30 fps) edges and the legend's text stay sharp.
const BITS_PER_PIXEL: f64 = 0.25;

/// Seconds between key frames (players seek to them).
const KEY_FRAME_SECONDS: f64 = 2.0;

/// The `moov` time scale (ticks per second of the whole movie).
const MOVIE_TIMESCALE: u32 = 1000;

/// The MP4's track: the only one.
const TRACK: u32 = 1;

/// Checks that frames of `width` x `height` can be encoded into the MP4 at
/// `path` (after padding to even numbers).
pub(crate) fn check_size(path: &Path, width: u32, height: u32) -> Result<(), RenderError> {
    let (w, h) = padded_size((width, height));
    let (long, short) = MAX_SIZE;
    if w.max(h) > long || w.min(h) > short {
        return Err(RenderError::Encode {
            path: path.to_owned(),
            message: format!(
                "{width}x{height} pixels is larger than the H.264 encoder takes \
                 ({long}x{short}, or {short}x{long}); choose a smaller resolution, \
                 or apng or gif video"
            ),
        });
    }
    Ok(())
}

/// Writes `video.mp4` (see the module documentation).
pub(crate) struct Mp4Writer {
    /// The final path, for messages.
    path: PathBuf,
    encoder: Encoder,
    planes: Yuv420Frames,
    /// The padded frame size.
    size: (u32, u32),
    muxer: mp4::Mp4Writer<BufWriter<File>>,
    /// The first frame's SPS and PPS, once the track is added.
    parameter_sets: Option<(Vec<u8>, Vec<u8>)>,
    /// The latest frame's sample, length-prefixed NAL units.
    sample: Vec<u8>,
    /// The track's ticks per second and per frame.
    timescale: u32,
    frame_ticks: u32,
    /// Frames written.
    frames: u64,
}

impl Mp4Writer {
    /// Starts the MP4 in the temporary file of `partial`.
    pub fn new(spec: &VideoSpec<'_>, partial: &PartialFile) -> Result<Self, RenderError> {
        check_size(spec.path, spec.width, spec.height)?;
        let size = padded_size((spec.width, spec.height));
        let (numerator, denominator) = frame_delay(spec.fps);
        let scale = 10_000u32.div_ceil(u32::from(denominator));
        let key_frames = (KEY_FRAME_SECONDS * spec.fps).round().clamp(1.0, 1000.0) as u32;
        // OpenH264 budgets bits per frame from its frame rate, which it
        // clamps to 1..=60 frames per second.
        let rate = spec.fps.clamp(1.0, 60.0);
        let bitrate = (BITS_PER_PIXEL * f64::from(size.0) * f64::from(size.1) * rate) as u32;
        let config = EncoderConfig::new()
            // The encoder takes only the two real-time usages.
            .usage_type(UsageType::CameraVideoRealTime)
            .rate_control_mode(RateControlMode::Quality)
            .bitrate(BitRate::from_bps(bitrate))
            .max_frame_rate(FrameRate::from_hz(rate as f32))
            .skip_frames(false)
            .num_threads(1)
            .intra_frame_period(IntraFramePeriod::from_num_frames(key_frames))
            .vui(VuiConfig::bt709());
        let encoder = Encoder::with_api_config(OpenH264API::from_source(), config)
            .map_err(|e| encode_error(spec.path, format!("cannot start the H.264 encoder: {e}")))?;
        let file = BufWriter::with_capacity(1 << 20, partial.create()?);
        let brand = |name: &[u8; 4]| mp4::FourCC::from(*name);
        let movie = mp4::Mp4Config {
            major_brand: brand(b"isom"),
            minor_version: 512,
            compatible_brands: vec![
                brand(b"isom"),
                brand(b"iso2"),
                brand(b"avc1"),
                brand(b"mp41"),
            ],
            timescale: MOVIE_TIMESCALE,
        };
        let muxer =
            mp4::Mp4Writer::write_start(file, &movie).map_err(|e| mp4_error(spec.path, e))?;
        Ok(Self {
            path: spec.path.to_owned(),
            encoder,
            planes: Yuv420Frames::new((spec.width, spec.height), spec.background),
            size,
            muxer,
            parameter_sets: None,
            sample: Vec::new(),
            timescale: u32::from(denominator) * scale,
            frame_ticks: u32::from(numerator) * scale,
            frames: 0,
        })
    }

    /// Adds the track, described by the first frame's parameter sets.
    fn add_track(&mut self, sps: Vec<u8>, pps: Vec<u8>) -> Result<(), RenderError> {
        // avcC copies the profile and level from the SPS's bytes 1 to 3.
        if sps.len() < 4 || pps.is_empty() {
            return Err(encode_error(
                &self.path,
                format!(
                    "the H.264 encoder wrote a {}-byte SPS and a {}-byte PPS",
                    sps.len(),
                    pps.len()
                ),
            ));
        }
        let avc = mp4::AvcConfig {
            // At most 3840: `check_size`.
            width: self.size.0 as u16,
            height: self.size.1 as u16,
            seq_param_set: sps.clone(),
            pic_param_set: pps.clone(),
        };
        let track = mp4::TrackConfig {
            track_type: mp4::TrackType::Video,
            timescale: self.timescale,
            language: "und".into(),
            media_conf: mp4::MediaConfig::AvcConfig(avc),
        };
        self.muxer
            .add_track(&track)
            .map_err(|e| mp4_error(&self.path, e))?;
        self.parameter_sets = Some((sps, pps));
        Ok(())
    }
}

/// What one encoded frame holds.
struct EncodedFrame {
    /// The SPS and PPS, when the encoder wrote them (with each key frame).
    sps: Option<Vec<u8>>,
    pps: Option<Vec<u8>>,
    /// Holds an IDR slice: a key frame.
    key: bool,
}

/// Appends the NAL units of `stream` other than the parameter sets to
/// `sample`, each after its length as 4 bytes big-endian (the encoder writes
/// them after Annex B start codes).
fn to_sample(stream: &EncodedBitStream<'_>, sample: &mut Vec<u8>) -> EncodedFrame {
    let mut frame = EncodedFrame {
        sps: None,
        pps: None,
        key: false,
    };
    for layer in (0..stream.num_layers()).filter_map(|i| stream.layer(i)) {
        for unit in (0..layer.nal_count()).filter_map(|i| layer.nal_unit(i)) {
            let unit = strip_start_code(unit);
            let Some(&header) = unit.first() else {
                continue;
            };
            match header & 0x1f {
                7 => frame.sps = Some(unit.to_vec()),
                8 => frame.pps = Some(unit.to_vec()),
                kind => {
                    frame.key |= kind == 5;
                    sample.extend_from_slice(&(unit.len() as u32).to_be_bytes());
                    sample.extend_from_slice(unit);
                }
            }
        }
    }
    frame
}

/// `unit` without its Annex B start code (`00 00 01` or `00 00 00 01`).
fn strip_start_code(unit: &[u8]) -> &[u8] {
    let zeros = unit.iter().take_while(|&&b| b == 0).count();
    if zeros >= 2 && unit.get(zeros) == Some(&1) {
        &unit[zeros + 1..]
    } else {
        unit
    }
}

impl VideoWriter for Mp4Writer {
    fn push(&mut self, frame: &Arc<RgbaImage>) -> Result<(), RenderError> {
        let index = self.frames;
        // One I420 buffer: Y, then Cb, then Cr.
        let i420 = self.planes.convert(frame);
        let (width, height) = (self.size.0 as usize, self.size.1 as usize);
        if i420.len() != width * height * 3 / 2 {
            return Err(encode_error(
                &self.path,
                format!(
                    "frame {index} has {} bytes of YUV 4:2:0, not {} for {width}x{height}",
                    i420.len(),
                    width * height * 3 / 2
                ),
            ));
        }
        let (luma, chroma) = i420.split_at(width * height);
        let (cb, cr) = chroma.split_at(luma.len() / 4);
        let source = YUVSlices::new(
            (luma, cb, cr),
            (width, height),
            (width, width / 2, width / 2),
        );
        self.sample.clear();
        let encoded = match self.encoder.encode(&source) {
            Ok(stream) => to_sample(&stream, &mut self.sample),
            Err(e) => {
                return Err(encode_error(
                    &self.path,
                    format!("the H.264 encoder failed on frame {index}: {e}"),
                ));
            }
        };
        if self.sample.is_empty() {
            return Err(encode_error(
                &self.path,
                format!("the H.264 encoder wrote nothing for frame {index}"),
            ));
        }
        match (&self.parameter_sets, encoded.sps, encoded.pps) {
            (None, Some(sps), Some(pps)) => self.add_track(sps, pps)?,
            (None, _, _) => {
                return Err(encode_error(
                    &self.path,
                    "the H.264 encoder's first frame has no SPS and PPS".into(),
                ));
            }
            // The parameter sets repeat with every key frame and must not change.
            (Some((first_sps, first_pps)), sps, pps) => {
                let changed = |now: &Option<Vec<u8>>, first: &Vec<u8>| {
                    now.as_ref().is_some_and(|now| now != first)
                };
                if changed(&sps, first_sps) || changed(&pps, first_pps) {
                    return Err(encode_error(
                        &self.path,
                        format!("the H.264 encoder changed its parameter sets at frame {index}"),
                    ));
                }
            }
        }
        let sample = mp4::Mp4Sample {
            start_time: index * u64::from(self.frame_ticks),
            duration: self.frame_ticks,
            rendering_offset: 0,
            is_sync: encoded.key,
            bytes: bytes::Bytes::copy_from_slice(&self.sample),
        };
        self.muxer
            .write_sample(TRACK, &sample)
            .map_err(|e| mp4_error(&self.path, e))?;
        self.frames += 1;
        Ok(())
    }

    fn finish(mut self: Box<Self>) -> Result<(), RenderError> {
        self.muxer
            .write_end()
            .map_err(|e| mp4_error(&self.path, e))?;
        let Self { path, muxer, .. } = *self;
        muxer
            .into_writer()
            .flush()
            .map_err(|source| RenderError::Io { path, source })
    }
}

fn encode_error(path: &Path, message: String) -> RenderError {
    RenderError::Encode {
        path: path.to_owned(),
        message,
    }
}

fn mp4_error(path: &Path, error: mp4::Error) -> RenderError {
    match error {
        mp4::Error::IoError(source) => RenderError::Io {
            path: path.to_owned(),
            source,
        },
        other => encode_error(path, format!("cannot write the MP4: {other}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_codes_of_three_and_four_bytes_are_stripped() {
        assert_eq!(strip_start_code(&[0, 0, 0, 1, 0x67, 9]), [0x67, 9]);
        assert_eq!(strip_start_code(&[0, 0, 1, 0x68]), [0x68]);
        // Not a start code: left alone.
        assert_eq!(strip_start_code(&[0, 1, 0x65]), [0, 1, 0x65]);
        assert_eq!(strip_start_code(&[0x41, 0, 0, 1]), [0x41, 0, 0, 1]);
    }

    #[test]
    fn frames_up_to_3840x2160_either_way_up_can_be_encoded() {
        let path = Path::new("out/video.mp4");
        for (w, h) in [(3840, 2160), (2160, 3840), (3839, 2159), (1, 1)] {
            check_size(path, w, h).unwrap();
        }
        for (w, h) in [(3841, 100), (100, 3841), (2400, 2400)] {
            let error = check_size(path, w, h).unwrap_err().to_string();
            assert!(
                error.contains("out/video.mp4") && error.contains(&format!("{w}x{h}")),
                "{error}"
            );
        }
    }
}
