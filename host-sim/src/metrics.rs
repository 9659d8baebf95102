//! Image comparison metrics: an RGBA8 image against another RGBA8 image or an f64 reference image.
//!
//! Per channel (R, G, B, A): the maximum and the mean absolute error. Over R, G, B together: the
//! PSNR `10 log10(255^2 / MSE)` in dB. Per pixel: `within_one_step`, the fraction of pixels whose
//! every channel (alpha included) differs by at most 1 from the other image (an f64 reference is
//! rounded to the nearest integer first, half away from zero).
//!
//! Against an f64 reference the max / mean / PSNR errors are measured against the **unrounded**
//! reference, so they include the unavoidable 8-bit quantisation (at most 0.5 per channel).
//!
//! JSON: [`Metrics`] serializes as `{"max_error": e, "mean_error": e, "max_error_per_channel":
//! [r, g, b, a], "mean_error_per_channel": [r, g, b, a], "psnr": dB, "within_one_step": frac,
//! "pixels": count}` (`max_error` is the largest over channels, `mean_error` the mean over
//! channels). PSNR is capped at [`PSNR_CAP`] = 100 dB, which identical images report, so it is
//! always a finite JSON number.

use serde::{Deserialize, Serialize};

/// The PSNR reported for identical images, and the cap of every PSNR (dB).
pub const PSNR_CAP: f64 = 100.0;

/// Comparison of two images.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Largest absolute error over all channels and pixels, 8-bit units.
    pub max_error: f64,
    /// Mean absolute error over all channels and pixels, 8-bit units.
    pub mean_error: f64,
    /// Per-channel (R, G, B, A) maximum absolute error, 8-bit units.
    pub max_error_per_channel: [f64; 4],
    /// Per-channel (R, G, B, A) mean absolute error, 8-bit units.
    pub mean_error_per_channel: [f64; 4],
    /// PSNR over R, G, B in dB, capped at [`PSNR_CAP`] (identical images).
    pub psnr: f64,
    /// Fraction of pixels with every channel within 1 of the (rounded) other image.
    pub within_one_step: f64,
    /// Number of pixels compared.
    pub pixels: usize,
}

/// The images cannot be compared.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MetricsError {
    /// Different pixel counts.
    #[error("image sizes differ: {0} vs {1} pixels")]
    SizeMismatch(usize, usize),
    /// No pixels.
    #[error("empty images")]
    Empty,
}

/// Accumulates per-pixel channel differences.
struct Acc {
    max: [f64; 4],
    sum: [f64; 4],
    sq_rgb: f64,
    within: usize,
    pixels: usize,
}

impl Acc {
    fn new() -> Acc {
        Acc {
            max: [0.0; 4],
            sum: [0.0; 4],
            sq_rgb: 0.0,
            within: 0,
            pixels: 0,
        }
    }

    /// `diff`: signed channel errors; `step_ok`: every channel within one step.
    fn add(&mut self, diff: [f64; 4], step_ok: bool) {
        for (k, d) in diff.iter().enumerate() {
            let d = d.abs();
            self.max[k] = self.max[k].max(d);
            self.sum[k] += d;
            if k < 3 {
                self.sq_rgb += d * d;
            }
        }
        self.within += usize::from(step_ok);
        self.pixels += 1;
    }

    fn finish(self) -> Metrics {
        let n = self.pixels as f64;
        let mse = self.sq_rgb / (3.0 * n);
        let psnr = if mse == 0.0 {
            PSNR_CAP
        } else {
            (10.0 * (255.0 * 255.0 / mse).log10()).min(PSNR_CAP)
        };
        let mean = self.sum.map(|s| s / n);
        Metrics {
            max_error: self.max.iter().copied().fold(0.0, f64::max),
            mean_error: mean.iter().sum::<f64>() / 4.0,
            max_error_per_channel: self.max,
            mean_error_per_channel: mean,
            psnr,
            within_one_step: self.within as f64 / n,
            pixels: self.pixels,
        }
    }
}

fn check_sizes(a: usize, b: usize) -> Result<(), MetricsError> {
    if a != b {
        Err(MetricsError::SizeMismatch(a, b))
    } else if a == 0 {
        Err(MetricsError::Empty)
    } else {
        Ok(())
    }
}

/// Compare two RGBA8 images (same pixel order, equal sizes).
pub fn compare_rgba8(image: &[[u8; 4]], other: &[[u8; 4]]) -> Result<Metrics, MetricsError> {
    check_sizes(image.len(), other.len())?;
    let mut acc = Acc::new();
    for (a, b) in image.iter().zip(other) {
        let diff = [0, 1, 2, 3].map(|k| f64::from(a[k]) - f64::from(b[k]));
        let ok = (0..4).all(|k| a[k].abs_diff(b[k]) <= 1);
        acc.add(diff, ok);
    }
    Ok(acc.finish())
}

