//! Filling shapes with a texture ([`TextureStyle`]): each row run of a shape one span, the
//! spans of one shape through its visible area's plane set-up ([`AreaShader`]).

use super::*;

/// A texture evaluator shading the spans of one display rectangle through its plane's set-up
/// ([`PlaneMapping::span_plane`], [`TextureEvaluator::shade_plane`]) when it has one, span by
/// span otherwise: the same colours either way. With `W > 0` (feature `differences`) and a
/// rectangle at most `W` pixels wide, its runs are shaded with the filter widths from
/// differences instead ([`AreaShader::shade_differences`]).
struct AreaShader<'t, 'm, const T: usize, const N: usize, const W: usize> {
    ev: TextureEvaluator<'t, T, N>,
    mapping: &'m PlaneMapping,
    /// The plane's set-up and the rectangle's top-left pixel.
    plane: Option<(PlaneSetup<'t, T>, Point)>,
    /// The difference memory and the rectangle's top-left pixel (the widths from differences).
    #[cfg(feature = "differences")]
    diff: Option<(crate::texture::DifferenceMemory<W>, Point)>,
}

impl<'t, 'm, const T: usize, const N: usize, const W: usize> AreaShader<'t, 'm, T, N, W> {
    fn new(texture: &'t Texture<T, N>, mapping: &'m PlaneMapping, area: &Rectangle) -> Self {
        let ev = texture.evaluator();
        // The widths from differences for a filtered texture on a rectangle that fits the
        // memory (its runs never take the plane's set-up; an unfiltered texture needs no
        // widths).
        #[cfg(feature = "differences")]
        if W > 0
            && area.size.width as usize <= W
            && texture.stage().antialias() != crate::filter::Antialias::None
        {
            return AreaShader {
                ev,
                mapping,
                plane: None,
                diff: Some((crate::texture::DifferenceMemory::new(), area.top_left)),
            };
        }
        let plane = mapping
            .span_plane(area)
            .and_then(|p| ev.plane_setup(&p))
            .map(|s| (s, area.top_left));
        AreaShader {
            ev,
            mapping,
            plane,
            #[cfg(feature = "differences")]
            diff: None,
        }
    }

    /// With the widths from differences: shades the run `x..x + len` of row `y` (inside the
    /// rectangle) as one span, its pixel above from the row shaded before it (relative to the
    /// rectangle's top-left pixel: [`TextureEvaluator::shade_differences`]), handing `piece`
    /// its colours in pieces of at most [`RUN_CHUNK`] pixels with each piece's first column.
    /// `false` (nothing shaded) without a difference memory or outside the rectangle.
    #[cfg(feature = "differences")]
    fn shade_differences(
        &mut self,
        (x, y, len): (i32, i32, u16),
        mut piece: impl FnMut(i32, &[Rgba8888]),
    ) -> bool {
        let Some((mem, at)) = self.diff.as_mut() else {
            return false;
        };
        let (Ok(dx), Ok(dy)) = (
            u16::try_from(i64::from(x) - i64::from(at.x)),
            u16::try_from(i64::from(y) - i64::from(at.y)),
        ) else {
            return false;
        };
        let span = self.mapping.span(x, y, len);
        let mut rows = mem.rows_mut(crate::span::Faces::none());
        self.ev
            .differences_pieces::<Rgba8888, _, RUN_CHUNK>(&mut rows, dx, dy, &span, |off, px| {
                piece(x.saturating_add(i32::from(off)), px)
            })
    }

    /// Shades the `len` pixels of display row `y` from column `x` (inside the rectangle, or
    /// shaded span by span).
    fn shade(&mut self, x: i32, y: i32, len: u16, emit: impl FnMut(Rgba8888)) {
        if let Some((setup, at)) = &self.plane {
            let (dx, dy) = (
                u16::try_from(i64::from(x) - i64::from(at.x)),
                u16::try_from(i64::from(y) - i64::from(at.y)),
            );
            if let (Ok(dx), Ok(dy)) = (dx, dy) {
                if setup.plane().contains(dx, dy, len) {
                    self.ev.shade_plane(setup, dx, dy, len, emit);
                    return;
                }
            }
        }
        self.ev.shade(&self.mapping.span(x, y, len), emit);
    }
}

/// A primitive style that fills a shape with a texture placed by a [`PlaneMapping`]. `C` is the
/// display colour (inferred from the draw target).
///
/// With `W > 0` (feature `differences`, `TextureStyle::with_differences`) a filtered texture
/// takes its filter widths from the differences of neighbouring values (the named approximate
/// mode of [`crate::texture::DifferenceSpans`]: exact values without their gradients, about
/// half the noise's cost), a memory of two rows of `W` pixels (`8 W` bytes) on the stack during
/// `draw`. Each row run of the shape is then one span (the pixel above from the run shaded
/// before it on the row above, rows counted from the visible part's top, tiles of
/// [`crate::texture::TILE_ROWS`] rows as `TextureEvaluator::shade_differences` takes them),
/// written in pieces of [`RUN_CHUNK`] pixels. A shape whose visible part is wider than `W`
/// pixels, or a texture without antialiasing, is shaded as without it (widths from the
/// gradients; none).
#[derive(Debug)]
pub struct TextureStyle<'t, C, const T: usize, const N: usize, const W: usize = 0> {
    texture: &'t Texture<T, N>,
    mapping: PlaneMapping,
    color: PhantomData<fn() -> C>,
}

