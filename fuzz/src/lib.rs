//! Helpers of the fuzz targets: a reader that turns the fuzzer's bytes into bounded values
//! (every read succeeds; past the end it yields zeros, so every input is a valid case).

/// Reads little-endian values from the fuzzer's input, zeros past its end.
pub struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    /// A reader over `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data }
    }

    /// Whether every byte has been read.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The next byte (0 past the end).
    pub fn u8(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    /// The next two bytes, little-endian.
    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    /// The next four bytes, little-endian.
    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    /// The next four bytes as an `i32`.
    pub fn i32(&mut self) -> i32 {
        self.u32() as i32
    }

    /// A value below `n` (`n > 0`) from one byte.
    pub fn below(&mut self, n: u8) -> u8 {
        self.u8() % n
    }

    /// A boolean from one byte.
    pub fn bool(&mut self) -> bool {
        self.u8() & 1 == 1
    }

    /// An `i32` of varied magnitude: one byte picks a shift, so small, medium and full-range
    /// values are all frequent (fixed-point edge cases live at every scale).
    pub fn i32_scaled(&mut self) -> i32 {
        let shift = u32::from(self.below(32));
        self.i32() >> shift
    }

    /// One of `items`, chosen by one byte.
    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[usize::from(self.u8()) % items.len()]
    }
}
