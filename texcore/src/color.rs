//! Colours: `Rgba8888` (colour-table entries and pixels) and `Rgb565` (display output).
