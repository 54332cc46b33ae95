//! The measurements of docs/maths.md §11: accuracy, the fold layer, det J against the distance
//! from the boundary, the certificate and solve times.
//!
//! `cargo run --release -p harmonav-harmonic --example study [times]` (`times`: only the
//! solve and evaluation times, up to N ≈ 2 000).

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use harmonav_harmonic::{CertifyOptions, Domain, HarmonicMap, MeshOptions, certify, sampled_check};
use std::f64::consts::{PI, TAU};
use std::time::Instant;

fn disk(n: usize) -> (usize, f64) {
    let d = Domain::new(ngon(v(0.0, 0.0), 1.0, n, true), vec![]).unwrap();
    let chord = 2.0 * (PI / n as f64).sin();
    let map = HarmonicMap::new(&d, &MeshOptions::uniform(chord * 1.001)).unwrap();
    let mut worst = 0.0_f64;
    for i in 0..=18 {
        for j in 0..36 {
            let r = 0.9 * i as f64 / 18.0;
            let t = TAU * j as f64 / 36.0;
            let x = v(r * t.cos(), r * t.sin());
            worst = worst.max((map.eval(x).unwrap().value - x).norm());
        }
    }
    (map.elements().len(), worst)
}

/// Deepest fold (in units of the longest element) and min det J in bands of distance.
fn layer(name: &str, d: &Domain, options: MeshOptions, spacing: f64) {
    let t = Instant::now();
    let map = HarmonicMap::new(d, &options).unwrap();
    let solve = t.elapsed().as_secs_f64();
    let h = map.max_element_length();
    let bands = [0.0, 0.25, 0.5, 1.0, 2.0, 4.0, f64::INFINITY];
    let mut min = vec![f64::INFINITY; bands.len() - 1];
    let mut deepest = 0.0_f64;
    let mut over = 0.0_f64;
    let mut folds = 0;
    for x in grid(d, spacing, 1e-9) {
        let dist = d.distance_to_boundary(x) / h;
        let Ok(e) = map.eval(x) else { continue };
        let det = e.det();
        if det <= 0.0 {
            folds += 1;
            deepest = deepest.max(dist);
        }
        if e.value.norm() >= 1.0 {
            over = over.max(dist);
        }
        let b = bands
            .windows(2)
            .position(|w| dist >= w[0] && dist < w[1])
            .unwrap();
        min[b] = min[b].min(det);
    }
    let r = map.residuals();
    let cert = certify(&map, &CertifyOptions::new(h));
    print!(
        "{name:>10} N={:>5} h={h:.3} solve {solve:.3}s res {:.0e}/{:.0e}/{:.0e} folds {folds} deepest {deepest:.2}h |H|>=1 deepest {over:.2}h | min det by d/h:",
        map.elements().len(),
        r.outer,
        r.holes,
        r.flux
    );
    for (w, m) in bands.windows(2).zip(&min) {
        print!(" [{},{}) {m:.1e}", w[0], w[1]);
    }
    match cert {
        Ok(c) => println!(
            " | certify(δ=h): {} evals {} certified {:.3} undecided {:.3}",
            c.verdict.as_str(),
            c.evaluations,
            c.certified_area,
            c.undecided_area
        ),
        Err(e) => println!(" | certify: {e}"),
    }
}

fn main() {
    let times_only = std::env::args().any(|a| a == "times");
    if !times_only {
        studies();
    }
    times(if times_only {
        &[0.05, 0.0125, 0.008, 0.005]
    } else {
        &[0.05, 0.025, 0.0125]
    });
}

fn studies() {
    println!("## disk: max |H(x) − x| over |x| ≤ 0.9 (regular n-gon, one element per edge)");
    for n in [16, 32, 64, 128, 256, 512] {
        let (n, e) = disk(n);
        println!("N = {n:>4}: {e:.3e}");
    }
    println!("## fold layer and det J against the distance from the boundary");
    for h in [0.08, 0.04, 0.02] {
        layer(
            "square/u",
            &square_with_hole(),
            MeshOptions::uniform(h),
            h / 8.0,
        );
        layer(
            "square/g",
            &square_with_hole(),
            MeshOptions::graded(h),
            h / 8.0,
        );
    }
    for (name, d, h) in [
        ("U", u_world(), 0.1),
        ("U", u_world(), 0.05),
        ("L", l_world(), 0.1),
        ("L", l_world(), 0.05),
        ("rooms", two_rooms(), 0.1),
        ("rooms", two_rooms(), 0.05),
    ] {
        layer(name, &d, MeshOptions::graded(h), h / 4.0);
    }
}

fn times(hs: &[f64]) {
    println!("## solve and evaluation times (square with hole, graded)");
    for &h in hs {
        let d = square_with_hole();
        let t = Instant::now();
        let map = HarmonicMap::new(&d, &MeshOptions::graded(h)).unwrap();
        let solve = t.elapsed().as_secs_f64();
        let pts = grid(&d, 0.05, 0.1);
        let t = Instant::now();
        let mut acc = 0.0;
        for &x in &pts {
            acc += map.eval(x).unwrap().det();
        }
        let per = t.elapsed().as_secs_f64() / pts.len() as f64;
        let s = sampled_check(&map, map.max_element_length(), 0.02).unwrap();
        println!(
            "N = {:>5}: setup {solve:.3} s, H + J {:.1} µs/point ({:.0} ns/element), min det(δ=h) {:.2e} (checksum {acc:.3})",
            map.elements().len(),
            per * 1e6,
            per * 1e9 / map.elements().len() as f64,
            s.min_det
        );
    }
}
