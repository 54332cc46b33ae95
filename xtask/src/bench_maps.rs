//! `cargo xtask bench --only map_`: the cost of refusing a hostile ROS map (issue 56, D3).
//!
//! World: the hostile round's pillar map, a 1000 × 1000 image at 0.05 m/pixel (a 3 KB PNG) of
//! 2 × 2-pixel pillars every 6 pixels: 25 600 islands in the goal's free component, far above
//! what a floor plan takes. Figure:
//!
//! - `map_pillars_refuse_ms`: `RosMap::load` then `RosMap::to_floor_map` until it is refused
//!   (`MapProblem::TooManyIslands`), the median of a few (target: ≤ 1 000 ms; before the early
//!   count it took hours, 110 s measured before it was killed).

use harmonav::Vector2;
use harmonav::floorplan::{FloorOptions, MapOptions, MapProblem, RosMap};

use crate::bench::median_ns;

/// The pillar map's side, pixels.
const SIDE: usize = 1000;

/// Writes the pillar map (PGM and YAML) into a scratch folder; the YAML's path.
fn pillars() -> Result<std::path::PathBuf, String> {
    let dir = std::env::temp_dir().join(format!("harmonav-bench-pillars-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let n = SIDE;
    let mut pgm = format!("P5\n{n} {n}\n255\n").into_bytes();
    pgm.extend((0..n * n).map(|i| {
        let (r, c) = (i / n, i % n);
        let wall = r < 2 || c < 2 || r >= n - 2 || c >= n - 2;
        let inner = (21..n - 20).contains(&r) && (21..n - 20).contains(&c);
        let pillar = inner && r % 6 < 2 && c % 6 < 2;
        if wall || pillar { 0u8 } else { 254u8 }
    }));
    std::fs::write(dir.join("pillars.pgm"), pgm).map_err(|e| e.to_string())?;
    let yaml = dir.join("pillars.yaml");
    std::fs::write(
        &yaml,
        "image: pillars.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .map_err(|e| e.to_string())?;
    Ok(yaml)
}

/// The figures of the module docs.
pub fn figures(put: &mut impl FnMut(&str, f64)) -> Result<(), String> {
    let yaml = pillars()?;
    let options = MapOptions::new(FloorOptions::new(0.05, 0.01));
    let (start, goal) = (Vector2::new(0.5, 0.5), Vector2::new(49.0, 49.0));
    let refuse = || -> Result<(), String> {
        let map = RosMap::load(&yaml).map_err(|e| e.to_string())?;
        match map.to_floor_map(start, goal, &options) {
            Err(e) if matches!(e.problem, MapProblem::TooManyIslands { .. }) => Ok(()),
            Err(e) => Err(format!("the pillar map: another error: {e}")),
            Ok(_) => Err("the pillar map loaded".into()),
        }
    };
    refuse()?;
    let ns = median_ns(5, 1.0, || {
        let _ = refuse();
    });
    put("map_pillars_refuse_ms", ns / 1e6);
    let _ = std::fs::remove_dir_all(yaml.parent().unwrap_or(&yaml));
    Ok(())
}
