//! The report's images: error against device instructions with the Pareto front
//! (`docs/accuracy.png`), and the precision contact sheet (`docs/precision.png`).
//!
//! Shapes are drawn with plotters' bitmap backend; text with the built-in pixel font
//! ([`super::font`]), so no system font is needed.

use plotters::prelude::*;

use super::font::{draw_text, text_height, text_width};
use super::{cost, Report};
use crate::output::Frame;

const W: u32 = 900;
const H: u32 = 560;
const LEFT: i32 = 80;
const RIGHT: i32 = 30;
const TOP: i32 = 50;
const BOTTOM: i32 = 60;

fn rgba(rgb: &[u8], w: u32, h: u32) -> Frame {
    Frame {
        width: w,
        height: h,
        pixels: rgb.chunks(3).map(|p| [p[0], p[1], p[2], 255]).collect(),
    }
}

/// "Nice" tick values (1, 2, 5 times powers of ten) covering `lo..hi` on a log axis.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut t = Vec::new();
    let mut p = 10f64.powf(lo.log10().floor());
    while p <= hi * 1.0001 {
        for m in [1.0, 2.0, 5.0] {
            let v = p * m;
            if v >= lo * 0.9999 && v <= hi * 1.0001 {
                t.push(v);
            }
        }
        p *= 10.0;
    }
    t
}

