//! The supersampled truth of a scene frame and how close texcore's filtered and unfiltered images
//! come to it (`texsim check SCENE --supersampled N`).
//!
//! - **Truth**: the f64 reference model at `N x N` stratified point samples a pixel (the scene
//!   rendered at `N` times its size with exact perspective, every octave evaluated, no culling,
//!   no colour-table filter, nearest entry), each `N x N` block averaged.
//! - **Filtered**: texcore's image with the given knobs (the default: `csat`, culling on).
//! - **Unfiltered**: the same knobs with `--aa none`; also without culling.
//! - **Supersampled texcore**: the unfiltered image rendered at `k` times the size (`k x k`
//!   samples a pixel, `k` = 2 and 4) and box-averaged: the scale a one-sample filtered pixel is
//!   measured against (2x2 costs four unfiltered samples a pixel, 4x4 sixteen).
//! - **Flat rows**: a row is *flat where the truth shows texture* when the standard deviation of
//!   the image's luma along the row is below [`FLAT_STD`] while the truth's is at least
//!   [`TEXTURED_STD`] (8-bit units). `longest_flat_band` is the longest run of such rows.
//!
//! - **Flicker** (`--flicker FRAMES`, [`flicker`]): the mean absolute frame-to-frame difference
//!   (8-bit RGB units) over the band of rows around the image centre, a quarter of the image
//!   height (the horizon of the seascape and the flight), over `FRAMES` consecutive frames, for
//!   the filtered image, the unfiltered one and the truth: a filter that freezes the band flat
//!   flickers far less than the truth, an aliasing one far more.
//!
//! Guarantees: every figure is a finite number (PSNR capped at [`crate::metrics::PSNR_CAP`]);
//! sizes are checked ([`UnitError`] otherwise); nothing here panics on any scene.

use serde::Serialize;
use texcore::filter::Antialias;
use texcore::hash::HashKind;
use texcore::raster::Perspective;
use texcore::table::TableLookup;

use crate::metrics::compare_to_reference;
use crate::scenes::{reference_framed, render_host_frame, render_n, HostScene};
use crate::unit::{UnitConfig, UnitError};
use texcore::render::Output;

/// A row whose luma standard deviation is below this (8-bit units) is flat.
pub const FLAT_STD: f64 = 0.5;
/// A truth row whose luma standard deviation is at least this (8-bit units) shows texture.
pub const TEXTURED_STD: f64 = 2.0;
/// Largest supersampling factor per axis.
pub const MAX_SUPERSAMPLE: u16 = 16;

/// How texcore's images of a scene frame compare with its supersampled truth.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SupersampledReport {
    /// Scene name.
    pub name: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Frame.
    pub frame: u32,
    /// Samples a pixel per axis of the truth.
    pub supersampled: u16,
    /// PSNR (dB) of the filtered image (the given knobs) against the truth.
    pub psnr_filtered: f64,
    /// PSNR (dB) of the unfiltered image (the same knobs with `--aa none`) against the truth.
    pub psnr_unfiltered: f64,
    /// `psnr_filtered - psnr_unfiltered`.
    pub gain_db: f64,
    /// PSNR (dB) of the unfiltered image without octave culling.
    pub psnr_unfiltered_no_cull: f64,
    /// PSNR (dB) of texcore's unfiltered image at 2x2 samples a pixel, box-averaged.
    pub psnr_supersampled_2x2: f64,
    /// PSNR (dB) of texcore's unfiltered image at 4x4 samples a pixel, box-averaged.
    pub psnr_supersampled_4x4: f64,
    /// Longest run of rows of the filtered image that are flat where the truth shows texture.
    pub longest_flat_band: u32,
    /// Number of such rows in the filtered image.
    pub flat_rows: u32,
    /// The same for the unfiltered image.
    pub longest_flat_band_unfiltered: u32,
    /// Flicker over the following frames, when asked for ([`flicker`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flicker: Option<FlickerReport>,
}

/// Largest number of frames of a flicker measurement.
pub const MAX_FLICKER_FRAMES: u32 = 256;

/// Flicker near the horizon over a run of frames, texcore's images and the truth.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FlickerReport {
    /// First frame.
    pub first: u32,
    /// Number of frames (2 or more).
    pub frames: u32,
    /// The band of rows measured, `[start, end)`.
    pub rows: [u32; 2],
    /// Flicker of the filtered image (8-bit units, mean absolute frame-to-frame RGB difference).
    pub flicker_filtered: f64,
    /// Flicker of the unfiltered image.
    pub flicker_unfiltered: f64,
    /// Flicker of the supersampled truth.
    pub flicker_truth: f64,
    /// `flicker_filtered / flicker_truth` (0 when the truth does not flicker).
    pub ratio: f64,
}

