#!/usr/bin/env bash
# lashid hil --attach: QEMU is started here, by "the user", with its UARTs on server sockets; the tool attaches.
# Usage: attach.sh LASHID QEMU FIRMWARE CONFIG (the design sent, with the scenario dis_paper's plant)
set -euo pipefail
lashid=$1 qemu=$2 firmware=$3 config=$4
dir=$(mktemp -d)
qemu_pid=""
trap 'kill "${qemu_pid}" 2>/dev/null || true; rm -rf "${dir}"' EXIT
# The command line from the tool (cmake/Qemu.cmake's flags), one argument per line; UART0 and UART1 on server sockets.
qemu_command=$("${lashid}" qemu-command --qemu "${qemu}" --machine mps2-an386 \
  --serial "unix:${dir}/link.sock,server=on,wait=off" --serial "unix:${dir}/plant.sock,server=on,wait=off" \
  --kernel "${firmware}")
mapfile -t qemu_command <<<"${qemu_command}"
"${qemu_command[@]}" >"${dir}/qemu.log" 2>&1 &
qemu_pid=$!
"${lashid}" hil --attach "${dir}/link.sock" "${dir}/plant.sock" --scenario dis_paper --config "${config}" \
  --seed 11 --compare-host --timeout 240
wait "${qemu_pid}"  # the firmware exits QEMU with 0 after a successful run
