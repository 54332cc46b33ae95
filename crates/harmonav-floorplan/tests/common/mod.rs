//! Test maps: a tiny raster painter, a PGM/YAML writer, and the generator of the suite's maps
//! under `scenarios/floorplans/maps/` (the committed files are checked against it).

#![allow(dead_code)] // each test binary uses part of it

use std::path::{Path, PathBuf};
use std::sync::Arc;

use harmonav_floorplan::{CentrePolicy, FloorMap, FloorOptions};
use nalgebra::Vector2;

/// map_server's colours: 254 free (map_saver writes 254), 0 occupied, 205 unknown.
pub const FREE: u8 = 254;
/// Occupied.
pub const WALL: u8 = 0;
/// Unknown (p = 0.196…, between the usual thresholds).
pub const UNKNOWN: u8 = 205;

/// A grey image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Img {
    pub w: usize,
    pub h: usize,
    pub px: Vec<u8>,
}

impl Img {
    /// All `v`.
    pub fn new(w: usize, h: usize, v: u8) -> Self {
        Self {
            w,
            h,
            px: vec![v; w * h],
        }
    }

    /// Columns `c0..c1`, rows `r0..r1` (row 0 at the top) set to `v`.
    pub fn rect(&mut self, c0: usize, r0: usize, c1: usize, r1: usize, v: u8) -> &mut Self {
        for r in r0..r1.min(self.h) {
            for c in c0..c1.min(self.w) {
                self.px[r * self.w + c] = v;
            }
        }
        self
    }

    /// A rectangle given in metres of the map frame (`x` right, `y` up from the lower-left
    /// corner), at `res` m/pixel.
    pub fn rect_m(&mut self, res: f64, x0: f64, y0: f64, x1: f64, y1: f64, v: u8) -> &mut Self {
        let px = |m: f64| (m / res).round() as usize;
        let (c0, c1) = (px(x0), px(x1));
        let (r0, r1) = (self.h - px(y1).min(self.h), self.h - px(y0).min(self.h));
        self.rect(c0, r0, c1, r1, v)
    }

    /// A `t`-pixel wall around the image's edge.
    pub fn border(&mut self, t: usize) -> &mut Self {
        let (w, h) = (self.w, self.h);
        self.rect(0, 0, w, t, WALL)
            .rect(0, h - t, w, h, WALL)
            .rect(0, 0, t, h, WALL)
            .rect(w - t, 0, w, h, WALL)
    }

    /// How many pixels are `v`.
    pub fn count(&self, v: u8) -> usize {
        self.px.iter().filter(|&&p| p == v).count()
    }

    /// Binary PGM (P5), as map_saver writes it.
    pub fn pgm(&self) -> Vec<u8> {
        let mut out = format!(
            "P5\n# CREATOR: harmonav tests\n{} {}\n255\n",
            self.w, self.h
        )
        .into_bytes();
        out.extend(&self.px);
        out
    }

    /// Every pixel inverted (`255 − v`), for `negate`.
    pub fn inverted(&self) -> Self {
        Self {
            px: self.px.iter().map(|v| 255 - v).collect(),
            ..self.clone()
        }
    }
}

/// A map_server YAML text.
pub fn yaml(image: &str, res: f64, origin: [f64; 3], negate: bool, extra: &str) -> String {
    format!(
        "image: {image}\nresolution: {res}\norigin: [{}, {}, {}]\nnegate: {}\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n{extra}",
        origin[0],
        origin[1],
        origin[2],
        u8::from(negate)
    )
}

/// A fresh folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("harmonav-ros-map-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `name.pgm` and `name.yaml` into `dir`; returns the YAML's path.
pub fn write_map(dir: &Path, name: &str, img: &Img, res: f64, origin: [f64; 3]) -> PathBuf {
    std::fs::write(dir.join(format!("{name}.pgm")), img.pgm()).unwrap();
    let y = dir.join(format!("{name}.yaml"));
    std::fs::write(&y, yaml(&format!("{name}.pgm"), res, origin, false, "")).unwrap();
    y
}

/// One of the suite's maps: its image and a start and goal (world coordinates).
pub struct SuiteMap {
    pub name: &'static str,
    pub img: Img,
    pub res: f64,
    pub origin: [f64; 3],
    pub start: [f64; 2],
    pub goal: [f64; 2],
}

/// The suite's resolution (m/pixel).
pub const RES: f64 = 0.05;

