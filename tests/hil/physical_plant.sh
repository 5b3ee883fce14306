#!/usr/bin/env bash
# lashid hil --physical-plant with the STM32F405's analog image (lashid_fw_analog.elf: v on the DAC, y from ADC1) in
# QEMU netduinoplus2, which has no DAC (writes ignored) and an ADC whose DR answers 7 above its last code, modulo 4096,
# at each conversion (hw/adc/stm32f2xx_adc.c). Nothing is played: the firmware's own loop of DAC writes and ADC reads
# must run every sample of the design, and its count of bad sensor values must be the closed form's: the clipped
# codes 0 and 4095 of the sawtooth 7k mod 4096, k = 1..S (4095 at k = 585 + 4096 j, since 7 x 585 = 4095; 0 at
# k = 4096 j). For S = 5,002: k = 585, 4096 and 4681, so 3. Then: a design beyond what the DAC reaches refused by
# the firmware before any sample (kOutsideActuatorRange); the link alone attached to a QEMU started here; the options a
# physical plant cannot have, refused by name. The image must have the default analog plan (Vref 3.3 V, v and y in
# volts at the pins: the DAC reaches 0.2-3.1 V), as the stm32f405-release preset configures it.
# Usage: physical_plant.sh LASHID QEMU FIRMWARE
set -euo pipefail
lashid=$1 qemu=$2 firmware=$3
dir=$(mktemp -d)
qemu_pid=""
trap 'kill "${qemu_pid}" 2>/dev/null || true; rm -rf "${dir}"' EXIT
fail() { echo "physical_plant: $*" >&2; exit 1; }
# A field of the run's --json, e.g. "samples": 5002 -> 5002 (nlohmann's indented output: one key per line).
field() { sed -n "s/^ *\"$1\": *\\([-0-9]*\\),\\?\$/\\1/p" "$2" | head -1; }

# S = 2 (L + 1) + 2 N + val = 2 x 1001 + 2 x 1000 + 1000 = 5,002 samples; a switch (no interval check).
"${lashid}" design --n 2 --m 4 --v-min 0.3 --v-max 3.0 --operator switch --step-length 1000 --pulse-length 1000 \
  --val-length 1000 --out "${dir}/design.json" >/dev/null
"${lashid}" hil --firmware "${firmware}" --machine netduinoplus2 --physical-plant --config "${dir}/design.json" \
  --timeout 120 --json "${dir}/run.json" >"${dir}/out.txt" 2>&1 || true  # the sawtooth is no plant: status aside
cat "${dir}/out.txt"
grep -q "plant physical (the board's own actuator and sensor)" "${dir}/out.txt" || fail "not run as a physical plant"
[[ "$(field design_status "${dir}/run.json")" == 0 ]] || fail "design not accepted"
[[ "$(field samples "${dir}/run.json")" == 5002 ]] || fail "expected 5002 samples on the board"
[[ "$(field bad_sensor_values "${dir}/run.json")" == 3 ]] || fail "expected 3 clipped ADC codes (k = 585, 4096, 4681)"
done_status=$(field done "${dir}/run.json")
[[ "${done_status}" =~ ^[0-9]+$ ]] || fail "no final report from the firmware"
[[ "$(field qemu_exit "${dir}/run.json")" == $((done_status == 0 ? 0 : 10 + done_status)) ]] ||
  fail "QEMU's exit status is not the firmware's run status"

# Beyond the DAC: v_max = 3.2 V > 3.1 V, the most the buffered output reaches at Vref = 3.3 V. The host cannot know
# the board's range; the firmware refuses, naming it, and drives nothing.
"${lashid}" design --n 2 --m 4 --v-min 0.3 --v-max 3.2 --operator switch --out "${dir}/beyond.json" >/dev/null
if "${lashid}" hil --firmware "${firmware}" --machine netduinoplus2 --physical-plant --config "${dir}/beyond.json" \
  --timeout 60 --json "${dir}/beyond_run.json" >"${dir}/beyond.txt" 2>&1; then
  cat "${dir}/beyond.txt"
  fail "a design beyond the DAC's range passed"
fi
cat "${dir}/beyond.txt"
grep -q "the firmware refused the design: the working interval reaches beyond the board's actuator range" \
  "${dir}/beyond.txt" || fail "the refusal is not named"
[[ "$(field samples "${dir}/beyond_run.json")" == 0 ]] || fail "samples were taken on a refused design"

# The link alone, attached to a QEMU started by "the user": UART0 on a server socket, USART2 to nothing.
qemu_command=$("${lashid}" qemu-command --qemu "${qemu}" --machine netduinoplus2 \
  --serial "unix:${dir}/link.sock,server=on,wait=off" --serial null --kernel "${firmware}")
mapfile -t qemu_command <<<"${qemu_command}"
"${qemu_command[@]}" >"${dir}/qemu.log" 2>&1 &
qemu_pid=$!
"${lashid}" hil --attach "${dir}/link.sock" --machine netduinoplus2 --physical-plant --config "${dir}/design.json" \
  --timeout 120 --json "${dir}/attached.json" >"${dir}/attached.txt" 2>&1 || true
cat "${dir}/attached.txt"
[[ "$(field samples "${dir}/attached.json")" == 5002 ]] || fail "attached: expected 5002 samples"
[[ "$(field bad_sensor_values "${dir}/attached.json")" == 3 ]] || fail "attached: expected 3 clipped codes"
wait "${qemu_pid}" || true
qemu_pid=""

# What a physical plant cannot have: a recording (the host sees no sample), a played plant, a plant port.
refuse_with() {
  if "${lashid}" hil --firmware "${firmware}" --machine netduinoplus2 --physical-plant --config "${dir}/design.json" \
    "$@" >"${dir}/refused.txt" 2>&1; then
    fail "--physical-plant $* was accepted"
  fi
  grep -q "excludes" "${dir}/refused.txt" || { cat "${dir}/refused.txt"; fail "$*: no reason given"; }
}
refuse_with --record "${dir}/r.csv"
refuse_with --scenario dis_paper
refuse_with --compare-host
if "${lashid}" hil --attach "${dir}/a.sock" "${dir}/b.sock" --physical-plant --config "${dir}/design.json" \
  >"${dir}/two.txt" 2>&1; then
  fail "two attach paths accepted for a physical plant"
fi
grep -q "a physical plant has no plant port" "${dir}/two.txt" || { cat "${dir}/two.txt"; fail "two paths: no reason"; }
echo "physical_plant: ok"
