//! Seeded random truths and scans shared by the tests.

#![allow(dead_code)]

use std::f64::consts::TAU;

use harmonav_perception::sim::Lidar;
use harmonav_perception::{
    Fit, FitFailure, FreeSpace, LaserScan, Options, Pose, fit_in_scan, hit_point, segment,
};
use harmonav_transform::StarShape;
use harmonav_transform::random::{self, Kind, Rng};
use nalgebra::Vector2;

/// One random trial: a true obstacle about the origin, a pose outside it, a lidar whose noise
/// is within the bound, and options whose priors the truth satisfies.
pub struct Trial {
    pub truth: StarShape,
    pub pose: Pose,
    pub lidar: Lidar,
    pub options: Options,
}

/// The true obstacle's smallest |curvature radius| (convex and concave parts), sampled on 4096
/// directions: (A2) needs it, `StarShape::rho_min` covers the convex parts only.
pub fn min_abs_curvature_radius(s: &StarShape) -> f64 {
    let n = 4096;
    let p = |t: f64| s.boundary_point(t);
    let h = TAU / n as f64;
    (0..n)
        .map(|i| {
            let t = i as f64 * h;
            let (a, b, c) = (p(t - h), p(t), p(t + h));
            // Circumradius of three neighbouring boundary points.
            let (ab, bc, ca) = ((b - a).norm(), (c - b).norm(), (a - c).norm());
            let cross = ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs();
            if cross == 0.0 {
                f64::INFINITY
            } else {
                ab * bc * ca / (2.0 * cross)
            }
        })
        .fold(f64::INFINITY, f64::min)
}

pub fn trial(seed: u64, noise_bound: f64) -> Trial {
    let mut rng = Rng::new(seed);
    let kind = [Kind::Circle, Kind::Ellipse, Kind::Star][rng.below(3)];
    let size = rng.uniform(0.15, 0.6);
    let truth = random::shape(&mut rng, kind, Vector2::zeros(), size);
    let (_, r_max) = truth.radius_bounds();
    let dist = rng.uniform(r_max + 0.3, 4.0);
    let bearing = rng.uniform(0.0, TAU);
    let pose = Pose::new(
        dist * bearing.cos(),
        dist * bearing.sin(),
        rng.uniform(-3.0, 3.0),
    );
    let beams = [360, 720, 1080][rng.below(3)];
    let lidar = Lidar {
        noise: rng.uniform(0.0, noise_bound),
        dropout: 0.02,
        ..Lidar::full_turn(beams, 8.0)
    };
    let options = Options {
        range_noise: noise_bound,
        // The diameter bound 2·max R, with some slack sometimes.
        max_obstacle_depth: 2.0 * r_max * rng.uniform(1.0, 1.3),
        rho_min: min_abs_curvature_radius(&truth).min(0.5),
        ..Options::default()
    };
    Trial {
        truth,
        pose,
        lidar,
        options,
    }
}

/// The fits of every segment of one scan (no known shapes), each on its own.
pub fn fits(scan: &LaserScan, pose: &Pose, options: &Options) -> Vec<Result<Fit, FitFailure>> {
    let n = scan.ranges.len();
    let usable: Vec<bool> = (0..n).map(|i| hit_point(scan, pose, i).is_some()).collect();
    let params = params(options);
    let free = FreeSpace::of_scan(scan, pose, options.range_noise, options.rho_min);
    segment(scan, pose, &usable, options.jump_distance)
        .iter()
        .map(|seg| fit_in_scan(scan, pose, seg, &params, &free))
        .collect()
}

/// The fit's parameters from the perception's options.
pub fn params(options: &Options) -> harmonav_perception::FitParams {
    harmonav_perception::FitParams {
        range_noise: options.range_noise,
        max_obstacle_depth: options.max_obstacle_depth,
        rho_min: options.rho_min,
        order: options.order,
        form: options.form,
        check_spacing: options.check_spacing,
        keep_out: options.keep_out,
    }
}

/// Boundary points of the truth, 2048 evenly in angle about its centre.
pub fn truth_points(truth: &StarShape) -> Vec<Vector2<f64>> {
    (0..2048)
        .map(|i| truth.boundary_point(TAU * i as f64 / 2048.0))
        .collect()
}

/// The largest `signed_distance_F(x)` over the truth's boundary points: `≤ 0` iff contained
/// (to the sampling), `≤ −0.02` iff the fit shrunk by 2 cm still contains them.
pub fn worst_depth(fit: &StarShape, truth: &[Vector2<f64>]) -> f64 {
    truth
        .iter()
        .map(|&x| fit.signed_distance(x))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The area of a closed polygon (shoelace).
pub fn polygon_area(points: &[Vector2<f64>]) -> f64 {
    let n = points.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            a.x * b.y - a.y * b.x
        })
        .sum::<f64>()
        .abs()
}