/// Compare an RGBA8 image against an f64 reference image (0..255 units, same pixel order).
pub fn compare_to_reference(
    image: &[[u8; 4]],
    reference: &[[f64; 4]],
) -> Result<Metrics, MetricsError> {
    check_sizes(image.len(), reference.len())?;
    let mut acc = Acc::new();
    for (a, r) in image.iter().zip(reference) {
        let diff = [0, 1, 2, 3].map(|k| f64::from(a[k]) - r[k]);
        let ok = (0..4).all(|k| (f64::from(a[k]) - r[k].round().clamp(0.0, 255.0)).abs() <= 1.0);
        acc.add(diff, ok);
    }
    Ok(acc.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(n: usize, seed: u8) -> Vec<[u8; 4]> {
        (0..n)
            .map(|i| {
                let v = (i as u8).wrapping_mul(31).wrapping_add(seed);
                [v, v.wrapping_mul(3), 255 - v, 255]
            })
            .collect()
    }

    #[test]
    fn identical_images() {
        let a = image(256 * 256, 5);
        let m = compare_rgba8(&a, &a).unwrap();
        assert_eq!(m.max_error, 0.0);
        assert_eq!(m.mean_error, 0.0);
        assert_eq!(m.max_error_per_channel, [0.0; 4]);
        assert_eq!(m.psnr, PSNR_CAP);
        assert_eq!(m.within_one_step, 1.0);
        assert_eq!(m.pixels, 65536);
        let json = serde_json::to_string(&m).unwrap();
        assert!(json.contains("\"psnr\":100.0"), "{json}");
        let back: Metrics = serde_json::from_str(&json).unwrap();
        assert_eq!(back, m);
        // Against itself as an f64 reference.
        let r: Vec<[f64; 4]> = a.iter().map(|p| p.map(f64::from)).collect();
        assert_eq!(compare_to_reference(&a, &r).unwrap(), m);
    }

    #[test]
    fn single_pixel_error() {
        let a = image(256 * 256, 9);
        let mut b = a.clone();
        b[1000][0] = b[1000][0].wrapping_add(10);
        let m = compare_rgba8(&a, &b).unwrap();
        assert_eq!(m.max_error_per_channel, [10.0, 0.0, 0.0, 0.0]);
        assert_eq!(m.max_error, 10.0);
        assert_eq!(m.mean_error_per_channel[0], 10.0 / 65536.0);
        assert_eq!(m.mean_error, 10.0 / 65536.0 / 4.0);
        // MSE = 10^2 / (3 * 65536): PSNR = 10 log10(255^2 * 3 * 65536 / 100) = 81.0668... dB.
        let expected = 10.0 * (255.0f64 * 255.0 * 3.0 * 65536.0 / 100.0).log10();
        assert!((m.psnr - expected).abs() < 1e-9, "{} {}", m.psnr, expected);
        assert!((m.psnr - 81.0668).abs() < 1e-3, "{}", m.psnr);
        assert_eq!(m.within_one_step, 65535.0 / 65536.0);
        let json = serde_json::to_value(m).unwrap();
        for key in [
            "max_error",
            "mean_error",
            "psnr",
            "within_one_step",
            "pixels",
        ] {
            assert!(json.get(key).is_some(), "{key}");
        }
        assert_eq!(json["pixels"], 65536);
        // One-step errors keep within_one_step at 1; alpha counts too.
        let mut c = a.clone();
        c[0][1] = c[0][1].wrapping_add(1);
        assert_eq!(compare_rgba8(&a, &c).unwrap().within_one_step, 1.0);
        c[0][3] = c[0][3].wrapping_sub(2);
        let mc = compare_rgba8(&a, &c).unwrap();
        assert_eq!(mc.within_one_step, 65535.0 / 65536.0);
        assert_eq!(mc.max_error_per_channel[3], 2.0);
    }

    #[test]
    fn against_f64_reference() {
        let img = vec![[10u8, 20, 30, 255], [0, 0, 0, 0]];
        let reference = vec![[10.4, 21.5, 28.6, 255.0], [0.0, 0.0, 0.0, 0.0]];
        let m = compare_to_reference(&img, &reference).unwrap();
        assert!((m.max_error_per_channel[0] - 0.4).abs() < 1e-12);
        assert!((m.max_error_per_channel[1] - 1.5).abs() < 1e-12);
        assert!((m.max_error_per_channel[2] - 1.4).abs() < 1e-12);
        // 21.5 rounds to 22 (two steps from 20): pixel 0 fails; 28.6 -> 29 is one step.
        assert_eq!(m.within_one_step, 0.5);
        let mse = (0.4f64.powi(2) + 1.5f64.powi(2) + 1.4f64.powi(2)) / 6.0;
        assert!((m.psnr - 10.0 * (65025.0 / mse).log10()).abs() < 1e-9);
        assert!((m.mean_error_per_channel[1] - 0.75).abs() < 1e-12);
    }

    #[test]
    fn size_errors() {
        let a = image(4, 0);
        assert_eq!(
            compare_rgba8(&a, &a[..3]),
            Err(MetricsError::SizeMismatch(4, 3))
        );
        assert_eq!(compare_rgba8(&[], &[]), Err(MetricsError::Empty));
        assert_eq!(
            compare_to_reference(&a, &[]),
            Err(MetricsError::SizeMismatch(4, 0))
        );
    }
}
