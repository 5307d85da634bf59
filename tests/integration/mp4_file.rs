//! A small MP4 reader for the tests: checks an MP4 without ffprobe by
//! walking its boxes (ISO/IEC 14496-12 and, for `avcC`, 14496-15), and
//! decodes its H.264 samples with OpenH264's decoder.
#![allow(dead_code)]

use std::path::Path;

/// What the tests check of an MP4 with one H.264 video track.
#[derive(Debug)]
pub struct Mp4File {
    /// `ftyp`'s major brand.
    pub major_brand: String,
    /// `tkhd`'s width and height (16.16 fixed point, whole pixels here).
    pub track_size: (u32, u32),
    /// The `avc1` sample entry's width and height.
    pub coded_size: (u32, u32),
    /// `mdhd`'s ticks per second.
    pub timescale: u32,
    /// Each sample's duration in ticks (`stts`).
    pub durations: Vec<u32>,
    /// The sync samples, from 1 (`stss`; `None` when every sample is one).
    pub sync_samples: Option<Vec<u32>>,
    /// `avcC`'s parameter sets.
    pub sps: Vec<u8>,
    pub pps: Vec<u8>,
    /// Each sample's bytes (length-prefixed NAL units), found through
    /// `stsz`, `stsc` and `stco` / `co64`.
    pub samples: Vec<Vec<u8>>,
}

/// The boxes in `data`, as (type, payload).
fn boxes(data: &[u8]) -> Result<Vec<(String, &[u8])>, String> {
    let mut found = Vec::new();
    let mut at = 0usize;
    while at < data.len() {
        let header = data
            .get(at..at + 8)
            .ok_or_else(|| format!("a box header cut short at byte {at}"))?;
        let kind = String::from_utf8_lossy(&header[4..8]).into_owned();
        let (size, header_size) = match u32::from_be_bytes(header[..4].try_into().unwrap()) {
            0 => (data.len() - at, 8),
            1 => {
                let large = data
                    .get(at + 8..at + 16)
                    .ok_or_else(|| format!("{kind}: large size cut short"))?;
                (u64::from_be_bytes(large.try_into().unwrap()) as usize, 16)
            }
            size => (size as usize, 8),
        };
        if size < header_size || at + size > data.len() {
            return Err(format!(
                "{kind} at byte {at}: size {size} does not fit in {}",
                data.len()
            ));
        }
        found.push((kind, &data[at + header_size..at + size]));
        at += size;
    }
    Ok(found)
}

/// The payload of the one box at `path` (e.g. `["moov", "trak"]`).
fn child<'a>(data: &'a [u8], path: &[&str]) -> Result<&'a [u8], String> {
    let mut current = data;
    for (depth, name) in path.iter().enumerate() {
        let matching: Vec<_> = boxes(current)?
            .into_iter()
            .filter(|(kind, _)| kind == name)
            .collect();
        match matching.as_slice() {
            [(_, payload)] => current = payload,
            found => {
                return Err(format!(
                    "{} boxes at {}",
                    found.len(),
                    path[..=depth].join("/")
                ));
            }
        }
    }
    Ok(current)
}

fn u16_at(data: &[u8], at: usize) -> Result<u16, String> {
    data.get(at..at + 2)
        .map(|b| u16::from_be_bytes(b.try_into().unwrap()))
        .ok_or_else(|| format!("no u16 at byte {at} of {}", data.len()))
}

fn u32_at(data: &[u8], at: usize) -> Result<u32, String> {
    data.get(at..at + 4)
        .map(|b| u32::from_be_bytes(b.try_into().unwrap()))
        .ok_or_else(|| format!("no u32 at byte {at} of {}", data.len()))
}

fn u64_at(data: &[u8], at: usize) -> Result<u64, String> {
    data.get(at..at + 8)
        .map(|b| u64::from_be_bytes(b.try_into().unwrap()))
        .ok_or_else(|| format!("no u64 at byte {at} of {}", data.len()))
}

