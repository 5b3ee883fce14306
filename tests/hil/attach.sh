#!/usr/bin/env bash
# lashid hil --attach: QEMU is started here, by "the user", with its UARTs on server sockets; the tool attaches.
# Usage: attach.sh LASHID QEMU FIRMWARE
set -euo pipefail
lashid=$1 qemu=$2 firmware=$3
dir=$(mktemp -d)
trap 'kill "${qemu_pid}" 2>/dev/null || true; rm -rf "${dir}"' EXIT
"${qemu}" -machine mps2-an386 -nographic -monitor none \
  -serial "unix:${dir}/link.sock,server=on,wait=off" -serial "unix:${dir}/plant.sock,server=on,wait=off" \
  -semihosting-config enable=on,target=native -kernel "${firmware}" >"${dir}/qemu.log" 2>&1 &
qemu_pid=$!
"${lashid}" hil --attach "${dir}/link.sock" "${dir}/plant.sock" --scenario dis_paper --seed 11 --compare-host \
  --timeout 240
wait "${qemu_pid}"  # the firmware exits QEMU with 0 after a successful run
