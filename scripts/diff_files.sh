#!/usr/bin/env bash
# The star files of scenarios/diff flown by a harmonav binary, each against the same file with
# a holonomic robot (the base's keys removed, the same v_max), as `cargo xtask verify`'s
# `diff.*` line compares them (docs/unicycle.md sections 7.6 and 11). Usage:
#
#     scripts/diff_files.sh [HARMONAV_BINARY]      # default: target/release/harmonav
#
# Prints one line per file: the time of each robot and their ratio (the target for
# random headings: at most 1.2).
set -euo pipefail
bin=${1:-target/release/harmonav}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
time_of() { "$bin" run "$1" 2>&1 | sed -n -E 's/^  time ([0-9.]+) s.*/\1/p' | head -1; }
for f in scenarios/diff/*.toml; do
    grep -q '^\[floor_plan\]' "$f" && continue
    name=$(basename "$f" .toml)
    grep -v -E '^(base|omega_max|yaw|a_max|alpha_max) *=' "$f" > "$tmp/$name.toml"
    d=$(time_of "$f")
    h=$(time_of "$tmp/$name.toml")
    awk -v n="$name" -v d="$d" -v h="$h" \
        'BEGIN { printf "%-22s diff %7.2f s  holonomic %7.2f s  ratio %.3f\n", n, d, h, d / h }'
done