/// A full box's table: `count` entries of `width` u32 values after the
/// version, flags and entry count (plus `skip` bytes before the count).
fn table(payload: &[u8], skip: usize, width: usize) -> Result<Vec<Vec<u32>>, String> {
    let count = u32_at(payload, 4 + skip)? as usize;
    (0..count)
        .map(|i| {
            (0..width)
                .map(|j| u32_at(payload, 8 + skip + 4 * (i * width + j)))
                .collect()
        })
        .collect()
}

impl Mp4File {
    /// Reads the MP4 at `path`, or says what is wrong with it.
    pub fn read(path: &Path) -> Result<Self, String> {
        let data = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let top = boxes(&data)?;
        let kinds: Vec<&str> = top.iter().map(|(kind, _)| kind.as_str()).collect();
        if kinds.first() != Some(&"ftyp") || !kinds.contains(&"moov") || !kinds.contains(&"mdat") {
            return Err(format!("top-level boxes {kinds:?}"));
        }
        let major_brand = String::from_utf8_lossy(&top[0].1[..4]).into_owned();
        let trak = child(&data, &["moov", "trak"])?;
        let tkhd = child(trak, &["tkhd"])?;
        // After version and flags, times, ids and duration (20 or 32 bytes),
        // then 52 bytes of reserved fields, layer, volume and matrix.
        let size_at = if tkhd[0] == 1 {
            4 + 32 + 52
        } else {
            4 + 20 + 52
        };
        let track_size = (
            u32_at(tkhd, size_at)? >> 16,
            u32_at(tkhd, size_at + 4)? >> 16,
        );
        let mdia = child(trak, &["mdia"])?;
        let mdhd = child(mdia, &["mdhd"])?;
        let timescale = u32_at(mdhd, if mdhd[0] == 1 { 20 } else { 12 })?;
        let stbl = child(mdia, &["minf", "stbl"])?;
        // stsd: version, flags, entry count, then the sample entries.
        let entries = boxes(child(stbl, &["stsd"])?.get(8..).unwrap_or_default())?;
        let avc1 = match entries.as_slice() {
            [(kind, payload)] if kind == "avc1" => *payload,
            other => {
                let kinds: Vec<_> = other.iter().map(|(kind, _)| kind).collect();
                return Err(format!("sample entries {kinds:?}, not one avc1"));
            }
        };
        let coded_size = (u32::from(u16_at(avc1, 24)?), u32::from(u16_at(avc1, 26)?));
        // The visual sample entry is 78 bytes; avcC follows.
        let avcc = child(avc1.get(78..).unwrap_or_default(), &["avcC"])?;
        if avcc[4] & 3 != 3 {
            return Err(format!("NAL lengths of {} bytes, not 4", (avcc[4] & 3) + 1));
        }
        let mut at = 5;
        let mut parameter_set = |count_mask: u8| -> Result<Vec<u8>, String> {
            let count = avcc.get(at).ok_or("avcC cut short")? & count_mask;
            if count != 1 {
                return Err(format!("{count} parameter sets in avcC, not 1"));
            }
            let length = usize::from(u16_at(avcc, at + 1)?);
            let set = avcc
                .get(at + 3..at + 3 + length)
                .ok_or("avcC cut short")?
                .to_vec();
            at += 3 + length;
            Ok(set)
        };
        let sps = parameter_set(0x1f)?;
        let pps = parameter_set(0xff)?;

        let stsz = child(stbl, &["stsz"])?;
        let (fixed, count) = (u32_at(stsz, 4)?, u32_at(stsz, 8)? as usize);
        let sizes: Vec<u32> = if fixed == 0 {
            (0..count)
                .map(|i| u32_at(stsz, 12 + 4 * i))
                .collect::<Result<_, _>>()?
        } else {
            vec![fixed; count]
        };
        let durations: Vec<u32> = table(child(stbl, &["stts"])?, 0, 2)?
            .into_iter()
            .flat_map(|entry| std::iter::repeat_n(entry[1], entry[0] as usize))
            .collect();
        let sync_samples = match child(stbl, &["stss"]) {
            Ok(stss) => Some(table(stss, 0, 1)?.into_iter().map(|e| e[0]).collect()),
            Err(_) => None,
        };
        let offsets: Vec<u64> = match child(stbl, &["stco"]) {
            Ok(stco) => table(stco, 0, 1)?
                .into_iter()
                .map(|e| u64::from(e[0]))
                .collect(),
            Err(_) => {
                let co64 = child(stbl, &["co64"])?;
                (0..u32_at(co64, 4)? as usize)
                    .map(|i| u64_at(co64, 8 + 8 * i))
                    .collect::<Result<_, _>>()?
            }
        };
        // stsc: (first chunk, samples per chunk, description) runs.
        let runs = table(child(stbl, &["stsc"])?, 0, 3)?;
        let mut samples = Vec::with_capacity(sizes.len());
        let mut sizes_left = sizes.iter();
        for (chunk, &offset) in offsets.iter().enumerate() {
            let per_chunk = runs
                .iter()
                .rev()
                .find(|run| run[0] as usize <= chunk + 1)
                .ok_or("stsc does not cover the first chunk")?[1];
            let mut at = offset as usize;
            for _ in 0..per_chunk {
                let size = *sizes_left
                    .next()
                    .ok_or("more samples in chunks than in stsz")?
                    as usize;
                let bytes = data
                    .get(at..at + size)
                    .ok_or_else(|| format!("sample at {at} of {size} bytes outside the file"))?;
                samples.push(bytes.to_vec());
                at += size;
            }
        }
        if samples.len() != sizes.len() {
            return Err(format!(
                "{} samples in chunks, {} in stsz",
                samples.len(),
                sizes.len()
            ));
        }
        Ok(Self {
            major_brand,
            track_size,
            coded_size,
            timescale,
            durations,
            sync_samples,
            sps,
            pps,
            samples,
        })
    }

