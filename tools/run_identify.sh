#!/usr/bin/env bash
# The identification benchmark (issue 11): identify over evaluation units of the population
# (both classes, spread all), the identified parameters against each unit's own, and the
# estimator's velocity RMSE with identified vs true parameters. Writes out/identify/summary.json.
#   usage: tools/run_identify.sh [--units N] [--first-unit ID] [--scenarios LIST] ...  (tools/run_identify.py --help)
# Default: 30 units (10 of class b), about 1.5 minutes on one core. Fails only if a step cannot run.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset host-release >/dev/null
cmake --build build/host-release -j2 --target host_sim identify >/dev/null
exec /usr/bin/python3 tools/run_identify.py "$@"