impl<C, const T: usize, const N: usize, const W: usize> Clone for TextureStyle<'_, C, T, N, W> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C, const T: usize, const N: usize, const W: usize> Copy for TextureStyle<'_, C, T, N, W> {}

impl<'t, C, const T: usize, const N: usize> TextureStyle<'t, C, T, N> {
    /// Fills with `texture` placed by `mapping`.
    pub const fn new(texture: &'t Texture<T, N>, mapping: PlaneMapping) -> Self {
        TextureStyle {
            texture,
            mapping,
            color: PhantomData,
        }
    }
}

#[cfg(feature = "differences")]
impl<'t, C, const T: usize, const N: usize, const W: usize> TextureStyle<'t, C, T, N, W> {
    /// The same style with the filter widths from the differences of neighbouring values (see
    /// the type's documentation), shapes up to `W2` pixels wide.
    pub const fn with_differences<const W2: usize>(self) -> TextureStyle<'t, C, T, N, W2> {
        TextureStyle {
            texture: self.texture,
            mapping: self.mapping,
            color: PhantomData,
        }
    }
}

impl<'t, C, const T: usize, const N: usize, const W: usize> TextureStyle<'t, C, T, N, W> {
    /// The texture.
    pub const fn texture(&self) -> &'t Texture<T, N> {
        self.texture
    }

    /// The mapping.
    pub const fn mapping(&self) -> PlaneMapping {
        self.mapping
    }

    /// The same style with another mapping.
    pub const fn with_mapping(mut self, mapping: PlaneMapping) -> Self {
        self.mapping = mapping;
        self
    }
}

/// Shades a row run `x .. x + len` of row `y` and writes it with `fill_contiguous`, in pieces
/// of at most [`RUN_CHUNK`] pixels.
fn fill_run<D, const T: usize, const N: usize, const W: usize>(
    ev: &mut AreaShader<'_, '_, T, N, W>,
    (x, y, len): (i32, i32, u32),
    target: &mut D,
) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    // The widths from differences: the run as one span (runs are at most `W <= u16::MAX`
    // pixels there), its pieces written as they come, the first display error kept.
    #[cfg(feature = "differences")]
    if let Ok(n) = u16::try_from(len) {
        let mut result = Ok(());
        let done = ev.shade_differences((x, y, n), |x0, px| {
            if result.is_ok() {
                let area = Rectangle::new(Point::new(x0, y), Size::new(px.len() as u32, 1));
                result = target.fill_contiguous(&area, px.iter().map(|&c| display_color(c)));
            }
        });
        if done {
            return result;
        }
    }
    let mut buf = [Rgba8888::BLACK; RUN_CHUNK];
    let mut done = 0u32;
    while done < len {
        let n = (len - done).min(RUN_CHUNK as u32);
        let x0 = x.saturating_add(done as i32);
        let mut i = 0;
        ev.shade(x0, y, n as u16, |c| {
            if let Some(b) = buf.get_mut(i) {
                *b = c;
            }
            i += 1;
        });
        let area = Rectangle::new(Point::new(x0, y), Size::new(n, 1));
        let colors = buf.iter().take(n as usize).map(|&c| display_color(c));
        target.fill_contiguous(&area, colors)?;
        done += n;
    }
    Ok(())
}

/// The visible part `[x0, x1)` of a run on row `y`: `None` outside `clip`.
fn clip_run(clip: &Rectangle, y: i32, x0: i32, x1: i32) -> Option<(i32, i32, u32)> {
    let br = clip.bottom_right()?;
    if y < clip.top_left.y || y > br.y {
        return None;
    }
    let a = x0.max(clip.top_left.x);
    let b = x1.min(br.x.saturating_add(1));
    (a < b).then(|| (a, y, (b - a) as u32))
}