    /// Decodes every sample; returns each frame as RGB bytes of the coded
    /// size, converted back with BT.709 in limited range (what the SPS says).
    pub fn decode_rgb(&self) -> Result<Vec<Vec<u8>>, String> {
        use openh264::formats::YUVSource;
        let mut decoder = openh264::decoder::Decoder::new().map_err(|e| e.to_string())?;
        let mut frames = Vec::new();
        for (index, sample) in self.samples.iter().enumerate() {
            // Annex B for the decoder: start codes, and the parameter sets first.
            let mut stream = Vec::new();
            if index == 0 {
                for set in [&self.sps, &self.pps] {
                    stream.extend_from_slice(&[0, 0, 0, 1]);
                    stream.extend_from_slice(set);
                }
            }
            let mut at = 0;
            while at < sample.len() {
                let length = u32_at(sample, at)? as usize;
                let unit = sample
                    .get(at + 4..at + 4 + length)
                    .ok_or_else(|| format!("sample {index}: a NAL unit cut short"))?;
                stream.extend_from_slice(&[0, 0, 0, 1]);
                stream.extend_from_slice(unit);
                at += 4 + length;
            }
            let image = decoder
                .decode(&stream)
                .map_err(|e| format!("sample {index}: {e}"))?
                .ok_or_else(|| format!("sample {index} gave no picture"))?;
            let (width, height) = image.dimensions();
            let (y_stride, u_stride, v_stride) = image.strides();
            let mut rgb = Vec::with_capacity(width * height * 3);
            for y in 0..height {
                for x in 0..width {
                    let luma = f64::from(image.y()[y * y_stride + x]) - 16.0;
                    let cb = f64::from(image.u()[y / 2 * u_stride + x / 2]) - 128.0;
                    let cr = f64::from(image.v()[y / 2 * v_stride + x / 2]) - 128.0;
                    let luma = luma * 255.0 / 219.0;
                    let (cb, cr) = (cb * 255.0 / 224.0, cr * 255.0 / 224.0);
                    // BT.709: Kr = 0.2126, Kb = 0.0722.
                    let r = luma + 1.5748 * cr;
                    let g = luma - 0.187324 * cb - 0.468124 * cr;
                    let b = luma + 1.8556 * cb;
                    rgb.extend([r, g, b].map(|c| c.round().clamp(0.0, 255.0) as u8));
                }
            }
            frames.push(rgb);
        }
        Ok(frames)
    }
}
