//! Pixels to cells (map_server's interpretation), connected components and speck removal.

use image::DynamicImage;

use super::{Cell, MapMode};

/// map_server's reading of one pixel, from the mean `x` of its colour channels (`0..=255`) and
/// its alpha (`255` when the image has none):
///
/// ```text
/// p = (255 − x)/255   (negate = false),     p = x/255   (negate = true)
/// trinary: p > occupied → Occupied,  p < free → Free,  else Unknown
/// scale:   alpha < 255 → Unknown, then as trinary, except that p between the thresholds
///          (an occupancy of 1–99 for map_server) is Occupied
/// raw:     x is the occupancy itself: 0 → Free, 1..=100 → Occupied, above → Unknown
///          (negate does not apply)
/// ```
///
/// Ties are conservative: `p = free` is not free (map_server's documentation says `<`, its
/// doxygen `≤`).
#[must_use]
pub(crate) fn classify(
    x: f64,
    alpha: u8,
    negate: bool,
    occupied: f64,
    free: f64,
    mode: MapMode,
) -> Cell {
    if mode == MapMode::Raw {
        return if x == 0.0 {
            Cell::Free
        } else if x <= 100.0 {
            Cell::Occupied
        } else {
            Cell::Unknown
        };
    }
    if mode == MapMode::Scale && alpha < u8::MAX {
        return Cell::Unknown;
    }
    let p = if negate {
        x / 255.0
    } else {
        (255.0 - x) / 255.0
    };
    if p > occupied {
        Cell::Occupied
    } else if p < free {
        Cell::Free
    } else if mode == MapMode::Scale {
        Cell::Occupied
    } else {
        Cell::Unknown
    }
}

/// Every pixel's cell, row 0 at the top, row-major. Colour is averaged to grey with equal
/// weights (map_server's `color_avg`, not a luminance); 16-bit images are first scaled to
/// 8 bits by the `image` crate.
pub(crate) fn cells(
    img: &DynamicImage,
    negate: bool,
    occupied: f64,
    free: f64,
    mode: MapMode,
) -> Vec<Cell> {
    let has_alpha = img.color().has_alpha();
    let grey = img.color().channel_count() <= 2;
    let rgba = img.to_rgba8();
    rgba.pixels()
        .map(|px| {
            let [r, g, b, a] = px.0;
            let x = if grey {
                f64::from(r)
            } else {
                (f64::from(r) + f64::from(g) + f64::from(b)) / 3.0
            };
            let alpha = if has_alpha { a } else { u8::MAX };
            classify(x, alpha, negate, occupied, free, mode)
        })
        .collect()
}

/// No component.
pub(crate) const NONE: u32 = u32::MAX;

/// Connected components of the `true` pixels of a `width × height` mask: 4-connected
/// (edge neighbours) or 8-connected (also the diagonals). Returns each pixel's label
/// ([`NONE`] for `false` pixels) and each label's pixel count. An explicit stack, no recursion.
pub(crate) fn components(
    mask: &[bool],
    width: usize,
    height: usize,
    eight: bool,
) -> (Vec<u32>, Vec<usize>) {
    let mut label = vec![NONE; mask.len()];
    let mut sizes = Vec::new();
    let mut stack = Vec::new();
    for seed in 0..mask.len() {
        if !mask[seed] || label[seed] != NONE {
            continue;
        }
        let id = u32::try_from(sizes.len()).unwrap_or(NONE - 1);
        let mut size = 0;
        label[seed] = id;
        stack.push(seed);
        while let Some(i) = stack.pop() {
            size += 1;
            let (c, r) = (i % width, i / width);
            for (dc, dr) in [
                (-1, 0),
                (1, 0),
                (0, -1),
                (0, 1),
                (-1, -1),
                (1, -1),
                (-1, 1),
                (1, 1),
            ]
            .into_iter()
            .take(if eight { 8 } else { 4 })
            {
                let (Some(nc), Some(nr)) = (c.checked_add_signed(dc), r.checked_add_signed(dr))
                else {
                    continue;
                };
                if nc >= width || nr >= height {
                    continue;
                }
                let j = nr * width + nc;
                if mask[j] && label[j] == NONE {
                    label[j] = id;
                    stack.push(j);
                }
            }
        }
        sizes.push(size);
    }
    (label, sizes)
}

