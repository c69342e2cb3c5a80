#!/usr/bin/env bash
# Builds the Python package and runs its pytest suite (python/tests). Meant to be called by the
# README's test command (scripts/test.sh), after the C++ build: the CLI-parity tests use the C++ tool
# from build/ or build-test/ when it is there (GEOVORONOI_CLI=path overrides), and are skipped, saying why, otherwise.
#
# Python: Debian's /usr/bin/python3 with Debian's NumPy, SciPy, scikit-image and pytest. The package
# is installed into a virtual environment over those (build-python/venv, --system-site-packages), not
# into the system interpreter (Debian marks it externally managed). The build dependencies are the
# versions pinned in pyproject.toml, installed from PyPI into the venv; the build runs without pip's
# build isolation in a kept folder (build-python/wheel), so a second run only recompiles what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/packages.sh
ensure_packages g++ cmake libeigen3-dev zlib1g-dev python3-dev python3-pip python3-venv \
                python3-numpy python3-scipy python3-skimage python3-pytest

py=/usr/bin/python3
venv=build-python/venv
start=$SECONDS
if [ ! -x "$venv/bin/python" ]; then
  "$py" -m venv --system-site-packages "$venv"
fi
# the build requirements exactly as pinned in pyproject.toml's [build-system]
reqs=$("$venv/bin/python" -c 'import tomllib; print(" ".join(tomllib.load(open("pyproject.toml","rb"))["build-system"]["requires"]))')
"$venv/bin/python" -m pip install -q --disable-pip-version-check $reqs
# GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE, when set, replaces the Release flags (-O3 -DNDEBUG): the
# README's test command builds the extension at -O1, like its C++ build (about half the compile time)
flags=()
if [ -n "${GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE:-}" ]; then
  flags+=(--config-settings="cmake.define.CMAKE_CXX_FLAGS_RELEASE=${GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE}")
fi
echo "== building the Python package (pip install .; Release flags: ${GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE:-the default, -O3})"
CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}" \
  "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps \
  --config-settings=build-dir=build-python/wheel --config-settings=cmake.define.GEOVORONOI_PYTHON_WERROR=ON \
  "${flags[@]}" .

if [ -z "${GEOVORONOI_CLI:-}" ]; then
  for c in build/bin/geovoronoi build-test/bin/geovoronoi build/tools/geovoronoi/geovoronoi; do
    if [ -f "$c" ] && [ -x "$c" ]; then export GEOVORONOI_CLI="$PWD/$c"; break; fi
  done
fi
echo "== Python tests (pytest; C++ tool: ${GEOVORONOI_CLI:-none in build/, the parity tests look in build-python/cli too and skip without one})"
rc=0
(cd python/tests && "../../$venv/bin/python" -m pytest -q -p no:cacheprovider .) || rc=$?
if [ "$rc" -eq 5 ]; then
  echo "pytest collected no tests: that is a failure"
  exit 1
fi
if [ "$rc" -ne 0 ]; then exit "$rc"; fi
echo "== Python package built and tested in $((SECONDS - start)) s"
