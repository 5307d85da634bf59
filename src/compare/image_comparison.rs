//! [`ImageComparison`]: FLIP on two same-sized images, judged by
//! [`CompareThresholds`].

use super::{CompareError, CompareThresholds};
use image::{ImageBuffer, Luma, RgbImage, RgbaImage};

/// The FLIP comparison of two same-sized images.
#[derive(Clone, PartialEq)]
pub struct ImageComparison {
    /// Mean FLIP error.
    pub mean: f32,
    /// FLIP error at the thresholds' percentile.
    pub percentile_value: f32,
    /// Largest FLIP error of any pixel.
    pub max: f32,
    /// Within both thresholds.
    pub passed: bool,
    /// Per-pixel FLIP error in [0, 1].
    pub error_map: ImageBuffer<Luma<f32>, Vec<f32>>,
}

impl std::fmt::Debug for ImageComparison {
    /// The figures and the map's size, not its pixels.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImageComparison")
            .field("mean", &self.mean)
            .field("percentile_value", &self.percentile_value)
            .field("max", &self.max)
            .field("passed", &self.passed)
            .field("error_map", &self.error_map.dimensions())
            .finish()
    }
}

impl ImageComparison {
    /// The error map coloured with the magma palette (black: no error,
    /// yellow-white: largest error).
    pub fn diff_image(&self) -> RgbImage {
        let (width, height) = self.error_map.dimensions();
        let map = nv_flip::FlipImageFloat::with_data(width, height, self.error_map.as_raw());
        let coloured = map.apply_color_lut(&nv_flip::magma_lut());
        RgbImage::from_raw(width, height, coloured.to_vec())
            .expect("nv-flip returns width * height RGB pixels")
    }
}

/// Compares `actual` with `golden` by FLIP and judges it with `thresholds`.
///
/// Fails only when the sizes differ.
pub fn compare_images(
    golden: &RgbaImage,
    actual: &RgbaImage,
    thresholds: &CompareThresholds,
) -> Result<ImageComparison, CompareError> {
    if golden.dimensions() != actual.dimensions() {
        return Err(CompareError::SizeMismatch {
            golden: golden.dimensions(),
            actual: actual.dimensions(),
        });
    }
    let (width, height) = golden.dimensions();
    let flip_image = |img: &RgbaImage| {
        let rgb: Vec<u8> = img
            .as_raw()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        nv_flip::FlipImageRgb8::with_data(width, height, &rgb)
    };
    let map = nv_flip::flip(
        flip_image(golden),
        flip_image(actual),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&map).mean();
    let errors = map.to_vec();
    // FlipPool's maximum starts at f32::MIN_POSITIVE, not 0.
    let max = errors.iter().copied().fold(0.0, f32::max);
    // FlipPool's own unweighted percentile indexes past its data for `p`
    // close to 1, so the nearest rank is taken here.
    let percentile_value = percentile(&errors, thresholds.percentile);
    let error_map = ImageBuffer::from_raw(width, height, errors)
        .expect("nv-flip returns width * height errors");
    Ok(ImageComparison {
        mean,
        percentile_value,
        max,
        passed: thresholds.accepts(mean, percentile_value),
        error_map,
    })
}

/// The nearest-rank `p`-percentile of `values`: the smallest value that at
/// least a fraction `p` of them do not exceed (0 for no values).
fn percentile(values: &[f32], p: f32) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_unstable_by(f32::total_cmp);
    // Back to the decimal the caller wrote (0.995_f32 is 0.99500000477), so
    // that 0.995 of 76800 pixels is rank 76416, not 76417.
    let p = (f64::from(p) * 1e7).round() / 1e7;
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}