/// The occupied islands of at most `speck` pixels (8-connected non-free pixels not touching
/// the image's edge): `(label, sizes, dropped)`, `dropped[l]` for each island label `l` that
/// goes. `None` when `speck` is 0.
fn islands(
    cells: &[Cell],
    width: usize,
    height: usize,
    speck: usize,
) -> Option<(Vec<u32>, Vec<usize>, Vec<bool>)> {
    if speck == 0 {
        return None;
    }
    let walls: Vec<bool> = cells.iter().map(|&c| c != Cell::Free).collect();
    let (label, sizes) = components(&walls, width, height, true);
    let mut dropped: Vec<bool> = sizes.iter().map(|&n| n <= speck).collect();
    for (i, &l) in label.iter().enumerate() {
        let (c, r) = (i % width, i / width);
        if l != NONE && (c == 0 || r == 0 || c + 1 == width || r + 1 == height) {
            dropped[l as usize] = false;
        }
    }
    Some((label, sizes, dropped))
}

/// The islands [`goal_component`] drops as specks: each one's pixel count and the index of
/// its first pixel (row-major), largest first.
pub(crate) fn specks(
    cells: &[Cell],
    width: usize,
    height: usize,
    speck: usize,
) -> Vec<(usize, usize)> {
    let Some((label, sizes, dropped)) = islands(cells, width, height, speck) else {
        return Vec::new();
    };
    let mut first = vec![usize::MAX; sizes.len()];
    for (i, &l) in label.iter().enumerate() {
        if l != NONE && dropped[l as usize] && first[l as usize] == usize::MAX {
            first[l as usize] = i;
        }
    }
    let mut out: Vec<(usize, usize)> = (0..sizes.len())
        .filter(|&l| dropped[l])
        .map(|l| (sizes[l], first[l]))
        .collect();
    out.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    out
}

/// The free mask of the goal's component, after the specks: occupied islands (8-connected
/// non-free pixels not touching the image's edge) of at most `speck` pixels become free; then
/// only the 4-connected free component holding pixel `goal` is kept. Returns the mask and the
/// component labels of the free pixels before that last step (to tell an unreachable start).
pub(crate) fn goal_component(
    cells: &[Cell],
    width: usize,
    height: usize,
    speck: usize,
    goal: usize,
) -> (Vec<bool>, Vec<u32>) {
    let mut free: Vec<bool> = cells.iter().map(|&c| c == Cell::Free).collect();
    if let Some((label, _, dropped)) = islands(cells, width, height, speck) {
        for (f, &l) in free.iter_mut().zip(&label) {
            if l != NONE && dropped[l as usize] {
                *f = true;
            }
        }
    }
    let (label, _) = components(&free, width, height, false);
    let keep = label[goal];
    let mask = label.iter().map(|&l| l != NONE && l == keep).collect();
    (mask, label)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_and_eight_connectivity_differ_on_a_diagonal() {
        // 1 0
        // 0 1
        let mask = [true, false, false, true];
        assert_eq!(components(&mask, 2, 2, false).1, vec![1, 1]);
        assert_eq!(components(&mask, 2, 2, true).1, vec![2]);
    }

    #[test]
    fn thresholds_are_strict_and_ties_not_free() {
        let c = |x: f64, negate, mode| classify(x, 255, negate, 0.65, 0.2, mode);
        // p = (255 − 204)/255 = 0.2 exactly: not free.
        assert_eq!(c(204.0, false, MapMode::Trinary), Cell::Unknown);
        assert_eq!(c(205.0, false, MapMode::Trinary), Cell::Free);
        assert_eq!(c(0.0, false, MapMode::Trinary), Cell::Occupied);
        assert_eq!(c(0.0, true, MapMode::Trinary), Cell::Free);
        assert_eq!(c(128.0, false, MapMode::Scale), Cell::Occupied);
        assert_eq!(
            classify(255.0, 100, false, 0.65, 0.2, MapMode::Scale),
            Cell::Unknown
        );
        assert_eq!(
            classify(255.0, 100, false, 0.65, 0.2, MapMode::Trinary),
            Cell::Free
        );
        assert_eq!(c(0.0, true, MapMode::Raw), Cell::Free);
        assert_eq!(c(100.0, false, MapMode::Raw), Cell::Occupied);
        assert_eq!(c(255.0, false, MapMode::Raw), Cell::Unknown);
    }
}
