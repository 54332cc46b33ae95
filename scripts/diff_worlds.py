#!/usr/bin/env python3
"""Writes the worlds of a `bench/diff/run.py --json` record as plain text for the Rust
measurement `crates/harmonav/tests/diff_time.rs` (docs/unicycle.md section 11), with the
reference times of the record's HL and holonomic runs, so that a change of the
differential-drive law can be measured against the same HL runs without navground.

    python3 scripts/diff_worlds.py diff-uniform.json > /tmp/uniform.txt

One line per world: seed, margin, HL's time (random heading, away; `nan` when it did not
arrive), the holonomic harmonav robot's time, the record's harmonav times (random, away),
start x y, goal x y, random yaw, the number of discs, then x y r per disc (floats as `repr`,
so the worlds are bit for bit those of the record).
"""

import json
import math
import sys


def time_of(runs, key, seed):
    r = runs.get(key, {}).get(str(seed))
    return r["time"] if r and r.get("arrived") else math.nan


def main(path):
    d = json.load(open(path))
    margin = d["meta"]["margin"]
    runs = d["runs"]
    for seed, w in sorted(d["worlds"].items(), key=lambda kv: int(kv[0])):
        fields = [seed, margin,
                  time_of(runs, "HL/random", seed), time_of(runs, "HL/away", seed),
                  time_of(runs, "holonomic/random", seed),
                  time_of(runs, "harmonav/random", seed), time_of(runs, "harmonav/away", seed),
                  *w["start"], *w["goal"], w["yaw"], len(w["discs"])]
        for disc in w["discs"]:
            fields += disc
        print(" ".join(repr(f) if isinstance(f, float) else str(f) for f in fields))


if __name__ == "__main__":
    main(sys.argv[1])
