#!/usr/bin/env bash
# A design the firmware must refuse by its own check (the host's is skipped with --unchecked-design): V_d's last two
# levels are distinct doubles but the same float32, so (3.1)'s strict order fails on the device. The run must end
# with the named status and nothing actuated; without --unchecked-design the host refuses it before QEMU starts.
# With --record and --json: nothing to record is said so (the file named keeps its content), and the verdict and the
# JSON are still there (an empty recording used to replace both with "refusing to write an empty recording").
# Usage: refused_design.sh LASHID FIRMWARE
set -euo pipefail
lashid=$1 firmware=$2
dir=$(mktemp -d)
trap 'rm -rf "${dir}"' EXIT
cat >"${dir}/config.json" <<'JSON'
{"n": 2, "m": 6, "v_min": -3, "v_max": 4, "operator": "backlash",
 "V_d": [-3, -2, -1, 1, 2, 2.00000001], "V_a": [4, 3, 2, 1, -1, -2]}
JSON
echo "kept" >"${dir}/old.csv"
if "${lashid}" hil --firmware "${firmware}" --config "${dir}/config.json" --scenario dis_paper --unchecked-design \
  --timeout 60 --record "${dir}/old.csv" --json "${dir}/run.json" >"${dir}/out.txt" 2>&1; then
  cat "${dir}/out.txt"
  echo "refused_design: the run passed on a design the firmware must refuse" >&2
  exit 1
fi
cat "${dir}/out.txt"
grep -q "the firmware refused the design: (3.1): V_d must be strictly increasing" "${dir}/out.txt"
grep -q "firmware result: design rejected" "${dir}/out.txt"
grep -q "host: 0 plant samples" "${dir}/out.txt"
grep -q "no recording written: not a sample was measured" "${dir}/out.txt"
grep -q "verdict: FAIL" "${dir}/out.txt"
[[ "$(cat "${dir}/old.csv")" == kept ]]
grep -q '"ok": *false' "${dir}/run.json"
if "${lashid}" hil --firmware "${firmware}" --config "${dir}/config.json" --scenario dis_paper \
  >"${dir}/host.txt" 2>&1; then
  echo "refused_design: the host sent a design it must refuse" >&2
  exit 1
fi
cat "${dir}/host.txt"
grep -q "V_d" "${dir}/host.txt"
# A machine QEMU does not know: QEMU exits at once, and so does hil, with QEMU's own words (it used to wait the whole
# 10 s for the link socket and then say only that QEMU did not connect).
if "${lashid}" hil --firmware "${firmware}" --scenario dis_paper --machine no-such-board >"${dir}/machine.txt" 2>&1; then
  echo "refused_design: a run on an unknown machine passed" >&2
  exit 1
fi
cat "${dir}/machine.txt"
grep -q "QEMU exited before it connected to the link (UART0) socket: " "${dir}/machine.txt"
