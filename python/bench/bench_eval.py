"""Field.eval against a plain vectorised NumPy implementation of the same Θ and ∇Θ, and
against Rust's own per-point evaluation, on scenarios/scale/discs-20-global.toml (20 discs).

    python python/bench/bench_eval.py [--points 100000] [--rust-ns NS]

--rust-ns is Rust's batched per-point figure `field_eval_many_ns_discs20` of
`cargo xtask bench --json` (`Field::eval_many`, one thread, compiled for this CPU as the
package is); without it the script runs `cargo xtask bench --json --only field_eval`. Prints one JSON object. Wall-clock figures: run it on an idle machine and compare the
figures of one run side by side.
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

import harmonav

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "python" / "tests"))
from reference import from_scenario  # noqa: E402

WORLD = REPO / "scenarios" / "scale" / "discs-20-global.toml"


def best_of(repeats, f):
    """The fastest of `repeats` wall-clock timings of f(), s (the least disturbed)."""
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def rust_ns():
    out = subprocess.run(
        ["cargo", "xtask", "bench", "--json", "--only", "field_eval"],
        cwd=REPO,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out)["field_eval_many_ns_discs20"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--rust-ns", type=float, default=None)
    args = ap.parse_args()
    field = harmonav.Scenario.load(WORLD).field()
    reference = from_scenario(WORLD)
    rng = np.random.default_rng(0)
    pts = rng.uniform(-7, 7, size=(4 * args.points, 2))
    pts = pts[field.free(pts)][: args.points]
    theta, grad = field.eval(pts)
    ref_theta, ref_grad = reference.eval(pts)
    agree = float(np.max(np.abs(theta - ref_theta)))
    small = pts[:2000]  # below the parallel threshold: one thread
    ours = best_of(5, lambda: field.eval(pts)) / len(pts) * 1e9
    ours_1t = best_of(20, lambda: field.eval(small)) / len(small) * 1e9
    numpy_ns = best_of(3, lambda: reference.eval(pts)) / len(pts) * 1e9
    rust = args.rust_ns if args.rust_ns is not None else rust_ns()
    print(
        json.dumps(
            {
                "points": len(pts),
                "cores": os.cpu_count(),
                "max_abs_theta_difference": agree,
                "python_ns_per_point": round(ours, 1),
                "python_one_thread_ns_per_point": round(ours_1t, 1),
                "numpy_ns_per_point": round(numpy_ns, 1),
                "rust_batched_one_thread_ns_per_point": rust,
                "speedup_over_numpy": round(numpy_ns / ours, 1),
                "python_one_thread_over_rust_batched": round(ours_1t / rust, 2),
            },
            indent=2,
        )
    )


if __name__ == "__main__":
    main()