/// The flicker of frames `first .. first + frames` of `scene` in the band of rows around the
/// image centre (a quarter of the height): texcore filtered (`cfg`), unfiltered, and the
/// `n x n` supersampled truth. `frames` in `2..=MAX_FLICKER_FRAMES`.
pub fn flicker(
    scene: &HostScene,
    first: u32,
    frames: u32,
    cfg: &UnitConfig,
    hash: HashKind,
    n: u16,
) -> Result<FlickerReport, UnitError> {
    if !(2..=MAX_FLICKER_FRAMES).contains(&frames) {
        return Err(UnitError::Render(format!(
            "flicker frames {frames} out of range 2..={MAX_FLICKER_FRAMES}"
        )));
    }
    let plain_cfg = UnitConfig {
        aa: Antialias::None,
        ..*cfg
    };
    let (mut tr, mut fi, mut un) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..frames {
        let frame = first.wrapping_add(k);
        tr.push(truth(scene, frame, cfg, hash, n)?);
        let f = render_host_frame(scene, frame, cfg, hash, Output::Color)?;
        fi.push(to_f64(&f.frame.pixels));
        let u = render_host_frame(scene, frame, &plain_cfg, hash, Output::Color)?;
        un.push(to_f64(&u.frame.pixels));
    }
    let (w, h) = scene.scene.size();
    let (w, h) = (u32::from(w), u32::from(h));
    let rows = (h / 2 - h / 8)..(h / 2 + h / 8);
    let fl = |img: &[Vec<[f64; 4]>]| crate::accuracy::measure::flicker(img, w, rows.clone());
    let (ff, fu, ft) = (fl(&fi), fl(&un), fl(&tr));
    Ok(FlickerReport {
        first,
        frames,
        rows: [rows.start, rows.end],
        flicker_filtered: ff,
        flicker_unfiltered: fu,
        flicker_truth: ft,
        ratio: if ft > 0.0 { ff / ft } else { 0.0 },
    })
}

/// A scene frame enlarged for supersampling: the scene, its materials and its own image size.
type Enlarged = (
    texcore::scene::Scene,
    Vec<crate::unit::MaterialSpec>,
    (u16, u16),
);

/// Frame `frame` of `scene` and its materials with the image `n` times as large on each axis,
/// and the scene's own size; `n` and the enlarged size checked.
fn enlarged_frame(
    scene: &HostScene,
    frame: u32,
    hash: HashKind,
    n: u16,
) -> Result<Enlarged, UnitError> {
    if n == 0 || n > MAX_SUPERSAMPLE {
        return Err(UnitError::Render(format!(
            "supersampling factor {n} out of range 1..={MAX_SUPERSAMPLE}"
        )));
    }
    let (mut s, materials) = scene.frame(frame, hash)?;
    let (w, h) = s.size();
    let (bw, bh) = (u32::from(w) * u32::from(n), u32::from(h) * u32::from(n));
    if bw > 16384 || bh > 16384 {
        return Err(UnitError::Render(format!(
            "supersampled image {bw}x{bh} too large (at most 16384 a side)"
        )));
    }
    s.camera.width = bw as u16;
    s.camera.height = bh as u16;
    Ok((s, materials, (w, h)))
}

/// The truth of frame `frame` of `scene`: `n x n` stratified point samples a pixel of the f64
/// model (every octave, exact perspective, nearest entry), averaged.
pub fn truth(
    scene: &HostScene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
    n: u16,
) -> Result<Vec<[f64; 4]>, UnitError> {
    let (mut s, materials, (w, h)) = enlarged_frame(scene, frame, hash, n)?;
    for o in s.objects.iter_mut() {
        o.perspective = Perspective::Exact;
    }
    let point = UnitConfig {
        aa: Antialias::None,
        lookup: TableLookup::Nearest,
        cull: false,
        ..*cfg
    };
    let big = reference_framed(&s, &materials, &point)?;
    Ok(crate::accuracy::measure::downsample(
        &big,
        u32::from(w),
        u32::from(h),
        u32::from(n),
    ))
}

