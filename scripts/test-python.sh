#!/usr/bin/env bash
# Builds the Python package with `pip install .` and runs its pytest suite (python/tests).
#
# Python: Debian's /usr/bin/python3 with Debian's NumPy, SciPy, scikit-image and pytest; the package
# goes into build-python/venv, a virtual environment over them that holds the build requirements as
# pinned in pyproject.toml (scripts/lib/python-venv.sh). pip builds without build isolation, with
# those requirements.
#
# Alone (a developer): the build runs in a kept folder, build-python/wheel, so a second run only
# recompiles what changed, with -Werror. GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE, when set, replaces the
# Release flags (-O3 -DNDEBUG).
#
# In the README's test command (scripts/test.sh): GEOVORONOI_PYTHON_BUILD_DIR names the test build
# (build-test/), configured with GEOVORONOI_BUILD_PYTHON=ON, whose objects (the front end it shares
# with the command-line tool, and the extension) are compiled already. pip's build re-configures that
# tree with the tree's own values of every option pyproject.toml sets, so that nothing recompiles, and
# installs the extension it holds: `pip install .` still runs end to end, the wheel's own option
# values are what it does not exercise. The tests then compare `python -m geovoronoi` with that
# tree's tool (bin/geovoronoi) byte for byte.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/packages.sh
source scripts/lib/python-venv.sh
ensure_packages g++ cmake ninja-build libeigen3-dev zlib1g-dev libpng-dev python3-dev python3-pip python3-venv \
                python3-numpy python3-scipy python3-skimage python3-pytest

start=$SECONDS
python_venv
settings=()
build_dir="${GEOVORONOI_PYTHON_BUILD_DIR:-}"
if [ -n "$build_dir" ]; then
  cache="$build_dir/CMakeCache.txt"
  if ! grep -qx "GEOVORONOI_BUILD_PYTHON:BOOL=ON" "$cache" 2>/dev/null; then
    echo "$build_dir is not a build folder configured with GEOVORONOI_BUILD_PYTHON=ON"
    exit 1
  fi
  settings+=(--config-settings=build-dir="$build_dir")
  # every option pyproject.toml sets, and the build type, at the tree's own value
  names=$("$venv_python" -c 'import tomllib; print(" ".join(tomllib.load(open("pyproject.toml","rb"))["tool"]["scikit-build"]["cmake"]["define"]))')
  for name in $names; do
    if ! grep -q "^$name:" "$cache"; then
      echo "$build_dir has no $name in its cache"
      exit 1
    fi
    settings+=(--config-settings="cmake.define.$name=$(sed -n "s/^$name:[A-Z]*=//p" "$cache")")
  done
  settings+=(--config-settings="cmake.build-type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$cache")")
  if [ -z "${GEOVORONOI_CLI:-}" ] && [ -x "$build_dir/bin/geovoronoi" ]; then
    export GEOVORONOI_CLI="$PWD/$build_dir/bin/geovoronoi"
  fi
  what="reusing the objects of $build_dir"
else
  settings+=(--config-settings=build-dir=build-python/wheel --config-settings=cmake.define.GEOVORONOI_WERROR=ON)
  if [ -n "${GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE:-}" ]; then
    settings+=(--config-settings="cmake.define.CMAKE_CXX_FLAGS_RELEASE=${GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE}")
  fi
  what="in build-python/wheel; Release flags: ${GEOVORONOI_PYTHON_CXX_FLAGS_RELEASE:-the default, -O3}"
fi
echo "== building the Python package (pip install .; $what)"
CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}" \
  "$venv_python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps "${settings[@]}" .
echo "== built and installed in $((SECONDS - start)) s"

echo "== Python tests (pytest; the C++ tool for the byte-for-byte test: ${GEOVORONOI_CLI:-build/ or build-test/ when built there, else skipped})"
rc=0
(cd python/tests && "$venv_python" -m pytest -q -p no:cacheprovider .) || rc=$?
if [ "$rc" -eq 5 ]; then
  echo "pytest collected no tests: that is a failure"
  exit 1
fi
if [ "$rc" -ne 0 ]; then exit "$rc"; fi
echo "== Python package built and tested in $((SECONDS - start)) s"
