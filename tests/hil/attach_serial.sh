#!/usr/bin/env bash
# lashid hil --attach on serial ports: QEMU's UARTs on pseudo-terminals (-serial pty), the same character devices a
# board's USB serial adapters are, opened by the tool raw at 115200 baud. Then a character device that is not a
# serial port must be refused, naming it.
# Usage: attach_serial.sh LASHID QEMU FIRMWARE CONFIG (the design sent, with the scenario dis_paper's plant)
set -euo pipefail
lashid=$1 qemu=$2 firmware=$3 config=$4
dir=$(mktemp -d)
qemu_pid=""
trap 'kill "${qemu_pid}" 2>/dev/null || true; rm -rf "${dir}"' EXIT
qemu_command=$("${lashid}" qemu-command --qemu "${qemu}" --machine mps2-an386 --serial pty --serial pty \
  --kernel "${firmware}")
mapfile -t qemu_command <<<"${qemu_command}"
"${qemu_command[@]}" >"${dir}/qemu.log" 2>&1 &
qemu_pid=$!
# QEMU names its pseudo-terminals on its console: "char device redirected to /dev/pts/N (label serial0)".
ptys=()
for _ in $(seq 100); do
  mapfile -t ptys < <(grep -o '/dev/pts/[0-9]*' "${dir}/qemu.log" || true)
  [[ ${#ptys[@]} -ge 2 ]] && break
  sleep 0.1
done
[[ ${#ptys[@]} -ge 2 ]] || { cat "${dir}/qemu.log"; echo "attach_serial: QEMU named no pseudo-terminals" >&2; exit 1; }
"${lashid}" hil --attach "${ptys[0]}" "${ptys[1]}" --scenario dis_paper --config "${config}" --seed 11 --compare-host \
  --timeout 240
wait "${qemu_pid}"  # the firmware exits QEMU with 0 after a successful run
qemu_pid=""

# /dev/null is a character device but no terminal: refused before anything is sent, exit 1, named.
set +e
words=$("${lashid}" hil --attach /dev/null /dev/null --scenario dis_paper --seed 11 --timeout 5 2>&1)
status=$?
set -e
[[ ${status} -eq 1 ]] || { echo "attach_serial: /dev/null: exit ${status}, expected 1: ${words}" >&2; exit 1; }
grep -q '/dev/null is a character device but not a serial port' <<<"${words}" \
  || { echo "attach_serial: /dev/null: unexpected words: ${words}" >&2; exit 1; }
echo "attach_serial: passed"
