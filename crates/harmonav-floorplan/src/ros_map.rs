//! ROS map_server occupancy grids (a YAML file and its PGM or PNG image) to floor plans
//! (issue 25, part 3; docs/maths.md §13.1).
//!
//! ```text
//! YAML + image ─→ cells (map_server's p, thresholds; unknown = occupied)
//!   ─→ occupied specks ≤ speck_pixels removed ─→ the goal's 4-connected free component
//!   ─→ marching squares (contour) ─→ Visvalingam–Whyatt, topology-preserving (geo)
//!   ─→ opening by the robot's disc ρ = max(radius + margin, δ) (geo Buffer ∩ the outline)
//!   ─→ FloorMap::new (shrink by radius + margin − δ, H, W_δ)
//! ```
//!
//! **Conventions (map_server's, followed exactly).** `image` is relative to the YAML file's
//! folder (or absolute). Row 0 is the top of the image. `origin = [x, y, yaw]` is the pose of
//! the lower-left corner of the lower-left pixel: pixel (column `c`, row `r`) covers, in the
//! map frame, `[c·res, (c+1)·res] × [(H−1−r)·res, (H−r)·res]`, and a map-frame point `l` is the
//! world point `o + R(yaw)·l` (yaw counter-clockwise; supported, not refused: a rotation is
//! exact and map_server documents its meaning). `p = (255 − x)/255`, or `x/255` with `negate`,
//! `x` the mean of the colour channels; `p > occupied_thresh` occupied, `p < free_thresh`
//! free, else unknown, and **unknown counts as occupied** (see [`Cell`] for `scale` and `raw`).

mod bridge;
mod error;
pub(crate) mod grid;
mod outline;
mod pixels;
mod yaml;

use std::io::Cursor;
use std::path::{Path, PathBuf};

use geo::{Coord, Point};
use image::{ImageReader, Limits};
use nalgebra::{Matrix2, Vector2};

pub use error::{MapError, MapPoint, MapProblem};
pub use pixels::OccupiedPixels;
pub use yaml::RESOLUTION_RANGE;

use crate::{FloorMap, FloorOptions};

/// The largest image side accepted (pixels): 4096 px is 205 m at 0.05 m/pixel; the grid and
/// its labels take about 13 bytes per pixel (≈ 220 MB at the cap).
pub const MAX_SIDE: u32 = 4096;

/// The most islands (holes of the goal's free component, after the specks) a map's outline may
/// have before it is simplified and opened: four times the floor plan's cap
/// ([`harmonav_harmonic::domain::MAX_HOLES`]). The robot's opening only merges holes (two closer than
/// its diameter, or one that close to the outer ring), so a map far above the cap cannot load,
/// and the simplification's validity check grows with the square of the holes (1 849 holes:
/// 1.3 s; 25 600: 140 s, issue 56, D3).
pub const MAX_TRACED_HOLES: usize = 4 * harmonav_harmonic::domain::MAX_HOLES;

/// map_server's `mode` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapMode {
    /// Three classes by the thresholds (the default).
    Trinary,
    /// Graded occupancy between the thresholds; transparent pixels unknown.
    Scale,
    /// The pixel value is the occupancy itself (0–100; above: unknown).
    Raw,
}

impl MapMode {
    /// `"trinary"`, `"scale"` or `"raw"`, as in the YAML file.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Trinary => "trinary",
            Self::Scale => "scale",
            Self::Raw => "raw",
        }
    }
}

/// One pixel's class. With `x` the mean of its colour channels and
/// `p = (255 − x)/255` (`x/255` with `negate`):
///
/// - `trinary`: `p > occupied_thresh` → `Occupied`, `p < free_thresh` → `Free`, else
///   `Unknown`;
/// - `scale`: a pixel with alpha below 255 → `Unknown`; otherwise as trinary, except that
///   between the thresholds (map_server's graded occupancy 1–99) → `Occupied`;
/// - `raw`: `x` is the occupancy: 0 → `Free`, 1–100 → `Occupied`, above → `Unknown`
///   (`negate` does not apply).
///
/// Ties are not free (`p = free_thresh`). Only `Free` is free space: `Unknown` counts as
/// occupied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cell {
    /// Free space.
    Free,
    /// A wall or obstacle.
    Occupied,
    /// Not observed; treated as occupied.
    Unknown,
}

