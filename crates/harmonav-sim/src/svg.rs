//! A small SVG canvas for the figures (paths, discs, labels in world coordinates).
//!
//! Hand-written rather than a plotting crate: the figures need only polylines, circles and
//! text, and no font handling.

use std::fmt::Write as _;

use nalgebra::Vector2;

/// Polyline vertices closer than this many pixels to the previous one are not written.
pub const MIN_SEGMENT_PX: f64 = 0.5;

/// A rectangular panel mapping a world window onto pixels (y up in the world, down on screen).
#[derive(Clone, Copy, Debug)]
pub struct Panel {
    /// Left pixel of the panel.
    pub left: f64,
    /// Top pixel of the panel.
    pub top: f64,
    /// Panel width and height in pixels.
    pub size: (f64, f64),
    /// World window: lower-left corner and upper-right corner.
    pub window: (Vector2<f64>, Vector2<f64>),
}

impl Panel {
    /// Pixel coordinates of a world point.
    pub fn px(&self, p: Vector2<f64>) -> (f64, f64) {
        let (lo, hi) = self.window;
        let sx = self.size.0 / (hi.x - lo.x);
        let sy = self.size.1 / (hi.y - lo.y);
        (self.left + (p.x - lo.x) * sx, self.top + (hi.y - p.y) * sy)
    }

    /// Whether a world point lies in the window.
    pub fn inside(&self, p: Vector2<f64>) -> bool {
        let (lo, hi) = self.window;
        p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y
    }

    /// Pixels per world unit (horizontal).
    pub fn scale(&self) -> f64 {
        self.size.0 / (self.window.1.x - self.window.0.x)
    }
}

/// An SVG document being written.
#[derive(Clone, Debug)]
pub struct Canvas {
    body: String,
    width: f64,
    height: f64,
}

impl Canvas {
    /// An empty white canvas.
    pub fn new(width: f64, height: f64) -> Self {
        Self {
            body: String::new(),
            width,
            height,
        }
    }

    /// A polyline through world points, broken at `None` and outside the panel window;
    /// `style` holds SVG attributes. Vertices closer than [`MIN_SEGMENT_PX`] to the last one
    /// written are dropped (the last vertex of each piece is always kept), so a run of 10⁴
    /// samples stays a few kilobytes.
    pub fn path(
        &mut self,
        panel: &Panel,
        points: impl IntoIterator<Item = Option<Vector2<f64>>>,
        style: &str,
    ) {
        let mut d = String::new();
        // The last vertex written, and one held back because it was too close to it.
        let mut last: Option<(f64, f64)> = None;
        let mut held: Option<(f64, f64)> = None;
        let flush = |d: &mut String, held: &mut Option<(f64, f64)>| {
            if let Some((x, y)) = held.take() {
                let _ = write!(d, "L{x:.2},{y:.2} ");
            }
        };
        for p in points {
            match p.filter(|p| panel.inside(*p)) {
                Some(p) => {
                    let (x, y) = panel.px(p);
                    match last {
                        Some((lx, ly)) if (x - lx).hypot(y - ly) < MIN_SEGMENT_PX => {
                            held = Some((x, y));
                        }
                        _ => {
                            held = None;
                            let pen = if last.is_some() { "L" } else { "M" };
                            let _ = write!(d, "{pen}{x:.2},{y:.2} ");
                            last = Some((x, y));
                        }
                    }
                }
                None => {
                    flush(&mut d, &mut held);
                    last = None;
                }
            }
        }
        flush(&mut d, &mut held);
        if !d.is_empty() {
            let _ = writeln!(self.body, r#"<path d="{}" {style}/>"#, d.trim_end());
        }
    }

    /// A closed polygon through world points.
    pub fn polygon(
        &mut self,
        panel: &Panel,
        points: impl IntoIterator<Item = Vector2<f64>>,
        style: &str,
    ) {
        let pts: Vec<String> = points
            .into_iter()
            .map(|p| {
                let (x, y) = panel.px(p);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        let _ = writeln!(
            self.body,
            r#"<polygon points="{}" {style}/>"#,
            pts.join(" ")
        );
    }

    /// A disc of `radius` pixels at a world point.
    pub fn dot(&mut self, panel: &Panel, p: Vector2<f64>, radius: f64, fill: &str) {
        let (x, y) = panel.px(p);
        let _ = writeln!(
            self.body,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="{radius}" fill="{fill}"/>"#
        );
    }

    /// Text at a world point, offset by `(dx, dy)` pixels.
    pub fn label(&mut self, panel: &Panel, p: Vector2<f64>, (dx, dy): (f64, f64), text: &str) {
        let (x, y) = panel.px(p);
        self.text(x + dx, y + dy, text, "");
    }

    /// Text at pixel coordinates.
    pub fn text(&mut self, x: f64, y: f64, text: &str, style: &str) {
        let escaped = text
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        let _ = writeln!(
            self.body,
            r#"<text x="{x:.1}" y="{y:.1}" {style}>{escaped}</text>"#
        );
    }

    /// A raw element.
    pub fn raw(&mut self, element: &str) {
        self.body.push_str(element);
        self.body.push('\n');
    }

    /// The finished document.
    pub fn finish(self) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_panel() -> Panel {
        Panel {
            left: 0.0,
            top: 0.0,
            size: (100.0, 100.0),
            window: (Vector2::new(0.0, 0.0), Vector2::new(100.0, 100.0)),
        }
    }

    fn vertices(svg: &str) -> Vec<(f64, f64)> {
        let d = svg.split("d=\"").nth(1).unwrap().split('"').next().unwrap();
        d.split_whitespace()
            .map(|v| {
                let (x, y) = v[1..].split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect()
    }

    #[test]
    fn dense_paths_are_thinned_but_keep_their_ends() {
        let mut c = Canvas::new(100.0, 100.0);
        // 1001 points 0.01 px apart along y = 50 (10 px long).
        let pts = (0..=1000).map(|i| Some(Vector2::new(10.0 + 0.01 * i as f64, 50.0)));
        c.path(&unit_panel(), pts, "");
        let v = vertices(&c.finish());
        assert_eq!(v.first(), Some(&(10.0, 50.0)));
        assert_eq!(v.last(), Some(&(20.0, 50.0)));
        assert!((20..=22).contains(&v.len()), "{} vertices", v.len());
        // Every kept segment but the last is just over the threshold: no more is dropped
        // than needed (the points are 0.01 px apart; the output is rounded to 0.01 px).
        for w in v[..v.len() - 1].windows(2) {
            let step = w[1].0 - w[0].0;
            assert!(
                (MIN_SEGMENT_PX - 0.011..=MIN_SEGMENT_PX + 0.011).contains(&step),
                "{step}"
            );
        }
    }

    #[test]
    fn a_gap_starts_a_new_piece() {
        let mut c = Canvas::new(100.0, 100.0);
        let pts = [
            Some(Vector2::new(1.0, 1.0)),
            Some(Vector2::new(5.0, 1.0)),
            None,
            Some(Vector2::new(9.0, 1.0)),
            Some(Vector2::new(9.1, 1.0)),
        ];
        c.path(&unit_panel(), pts, "");
        let svg = c.finish();
        assert!(
            svg.contains("M1.00,99.00 L5.00,99.00 M9.00,99.00 L9.10,99.00"),
            "{svg}"
        );
    }
}