/// Compares texcore's filtered (`cfg`) and unfiltered (`cfg` with no filter) images of frame
/// `frame` with the `n x n` supersampled truth.
pub fn check(
    scene: &HostScene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
    n: u16,
) -> Result<SupersampledReport, UnitError> {
    let t = truth(scene, frame, cfg, hash, n)?;
    let filtered = render_host_frame(scene, frame, cfg, hash, Output::Color)?;
    let plain_cfg = UnitConfig {
        aa: Antialias::None,
        ..*cfg
    };
    let plain = render_host_frame(scene, frame, &plain_cfg, hash, Output::Color)?;
    let err = |e: crate::metrics::MetricsError| UnitError::Render(e.to_string());
    let mf = compare_to_reference(&filtered.frame.pixels, &t).map_err(err)?;
    let mu = compare_to_reference(&plain.frame.pixels, &t).map_err(err)?;
    let width = filtered.frame.width;
    let height = filtered.frame.height;
    let truth_std = row_stds(&t, width);
    let f_std = row_stds(&to_f64(&filtered.frame.pixels), width);
    let u_std = row_stds(&to_f64(&plain.frame.pixels), width);
    let no_cull = render_host_frame(
        scene,
        frame,
        &UnitConfig {
            cull: false,
            ..plain_cfg
        },
        hash,
        Output::Color,
    )?;
    let mn = compare_to_reference(&no_cull.frame.pixels, &t).map_err(err)?;
    let ss2 = texcore_supersampled(scene, frame, &plain_cfg, hash, 2)?;
    let ss4 = texcore_supersampled(scene, frame, &plain_cfg, hash, 4)?;
    // The box-averaged images as a display shows them: rounded to 8 bits.
    let psnr = |img: &[[f64; 4]]| -> Result<f64, UnitError> {
        let px: Vec<[u8; 4]> = img
            .iter()
            .map(|p| p.map(|c| c.round().clamp(0.0, 255.0) as u8))
            .collect();
        Ok(compare_to_reference(&px, &t).map_err(err)?.psnr)
    };
    let (band, rows) = flat_band(&f_std, &truth_std);
    let (band_u, _) = flat_band(&u_std, &truth_std);
    Ok(SupersampledReport {
        name: scene.scene.name.to_string(),
        width,
        height,
        frame,
        supersampled: n,
        psnr_filtered: mf.psnr,
        psnr_unfiltered: mu.psnr,
        gain_db: mf.psnr - mu.psnr,
        psnr_unfiltered_no_cull: mn.psnr,
        psnr_supersampled_2x2: psnr(&ss2)?,
        psnr_supersampled_4x4: psnr(&ss4)?,
        longest_flat_band: band,
        flat_rows: rows,
        longest_flat_band_unfiltered: band_u,
        flicker: None,
    })
}

/// Texcore's image of frame `frame` with `cfg`, rendered at `k` times the size (`k x k` samples
/// a pixel) and box-averaged to the scene's size.
pub fn texcore_supersampled(
    scene: &HostScene,
    frame: u32,
    cfg: &UnitConfig,
    hash: HashKind,
    k: u16,
) -> Result<Vec<[f64; 4]>, UnitError> {
    let (s, materials, (w, h)) = enlarged_frame(scene, frame, hash, k)?;
    let big =
        crate::dispatch_table_size!(cfg.table_size, render_n(&s, &materials, cfg, Output::Color))?;
    Ok(crate::accuracy::measure::downsample(
        &to_f64(&big.frame.pixels),
        u32::from(w),
        u32::from(h),
        u32::from(k),
    ))
}

fn to_f64(img: &[[u8; 4]]) -> Vec<[f64; 4]> {
    img.iter().map(|p| p.map(f64::from)).collect()
}

/// Luma (Rec. 601) of an RGB pixel.
fn luma(p: &[f64; 4]) -> f64 {
    0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]
}

/// The standard deviation of the luma along each row of a `width`-pixel image.
pub fn row_stds(img: &[[f64; 4]], width: u32) -> Vec<f64> {
    if width == 0 {
        return Vec::new();
    }
    img.chunks(width as usize)
        .map(|row| {
            let n = row.len() as f64;
            let mean = row.iter().map(luma).sum::<f64>() / n;
            let var = row.iter().map(|p| (luma(p) - mean).powi(2)).sum::<f64>() / n;
            var.sqrt()
        })
        .collect()
}

/// The longest run of rows flat in `img` (std below [`FLAT_STD`]) where `truth` shows texture
/// (std at least [`TEXTURED_STD`]), and the number of such rows.
pub fn flat_band(img: &[f64], truth: &[f64]) -> (u32, u32) {
    let mut best = 0u32;
    let mut run = 0u32;
    let mut rows = 0u32;
    for (a, t) in img.iter().zip(truth) {
        if *a < FLAT_STD && *t >= TEXTURED_STD {
            run += 1;
            rows += 1;
            best = best.max(run);
        } else {
            run = 0;
        }
    }
    (best, rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_band_counts_runs_where_truth_is_textured() {
        let img = [0.0, 0.1, 3.0, 0.0, 0.0, 0.0, 0.2];
        let truth = [5.0, 5.0, 5.0, 5.0, 5.0, 1.0, 5.0];
        // Rows 0-1 (run 2), rows 3-4 (run 2; row 5's truth is flat too), row 6.
        assert_eq!(flat_band(&img, &truth), (2, 5));
        assert_eq!(flat_band(&[], &[]), (0, 0));
    }

    #[test]
    fn row_stds_of_constant_and_striped_rows() {
        let img = vec![
            [10.0, 10.0, 10.0, 255.0],
            [10.0, 10.0, 10.0, 255.0],
            [0.0, 0.0, 0.0, 255.0],
            [100.0, 100.0, 100.0, 255.0],
        ];
        let s = row_stds(&img, 2);
        assert_eq!(s[0], 0.0);
        assert!((s[1] - 50.0).abs() < 1e-9);
    }

    #[test]
    fn truth_rejects_bad_factors() {
        let scene = HostScene::builtin(texcore::scene::by_name("marble").unwrap());
        let cfg = crate::unit::UnitConfig::default();
        assert!(truth(&scene, 0, &cfg, HashKind::Permutation, 0).is_err());
        assert!(truth(&scene, 0, &cfg, HashKind::Permutation, 17).is_err());
    }
}