/// Fills the pixels of `points` (any order; runs of consecutive pixels of a row are shaded as
/// one span) with the style's texture.
fn fill_points<D, I, const T: usize, const N: usize, const W: usize>(
    points: I,
    bounds: Rectangle,
    style: &TextureStyle<'_, D::Color, T, N, W>,
    target: &mut D,
) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
    I: Iterator<Item = Point>,
{
    let clip = target.bounding_box();
    let mut ev =
        AreaShader::<T, N, W>::new(style.texture, &style.mapping, &bounds.intersection(&clip));
    // The open run: row, first column, one past the last column.
    let mut run: Option<(i32, i32, i32)> = None;
    for p in points {
        match run {
            Some((y, x0, x1)) if y == p.y && x1 == p.x && x1 < i32::MAX => {
                run = Some((y, x0, x1 + 1));
            }
            _ => {
                if let Some((y, x0, x1)) = run {
                    if let Some(r) = clip_run(&clip, y, x0, x1) {
                        fill_run(&mut ev, r, target)?;
                    }
                }
                run = Some((p.y, p.x, p.x.saturating_add(1)));
            }
        }
    }
    if let Some((y, x0, x1)) = run {
        if let Some(r) = clip_run(&clip, y, x0, x1) {
            fill_run(&mut ev, r, target)?;
        }
    }
    Ok(())
}

/// The colours of a rectangle's rows, shaded [`RUN_CHUNK`] pixels at a time (the iterator of
/// the rectangle's single `fill_contiguous` call).
struct RectColors<'e, 't, 'm, C, const T: usize, const N: usize> {
    ev: &'e mut AreaShader<'t, 'm, T, N, 0>,
    area: Rectangle,
    /// Next pixel to shade (relative to the area).
    x: u32,
    y: u32,
    buf: [Rgba8888; RUN_CHUNK],
    len: usize,
    pos: usize,
    color: PhantomData<fn() -> C>,
}

impl<C: From<Rgb888>, const T: usize, const N: usize> Iterator for RectColors<'_, '_, '_, C, T, N> {
    type Item = C;

    fn next(&mut self) -> Option<C> {
        if self.pos == self.len {
            if self.y >= self.area.size.height {
                return None;
            }
            let w = self.area.size.width;
            let n = (w - self.x).min(RUN_CHUNK as u32);
            let px = self.area.top_left.x.saturating_add(self.x as i32);
            let py = self.area.top_left.y.saturating_add(self.y as i32);
            let buf = &mut self.buf;
            let mut i = 0;
            self.ev.shade(px, py, n as u16, |c| {
                if let Some(b) = buf.get_mut(i) {
                    *b = c;
                }
                i += 1;
            });
            self.len = n as usize;
            self.pos = 0;
            self.x += n;
            if self.x >= w {
                self.x = 0;
                self.y += 1;
            }
        }
        let c = self.buf.get(self.pos).copied().unwrap_or(Rgba8888::BLACK);
        self.pos += 1;
        Some(display_color(c))
    }
}

impl<'t, C, const T: usize, const N: usize, const W: usize>
    StyledDrawable<TextureStyle<'t, C, T, N, W>> for Rectangle
where
    C: PixelColor + From<Rgb888>,
{
    type Color = C;
    type Output = ();

    /// One `fill_contiguous` call for the visible part of the rectangle (with the widths from
    /// differences, one a row run piece).
    fn draw_styled<D>(
        &self,
        style: &TextureStyle<'t, C, T, N, W>,
        target: &mut D,
    ) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let area = self.intersection(&target.bounding_box());
        if area.size.width == 0 || area.size.height == 0 {
            return Ok(());
        }
        // With the widths from differences, each visible row is one run (as a shape's runs).
        #[cfg(feature = "differences")]
        if W > 0 {
            let mut ev = AreaShader::<T, N, W>::new(style.texture, &style.mapping, &area);
            let (x, w) = (area.top_left.x, area.size.width);
            for dy in 0..area.size.height {
                let y = area.top_left.y.saturating_add(dy as i32);
                fill_run(&mut ev, (x, y, w), target)?;
            }
            return Ok(());
        }
        let mut ev = AreaShader::<T, N, 0>::new(style.texture, &style.mapping, &area);
        let colors = RectColors {
            ev: &mut ev,
            area,
            x: 0,
            y: 0,
            buf: [Rgba8888::BLACK; RUN_CHUNK],
            len: 0,
            pos: 0,
            color: PhantomData::<fn() -> C>,
        };
        target.fill_contiguous(&area, colors)
    }
}

/// `StyledDrawable<TextureStyle>` for shapes filled through their points.
macro_rules! textured_by_points {
    ($($shape:ty),*) => {$(
        impl<'t, C, const T: usize, const N: usize, const W: usize>
            StyledDrawable<TextureStyle<'t, C, T, N, W>> for $shape
        where
            C: PixelColor + From<Rgb888>,
        {
            type Color = C;
            type Output = ();

            fn draw_styled<D>(
                &self,
                style: &TextureStyle<'t, C, T, N, W>,
                target: &mut D,
            ) -> Result<(), D::Error>
            where
                D: DrawTarget<Color = C>,
            {
                fill_points(self.points(), self.bounding_box(), style, target)
            }
        }
    )*};
}

// Not `Sector`: its `points()` differ from its `PrimitiveStyle` fill by a few edge pixels in
// embedded-graphics 0.8, so a textured sector would not cover the filled one exactly.
textured_by_points!(Circle, Ellipse, Triangle, RoundedRectangle);
