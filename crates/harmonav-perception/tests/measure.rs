//! Measurements for docs/maths.md §12 (run with `--ignored --nocapture`).

mod common;

use std::time::Instant;

use harmonav_transform::random::Rng;

#[test]
#[ignore]
fn measure_containment() {
    let trials: u64 = std::env::var("TRIALS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let eps = 0.02;
    let (mut fits, mut contained, mut ctl_fail, mut ctl_star, mut shrunk_fail, mut wide) =
        (0, 0, 0, 0, 0, 0);
    let mut ratios = Vec::new();
    let mut time = 0.0;
    let mut fallback = 0;
    for seed in 0..trials {
        let mut t = common::trial(seed, eps);
        if std::env::var("FULL_NOISE").is_ok() {
            t.lidar.noise = eps;
        }
        let mut rng = Rng::new(seed ^ 0xABCD);
        let scan = t
            .lidar
            .scan(&t.pose, std::slice::from_ref(&t.truth), None, &mut rng);
        let truth = common::truth_points(&t.truth);
        let area = common::polygon_area(&truth);
        let start = Instant::now();
        let results = common::fits(&scan, &t.pose, &t.options);
        time += start.elapsed().as_secs_f64();
        let control = common::fits(
            &scan,
            &t.pose,
            &harmonav_perception::Options {
                range_noise: 0.0,
                ..t.options
            },
        );
        for (r, c) in results.iter().zip(&control) {
            match r {
                Ok(f) => {
                    fits += 1;
                    if f.certification.disc_fallback {
                        fallback += 1;
                    }
                    let w = common::worst_depth(f.perceived.shape(), &truth);
                    if w <= 0.0 {
                        contained += 1
                    } else {
                        println!("seed {seed}: not contained by {w:.4}")
                    }
                    if w > -0.02 {
                        shrunk_fail += 1
                    }
                    ratios.push(f.perceived.area() / area);
                }
                Err(_) => wide += 1,
            }
            if let Ok(c) = c {
                if truth.iter().any(|&x| !c.region_contains(x)) {
                    ctl_fail += 1
                }
                if common::worst_depth(c.perceived.shape(), &truth) > 0.0 {
                    ctl_star += 1
                }
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    let q = |f: f64| ratios[((ratios.len() - 1) as f64 * f) as usize];
    println!("fits {fits}, contained {contained}, disc fallbacks {fallback}, too wide {wide}");
    println!(
        "negative control eps=0: Y misses truth in {ctl_fail} of {fits}, star misses in {ctl_star}; star shrunk 2 cm: {shrunk_fail} fail"
    );
    println!(
        "area ratio min {:.2} median {:.2} p90 {:.2} max {:.2}",
        q(0.0),
        q(0.5),
        q(0.9),
        q(1.0)
    );
    println!("fit time per scan {:.2} ms", 1e3 * time / trials as f64);
}

#[test]
#[ignore]
fn debug_one() {
    let seed: u64 = std::env::var("SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let t = common::trial(seed, 0.02);
    let mut rng = Rng::new(seed ^ 0xABCD);
    let scan = t
        .lidar
        .scan(&t.pose, std::slice::from_ref(&t.truth), None, &mut rng);
    let truth = common::truth_points(&t.truth);
    println!(
        "truth r {:?} rho {:.3} D {:.3} pose {:?}",
        t.truth.radius_bounds(),
        t.options.rho_min,
        t.options.max_obstacle_depth,
        t.pose
    );
    for f in common::fits(&scan, &t.pose, &t.options) {
        let f = f.unwrap();
        println!(
            "cut {} cert {:?} {:?} centre {:?} area ratio {:.2} worst {:.4}",
            f.cut_wedges,
            f.certification,
            f.perceived.fourier(),
            f.perceived.centre(),
            f.perceived.area() / common::polygon_area(&truth),
            common::worst_depth(f.perceived.shape(), &truth)
        );
    }
}
