//! Measures the lidar suites (ignored; `cargo test --release -p harmonav --test scan_measure -- --ignored --nocapture`).

use harmonav::Law;
use harmonav::checks::lidar::LidarSuite;

#[test]
#[ignore]
fn measure() {
    let n: u64 = std::env::var("N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(6);
    let k = LidarSuite {
        seeds: 0..n,
        ..LidarSuite::new(Law::kinematic(1.0), 0.01)
    };
    let mut noisy = k.clone();
    noisy.lidar.noise = 0.05;
    for (name, s) in [
        (
            "kin discs",
            LidarSuite {
                discs_only: true,
                ..k.clone()
            },
        ),
        ("kin", k.clone()),
        (
            "dyn",
            LidarSuite {
                seeds: 0..n,
                ..LidarSuite::new(Law::dynamic(1.0, 2.0), 0.001)
            },
        ),
        (
            "ctl D=0.3",
            LidarSuite {
                max_obstacle_depth: 0.3,
                ..k.clone()
            },
        ),
        (
            "ctl eps=0 noise .05",
            LidarSuite {
                range_noise: 0.0,
                ..noisy.clone()
            },
        ),
        (
            "ctl eps=0",
            LidarSuite {
                range_noise: 0.0,
                ..k.clone()
            },
        ),
    ] {
        let t = std::time::Instant::now();
        let r = s.run().unwrap();
        println!(
            "{name}: runs {} reached {} stalled {} refused {:?} failures {} unc {} scans {} events {} minclr {:.3} minev {:.3} mindet {:.3} cons {:.2} t {:.1}s",
            r.runs,
            r.reached,
            r.stalled,
            r.refused,
            r.failures.len(),
            r.uncovered,
            r.scans,
            r.events,
            r.min_clearance,
            r.min_event_clearance,
            r.min_detection_clearance,
            r.median_conservatism,
            t.elapsed().as_secs_f64()
        );
    }
}
