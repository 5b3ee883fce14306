#!/usr/bin/env bash
# `lashid hil` stopped by the user in the middle of a run (SIGTERM, as a CI runner or `timeout` sends; SIGINT, as
# Ctrl-C sends to the whole process group, QEMU included). It must exit with 128 + the signal, say so, kill its QEMU,
# remove its socket folder and the recording's temporary file, keep what was measured (marked partial), and replace an
# earlier --json by the error's (they used to stay: the default action of the signal ended the tool at once).
# Usage: interrupted.sh LASHID FIRMWARE
set -euo pipefail
lashid=$1 firmware=$2
# shellcheck source=mid_run.sh
source "$(dirname "${BASH_SOURCE[0]}")/mid_run.sh"

# Starts hil in the background with its temporary directory in ${dir}/tmp, waits until the firmware has entered its
# DP pulse experiment, sends SIGNAL (to hil, or with `group` to hil and its QEMU as a terminal's Ctrl-C does) and
# checks what is left.
interrupt() {
  local signal=$1 code=$2 target=$3 name=$4
  local tmp="${dir}/tmp-${name}" out="${dir}/${name}.txt" record="${dir}/${name}.csv" json="${dir}/${name}.json"
  mkdir -p "${tmp}"
  echo '{"verdict": {"ok": true}}' >"${json}"
  TMPDIR="${tmp}" "${lashid}" hil --firmware "${firmware}" --scenario dis_paper --seed 11 --timeout 120 \
    --record "${record}" --json "${json}" >"${out}" 2>&1 &
  hil_pid=$!
  local qemu
  qemu=$(wait_for_dp_pulse interrupted "${out}")
  [[ -n "$(ls -A "${tmp}")" ]] || { echo "interrupted: no session folder in TMPDIR (test is void)" >&2; exit 1; }
  if [[ "${target}" == group ]]; then kill "-${signal}" "${hil_pid}" "${qemu}"; else kill "-${signal}" "${hil_pid}"; fi
  local status=0
  wait "${hil_pid}" || status=$?
  hil_pid=
  grep -v '^    ' "${out}"
  echo "interrupted: ${name}: exit status ${status}"
  test "${status}" -eq "${code}"
  grep -q "lashid: error: hil: stopped by SIG${signal} (signal $((code - 128)))" "${out}"
  grep -q 'marked partial' "${out}"
  grep -q '^# partial recording' "${record}"
  [[ -z "$(ls -A "${tmp}")" ]] || { echo "interrupted: left in TMPDIR:" >&2; ls -la "${tmp}" >&2; exit 1; }
  if compgen -G "${dir}/.${name}.csv.tmp-*" >/dev/null; then echo "interrupted: temporary recording left" >&2; exit 1; fi
  if kill -0 "${qemu}" 2>/dev/null; then echo "interrupted: QEMU ${qemu} still running" >&2; exit 1; fi
  grep -q '"error": "hil: stopped by SIG' "${json}"
  grep -q '"ok": false' "${json}"
}

interrupt TERM 143 hil term
interrupt INT 130 group int
