//! Runs every host example into a temporary directory and checks what it wrote.

use std::path::PathBuf;

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texcore-examples-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn textured_rectangle() {
    let d = out_dir("rect");
    let png = d.join("rect.png");
    let display = texcore_examples::textured_rectangle(&png).unwrap();
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (240, 160));
    // The marble rectangle: its pixels are the marble texture's, not the background.
    let bg = Rgb565::new(4, 8, 6);
    assert_ne!(display.get_pixel(Point::new(40, 40)), bg);
    assert_eq!(display.get_pixel(Point::new(4, 4)), bg);
    // Many colours (a texture, not a flat fill).
    let mut colours: Vec<_> = img.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 100, "{} colours", colours.len());
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn spinning_teapot() {
    let d = out_dir("teapot");
    let gif = d.join("teapot.gif");
    assert_eq!(texcore_examples::spinning_teapot(&gif, 4).unwrap(), 4);
    let frames = gif_frames(&gif);
    assert_eq!(frames.len(), 4);
    assert_eq!(frames[0].dimensions(), (320, 240));
    assert_ne!(frames[0], frames[1], "the teapot turns");
    std::fs::remove_dir_all(d).unwrap();
}

#[test]
fn fire_panel() {
    let d = out_dir("fire");
    let gif = d.join("fire.gif");
    texcore_examples::fire_panel(&gif, 3).unwrap();
    let frames = gif_frames(&gif);
    assert_eq!(frames.len(), 3);
    assert_eq!(frames[0].dimensions(), (96, 128));
    assert_ne!(frames[0], frames[2], "the flames move");
    std::fs::remove_dir_all(d).unwrap();
}

fn gif_frames(path: &std::path::Path) -> Vec<image::RgbaImage> {
    use image::AnimationDecoder;
    let f = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(f)
        .unwrap()
        .into_frames()
        .map(|f| f.unwrap().into_buffer())
        .collect()
}
