#!/usr/bin/env bash
# The whole loop through the generic image: `lashid design` writes a config, `lashid hil` sends its design to the
# firmware in QEMU, plays a plant file and records what the firmware measured (its verdict includes: the on-device
# estimates equal `lashid identify --float` on the recording, relative 1e-3), and `lashid diagnose` reads the
# recording. With EXPECTED_CAUSE, the diagnosis must name it.
# Usage: plant_loop.sh LASHID FIRMWARE PLANT EXPECTED_CAUSE|any DESIGN_ARGS...
set -euo pipefail
lashid=$1 firmware=$2 plant=$3 expected=$4
shift 4
dir=$(mktemp -d)
trap 'rm -rf "${dir}"' EXIT
"${lashid}" design "$@" --out "${dir}/config.json"
"${lashid}" hil --firmware "${firmware}" --config "${dir}/config.json" --plant "${plant}" --seed 3 \
  --record "${dir}/recording.csv" --json "${dir}/hil.json" --timeout 240
grep -q '"recording_relative_difference"' "${dir}/hil.json" || {
  echo "plant_loop: the recording was not compared with the on-device estimates" >&2
  exit 1
}
"${lashid}" diagnose --config "${dir}/config.json" --data "${dir}/recording.csv" | tee "${dir}/diagnosis.txt"
if [[ "${expected}" != any ]] && ! grep -q "^cause: ${expected}" "${dir}/diagnosis.txt"; then
  echo "plant_loop: the diagnosis does not name ${expected}" >&2
  exit 1
fi