/// Error (PSNR against the baseline's f64 image) against device instructions per pixel (M4F; host
/// ns without QEMU), one point per configuration, the Pareto front joined and highlighted.
pub fn front_plot(report: &Report) -> Option<Frame> {
    let pts: Vec<(f64, f64, bool, String)> = {
        let mut seen = std::collections::HashSet::new();
        report
            .rows
            .iter()
            .filter(|r| r.base.is_some())
            .filter(|r| seen.insert(format!("{}/{}", r.checksum, cost(r))))
            .map(|r| {
                (
                    cost(r),
                    r.base.map_or(0.0, |b| b.psnr),
                    r.pareto,
                    super::output::label(r),
                )
            })
            .collect()
    };
    if pts.is_empty() {
        return None;
    }
    let device = report.rows.iter().any(|r| {
        r.device_instructions_per_pixel
            .contains_key("thumbv7em-none-eabihf")
    });
    let (xmin, xmax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (ymin, ymax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let (x0, x1) = ((xmin / 1.3).max(1e-3), xmax * 1.3);
    let (y0, y1) = (
        (ymin / 5.0).floor() * 5.0 - 2.0,
        (ymax / 5.0).ceil() * 5.0 + 2.0,
    );
    let pw = (W as i32 - LEFT - RIGHT) as f64;
    let ph = (H as i32 - TOP - BOTTOM) as f64;
    let sx = |x: f64| LEFT + ((x.ln() - x0.ln()) / (x1.ln() - x0.ln()) * pw) as i32;
    let sy = |y: f64| TOP + ((y1 - y) / (y1 - y0) * ph) as i32;

    let mut buf = vec![255u8; (W * H * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (W, H)).into_drawing_area();
        let grid = RGBColor(225, 225, 225);
        let axis = RGBColor(60, 60, 60);
        for t in log_ticks(x0, x1) {
            let x = sx(t);
            root.draw(&PathElement::new(
                vec![(x, TOP), (x, H as i32 - BOTTOM)],
                grid,
            ))
            .ok()?;
        }
        let mut y = (y0 / 5.0).ceil() * 5.0;
        while y <= y1 {
            let py = sy(y);
            root.draw(&PathElement::new(
                vec![(LEFT, py), (W as i32 - RIGHT, py)],
                grid,
            ))
            .ok()?;
            y += 5.0;
        }
        root.draw(&Rectangle::new(
            [(LEFT, TOP), (W as i32 - RIGHT, H as i32 - BOTTOM)],
            axis.stroke_width(1),
        ))
        .ok()?;
        let mut front: Vec<(f64, f64)> = pts.iter().filter(|p| p.2).map(|p| (p.0, p.1)).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        front.dedup();
        let path: Vec<(i32, i32)> = front.iter().map(|p| (sx(p.0), sy(p.1))).collect();
        root.draw(&PathElement::new(path, RED.stroke_width(2)))
            .ok()?;
        for p in &pts {
            let c = (sx(p.0), sy(p.1));
            if p.2 {
                root.draw(&Circle::new(c, 5, RED.filled())).ok()?;
            } else {
                root.draw(&Circle::new(c, 4, RGBColor(90, 90, 140).stroke_width(1)))
                    .ok()?;
            }
        }
        root.present().ok()?;
    }
    // Text.
    let black = [20, 20, 20];
    let title = if device {
        "MARBLE CHECK PLANE: ERROR VS CORTEX-M4F INSTRUCTIONS PER PIXEL"
    } else {
        "MARBLE CHECK PLANE: ERROR VS HOST NS PER PIXEL (NO QEMU)"
    };
    draw_text(&mut buf, W, H, LEFT, 15, title, 2, black);
    for t in log_ticks(x0, x1) {
        let s = format!("{t}");
        let x = sx(t) - text_width(&s, 1) as i32 / 2;
        draw_text(&mut buf, W, H, x, H as i32 - BOTTOM + 8, &s, 1, black);
    }
    let xl = if device {
        "INSTRUCTIONS PER PIXEL (LOG SCALE)"
    } else {
        "HOST NS PER PIXEL (LOG SCALE)"
    };
    draw_text(
        &mut buf,
        W,
        H,
        LEFT + (W as i32 - LEFT - RIGHT) / 2 - text_width(xl, 2) as i32 / 2,
        H as i32 - 30,
        xl,
        2,
        black,
    );
    let mut y = (y0 / 5.0).ceil() * 5.0;
    while y <= y1 {
        let s = format!("{y:.0}");
        draw_text(
            &mut buf,
            W,
            H,
            LEFT - 8 - text_width(&s, 1) as i32,
            sy(y) - 3,
            &s,
            1,
            black,
        );
        y += 5.0;
    }
    draw_text(&mut buf, W, H, 6, TOP - 14, "PSNR DB", 1, black);
    // Labels of the front's points, alternately above and below the front.
    let mut labelled: Vec<&(f64, f64, bool, String)> = pts.iter().filter(|p| p.2).collect();
    labelled.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut last = String::new();
    for (k, p) in labelled.iter().enumerate() {
        let key = format!("{:.0}/{:.2}", p.0, p.1);
        if key == last {
            continue;
        }
        last = key;
        let dy = if k % 2 == 0 { -14 } else { 8 };
        draw_text(
            &mut buf,
            W,
            H,
            sx(p.0) + 7,
            sy(p.1) + dy,
            p.3.as_str(),
            1,
            [170, 0, 0],
        );
    }
    let legend = "RED: PARETO FRONT   BLUE: OTHER CONFIGURATIONS";
    draw_text(
        &mut buf,
        W,
        H,
        W as i32 - RIGHT - text_width(legend, 1) as i32 - 6,
        TOP + 6,
        legend,
        1,
        black,
    );
    Some(rgba(&buf, W, H))
}

/// The `marble` scene at each coordinate precision, side by side in a 2x2 grid, each labelled
/// with its bits (the paper's Fig. 10).
pub fn contact_sheet(report: &Report) -> Option<Frame> {
    let imgs = &report.precision_images;
    if imgs.is_empty() {
        return None;
    }
    let (w, h) = (
        u32::from(report.settings.precision_scene.0),
        u32::from(report.settings.precision_scene.1),
    );
    let scale = if w >= 200 { 2 } else { 1 };
    let label_h = text_height(scale) + 8;
    let cols = 2u32.min(imgs.len() as u32);
    let rows = (imgs.len() as u32).div_ceil(cols);
    let (sw, sh) = (cols * w, rows * (h + label_h));
    let mut buf = vec![30u8; (sw * sh * 3) as usize];
    for (k, (bits, img)) in imgs.iter().enumerate() {
        let (cx, cy) = ((k as u32 % cols) * w, (k as u32 / cols) * (h + label_h));
        let long = if *bits == 16 {
            format!("{bits} FRACTION BITS (NATIVE)")
        } else {
            format!("{bits} FRACTION BITS")
        };
        let label = if text_width(&long, scale) + 8 <= w {
            long
        } else {
            format!("F={bits}")
        };
        draw_text(
            &mut buf,
            sw,
            sh,
            (cx + 6) as i32,
            (cy + 4) as i32,
            &label,
            scale,
            [240, 240, 240],
        );
        for y in 0..h {
            for x in 0..w {
                let p = img[(y * w + x) as usize];
                let i = (((cy + label_h + y) * sw + cx + x) * 3) as usize;
                buf[i..i + 3].copy_from_slice(&p[..3]);
            }
        }
    }
    Some(rgba(&buf, sw, sh))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks() {
        assert_eq!(log_ticks(150.0, 3000.0), vec![200.0, 500.0, 1000.0, 2000.0]);
    }
}
