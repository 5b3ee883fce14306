#!/usr/bin/env bash
# Regenerates every number quoted in docs/friction-damper.md: builds lashid (preset host-release) and runs
# `lashid operator-fit` on the measured friction damper (tests/data/friction_damper). Writes
# docs/friction-damper.json and docs/friction-damper.png and prints the report. Run from anywhere.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "${root}"
if [[ ! -f build/host-release/CMakeCache.txt ]]; then cmake --preset host-release >/dev/null; fi
cmake --build --preset host-release -j2 --target lashid >/dev/null
d=tests/data/friction_damper
# Training (the operators, the operator per band tension, the dynamics after it and their order): at 30 lb and at
# 36 lb band tension, the same three (frequency, amplitude) pairs, one per frequency and one per amplitude (a Latin
# square). Testing, never fitted on: the other six 30 lb char_ files, the 2 Hz sinusoid (above every training
# frequency) and the two earthquake records, whose 36 lb tension is not in their names, hence --tension.
build/host-release/host_sim/lashid operator-fit \
  --train "${d}/char_0.25Hz30lbtension1amplitude.csv" "${d}/char_0.5Hz30lbtension0.5amplitude.csv" \
          "${d}/char_1Hz30lbtension1.5amplitude.csv" \
          "${d}/char_0.25Hz36lbtension1amplitude.csv" "${d}/char_0.5Hz36lbtension0.5amplitude.csv" \
          "${d}/char_1Hz36lbtension1.5amplitude.csv" \
  --test "${d}/char_0.25Hz30lbtension0.5amplitude.csv" "${d}/char_0.25Hz30lbtension1.5amplitude.csv" \
         "${d}/char_0.5Hz30lbtension1amplitude.csv" "${d}/char_0.5Hz30lbtension1.5amplitude.csv" \
         "${d}/char_1Hz30lbtension0.5amplitude.csv" "${d}/char_1Hz30lbtension1amplitude.csv" \
         "${d}/char_2Hz30lbtension0.5amplitude.csv" "${d}/eq_KocaeliDBE.csv" "${d}/eq_ImperialValleyDBE.csv" \
  --tension eq_KocaeliDBE.csv=36 eq_ImperialValleyDBE.csv=36 \
  --json docs/friction-damper.json --plot docs/friction-damper.png "$@"