impl Cell {
    /// `"free"`, `"occupied"` or `"unknown"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Free => "free",
            Self::Occupied => "occupied",
            Self::Unknown => "unknown",
        }
    }
}

/// The default [`MapOptions::speck_pixels`]: 0, every occupied island is kept. Until 2026-12-06
/// the default was 2 (islands of one or two pixels taken for SLAM noise and dropped), and on
/// real maps they were posts: runs from seeded starts of `depot`, `warehouse`, `fetch-office`,
/// `willow-2010` and `willow-full` touched them (down to −10 mm from a non-free pixel) while the
/// navigator, which never knew them, reported every guarantee of its polygon.
pub const DEFAULT_SPECK_PIXELS: usize = 0;

/// The speck size [`MapOptions::speck_pixels`] always accepts, whatever the robot: islands of
/// one or two pixels (0.005 m² at 0.05 m/pixel), the salt noise of a SLAM map, when the user
/// knows their map has it.
pub const NOISE_SPECK_PIXELS: usize = 2;

/// The largest speck size [`MapOptions::speck_pixels`] accepts for a robot of clearance
/// `clearance = radius + margin` on a map of `resolution` m/pixel: an island larger than the
/// robot's clearance disc `π·clearance²` is an obstacle, not noise, and is never a speck;
/// islands of up to [`NOISE_SPECK_PIXELS`] always may be (a run is judged against the
/// map's own pixels all the same, [`OccupiedPixels`]).
///
/// ```text
/// max_speck = max(NOISE_SPECK_PIXELS, ⌊π·clearance² / resolution²⌋)
/// ```
#[must_use]
pub fn max_speck_pixels(clearance: f64, resolution: f64) -> usize {
    let disc = std::f64::consts::PI * clearance * clearance / (resolution * resolution);
    // NaN or a negative area gives the default; ∞ saturates.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let pixels = if disc.is_nan() {
        0
    } else {
        disc.floor() as usize
    };
    pixels.max(NOISE_SPECK_PIXELS)
}

/// The occupied islands a map's pipeline drops as specks ([`RosMap::specks`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Specks {
    /// How many islands are dropped.
    pub count: usize,
    /// Their pixels, all together.
    pub pixels: usize,
    /// The largest one's pixels (0 with none).
    pub largest: usize,
    /// The world point of the centre of the largest one's first pixel (row-major; `None` with
    /// none).
    pub largest_at: Option<[f64; 2]>,
}

/// The simplification's tolerance, in square pixels ([`MapOptions::simplify`]).
pub const DEFAULT_SIMPLIFY: f64 = 0.5;

/// How far the first simplification (of the traced pixel outline) may move a wall, pixels:
/// its tolerance is halved until no vertex of the traced rings lies farther than this from the
/// simplified ones. At the default tolerance a pixel staircase loses vertices up to `√2.5 ≈
/// 1.58` px off the new edges (measured on the public maps: 0.45–1.58), which this keeps; a
/// tolerance as large as the map, which removed whole walls, is lowered.
pub const TRACED_MOVE_PIXELS: f64 = 2.0;

/// How far the second simplification (of the outline opened by the robot's disc) may move a
/// wall, pixels, likewise: the opened rings are smooth, and a vertex off by more than a pixel
/// is a speck's short ring (1.28 px on `fetch-office`) or a tolerance too large.
pub const OPENED_MOVE_PIXELS: f64 = 1.0;

