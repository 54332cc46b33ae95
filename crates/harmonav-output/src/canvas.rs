//! SVG drawn at a multiple of its nominal size: plotters' SVG backend rounds every coordinate
//! to a whole pixel, which stair-steps a path or a level line drawn at the figure's own size.
//! A figure drawn at [`Scale::FINE`] (4 backend pixels per nominal pixel, every length, font
//! size and stroke width scaled alike) keeps its `viewBox` at the large size while its
//! `width` and `height` say the nominal one, so a viewer shows the same figure with
//! coordinates to a quarter of a pixel.

use plotters::coord::Shift;
use plotters::prelude::*;

/// The figures' font family.
pub(crate) const FONT: &str = "sans-serif";

/// A plotters error as text.
pub fn err(e: impl std::fmt::Debug) -> String {
    format!("drawing a figure: {e:?}")
}

/// Backend pixels per nominal pixel of a figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Scale(pub u32);

impl Scale {
    /// One backend pixel per nominal pixel: plotters' own drawing.
    pub const ONE: Self = Self(1);
    /// Four backend pixels per nominal pixel: the plane figures' drawing.
    pub const FINE: Self = Self(4);

    /// `v` nominal pixels in backend pixels.
    pub fn px(self, v: i32) -> i32 {
        v * self.0 as i32
    }

    /// `v` nominal pixels (a size) in backend pixels.
    pub fn size(self, v: u32) -> u32 {
        v * self.0
    }

    /// A stroke of `color`, `width` nominal pixels wide.
    pub fn stroke<C: Color>(self, color: C, width: u32) -> ShapeStyle {
        color.stroke_width(self.size(width))
    }

    /// The figures' sans-serif font at `size` nominal pixels.
    pub fn font(self, size: u32) -> FontDesc<'static> {
        (FONT, f64::from(self.size(size))).into_font()
    }
}

/// The SVG drawn by `draw` on a white area of `size` nominal pixels at `scale`: the backend
/// is `scale` times larger, and the document's `width` and `height` are set back to `size`
/// (its `viewBox` keeps the backend's size), so it shows at `size`.
///
/// # Errors
/// `draw`'s error, or plotters' as text.
pub fn scaled_svg(
    size: (u32, u32),
    scale: Scale,
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<String, String> {
    let big = (scale.size(size.0), scale.size(size.1));
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, big).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        draw(&root)?;
        root.present().map_err(err)?;
    }
    Ok(nominal_size(&out, big, size))
}

/// `svg` with its root's `width="W" height="H"` (the backend's `big`) set to `size`.
fn nominal_size(svg: &str, big: (u32, u32), size: (u32, u32)) -> String {
    let from = format!("<svg width=\"{}\" height=\"{}\"", big.0, big.1);
    let to = format!("<svg width=\"{}\" height=\"{}\"", size.0, size.1);
    svg.replacen(&from, &to, 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scaled_figure_shows_at_its_nominal_size_with_the_large_view_box() {
        let svg = scaled_svg((100, 50), Scale::FINE, |area| {
            area.draw(&Circle::new((200, 100), 20, BLACK.filled()))
                .map_err(err)
        })
        .unwrap();
        assert!(
            svg.contains(r#"<svg width="100" height="50" viewBox="0 0 400 200""#),
            "{svg}"
        );
    }
}
