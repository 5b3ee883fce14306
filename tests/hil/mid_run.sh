# Sourced by the HIL scripts that act in the middle of a run (qemu_gone.sh, interrupted.sh); not a test itself.
# Sets `dir` (a scratch folder removed at exit) and `hil_pid` (killed at exit if still set).
dir=$(mktemp -d)
hil_pid=
cleanup() {
  [[ -n "${hil_pid}" ]] && kill -KILL "${hil_pid}" 2>/dev/null || true
  rm -rf "${dir}"
}
trap cleanup EXIT

# wait_for_dp_pulse NAME OUT: waits until the hil run ${hil_pid} has started QEMU and the firmware has entered its DP
# pulse experiment (over 2,000 samples measured, printed by hil as progress to OUT), and prints QEMU's pid. Fails by
# name if the run ends first or nothing happens for 120 s: the signal must come mid-run.
wait_for_dp_pulse() {
  local name=$1 out=$2 qemu=
  for _ in $(seq 1 1200); do
    qemu=$(pgrep -P "${hil_pid}" -f qemu-system-arm || true)
    if [[ -n "${qemu}" ]] && grep -q 'DP pulse experiment' "${out}"; then
      echo "${qemu}"
      return 0
    fi
    kill -0 "${hil_pid}" 2>/dev/null || break
    sleep 0.1
  done
  echo "${name}: the firmware never reached its DP pulse experiment (the signal must come mid-run)" >&2
  cat "${out}" >&2
  return 1
}
