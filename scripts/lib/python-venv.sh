# Sourced by scripts/test.sh and scripts/test-python.sh (not run on its own).
#
# python_venv: makes sure build-python/venv exists (a virtual environment over Debian's
# /usr/bin/python3 and its NumPy, SciPy, scikit-image and pytest: --system-site-packages; Debian marks
# the system interpreter externally managed) and holds the build requirements exactly as pinned in
# pyproject.toml's [build-system] (from PyPI). Sets `venv` (relative) and `venv_python` (absolute: the
# interpreter CMake is given, the same path pip's build passes as Python_EXECUTABLE).
python_venv() {
  venv=build-python/venv
  if [ ! -x "$venv/bin/python" ]; then
    /usr/bin/python3 -m venv --system-site-packages "$venv"
  fi
  venv_python="$PWD/$venv/bin/python"
  local reqs
  reqs=$("$venv_python" -c 'import tomllib; print(" ".join(tomllib.load(open("pyproject.toml","rb"))["build-system"]["requires"]))')
  # shellcheck disable=SC2086
  "$venv_python" -m pip install -q --disable-pip-version-check $reqs
}
