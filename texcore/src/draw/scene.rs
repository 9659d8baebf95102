//! A scene drawn through the renderer as one `Drawable` ([`TexturedScene`]), its spans
//! written to the draw target ([`TargetSink`]).

use super::*;

/// A pixel sink over a draw target that keeps the first display error (and writes nothing
/// after it).
struct TargetSink<'d, D: DrawTarget> {
    target: &'d mut D,
    error: Option<D::Error>,
}

impl<D> PixelSink for TargetSink<'_, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    fn write_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        if self.error.is_some() {
            return;
        }
        let n = colors.len().min(usize::from(u16::MAX)) as u32;
        let area = Rectangle::new(Point::new(i32::from(x), i32::from(y)), Size::new(n, 1));
        let pixels = colors.iter().map(|&c| display_color(c));
        if let Err(e) = self.target.fill_contiguous(&area, pixels) {
            self.error = Some(e);
        }
    }

    fn fill_span(&mut self, x: u16, y: u16, len: u16, color: Rgba8888) {
        if self.error.is_some() {
            return;
        }
        let area = Rectangle::new(
            Point::new(i32::from(x), i32::from(y)),
            Size::new(u32::from(len), 1),
        );
        if let Err(e) = self.target.fill_solid(&area, display_color(color)) {
            self.error = Some(e);
        }
    }
}

/// A scene (any [`TriangleSource`]: a [`crate::scene::Scene`] of textured mesh objects) with its
/// textures, drawn through the [`Renderer`] as one `Drawable`.
///
/// Scenes without depth or blending stream their segments straight to the display; the others
/// render in bands through a band and a depth buffer of `BAND` pixels each on the stack
/// (`BAND * 6` bytes; `BAND / width` rows per band, at least one row). `draw` returns
/// `Err(D::Error)` for a display error and `Ok` with the renderer's result (its counters, or
/// why the scene could not be rendered: [`RenderError`]).
///
/// With `W > 0` (feature `differences`, `TexturedScene::with_differences`) the filter widths
/// come from the differences of neighbouring values (`Renderer::with_differences`, a named
/// approximate mode), the memory of rows of `W` pixels and a face cache of [`DRAW_FACES`]
/// entries on the stack during `draw` (`8 W + 32 DRAW_FACES` bytes and the cache's lanes); a
/// scene wider than `W` pixels is refused ([`RenderError::MemoryTooNarrow`]). Its bands are
/// then whole tiles of `texture::TILE_ROWS` rows, so the image is the streamed one (and
/// `texsim render --widths differences`'s) whenever `BAND` holds that many rows.
#[derive(Debug)]
pub struct TexturedScene<
    'a,
    S,
    C,
    const T: usize,
    const N: usize,
    const BAND: usize = 2048,
    const W: usize = 0,
> {
    scene: &'a S,
    textures: &'a [Texture<T, N>],
    color: PhantomData<fn() -> C>,
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize> Clone
    for TexturedScene<'_, S, C, T, N, BAND, W>
{
    fn clone(&self) -> Self {
        *self
    }
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize> Copy
    for TexturedScene<'_, S, C, T, N, BAND, W>
{
}

/// Face-cache entries of a [`TexturedScene`] drawn with the widths from differences (32 bytes
/// each, on the stack during `draw`; the values are the same with any number).
pub const DRAW_FACES: usize = 64;

impl<'a, S, C, const T: usize, const N: usize, const BAND: usize>
    TexturedScene<'a, S, C, T, N, BAND>
{
    /// `scene` with `textures` (the object's texture slot `i` is `textures[i]`).
    pub const fn new(scene: &'a S, textures: &'a [Texture<T, N>]) -> Self {
        TexturedScene {
            scene,
            textures,
            color: PhantomData,
        }
    }
}

#[cfg(feature = "differences")]
impl<'a, S, C, const T: usize, const N: usize, const BAND: usize, const W: usize>
    TexturedScene<'a, S, C, T, N, BAND, W>
{
    /// The same scene drawn with the filter widths from the differences of neighbouring values
    /// (see the type's documentation), rows of up to `W2` pixels (at least the scene's width).
    pub const fn with_differences<const W2: usize>(
        self,
    ) -> TexturedScene<'a, S, C, T, N, BAND, W2> {
        TexturedScene {
            scene: self.scene,
            textures: self.textures,
            color: PhantomData,
        }
    }
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize> Drawable
    for TexturedScene<'_, S, C, T, N, BAND, W>
where
    S: TriangleSource,
    C: PixelColor + From<Rgb888>,
{
    type Color = C;
    type Output = Result<RenderStats, RenderError>;

    fn draw<D>(&self, target: &mut D) -> Result<Self::Output, D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        #[cfg(feature = "differences")]
        if W > 0 {
            let mut mem = crate::texture::DifferenceMemory::<W>::new();
            let mut faces = crate::span::FaceCache::<DRAW_FACES, T>::new();
            let renderer = Renderer::new(self.textures).with_differences(&mut mem, &mut faces);
            return self.draw_with(&renderer, target);
        }
        self.draw_with(&Renderer::new(self.textures), target)
    }
}

impl<S, C, const T: usize, const N: usize, const BAND: usize, const W: usize>
    TexturedScene<'_, S, C, T, N, BAND, W>
where
    S: TriangleSource,
    C: PixelColor + From<Rgb888>,
{
    /// Draws the scene through `renderer`.
    fn draw_with<D>(
        &self,
        renderer: &Renderer<'_, T, N>,
        target: &mut D,
    ) -> Result<Result<RenderStats, RenderError>, D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let mut sink = TargetSink {
            target,
            error: None,
        };
        let result = match renderer.needs_bands(self.scene) {
            Err(e) => Err(e),
            Ok(false) => renderer.render_streamed(self.scene, &mut sink),
            Ok(true) => {
                let mut band = [Rgba8888::BLACK; BAND];
                let mut depth = [0u16; BAND];
                let w = usize::from(self.scene.size().0.max(1));
                let mut rows = (BAND / w).min(usize::from(u16::MAX)) as u16;
                // Bands of whole tiles with the widths from differences: the streamed image.
                if W > 0 && rows >= crate::texture::TILE_ROWS {
                    rows -= rows % crate::texture::TILE_ROWS;
                }
                renderer.render_banded(self.scene, &mut band, &mut depth, rows, &mut sink)
            }
        };
        match sink.error {
            Some(e) => Err(e),
            None => Ok(result),
        }
    }
}