/// Two rings of the opened free space closer than this many times the shrink of
/// [`FloorMap::new`] (`s = radius + margin − δ`) are joined before it: each shrunk ring moves by
/// up to `s/cos(π/16)` (its circumscribed arcs), so `2.04 s` would touch; the rest is room.
/// The outline's walls within `ρ` (the opening's radius) of such a gap are joined by their
/// convex hull, and the outline opened again.
pub const JOIN_GAP: f64 = 2.5;

/// Options of [`RosMap::to_floor_map`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    /// The floor plan's elements and the robot's clearance (`radius + margin`).
    pub floor: FloorOptions,
    /// Occupied islands (8-connected non-free pixels not touching the image's edge) of at most
    /// this many pixels become free: SLAM's salt noise. `0`, the default, keeps every island.
    /// An island dropped is an obstacle the floor plan does not see: set this only below the
    /// smallest real obstacle (a post is often one or two pixels). At most
    /// [`max_speck_pixels`] (the robot's clearance disc; above, [`MapProblem::SpeckTooLarge`]);
    /// [`RosMap::specks`] lists what goes, and a run is judged against the map's own pixels
    /// ([`OccupiedPixels`]). Free islands not 4-connected to the goal's pixel are all dropped
    /// (unreachable).
    pub speck_pixels: usize,
    /// The Visvalingam–Whyatt tolerance in square pixels: a vertex goes while the triangle it
    /// makes with its neighbours is smaller than `simplify · res²`. Each removal changes the
    /// area by less than that (docs/maths.md §13.1 bounds the total). `0` keeps every vertex.
    /// An upper bound: where it would move the walls farther than [`TRACED_MOVE_PIXELS`] (the
    /// traced outline) or [`OPENED_MOVE_PIXELS`] (the opened one), or leave an invalid polygon,
    /// it is halved until they stay that close.
    pub simplify: f64,
}

impl MapOptions {
    /// The floor options with the default speck size ([`DEFAULT_SPECK_PIXELS`]) and
    /// simplification ([`DEFAULT_SIMPLIFY`]).
    #[must_use]
    pub fn new(floor: FloorOptions) -> Self {
        Self {
            floor,
            speck_pixels: DEFAULT_SPECK_PIXELS,
            simplify: DEFAULT_SIMPLIFY,
        }
    }
}

/// The free space of a map as a polygon with holes, in world coordinates: the rings as
/// [`FloorMap::new`] takes them (outer counter-clockwise, holes clockwise, no repeated closing
/// vertex).
#[derive(Clone, Debug, PartialEq)]
pub struct MapOutline {
    /// The outer ring (counter-clockwise).
    pub outer: Vec<Vector2<f64>>,
    /// The holes (clockwise).
    pub holes: Vec<Vec<Vector2<f64>>>,
    /// Free pixels in the goal's component, after the specks.
    pub free_pixels: usize,
    /// The enclosed area, holes subtracted (m²).
    pub area: f64,
}

/// A ROS map_server map: its YAML keys and its pixels' classes ([`RosMap::load`]).
#[derive(Clone, Debug)]
pub struct RosMap {
    yaml_path: PathBuf,
    image_path: PathBuf,
    resolution: f64,
    origin: [f64; 3],
    negate: bool,
    occupied_thresh: f64,
    free_thresh: f64,
    mode: MapMode,
    width: usize,
    height: usize,
    cells: Vec<Cell>,
}

/// The largest image file read (bytes): a [`MAX_SIDE`]² image in the most verbose encoding
/// accepted, ASCII PNM of three 16-bit channels (`"65535 "`, 6 bytes a sample), and 1 MiB of
/// header and comments; any PNG or binary PGM of that size is smaller.
pub const MAX_IMAGE_BYTES: u64 = (MAX_SIDE as u64) * (MAX_SIDE as u64) * 3 * 6 + (1 << 20);