/// An office, 10 × 8 m: a corridor 1.6 m wide across the middle, three rooms above and two
/// below, each with a 0.9 m door onto the corridor; a desk in two rooms, a pillar in the
/// corridor. Walls 0.1 m.
pub fn office() -> SuiteMap {
    let (w, h) = (200, 160);
    let mut img = Img::new(w, h, FREE);
    img.border(2);
    let r = RES;
    // Corridor between y = 3.2 and y = 4.8; walls along it.
    img.rect_m(r, 0.0, 3.1, 10.0, 3.2, WALL);
    img.rect_m(r, 0.0, 4.8, 10.0, 4.9, WALL);
    // Rooms above: walls at x = 3.3, 6.6; below: at x = 5.0.
    img.rect_m(r, 3.3, 4.8, 3.4, 8.0, WALL);
    img.rect_m(r, 6.6, 4.8, 6.7, 8.0, WALL);
    img.rect_m(r, 5.0, 0.0, 5.1, 3.2, WALL);
    // Doors (0.9 m) onto the corridor.
    for x in [1.2, 4.6, 8.0] {
        img.rect_m(r, x, 4.8, x + 0.9, 4.9, FREE);
    }
    for x in [2.0, 7.0] {
        img.rect_m(r, x, 3.1, x + 0.9, 3.2, FREE);
    }
    // Desks and a pillar.
    img.rect_m(r, 1.0, 6.4, 2.4, 7.1, WALL);
    img.rect_m(r, 7.4, 0.8, 8.6, 1.6, WALL);
    img.rect_m(r, 5.6, 3.8, 5.9, 4.1, WALL);
    SuiteMap {
        name: "office",
        img,
        res: r,
        origin: [0.0, 0.0, 0.0],
        start: [1.5, 1.5],
        goal: [8.5, 6.5],
    }
}

/// A serpentine maze, 8 × 8 m: four walls 0.1 m thick across it, each leaving a 1 m gap,
/// alternately at the right and the left; the walls join the outer ring (no holes).
pub fn maze() -> SuiteMap {
    let (w, h) = (160, 160);
    let mut img = Img::new(w, h, FREE);
    img.border(2);
    let r = RES;
    for (i, y) in [1.6, 3.2, 4.8, 6.4].into_iter().enumerate() {
        if i % 2 == 0 {
            img.rect_m(r, 0.0, y, 7.0, y + 0.1, WALL);
        } else {
            img.rect_m(r, 1.0, y, 8.0, y + 0.1, WALL);
        }
    }
    SuiteMap {
        name: "maze",
        img,
        res: r,
        origin: [-4.0, -4.0, 0.0],
        start: [-3.2, -3.3],
        goal: [3.2, 3.3],
    }
}

/// A U-trap, 8 × 5 m: a U-shaped obstacle 2 × 3 m whose 1.4 × 1.5 m pocket opens towards the
/// start (the trap of reactive planners).
pub fn u_trap() -> SuiteMap {
    let (w, h) = (160, 100);
    let mut img = Img::new(w, h, FREE);
    img.border(2);
    let r = RES;
    img.rect_m(r, 3.0, 1.0, 5.0, 4.0, WALL);
    img.rect_m(r, 3.0, 1.8, 4.5, 3.2, FREE);
    SuiteMap {
        name: "u-trap",
        img,
        res: r,
        origin: [0.0, 0.0, 0.0],
        start: [1.0, 2.3],
        goal: [6.8, 2.5],
    }
}

/// A warehouse, 12 × 8 m: three rows of four shelves (2 × 0.6 m), 1.4 m aisles, and a wall
/// stub on the east wall.
pub fn warehouse() -> SuiteMap {
    let (w, h) = (240, 160);
    let mut img = Img::new(w, h, FREE);
    img.border(2);
    let r = RES;
    for row in 0..3 {
        let y = 1.6 + 2.0 * f64::from(row);
        for col in 0..4 {
            let x = 1.5 + 2.4 * f64::from(col);
            img.rect_m(r, x, y, x + 2.0, y + 0.6, WALL);
        }
    }
    img.rect_m(r, 10.8, 2.9, 12.0, 3.0, WALL);
    SuiteMap {
        name: "warehouse",
        img,
        res: r,
        origin: [0.0, 0.0, 0.0],
        start: [0.6, 0.6],
        goal: [11.2, 7.2],
    }
}

/// Every map of the suite.
pub fn suite() -> Vec<SuiteMap> {
    vec![office(), maze(), u_trap(), warehouse()]
}

/// `scenarios/floorplans/maps/` from this crate.
pub fn suite_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/floorplans/maps")
}

/// The YAML text of a suite map.
pub fn suite_yaml(m: &SuiteMap) -> String {
    format!(
        "# {} (harmonav's floor-plan suite; made by `cargo test -p harmonav-floorplan --test \
         ros_map -- --ignored write_suite_maps`)\n{}",
        m.name,
        yaml(
            &format!("{}.pgm", m.name),
            m.res,
            m.origin,
            false,
            "mode: trinary\n"
        )
    )
}

/// A 6 × 4 room with a U-shaped hole (2 × 2, pocket 1 wide and 1.4 deep, open upward),
/// boundary elements of at most `h`, `clearance` = radius + margin, under `centre`.
pub fn u_room(h: f64, clearance: f64, centre: CentrePolicy) -> Arc<FloorMap> {
    let v = Vector2::new;
    let room = vec![v(0.0, 0.0), v(6.0, 0.0), v(6.0, 4.0), v(0.0, 4.0)];
    let u = vec![
        v(2.0, 1.0),
        v(4.0, 1.0),
        v(4.0, 3.0),
        v(3.5, 3.0),
        v(3.5, 1.6),
        v(2.5, 1.6),
        v(2.5, 3.0),
        v(2.0, 3.0),
    ];
    let options = FloorOptions::new(h, clearance).with_centre(centre);
    Arc::new(FloorMap::new(room, vec![u], &options).unwrap())
}
