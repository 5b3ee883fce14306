#!/usr/bin/env bash
# The Debian package as a user gets it (cmake/Package.cmake, docs/package.md): CPack makes the .deb from the build
# tree; its name, control fields (Depends from dpkg-shlibdeps plus Eigen) and file list are checked with dpkg-deb; it
# is extracted with `dpkg-deb -x` (no root, nothing installed on the machine), the consumer (tests/package/consumer)
# is built against the extracted /usr and run, and so is the extracted `lashid --help`.
# Usage: deb_check.sh BUILD_DIR SOURCE_DIR CPACK_COMMAND VERSION
set -euo pipefail
build=$1 src=$2 cpack=$3 version=$4
work=$(mktemp -d)
trap 'rm -rf "${work}"' EXIT
fail() { echo "deb_check: $*" >&2; exit 1; }

arch=$(dpkg --print-architecture)
deb=${work}/lashid_${version}_${arch}.deb
start=${SECONDS}
# -B: the .deb and CPack's staging tree go to the temporary folder, not into the build tree.
"${cpack}" -G DEB --config "${build}/CPackConfig.cmake" -B "${work}" >"${work}/cpack.log" 2>&1 ||
  { cat "${work}/cpack.log" >&2; fail "cpack -G DEB failed"; }
[[ -f "${deb}" ]] || { ls "${work}" >&2; fail "cpack made no $(basename "${deb}")"; }
echo "$(basename "${deb}"): $(stat -c %s "${deb}") bytes, made in $((SECONDS - start)) s"

echo "== dpkg-deb --info =="
dpkg-deb --info "${deb}" >"${work}/info.txt"
cat "${work}/info.txt"
field() { dpkg-deb --field "${deb}" "$1"; }
[[ "$(field Package)" == lashid ]] || fail "Package is '$(field Package)', not lashid"
[[ "$(field Version)" == "${version}" ]] || fail "Version is '$(field Version)', not ${version}"
[[ "$(field Architecture)" == "${arch}" ]] || fail "Architecture is '$(field Architecture)', not ${arch}"
for name in Maintainer Section Description; do
  [[ -n "$(field "${name}")" ]] || fail "no ${name} field"
done
[[ "$(field Description | wc -l)" -gt 2 ]] || fail "the Description has no paragraph under its summary"
depends=$(field Depends)
# Eigen from CPACK_DEBIAN_PACKAGE_DEPENDS (the package config's find_dependency); the C and C++ runtimes from
# dpkg-shlibdeps, which only an ELF the tool links can give (no one lists them by hand).
for dependency in 'libeigen3-dev (>= 3.4)' 'libc6 (>=' 'libstdc++6 (>='; do
  [[ "${depends}" == *"${dependency}"* ]] || fail "Depends lacks '${dependency}': ${depends}"
done

echo "== dpkg-deb --contents =="
dpkg-deb --contents "${deb}" | awk '{print $6}' | sed 's|^\./||' >"${work}/contents.txt"
echo "$(grep -vc '/$' "${work}/contents.txt") files"
# The package config where find_package(lashid CONFIG) looks under a prefix: lib/cmake (LASHID_INSTALL_CMAKEDIR's
# default in a tree configured for /usr/local), lib/<multiarch>/cmake (configured for /usr) or share/cmake.
cmakedir=$(sed -En 's|^(usr/(lib\|lib/[^/]+-linux-[^/]+\|share)/cmake/lashid)/lashidConfig\.cmake$|\1|p' "${work}/contents.txt")
[[ -n "${cmakedir}" ]] || fail "no lashidConfig.cmake under usr/lib/cmake, usr/lib/<multiarch>/cmake or usr/share/cmake"
echo "package config in ${cmakedir}/"
for f in usr/bin/lashid usr/include/lashid/estimator.hpp usr/include/lashid/estimator/identifier.hpp \
         usr/include/lashid/firmware/sequencer.hpp usr/include/lashid/hal/board.hpp \
         usr/include/lashid/hal/host_board.hpp "${cmakedir}/lashidConfigVersion.cmake" "${cmakedir}/lashidTargets.cmake" \
         usr/share/doc/lashid/README.md usr/share/doc/lashid/copyright usr/share/doc/lashid/docs/package.md \
         usr/share/doc/lashid/docs/friction-damper.png usr/share/doc/lashid/tests/data/friction_damper/README.md \
         usr/share/doc/lashid/tests/data/friction_damper/LICENSE; do
  grep -qxF "${f}" "${work}/contents.txt" || fail "${f} is not in the package"
done
# Everything under /usr, none of it under /usr/local; headers only of lashid (nothing of a dependency's).
# (grep -c, not a pipe into grep -q: under pipefail the first grep's SIGPIPE would turn a finding into a pass)
if [ "$(grep -cv '^usr/' "${work}/contents.txt" || true)" != 0 ]; then
  fail "paths outside usr/: $(grep -v '^usr/' "${work}/contents.txt")"
fi
if grep -q '^usr/local/' "${work}/contents.txt"; then fail "paths under usr/local/"; fi
if [ "$(grep '^usr/include/.' "${work}/contents.txt" | grep -cv '^usr/include/lashid/' || true)" != 0 ]; then
  fail "headers outside usr/include/lashid/: $(grep '^usr/include/.' "${work}/contents.txt" | grep -v '^usr/include/lashid/')"
fi

echo "== dpkg-deb -x, then the consumer against the extracted tree =="
root=${work}/root
dpkg-deb -x "${deb}" "${root}"
file "${root}/usr/bin/lashid" | grep -q ', stripped' || fail "usr/bin/lashid is not stripped"
"${root}/usr/bin/lashid" --help >"${work}/help.txt" || fail "the extracted lashid --help failed"
grep -q 'identify' "${work}/help.txt" || fail "the extracted lashid --help lists no identify command"
echo "usr/bin/lashid --help: $(wc -l <"${work}/help.txt") lines"
cmake -S "${src}/tests/package/consumer" -B "${work}/host" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="${root}/usr" >"${work}/configure.log" || { cat "${work}/configure.log" >&2; fail "configure"; }
# The package the consumer found must be the extracted one, not an installed lashid or a build tree.
found=$(sed -n 's/^lashid_DIR:PATH=//p' "${work}/host/CMakeCache.txt")
[[ "${found}" == "${root}/${cmakedir}" ]] || fail "the consumer found lashid in '${found}', not in ${root}/${cmakedir}"
cmake --build "${work}/host" -j2 >"${work}/build.log" || { cat "${work}/build.log" >&2; fail "the consumer did not build"; }
"${work}/host/consumer_demo"
echo "deb_check: ok ($((SECONDS - start)) s)"