/// The file at `path`, read through a cap of `cap` bytes (issue 56, D4: `image: /dev/zero` or a
/// sparse 3 GiB YAML was read whole before any size check). Only a regular file is opened: a
/// FIFO would block in `open` and a device never ends (D14).
fn read(path: &Path, cap: u64, what: &str) -> Result<Vec<u8>, MapError> {
    use std::io::Read;
    let error = |p| MapError::new(path, p);
    let read_error = |e: std::io::Error| error(MapProblem::Read(e.to_string()));
    let meta = std::fs::metadata(path).map_err(read_error)?;
    if !meta.is_file() {
        return Err(error(MapProblem::Read(
            "not a regular file (a folder, a FIFO or a device)".into(),
        )));
    }
    if meta.len() > cap {
        return Err(error(MapProblem::TooLarge {
            what: what.to_owned(),
            bytes: meta.len(),
            cap,
        }));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .map_err(read_error)?
        .take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    // The file may have grown since its metadata was read.
    if bytes.len() as u64 > cap {
        return Err(error(MapProblem::TooLarge {
            what: what.to_owned(),
            bytes: bytes.len() as u64,
            cap,
        }));
    }
    Ok(bytes)
}

impl RosMap {
    /// Reads the YAML file at `yaml_path` and the image it names (relative to the YAML file's
    /// folder unless absolute; PGM or PNG, told by its content), and classifies every pixel
    /// ([`Cell`]).
    ///
    /// # Errors
    /// A [`MapError`] naming the file: [`MapProblem::Read`] (missing file), [`MapProblem::Yaml`],
    /// [`MapProblem::MissingField`], [`MapProblem::InvalidField`], [`MapProblem::Resolution`],
    /// [`MapProblem::Threshold`], [`MapProblem::ThresholdOrder`] for the YAML file;
    /// [`MapProblem::Read`], [`MapProblem::Image`] (truncated or not an image) and
    /// [`MapProblem::ImageSize`] for the image.
    pub fn load(yaml_path: impl AsRef<Path>) -> Result<Self, MapError> {
        let yaml_path = yaml_path.as_ref();
        let bytes = read(yaml_path, yaml::MAX_YAML_BYTES as u64, "a map's YAML file")?;
        let text = String::from_utf8(bytes)
            .map_err(|_| MapError::new(yaml_path, MapProblem::Yaml("not UTF-8 text".into())))?;
        let keys = yaml::parse(&text).map_err(|p| MapError::new(yaml_path, p))?;
        let image_path = yaml_path
            .parent()
            .unwrap_or(Path::new(""))
            .join(&keys.image);
        let bytes = read(&image_path, MAX_IMAGE_BYTES, "a map's image")?;
        let image_error = |p| MapError::new(&image_path, p);
        let mut reader = ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| image_error(MapProblem::Image(e.to_string())))?;
        let mut limits = Limits::default();
        limits.max_image_width = Some(MAX_SIDE);
        limits.max_image_height = Some(MAX_SIDE);
        reader.limits(limits);
        let img = reader
            .decode()
            .map_err(|e| image_error(MapProblem::Image(e.to_string())))?;
        let (w, h) = (img.width(), img.height());
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
            return Err(image_error(MapProblem::ImageSize {
                width: w,
                height: h,
            }));
        }
        let cells = grid::cells(
            &img,
            keys.negate,
            keys.occupied_thresh,
            keys.free_thresh,
            keys.mode,
        );
        Ok(Self {
            yaml_path: yaml_path.to_path_buf(),
            image_path,
            resolution: keys.resolution,
            origin: keys.origin,
            negate: keys.negate,
            occupied_thresh: keys.occupied_thresh,
            free_thresh: keys.free_thresh,
            mode: keys.mode,
            width: w as usize,
            height: h as usize,
            cells,
        })
    }

    /// The YAML file's path, as given to [`RosMap::load`].
    #[must_use]
    pub fn yaml_path(&self) -> &Path {
        &self.yaml_path
    }

    /// The image file's path (the YAML's `image`, joined to the YAML file's folder).
    #[must_use]
    pub fn image_path(&self) -> &Path {
        &self.image_path
    }

    /// `resolution` (m/pixel).
    #[must_use]
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// `origin = [x, y, yaw]`: the pose of the lower-left corner of the image (m, m, rad).
    #[must_use]
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// `negate`.
    #[must_use]
    pub fn negate(&self) -> bool {
        self.negate
    }

    /// `(free_thresh, occupied_thresh)`.
    #[must_use]
    pub fn thresholds(&self) -> (f64, f64) {
        (self.free_thresh, self.occupied_thresh)
    }

    /// `mode`.
    #[must_use]
    pub fn mode(&self) -> MapMode {
        self.mode
    }

    /// `(width, height)` in pixels.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The class of pixel (`column`, `row`), row 0 at the top; `None` outside the image.
    #[must_use]
    pub fn cell(&self, column: usize, row: usize) -> Option<Cell> {
        (column < self.width && row < self.height).then(|| self.cells[row * self.width + column])
    }

    /// How many pixels are free (before specks and components).
    #[must_use]
    pub fn free_count(&self) -> usize {
        self.cells.iter().filter(|&&c| c == Cell::Free).count()
    }

    fn rotation(&self) -> Matrix2<f64> {
        let (s, c) = self.origin[2].sin_cos();
        Matrix2::new(c, -s, s, c)
    }

    /// The world point of a map-frame point `l` (metres from the image's lower-left corner):
    /// `o + R(yaw)·l`.
    #[must_use]
    pub fn to_world(&self, l: Vector2<f64>) -> Vector2<f64> {
        Vector2::new(self.origin[0], self.origin[1]) + self.rotation() * l
    }

    /// The map-frame point of a world point `w`: `R(−yaw)·(w − o)`.
    #[must_use]
    pub fn to_map_frame(&self, w: Vector2<f64>) -> Vector2<f64> {
        self.rotation().transpose() * (w - Vector2::new(self.origin[0], self.origin[1]))
    }

    /// The pixel (column, row; row 0 at the top) holding the world point `w`, `None` outside
    /// the image (a point on the image's right or top edge is outside; a non-finite point too).
    #[must_use]
    pub fn pixel_at(&self, w: Vector2<f64>) -> Option<[usize; 2]> {
        let l = self.to_map_frame(w) / self.resolution;
        let (cx, cy) = (l.x.floor(), l.y.floor());
        #[allow(clippy::cast_precision_loss)] // sides ≤ MAX_SIDE
        let (wf, hf) = (self.width as f64, self.height as f64);
        if !(cx >= 0.0 && cy >= 0.0 && cx < wf && cy < hf) {
            return None;
        }
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // in [0, side)
        let (c, yrow) = (cx as usize, cy as usize);
        Some([c, self.height - 1 - yrow])
    }

    fn error(&self, problem: MapProblem) -> MapError {
        MapError::new(&self.yaml_path, problem)
    }

    /// The free pixel holding `x`, or why not.
    fn free_pixel(&self, point: MapPoint, x: Vector2<f64>) -> Result<usize, MapError> {
        if !(x.x.is_finite() && x.y.is_finite()) {
            return Err(self.error(MapProblem::NonFinitePoint(point)));
        }
        let at = [x.x, x.y];
        let pixel = self
            .pixel_at(x)
            .ok_or_else(|| self.error(MapProblem::OutsideImage { point, at }))?;
        let i = pixel[1] * self.width + pixel[0];
        match self.cells[i] {
            Cell::Free => Ok(i),
            cell => Err(self.error(MapProblem::NotFree {
                point,
                at,
                cell,
                pixel,
            })),
        }
    }

    /// The world point of the centre of pixel `i` (row-major, row 0 at the top).
    fn pixel_centre(&self, i: usize) -> Vector2<f64> {
        let (c, r) = (i % self.width, i / self.width);
        #[allow(clippy::cast_precision_loss)] // sides ≤ MAX_SIDE
        let l = Vector2::new(c as f64 + 0.5, (self.height - r) as f64 - 0.5) * self.resolution;
        self.to_world(l)
    }

    /// The occupied islands of at most `speck_pixels` pixels that the pipeline drops as
    /// sensor noise ([`MapOptions::speck_pixels`]): what `harmonav check` lists, so that a user
    /// sees what the floor plan no longer holds.
    #[must_use]
    pub fn specks(&self, speck_pixels: usize) -> Specks {
        let all = grid::specks(&self.cells, self.width, self.height, speck_pixels);
        Specks {
            count: all.len(),
            pixels: all.iter().map(|s| s.0).sum(),
            largest: all.first().map_or(0, |s| s.0),
            largest_at: all.first().map(|s| {
                let p = self.pixel_centre(s.1);
                [p.x, p.y]
            }),
        }
    }

    /// The map's own non-free pixels (occupied and unknown, and everything outside the
    /// image), whatever the pipeline does to them: a run on this map is judged against these
    /// ([`OccupiedPixels::signed_distance`]).
    #[must_use]
    pub fn occupied_pixels(&self) -> OccupiedPixels {
        OccupiedPixels::new(self)
    }

    /// The goal's free component, the start checked against it: `(mask, pixels)`.
    fn component(
        &self,
        start: Vector2<f64>,
        goal: Vector2<f64>,
        options: &MapOptions,
    ) -> Result<(Vec<bool>, usize), MapError> {
        let most = max_speck_pixels(options.floor.clearance, self.resolution);
        if options.speck_pixels > most {
            return Err(self.error(MapProblem::SpeckTooLarge {
                speck_pixels: options.speck_pixels,
                most,
                clearance: options.floor.clearance,
                resolution: self.resolution,
            }));
        }
        let g = self.free_pixel(MapPoint::Goal, goal)?;
        let s = self.free_pixel(MapPoint::Start, start)?;
        let (mask, label) = grid::goal_component(
            &self.cells,
            self.width,
            self.height,
            options.speck_pixels,
            g,
        );
        if label[s] != label[g] {
            return Err(self.error(MapProblem::Unreachable));
        }
        let n = mask.iter().filter(|&&f| f).count();
        Ok((mask, n))
    }

    fn to_outline(&self, poly: &geo::Polygon<f64>, free_pixels: usize) -> MapOutline {
        let (outer, holes) = outline::rings(poly);
        let world = |r: Vec<Coord<f64>>| -> Vec<Vector2<f64>> {
            r.into_iter()
                .map(|c| self.to_world(Vector2::new(c.x, c.y)))
                .collect()
        };
        MapOutline {
            outer: world(outer),
            holes: holes.into_iter().map(world).collect(),
            free_pixels,
            area: outline::area(poly),
        }
    }

    /// The goal component's outline in the map frame, simplified.
    fn traced(
        &self,
        start: Vector2<f64>,
        goal: Vector2<f64>,
        options: &MapOptions,
    ) -> Result<(geo::Polygon<f64>, usize), MapError> {
        // The tolerance of Visvalingam–Whyatt, square pixels: 0 keeps every vertex; NaN or ∞
        // would drop vertices without bound.
        let t = options.simplify;
        if !(t.is_finite() && t >= 0.0) {
            return Err(
                self.error(MapProblem::Floor(crate::FloorError::InvalidOption {
                    field: "simplify",
                    value: t,
                })),
            );
        }
        let (mask, n) = self.component(start, goal, options)?;
        let res = self.resolution;
        let mp = outline::trace(&mask, self.width, self.height, res)
            .map_err(|e| self.error(MapProblem::Outline(e)))?;
        // Select by the goal pixel's centre: the goal itself may sit in a corner that
        // marching squares cut off.
        let g = self.pixel_at(goal).unwrap_or([0, 0]);
        #[allow(clippy::cast_precision_loss)] // sides ≤ MAX_SIDE
        let centre = Point::new(
            (g[0] as f64 + 0.5) * res,
            (self.height - g[1]) as f64 * res - 0.5 * res,
        );
        let poly = outline::containing(mp, centre).ok_or_else(|| {
            self.error(MapProblem::Outline(
                "no ring of marching squares holds the goal's pixel".into(),
            ))
        })?;
        // The simplification's validity check (geo's) compares every pair of rings: 1 849
        // holes took 1.3 s, 25 600 took 140 s (issue 56, D3). The opening only merges holes, so
        // a map far above the floor plan's hole cap is refused here, before that cost.
        let islands = poly.interiors().len();
        if islands > MAX_TRACED_HOLES {
            return Err(self.error(MapProblem::TooManyIslands {
                islands,
                most: MAX_TRACED_HOLES,
            }));
        }
        // At most `TRACED_MOVE_PIXELS` from the traced walls: the default never comes near it,
        // a tolerance as large as the map (which removed whole walls) is lowered.
        let eps = options.simplify.max(0.0) * res * res;
        Ok((outline::simplify(&poly, eps, TRACED_MOVE_PIXELS * res), n))
    }

    /// The outline of the free pixels 4-connected to the goal's (after the specks), by marching
    /// squares and simplified, without the robot: its area is the free pixels' count × res²
    /// to within the bound of docs/maths.md §13.1.
    ///
    /// # Errors
    /// [`MapProblem::NonFinitePoint`], [`MapProblem::OutsideImage`], [`MapProblem::NotFree`]
    /// for the start or goal, [`MapProblem::Unreachable`], [`MapProblem::Outline`].
    pub fn outline(
        &self,
        start: Vector2<f64>,
        goal: Vector2<f64>,
        options: &MapOptions,
    ) -> Result<MapOutline, MapError> {
        let (poly, n) = self.traced(start, goal, options)?;
        Ok(self.to_outline(&poly, n))
    }

    /// The radius of the robot-disc opening: `ρ = max(radius + margin, δ)`, `δ` =
    /// `max_element` (the certified region `W_δ` is the free space eroded by `ρ`, §13).
    #[must_use]
    pub fn opening_radius(options: &MapOptions) -> f64 {
        options.floor.clearance.max(options.floor.max_element)
    }

    /// The free space the floor plan is built on: [`RosMap::outline`] opened by the robot's
    /// disc of radius `ρ` ([`RosMap::opening_radius`]), `(C ⊕ ρ) ∩ outline` with `C` the goal's
    /// component of `outline ⊖ ρ` (geo `Buffer`), and simplified again. Walls only grow; the
    /// parts no robot of that clearance reaches (dead-end slits, gaps beside pillars) are
    /// walls, and holes it cannot pass around join the outer ring.
    ///
    /// # Errors
    /// Those of [`RosMap::outline`], and [`MapProblem::TooNarrow`] when the goal is closer
    /// than `ρ` to a wall or the start is not in the goal's component of `outline ⊖ ρ`.
    pub fn free_space(
        &self,
        start: Vector2<f64>,
        goal: Vector2<f64>,
        options: &MapOptions,
    ) -> Result<MapOutline, MapError> {
        let (mut poly, n) = self.traced(start, goal, options)?;
        let rho = Self::opening_radius(options);
        if !(rho.is_finite() && rho > 0.0) {
            return Err(
                self.error(MapProblem::Floor(crate::FloorError::InvalidOption {
                    field: "max_element",
                    value: options.floor.max_element,
                })),
            );
        }
        let local = |x: Vector2<f64>| {
            let l = self.to_map_frame(x);
            Point::new(l.x, l.y)
        };
        // Walls that `FloorMap::new`'s shrink by `s` would make meet are joined in the outline,
        // and the opening done again, which rounds the joints by ρ (issue 52: "the boundaries
        // of hole 37 and hole 38 cross or touch" on SLAM clutter).
        let shrink = options.floor.clearance - options.floor.max_element;
        let mut round = 0;
        loop {
            let simplified = self.opened(&poly, rho, local(start), local(goal), options)?;
            round += 1;
            if shrink <= 0.0 || round > bridge::ROUNDS {
                return Ok(self.to_outline(&simplified, n));
            }
            let spots = bridge::close_spots(&simplified, JOIN_GAP * shrink, 0.5 * rho);
            if spots.is_empty() {
                return Ok(self.to_outline(&simplified, n));
            }
            match bridge::join_at(&poly, &simplified, &spots, rho, local(goal)) {
                Some(joined) => poly = joined,
                None => return Ok(self.to_outline(&simplified, n)),
            }
        }
    }

    /// `poly` opened by the robot's disc of radius `rho` about the goal's component
    /// ([`RosMap::free_space`]) and simplified.
    fn opened(
        &self,
        poly: &geo::Polygon<f64>,
        rho: f64,
        start: Point<f64>,
        goal: Point<f64>,
        options: &MapOptions,
    ) -> Result<geo::Polygon<f64>, MapError> {
        let opened = outline::open(poly, rho, goal, start).map_err(|cut| {
            self.error(MapProblem::TooNarrow {
                point: match cut {
                    outline::Cut::Goal => MapPoint::Goal,
                    outline::Cut::Start => MapPoint::Start,
                },
                clearance: rho,
            })
        })?;
        let eps = options.simplify.max(0.0) * self.resolution * self.resolution;
        // Within one pixel of the opened walls: the tolerance is lowered where it would move
        // them farther (`outline::simplify`).
        let simplified = outline::simplify(&opened, eps, OPENED_MOVE_PIXELS * self.resolution);
        Ok(simplified)
    }

    /// The floor plan of this map for a robot going from `start` to `goal` (world
    /// coordinates): [`RosMap::free_space`] handed to [`FloorMap::new`] with
    /// `options.floor`, and both points checked to lie in its certified region `W_δ`.
    ///
    /// # Errors
    /// Those of [`RosMap::free_space`]; [`MapProblem::Floor`] when [`FloorMap::new`] refuses
    /// the polygon ([`crate::FloorError::TooNarrow`]: a passage narrower than the robot, too
    /// many vertices or elements, …); [`MapProblem::NotCertified`] when the start or the goal
    /// lies in the boundary layer.
    pub fn to_floor_map(
        &self,
        start: Vector2<f64>,
        goal: Vector2<f64>,
        options: &MapOptions,
    ) -> Result<FloorMap, MapError> {
        let space = self.free_space(start, goal, options)?;
        let floor = FloorMap::new(space.outer, space.holes, &options.floor)
            .map_err(|e| self.error(MapProblem::Floor(e)))?;
        for (point, x) in [(MapPoint::Goal, goal), (MapPoint::Start, start)] {
            let clearance = floor.clearance(x);
            // NaN (a point the walls' query cannot place) is refused like a negative clearance.
            if clearance.is_nan() || clearance < 0.0 {
                return Err(self.error(MapProblem::NotCertified { point, clearance }));
            }
        }
        Ok(floor)
    }
}

impl FloorMap {
    /// The floor plan of the ROS map_server map at `yaml_path` for a robot going from `start`
    /// to `goal` (world coordinates): [`RosMap::load`] then [`RosMap::to_floor_map`].
    ///
    /// # Errors
    /// [`MapError`], naming the file and the problem.
    pub fn from_ros_map(
        yaml_path: impl AsRef<Path>,
        start: Vector2<f64>,
        goal: Vector2<f64>,
        options: &MapOptions,
    ) -> Result<Self, MapError> {
        RosMap::load(yaml_path)?.to_floor_map(start, goal, options)
    }
}
