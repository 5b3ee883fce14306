#!/usr/bin/env bash
# lashid hil --physical-plant with the STM32F405's analog image (lashid_fw_analog.elf: v on the DAC, y from ADC1) in
# QEMU netduinoplus2, which has no DAC (writes ignored) and an ADC whose DR answers 7 above its last code, modulo 4096,
# at each conversion (hw/adc/stm32f2xx_adc.c). Nothing is played: the firmware's own loop of DAC writes and ADC reads
# must run every sample of the design, and its count of bad sensor values must be the closed form's: the clipped
# codes 0 and 4095 of the sawtooth 7k mod 4096, k = 1..S (4095 at k = 585 + 4096 j, since 7 x 585 = 4095; 0 at
# k = 4096 j). For S = 5,002: k = 585, 4096 and 4681, so 3. With --record the firmware streams its samples (kSamples
# through its interrupt-driven transmitter): the recording's k-th y must be that sawtooth, 3.3 x (7k mod 4096) / 4095
# volts, every row in order, with the 3 set-aside samples marked; the host's identification of it, without them as
# on the device, must equal the device's estimates; and `lashid diagnose` must take it. Then: a design beyond what the DAC reaches refused by
# the firmware before any sample (kOutsideActuatorRange); the link alone attached to a QEMU started here; the options a
# physical plant cannot have, and the wrong mode for an image (the analog image played, the plant-port image
# lashid_fw.elf beside it as a physical plant), refused by name. The image must have the default analog plan (Vref 3.3 V, v and y in
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
  --timeout 120 --record "${dir}/rec.csv" --json "${dir}/run.json" >"${dir}/out.txt" 2>&1 ||
  true  # the sawtooth is no plant: its status aside
cat "${dir}/out.txt"
grep -q "plant physical (the board's own actuator and sensor)" "${dir}/out.txt" || fail "not run as a physical plant"
[[ "$(field design_status "${dir}/run.json")" == 0 ]] || fail "design not accepted"
[[ "$(field samples "${dir}/run.json")" == 5002 ]] || fail "expected 5002 samples on the board"
[[ "$(field bad_sensor_values "${dir}/run.json")" == 3 ]] || fail "expected 3 clipped ADC codes (k = 585, 4096, 4681)"
grep -q "recorded 5002 samples to ${dir}/rec.csv" "${dir}/out.txt" || fail "the streamed recording is not complete"
# The recording holds the 3 clipped values as measured, each followed by a comment; the device left them out, and so
# does the host's identification it is compared with: it must equal the device's estimates.
[[ "$(grep -c "the firmware set aside the row above" "${dir}/rec.csv")" == 3 ]] ||
  fail "the 3 set-aside samples are not marked in the recording"
grep -Eq "on-device estimates vs .lashid identify --float. on .*: equal" "${dir}/out.txt" ||
  fail "the host's identification of the streamed recording differs from the device's estimates"
# Data row i (from 0) is sample i, the ADC's conversion i + 1: code 7 (i + 1) mod 4096.
awk -F, '!/^#/ && $1 != "phase" {
  code = (7 * (n + 1)) % 4096; expected = 3.3 * code / 4095; n++
  if ($4 - expected > 1e-5 || expected - $4 > 1e-5) { printf "row %d: y %s, expected %.7f\n", n, $4, expected; bad++ }
} END { if (n != 5002 || bad > 0) { printf "%d rows, %d wrong\n", n, bad; exit 1 } }' "${dir}/rec.csv" ||
  fail "the streamed y is not QEMU's ADC sawtooth"
"${lashid}" diagnose --config "${dir}/design.json" --data "${dir}/rec.csv" >"${dir}/diagnose.txt" 2>&1 ||
  { cat "${dir}/diagnose.txt"; fail "lashid diagnose did not take the streamed recording"; }
grep -q "^causes: " "${dir}/diagnose.txt" || fail "lashid diagnose named no cause"
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

# What a physical plant cannot have: a played plant, a host-board comparison, a plant port.
refuse_with() {
  if "${lashid}" hil --firmware "${firmware}" --machine netduinoplus2 --physical-plant --config "${dir}/design.json" \
    "$@" >"${dir}/refused.txt" 2>&1; then
    fail "--physical-plant $* was accepted"
  fi
  grep -q "excludes" "${dir}/refused.txt" || { cat "${dir}/refused.txt"; fail "$*: no reason given"; }
}
refuse_with --scenario dis_paper
refuse_with --compare-host
# The wrong mode for an image is refused before QEMU starts, by the image's own tag (section .lashid.plant).
if "${lashid}" hil --firmware "${firmware}" --machine netduinoplus2 --scenario dis_paper --timeout 30 \
  >"${dir}/own.txt" 2>&1; then
  fail "the analog image was run with a played plant"
fi
grep -q "drives its own actuator and sensor (an analog image): run it with --physical-plant" "${dir}/own.txt" ||
  { cat "${dir}/own.txt"; fail "the analog image without --physical-plant: no reason given"; }
played_image="$(dirname "${firmware}")/lashid_fw.elf"
if "${lashid}" hil --firmware "${played_image}" --machine netduinoplus2 --physical-plant --config "${dir}/design.json" \
  --timeout 30 >"${dir}/port.txt" 2>&1; then
  fail "the plant-port image was run as a physical plant"
fi
grep -q "has its plant played over its plant port" "${dir}/port.txt" ||
  { cat "${dir}/port.txt"; fail "the plant-port image with --physical-plant: no reason given"; }
if "${lashid}" hil --attach "${dir}/a.sock" "${dir}/b.sock" --physical-plant --config "${dir}/design.json" \
  >"${dir}/two.txt" 2>&1; then
  fail "two attach paths accepted for a physical plant"
fi
grep -q "a physical plant has no plant port" "${dir}/two.txt" || { cat "${dir}/two.txt"; fail "two paths: no reason"; }
echo "physical_plant: ok"
