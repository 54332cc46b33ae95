#!/usr/bin/env bash
# Writes summary.json of every scenario suite file, run with each robot model
# (built-in integrator) and with rapier (the file's model), into OUT:
# OUT/<path under scenarios/ with / as __>.<kinematic|dynamic|rapier>.json. Run it before and after a change that
# must not alter any run (a refactor), then `diff -r BEFORE AFTER`: issue 24's check that the
# move of the simulator into its crates left every summary byte-identical.
#
#   scripts/summaries.sh OUT [CLI]     (CLI: the harmonav binary, default target/release/harmonav)
#
# The suites are the files `cargo xtask verify` runs: everything under scenarios/ except the
# adversarial/ and long/ folders, floor plans included (issue 51). A floor plan's `setup_s` (the
# wall-clock time of its solve) is left out.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out=${1:?usage: scripts/summaries.sh OUT [CLI]}
cli=${2:-target/release/harmonav}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
find scenarios -name '*.toml' -not -path '*/adversarial/*' -not -path '*/long/*' | sort | while read -r f; do
    name=$(echo "${f#scenarios/}" | sed 's|/|__|g; s|\.toml$||')
    for run in kinematic dynamic rapier; do
        case $run in
            rapier) args=(--physics rapier) ;;
            # --controller: the old name, which binaries from before the split also accept.
            *) args=(--controller "$run") ;;
        esac
        rm -rf "$tmp/run"
        # A run may fail its guarantees (exit 1) and still write its summary: keep going. The
        # CLI gets no stdin, so that it cannot eat the list of files.
        "$cli" run "$f" "${args[@]}" --out "$tmp/run" </dev/null >"$tmp/log" 2>&1 || true
        if [ -f "$tmp/run/summary.json" ]; then
            python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
d.pop("setup_s", None)
json.dump(d, open(sys.argv[2], "w"), indent=2, sort_keys=False)' "$tmp/run/summary.json" "$out/$name.$run.json"
        else
            { echo "no summary:"; cat "$tmp/log"; } >"$out/$name.$run.json"
        fi
    done
done
echo "$(ls "$out" | wc -l) summaries in $out"
