#!/usr/bin/env bash
# The package as another project sees it: install the build tree into a fresh prefix, check what is there, build the
# consumer (tests/package/consumer) against it for the host and run it, then cross-compile it for the Cortex-M4F
# with lashid's toolchain file and check that the object links no allocator.
# Usage: consumer_check.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
work=$(mktemp -d)
trap 'rm -rf "${work}"' EXIT
prefix=${work}/prefix
cmake --install "${build}" --prefix "${prefix}" >"${work}/install.log"
for f in bin/lashid include/lashid/estimator.hpp include/lashid/estimator/identifier.hpp \
         include/lashid/firmware/sequencer.hpp include/lashid/hal/board.hpp include/lashid/hal/host_board.hpp \
         lib/cmake/lashid/lashidConfig.cmake lib/cmake/lashid/lashidConfigVersion.cmake \
         lib/cmake/lashid/lashidTargets.cmake share/doc/lashid/docs/package.md share/doc/lashid/copyright \
         share/doc/lashid/tests/data/friction_damper/README.md share/doc/lashid/tests/data/friction_damper/LICENSE; do
  [[ -e "${prefix}/${f}" ]] || { echo "consumer_check: ${f} not installed" >&2; exit 1; }
done
"${prefix}/bin/lashid" --help >/dev/null

echo "== host =="
cmake -S "${src}/tests/package/consumer" -B "${work}/host" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="${prefix}" >/dev/null
cmake --build "${work}/host" -j2 >/dev/null
"${work}/host/consumer_demo"

echo "== Cortex-M4F (toolchains/arm-none-eabi.cmake) =="
cmake -S "${src}/tests/package/consumer" -B "${work}/m4f" -DCMAKE_BUILD_TYPE=Release \
  --toolchain "${src}/toolchains/arm-none-eabi.cmake" \
  -DLASHID_CPU_FLAGS="-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16" \
  -Dlashid_DIR="${prefix}/lib/cmake/lashid" >/dev/null
cmake --build "${work}/m4f" -j2 >/dev/null
library=${work}/m4f/libestimate_from_arrays.a
# The firmware's own heap check (cmake/Firmware.cmake: every allocator name, array new/delete, newlib's _r forms),
# not a shorter list of its own.
cmake -DLASHID_FIRMWARE_ACTION=heap-check -DNM=arm-none-eabi-nm -DELF="${library}" -P "${src}/cmake/Firmware.cmake" ||
  { echo "consumer_check: the Cortex-M4F object references an allocator" >&2; exit 1; }
arm-none-eabi-size "${library}" | tail -n 1
echo "consumer_check: ok"
