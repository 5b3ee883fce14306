#!/usr/bin/env bash
# A design the firmware must refuse by its own check (the host's is skipped with --unchecked-design): V_d's last two
# levels are distinct doubles but the same float32, so (3.1)'s strict order fails on the device. The run must end
# with the named status and nothing actuated; without --unchecked-design the host refuses it before QEMU starts.
# With --record and --json: nothing to record is said so (the file named keeps its content), and the verdict and the
# JSON are still there (an empty recording used to replace both with "refusing to write an empty recording").
# An image run on a machine it was not built for is refused before QEMU starts; an unknown machine ends at once.
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
grep -q "'V_d\[5\]' = 2 is not greater than 'V_d\[4\]' = 2" "${dir}/host.txt"
# Refused before QEMU starts: no firmware console, no host exchange.
if grep -Eq 'firmware console|host: [0-9]+ plant samples' "${dir}/host.txt"; then
  echo "refused_design: QEMU ran a design the host must refuse first" >&2
  exit 1
fi
# The image on a machine it was not built for (its section .lashid.machine names mps2-an386): refused before QEMU
# starts, naming both machines (it used to run until --timeout: "the firmware never answered a query on the link").
# The run's --json is replaced by the error's, not left from the run above.
if "${lashid}" hil --firmware "${firmware}" --scenario dis_paper --machine netduinoplus2 --timeout 60 \
  --json "${dir}/run.json" >"${dir}/other.txt" 2>&1; then
  echo "refused_design: the image ran on a machine it was not built for" >&2
  exit 1
fi
cat "${dir}/other.txt"
grep -q "is built for QEMU machine 'mps2-an386', not 'netduinoplus2': run it with --machine mps2-an386" \
  "${dir}/other.txt"
grep -q '"error": "hil: firmware .* is built for QEMU machine' "${dir}/run.json"
# A machine QEMU does not know, with a copy of the image without that section (an image from elsewhere is run as it
# is): QEMU exits at once, and so does hil, with QEMU's own words (it used to wait the whole 10 s for the link socket
# and then say only that QEMU did not connect).
arm-none-eabi-objcopy --remove-section .lashid.machine "${firmware}" "${dir}/untagged.elf"
if "${lashid}" hil --firmware "${dir}/untagged.elf" --scenario dis_paper --machine no-such-board \
  >"${dir}/machine.txt" 2>&1; then
  echo "refused_design: a run on an unknown machine passed" >&2
  exit 1
fi
cat "${dir}/machine.txt"
grep -q "QEMU exited before it connected to the link (UART0) socket: " "${dir}/machine.txt"
